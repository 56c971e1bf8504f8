"""``associate_scans`` (one call, scans in parallel in the core) against a Python loop over
``associate_static``, same scans, same run: S = 3 sensors, M = 20 targets with misses and
false alarms (the static-association paper's scene), the Lagrangian method by default.

    python3 benches/bench_associate_scans.py [--scans 2000] [--method lagrangian] [--loop-scans 200] [--sensors 3]

Prints scans per second of each (the loop over its first ``--loop-scans`` scans) and checks
that both give the same targets on those scans. The target is ≥ 1000 scans/s on 2 cores with
the Lagrangian method.
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np
import passive_assoc as pa
from passive_assoc.simulation import static_scan


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scans", type=int, default=2000)
    parser.add_argument("--targets", type=int, default=20)
    parser.add_argument("--sensors", type=int, default=3)
    parser.add_argument("--method", default="lagrangian", choices=("intensity", "lagrangian", "exact"))
    parser.add_argument("--loop-scans", type=int, default=200)
    args = parser.parse_args()
    scene = {"n_targets": args.targets, "n_sensors": args.sensors}
    parts = [static_scan(seed, **scene).measurements.to_arrays() for seed in range(args.scans)]
    columns = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    columns["time"] = np.repeat(np.arange(args.scans, dtype=float), [len(p["time"]) for p in parts])
    table, sensors = pa.MeasurementTable.from_columns(columns), static_scan(0, **scene).sensors
    settings: dict[str, Any] = {"exact_backend": "branch_bound"} if args.method == "exact" else {}
    start = time.perf_counter()
    batch = pa.associate_scans(table, sensors, method=args.method, **settings)
    batch_s = time.perf_counter() - start
    loop_n = min(args.loop_scans, args.scans)
    start = time.perf_counter()
    for k in range(loop_n):
        one = pa.associate_static(table.select(np.flatnonzero(table.time == k)), sensors, args.method, **settings)
        mine = np.flatnonzero(batch.target_scan == k)
        assert np.array_equal(one.positions, batch.positions[mine]), f"scan {k} differs"
    loop_s = time.perf_counter() - start
    rate, loop_rate = args.scans / batch_s, loop_n / loop_s
    print(f"S = {args.sensors}, M = {args.targets}, {args.method}, {len(table)} reports in {args.scans} scans")
    print(f"  associate_scans:           {rate:8.0f} scans/s ({batch_s:.2f} s)")
    print(f"  loop over associate_static: {loop_rate:7.0f} scans/s (first {loop_n} scans, same targets)")
    print(f"  ratio: {rate / loop_rate:.2f}x")


if __name__ == "__main__":
    main()
