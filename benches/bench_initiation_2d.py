"""The 2-D bearing-only initiation of issue 16: ``bearing_only_2d_scenario(3, n_targets=N,
n_sensors=3, clutter_ratio=2)`` with the default `FuzzyTrackInitiator`, with and without the
support gate. Prints the time, the tracks, how many rows of each track are one target's, and
the stage counts.

    python3 benches/bench_initiation_2d.py [--targets 5 8] [--no-gate-too]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import passive_assoc as pa


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--targets", type=int, nargs="+", default=[5, 8])
    parser.add_argument("--no-gate-too", action="store_true", help="also run with support_gate=False (slow)")
    args = parser.parse_args()
    for n in args.targets:
        scenario = pa.bearing_only_2d_scenario(3, n_targets=n, n_sensors=3, clutter_ratio=2)
        for gate in (True, False) if args.no_gate_too else (True,):
            start = time.perf_counter()
            result = pa.FuzzyTrackInitiator(support_gate=gate).initiate(scenario.measurements, scenario.sensors)
            seconds = time.perf_counter() - start
            truth = scenario.measurements.truth
            assert truth is not None
            kinds = []
            for track in result.tracks:
                labels, counts = np.unique(truth[track.measurements], return_counts=True)
                kinds.append(f"{int(labels[np.argmax(counts)])}:{counts.max()}/{len(track.measurements)}")
            print(
                f"{n} targets, {len(scenario.measurements)} rows, support_gate={gate}: {seconds:.2f} s, "
                f"{len(result.tracks)} tracks (majority target:rows) {' '.join(kinds)}"
            )
            print(f"  stage counts {result.diagnostics.stage_counts}")


if __name__ == "__main__":
    main()
