"""Gated global nearest neighbour: which report of one sensor's scan updates which track.

A report is a candidate for a track when its normalised innovation squared against the
track's prediction is within the gate (``nis ≤ gate``, a χ² gate). Among the candidates, the
one-to-one pairing of tracks and reports that minimises the summed NIS is chosen, a track
that takes no report costing ``gate`` (so a pairing is never forced on a report outside the
gate, and a track takes a far report only when that beats leaving it and its rival
unpaired). Solved exactly by :func:`~passive_assoc.assignment.linear_assignment`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, as_float_scalar
from ..assignment import linear_assignment

__all__ = ["nearest_neighbour"]


def nearest_neighbour(nis: ArrayLike, gate: float) -> NDArray[np.int64]:
    """Each report's track under the gated global nearest neighbour rule (module doc).

    Parameters
    ----------
    nis : array_like, shape (T, R)
        The NIS of every (track, report) pair, ≥ 0 (``inf``: never a pair).
    gate : float
        The χ² gate, > 0.

    Returns
    -------
    ndarray of int, shape (R,)
        Each report's track (row of ``nis``), or −1.
    """
    costs = as_float_array("nis", nis, ndim=2)
    if np.isnan(costs).any() or (costs < 0).any():
        raise ValueError("nis: every value must be >= 0 (inf for no pair)")
    limit = as_float_scalar("gate", gate, finite=True)
    if not limit > 0:
        raise ValueError(f"gate: must be > 0, got {limit!r}")
    n_tracks, n_reports = costs.shape
    out = np.full(n_reports, -1, dtype=np.int64)
    if n_tracks == 0 or n_reports == 0:
        return out
    # One "no report" column per track, then the reports inside the gate.
    miss = np.full((n_tracks, n_tracks), np.inf)
    np.fill_diagonal(miss, limit)
    matrix = np.ascontiguousarray(np.hstack([miss, np.where(costs <= limit, costs, np.inf)]))
    rows, cols, _ = linear_assignment(matrix)
    taken = cols >= n_tracks
    out[cols[taken] - n_tracks] = rows[taken]
    return out
