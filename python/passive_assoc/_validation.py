"""Argument-checking helpers shared across the package.

Every public entry point converts its array arguments through these helpers so that a bad
input fails early, at the boundary, with a message that starts with the argument's name,
says what is wrong, and points at the first offending element. Wrong *kinds* of data
(strings, objects, complex numbers, booleans) raise :class:`TypeError`; wrong *values*
(shape, NaN/inf, sign) raise :class:`ValueError`.

This module is pure Python/NumPy and must not import the compiled extension.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "as_float_array",
    "as_int_array",
    "as_float_scalar",
    "as_int_scalar",
    "as_interval",
    "require_finite",
    "require_positive",
    "require_nonnegative",
    "require_time_range",
    "readonly",
]

#: Shape pattern: an int fixes a dimension, ``None`` accepts any length.
ShapeSpec = Sequence["int | None"]


def _where(name: str, arr: NDArray[Any], flat_index: int) -> str:
    """Format ``name[i]`` / ``name[i, j]`` for the element at ``flat_index``."""
    if arr.ndim == 0:
        return name
    idx = np.unravel_index(flat_index, arr.shape)
    return f"{name}[{', '.join(str(int(i)) for i in idx)}]"


def _to_array(name: str, value: ArrayLike) -> NDArray[Any]:
    """``np.asarray`` that reports ragged input as a ValueError naming the argument."""
    if value is None:
        raise TypeError(f"{name}: expected an array of numbers, got None")
    try:
        return np.asarray(value)
    except (ValueError, TypeError) as exc:  # ragged nested lists in NumPy >= 1.24
        raise ValueError(f"{name}: cannot be converted to an array ({exc})") from None


def _big_integers(name: str, arr: NDArray[Any], kind: str) -> NDArray[Any]:
    """An object array of Python integers beyond int64 (``np.asarray(2**70)``) as float64
    (``kind`` "f"), or a ValueError naming the first element int64 cannot hold (``kind`` "i");
    any other array unchanged. They are real numbers, not objects of another kind."""
    if arr.dtype != object or arr.size == 0:
        return arr
    flat = arr.ravel()
    if not all(type(v) is int or isinstance(v, np.integer) for v in flat):
        return arr
    if kind == "i":
        i = next(k for k, v in enumerate(flat) if not -(2**63) <= int(v) < 2**63)
        raise ValueError(f"{_where(name, arr, i)} = {integer_text(int(flat[i]))} is out of the 64-bit integer range")
    beyond = next((k for k, v in enumerate(flat) if abs(int(v)) > _FLOAT_MAX), None)
    if beyond is not None:
        text = integer_text(int(flat[beyond]))
        raise ValueError(f"{_where(name, arr, beyond)} = {text} is beyond the range of a float")
    return np.array([float(v) for v in flat], dtype=np.float64).reshape(arr.shape)


#: The largest finite float64, as an exact integer (comparing a huge int with a float would
#: convert the int and overflow).
_FLOAT_MAX = int(np.finfo(np.float64).max)


def integer_text(value: int) -> str:
    """An integer for an error message: its digits, or their count past 30 of them."""
    digits = str(value)
    return digits if len(digits) <= 30 else f"an integer of {len(digits.lstrip('-'))} digits"


def _check_kind(name: str, arr: NDArray[Any], allowed: str, what: str) -> None:
    """Reject dtypes whose kind letter is not in ``allowed`` with a TypeError."""
    if arr.dtype.kind not in allowed:
        raise TypeError(f"{name}: expected {what}, got an array of dtype {arr.dtype}")


def _check_shape(name: str, arr: NDArray[Any], ndim: int | None, shape: ShapeSpec | None) -> None:
    """Check the number of dimensions and, where given, each dimension's length."""
    if shape is not None:
        ndim = len(shape)
    if ndim is not None and arr.ndim != ndim:
        raise ValueError(f"{name}: expected a {ndim}-dimensional array, got shape {arr.shape}")
    if shape is not None:
        for axis, (want, got) in enumerate(zip(shape, arr.shape, strict=True)):
            if want is not None and want != got:
                dims = ["*" if s is None else str(s) for s in shape]
                pattern = f"({', '.join(dims)}{',' if len(dims) == 1 else ''})"
                raise ValueError(
                    f"{name}: expected shape {pattern}, got {arr.shape} (axis {axis} has length {got}, expected {want})"
                )


def as_float_array(
    name: str,
    value: ArrayLike,
    ndim: int | None = None,
    shape: ShapeSpec | None = None,
) -> NDArray[np.float64]:
    """Convert ``value`` to a fresh C-contiguous float64 array and check its shape.

    Parameters
    ----------
    name : str
        Argument name used at the start of every error message.
    value : array_like
        Integers or floats. Booleans, complex numbers, strings and objects are rejected.
    ndim : int, optional
        Required number of dimensions.
    shape : sequence of int or None, optional
        Required shape; ``None`` entries accept any length. Implies ``ndim``.

    Returns
    -------
    numpy.ndarray
        A float64 copy (never a view of the caller's data, so it may be frozen).

    Raises
    ------
    TypeError
        If the data are not real numbers.
    ValueError
        If the shape is wrong or the input is ragged.
    """
    arr = _big_integers(name, _to_array(name, value), "f")
    _check_kind(name, arr, "iuf", "real numbers")
    _check_shape(name, arr, ndim, shape)
    return np.array(arr, dtype=np.float64, order="C", copy=True)


def as_int_array(
    name: str,
    value: ArrayLike,
    ndim: int | None = None,
    shape: ShapeSpec | None = None,
) -> NDArray[np.int64]:
    """Convert ``value`` to a fresh C-contiguous int64 array and check its shape.

    Floats are accepted only when every element is an exact integer (CSV and pandas
    round-trips can turn integer columns into floats); the message points at the first
    element that is not.

    Parameters
    ----------
    name : str
        Argument name used at the start of every error message.
    value : array_like
        Integers, or integer-valued floats.
    ndim : int, optional
        Required number of dimensions.
    shape : sequence of int or None, optional
        Required shape; ``None`` entries accept any length.

    Returns
    -------
    numpy.ndarray
        An int64 copy.

    Raises
    ------
    TypeError
        If the data are not real numbers.
    ValueError
        If the shape is wrong or a float element is not an exact integer.
    """
    arr = _big_integers(name, _to_array(name, value), "i")
    _check_kind(name, arr, "iuf", "integers")
    _check_shape(name, arr, ndim, shape)
    if arr.dtype.kind == "f":
        bad = ~np.isfinite(arr) | (arr != np.round(arr))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(f"{_where(name, arr, i)} = {arr.flat[i].item()!r} is not an integer")
        huge = np.abs(arr) >= 2.0**63  # integral but beyond int64: the cast would wrap
        if huge.any():
            i = int(np.flatnonzero(huge)[0])
            raise ValueError(f"{_where(name, arr, i)} = {arr.flat[i].item()!r} is out of the 64-bit integer range")
    if arr.dtype.kind == "u" and arr.size and int(arr.max()) > np.iinfo(np.int64).max:
        raise ValueError(f"{name}: values exceed the int64 range")
    return np.array(arr, dtype=np.int64, order="C", copy=True)


def as_float_scalar(name: str, value: Any, *, finite: bool = False) -> float:
    """Convert a real scalar (Python or NumPy number, or 0-d array) to ``float``.

    Raises
    ------
    TypeError
        If ``value`` is not a real, non-boolean number.
    ValueError
        If ``finite`` is set and the value is NaN or infinite.
    """
    arr = _big_integers(name, _to_array(name, value), "f")
    if arr.ndim != 0:
        raise TypeError(f"{name}: expected a scalar, got an array of shape {arr.shape}")
    _check_kind(name, arr, "iuf", "a real number")
    out = float(arr)
    if finite and not np.isfinite(out):
        raise ValueError(f"{name} = {out!r}; must be finite")
    return out


def as_int_scalar(name: str, value: Any, *, minimum: int | None = None) -> int:
    """Check that ``value`` is an integer (not a bool or float), optionally ``>= minimum``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name}: expected an int, got {value!r}")
    if minimum is not None and value < minimum:
        raise ValueError(f"{name}: must be >= {minimum}, got {value}")
    if not -(2**63) <= value < 2**63:  # the core takes int64; beyond it PyO3 raises OverflowError
        raise ValueError(f"{name}: {value} is out of the 64-bit integer range")
    return int(value)


def as_interval(name: str, value: ArrayLike) -> tuple[float, float]:
    """Check a finite ``(low, high)`` pair with ``low < high``."""
    lo_hi = as_float_array(name, value, shape=(2,))
    require_finite(name, lo_hi)
    if not lo_hi[0] < lo_hi[1]:
        raise ValueError(f"{name}: expected (low, high) with low < high, got {tuple(lo_hi.tolist())}")
    return float(lo_hi[0]), float(lo_hi[1])


def require_finite(name: str, arr: NDArray[Any]) -> None:
    """Raise ValueError naming the first NaN or infinite element of ``arr``."""
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{_where(name, arr, i)} = {arr.flat[i].item()!r}; all values must be finite")


def require_positive(name: str, arr: NDArray[Any]) -> None:
    """Raise ValueError naming the first element that is not ``> 0`` (NaN included)."""
    bad = ~(arr > 0)  # written this way so that NaN counts as bad
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{_where(name, arr, i)} = {arr.flat[i].item()!r}; must be > 0")


def require_nonnegative(name: str, arr: NDArray[Any]) -> None:
    """Raise ValueError naming the first element that is not ``>= 0`` (NaN included)."""
    bad = ~(arr >= 0)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{_where(name, arr, i)} = {arr.flat[i].item()!r}; must be >= 0")


#: Largest magnitude accepted for a state component (metres, m/s): beyond it the angle
#: arithmetic keeps no digits of a sensor's offset (at 1e300 the closeness gradients are NaN).
MAX_STATE_MAGNITUDE = 1e12


def require_state_range(name: str, arr: NDArray[Any]) -> None:
    """Raise ValueError naming the first element beyond ±:data:`MAX_STATE_MAGNITUDE`."""
    require_finite(name, arr)
    bad = np.abs(arr) > MAX_STATE_MAGNITUDE
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{_where(name, arr, i)} = {arr.flat[i].item()!r}; state components must lie within "
            f"±{MAX_STATE_MAGNITUDE:g} (m, m/s), where the angle arithmetic stays exact enough"
        )


#: Largest magnitude accepted for a time, seconds (32 000 years): the bound of every epoch
#: ``t0`` (``_params.Epoch``) and of the Kalman filter's times. Beyond it a time step keeps
#: no digits of the times it separates.
MAX_TIME_MAGNITUDE = 1e12


def require_time_range(name: str, arr: NDArray[Any]) -> None:
    """Raise ValueError naming the first element that is not finite or beyond
    ±:data:`MAX_TIME_MAGNITUDE` seconds."""
    require_finite(name, arr)
    bad = np.abs(arr) > MAX_TIME_MAGNITUDE
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{_where(name, arr, i)} = {arr.flat[i].item()!r}; times must lie within ±{MAX_TIME_MAGNITUDE:g} s"
        )


def readonly(arr: NDArray[Any]) -> NDArray[Any]:
    """Mark ``arr`` read-only and return it (frozen containers hand out such arrays)."""
    arr.flags.writeable = False
    return arr
