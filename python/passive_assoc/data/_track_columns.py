"""The flat columns of a :class:`TrackTable` (CSV headers, DataFrame columns): their names,
and the split of a flat mapping back into the table's block columns."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ._track_checks import BLOCKS

__all__ = ["KEYS", "block_names", "covariance_names", "split_columns"]

KEYS = ("source", "track", "time")
_AXES = ("x", "y", "z")
#: Column prefix of each state block: x, vx, ax.
_PREFIX = {"position": "", "velocity": "v", "acceleration": "a"}


def block_names(block: str, ndim: int) -> list[str]:
    """Flat column names of one state block: ``["vx", "vy"]`` for a 2-D velocity."""
    return [_PREFIX[block] + axis for axis in _AXES[:ndim]]


def covariance_names(d: int) -> list[tuple[int, int, str]]:
    """``(i, j, "cov_i_j")`` for the upper triangle ``i <= j`` of a d × d covariance."""
    return [(i, j, f"cov_{i}_{j}") for i in range(d) for j in range(i, d)]


def _missing(names: list[str], columns: Mapping[str, ArrayLike]) -> list[str]:
    return [name for name in names if name not in columns]


def _ndim(columns: Mapping[str, ArrayLike]) -> int:
    present = [axis in columns for axis in _AXES]
    ndim = sum(present)
    if ndim == 0 or present[:ndim] != [True] * ndim:
        raise ValueError(f"columns: position needs x, then y, then z (got {[a for a in _AXES if a in columns]})")
    return ndim


def _block(block: str, ndim: int, columns: Mapping[str, ArrayLike]) -> Any:
    names = block_names(block, ndim)
    missing = _missing(names, columns)
    if len(missing) == len(names):
        return None
    if missing:
        raise ValueError(f"columns: {block} needs {names}, missing {missing}")
    return np.column_stack([np.asarray(columns[name]) for name in names])


def _covariance(d: int, columns: Mapping[str, ArrayLike]) -> Any:
    names = covariance_names(d)
    missing = _missing([name for _, _, name in names], columns)
    if len(missing) == len(names):
        return None
    if missing:
        raise ValueError(
            f"columns: the covariance of a {d}-long state needs every cov_i_j, i <= j < {d}; missing {missing}"
        )
    n = len(np.asarray(columns[names[0][2]]))
    cov = np.empty((n, d, d))
    for i, j, name in names:
        cov[:, i, j] = cov[:, j, i] = columns[name]
    return cov


def split_columns(columns: Mapping[str, ArrayLike]) -> dict[str, Any]:
    """Flat columns → the keyword arguments of :meth:`TrackTable.from_arrays`."""
    names = list(columns)
    for required in (*KEYS, "x"):
        if required not in columns:
            raise ValueError(f"columns: missing required column {required!r} (got {names})")
    ndim = _ndim(columns)
    out: dict[str, Any] = {key: columns[key] for key in KEYS}
    out["position"] = _block("position", ndim, columns)
    out["velocity"] = _block("velocity", ndim, columns)
    out["acceleration"] = _block("acceleration", ndim, columns)
    n_blocks = sum(out[block] is not None for block in BLOCKS)
    out["covariance"] = _covariance(ndim * n_blocks, columns)
    out["truth"] = columns.get("truth")
    known = {*KEYS, "truth"}
    known.update(name for block in BLOCKS for name in block_names(block, ndim))
    known.update(name for _, _, name in covariance_names(ndim * n_blocks))
    unknown = [name for name in names if name not in known]
    if unknown:
        raise ValueError(
            f"columns: unknown column {unknown[0]!r}; a {ndim}-D table with blocks {BLOCKS[:n_blocks]} has "
            f"{sorted(known)}"
        )
    return out
