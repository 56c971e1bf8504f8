"""Exact S-D assignment at scale: the core's branch-and-bound, HiGHS through SciPy (what a user
would otherwise call), and ``assign_sd(method="exact")``'s backends, on the same random sparse
problems in one run. The figures go to docs/performance.md.

Problems: S = 3 with 25 reports per sensor and S = 5 with 8 or 10, each candidate tuple of
two or more reports kept with a fixed probability, costs N(−5, 3²): K ≈ 1 400–1 800 tuples.

    python benches/bench_exact_sd.py [--instances 4] [--bb-time-limit 10]
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

import numpy as np
import passive_assoc as pa
from numpy.typing import NDArray
from passive_assoc.assignment.highs import solve_highs

Problem = tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.int64]]
FAMILIES = {"S=3 n=25": (3, 25, 0.08), "S=5 n=10": (5, 10, 0.01), "S=5 n=8": (5, 8, 0.03)}


def random_problem(seed: int, n_sensors: int, n: int, density: float) -> Problem:
    rng = np.random.default_rng(seed)
    grid = np.stack(np.meshgrid(*[np.arange(n + 1)] * n_sensors, indexing="ij"), -1).reshape(-1, n_sensors)
    grid = grid[(grid > 0).sum(axis=1) >= 2]
    tuples = grid[rng.random(len(grid)) < density]
    return tuples, rng.normal(-5.0, 3.0, len(tuples)), np.full(n_sensors, n)


def timed(solve: Callable[[], tuple[float, bool]]) -> tuple[float, float, bool]:
    start = time.perf_counter()
    cost, proven = solve()
    return time.perf_counter() - start, cost, proven


def run(problem: Problem, bb_limit: float) -> dict[str, tuple[float, float, bool]]:
    t, c, n = problem

    def backend(name: str, limit: float) -> Callable[[], tuple[float, bool]]:
        def solve() -> tuple[float, bool]:
            r = pa.assign_sd(t, c, n, method="exact", exact_backend=name, time_limit=limit)
            return r.primal_cost, r.optimal

        return solve

    def scipy_highs() -> tuple[float, bool]:
        _, primal, _, _, proven = solve_highs(t, c, n, 60.0)
        return primal, proven

    return {
        "branch_bound": timed(backend("branch_bound", bb_limit)),
        "scipy milp (HiGHS)": timed(scipy_highs),
        "exact, highs": timed(backend("highs", 60.0)),
        "exact, auto": timed(backend("auto", 60.0)),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--instances", type=int, default=4, help="problems per family (default 4)")
    parser.add_argument("--bb-time-limit", type=float, default=10.0, help="branch-and-bound limit, s (10)")
    args = parser.parse_args()
    for family, (s, n, density) in FAMILIES.items():
        results = [run(random_problem(seed, s, n, density), args.bb_time_limit) for seed in range(args.instances)]
        print(f"{family}: K = {[len(random_problem(k, s, n, density)[1]) for k in range(args.instances)]}")
        for name in results[0]:
            times = [r[name][0] for r in results]
            proven = sum(r[name][2] for r in results)
            worst = max(r[name][1] - r["scipy milp (HiGHS)"][1] for r in results)
            print(
                f"  {name:<20} proven {proven}/{len(results)}  median {statistics.median(times):7.3f} s"
                f"  max {max(times):7.3f} s  worst cost above HiGHS's {worst:+.4f}"
            )


if __name__ == "__main__":
    main()
