"""The Lagrangian's end-of-solve polish, on and off, against the optimum (HiGHS) on random
sparse S = 5 and S = 3 problems — the measurement behind ``assign_sd``'s ``polish=True``
default. Figures go to docs/performance.md.

    python benches/bench_polish.py [--instances 20]
"""

from __future__ import annotations

import argparse
import statistics
import time

import passive_assoc as pa
from bench_exact_sd import random_problem
from passive_assoc.assignment.highs import solve_highs

FAMILIES = {"S=5 n=6": (5, 6, 0.02), "S=3 n=20": (3, 20, 0.05)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--instances", type=int, default=20)
    args = parser.parse_args()
    for family, (s, n, density) in FAMILIES.items():
        rows: dict[bool, list[tuple[float, bool, float]]] = {False: [], True: []}
        for seed in range(args.instances):
            t, c, sizes = random_problem(100 + seed, s, n, density)
            _, optimum, _, _, _ = solve_highs(t, c, sizes, 60.0)
            for polish in (False, True):
                start = time.perf_counter()
                result = pa.assign_sd(t, c, sizes, polish=polish)
                seconds = time.perf_counter() - start
                above = (result.primal_cost - optimum) / abs(optimum) * 100
                rows[polish].append((above, abs(result.primal_cost - optimum) < 1e-9, seconds))
        for polish, found in rows.items():
            excess = [a for a, _, _ in found]
            print(
                f"{family} polish={polish}: {statistics.mean(excess):.2f} % above the optimum on average "
                f"(max {max(excess):.2f} %), exact on {sum(e for _, e, _ in found)}/{len(found)}, "
                f"median {statistics.median(t for _, _, t in found) * 1e3:.1f} ms"
            )


if __name__ == "__main__":
    main()
