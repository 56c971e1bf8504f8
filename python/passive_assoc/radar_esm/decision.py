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

__all__ = ["repeated_maximum"]

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
