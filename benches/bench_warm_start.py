"""The Lagrangian solver with its inner 2-D solves warm-started against cold, in one run.

On the `reproduce intensity` scans (EXPERIMENTS.md geometry, R = 15), S = 3 and 4: the same
enumerated candidates go to ``assign_sd(..., warm_start="always")`` and ``"never"``, both with
``polish=False`` (the configuration of docs/performance.md's warm-start table), interleaved,
best of the repeats per scan; printed per (S, M): the median over the scans of each time and of
the ratio warm / cold. This is the evidence for ``warm_start="auto"`` (warm for S = 3 from 50
reports on the first two sensors).

    python benches/bench_warm_start.py [--scans 5] [--repeats 3]
"""

from __future__ import annotations

import argparse
import time
from typing import Literal

import numpy as np
import passive_assoc as pa
from passive_assoc.simulation import static_scan
from passive_assoc.static_los import Candidates, enumerate_candidates

CASES = [(3, 18), (3, 50), (3, 100), (4, 50), (4, 100)]


def best_seconds(cands: Candidates, warm_start: Literal["always", "never"], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        pa.assign_sd(cands.tuples, cands.costs, cands.sizes, warm_start=warm_start, polish=False)
        times.append(time.perf_counter() - start)
    return float(np.min(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scans", type=int, default=5)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print(f"{'S':>2} {'M':>4} {'warm ms':>9} {'cold ms':>9} {'warm/cold':>10}   (medians over {args.scans} scans)")
    for n_sensors, n_targets in CASES:
        warm, cold, ratio = [], [], []
        for k in range(args.scans):
            scan = static_scan(
                2026 + 7 * n_targets + n_sensors + 1000 * k, n_targets=n_targets, n_sensors=n_sensors, ratio=15.0
            )
            cands = enumerate_candidates(scan.measurements, scan.sensors)
            w, c = np.inf, np.inf
            for _ in range(2):  # interleaved, so both see the same machine
                w = min(w, best_seconds(cands, "always", args.repeats))
                c = min(c, best_seconds(cands, "never", args.repeats))
            warm.append(w)
            cold.append(c)
            ratio.append(w / c)
        print(
            f"{n_sensors:>2} {n_targets:>4} {1e3 * np.median(warm):>9.2f} {1e3 * np.median(cold):>9.2f} "
            f"{np.median(ratio):>10.2f}"
        )


if __name__ == "__main__":
    main()
