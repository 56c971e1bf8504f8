"""The Lagrangian S-D solver per scan on one thread: 400 scans of the static-association
paper's scene, S = 3, M = 20 (60 reports a scan; ``--sensors`` and ``--targets`` change
them), through ``associate_scans`` (the whole loop
in Rust, so the figure is the solver's, not Python's). Prints ms per scan and the mean
iterations; ``perf record python3 benches/bench_lagrangian_scans.py`` profiles it. With
``--solver-only`` it times ``assign_sd`` alone on the scans' enumerated candidates (one call
per scan, the polish on as by default), so enumeration is left out. ``--dump FILE`` writes
those candidates for ``benches/lagrangian_profile.rs`` (the solver without Python, for
callgrind) and times nothing.

    python3 benches/bench_lagrangian_scans.py [--scans 400] [--repeat 3] [--solver-only]
    python3 benches/bench_lagrangian_scans.py --scans 100 [--targets 20] [--sensors 3] --dump FILE
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import passive_assoc as pa
from passive_assoc.simulation import static_scan


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scans", type=int, default=400)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--targets", type=int, default=20, help="targets (M) per scan")
    parser.add_argument("--sensors", type=int, default=3, help="sensors (S)")
    parser.add_argument("--solver-only", action="store_true", help="time assign_sd alone")
    parser.add_argument("--dump", metavar="FILE", help="write the enumerated candidates for lagrangian_profile.rs")
    args = parser.parse_args()
    if args.dump:
        dump(args.scans, args.targets, args.dump, args.sensors)
        return
    if args.solver_only:
        solver_only(args.scans, args.targets, args.repeat, args.sensors)
        return
    scene = {"n_targets": args.targets, "n_sensors": args.sensors}
    parts = [static_scan(seed, **scene).measurements.to_arrays() for seed in range(args.scans)]
    columns = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    columns["time"] = np.repeat(np.arange(float(args.scans)), [len(p["time"]) for p in parts])
    table, sensors = pa.MeasurementTable.from_columns(columns), static_scan(0, **scene).sensors
    best = float("inf")
    for _ in range(args.repeat):
        start = time.perf_counter()
        pa.associate_scans(table, sensors, method="lagrangian", n_threads=1)
        best = min(best, time.perf_counter() - start)
    iterations = []
    for seed in range(min(args.scans, 100)):
        scan = static_scan(seed, **scene)
        c = pa.enumerate_candidates(scan.measurements, scan.sensors)
        iterations.append(pa.assign_sd(c.tuples, c.costs, c.sizes).iterations)
    per_scan = best / args.scans * 1e3
    print(f"{per_scan:.2f} ms a scan (best of {args.repeat}); {np.mean(iterations):.0f} iterations on average")


def enumerated(n_scans: int, n_targets: int, n_sensors: int = 3) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    problems = []
    for seed in range(n_scans):
        scan = static_scan(seed, n_targets=n_targets, n_sensors=n_sensors)
        c = pa.enumerate_candidates(scan.measurements, scan.sensors)
        problems.append((np.asarray(c.tuples), np.asarray(c.costs, dtype=np.float64), np.asarray(c.sizes)))
    return problems


def dump(n_scans: int, n_targets: int, path: str, n_sensors: int = 3) -> None:
    """Per problem: `S sizes... n_tuples`, the flat tuples, the costs as f64 bit patterns."""
    with open(path, "w") as f:
        for tuples, costs, sizes in enumerated(n_scans, n_targets, n_sensors):
            f.write(f"{len(sizes)} {' '.join(map(str, sizes.tolist()))} {len(costs)}\n")
            f.write(" ".join(map(str, tuples.ravel().tolist())) + "\n")
            f.write(" ".join(map(str, costs.view(np.uint64).tolist())) + "\n")
    print(f"{n_scans} problems written to {path}")


def solver_only(n_scans: int, n_targets: int, repeat: int, n_sensors: int = 3) -> None:
    problems = enumerated(n_scans, n_targets, n_sensors)
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        results = [pa.assign_sd(*p) for p in problems]
        best = min(best, time.perf_counter() - start)
    iterations = np.mean([r.iterations for r in results])
    primal = sum(r.primal_cost for r in results)
    per_solve = best / n_scans * 1e3
    print(f"{per_solve:.2f} ms a solve (best of {repeat}); {iterations:.0f} iterations on average;", end=" ")
    print(f"primal costs sum to {primal:.9f}")


if __name__ == "__main__":
    main()
