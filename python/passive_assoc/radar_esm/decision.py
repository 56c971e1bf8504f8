"""One-to-one decisions of every scan at once (METHODS §5 step 4).

*Repeated maximum*: take the largest score among the pairs allowed; if it exceeds the
threshold, pair its two tracks and strike both; repeat until no allowed score is left above
it. Exact ties go to the pair whose positions are closer (``tie``, smaller wins), then to the
first in the rows' id-free order (:mod:`.scans`). In the Rust core, scans in parallel.

*Optimal assignment* (the nearest-neighbour baseline): the gated minimum-cost assignment per
scan, on the project's 2-D solver.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .. import _core
from ..assignment import linear_assignment

__all__ = ["repeated_maximum", "gated_assignment"]

Pairs = tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp]]


def repeated_maximum(
    score: NDArray[np.float64],
    allowed: NDArray[np.bool_],
    threshold: float,
    tie: NDArray[np.float64],
    n_threads: int | None = None,
) -> Pairs:
    """Pairs ``(scan, radar row, esm row)`` chosen by repeated maximum of ``score`` (K, n_r, n_e)
    over the ``allowed`` entries with ``score > threshold``, ties by ``tie`` then order.

    The Rust core does it as one sort per scan and a greedy sweep — the same picks as
    re-taking the maximum after each strike, without a pass over every pair per pick — with
    the scans in parallel."""
    scans, rows, cols = _core.repeated_maximum(
        np.ascontiguousarray(score, dtype=np.float64),
        np.ascontiguousarray(allowed, dtype=np.bool_),
        np.ascontiguousarray(tie, dtype=np.float64),
        float(threshold),
        n_threads,
    )
    return scans.astype(np.intp), rows.astype(np.intp), cols.astype(np.intp)


def gated_assignment(cost: NDArray[np.float64], allowed: NDArray[np.bool_]) -> Pairs:
    """Per scan, the assignment of most allowed pairs and, among those, least total ``cost``
    (K, n_r, n_e); disallowed pairs are never made."""
    scans, rows, cols = [], [], []
    for k in range(cost.shape[0]):
        r_live = np.flatnonzero(allowed[k].any(axis=1))
        c_live = np.flatnonzero(allowed[k].any(axis=0))
        if len(r_live) == 0:
            continue
        if len(r_live) == cost.shape[1] and len(c_live) == cost.shape[2]:
            sub_allowed, sub = allowed[k], cost[k]
        else:
            sub_allowed, sub = allowed[k][np.ix_(r_live, c_live)], cost[k][np.ix_(r_live, c_live)]
        # Forbidden entries cost more than any whole assignment of allowed ones, so the solver
        # first maximises how many allowed pairs it makes.
        big = 1.0 + float(np.abs(sub[sub_allowed]).sum()) * 2.0
        r, c, _ = linear_assignment(np.where(sub_allowed, sub, big))
        keep = sub_allowed[r, c]
        scans.append(np.full(int(keep.sum()), k, np.intp))
        rows.append(r_live[r[keep]])
        cols.append(c_live[c[keep]])
    if not scans:
        empty = np.empty(0, np.intp)
        return empty, empty, empty
    return np.concatenate(scans), np.concatenate(rows).astype(np.intp), np.concatenate(cols).astype(np.intp)
