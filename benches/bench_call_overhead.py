"""The fixed cost of a compiled call on a tiny input (target ≤ 15 µs), with the default thread
count and with ``n_threads=1`` (the call runs on the calling thread), and of a tiny static scan
end to end (target ≤ 80 µs with default settings). Prints µs per call, the median of 5 batches.

    python3 benches/bench_call_overhead.py [--calls 3000]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np
import passive_assoc as pa
from passive_assoc import _core
from passive_assoc.assignment.sd import SdParameters
from passive_assoc.data.attributes import attribute_evidence
from passive_assoc.simulation import static_scan
from passive_assoc.static_los import Method


def per_call(work: Callable[[], object], calls: int) -> float:
    """Median over 5 batches of the mean µs per call."""
    work()
    batches = []
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(calls):
            work()
        batches.append((time.perf_counter() - start) / calls * 1e6)
    return float(np.median(batches))


def with_threads(call: Callable[[int | None], object], n_threads: int | None) -> Callable[[], object]:
    """``call(n_threads)`` as a call of no arguments."""
    return lambda: call(n_threads)


def scan_call(
    table: pa.MeasurementTable, sensors: pa.SensorNetwork, method: Method, n_threads: int | None
) -> Callable[[], object]:
    """``associate_static`` of one scan as a call of no arguments."""
    return lambda: pa.associate_static(table, sensors, method, n_threads=n_threads)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=3000)
    args = parser.parse_args()
    scan = static_scan(1, n_targets=2, n_sensors=3)
    table, sensors = scan.measurements, scan.sensors
    cands = pa.enumerate_candidates(table, sensors)
    sd = SdParameters()
    evidence = attribute_evidence(table, sensors, (), None, 0.6, "simple")
    pd, density = np.full(3, 0.95), np.full(3, 0.5)
    costs = np.random.default_rng(0).random((10, 10))
    times, z = np.arange(5.0), np.arange(5.0)[:, None] * 10.0
    print(f"compiled calls on tiny inputs, µs per call ({args.calls} calls, median of 5 batches):")
    print(f"{'call':<42} {'n_threads=None':>15} {'n_threads=1':>12}")
    per_thread_count: tuple[tuple[str, Callable[[int | None], object]], ...] = (
        (
            "_core.enumerate_static (3 sensors, 2 targets)",
            lambda n: _core.enumerate_static(table, sensors, pd, density, pa.StaticAssociator(n_threads=n), evidence),
        ),
        (
            "KalmanFilter.filter (one 5-row track)",
            lambda n: pa.KalmanFilter(process_noise=1.0, n_threads=n).filter(times, z, np.arange(5), noise=1.0),
        ),
    )
    for label, call in per_thread_count:
        print(
            f"{label:<42} {per_call(with_threads(call, None), args.calls):>15.1f} "
            f"{per_call(with_threads(call, 1), args.calls):>12.1f}"
        )
    for label, single in (
        (
            "_core.assign_sd (16 candidate tuples)",
            lambda: _core.assign_sd(cands.tuples, cands.costs, cands.sizes, "lagrangian", sd),
        ),
        ("_core.assign_2d (10 × 10)", lambda: _core.assign_2d(costs)),
        ("linear_assignment (10 × 10)", lambda: pa.linear_assignment(costs)),
    ):
        print(f"{label:<42} {per_call(single, args.calls):>15.1f} {'-':>12}")
    print("\na tiny static scan end to end (associate_static, default settings):")
    method: Method
    for method in ("intensity", "lagrangian", "exact"):
        for n_threads in (None, 1):
            cost = per_call(scan_call(table, sensors, method, n_threads), args.calls)
            print(f"  {method:<11} n_threads={n_threads!s:<5} {cost:7.1f} µs")


if __name__ == "__main__":
    main()
