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
    arr = as_float_array(name, value)
    # np.full, not broadcast_to(...).copy(): a scalar is the common case, and this runs on
    # every static solve.
    arr = np.full(n, arr.reshape(-1)[0]) if arr.ndim == 0 or arr.shape == (1,) else arr
    if arr.shape != (n,):
        raise ValueError(f"{name}: expected a scalar or {n} values (one per sensor), got shape {arr.shape}")
    bad = ~((arr > low) & (arr < high))
    if bad.any():
        raise ValueError(f"{name}: sensor {int(np.flatnonzero(bad)[0])} has {arr[bad][0]}, must be in ({low}, {high})")
    return arr


def default_false_alarm_density(
    measurements: MeasurementTable, n_sensors: int, p_false: float = 0.05
) -> NDArray[np.float64]:
    """False alarms per radian (per rad² in 3-D) when the caller gives none: the false alarms
    :func:`expected_false_alarms` counts for each sensor, spread over the azimuth
    (× elevation) sector its reports span. The paper's P_FA = 0.05 is the default fraction."""
    # All sensors at once (a per-sensor loop of NumPy calls cost more than the solve on a
    # small scan).
    sensor = measurements.sensor
    ours = sensor < n_sensors
    sensor = sensor[ours]
    counts = np.bincount(sensor, minlength=n_sensors)
    area = np.maximum(_spans(sensor, measurements.azimuth[ours], counts), 1e-3)
    if measurements.ndim == 3:
        heights = np.maximum(_spans(sensor, measurements.elevation[ours], counts), 1e-3)
        area = np.where(counts > 0, area * heights, area)
    density: NDArray[np.float64] = np.maximum(expected_false_alarms(counts, p_false) / area, 1e-12)
    return density


def expected_false_alarms(counts: NDArray[np.int64], p_false: float) -> NDArray[np.float64]:
    """False alarms to expect per sensor (last axis) of a scan: ``p_false`` of its reports,
    or its excess over the sensors' median report count when that is larger.

    All sensors see the same targets, so reports beyond what the median sensor has are
    false alarms (or the others' misses): a sensor with 4 reports where the others have 3
    holds at least about one, where ``p_false · n`` expects 0.2. Too low a density makes a
    false alarm look like a target to eq. 2 (issue 16: a ghost at it and a true target split).
    """
    base = p_false * np.maximum(counts, 1)
    excess = counts - _median_last_axis(counts)
    expected: NDArray[np.float64] = np.maximum(base, excess)
    return expected


def _median_last_axis(counts: NDArray[np.int64]) -> NDArray[np.float64]:
    """``np.median(counts, axis=-1, keepdims=True)`` by one sort: every static solve calls
    this, and ``np.median``'s own overhead was a fifth of a tiny scan's time."""
    ordered = np.sort(counts, axis=-1)
    n = ordered.shape[-1]
    middle = ordered[..., n // 2 : n // 2 + 1].astype(np.float64)
    if n % 2 == 0 and n > 0:
        middle = 0.5 * (middle + ordered[..., n // 2 - 1 : n // 2])
    return middle


def _spans(sensor: NDArray[np.int64], values: NDArray[np.float64], counts: NDArray[np.int64]) -> NDArray[np.float64]:
    """Per sensor, max − min of its values; π for a sensor without values. One sort by
    (sensor, value) gives each sensor's least and greatest value at the ends of its run
    (``ufunc.at`` cost more than the sort on the small scans every solve sees)."""
    order = np.lexsort((values, sensor))
    ends = np.cumsum(counts)
    present = counts > 0
    spans = np.full(len(counts), np.pi)
    ordered = values[order]
    spans[present] = ordered[ends[present] - 1] - ordered[ends[present] - counts[present]]
    return spans


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
    density = (
        default_false_alarm_density(table, n)
        if false_alarm_density is None
        else _per_sensor("false_alarm_density", false_alarm_density, n, 0.0, np.inf)
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
