"""Tests of the evaluation metrics against hand-computed values."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from passive_assoc.evaluation import (
    association_accuracy,
    efficiency,
    gospa,
    pairwise_scores,
    rms_per_component,
    same_cluster_pairs,
)

# --------------------------------------------------------------------------- RMS


def test_rms_per_component_hand_values() -> None:
    est = [[1.0, 2.0, 0.0], [3.0, 2.0, 4.0]]
    assert rms_per_component(est, [2.0, 2.0, 0.0]).tolist() == [1.0, 0.0, math.sqrt(8.0)]
    per_run = [[1.0, 2.0, 0.0], [3.0, 0.0, 4.0]]
    assert rms_per_component(est, per_run).tolist() == [0.0, math.sqrt(2.0), 0.0]


def test_rms_rejects_bad_input() -> None:
    with pytest.raises(ValueError, match=r"^truth: expected shape \(2,\) or \(1, 2\)"):
        rms_per_component([[1.0, 2.0]], [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match=r"^estimates: need at least one run"):
        rms_per_component(np.zeros((0, 2)), [0.0, 0.0])
    with pytest.raises(ValueError, match=r"^estimates\[1, 0\] = nan"):
        rms_per_component([[1.0], [np.nan]], [0.0])
    with pytest.raises(ValueError, match=r"^estimates: expected a 2-dimensional"):
        rms_per_component([1.0, 2.0], [0.0])


def test_efficiency() -> None:
    cov = np.array([[4.0, 1.0], [1.0, 9.0]])
    assert efficiency([2.0, 6.0], cov).tolist() == [1.0, 2.0]
    with pytest.raises(ValueError, match=r"^covariance diagonal\[1\] = 0\.0; must be > 0"):
        efficiency([1.0, 1.0], np.diag([1.0, 0.0]))
    with pytest.raises(ValueError, match=r"^covariance: expected shape \(2, 2\)"):
        efficiency([1.0, 1.0], np.eye(3))


# --------------------------------------------------------------------------- GOSPA


def test_gospa_identical_and_empty() -> None:
    pts = [[1.0, 2.0], [5.0, -1.0]]
    r = gospa(pts, pts, c=3.0)
    assert r.total == 0.0 and r.assignment.tolist() == [[0, 0], [1, 1]]
    r = gospa([], [], c=3.0)
    assert (r.total, r.localisation, r.missed, r.false) == (0.0, 0.0, 0.0, 0.0)
    assert r.assignment.shape == (0, 2)


def test_gospa_all_missed_and_all_false() -> None:
    r = gospa([], [[0.0, 0.0], [1.0, 1.0], [5.0, 5.0]], c=10.0)  # p = 2: c^p/2 = 50 each
    assert (r.localisation, r.missed, r.false) == (0.0, 150.0, 0.0)
    assert r.total == pytest.approx(math.sqrt(150.0), rel=1e-15)
    r = gospa(np.zeros((2, 3)), np.zeros((0, 3)), c=4.0, p=1.0)  # c^p/2 = 2 each
    assert (r.missed, r.false, r.total) == (0.0, 4.0, 4.0)


def test_gospa_localisation_and_cutoff() -> None:
    r = gospa([[0.0, 0.0]], [[3.0, 4.0]], c=10.0)
    assert (r.localisation, r.missed, r.false, r.total) == (25.0, 0.0, 0.0, 5.0)
    # Beyond the cut-off the pair is one missed plus one false target, c^p/2 each.
    r = gospa([[0.0, 0.0]], [[30.0, 40.0]], c=10.0)
    assert (r.localisation, r.missed, r.false) == (0.0, 50.0, 50.0)
    assert r.total == 10.0 and r.assignment.shape == (0, 2)


def test_gospa_mixed_case() -> None:
    # est0 -> truth0 at d = 1; est1 is farther than c from everything; two truths left.
    r = gospa([[0.0, 0.0], [10.0, 0.0]], [[1.0, 0.0], [50.0, 50.0], [3.0, 3.0]], c=5.0)
    assert (r.localisation, r.missed, r.false) == (1.0, 25.0, 12.5)
    assert r.total == pytest.approx(math.sqrt(38.5), rel=1e-15)
    assert r.assignment.tolist() == [[0, 0]]


def test_gospa_is_optimal_not_greedy() -> None:
    # Greedy nearest-first would pair 2 with 1 (d = 1) and then 0 with 3 (d = 3).
    r = gospa([[0.0], [2.0]], [[1.0], [3.0]], c=10.0, p=1.0)
    assert r.localisation == 2.0 and sorted(r.assignment.tolist()) == [[0, 0], [1, 1]]


def test_gospa_other_alpha() -> None:
    # alpha = 1: cardinality mismatch costs c^p / alpha = 4 per point.
    r = gospa([[0.0, 0.0]], [[0.0, 1.0], [100.0, 100.0]], c=2.0, alpha=1.0)
    assert (r.localisation, r.missed, r.false) == (1.0, 4.0, 0.0)
    assert r.total == pytest.approx(math.sqrt(5.0))


def _brute_gospa(x: np.ndarray, y: np.ndarray, c: float, p: float) -> float:
    """alpha = 2 GOSPA as min over all partial matchings (unmatched points cost c^p/2)."""
    best = math.inf
    for k in range(min(len(x), len(y)) + 1):
        for xs in itertools.combinations(range(len(x)), k):
            for ys in itertools.permutations(range(len(y)), k):
                pairs = zip(xs, ys, strict=True)
                cost = sum(min(np.linalg.norm(x[i] - y[j]), c) ** p for i, j in pairs)
                cost += (len(x) + len(y) - 2 * k) * c**p / 2
                best = min(best, cost)
    return best ** (1 / p)


point_sets = arrays(np.float64, st.tuples(st.integers(0, 4), st.just(2)), elements=st.floats(-10, 10))


@settings(max_examples=80, deadline=None)
@given(point_sets, point_sets, st.floats(0.5, 8.0), st.sampled_from([1.0, 2.0, 3.0]))
def test_gospa_matches_brute_force_and_is_symmetric(x: np.ndarray, y: np.ndarray, c: float, p: float) -> None:
    r = gospa(x, y, c=c, p=p)
    assert r.total == pytest.approx(_brute_gospa(x, y, c, p), rel=1e-9, abs=1e-12)
    parts = r.localisation + r.missed + r.false
    assert r.total == pytest.approx(parts ** (1 / p), rel=1e-12)
    s = gospa(y, x, c=c, p=p)
    assert s.total == pytest.approx(r.total, rel=1e-9, abs=1e-12)
    assert s.missed == pytest.approx(r.false) and s.false == pytest.approx(r.missed)


def test_gospa_rejects_bad_input() -> None:
    with pytest.raises(ValueError, match=r"^c: must be finite and > 0"):
        gospa([[0.0]], [[0.0]], c=0.0)
    with pytest.raises(ValueError, match=r"^p: must be finite and >= 1"):
        gospa([[0.0]], [[0.0]], c=1.0, p=0.5)
    with pytest.raises(ValueError, match=r"^alpha: must be in \(0, 2\]"):
        gospa([[0.0]], [[0.0]], c=1.0, alpha=3.0)
    with pytest.raises(ValueError, match=r"^truth: points have dimension 3"):
        gospa([[0.0, 0.0]], [[0.0, 0.0, 0.0]], c=1.0)
    with pytest.raises(ValueError, match=r"^estimates\[0, 1\] = nan"):
        gospa([[0.0, np.nan]], [[0.0, 0.0]], c=1.0)
    with pytest.raises(TypeError, match=r"^c: expected a real number"):
        gospa([[0.0]], [[0.0]], c="1")  # type: ignore[arg-type]


# --------------------------------------------------------------------------- association


def test_association_accuracy() -> None:
    true = [(1, 2, 0), (3, 0, 1), (2, 2, 2)]
    est = [(1, 2, 0), (0, 3, 1), (2, 2, 2), (9, 9, 9)]
    assert association_accuracy(est, true) == pytest.approx(2 / 3)
    assert association_accuracy(est, true, ordered=False) == 1.0  # (0,3,1) ~ (3,0,1)
    assert association_accuracy([4, 5], [4, 6]) == 0.5  # ints are 1-tuples
    assert association_accuracy([np.array([1, 2])], [[1, 2], [1, 2]]) == 1.0
    assert association_accuracy([], [(1, 2)]) == 0.0
    with pytest.raises(ValueError, match=r"^true_tuples: is empty"):
        association_accuracy([(1, 2)], [])
    with pytest.raises(ValueError, match=r"^estimated_tuples\[0\]\[1\] = 1\.5 is not an integer"):
        association_accuracy([(1, 1.5)], [(1, 2)])


def test_pairwise_scores_hand_values() -> None:
    pred = {(0, 1), (2, 3), (4, 5), (6, 7)}
    true = {(0, 1), (2, 3), (1, 2)}
    s = pairwise_scores(pred, true)
    assert (s.tp, s.fp, s.fn) == (2, 2, 1)
    assert s.precision == 0.5 and s.recall == pytest.approx(2 / 3)
    assert s.f1 == pytest.approx(2 * 0.5 * (2 / 3) / (0.5 + 2 / 3))
    assert pairwise_scores([(0, 1), (0, 1)], [(0, 1)]).f1 == 1.0  # duplicates ignored


def test_pairwise_scores_degenerate() -> None:
    s = pairwise_scores([], [])
    assert (s.precision, s.recall, s.f1, s.tp, s.fp, s.fn) == (1.0, 1.0, 1.0, 0, 0, 0)
    s = pairwise_scores([], [(0, 1)])
    assert (s.precision, s.recall, s.f1, s.fn) == (1.0, 0.0, 0.0, 1)
    s = pairwise_scores([], [(0, 1)], zero_division=0.0)
    assert (s.precision, s.recall, s.f1) == (0.0, 0.0, 0.0)
    s = pairwise_scores([(0, 1)], [(2, 3)])
    assert (s.precision, s.recall, s.f1) == (0.0, 0.0, 0.0)


def test_same_cluster_pairs() -> None:
    assert same_cluster_pairs([0, 1, 0, -1, -1, 1, 0]) == {(0, 2), (0, 6), (2, 6), (1, 5)}
    assert same_cluster_pairs([-1, -1, -1]) == set()
    assert same_cluster_pairs([]) == set()
    assert same_cluster_pairs([3, 7]) == set()
    with pytest.raises(ValueError, match=r"^labels\[1\] = -2"):
        same_cluster_pairs([0, -2])
    with pytest.raises(ValueError, match=r"^labels: expected a 1-dimensional"):
        same_cluster_pairs([[0, 1]])


def test_pairwise_from_labels_end_to_end() -> None:
    true = same_cluster_pairs([0, 0, 0, 1, 1, -1])  # 3 + 1 = 4 true pairs
    pred = same_cluster_pairs([0, 0, 1, 1, 1, -1])  # (0,1) right; (2,3),(2,4) wrong; (3,4) right
    s = pairwise_scores(pred, true)
    assert (s.tp, s.fp, s.fn) == (2, 2, 2) and s.f1 == 0.5


def test_track_targets_names_the_target_of_each_track() -> None:
    from passive_assoc.evaluation import track_targets

    # Track 0: 2 of 3 rows are target 4's (exactly two thirds); track 1: target 0 and clutter
    # tie, and a tie is no majority; track 2: all clutter; the last row is clutter.
    labels = [0, 0, 0, 1, 1, 2, 2, -1]
    truth = [4, 4, 1, 0, -1, -1, -1, 0]
    assert track_targets(labels, truth).tolist() == [4, -1, -1]
    assert track_targets(labels, truth, min_share=0.5).tolist() == [4, -1, -1]
    assert track_targets(labels, truth, min_share=0.9).tolist() == [-1, -1, -1]
    assert track_targets([], []).tolist() == []
    with pytest.raises(ValueError, match="min_share"):
        track_targets(labels, truth, min_share=0.0)
    with pytest.raises(ValueError, match="truth"):
        track_targets(labels, truth[:-1])
