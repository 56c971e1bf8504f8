"""Sparse S-D assignment (METHODS §2 baselines A and B), in the Rust core with the GIL released."""

from __future__ import annotations

import time
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Annotated, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._params import COUNT, POSITIVE, Boolean, Configurable, Interval, Options
from .._validation import as_float_array, as_int_array
from ..outcome import Outcome
from .highs import solve_highs

#: Why an S-D solver stopped (``SdAssignment.termination``).
SdTermination = Literal["optimal", "gap_reached", "max_iterations", "stalled", "node_limit", "time_limit"]

#: Each termination in words (``SdAssignment.message``).
SD_MESSAGES: dict[SdTermination, str] = {
    "optimal": "optimal: the primal cost equals the dual bound",
    "gap_reached": "the relative duality gap fell to gap_tol",
    "max_iterations": "max_iter reached before the gap closed",
    "stalled": "the subgradient step vanished: the dual bound stopped improving",
    "node_limit": "branch and bound hit max_nodes; the best solution found is not proven optimal",
    "time_limit": "the solver hit time_limit; the best solution found is not proven optimal",
}


@dataclass(frozen=True)
class SdAssignment(Outcome):
    """Result of :func:`assign_sd`.

    Attributes
    ----------
    termination, success, message
        As every result (:class:`~passive_assoc.outcome.Outcome`): why the solver stopped
        (``optimal``, ``gap_reached``, ``max_iterations``, ``stalled``, ``node_limit`` or
        ``time_limit``); ``success`` when it met its target, optimality proven or the gap
        within ``gap_tol`` (as SciPy's ``OptimizeResult.success``); the reason in words.
    chosen : ndarray of int
        Indices (into the input tuples) of the chosen tuples, ascending.
    primal_cost : float
        Total cost of the chosen tuples (unused reports are false alarms at cost 0).
    dual_bound : float
        Lower bound on the optimum from the Lagrangian dual.
    gap : float
        ``max(0, primal − dual) / max(1, |primal|)``.
    iterations : int
        Subgradient iterations (Lagrangian) or search nodes (exact).
    optimal : bool
        True when optimality is proven.
    """

    chosen: NDArray[np.int64]
    primal_cost: float
    dual_bound: float
    gap: float
    iterations: int
    optimal: bool


def sd_assignment(
    chosen: NDArray[np.int64],
    primal_cost: float,
    dual_bound: float,
    gap: float,
    iterations: int,
    termination: SdTermination,
    optimal: bool,
) -> SdAssignment:
    """An :class:`SdAssignment`, its success and message from its termination."""
    return SdAssignment(
        chosen,
        primal_cost,
        dual_bound,
        gap,
        iterations,
        optimal,
        termination=termination,
        success=termination in ("optimal", "gap_reached"),
        message=SD_MESSAGES[termination],
    )


#: ``assign_sd``'s default branch-and-bound node cap (the static associator uses it too).
ASSIGN_SD_MAX_NODES = 10_000_000

SdMethod = Literal["lagrangian", "exact"]


@dataclass(frozen=True, kw_only=True)
class SdParameters(Configurable):
    """The S-D solvers' parameters, declared once: :func:`assign_sd` takes them as keywords
    and :class:`~passive_assoc.StaticAssociator` inherits them (see :func:`assign_sd` for
    what each means)."""

    max_iter: Annotated[int, COUNT] = 200
    gap_tol: Annotated[float, Interval(float, 0.0, None)] = 1e-3
    max_nodes: Annotated[int, COUNT] = ASSIGN_SD_MAX_NODES
    time_limit: Annotated[float | None, POSITIVE, None] = 10.0
    warm_start: Annotated[Literal["auto", "always", "never"], Options("auto", "always", "never")] = "auto"
    sensor_order: Annotated[Literal["auto", "given"], Options("auto", "given")] = "auto"
    polish: Annotated[bool, Boolean()] = True
    exact_backend: Annotated[Literal["auto", "branch_bound", "highs"], Options("auto", "branch_bound", "highs")] = (
        "auto"
    )


def assign_sd(
    tuples: ArrayLike,
    costs: ArrayLike,
    sizes: ArrayLike,
    *,
    method: SdMethod = "lagrangian",
    **parameters: Any,
) -> SdAssignment:
    """Sparse S-D assignment: choose candidate tuples of minimum total cost such that every
    report of every sensor is used at most once (like MATLAB's ``assignsd``, but on a sparse
    list of candidates instead of a dense S-dimensional cost array).

    Parameters
    ----------
    tuples : array_like of int, shape (K, S)
        Candidate tuples; entry ``s`` is 0 for "sensor s missed it" or ``1..sizes[s]``.
    costs : array_like of float, shape (K,)
        Cost of each tuple (negative log-likelihood ratio); only negative costs can help.
    sizes : array_like of int, shape (S,)
        Reports per sensor.
    method : {"lagrangian", "exact"}
        Lagrangian relaxation with subgradient updates and feasible recovery, or exact
        branch-and-bound (which returns ``optimal=False`` at ``max_nodes``/``time_limit``
        rather than running on).
    **parameters
        :class:`SdParameters`: ``max_iter``, ``gap_tol``, ``max_nodes``, ``time_limit``,
        ``warm_start``, ``sensor_order``, ``polish``, ``exact_backend``, as follows.

    Other Parameters
    ----------------
    max_iter : int
        Lagrangian iteration cap (default 200).
    gap_tol : float
        Lagrangian relative duality-gap target (default 1e-3). MATLAB's ``assignsd`` stops
        at 100 iterations or a 1 % gap; these defaults are tighter, for answers nearer the
        optimum at more time (``max_iter=100, gap_tol=0.01`` gives MATLAB's limits).
    max_nodes : int
        Branch-and-bound node cap.
    time_limit : float or None
        Wall-clock limit in seconds of either method (``time_limit=None``: none). A
        Lagrangian solve that reaches it returns its best feasible solution with
        ``termination="time_limit"``.
    warm_start : {"auto", "always", "never"}
        Whether each Lagrangian iteration's inner 2-D assignment starts from the previous
        one's solution. It is exact either way, so only speed differs (and, between equally
        good solutions, which one is found). "auto" warms up where that measured faster:
        S = 3 with at least 50 reports on the two sensors it keeps (see ``sensor_order``)
        (``python benches/bench_warm_start.py`` compares the two on paper scans).
    sensor_order : {"auto", "given"}
        Which sensors the Lagrangian relaxation keeps as its 2-D problem (the rest have their
        constraints relaxed). "given": sensors 0 and 1, the textbook layout. "auto": for
        S = 3, the two with the fewest reports, relaxing the largest; on paper scans its dual
        bound comes much nearer the LP bound it converges to, in less time
        (``python benches/bench_sensor_order.py``); other S as given. Either way the bound is
        valid; the solution found may differ.
    polish : bool
        Lagrangian: give the best solution, once at the end, compound moves the per-iteration
        search cannot make (bring in a tuple, evict what it conflicts with, refill the freed
        reports). On by default, by measurement: on random problems it brings the answer
        markedly nearer the optimum for little time (``python benches/bench_polish.py``), and
        on paper scans nearer the LP bound for more (``python benches/bench_sensor_order.py``;
        both in docs/performance.md). ``polish=False`` for speed. It runs only
        when the solve ended on ``max_iter`` or a stalled step, and ``time_limit`` does not
        bound it.
    exact_backend : {"auto", "branch_bound", "highs"}
        The exact method's solver: the core's depth-first branch-and-bound, HiGHS's MILP
        solver (:func:`scipy.optimize.milp`, whose LP bounds prove in seconds what the
        branch-and-bound does not prove in minutes on problems of a thousand tuples and more),
        or "auto": branch-and-bound for up to 50 000 nodes (it proves small problems faster
        than HiGHS starts), then HiGHS for the rest of ``time_limit``
        (``python benches/bench_exact_sd.py``). ``iterations`` counts the nodes of the solver
        that answered.

    Returns
    -------
    SdAssignment

    Examples
    --------
    >>> import passive_assoc as pa
    >>> r = pa.assign_sd([[1, 1, 1], [1, 2, 0], [0, 2, 1]], [-5.0, -3.0, -4.0], [1, 2, 1])
    >>> r.chosen.tolist(), r.primal_cost
    ([0], -5.0)
    """
    t = as_int_array("tuples", tuples, ndim=2)
    if t.shape[1] < 2:
        raise ValueError(f"tuples: S-D assignment needs at least 2 sensors (columns), got {t.shape[1]}")
    c = as_float_array("costs", costs, shape=(t.shape[0],))
    n = as_int_array("sizes", sizes, shape=(t.shape[1],))
    n = _solver_sizes(t, n)
    empty = np.flatnonzero((t == 0).all(axis=1))
    if len(empty):  # uses no report, so no constraint binds it: its cost would count silently
        raise ValueError(f"tuples: row {empty[0]} has no report (all zeros); every tuple must use at least one")
    if method not in ("lagrangian", "exact"):
        raise ValueError(f"method: must be 'lagrangian' or 'exact', got {method!r}")
    return solve_validated(t, c, n, method, SdParameters(**parameters))


def solve_validated(
    t: NDArray[np.int64], c: NDArray[np.float64], n: NDArray[np.int64], method: SdMethod, settings: SdParameters
) -> SdAssignment:
    """:func:`assign_sd` on arrays and settings already checked: C-contiguous int64 tuples
    without an all-zero row, float64 costs, int64 sizes — the static associator's candidates,
    whose per-scan checks would otherwise cost more than a small scan's solve. The core still
    validates every index against the sizes."""
    if method == "exact" and settings.exact_backend != "branch_bound":
        return _exact_with_highs(t, c, n, settings, settings.exact_backend == "auto")
    return _from_core(_core.assign_sd(t, c, n, method, settings))


#: Branch-and-bound nodes the "auto" exact backend tries before HiGHS (a few milliseconds).
AUTO_BRANCH_BOUND_NODES = 50_000


def _exact_with_highs(
    t: NDArray[np.int64], c: NDArray[np.float64], n: NDArray[np.int64], settings: SdParameters, auto: bool
) -> SdAssignment:
    """HiGHS, after a short branch-and-bound when ``auto`` (which also validates the input:
    with "highs" a one-node search does, so both backends refuse exactly the same problems)."""
    start = time.perf_counter()
    nodes = min(settings.max_nodes, AUTO_BRANCH_BOUND_NODES) if auto else 1
    first = _from_core(_core.assign_sd(t, c, n, "exact", _with_nodes(settings, nodes)))
    if auto and (first.optimal or first.termination == "time_limit"):
        return first
    remaining = None if settings.time_limit is None else settings.time_limit - (time.perf_counter() - start)
    if remaining is not None and remaining <= 0:  # the search's own stop is not what ended it
        return first if first.optimal else _retermination(first, "time_limit")
    chosen, primal, dual, iterations, proven = solve_highs(t, c, n, remaining)
    if not proven and first.primal_cost < primal:  # HiGHS ran out of time behind the search
        chosen, primal = first.chosen, first.primal_cost
    dual = max(dual, first.dual_bound)
    gap = max(0.0, primal - dual) / max(1.0, abs(primal))
    termination: SdTermination = "optimal" if proven else "time_limit"
    return sd_assignment(chosen, primal, dual, gap, iterations, termination, proven)


def _with_nodes(settings: SdParameters, nodes: int) -> Any:
    """``settings`` as the core reads them, with another node cap."""
    fields = ("max_iter", "gap_tol", "time_limit", "warm_start", "sensor_order", "polish")
    return SimpleNamespace(**{name: getattr(settings, name) for name in fields}, max_nodes=nodes)


def _retermination(result: SdAssignment, termination: SdTermination) -> SdAssignment:
    """``result`` with another termination (and its success and message)."""
    return sd_assignment(
        result.chosen,
        result.primal_cost,
        result.dual_bound,
        result.gap,
        result.iterations,
        termination,
        result.optimal,
    )


#: Declared reports (all sensors) above which the solvers size their per-report arrays by the
#: reports the tuples use instead (8 bytes each per multiplier set).
MAX_DECLARED_REPORTS = 10_000_000


def _solver_sizes(t: NDArray[np.int64], n: NDArray[np.int64]) -> NDArray[np.int64]:
    """``sizes``, or — when they declare more than :data:`MAX_DECLARED_REPORTS` reports — each
    sensor's largest report the tuples use. A report no tuple uses cannot change the answer,
    but the solvers allocate per declared report: S = 40 sensors declaring 10⁷ reports each
    would take gigabytes for a handful of tuples. Below the threshold nothing changes (the
    S = 3 sensor order and the 2-D problems' sizes depend on the declared sizes)."""
    # A list sum: on the few sensors of a scan it takes a tenth of np.clip(...).sum()'s time.
    if sum(size for size in n.tolist() if size > 0) <= MAX_DECLARED_REPORTS:
        return n
    if int(n.max()) > MAX_DECLARED_REPORTS:
        return n  # one sensor beyond the core's per-sensor cap: its error names it
    used = t.max(axis=0) if len(t) else np.zeros_like(n)
    return np.where(used <= n, used, n)  # an index beyond its size stays, for the core's error


def _from_core(out: _core.SdResult) -> SdAssignment:
    return sd_assignment(
        out.chosen, out.primal_cost, out.dual_bound, out.gap, out.iterations, out.termination, out.optimal
    )
