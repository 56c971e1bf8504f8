"""Which true target an initiated track is, from the simulation's truth labels."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_int_array


def track_targets(labels: ArrayLike, truth: ArrayLike, min_share: float = 2 / 3) -> NDArray[np.int64]:
    """The target each track holds: for track k (the rows with ``labels == k``, as
    :attr:`InitiationResult.labels`), the true target whose rows make at least ``min_share`` of
    it, or -1 (mostly clutter, or no majority; a tie with clutter is no majority). Rows where
    two targets cross can go to the other's track, so a share below 1 is still that target's
    track.

    >>> track_targets([0, 0, 0, 1, 1, -1], [2, 2, -1, -1, -1, 0]).tolist()
    [2, -1]
    """
    lab = as_int_array("labels", labels, shape=(None,))
    tru = as_int_array("truth", truth, shape=(len(lab),))
    if not 0.0 < min_share <= 1.0:
        raise ValueError(f"min_share: must be in (0, 1], got {min_share}")
    n_tracks = int(lab.max()) + 1 if len(lab) else 0
    out = np.full(n_tracks, -1, dtype=np.int64)
    for k in range(n_tracks):
        values, counts = np.unique(tru[lab == k], return_counts=True)
        if len(counts) and values[np.argmax(counts)] >= 0 and counts.max() >= min_share * counts.sum():
            out[k] = values[np.argmax(counts)]
    return out
