"""The 2-D radar + passive demo of ``reproduce wavelet`` (EXPERIMENTS ``wavelet``: "also run the
method on a 2-D radar + passive (triangulated ESM) scenario").

The paper's 10 targets fly along random directions in the plane
(``paper_wavelet_scenario(ndim=2)``). The radar's tracks are filtered from its position
reports (noise variance 0.5 km² per axis). The passive picture has no positions at all: three
ESM sites measure bearings (:data:`BEARING_STD`), each scan's three bearings of a target are
triangulated by the project's ML fitter (``fit_ml(motion="static")``, with its covariance),
and those fixes — accurate across the lines of sight, poor along them, and differently for
every target — are filtered by the same constant-acceleration Kalman filter with each fix's
own covariance as its noise.
"""

from __future__ import annotations

from concurrent.futures import Executor
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._settings import KalmanInit
from ..data import MeasurementTable, SensorNetwork, TrackTable
from ..radar_esm import bearing_fixes, filter_reports
from ..simulation.radar_esm import RadarEsmScenario, paper_wavelet_scenario
from .common import print_rows, run_seeds
from .wavelet_runs import METHODS, RAW, RunScores, Settings, map_seeds, methods, score, summarise

#: The three ESM sites (m): a triangle about 50 km around the targets' [0, 20] km square.
ESM_SITES = np.array([[-40e3, -30e3], [60e3, -30e3], [10e3, 60e3]])
#: Bearing noise std of every ESM site (rad), about 0.57°.
BEARING_STD = 0.01
PASSIVE_SOURCE = 1


def passive_fixes(
    scenario: RadarEsmScenario, rng: np.random.Generator, sites: NDArray[np.float64] = ESM_SITES
) -> TrackTable:
    """Per target and scan, the ML position fix from one noisy bearing per ESM site, with its
    covariance (:func:`~passive_assoc.radar_esm.bearing_fixes`); track ids shuffled."""
    truth = scenario.true_position  # (n, K, 2)
    n, k, _ = truth.shape
    delta = truth[:, :, None, :] - sites[None, None, :, :]  # (n, K, S, 2)
    bearing = np.arctan2(delta[..., 1], delta[..., 0]) + BEARING_STD * rng.standard_normal((n, k, len(sites)))
    sensor = np.broadcast_to(np.arange(len(sites)), bearing.shape)
    time = np.broadcast_to(scenario.scan_times[None, :, None], bearing.shape)
    target = np.broadcast_to(np.arange(n)[:, None, None], bearing.shape).ravel()
    table = MeasurementTable(sensor.ravel(), time.ravel(), np.angle(np.exp(1j * bearing.ravel())), truth=target)
    ids = rng.permutation(n)
    return bearing_fixes(
        table, SensorNetwork.planar(sites, BEARING_STD), ids[target], source=PASSIVE_SOURCE, n_threads=1
    )


def demo_tracks(
    seed: int | np.random.SeedSequence, process_noise: float, init: KalmanInit = "single_point"
) -> tuple[RadarEsmScenario, TrackTable, TrackTable, TrackTable]:
    """One demo run: the scenario, the radar's tracks, the passive fixes and the passive tracks."""
    rng = np.random.default_rng(seed)
    scenario = paper_wavelet_scenario(rng, ndim=2)
    radar = filter_reports(scenario.measurements.of(0), process_noise, init=init, n_threads=1)
    fixes = passive_fixes(scenario, rng)
    return scenario, radar, fixes, filter_reports(fixes, process_noise, init=init, n_threads=1)


def _fix_rms(scenario: RadarEsmScenario, fixes: TrackTable) -> float:
    assert fixes.truth is not None
    scan = np.searchsorted(scenario.scan_times, fixes.time)
    error = fixes.position - scenario.true_position[fixes.truth, scan]
    return float(np.sqrt(np.mean(np.sum(error**2, axis=1))))


def demo_run(seed: np.random.SeedSequence, settings: Settings) -> tuple[RunScores, float]:
    """One demo run's scores (as :func:`.wavelet_runs.run_once`'s) and its fixes' RMS error (m)."""
    scenario, radar, fixes, passive = demo_tracks(seed, settings.process_noise, settings.init)
    correct, keeps = {}, {}
    for name, method in methods(settings).items():
        # The raw-input methods take the radar's reports and the fixes as they are.
        sides = (scenario.measurements.of(0), fixes) if name in RAW else (radar, passive)
        correct[name], keeps[name] = score(
            method.associate(local=sides[1], system=sides[0]), sides[0], sides[1], scenario.scan_times
        )
    return RunScores(correct, keeps), _fix_rms(scenario, fixes)


def run_demo(pool: Executor | None, runs: int, seed: int, settings: Settings) -> dict[str, Any]:
    """Summaries of the demo (as :func:`.wavelet_runs.summarise`) and the fixes' mean RMS error."""
    seeds = run_seeds(seed + 1, runs)  # other scenes than the 1-D runs'
    results = map_seeds(pool, demo_run, seeds, (settings,), "wavelet, 2-D radar + passive")
    summary = summarise([scores for scores, _ in results])
    rms = float(np.mean([r for _, r in results]))
    return {"runs": runs, "fix_rms_m": rms, "radar_noise_std_m": float(np.sqrt(0.5e6)), **summary}


def print_demo(demo: dict[str, Any]) -> None:
    print(
        f"\n2-D radar + passive demo, {demo['runs']} runs: radar position reports (std "
        f"{demo['radar_noise_std_m']:.0f} m per axis) against tracks of ML fixes of 3 ESM bearings "
        f"(σθ = {BEARING_STD * 1e3:g} mrad; fix RMS error {demo['fix_rms_m']:.0f} m)"
    )
    table = [["", *METHODS.values()]]
    table.append(["mean 6-30", *(f"{demo[m]['mean_6_30']:.3f}" for m in METHODS)])
    table.append(["min 15-30", *(f"{demo[m]['min_15_30']:.3f}" for m in METHODS)])
    table.append(["gate keeps", *(f"{demo[m]['gate_keeps_true_6_30']:.3f}" for m in METHODS)])
    print_rows(table, [10, *(max(13, len(t)) for t in METHODS.values())])
