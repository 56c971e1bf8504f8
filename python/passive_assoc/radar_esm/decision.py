"""One-to-one decisions of every scan at once (METHODS §5 step 4).

*Repeated maximum*: take the largest score among the pairs allowed; if it exceeds the
threshold, pair its two tracks and strike both; repeat until no allowed score is left above
it. Exact ties go to the pair whose positions are closer (``tie``, smaller wins), then to the
first in the rows' id-free order (:mod:`.scans`). The scans are independent, so the loop runs
over pairs made (at most ``min(n_radar, n_esm)`` rounds), each round vectorised over scans.

*Optimal assignment* (the nearest-neighbour baseline): the gated minimum-cost assignment per
scan, on the project's 2-D solver.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..assignment import linear_assignment

__all__ = ["repeated_maximum", "gated_assignment"]

Pairs = tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp]]


def repeated_maximum(
    score: NDArray[np.float64], allowed: NDArray[np.bool_], threshold: float, tie: NDArray[np.float64]
) -> Pairs:
    """Pairs ``(scan, radar row, esm row)`` chosen by repeated maximum of ``score`` (K, n_r, n_e)
    over the ``allowed`` entries with ``score > threshold``."""
    k, n_r, n_e = score.shape
    live = np.where(allowed & (score > threshold), score, -np.inf).reshape(k, n_r * n_e)
    ties = np.where(np.isfinite(tie), tie, np.inf).reshape(k, n_r * n_e)
    chosen: list[tuple[NDArray[np.intp], NDArray[np.intp]]] = []
    for _ in range(min(n_r, n_e)):
        best = live.max(axis=1) if n_r * n_e else np.full(k, -np.inf)
        scans = np.flatnonzero(best > -np.inf)
        if len(scans) == 0:
            break
        at_best = live[scans] == best[scans, None]
        flat = np.argmin(np.where(at_best, ties[scans], np.inf), axis=1)
        # A tie key of inf everywhere (no position) still picks a maximum: argmin of all-inf is 0.
        flat = np.where(at_best[np.arange(len(scans)), flat], flat, np.argmax(at_best, axis=1))
        chosen.append((scans, flat))
        rows, cols = np.divmod(flat, n_e)
        grid = live.reshape(k, n_r, n_e)
        grid[scans, rows, :] = -np.inf
        grid[scans, :, cols] = -np.inf
    if not chosen:
        empty = np.empty(0, np.intp)
        return empty, empty, empty
    scans = np.concatenate([s for s, _ in chosen])
    rows, cols = np.divmod(np.concatenate([f for _, f in chosen]), n_e)
    return scans, rows, cols


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
