"""Validation of :class:`TrackTable` columns: each check names the column and its first bad
row, as the other tables' checks do."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, as_int_array, require_finite

__all__ = ["SYMMETRY_TOLERANCE", "BLOCKS", "validated_columns", "check_order", "sort_order"]

#: A covariance ``C`` is accepted as symmetric when every ``|C[j, k] − C[k, j]|`` is at most
#: this times its largest absolute entry (rounding in a filter's update leaves ~1e-16
#: relative asymmetry; anything near this bound is a transposed or corrupt matrix).
SYMMETRY_TOLERANCE = 1e-9

#: The state blocks in stacking order (METHODS §0: positions first).
BLOCKS = ("position", "velocity", "acceleration")

Columns = dict[str, Any]


def _first(mask: NDArray[np.bool_]) -> int:
    return int(np.flatnonzero(mask)[0])


def _ids(name: str, value: ArrayLike, what: str) -> NDArray[np.int64]:
    arr = as_int_array(name, value, ndim=1)
    if (arr < 0).any():
        i = _first(arr < 0)
        raise ValueError(f"{name}[{i}] = {arr[i]}; {what} must be >= 0")
    return arr


def _check_length(name: str, length: int, n: int) -> None:
    if length != n:
        raise ValueError(
            f"{name}: has length {length} but source has length {n}; all columns must have the same length"
        )


def _position(value: ArrayLike, n: int) -> NDArray[np.float64]:
    arr = as_float_array("position", value)
    if arr.ndim == 1:  # a plain vector is a 1-D track (the x axis only, as in METHODS §5)
        arr = arr[:, None]
    if arr.ndim != 2 or arr.shape[1] not in (1, 2, 3):
        raise ValueError(f"position: expected shape (N, ndim) with ndim 1, 2 or 3, got {arr.shape}")
    _check_length("position", arr.shape[0], n)
    require_finite("position", arr)
    return arr


def _block(name: str, value: ArrayLike | None, shape: tuple[int, ...]) -> NDArray[np.float64] | None:
    if value is None:
        return None
    arr = as_float_array(name, value)
    if arr.ndim == 1 and shape[1] == 1:
        arr = arr[:, None]
    if arr.shape != shape:
        raise ValueError(f"{name}: expected shape {shape} like position, got {arr.shape}")
    require_finite(name, arr)
    return arr


def _covariance(value: ArrayLike | None, n: int, d: int, layout: str) -> NDArray[np.float64] | None:
    if value is None:
        return None
    cov = as_float_array("covariance", value)
    if cov.shape != (n, d, d):
        raise ValueError(f"covariance: expected shape {(n, d, d)} (N, d, d) with d = {layout}, got {cov.shape}")
    require_finite("covariance", cov)
    diagonal = np.diagonal(cov, axis1=1, axis2=2)
    if (diagonal < 0).any():
        i, k = np.unravel_index(_first((diagonal < 0).ravel()), diagonal.shape)
        raise ValueError(f"covariance[{i}, {k}, {k}] = {cov[i, k, k].item()!r}; a variance must be >= 0")
    scale = np.maximum(np.abs(cov).max(axis=(1, 2), initial=0.0), np.finfo(np.float64).tiny)
    asymmetry = np.abs(cov - cov.transpose(0, 2, 1)).max(axis=(1, 2), initial=0.0) / scale
    if (asymmetry > SYMMETRY_TOLERANCE).any():
        row = _first(asymmetry > SYMMETRY_TOLERANCE)
        raise ValueError(
            f"covariance[{row}] is not symmetric (largest |C - Cᵀ| is {asymmetry[row]:.3g} of its largest entry, "
            f"tolerance {SYMMETRY_TOLERANCE})"
        )
    # Stored exactly symmetric, so the upper triangle (all a CSV keeps) is the whole matrix.
    # Halves first where the sum would overflow (entries beyond ~9e307), else stored as inf.
    transposed = cov.transpose(0, 2, 1)
    with np.errstate(over="ignore"):
        symmetric = 0.5 * (cov + transposed)
    return np.where(np.isfinite(symmetric), symmetric, 0.5 * cov + 0.5 * transposed)


def _truth(value: ArrayLike | None, n: int) -> NDArray[np.int64] | None:
    if value is None:
        return None
    truth = as_int_array("truth", value, ndim=1)
    _check_length("truth", truth.shape[0], n)
    if (truth < -1).any():
        i = _first(truth < -1)
        raise ValueError(f"truth[{i}] = {truth[i]}; labels are target indices >= 0 or -1 (false track)")
    return truth


def validated_columns(
    source: ArrayLike,
    track: ArrayLike,
    time: ArrayLike,
    position: ArrayLike,
    velocity: ArrayLike | None,
    acceleration: ArrayLike | None,
    covariance: ArrayLike | None,
    truth: ArrayLike | None,
) -> Columns:
    """Fresh, checked arrays of every column (everything but the row order)."""
    src = _ids("source", source, "source indices")
    n = src.shape[0]
    trk = _ids("track", track, "track ids")
    _check_length("track", trk.shape[0], n)
    tim = as_float_array("time", time, ndim=1)
    _check_length("time", tim.shape[0], n)
    require_finite("time", tim)
    pos = _position(position, n)
    if acceleration is not None and velocity is None:
        raise ValueError(
            "acceleration: given without velocity; the state blocks are [position], "
            "[position, velocity] or [position, velocity, acceleration]"
        )
    vel = _block("velocity", velocity, pos.shape)
    acc = _block("acceleration", acceleration, pos.shape)
    n_blocks = 1 + (vel is not None) + (acc is not None)
    ndim = pos.shape[1]
    layout = f"ndim × blocks = {ndim} × {n_blocks}"
    return {
        "source": src,
        "track": trk,
        "time": tim,
        "position": pos,
        "velocity": vel,
        "acceleration": acc,
        "covariance": _covariance(covariance, n, ndim * n_blocks, layout),
        "truth": _truth(truth, n),
    }


def _key(columns: Columns, i: int) -> str:
    return f"(source, track, time) = ({columns['source'][i]}, {columns['track'][i]}, {float(columns['time'][i])!r})"


def _steps(columns: Columns) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Per pair of consecutive rows: does the key go backwards, is it repeated? (Compared,
    not differenced, so that huge times cannot overflow.)"""
    src, trk, tim = columns["source"], columns["track"], columns["time"]
    same_source = src[1:] == src[:-1]
    same_track = same_source & (trk[1:] == trk[:-1])
    backwards = (src[1:] < src[:-1]) | (same_source & (trk[1:] < trk[:-1])) | (same_track & (tim[1:] < tim[:-1]))
    return backwards, same_track & (tim[1:] == tim[:-1])


def check_order(columns: Columns) -> None:
    """Rows sorted by (source, track, time), no key twice; else name the first bad row."""
    backwards, repeated = _steps(columns)
    bad = backwards | repeated
    if not bad.any():
        return
    i = _first(bad) + 1
    if repeated[i - 1]:
        raise ValueError(f"rows {i - 1} and {i} have the same {_key(columns, i)}; a track has one state per time")
    raise ValueError(
        f"row {i} {_key(columns, i)} sorts before row {i - 1} {_key(columns, i - 1)}: rows must be sorted by "
        "(source, track, time); pass sort=True to TrackTable.from_arrays (or from_columns, from_csv, from_pandas)"
    )


def sort_order(columns: Columns) -> NDArray[np.int64]:
    """The stable permutation that sorts rows by (source, track, time).

    Raises
    ------
    ValueError
        If two rows share a (source, track, time), naming both by their original index.
    """
    keys = {name: columns[name] for name in ("source", "track", "time")}
    order = np.lexsort((keys["time"], keys["track"], keys["source"])).astype(np.int64)  # last key is primary
    _, repeated = _steps({name: value[order] for name, value in keys.items()})
    if repeated.any():
        k = _first(repeated)
        a, b = sorted((int(order[k]), int(order[k + 1])))
        raise ValueError(f"rows {a} and {b} have the same {_key(columns, b)}; a track has one state per time")
    return order
