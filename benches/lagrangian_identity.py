"""The Lagrangian S-D solver's answer quality on the ``associate_scans`` benchmark's scans
(S = 3, M = 20, the simulator's misses and clutter, about 60 reports a scan), with the default
settings: the mean primal cost, the mean relative duality gap, and the fraction of scans whose
primal is the proven optimum (HiGHS, ``exact_backend="highs"``, no time limit), each with its
Monte-Carlo standard error; and how far above that optimum the primal is. A change to the
solver's iterates (2-D solver, start, step rule, order) keeps its answers when, against the
build before it, the mean primal is no higher, the mean gap no wider and the optimum fraction
no lower, each within its error; the paired differences (same scans) are printed with theirs.

    python3 benches/lagrangian_identity.py --out before.pkl            # on the older build
    python3 benches/lagrangian_identity.py --against before.pkl         # on the newer one

The optimum of each scan does not depend on the build; it is computed once (about 2 s a scan
on one core) and kept in ``--optimum-cache``, for the first ``--optimum-scans`` scans.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import os
import pickle
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np
import passive_assoc as pa
from passive_assoc.simulation import static_scan


def candidates(seed: int, n_targets: int, n_sensors: int) -> Any:
    scan = static_scan(seed, n_targets=n_targets, n_sensors=n_sensors)
    return pa.enumerate_candidates(scan.measurements, scan.sensors)


def lagrangian(seed: int, n_targets: int, n_sensors: int) -> tuple[float, float, float]:
    """The default Lagrangian's primal cost, relative gap and dual bound on one scan."""
    c = candidates(seed, n_targets, n_sensors)
    r = pa.assign_sd(c.tuples, c.costs, c.sizes)
    return r.primal_cost, r.gap, r.dual_bound


def optimum(seed: int, n_targets: int, n_sensors: int) -> float:
    """The scan's proven optimum (HiGHS without a time limit)."""
    c = candidates(seed, n_targets, n_sensors)
    r = pa.assign_sd(c.tuples, c.costs, c.sizes, method="exact", exact_backend="highs")
    if not r.optimal:
        raise RuntimeError(f"scan {seed}: HiGHS did not prove its optimum ({r.termination})")
    return r.primal_cost


def mean_and_error(values: np.ndarray[Any, Any]) -> tuple[float, float]:
    return float(values.mean()), float(values.std(ddof=1) / math.sqrt(len(values)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scans", type=int, default=1000)
    parser.add_argument("--targets", type=int, default=20)
    parser.add_argument("--sensors", type=int, default=3)
    parser.add_argument("--optimum-scans", type=int, default=200)
    parser.add_argument("--optimum-cache", default="lagrangian_optima.pkl")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--out", help="write this build's per-scan figures here")
    parser.add_argument("--against", help="compare this build's figures with such a file")
    args = parser.parse_args()
    shape = (args.targets, args.sensors)
    seeds = list(range(args.scans))
    rows = np.array([lagrangian(seed, *shape) for seed in seeds])
    primal, gap = rows[:, 0], rows[:, 1]
    cache: dict[tuple[int, int, int], float] = {}
    if os.path.exists(args.optimum_cache):
        with open(args.optimum_cache, "rb") as f:
            cache = pickle.load(f)
    todo = [s for s in seeds[: args.optimum_scans] if (*shape, s) not in cache]
    if todo:
        # spawn: a forked child of a process whose thread pool is running can deadlock.
        with ProcessPoolExecutor(args.workers, mp_context=multiprocessing.get_context("spawn")) as pool:
            for seed, found in zip(
                todo, pool.map(optimum, todo, [shape[0]] * len(todo), [shape[1]] * len(todo)), strict=True
            ):
                cache[(*shape, seed)] = found
        with open(args.optimum_cache, "wb") as f:
            pickle.dump(cache, f)
    n_opt = min(args.optimum_scans, args.scans)
    best = np.array([cache[(*shape, s)] for s in seeds[:n_opt]])
    at_optimum = (primal[:n_opt] <= best + 1e-9 * np.maximum(1.0, np.abs(best))).astype(float)
    figures = {"primal": primal, "gap": gap, "at_optimum": at_optimum}
    print(f"S = {args.sensors}, M = {args.targets}: {args.scans} scans ({n_opt} with the proven optimum)")
    for name, values in figures.items():
        m, e = mean_and_error(values)
        print(f"  {name:11s} mean {m:12.6f} ± {e:.6f}")
    # How far the primal is from the optimum where it misses it (not a comparison figure).
    above = primal[:n_opt] - best
    m, e = mean_and_error(above)
    print(f"  above the optimum: mean {m:.6f} ± {e:.6f}, largest {above.max():.6f} ({n_opt} scans)")
    if args.out:
        with open(args.out, "wb") as f:
            pickle.dump(figures, f)
    if args.against:
        with open(args.against, "rb") as f:
            theirs = pickle.load(f)
        print(
            "  this build − the other (paired over the same scans; worse when above +2σ, or below −2σ for at_optimum):"
        )
        for name, values in figures.items():
            n = min(len(values), len(theirs[name]))
            m, e = mean_and_error(values[:n] - theirs[name][:n])
            print(f"  {name:11s} {m:+12.6f} ± {e:.6f}")


if __name__ == "__main__":
    main()
