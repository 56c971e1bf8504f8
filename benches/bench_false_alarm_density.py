"""Issue 16's hand-written case: the paper's three sensors, three well-separated targets
(2 mrad noise) and one false alarm on one sensor, 300 trials. Counts the Lagrangian's
outcomes with the default false-alarm density (p_false · n / span), with the same formula
floored at one false alarm per sensor sector (max(p_false · n, 1) / span, passed explicitly:
a candidate default, not the library's), and with fixed densities.

    python3 benches/bench_false_alarm_density.py [--trials 300]
"""

from __future__ import annotations

import argparse
import collections

import numpy as np
import passive_assoc as pa
from passive_assoc.static_los.batch import default_density_per_scan


def floored(table: pa.MeasurementTable, n_sensors: int, p_false: float = 0.05) -> np.ndarray:
    """max(p_false · n, 1) / span per sensor: the default with at least one false alarm."""
    default = default_density_per_scan(table, np.zeros(len(table), np.int64), 1, n_sensors, p_false)[0]
    counts = np.bincount(table.sensor, minlength=n_sensors)
    span = p_false * np.maximum(counts, 1) / default  # the default's area, recovered
    return np.maximum(p_false * counts, 1.0) / span


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=300)
    args = parser.parse_args()
    sensors = pa.SensorNetwork.planar([[-15e3, 0], [0, -5e3], [15e3, 0]], 2e-3)
    targets = np.array([[-5e3, 25e3], [0, 35e3], [6e3, 30e3]])
    rng = np.random.default_rng(0)
    right: collections.Counter[str] = collections.Counter()
    for _ in range(args.trials):
        rows = [
            (j, np.arctan2(*(t - p)[::-1]) + rng.normal(0, 2e-3))
            for j, p in enumerate(sensors.positions[:, :2])
            for t in targets
        ]
        j = int(rng.integers(3))
        own = [a for s, a in rows if s == j]
        rows.append((j, rng.uniform(min(own) - 0.2, max(own) + 0.2)))
        s, a = np.array(rows).T
        table = pa.MeasurementTable.from_arrays(s.astype(int), np.zeros(len(s)), a)
        for name, density in (("default", None), ("floored", floored(table, 3)), ("1.0", 1.0), ("3.0", 3.0)):
            r = pa.associate_static(table, sensors, "lagrangian", false_alarm_density=density)
            full = int(np.sum((r.tuples >= 0).sum(axis=1) == 3))
            right[name] += len(r.positions) == 3 and full == 3 and r.clutter.tolist() == [9]
    for name in ("default", "floored", "1.0", "3.0"):
        print(f"{name:>8}: three full targets and the false alarm as clutter in {right[name]}/{args.trials}")


if __name__ == "__main__":
    main()
