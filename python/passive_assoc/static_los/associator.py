"""Static bearing-only association by line-of-sight intersections (METHODS §2, paper 001).

One scan of bearings (2-D) or az/el (3-D) from S ≥ 2 sensors, with missed detections and
false alarms: which reports of different sensors are the same target, and where is it?
Candidates are enumerated in the Rust core sensor by sensor with the gate applied to partial
tuples (never the full product), each survivor is triangulated by ML, and one of three
methods picks a consistent set: the paper's attribute-intensity search, S-D assignment by
Lagrangian relaxation, or exact branch-and-bound.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Annotated, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._core import Candidates
from .._params import Boolean, Interval, Options, Threads
from ..assignment.sd import SdMethod, SdParameters, _solver_sizes, solve_validated
from ..data import MeasurementTable, SensorNetwork
from ..data.attributes import DEFAULT_ETA, AttributeStd, Combination, Eta
from ..outcome import COMPLETED, Outcome
from .candidates import DEFAULT_GATE_SIGMAS, _per_sensor, enumerate_validated
from .diagnostics import SolverDiagnostics, StaticDiagnostics, intensity_diagnostics, stage_counts
from .prior import PricedCandidates, check_region, priced
from .scan_window import check_one_scan, motion_inflated

__all__ = [
    "DEFAULT_METHOD",
    "Method",
    "StaticAssociation",
    "StaticAssociator",
    "associate_static",
    "enumerate_candidates",
]

Method = Literal["intensity", "lagrangian", "exact"]
#: The method of :class:`StaticAssociator`, :func:`associate_static`, :func:`associate_scans`
#: and ``passive-assoc associate`` when none is given. Lagrangian S-D assignment finds about
#: twice as many targets exactly as the intensity search (27 % against 13.5 % of 1277
#: simulated targets, 11 against 4 of the shipped example's 15) and within a point of the
#: exact solver, in 1-6 ms a scan where that takes 0.1-2.3 s (10-20 targets):
#: ``benches/static_method_choice.py``.
DEFAULT_METHOD: Method = "lagrangian"

POSITIVE = Interval(float, 0.0, None, closed="neither")


@dataclass(frozen=True)
class StaticAssociation(Outcome):
    """Output of :meth:`StaticAssociator.associate` and :func:`associate_static`.

    Every input row is in exactly one accepted target or in :attr:`clutter`; :attr:`labels`
    holds that partition as one array (target index, or -1 for clutter).

    Attributes
    ----------
    termination, success, message
        As every result (:class:`~passive_assoc.outcome.Outcome`): the S-D solver's
        termination (``"optimal"``, ``"gap_reached"``, ``"max_iterations"``, ``"stalled"``,
        ``"node_limit"``, ``"time_limit"``; see :class:`~passive_assoc.SdAssignment`) for the
        Lagrangian and exact methods, ``"completed"`` for the intensity method.
    rows : ndarray of int, shape (T, S)
        Table rows of each accepted target's reports, one column per sensor, −1 where a
        sensor missed it.
    positions : ndarray, shape (T, ndim)
        ML position of each target.
    covariances : ndarray, shape (T, ndim, ndim)
    costs : ndarray, shape (T,)
        Cost (negative log-likelihood ratio, eq. 2) of each accepted tuple.
    labels : ndarray of int, shape (N,)
        Target index of every input row, or −1 for clutter (a false alarm).
    diagnostics : StaticDiagnostics
        The enumeration's counts and the method's own figures (the solver's gap and bound,
        or the intensity search's levels).
    """

    rows: NDArray[np.int64]
    positions: NDArray[np.float64]
    covariances: NDArray[np.float64]
    costs: NDArray[np.float64]
    labels: NDArray[np.int64]
    diagnostics: StaticDiagnostics = field(repr=False)

    @property
    def clutter(self) -> NDArray[np.int64]:
        """Rows assigned to no target (false alarms), as :attr:`InitiationResult.clutter`."""
        return np.flatnonzero(self.labels < 0)


@dataclass(frozen=True)
class StaticAssociator(SdParameters):
    """Static association of one scan of passive reports across sensors (METHODS §2).

    Configure once, then call :meth:`associate` on each scan. One scan of bearings (2-D) or
    az/el (3-D) from S ≥ 2 sensors, with missed detections and false alarms: which reports of
    different sensors are the same target, and where is it?

    Parameters
    ----------
    method : {"intensity", "lagrangian", "exact"}
        The paper's intensity-ordered search with its vote, S-D assignment by Lagrangian
        relaxation, or exact branch-and-bound (small problems; ``max_nodes``, optionally ``time_limit``). Default
        :data:`DEFAULT_METHOD`, ``"lagrangian"``: it finds about twice as many targets right
        as the intensity search, the paper's method.
    pd : float or array_like
        Detection probability per sensor, in (0, 1).
    false_alarm_density : float or array_like, optional
        False alarms per radian (2-D) or per rad² (3-D), per sensor; default
        :func:`default_false_alarm_density`.
    gate_sigmas : float
        Gate on each angle of a candidate (eq. 3): its normalised residual, in standard
        deviations, must be at most this; default 2.576, the two-sided 99 % point (a χ² of
        6.63 on one degree of freedom).
    min_intensity : int
        Fewest lines of sight a candidate needs (≥ 2).
    vote_fraction : float
        Intensity method: a point is confirmed when more than this fraction of the chains
        accept it.
    valid_airspace : bool
        Intensity method: drop every candidate whose nearest intensity-S point (other than
        itself) is farther than the valid-airspace radius d (eq. 12–13), the paper's step 1.
        Off by default: it assumes clustered (formation) targets, and on spread-out targets it
        deletes isolated real ones even in noiseless data, while its accuracy gain on
        spread-out targets is small (compare ``passive-assoc reproduce intensity`` with and
        without ``--no-airspace``; docs/experiments.md). The reproduction runs it on, as the
        paper.
    max_chains : int, optional
        Intensity method: start at most this many chains (the first of the set H of points
        with the most exclusive rays). Default 64. None is the paper's rule, one chain per
        point of H: where ghosts are dense every point has 0 exclusive rays, H is the whole
        level, and the vote grows quadratically in the number of candidates (minutes at a few
        hundred targets). ``reproduce intensity`` runs the paper's rule up to M = 18
        and 64 beyond (docs/experiments.md).
    max_iter, gap_tol, max_nodes, time_limit, warm_start, sensor_order, polish, exact_backend
        Solver settings, as in :func:`passive_assoc.assign_sd`.
    max_candidates : int
        Refuse with a ValueError rather than enumerate more candidates than this.
    attributes : sequence of str, optional
        Emitter attribute columns for the attribute gate (METHODS §3 used by §2): a candidate
        holding two reports whose Dempster ``m(assoc)`` is below ``eta`` is never formed.
        Default ``()``: bearings only; None: every attribute column of the table.
    attribute_std, eta, combination
        The gate's attribute stds, threshold and Dempster reading, as in
        :class:`passive_assoc.FormationLocator`.
    region : sequence of float, optional
        Where targets can be: ``(xmin, xmax, ymin, ymax)`` (2-D) or with ``zmin, zmax`` (3-D),
        metres. With ``target_density`` it turns eq. 2 into the posterior cost under a uniform
        prior over the region (a project extension; :mod:`passive_assoc.static_los.prior`):
        candidates outside the region, or better explained as false alarms, are dropped before
        the method runs. Default None: eq. 2 as the paper.
    target_density : float, optional
        Expected targets per m² (2-D) or m³ (3-D) in the region, e.g. the number of targets
        you expect divided by the region's area. Needed with ``region``; alone, it applies the
        prior without a boundary.
    n_threads : int, optional
        Threads for the enumeration and the intensity method's chains (None: all cores);
        results are identical for any value.
    scan_window : float, optional
        Seconds: reports this close in time are one scan (real clocks jitter). In
        :func:`associate_scans` and ``passive-assoc associate`` it groups the table into scans
        by :func:`~passive_assoc.static_los.window_scans`'s rule; :meth:`associate` refuses a
        table whose times span more than it. Default None: one scan has one time, and
        :meth:`associate` warns when a table has several.
    v_max, min_range : float, optional
        The fastest target (m/s) and the nearest a target comes to a sensor (m): given both,
        each report's angle noise is widened by ``v_max·Δt/min_range`` (in quadrature), Δt
        its time from its scan's middle, for the targets' motion while a scan's reports come
        in (:func:`~passive_assoc.static_los.motion_inflated`). Default None: reports of one
        scan are taken as simultaneous.

    """

    method: Annotated[Method, Options("intensity", "lagrangian", "exact")] = DEFAULT_METHOD
    pd: ArrayLike = 0.95
    false_alarm_density: ArrayLike | None = None
    gate_sigmas: Annotated[float, Interval(float, 0.0, 1e6, closed="right")] = DEFAULT_GATE_SIGMAS
    min_intensity: Annotated[int, Interval(int, 2, None)] = 2
    vote_fraction: Annotated[float, Interval(float, 0.0, 1.0, closed="left")] = 0.5
    valid_airspace: Annotated[bool, Boolean()] = False
    max_chains: Annotated[int | None, Interval(int, 1, None), None] = 64
    max_candidates: Annotated[int, Interval(int, 1, None)] = 1_000_000
    n_threads: Threads = None
    attributes: Sequence[str] | None = ()
    attribute_std: AttributeStd | None = None
    eta: Eta = DEFAULT_ETA
    combination: Combination = "simple"
    region: Sequence[float] | None = None
    target_density: Annotated[float | None, POSITIVE, None] = None
    scan_window: Annotated[float | None, Interval(float, 0.0, None), None] = None
    v_max: Annotated[float | None, POSITIVE, None] = None
    min_range: Annotated[float | None, POSITIVE, None] = None

    def __post_init__(self) -> None:
        super().__post_init__()
        # Per-sensor arrays are checked against the network at associate(); a scalar now.
        if np.ndim(self.pd) == 0:
            _per_sensor("pd", self.pd, 1, 0.0, 1.0)
        if self.false_alarm_density is not None and np.ndim(self.false_alarm_density) == 0:
            _per_sensor("false_alarm_density", self.false_alarm_density, 1, 0.0, np.inf)
        if self.region is not None:
            if self.target_density is None:
                raise ValueError("target_density: needed with region (expected targets per m² or m³ in it)")
            n = np.size(self.region)
            check_region(self.region, 2 if n == 4 else 3)  # the network's dimension is checked per scan
        if (self.v_max is None) != (self.min_range is None):
            raise ValueError("v_max, min_range: give both (the motion within a scan) or neither")

    def candidates(self, measurements: MeasurementTable, sensors: SensorNetwork) -> Candidates:
        """Every gated candidate tuple of the scan (see :func:`enumerate_candidates`; the
        settings were validated when the associator was built)."""
        return enumerate_validated(
            measurements,
            sensors,
            pd=self.pd,
            false_alarm_density=self.false_alarm_density,
            settings=self,
            attributes=(self.attributes, self.attribute_std, self.eta, self.combination),
        )

    def associate(self, measurements: MeasurementTable, sensors: SensorNetwork) -> StaticAssociation:
        """Associate one scan.

        Parameters
        ----------
        measurements : MeasurementTable
            One scan: every report of every sensor (times are ignored).
        sensors : SensorNetwork
            At least 2 sensors (the paper uses 3).

        Returns
        -------
        StaticAssociation
            Every input row is in exactly one accepted target or in the clutter set.

        Warns
        -----
        UserWarning
            When the table holds several distinct times and no ``scan_window`` is set: it is
            treated as one scan, which is right only if the targets did not move between them.
        """
        check_one_scan(measurements, self.scan_window)
        moving = self.v_max is not None and self.min_range is not None
        if moving and isinstance(measurements, MeasurementTable) and len(measurements):
            one = np.zeros(len(measurements), dtype=np.int64)
            measurements = motion_inflated(measurements, sensors, one, self.v_max, self.min_range)  # type: ignore[arg-type]
        enumerated = self.candidates(measurements, sensors)
        cands: Candidates | PricedCandidates = enumerated
        priced_count = None
        if self.target_density is not None:
            cands = priced(enumerated, check_region(self.region, sensors.ndim), self.target_density)
            priced_count = len(cands.costs)
        counts = (self.method, len(enumerated.costs), stage_counts(enumerated), priced_count)
        if self.method == "intensity":
            out = _core.intensity_search(cands.tuples, cands.positions, cands.costs, cands.sizes, self)
            diagnostics = StaticDiagnostics(*counts, intensity=intensity_diagnostics(out))
            outcome = {"termination": COMPLETED, "success": True, "message": "the intensity search ran to its end"}
            chosen = out.chosen
        else:
            sizes = _solver_sizes(cands.tuples, cands.sizes)
            method: SdMethod = "exact" if self.method == "exact" else "lagrangian"
            solved = solve_validated(cands.tuples, cands.costs, sizes, method, self)
            solver = SolverDiagnostics(
                solved.primal_cost, solved.dual_bound, solved.gap, solved.iterations, solved.optimal
            )
            diagnostics = StaticDiagnostics(*counts, solver=solver)
            outcome = {"termination": solved.termination, "success": solved.success, "message": solved.message}
            chosen = solved.chosen
        return _result(cands, np.asarray(chosen, dtype=np.int64), len(measurements), diagnostics, outcome)


def associate_static(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    method: Method = DEFAULT_METHOD,
    **settings: Any,
) -> StaticAssociation:
    """Associate one scan: ``StaticAssociator(method, **settings).associate(measurements,
    sensors)``, for one-off calls. The settings are :class:`StaticAssociator`'s.

    >>> import passive_assoc as pa
    >>> from passive_assoc.simulation import static_scan
    >>> scan = static_scan(1, n_targets=5)
    >>> result = pa.associate_static(scan.measurements, scan.sensors, "lagrangian")
    >>> len(result.clutter) + int((result.rows >= 0).sum()) == len(scan.measurements)
    True
    """
    return _associator(method, settings).associate(measurements, sensors)


def enumerate_candidates(measurements: MeasurementTable, sensors: SensorNetwork, **settings: Any) -> Candidates:
    """All gated candidate tuples of one scan with their ML positions and costs (eq. 2–4):
    ``StaticAssociator(**settings).candidates(measurements, sensors)``. The settings that
    matter are the enumeration's (``pd``, ``false_alarm_density``, ``gate_sigmas``,
    ``min_intensity``, ``max_candidates``, ``n_threads`` and the attribute gate's).

    Returns a frozen :class:`Candidates` with the arrays ``tuples`` (K, S; 0 = missed, else the
    1-based report index within the sensor, the S-D solvers' input), ``rows`` (K, S; table row
    or −1), ``positions``, ``covariances``, ``costs``, ``intensity``, ``chi2``, ``sizes`` and
    ``stages`` (see :func:`~passive_assoc.static_los.stage_counts`).
    """
    return _associator("intensity", settings).candidates(measurements, sensors)


def _associator(method: Any, settings: dict[str, Any]) -> StaticAssociator:
    """A :class:`StaticAssociator` for these settings, reused across calls when they are all
    hashable: building one validates some twenty parameters, a tenth of a small scan's time.
    Keys hold each value's type, so ``True`` never reuses the associator built for ``1``."""
    key = (type(method), method, tuple(sorted((k, type(v), v) for k, v in settings.items())))
    try:
        hash(key)
    except TypeError:  # an array or list among the settings
        return StaticAssociator(method, **settings)
    return _cached_associator(key)


@functools.lru_cache(maxsize=32)
def _cached_associator(key: tuple[Any, ...]) -> StaticAssociator:
    _, method, items = key
    return StaticAssociator(method, **{k: v for k, _, v in items})


def _result(
    cands: Candidates | PricedCandidates,
    chosen: NDArray[np.int64],
    n_rows: int,
    diagnostics: StaticDiagnostics,
    outcome: dict[str, Any],
) -> StaticAssociation:
    rows = cands.rows[chosen]
    used = rows >= 0
    flat = rows[used]
    if len(flat) and np.bincount(flat).max() > 1:
        raise RuntimeError("internal: a report was assigned to two targets")  # solvers guarantee this
    labels = np.full(n_rows, -1, dtype=np.int64)
    labels[flat] = np.nonzero(used)[0]  # row-major: each used entry's target index
    return StaticAssociation(
        rows, cands.positions[chosen], cands.covariances[chosen], cands.costs[chosen], labels, diagnostics, **outcome
    )
