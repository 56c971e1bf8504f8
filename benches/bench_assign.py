"""The 2-D assignment solver against scipy.optimize.linear_sum_assignment, in one run.

Dense uniform random costs, 100x100 and 1000x1000; both solvers see the same matrices.
Prints the best time of each over the repeats (the statistic least disturbed by other load on
a shared machine, as timeit recommends) and the ratio (ours / scipy; the target is <= 1.5).

    python benches/bench_assign.py [--repeats 21]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np
import passive_assoc as pa
from scipy.optimize import linear_sum_assignment


def best_seconds(solve: Callable[[np.ndarray], object], matrices: list[np.ndarray]) -> float:
    times = []
    for c in matrices:
        start = time.perf_counter()
        solve(c)
        times.append(time.perf_counter() - start)
    return float(np.min(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=21)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    print(f"{'size':>10} {'ours':>11} {'scipy':>11} {'ours/scipy':>11}")
    for n in (100, 1000):
        matrices = [rng.uniform(0, 1, (n, n)) for _ in range(args.repeats if n == 100 else max(5, args.repeats // 4))]
        for c in matrices[:3]:  # same optimum, checked on every run of the bench
            _, _, total = pa.linear_assignment(c)
            r, k = linear_sum_assignment(c)
            assert abs(total - c[r, k].sum()) <= 1e-9 * abs(total)
        ours = best_seconds(pa.linear_assignment, matrices)
        theirs = best_seconds(linear_sum_assignment, matrices)
        print(f"{n:>4}x{n:<5} {1e3 * ours:9.3f}ms {1e3 * theirs:9.3f}ms {ours / theirs:11.2f}")


if __name__ == "__main__":
    main()
