"""Candidate tuples of one scan (METHODS §2, eq. 2–4): every gated line-of-sight
intersection with its ML position, covariance and eq. 2 cost, enumerated in the Rust core
sensor by sensor with the gate applied to partial tuples (never the full product)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._core import Candidates
from .._inputs import check_pair
from .._params import Constraint, Interval, validate
from .._settings import Combination, EnumerationSettings
from .._validation import as_float_array
from ..data import MeasurementTable, SensorNetwork
from ..data.attributes import ATTRIBUTE_CONSTRAINTS, AttributeStd, attribute_evidence

__all__ = ["CHI2_1DOF_99", "Candidates", "default_false_alarm_density", "enumerate_candidates", "stage_counts"]

#: χ²(1 dof) at 99 %: default gate on each normalised squared angle residual (eq. 3).
CHI2_1DOF_99 = 6.634896601021214

#: Declared constraints of the enumeration's scalar parameters (``pd`` and
#: ``false_alarm_density`` are per-sensor arrays, checked against the network).
ENUMERATION_CONSTRAINTS: dict[str, list[Constraint]] = {
    "chi2_gate": [Interval(float, 0.0, None, closed="neither")],
    "min_intensity": [Interval(int, 2, None)],
    "max_candidates": [Interval(int, 1, None)],
    "n_threads": [Interval(int, 1, None), None],
}


def _per_sensor(name: str, value: ArrayLike, n: int, low: float, high: float) -> NDArray[np.float64]:
    if type(value) is float:  # the common case, on every static solve: no array checks
        if not low < value < high:
            raise ValueError(f"{name}: sensor 0 has {value}, must be in ({low}, {high})")  # as an array's
        return np.full(n, value)
    arr = as_float_array(name, value)
    arr = np.full(n, arr.reshape(-1)[0]) if arr.ndim == 0 or arr.shape == (1,) else arr
    if arr.shape != (n,):
        raise ValueError(f"{name}: expected a scalar or {n} values (one per sensor), got shape {arr.shape}")
    bad = ~((arr > low) & (arr < high))
    if bad.any():
        raise ValueError(f"{name}: sensor {int(np.flatnonzero(bad)[0])} has {arr[bad][0]}, must be in ({low}, {high})")
    return arr


#: Declared constraints of :func:`default_false_alarm_density`'s scalars.
DENSITY_CONSTRAINTS: dict[str, list[Constraint]] = {
    "n_sensors": [Interval(int, 0, 2**20)],  # the core's MAX_SENSORS: the result's length
    "p_false": [Interval(float, 0.0, 1.0, closed="both")],
}


def default_false_alarm_density(
    measurements: MeasurementTable, n_sensors: int, p_false: float = 0.05
) -> NDArray[np.float64]:
    """False alarms per radian (per rad² in 3-D) of each sensor ``0 .. n_sensors - 1`` of one
    scan, the static methods' default when the caller gives none (docs/methods.md §2).

    A sensor's expected false alarms are ``p_false`` of its reports (the paper's P_FA = 0.05),
    or its excess over the median sensor's report count when that is larger: all sensors see
    the same targets, so reports beyond what the median sensor has are false alarms (or the
    others' misses). Too low a density makes a false alarm look like a target to eq. 2 (issue
    16: a ghost at it and a true target split). They are spread over the azimuth (×
    elevation) sector the sensor's reports span, each span at least 10⁻³ rad (π for a sensor
    without reports). Computed in the Rust core, as the solvers compute it when
    ``false_alarm_density`` is None."""
    checked = validate({"n_sensors": n_sensors, "p_false": p_false}, DENSITY_CONSTRAINTS)
    elevation = measurements.elevation if measurements.ndim == 3 else None
    density: NDArray[np.float64] = _core.default_false_alarm_density(
        measurements.sensor, measurements.azimuth, elevation, checked["n_sensors"], checked["p_false"]
    )
    return density


def enumerate_candidates(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    *,
    pd: ArrayLike = 0.95,
    false_alarm_density: ArrayLike | None = None,
    chi2_gate: float = CHI2_1DOF_99,
    min_intensity: int = 2,
    max_candidates: int = 1_000_000,
    n_threads: int | None = None,
    attributes: Sequence[str] | None = (),
    attribute_std: AttributeStd | None = None,
    eta: float = 0.6,
    combination: str = "simple",
) -> Candidates:
    """All gated candidate tuples of one scan with their ML positions and costs (eq. 2–4).

    Parameters are those of :class:`StaticAssociator`. Returns a frozen :class:`Candidates` with
    the arrays ``tuples`` (K, S; 0 = missed, else 1-based report index within the sensor),
    ``rows`` (K, S; table row or −1), ``positions``, ``covariances``, ``costs``,
    ``intensity``, ``chi2``, ``sizes`` and ``stages`` (see :func:`stage_counts`).
    """
    checked = validate(
        dict(chi2_gate=chi2_gate, min_intensity=min_intensity, max_candidates=max_candidates, n_threads=n_threads),
        ENUMERATION_CONSTRAINTS,
    )
    gate = validate({"eta": eta, "combination": combination}, ATTRIBUTE_CONSTRAINTS)
    return enumerate_validated(
        measurements,
        sensors,
        pd=pd,
        false_alarm_density=false_alarm_density,
        settings=EnumerationSettings(**checked),
        attributes=(attributes, attribute_std, gate["eta"], gate["combination"]),
    )


def enumerate_validated(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    *,
    pd: ArrayLike,
    false_alarm_density: ArrayLike | None,
    settings: EnumerationSettings,
    attributes: tuple[Sequence[str] | None, AttributeStd | None, float, Combination],
) -> Candidates:
    """:func:`enumerate_candidates` with its scalar settings already validated (by
    :class:`StaticAssociator`, which would otherwise check them twice a scan); the tables and
    the per-sensor arrays are checked here."""
    table, network = check_pair(measurements, sensors)
    if network.n_sensors < 2:
        raise ValueError(f"sensors: static association needs at least 2 sensors, got {network.n_sensors}")
    n = network.n_sensors
    # None: the core computes the default (`default_false_alarm_density`) from the scan.
    density = (
        None if false_alarm_density is None else _per_sensor("false_alarm_density", false_alarm_density, n, 0.0, np.inf)
    )
    names, stds, eta, combination = attributes
    evidence = attribute_evidence(table, network, names, stds, eta, combination)
    return _core.enumerate_static(table, network, _per_sensor("pd", pd, n, 0.0, 1.0), density, settings, evidence)


def stage_counts(candidates: Candidates) -> dict[str, int]:
    """The enumeration's partial tuples tested and pruned per depth k (``tested_k``,
    ``pruned_k`` for k = 2..S), those skipped by the bearing window or cut by the attribute
    gate, and the ``final`` count."""
    stages = candidates.stages
    counts: dict[str, int] = {}
    for k in range(2, len(stages.tested)):
        counts[f"tested_{k}"] = int(stages.tested[k])
        counts[f"pruned_{k}"] = int(stages.pruned[k])
    counts["windowed_out"] = int(stages.windowed_out)
    counts["attribute_pruned"] = int(stages.attribute_pruned)
    counts["final"] = int(stages.candidates)
    return counts
