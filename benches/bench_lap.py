"""``linear_assignment`` against the assignment solvers a Python user would otherwise reach for,
in one run, on the same matrices: ``scipy.optimize.linear_sum_assignment``, ``lap.lapjv`` and
``lapjv.lapjv`` (dense), ``lap.lapmod`` (sparse). ``lap`` and ``lapjv`` are benchmark-only
dependencies (``pip install lap lapjv``); a solver that is missing is skipped.

Cases (uniform random costs in [0, 1), seeds fixed): dense 10², 100², 1000², 3000²; gated
1000² and 3000² with 2 % of the entries allowed (plus the diagonal, so a complete assignment
exists) — ours on the SciPy sparse matrix and on the dense matrix with +inf. Prints the best
mean time of each and ours ÷ the fastest competitor; checks that every solver found the same
optimum. Only each solver's own call is timed: the total cost of its answer, which some
return and others leave to the caller, is summed outside the timed loop. Each figure is a mean
over several random matrices of the size (50 up to 100², 5 at 1000², 2 at 3000²), the best of
the repeats.

Not every competitor solves the problem it is given: ``lapjv`` (1.3) casts a float64 matrix to
float32 and solves that (its duals come back as float32), so where costs differ by less than
float32 resolves (1000 + 10⁻³·U at 100², checked first and printed) its answer is not the
optimum. Its uniform [0, 1) rows find the same optimum as the others, but the work timed is
single precision; each ratio is therefore given twice, against the fastest competitor and
against the fastest that found the optimum of the float64 check. ``ours (float32)`` is ours
on the same matrix cast to float32 first (the cast untimed): the input ``lapjv`` solves, read
at half the bytes, but solved exactly (its total is summed on the float64 matrix).

    python3 benches/bench_lap.py [--repeats 5] [--sizes 10 100 1000 3000]
    python3 benches/bench_lap.py --densities [--sizes 300 1000 3000]   # where the sparse path stops paying

``--densities`` times, at 1000² (or each of ``--sizes``), our sparse solve on the allowed
entries against our dense solve of the same matrix with the forbidden entries priced at 10⁶
instead of +inf (the dense path's cost: both get Jonker & Volgenant's start), for a range of
allowed shares, three matrices each: the crossover sets the share below which a dense matrix
with +inf is solved sparse (``sparse_max_share`` in ``rust/core/src/assign/lap/mod.rs``). The
``+inf`` column is the matrix with the forbidden entries at +inf, solved by the path that rule
picks (the sparse one after a pass to gather the allowed entries, or the dense one).
"""

from __future__ import annotations

import argparse
import functools
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import passive_assoc as pa
import scipy.sparse as sp
from scipy.optimize import linear_sum_assignment

try:
    import lap
except ImportError:  # benchmark-only dependency
    lap = None
try:
    import lapjv
except ImportError:
    lapjv = None


def best(solve: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    out, times = None, []
    for _ in range(repeats):
        start = time.perf_counter()
        out = solve()
        times.append(time.perf_counter() - start)
    return min(times), out


#: A solver: the call that is timed, and how the total cost is read from its answer (untimed).
Solver = tuple[Callable[[], Any], Callable[[Any], float]]


def dense_solvers(c: np.ndarray) -> dict[str, Solver]:
    def pairs_total(out: Any) -> float:
        return float(c[out[0], out[1]].sum())

    c32 = c.astype(np.float32)
    solvers: dict[str, Solver] = {
        "ours": (lambda: pa.linear_assignment(c), lambda out: float(out[2])),
        "ours (float32)": (lambda: pa.linear_assignment(c32), pairs_total),
        "scipy": (lambda: linear_sum_assignment(c), pairs_total),
    }
    if lap is not None:
        solvers["lap.lapjv"] = (lambda: lap.lapjv(c, extend_cost=True), lambda out: float(out[0]))
    if lapjv is not None:
        solvers["lapjv"] = (lambda: lapjv.lapjv(c), lambda out: float(c[np.arange(len(c)), out[0]].sum()))
    return solvers


def gated_solvers(c: np.ndarray, allowed: np.ndarray) -> dict[str, Solver]:
    n = len(c)
    gated = np.where(allowed, c, np.inf)
    csr = sp.csr_array(np.where(allowed, c, 0.0))
    csr.eliminate_zeros()  # uniform costs are never exactly 0, so only the gated-out go
    rows, cols = np.nonzero(allowed)
    solvers: dict[str, Solver] = {
        "ours (sparse)": (lambda: pa.linear_assignment(csr), lambda out: float(out[2])),
        "ours (dense +inf)": (lambda: pa.linear_assignment(gated), lambda out: float(out[2])),
        "scipy": (lambda: linear_sum_assignment(gated), lambda out: float(gated[out].sum())),
    }
    if lap is not None:
        first = np.searchsorted(rows, np.arange(n + 1)).astype(np.int32)
        values, kk = np.ascontiguousarray(c[rows, cols]), cols.astype(np.int32)
        solvers["lap.lapmod"] = (lambda: lap.lapmod(n, values, first, kk), lambda out: float(out[0]))
    return solvers


def exact_in_float64(n: int = 100) -> set[str]:
    """The dense solvers whose answer is the optimum where costs differ by less than float32
    resolves (1000 + 10⁻³·U): those solving in double precision. Prints each one's excess."""
    c = 1000.0 + np.random.default_rng(7).random((n, n)) * 1e-3
    optimum = float(c[linear_sum_assignment(c)].sum())
    exact = set()
    for name, (solve, total) in dense_solvers(c).items():
        excess = total(solve()) - optimum
        print(f"float64 check {n}², 1000 + 1e-3·U: {name} above the optimum by {excess:.3g}")
        if excess <= 1e-9 * optimum:
            exact.add(name)
    return exact


def report(label: str, cases: list[dict[str, Solver]], repeats: int, exact: set[str] | None = None) -> None:
    """Each solver's best over `repeats` of its mean time per matrix over `cases` (one dict of
    solvers per matrix): solve times vary by tens of percent between random matrices of one
    size, so one matrix can flatter or wrong any solver."""
    times: dict[str, float] = {}
    for name in cases[0]:
        per_repeat = []
        for _ in range(repeats):
            start = time.perf_counter()
            for case in cases:
                case[name][0]()
            per_repeat.append((time.perf_counter() - start) / len(cases))
        times[name] = min(per_repeat)
    for case in cases:
        totals = {name: total(solve()) for name, (solve, total) in case.items()}
        reference = totals["scipy"]
        for name, value in totals.items():
            assert abs(value - reference) <= 1e-9 * max(1.0, abs(reference)), (label, name, value, reference)
    ours = [k for k in times if k.startswith("ours")]
    rivals = {k: v for k, v in times.items() if not k.startswith("ours")}
    fastest = min(rivals, key=rivals.__getitem__)
    cells = "  ".join(f"{k} {v * 1e3:.4f} ms" for k, v in times.items())
    ratios = ", ".join(f"{k} ÷ {fastest} = {times[k] / rivals[fastest]:.2f}" for k in ours)
    double = {k: v for k, v in rivals.items() if exact is None or k in exact}
    fastest64 = min(double, key=double.__getitem__) if double else fastest
    if fastest64 != fastest:
        ratios += ", " + ", ".join(f"{k} ÷ {fastest64} = {times[k] / double[fastest64]:.2f}" for k in ours)
    print(f"{label:<14} {cells}\n{'':<14} {ratios}")


def matrices_for(n: int) -> int:
    """Matrices per size: many where a solve is short, so the mean is stable."""
    return 50 if n <= 100 else 5 if n <= 1000 else 2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--sizes", type=int, nargs="+", help="default 10 100 1000 3000; with --densities 1000")
    parser.add_argument("--densities", action="store_true", help="the sparse path's crossover instead")
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    if args.densities:
        for n in args.sizes or [1000]:
            crossover(rng, args.repeats, n)
        return
    exact = exact_in_float64()
    sizes = args.sizes or [10, 100, 1000, 3000]
    for n in sizes:
        cases = [dense_solvers(rng.random((n, n))) for _ in range(matrices_for(n))]
        repeats = args.repeats * (20 if n <= 10 else 2 if n <= 100 else 1)
        report(f"dense {n}²", cases, repeats, exact)
    for n in (s for s in sizes if s >= 1000):
        cases = []
        for _ in range(matrices_for(n)):
            allowed = rng.random((n, n)) < 0.02
            np.fill_diagonal(allowed, True)
            cases.append(gated_solvers(rng.random((n, n)), allowed))
        report(f"gated {n}²", cases, args.repeats)


def crossover(rng: np.random.Generator, repeats: int, n: int) -> None:
    """At `n`², per share of allowed entries, the mean over three matrices of each solve's
    best time: ours on the CSR matrix of the allowed entries (the sparse solver) and on the
    dense matrix with the others priced at 10⁶ (the dense solver, with Jonker & Volgenant's
    start, as a matrix holding +inf has it above the sparse share); and the dense matrix with
    the others at +inf, by the path the library picks for it."""
    print(f"{n}²\n{'allowed':>8} {'sparse':>10} {'dense':>10} {'+inf':>10}")
    for share in (0.02, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.5):
        sparse = dense = forbidden = 0.0
        for _ in range(3):
            c = rng.random((n, n))
            allowed = rng.random((n, n)) < share
            np.fill_diagonal(allowed, True)
            csr = sp.csr_array(np.where(allowed, c, 0.0))
            priced = np.where(allowed, c, 1e6)
            inf = np.where(allowed, c, np.inf)
            sparse += best(functools.partial(pa.linear_assignment, csr), repeats)[0] / 3
            dense += best(functools.partial(pa.linear_assignment, priced), repeats)[0] / 3
            forbidden += best(functools.partial(pa.linear_assignment, inf), repeats)[0] / 3
        print(f"{share:>8.2f} {sparse * 1e3:>8.2f} ms {dense * 1e3:>8.2f} ms {forbidden * 1e3:>8.2f} ms")


if __name__ == "__main__":
    main()
