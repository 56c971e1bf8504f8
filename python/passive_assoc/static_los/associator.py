"""Static bearing-only association by line-of-sight intersections (METHODS §2, paper 001).

One scan of bearings (2-D) or az/el (3-D) from S ≥ 2 sensors, with missed detections and
false alarms: which reports of different sensors are the same target, and where is it?
Candidates are enumerated in the Rust core sensor by sensor with the gate applied to partial
tuples (never the full product), each survivor is triangulated by ML, and one of three
methods picks a consistent set: the paper's attribute-intensity search, S-D assignment by
Lagrangian relaxation, or exact branch-and-bound.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._core import Candidates
from .._inputs import check_pair
from .._settings import EnumerationSettings, IntensitySettings
from .._validation import as_float_array, as_float_scalar, as_int_scalar
from ..assignment import assign_sd
from ..data import MeasurementTable, SensorNetwork

Method = Literal["intensity", "lagrangian", "exact"]
#: The per-level diagnostics of the intensity search, as ``report["levels"]`` lists them.
_LEVEL_FIELDS = ("intensity", "candidates", "starts", "chains", "confirmed")
#: χ²(1 dof) at 99 %: default gate on each normalised squared angle residual (eq. 3).
CHI2_1DOF_99 = 6.634896601021214


@dataclass(frozen=True)
class StaticAssociation:
    """Output of :func:`associate_static`.

    Attributes
    ----------
    tuples : ndarray of int, shape (T, S)
        Table rows of each accepted target's reports, −1 where a sensor missed it.
    positions : ndarray, shape (T, ndim)
        ML position of each target.
    covariances : ndarray, shape (T, ndim, ndim)
    costs : ndarray, shape (T,)
        Cost (negative log-likelihood ratio, eq. 2) of each accepted tuple.
    labels : ndarray of int, shape (N,)
        Target index of every input row, or −1 for a false alarm.
    report : dict
        Enumeration counts and the solver's report (gap, bound, iterations, termination, or
        the intensity search's airspace radius, ghosts dropped, chains).
    """

    tuples: NDArray[np.int64]
    positions: NDArray[np.float64]
    covariances: NDArray[np.float64]
    costs: NDArray[np.float64]
    labels: NDArray[np.int64]
    report: dict[str, Any] = field(repr=False)

    @property
    def false_alarms(self) -> NDArray[np.int64]:
        """Rows assigned to no target."""
        return np.flatnonzero(self.labels < 0)


def _per_sensor(name: str, value: ArrayLike, n: int, low: float, high: float) -> NDArray[np.float64]:
    arr = as_float_array(name, value)
    arr = np.broadcast_to(arr, (n,)).copy() if arr.ndim == 0 or arr.shape == (1,) else arr
    if arr.shape != (n,):
        raise ValueError(f"{name}: expected a scalar or {n} values (one per sensor), got shape {arr.shape}")
    bad = ~((arr > low) & (arr < high))
    if bad.any():
        raise ValueError(f"{name}: sensor {int(np.flatnonzero(bad)[0])} has {arr[bad][0]}, must be in ({low}, {high})")
    return arr


def default_false_alarm_density(
    measurements: MeasurementTable, n_sensors: int, p_false: float = 0.05
) -> NDArray[np.float64]:
    """False alarms per radian (per rad² in 3-D) when the caller gives none: a fraction
    ``p_false`` of each sensor's reports, spread over the azimuth (× elevation) sector its
    reports span. The paper's P_FA = 0.05 is the default fraction."""
    density = np.empty(n_sensors)
    for s in range(n_sensors):
        rows = measurements.sensor == s
        n = max(int(rows.sum()), 1)
        width = np.ptp(measurements.azimuth[rows]) if rows.any() else np.pi
        area = max(width, 1e-3)
        if measurements.ndim == 3 and rows.any():
            area *= max(np.ptp(measurements.elevation[rows]), 1e-3)
        density[s] = max(p_false * n / area, 1e-12)
    return density


def enumerate_candidates(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    *,
    pd: ArrayLike = 0.95,
    false_alarm_density: ArrayLike | None = None,
    gate: float = CHI2_1DOF_99,
    min_intensity: int = 2,
    max_candidates: int = 1_000_000,
    n_threads: int | None = None,
) -> Candidates:
    """All gated candidate tuples of one scan with their ML positions and costs (eq. 2–4).

    Parameters are those of :func:`associate_static`. Returns a frozen :class:`Candidates` with
    the arrays ``tuples`` (K, S; 0 = missed, else 1-based report index within the sensor),
    ``rows`` (K, S; table row or −1), ``positions``, ``covariances``, ``costs``,
    ``intensity``, ``chi2``, ``sizes`` and ``stages`` (see :func:`stage_counts`).
    """
    table, network = check_pair(measurements, sensors)
    if network.n_sensors < 2:
        raise ValueError(f"sensors: static association needs at least 2 sensors, got {network.n_sensors}")
    n = network.n_sensors
    density = (
        default_false_alarm_density(table, n)
        if false_alarm_density is None
        else _per_sensor("false_alarm_density", false_alarm_density, n, 0.0, np.inf)
    )
    settings = EnumerationSettings(
        chi2_gate=as_float_scalar("gate", gate, finite=True),
        min_intensity=as_int_scalar("min_intensity", min_intensity, minimum=2),
        max_candidates=as_int_scalar("max_candidates", max_candidates, minimum=1),
        n_threads=n_threads,
    )
    return _core.enumerate_static(table, network, _per_sensor("pd", pd, n, 0.0, 1.0), density, settings)


def stage_counts(candidates: Candidates) -> dict[str, int]:
    """The enumeration's partial tuples tested and pruned per depth k (``tested_k``,
    ``pruned_k`` for k = 2..S), those skipped by the bearing window, and the ``final`` count."""
    stages = candidates.stages
    counts: dict[str, int] = {}
    for k in range(2, len(stages.tested)):
        counts[f"tested_{k}"] = int(stages.tested[k])
        counts[f"pruned_{k}"] = int(stages.pruned[k])
    counts["windowed_out"] = int(stages.windowed_out)
    counts["final"] = int(stages.candidates)
    return counts


def associate_static(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    method: Method = "intensity",
    *,
    pd: ArrayLike = 0.95,
    false_alarm_density: ArrayLike | None = None,
    gate: float = CHI2_1DOF_99,
    min_intensity: int = 2,
    vote_fraction: float = 0.5,
    valid_airspace: bool = False,
    max_chains: int | None = None,
    max_iter: int = 200,
    gap_tol: float = 1e-3,
    time_limit: float | None = 10.0,
    sensor_order: Literal["auto", "given"] = "auto",
    polish: bool = False,
    max_candidates: int = 1_000_000,
    n_threads: int | None = None,
) -> StaticAssociation:
    """Associate one scan of passive reports across sensors.

    Parameters
    ----------
    measurements : MeasurementTable
        One scan: every report of every sensor (times are ignored).
    sensors : SensorNetwork
        At least 2 sensors (the paper uses 3).
    method : {"intensity", "lagrangian", "exact"}
        The paper's intensity-ordered search with its vote, S-D assignment by Lagrangian
        relaxation, or exact branch-and-bound (small problems; ``time_limit``).
    pd : float or array_like
        Detection probability per sensor, in (0, 1).
    false_alarm_density : float or array_like, optional
        False alarms per radian (2-D) or per rad² (3-D), per sensor; default
        :func:`default_false_alarm_density`.
    gate : float
        Largest normalised squared residual of any angle of a candidate (eq. 3).
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
        with the most exclusive rays). Default None: one chain per point of H, the paper's
        rule. Where ghosts are dense every point has 0 exclusive rays, H is the whole level,
        and the vote grows quadratically in the number of candidates; a cap such as 64 keeps
        large scans fast (``reproduce intensity`` uses 64 beyond M = 18).
    max_iter, gap_tol, time_limit, sensor_order, polish
        Solver settings, as in :func:`passive_assoc.assign_sd`.
    max_candidates : int
        Refuse with a ValueError rather than enumerate more candidates than this.
    n_threads : int, optional
        Threads for the enumeration and the intensity method's chains (None: all cores);
        results are identical for any value.

    Returns
    -------
    StaticAssociation
        Every input row is in exactly one accepted tuple or in the false-alarm set.
    """
    if method not in ("intensity", "lagrangian", "exact"):
        raise ValueError(f"method: must be 'intensity', 'lagrangian' or 'exact', got {method!r}")
    cands = enumerate_candidates(
        measurements,
        sensors,
        pd=pd,
        false_alarm_density=false_alarm_density,
        gate=gate,
        min_intensity=min_intensity,
        max_candidates=max_candidates,
        n_threads=n_threads,
    )
    report: dict[str, Any] = {
        "method": method,
        "candidates": len(cands.costs),
        "stage_counts": stage_counts(cands),
    }
    if method == "intensity":
        settings = IntensitySettings(
            vote_fraction=float(vote_fraction),
            valid_airspace=bool(valid_airspace),
            max_chains=None if max_chains is None else as_int_scalar("max_chains", max_chains, minimum=1),
            n_threads=n_threads,
        )
        out = _core.intensity_search(cands.tuples, cands.positions, cands.costs, cands.sizes, settings)
        chosen = out.chosen
        report.update(
            airspace_radius=out.airspace_radius,
            ghosts_dropped=out.ghosts_dropped,
            chains=out.chains,
            levels=[{name: getattr(level, name) for name in _LEVEL_FIELDS} for level in out.levels],
        )
    else:
        solved = assign_sd(
            cands.tuples,
            cands.costs,
            cands.sizes,
            method=method,
            max_iter=max_iter,
            gap_tol=gap_tol,
            time_limit=time_limit,
            sensor_order=sensor_order,
            polish=polish,
        )
        chosen = solved.chosen
        report.update(
            primal_cost=solved.primal_cost,
            dual_bound=solved.dual_bound,
            gap=solved.gap,
            iterations=solved.iterations,
            termination=solved.termination,
            optimal=solved.optimal,
        )
    return _result(cands, np.asarray(chosen, dtype=np.int64), len(measurements), report)


def _result(cands: Candidates, chosen: NDArray[np.int64], n_rows: int, report: dict[str, Any]) -> StaticAssociation:
    rows = cands.rows[chosen]
    used = rows >= 0
    flat = rows[used]
    if len(np.unique(flat)) != len(flat):
        raise RuntimeError("internal: a report was assigned to two targets")  # solvers guarantee this
    labels = np.full(n_rows, -1, dtype=np.int64)
    labels[flat] = np.nonzero(used)[0]  # row-major: each used entry's target index
    return StaticAssociation(
        rows, cands.positions[chosen], cands.covariances[chosen], cands.costs[chosen], labels, report
    )
