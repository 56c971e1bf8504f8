"""MeasurementTable's column checks: each column validated, copied and named in its errors."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, as_int_array, readonly, require_finite
from .sensors import ANGLE_STD_RANGE

__all__ = [
    "attribute_columns",
    "check_length",
    "elevation_column",
    "first",
    "float_column",
    "noise_column",
    "sensor_position_column",
    "truth_column",
]


def first(mask: NDArray[np.bool_]) -> int:
    return int(np.flatnonzero(mask)[0])


def check_length(name: str, arr: NDArray[Any], n: int) -> None:
    if arr.shape[0] != n:
        raise ValueError(
            f"{name}: has length {arr.shape[0]} but sensor has length {n}; all columns must have the same length"
        )


def float_column(name: str, value: ArrayLike, n: int, finite: bool = True) -> NDArray[np.float64]:
    arr = as_float_array(name, value, ndim=1)
    check_length(name, arr, n)
    if finite:
        require_finite(name, arr)
    return arr


def elevation_column(value: ArrayLike | None, n: int) -> NDArray[np.float64]:
    """All finite (3-D) or all NaN (2-D); a mixture is almost surely a data error."""
    if value is None:
        return np.full(n, np.nan)
    elevation = float_column("elevation", value, n, finite=False)
    nan = np.isnan(elevation)
    if nan.any() and not nan.all():
        # Point at the odd one out relative to the first row's kind.
        i = first(~nan) if nan[0] else first(nan)
        raise ValueError(
            f"elevation[{i}] = {elevation[i].item()!r}; elevation must be all finite (3-D) or all NaN (2-D)"
        )
    if np.isinf(elevation).any():
        i = first(np.isinf(elevation))
        raise ValueError(f"elevation[{i}] = {elevation[i].item()!r}; must be finite or NaN")
    return elevation


def noise_column(name: str, value: ArrayLike | None, n: int) -> NDArray[np.float64] | None:
    """A per-report std column: NaN (the sensor's value) or within :data:`ANGLE_STD_RANGE`."""
    if value is None:
        return None
    arr = float_column(name, value, n, finite=False)
    low, high = ANGLE_STD_RANGE
    bad = ~np.isnan(arr) & ~((arr >= low) & (arr <= high))
    if bad.any():
        i = first(bad)
        raise ValueError(
            f"{name}[{i}] = {float(arr[i])!r} rad; a report's angle std must lie in [{low:g}, π] "
            "(or be NaN: the sensor's)"
        )
    return readonly(arr)


def sensor_position_column(value: ArrayLike | None, n: int, planar: bool) -> NDArray[np.float64] | None:
    """Per-report sensor positions ``(N, 3)`` (``(N, 2)`` gets z = 0): each row all finite,
    or all NaN (the sensor's fixed position); z = 0 in a 2-D table."""
    if value is None:
        return None
    arr = as_float_array("sensor_position", value, ndim=2)
    if arr.shape[1] == 2:
        arr = np.column_stack([arr, np.zeros(arr.shape[0])])
    if arr.shape[1] != 3:
        raise ValueError(f"sensor_position: expected shape (N, 3) or (N, 2), got {arr.shape}")
    check_length("sensor_position", arr, n)
    given: NDArray[np.bool_] = np.asarray(np.isfinite(arr).all(axis=1))
    bad: NDArray[np.bool_] = ~given & ~np.isnan(arr).all(axis=1)
    if bad.any():
        i = first(bad)
        raise ValueError(f"sensor_position[{i}] = {arr[i].tolist()}; a row is all finite, or all NaN (the sensor's)")
    if planar and (given & (arr[:, 2] != 0.0)).any():
        i = first(given & (arr[:, 2] != 0.0))
        raise ValueError(f"sensor_position[{i}, 2] = {arr[i, 2]!r}; a 2-D table's sensors have z = 0")
    return readonly(np.ascontiguousarray(arr))


def truth_column(value: ArrayLike | None, n: int) -> NDArray[np.int64] | None:
    if value is None:
        return None
    truth = as_int_array("truth", value, ndim=1)
    check_length("truth", truth, n)
    if (truth < -1).any():
        i = first(truth < -1)
        raise ValueError(f"truth[{i}] = {truth[i]}; labels are target indices >= 0 or -1 (clutter)")
    return readonly(truth)


def _attribute_name(name: Any) -> str:
    """Attribute names become CSV headers, so keep them plain identifiers-ish."""
    if not isinstance(name, str):
        raise TypeError(f"attributes: names must be str, got {name!r}")
    if not name or any(c in name for c in ',"\r\n'):
        raise ValueError(f'attributes: invalid name {name!r} (empty, or has , " or newline)')
    return name


def attribute_columns(value: Any, n: int) -> dict[str, NDArray[np.float64]]:
    if not isinstance(value, Mapping):
        raise TypeError(f"attributes: expected a mapping name -> array, got {type(value).__name__}")
    out = {}
    for key, column in value.items():
        name = _attribute_name(key)
        out[name] = readonly(float_column(f"attributes[{name!r}]", column, n))
    return out
