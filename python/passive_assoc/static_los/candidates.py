"""Candidate tuples of one scan (METHODS §2, eq. 2–4): every gated line-of-sight
intersection with its ML position, covariance and eq. 2 cost, enumerated in the Rust core
sensor by sensor with the gate applied to partial tuples (never the full product)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Annotated, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._core import Candidates
from .._inputs import check_pair
from .._params import Interval, checked
from .._validation import as_float_array
from ..data import MeasurementTable, SensorNetwork
from ..data.attributes import AttributeStd, CombinationName, attribute_evidence

__all__ = ["DEFAULT_GATE_SIGMAS", "Candidates", "default_false_alarm_density"]

#: The default gate on each angle's normalised residual (eq. 3), in standard deviations: the
#: two-sided 99 % point, 2.576σ (a χ² of 6.6349 on one degree of freedom).
DEFAULT_GATE_SIGMAS = math.sqrt(6.634896601021214)


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


@checked
def default_false_alarm_density(
    measurements: MeasurementTable,
    n_sensors: Annotated[int, Interval(int, 0, 2**20)],  # the core's MAX_SENSORS: the result's length
    p_false: Annotated[float, Interval(float, 0.0, 1.0, closed="both")] = 0.05,
    *,
    sensors: SensorNetwork | None = None,
) -> NDArray[np.float64]:
    """False alarms per radian (per rad² in 3-D) of each sensor ``0 .. n_sensors - 1`` of one
    scan, the static methods' default when the caller gives none (docs/methods.md §2).

    A sensor's expected false alarms are ``p_false`` of its reports (the paper's P_FA = 0.05),
    or its excess over the median sensor's report count when that is larger: all sensors see
    the same targets, so reports beyond what the median sensor has are false alarms (or the
    others' misses). Too low a density makes a false alarm look like a target to eq. 2 (issue
    16: a ghost at it and a true target split). They are spread over the azimuth (×
    elevation) sector the sensor's reports span (π for a sensor without reports).

    Tiny scans: each span is at least 10⁻³ rad and, given ``sensors`` (a network of
    ``n_sensors`` sensors), at least the width of the default gate on the sensor's angle,
    2 × 2.576 σ (at most 2π). A scan of one report per sensor spans nothing; with the
    10⁻³ rad floor alone its density was 50 per radian, above the likelihood of a perfect
    report at σ = 10 mrad, and a lone noiseless target was called clutter. With ``sensors``
    these are the densities the solvers use when ``false_alarm_density`` is None; computed in
    the Rust core."""
    elevation = measurements.elevation if measurements.ndim == 3 else None
    sigma = None
    if sensors is not None:
        if not isinstance(sensors, SensorNetwork):
            raise TypeError(f"sensors: expected a SensorNetwork, got {type(sensors).__name__}")
        if sensors.n_sensors != n_sensors:
            raise ValueError(f"sensors: has {sensors.n_sensors} sensors, n_sensors is {n_sensors}")
        sigma = _stds(sensors)
    density: NDArray[np.float64] = _core.default_false_alarm_density(
        measurements.sensor, measurements.azimuth, elevation, n_sensors, p_false, sigma
    )
    return density


def _stds(sensors: SensorNetwork) -> NDArray[np.float64]:
    """``(S, 2)`` angle stds ``[σβ, σε]`` (σε = 1 in the plane, as the core reads them)."""
    elevation = sensors.sigma_elevation if sensors.ndim == 3 else np.ones(sensors.n_sensors)
    return np.ascontiguousarray(np.column_stack([sensors.sigma_azimuth, elevation]), dtype=np.float64)


def enumerate_validated(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    *,
    pd: ArrayLike,
    false_alarm_density: ArrayLike | None,
    settings: Any,
    attributes: tuple[Sequence[str] | None, AttributeStd | None, float, CombinationName],
) -> Candidates:
    """The candidates of one scan, the settings validated by their declaration
    (:class:`~passive_assoc.StaticAssociator`); the tables and the per-sensor arrays are
    checked here."""
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
