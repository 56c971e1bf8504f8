"""The initiation's track test at several tails: the paper's lines (100 runs each: Pd 1, 0.9,
0.8 and clutter 8x) and 2-D scenes of 3 sensors (5 targets over 8 scans, 3 targets over 5
scans; 20 seeds each), as targets found and other tracks.

    python3 benches/bench_track_test.py [--tails 1e-6 1e-4 1e-3]
"""

from __future__ import annotations

import argparse

import passive_assoc as pa
from passive_assoc.evaluation import track_targets
from passive_assoc.experiments.fti import run_experiment, summarise
from passive_assoc.fti import FuzzyTrackInitiator


def planar(initiator: FuzzyTrackInitiator, n: int, pd: float, seeds: int, n_scans: int) -> tuple[int, int]:
    """Targets found (:func:`passive_assoc.evaluation.track_targets`) and other tracks, over seeds."""
    found = extra = 0
    for seed in range(seeds):
        scene = pa.bearing_only_2d_scenario(seed, n_targets=n, n_sensors=3, clutter_ratio=2, pd=pd, n_scans=n_scans)
        assert scene.measurements.truth is not None
        result = initiator.initiate(scene.measurements, scene.sensors)
        held = track_targets(result.labels, scene.measurements.truth)
        distinct = len(set(held.tolist()) - {-1})
        found, extra = found + distinct, extra + len(held) - distinct
    return found, extra


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tails", type=float, nargs="+", default=[1e-6, 1e-4, 1e-3])
    args = parser.parse_args()
    for tail in args.tails:
        initiator = FuzzyTrackInitiator(track_test=tail)
        print(f"track_test={tail:g}")
        for pd, clutter in ((1.0, 2.0), (0.9, 2.0), (0.8, 2.0), (1.0, 8.0)):
            runs, _, _, crlbs = run_experiment(100, 2026, 1, pd, clutter, initiator)
            s = summarise(runs, crlbs)
            print(
                f"  paper Pd {pd} clutter {clutter:g}x: all found {s['all_found_runs']}/100, "
                f"false {s['mean_false_tracks']:.3f}, placed {100 * s['mean_correct_fraction']:.2f} %"
            )
        for n, n_scans in ((5, 8), (3, 5)):
            for pd in (1.0, 0.9):
                found, extra = planar(initiator, n, pd, 20, n_scans)
                print(f"  2-D {n} targets x {n_scans} scans, Pd {pd}: {found}/{20 * n} found, {extra} other tracks")


if __name__ == "__main__":
    main()
