"""Emitter attributes as the methods consume them: a table's attribute columns, chosen by name,
with one standard deviation per value (METHODS §3).

Stds come per attribute, per attribute and sensor, or per report: a report-level std is an
attribute column named ``<name>_std`` next to ``<name>`` (so files carry it), used when
``attribute_std`` is not given.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Annotated, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._params import Interval, Options
from .._settings import AttributeEvidence
from .._validation import as_float_array
from .measurements import MeasurementTable
from .sensors import SensorNetwork

__all__ = [
    "AttributeStd",
    "Combination",
    "CombinationName",
    "DEFAULT_ETA",
    "Eta",
    "STD_SUFFIX",
    "attribute_arrays",
    "attribute_evidence",
]

#: Suffix of an attribute column holding the per-report std of the attribute it names.
STD_SUFFIX = "_std"

#: Stds: one per attribute (a sequence in name order, or a mapping name -> std), where a
#: mapping's value may also be one std per sensor.
AttributeStd = Sequence[float] | Mapping[str, float | Sequence[float]] | NDArray[np.float64]


#: The attribute gate's threshold η (METHODS §3): the declaration the formation locator and
#: §2's gate share, and its default (the paper's 0.6).
Eta = Annotated[float, Interval(float, 0.0, 1.0, closed="neither")]
DEFAULT_ETA = 0.6
#: The Dempster reading of the attribute supports (METHODS §3), declared once for both methods.
CombinationName = Literal["simple", "two_outcome"]
Combination = Annotated[CombinationName, Options("simple", "two_outcome")]


def attribute_evidence(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    attributes: Sequence[str] | None,
    attribute_std: AttributeStd | None,
    eta: float,
    combination: CombinationName,
) -> AttributeEvidence | None:
    """The attribute gate's input for the core, or None when no attribute is used. ``eta`` and
    ``combination`` must have been validated (the callers' declarations, :data:`Eta` and
    :data:`Combination`, check them once)."""
    names, values, stds = attribute_arrays(measurements, sensors, attributes, attribute_std)
    if not names:
        return None
    return AttributeEvidence(values, stds, eta, combination)


def attribute_arrays(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    attributes: Sequence[str] | None,
    attribute_std: AttributeStd | None,
) -> tuple[list[str], NDArray[np.float64], NDArray[np.float64]]:
    """The chosen attribute columns stacked ``(K, N)``, and their stds ``(K, N)`` or, when
    each attribute has one std, ``(K, 1)`` (the core's layout: no transpose, no expansion).

    Parameters
    ----------
    attributes : sequence of str, optional
        Column names; None takes every attribute column of the table except ``*_std`` ones.
        An empty sequence (or a table without attributes) gives ``K = 0``.
    attribute_std : sequence, mapping or array, optional
        ``K`` stds in name order, or a mapping name -> std or name -> one std per sensor
        (every key an attribute column of the table: a key that names none is refused);
        None reads per-report stds from ``<name>_std`` columns.
    """
    names = _names(measurements, attributes)
    if isinstance(attribute_std, Mapping):
        unknown = [key for key in attribute_std if key not in measurements.attributes]
        if unknown:  # a typo would otherwise leave its attribute ungated or a std unread
            columns = list(measurements.attributes)
            raise ValueError(f"attribute_std: {unknown[0]!r} names no attribute column; the table has {columns}")
    n = len(measurements)
    if not names:
        return names, np.empty((0, n)), np.empty((0, 1))
    values = np.array([measurements.attributes[name] for name in names], dtype=np.float64)
    per_name = [
        _std_column(measurements, sensors, (name, k, len(names)), attribute_std) for k, name in enumerate(names)
    ]
    if all(isinstance(std, float) for std in per_name):  # one std per attribute: (K, 1)
        for name, std in zip(names, per_name, strict=True):
            if not (math.isfinite(std) and std > 0):
                raise ValueError(f"attribute_std: {name!r} has std {std}, must be finite and > 0")
        return names, values, np.array(per_name, dtype=np.float64).reshape(-1, 1)
    stds = np.array([np.broadcast_to(std, n) for std in per_name], dtype=np.float64)
    if not (np.isfinite(stds).all() and (stds > 0).all()):
        k, row = np.argwhere(~(np.isfinite(stds) & (stds > 0)))[0]
        raise ValueError(f"attribute_std: {names[k]!r} has std {stds[k, row]} at row {row}, must be finite and > 0")
    return names, values, stds


def _names(measurements: MeasurementTable, attributes: Sequence[str] | None) -> list[str]:
    table = list(measurements.attributes)
    if attributes is None:
        return [a for a in table if not (a.endswith(STD_SUFFIX) and a.removesuffix(STD_SUFFIX) in table)]
    if isinstance(attributes, str):
        raise TypeError(f"attributes: expected a sequence of column names, got the string {attributes!r}")
    names = list(attributes)
    for name in names:
        if name not in measurements.attributes:
            raise ValueError(f"attributes: the table has no attribute {name!r}; it has {table}")
    if len(set(names)) != len(names):
        raise ValueError(f"attributes: names repeat in {names}")
    return names


def _std_column(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    which: tuple[str, int, int],
    attribute_std: AttributeStd | None,
) -> float | NDArray[np.float64]:
    """The std column of attribute ``which = (name, index, count)``, or its one value."""
    name, k, count = which
    if attribute_std is None:
        column = measurements.attributes.get(name + STD_SUFFIX)
        if column is None:
            raise ValueError(
                f"attribute_std: required for {name!r} (give one std per attribute, or a "
                f"'{name}{STD_SUFFIX}' column of per-report stds)"
            )
        return np.asarray(column, dtype=np.float64)
    if isinstance(attribute_std, Mapping):
        if name not in attribute_std:
            raise ValueError(f"attribute_std: no std for {name!r}; the mapping has {list(attribute_std)}")
        per = _as_float_array(attribute_std[name], name)
        if per.ndim == 0:
            return float(per)
        if per.shape != (sensors.n_sensors,):
            expected = f"one std or one per sensor ({sensors.n_sensors})"
            raise ValueError(f"attribute_std: {name!r} must be {expected}, got shape {per.shape}")
        return per[measurements.sensor]
    flat = _as_float_array(attribute_std, "all")
    if flat.shape != (count,):
        raise ValueError(
            f"attribute_std: expected {count} stds (one per attribute, in name order), got shape {flat.shape}"
        )
    return float(flat[k])


def _as_float_array(value: ArrayLike | float, name: str) -> NDArray[np.float64]:
    try:  # a complex std would lose its imaginary part silently; 2**70 is a real number
        return as_float_array("attribute_std", value)
    except TypeError as err:
        raise TypeError(f"attribute_std: std of {name!r} is not numeric: {value!r}") from err
