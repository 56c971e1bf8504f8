"""How often the Lagrangian method gets a hand-written scan right under each false-alarm density:
the paper's three sensors, three well-separated targets (2 mrad noise) and one false alarm on
one sensor, 300 trials. Counts the trials that end with the three targets, each seen by all
three sensors, and the false alarm as clutter, with the library's default false-alarm density
(the larger of p_false · n and the sensor's report excess over the median sensor, per span),
with the fraction alone (p_false · n / span), with the fraction floored at one false alarm per
sensor sector (max(p_false · n, 1) / span), and with fixed densities.

    python3 benches/bench_false_alarm_density.py [--trials 300]
"""

from __future__ import annotations

import argparse
import collections

import numpy as np
import passive_assoc as pa


def per_span(table: pa.MeasurementTable, n_sensors: int, false_alarms: np.ndarray) -> np.ndarray:
    """``false_alarms`` per sensor over the bearing span of its reports (as the default)."""
    spans = np.array([np.ptp(table.azimuth[table.sensor == j]) for j in range(n_sensors)])
    density: np.ndarray = false_alarms / np.maximum(spans, 1e-3)
    return density


def fraction(table: pa.MeasurementTable, n_sensors: int, floor: float, p_false: float = 0.05) -> np.ndarray:
    """max(p_false · n, floor) / span per sensor."""
    counts = np.bincount(table.sensor, minlength=n_sensors)
    return per_span(table, n_sensors, np.maximum(p_false * np.maximum(counts, 1), floor))


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
        variants = (
            ("default", None),
            ("fraction", fraction(table, 3, 0.0)),
            ("floored", fraction(table, 3, 1.0)),
            ("1.0", 1.0),
            ("3.0", 3.0),
        )
        for name, density in variants:
            r = pa.associate_static(table, sensors, "lagrangian", false_alarm_density=density)
            full = int(np.sum((r.rows >= 0).sum(axis=1) == 3))
            right[name] += len(r.positions) == 3 and full == 3 and r.clutter.tolist() == [9]
    for name in ("default", "fraction", "floored", "1.0", "3.0"):
        print(f"{name:>8}: three full targets and the false alarm as clutter in {right[name]}/{args.trials}")


if __name__ == "__main__":
    main()
