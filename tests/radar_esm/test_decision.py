"""The repeated-maximum decision (METHODS §5 step 4) in the core against the literal loop —
take the best allowed score above the threshold, strike its row and column, repeat — on
random scans with ties, masks, NaN and thresholds."""

from __future__ import annotations

import numpy as np
import pytest
from passive_assoc.radar_esm.decision import repeated_maximum


def literal(score: np.ndarray, allowed: np.ndarray, threshold: float, tie: np.ndarray) -> set[tuple[int, int, int]]:
    """One scan at a time, one pick at a time: the smallest tie key among the maxima, then the
    first flat index."""
    out = set()
    for k in range(score.shape[0]):
        live = np.where(allowed[k] & (score[k] > threshold), score[k], -np.inf)
        keys = np.where(np.isfinite(tie[k]), tie[k], np.inf)
        while np.isfinite(live).any() and live.max() > -np.inf:
            best = live.max()
            at_best = np.flatnonzero(live.ravel() == best)
            flat = at_best[np.argmin(keys.ravel()[at_best])]
            r, e = divmod(int(flat), score.shape[2])
            out.add((k, r, e))
            live[r, :] = -np.inf
            live[:, e] = -np.inf
    return out


@pytest.mark.parametrize("seed", range(20))
def test_the_core_makes_the_literal_loops_picks(seed: int) -> None:
    rng = np.random.default_rng(seed)
    shape = (int(rng.integers(1, 6)), int(rng.integers(0, 9)), int(rng.integers(0, 9)))
    score = rng.integers(0, 5, shape) / 4.0  # few distinct values: many exact ties
    score[rng.random(shape) < 0.1] = np.nan
    tie = rng.integers(0, 3, shape).astype(float)
    tie[rng.random(shape) < 0.2] = np.inf
    allowed = rng.random(shape) < 0.8
    threshold = float(rng.choice([-np.inf, 0.0, 0.3]))
    scans, rows, cols = repeated_maximum(score, allowed, threshold, tie)
    picks = list(zip(scans.tolist(), rows.tolist(), cols.tolist(), strict=True))
    assert len(picks) == len(set(picks))
    assert set(picks) == literal(score, allowed, threshold, tie)
    assert all(allowed[p] and score[p] > threshold for p in picks)


def test_picks_do_not_depend_on_the_thread_count() -> None:
    rng = np.random.default_rng(1)
    score = rng.random((30, 60, 60))
    allowed = rng.random(score.shape) < 0.5
    tie = rng.random(score.shape)
    one = repeated_maximum(score, allowed, 0.2, tie, n_threads=1)
    for threads in (2, None):
        other = repeated_maximum(score, allowed, 0.2, tie, n_threads=threads)
        assert all(np.array_equal(a, b) for a, b in zip(one, other, strict=True))
    assert len(one[0]) > 30 * 40


def test_mismatched_shapes_are_named() -> None:
    with pytest.raises(ValueError, match="tie"):
        repeated_maximum(np.zeros((1, 2, 2)), np.ones((1, 2, 2), bool), 0.0, np.zeros((1, 2, 3)))
