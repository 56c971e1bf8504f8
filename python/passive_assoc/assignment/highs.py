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
import os
import re
import sys
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager
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
    with solver_output_silenced():
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


#: A line HiGHS writes itself, whatever ``disp`` says: a C++ qualified name at its start
#: ("HighsMipSolverData::transformNewIntegerFeasibleSolution tmpSolver.run();"), or its banner.
SOLVER_LINE = re.compile(rb"^(H[A-Za-z]*::|Running HiGHS)")

_silenced = threading.Lock()
_silencing: dict[str, Any] = {"depth": 0}


@contextmanager
def solver_output_silenced() -> Iterator[None]:
    """Keeps what HiGHS prints to the process's standard output (file descriptor 1, below
    Python's ``sys.stdout``) out of the caller's output: some of its messages ignore
    ``disp=False``. Descriptor 1 goes to a temporary file while solves run (nested and
    concurrent solves share one redirection); when the last ends, the lines others wrote
    meanwhile are passed on and only HiGHS's are dropped. Without a descriptor 1 to redirect,
    nothing is done."""
    with _silenced:
        active = _silencing["depth"] > 0 or _redirect()
        _silencing["depth"] += active
    if not active:
        yield
        return
    try:
        yield
    finally:
        with _silenced:
            _silencing["depth"] -= 1
            if _silencing["depth"] == 0:
                _restore()


def _redirect() -> bool:
    """Points descriptor 1 at a new temporary file, keeping the original; False if it cannot."""
    try:
        if sys.stdout is not None:
            sys.stdout.flush()  # what Python holds goes out first, in order
    except (OSError, ValueError):
        pass
    try:
        saved = os.dup(1)
    except OSError:
        return False
    capture = tempfile.TemporaryFile()  # noqa: SIM115 -- held open across the solves, closed by _restore
    try:
        os.dup2(capture.fileno(), 1)
    except OSError:
        os.close(saved)
        capture.close()
        return False
    _silencing.update(saved=saved, capture=capture)
    return True


def _restore() -> None:
    """Descriptor 1 back where it was, and the captured lines that are not HiGHS's written to it."""
    saved, capture = _silencing.pop("saved"), _silencing.pop("capture")
    try:
        if sys.stdout is not None:
            sys.stdout.flush()  # Python output written during the solve went to the capture too
    except (OSError, ValueError):
        pass
    os.dup2(saved, 1)
    os.close(saved)
    with capture:
        capture.seek(0)
        kept = b"".join(line for line in capture if not SOLVER_LINE.match(line))
    while kept:
        kept = kept[os.write(1, kept) :]
