"""Exact S-D assignment by HiGHS's MILP solver (through :func:`scipy.optimize.milp`).

The S-D problem is a set packing: one binary per candidate tuple, one "used at most once"
row per report. Its LP relaxation is often integral or nearly so, which HiGHS's bounds exploit
and the depth-first branch-and-bound of the core does not: on random problems of a thousand
tuples and more HiGHS proves what the branch-and-bound cannot within its caps
(``python benches/bench_exact_sd.py``; the figures are in docs/performance.md).
SciPy is already a dependency, so no solver is hand-written here.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import scipy.sparse as sparse
from numpy.typing import NDArray
from scipy.optimize import Bounds, LinearConstraint, milp

__all__ = ["HighsSolution", "solve_highs"]

#: (chosen, primal cost, dual bound, nodes, proven optimal)
HighsSolution = tuple[NDArray[np.int64], float, float, int, bool]


def solve_highs(
    tuples: NDArray[np.int64],
    costs: NDArray[np.float64],
    sizes: NDArray[np.int64],
    time_limit: float | None,
) -> HighsSolution:
    """Solve the validated S-D problem exactly, within ``time_limit`` seconds (None: none).

    Returns the chosen tuple indices (ascending), their total cost, HiGHS's dual bound, its
    branch-and-bound node count and whether optimality is proven.
    """
    n_tuples = len(costs)
    if n_tuples == 0:
        return np.zeros(0, dtype=np.int64), 0.0, 0.0, 0, True
    options: dict[str, Any] = {"disp": False}
    if time_limit is not None:
        options["time_limit"] = float(time_limit)
    result = milp(
        costs,
        constraints=LinearConstraint(_report_rows(tuples, sizes), -np.inf, 1.0),
        integrality=np.ones(n_tuples),
        bounds=Bounds(0.0, 1.0),
        options=options,
    )
    if result.x is None:  # no solution within the limit: choosing nothing is always feasible
        chosen = np.zeros(0, dtype=np.int64)
    else:
        chosen = np.flatnonzero(result.x > 0.5).astype(np.int64)
    _check_packing(tuples, chosen)
    primal = float(costs[chosen].sum())
    dual = getattr(result, "mip_dual_bound", None)
    dual_bound = float(dual) if dual is not None and math.isfinite(dual) else -math.inf
    nodes = int(getattr(result, "mip_node_count", 0) or 0)
    return chosen, primal, min(dual_bound, primal), nodes, result.status == 0


def _report_rows(tuples: NDArray[np.int64], sizes: NDArray[np.int64]) -> sparse.csr_array:
    """The (report × tuple) incidence matrix: row ``offset[s] + i − 1`` for report i of sensor s."""
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    rows, cols = [], []
    for s in range(tuples.shape[1]):
        used = np.flatnonzero(tuples[:, s] > 0)
        rows.append(offsets[s] + tuples[used, s] - 1)
        cols.append(used)
    row, col = np.concatenate(rows), np.concatenate(cols)
    return sparse.csr_array((np.ones(len(row)), (row, col)), shape=(int(offsets[-1]), len(tuples)))


def _check_packing(tuples: NDArray[np.int64], chosen: NDArray[np.int64]) -> None:
    """A solver answer that uses a report twice is a bug, never a result."""
    for s in range(tuples.shape[1]):
        used = tuples[chosen, s]
        used = used[used > 0]
        if len(np.unique(used)) != len(used):
            raise RuntimeError(f"internal: HiGHS's solution uses a report of sensor {s} twice")
