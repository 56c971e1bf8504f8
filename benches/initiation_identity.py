"""Whether two builds' fuzzy track initiations agree: dumps the labels, the track states and
the stage counts of 51 initiations (the dense 2-D scenes of ``bearing_only_2d_scenario`` with
3, 5 and 8 targets at Pd 1 and 0.9, the paper's scene at Pd 0.9 over 20 seeds, and 3-D scale scenes of 2-5 sensors,
all with the defaults), then compares with another build's dump. A change that claims to
leave every answer the same is checked this way: run it on the old build with ``--out``, on
the new one with ``--against``.

    PYTHONPATH=<old package> python3 benches/initiation_identity.py --out old.pkl
    python3 benches/initiation_identity.py --against old.pkl
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np
import passive_assoc as pa
from build_dump import dump_and_compare
from passive_assoc.simulation import Scenario
from passive_assoc.simulation.scenario import ConstantVelocityTarget, simulate

PLANAR = [(8, 1.0, 3), (8, 0.9, 2), (5, 0.9, 6), (3, 0.9, 10), (3, 1.0, 6)]  # targets, Pd, seeds
SPATIAL = [(8, 3, 0), (8, 3, 1), (16, 2, 0), (8, 5, 0)]  # targets, sensors, seed


def scale_scene(n_targets: int, n_sensors: int, seed: int) -> Scenario:
    """The scene of ``benches/bench_initiation_scale.py`` (the paper's, grown)."""
    rng = np.random.default_rng(seed)
    sensors = pa.SensorNetwork.spatial([[20e3 * j, 0.0, 0.0] for j in range(n_sensors)], 5e-3, 5e-3)
    speed, heading = rng.uniform(100, 200, n_targets), rng.uniform(-np.pi, np.pi, n_targets)
    states = np.column_stack([
        rng.uniform(0, 20e3 * (n_sensors - 1), n_targets), rng.uniform(1e3, 16e3, n_targets),
        np.full(n_targets, 1e3), speed * np.cos(heading), speed * np.sin(heading), np.zeros(n_targets),
    ])  # fmt: skip
    targets = [ConstantVelocityTarget(s, t0=0.0) for s in states]
    times = [5.0 * j + 15.0 * np.arange(8) for j in range(n_sensors)]
    return simulate(
        sensors, targets, times, clutter_per_scan=2 * n_targets, azimuth_window=(0, np.pi),
        elevation_window=(0, np.pi / 2), t0=0.0, seed=seed,
    )  # fmt: skip


def scenes() -> list[Scenario]:
    out = [
        pa.bearing_only_2d_scenario(seed, n_targets=n, n_sensors=3, clutter_ratio=2, pd=pd)
        for n, pd, seeds in PLANAR
        for seed in range(seeds)
    ]
    out += [pa.paper_fti_scenario(seed=seed, pd=0.9) for seed in range(20)]
    return out + [scale_scene(*case) for case in SPATIAL]


def initiations(order: str | None = None) -> list[tuple[Any, ...]]:
    """Each scene's initiation; ``order`` is the detection order, passed only when given (so a
    build without the option runs too)."""
    options: dict[str, Any] = {} if order is None else {"detection_order": order}
    out = []
    for scene in scenes():
        r = pa.FuzzyTrackInitiator(**options).initiate(scene.measurements, scene.sensors, t0=0.0)
        states = [t.state.tolist() for t in r.tracks]
        out.append((r.labels.tolist(), states, r.diagnostics.stage_counts))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write this build's initiations here")
    parser.add_argument("--against", help="compare this build's initiations with a dump")
    parser.add_argument("--detection-order", help="the initiator's detection_order (default: its default)")
    args = parser.parse_args()
    start = time.perf_counter()
    mine = initiations(args.detection_order)
    print(f"{len(mine)} initiations in {time.perf_counter() - start:.1f} s")
    dump_and_compare(mine, args.out, args.against, "initiations", "labels, states or stage counts")


if __name__ == "__main__":
    main()
