"""Which static-association method (METHODS §2) is right most often: ``intensity``,
``lagrangian`` or ``exact``, each with the library's other defaults, on the shipped example
(``examples/associate_*.csv``: three scans of 5 targets) and on simulated scans of
:func:`passive_assoc.simulation.static_scan` (3-5 sensors on a shallow arc, not on a line;
Pd < 1; false bearings). Prints one table: scene x method -> targets found exactly (the
located target holds every report of one true target and nothing else), found pure (reports
of one true target only, perhaps not all of them), false targets (a located target holding a
false bearing or reports of two targets) and the time per scan; then the totals over the
simulated scenes, with the share of declared targets (pure + false) that are exactly right.
The denominator is the targets seen by at least two sensors. ``associate``'s default method is chosen from this table.

    python3 benches/static_method_choice.py [--scans 20] [--threads 1]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import passive_assoc as pa
from passive_assoc.simulation import static_scan
from passive_assoc.static_los import Method

METHODS: tuple[Method, ...] = ("intensity", "lagrangian", "exact")
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
#: (label, static_scan keywords) of the simulated scenes.
SCENES = [
    ("M=5 S=3 Pd=.95", dict(n_targets=5, n_sensors=3)),
    ("M=10 S=3 Pd=.95", dict(n_targets=10, n_sensors=3)),
    ("M=10 S=4 Pd=.8", dict(n_targets=10, n_sensors=4, pd=0.8)),
    ("M=20 S=3 Pd=.9", dict(n_targets=20, n_sensors=3, pd=0.9)),
    ("M=10 S=5 Pd=.8", dict(n_targets=10, n_sensors=5, pd=0.8)),
    ("M=10 S=3 Pd=.9 R=5", dict(n_targets=10, n_sensors=3, pd=0.9, ratio=5.0)),
]


def score(labels: np.ndarray, truth: np.ndarray) -> tuple[int, int, int, int]:
    """(observable targets, found exactly, found pure, false targets) of one scan."""
    targets, counts = np.unique(truth[truth >= 0], return_counts=True)
    observable = int(np.sum(counts >= 2))
    exact = pure = false = 0
    for t in np.unique(labels[labels >= 0]):
        held = truth[labels == t]
        if held[0] >= 0 and np.all(held == held[0]):
            pure += 1
            exact += int(len(held) == counts[targets == held[0]][0])
        else:
            false += 1
    return observable, exact, pure, false


def run(scans: list[tuple[pa.MeasurementTable, pa.SensorNetwork]], method: Method, threads: int) -> list[float]:
    """[observable, exact, pure, false, seconds per scan] summed over ``scans``."""
    totals = np.zeros(4)
    seconds = 0.0
    for table, sensors in scans:
        start = time.perf_counter()
        found = pa.associate_static(table, sensors, method, n_threads=threads)
        seconds += time.perf_counter() - start
        assert table.truth is not None
        totals += score(found.labels, table.truth)
    return [*totals.tolist(), seconds / len(scans)]


def example_scans() -> list[tuple[pa.MeasurementTable, pa.SensorNetwork]]:
    table = pa.MeasurementTable.from_csv(EXAMPLES / "associate_measurements.csv")
    sensors = pa.SensorNetwork.from_csv(EXAMPLES / "associate_sensors.csv")
    return [(table.select(np.flatnonzero(table.time == t)), sensors) for t in np.unique(table.time)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scans", type=int, default=20, help="simulated scans per scene (seeds 0..N-1)")
    parser.add_argument("--threads", type=int, default=1, help="n_threads of every call")
    args = parser.parse_args()
    scenes: list[tuple[str, list[tuple[pa.MeasurementTable, pa.SensorNetwork]]]] = [
        ("shipped example (3 scans)", example_scans())
    ]
    for label, keywords in SCENES:
        simulated = [static_scan(seed, **keywords) for seed in range(args.scans)]  # type: ignore[arg-type]
        scenes.append((f"{label} ({args.scans} scans)", [(s.measurements, s.sensors) for s in simulated]))
    print(f"{'scene':<30} {'method':<10} {'exact':>11} {'pure':>11} {'false':>6} {'ms/scan':>9}")
    totals = {method: np.zeros(5) for method in METHODS}
    for k, (label, scans) in enumerate(scenes):
        rows = {method: run(scans, method, args.threads) for method in METHODS}
        best = max(rows[m][1] for m in METHODS)
        for method, row in rows.items():
            if k > 0:  # a simulated scene
                totals[method] += [*row[:4], row[4] * len(scans)]
            print(line(label, method, row) + (" *" if row[1] == best else ""))
    print("* finds the most targets exactly on the scene")
    n_scans = args.scans * len(SCENES)
    for method, (observable, exact, pure, false, seconds) in totals.items():
        declared = pure + false
        print(
            line("all simulated scenes", method, [observable, exact, pure, false, seconds / n_scans])
            + f"  {100 * exact / observable:.1f} % of targets, {100 * exact / declared:.1f} % of declared ones"
        )


def line(label: str, method: str, row: list[float]) -> str:
    observable, exact, pure, false, seconds = row
    return (
        f"{label:<30} {method:<10} {exact:>4.0f} of {observable:<4.0f}{pure:>4.0f} of {observable:<4.0f}"
        f"{false:>5.0f} {1e3 * seconds:>9.2f}"
    )


if __name__ == "__main__":
    main()
