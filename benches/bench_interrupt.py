"""Interrupt latency: SIGINT one second into long calls, and how long until KeyboardInterrupt.
The figures go to docs/reliability.md.

    python benches/bench_interrupt.py
"""

from __future__ import annotations

import os
import signal
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import passive_assoc as pa
from bench_exact_sd import random_problem
from passive_assoc.experiments.wavelet_runs import PROCESS_NOISE
from passive_assoc.radar_esm import filter_reports
from passive_assoc.simulation import paper_wavelet_scenario, static_scan


def cases() -> dict[str, Callable[[], Any]]:
    rng = np.random.default_rng(0)
    t, c, n = random_problem(0, 3, 25, 0.08)
    scan = static_scan(3, n_targets=300, ratio=2.0)
    dense = pa.MeasurementTable.from_arrays(np.repeat([0, 1], 6000), np.zeros(12000), rng.uniform(0.5, 2.5, 12000))
    two = pa.SensorNetwork.planar(np.array([[-1e4, 0.0], [1e4, 0.0]]), 1e-3)
    clutter = pa.MeasurementTable.from_arrays(
        np.repeat([0, 1, 0, 1], 400), np.repeat([0.0, 0.0, 30.0, 30.0], 400), rng.uniform(0.3, 2.8, 1600)
    )
    wide = pa.SensorNetwork.planar(np.array([[-2e4, 0.0], [2e4, 0.0]]), 2e-3)
    bearings = rng.uniform(0.5, 2.6, 15000)
    formation = pa.MeasurementTable.from_arrays(np.repeat([0, 1, 2], 5000), np.zeros(15000), bearings)
    three = pa.SensorNetwork.planar(np.array([[-80e3, -30e3], [-30e3, -30e3], [20e3, -30e3]]), np.radians(0.5))
    local, system = _pictures(rng, 2000, scans=4)
    wide_local, wide_system = _pictures(rng, 4000)
    scenario = paper_wavelet_scenario(1, n_clutter=1490)
    tracks = filter_reports(scenario.measurements, PROCESS_NOISE)
    return {
        "exact S-D, branch-and-bound, no limits (S=3, K=1429)": lambda: pa.assign_sd(
            t, c, n, method="exact", exact_backend="branch_bound", max_nodes=10**15, time_limit=None
        ),
        "intensity vote, M=300, max_chains=None": lambda: pa.associate_static(
            scan.measurements, scan.sensors, "intensity", max_chains=None
        ),
        "static enumeration, 2 x 6000 reports": lambda: pa.enumerate_candidates(
            dense, two, pd=0.9, max_candidates=10**9
        ),
        "fuzzy initiation, 4 scans x 400 clutter bearings": lambda: pa.FuzzyTrackInitiator(
            v_max=None, max_candidates=10**9, ray_gate_sigmas=None
        ).initiate(clutter, wide),
        "formation locator, 3 x 5000 reports (5e7 pairs, the default cap), one-to-one": lambda: pa.locate_formation(
            formation, three, attributes=[], one_to_one=True, progress=False
        ),
        "topology, 4 scans of 2000 x 2000 tracks, no gate, default window": lambda: pa.TopologyAssociator(
            gate=None
        ).associate(local=local, system=system, progress=False),
        "nearest neighbour, one scan of 4000 x 4000 tracks, no gate (16e6 pairs, the cap)": lambda: (
            pa.NearestNeighbourAssociator(gate_probability=None).associate(
                local=wide_local, system=wide_system, progress=False
            )
        ),
        "wavelet-fuzzy, 1500 x 1500 tracks, 28 scans": lambda: pa.WaveletFuzzyAssociator(
            process_noise=PROCESS_NOISE
        ).associate(local=tracks.of(1), system=tracks.of(0)),
    }


def _pictures(rng: np.random.Generator, n: int, scans: int = 1) -> tuple[pa.TrackTable, pa.TrackTable]:
    """``scans`` scans of ``n`` local and ``n`` system tracks, 10 m apart, over a 1 000 km square."""
    p = np.tile(rng.uniform(0, 1e6, (n, 2)), (scans, 1))
    track, times = np.tile(np.arange(n), scans), np.repeat(np.arange(float(scans)), n)

    def table(source: int, position: np.ndarray) -> pa.TrackTable:
        return pa.TrackTable.from_arrays(np.full(n * scans, source), track, times, position, sort=True)

    return table(1, p + rng.normal(0, 10, p.shape)), table(0, p)


def _interrupt_after(seconds: float, sent: list[float]) -> None:
    time.sleep(seconds)
    sent.append(time.perf_counter())
    os.kill(os.getpid(), signal.SIGINT)


def main() -> None:
    for name, call in cases().items():
        sent: list[float] = []
        threading.Thread(target=_interrupt_after, args=(1.0, sent), daemon=True).start()
        try:
            call()
            print(f"{name}: returned before the signal")
        except KeyboardInterrupt:
            print(f"{name}: KeyboardInterrupt {1e3 * (time.perf_counter() - sent[0]):.1f} ms after SIGINT")
        time.sleep(0.1)


if __name__ == "__main__":
    main()
