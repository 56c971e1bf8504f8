"""State-vector conventions: this library's *block* order and the *interleaved* order.

This library stacks a track state by block, all positions first (METHODS §0's
``X0 = (x0, y0, z0, vx, vy, vz)``, and :attr:`TrackTable.state`)::

    [x, y, z, vx, vy, vz, ax, ay, az]        (blocks: position, velocity, acceleration)

Stone Soup and MATLAB's tracking toolboxes interleave by axis::

    [x, vx, ax, y, vy, ay, z, vz, az]

Both orders hold the same numbers; the functions here permute states and covariances from
one to the other. ``ndim`` is the number of spatial axes (1, 2 or 3) and ``blocks`` the number
of blocks (1 = position, 2 = + velocity, 3 = + acceleration), so ``d = ndim * blocks``.

>>> to_interleaved([1.0, 2.0, 3.0, 4.0], ndim=2, blocks=2)  # (x, y, vx, vy)
array([1., 3., 2., 4.])
>>> from_interleaved([1.0, 3.0, 2.0, 4.0], ndim=2, blocks=2)
array([1., 2., 3., 4.])
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, as_int_scalar

__all__ = [
    "interleaved_order",
    "to_interleaved",
    "from_interleaved",
    "covariance_to_interleaved",
    "covariance_from_interleaved",
]


def interleaved_order(ndim: int, blocks: int) -> NDArray[np.int64]:
    """Indices ``P`` with ``interleaved = blocked[..., P]`` (length ``ndim * blocks``).

    Entry ``k * blocks + b`` (axis k, block b of the interleaved vector) is ``b * ndim + k``.
    """
    ndim, blocks = _check_layout(ndim, blocks)
    axis, block = np.meshgrid(np.arange(ndim), np.arange(blocks), indexing="ij")
    return (block * ndim + axis).ravel().astype(np.int64)


def _check_layout(ndim: int, blocks: int) -> tuple[int, int]:
    ndim = as_int_scalar("ndim", ndim, minimum=1)
    blocks = as_int_scalar("blocks", blocks, minimum=1)
    if ndim > 3:
        raise ValueError(f"ndim: expected 1, 2 or 3, got {ndim}")
    if blocks > 3:
        raise ValueError(f"blocks: expected 1 (position), 2 (+ velocity) or 3 (+ acceleration), got {blocks}")
    return ndim, blocks


def _vectors(name: str, value: ArrayLike, d: int) -> NDArray[np.float64]:
    arr = as_float_array(name, value)
    if arr.ndim < 1 or arr.shape[-1] != d:
        raise ValueError(f"{name}: expected shape (..., {d}) (ndim × blocks), got {arr.shape}")
    return arr


def _matrices(name: str, value: ArrayLike, d: int) -> NDArray[np.float64]:
    arr = as_float_array(name, value)
    if arr.ndim < 2 or arr.shape[-2:] != (d, d):
        raise ValueError(f"{name}: expected shape (..., {d}, {d}) (ndim × blocks), got {arr.shape}")
    return arr


def to_interleaved(state: ArrayLike, ndim: int, blocks: int) -> NDArray[np.float64]:
    """Block-ordered state(s) ``(..., d)`` → interleaved ``(..., d)`` (a new array)."""
    order = interleaved_order(ndim, blocks)
    return _vectors("state", state, order.size)[..., order]


def from_interleaved(state: ArrayLike, ndim: int, blocks: int) -> NDArray[np.float64]:
    """Interleaved state(s) ``(..., d)`` → block-ordered ``(..., d)`` (a new array)."""
    order = np.argsort(interleaved_order(ndim, blocks))
    return _vectors("state", state, order.size)[..., order]


def covariance_to_interleaved(covariance: ArrayLike, ndim: int, blocks: int) -> NDArray[np.float64]:
    """Block-ordered covariance(s) ``(..., d, d)`` → interleaved: rows and columns permuted."""
    order = interleaved_order(ndim, blocks)
    return _matrices("covariance", covariance, order.size)[..., order, :][..., order]


def covariance_from_interleaved(covariance: ArrayLike, ndim: int, blocks: int) -> NDArray[np.float64]:
    """Interleaved covariance(s) ``(..., d, d)`` → block-ordered: rows and columns permuted."""
    order = np.argsort(interleaved_order(ndim, blocks))
    return _matrices("covariance", covariance, order.size)[..., order, :][..., order]
