"""Evaluation metrics (METHODS §6): RMS and efficiency, GOSPA, association scores."""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linear_sum_assignment

from .._validation import (
    as_float_array,
    as_float_scalar,
    as_int_array,
    require_finite,
    require_positive,
)

__all__ = [
    "rms_per_component",
    "efficiency",
    "GospaResult",
    "gospa",
    "association_accuracy",
    "PairwiseScores",
    "pairwise_scores",
    "same_cluster_pairs",
]


def rms_per_component(estimates: ArrayLike, truth: ArrayLike) -> NDArray[np.float64]:
    """Root-mean-square error of each state component over runs.

    Parameters
    ----------
    estimates : array_like, shape (R, D)
        One estimated state per run (R >= 1), all finite.
    truth : array_like, shape (D,) or (R, D)
        The true state, common to all runs or one per run.

    Returns
    -------
    numpy.ndarray, shape (D,)
        ``sqrt(mean_r (estimates[r] - truth[r]) ** 2)`` per component.
    """
    est = as_float_array("estimates", estimates, ndim=2)
    if est.shape[0] == 0:
        raise ValueError("estimates: need at least one run, got shape (0, D)")
    require_finite("estimates", est)
    tru = as_float_array("truth", truth)
    if tru.shape not in ((est.shape[1],), est.shape):
        raise ValueError(f"truth: expected shape ({est.shape[1]},) or {est.shape}, got {tru.shape}")
    require_finite("truth", tru)
    rms: NDArray[np.float64] = np.sqrt(np.mean((est - tru) ** 2, axis=0))
    return rms


def efficiency(rms: ArrayLike, covariance: ArrayLike) -> NDArray[np.float64]:
    """RMS divided by the standard deviation implied by a covariance (e.g. the CRLB).

    Parameters
    ----------
    rms : array_like, shape (D,)
    covariance : array_like, shape (D, D)
        Its diagonal must be positive.

    Returns
    -------
    numpy.ndarray, shape (D,)
        ``rms / sqrt(diag(covariance))``; 1 means the bound is attained.
    """
    r = as_float_array("rms", rms, ndim=1)
    cov = as_float_array("covariance", covariance, shape=(r.shape[0], r.shape[0]))
    require_finite("rms", r)
    diag = np.ascontiguousarray(np.diag(cov))
    require_finite("covariance diagonal", diag)
    require_positive("covariance diagonal", diag)
    return r / np.sqrt(diag)


class GospaResult(NamedTuple):
    """GOSPA distance and its decomposition.

    ``localisation``, ``missed`` and ``false`` are the p-th-power contributions, so
    ``total == (localisation + missed + false) ** (1 / p)``. ``assignment`` is an (k, 2)
    int array of (estimate index, truth index) pairs counted as localisation.
    """

    total: float
    localisation: float
    missed: float
    false: float
    assignment: NDArray[np.int64]


def _points(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """An (n, d) point set; an empty input (``[]`` or shape (0, d)) gives n = 0."""
    arr = as_float_array(name, value)
    if arr.size == 0 and arr.ndim in (1, 2):
        return arr.reshape(0, arr.shape[1] if arr.ndim == 2 else 0)
    arr = as_float_array(name, arr, ndim=2)
    require_finite(name, arr)
    return arr


def gospa(estimates: ArrayLike, truth: ArrayLike, c: float, p: float = 2.0, alpha: float = 2.0) -> GospaResult:
    """Generalised OSPA metric (Rahmathullah, García-Fernández & Svensson, 2017).

    Parameters
    ----------
    estimates : array_like, shape (n, d)
        Estimated points (n may be 0; ``[]`` is accepted).
    truth : array_like, shape (m, d)
        True points (m may be 0).
    c : float
        Cut-off distance, > 0.
    p : float
        Order, >= 1.
    alpha : float
        In (0, 2]; 2 is the value for which the split into parts is meaningful.

    Returns
    -------
    GospaResult

    Notes
    -----
    The optimal assignment minimises ``sum min(d, c) ** p`` over assignments of the smaller
    set into the larger (``scipy.optimize.linear_sum_assignment``). With ``alpha = 2`` an
    assigned pair at distance ``>= c`` is counted as one missed and one false target (each
    ``c**p / 2``) and left out of ``assignment``; every unassigned truth adds ``c**p / 2``
    to ``missed`` and every unassigned estimate ``c**p / 2`` to ``false``. With another
    alpha, capped pairs stay in ``localisation`` (cost ``c**p``) and the cardinality
    mismatch costs ``c**p / alpha`` per point.
    """
    c = as_float_scalar("c", c)
    p = as_float_scalar("p", p)
    alpha = as_float_scalar("alpha", alpha)
    if not (np.isfinite(c) and c > 0):
        raise ValueError(f"c: must be finite and > 0, got {c!r}")
    if not (np.isfinite(p) and p >= 1):
        raise ValueError(f"p: must be finite and >= 1, got {p!r}")
    if not 0 < alpha <= 2:
        raise ValueError(f"alpha: must be in (0, 2], got {alpha!r}")
    x, y = _points("estimates", estimates), _points("truth", truth)
    n, m = x.shape[0], y.shape[0]
    if n and m and x.shape[1] != y.shape[1]:
        raise ValueError(f"truth: points have dimension {y.shape[1]} but estimates have {x.shape[1]}")
    if n == 0 or m == 0:
        dist = np.zeros((n, m))  # nothing to assign; only cardinality terms remain
    else:
        dist = np.linalg.norm(x[:, None, :] - y[None, :, :], axis=-1)
    rows, cols = linear_sum_assignment(np.minimum(dist, c) ** p)
    d = dist[rows, cols]
    keep = d < c if alpha == 2 else np.ones(d.shape, dtype=bool)
    loc = float(np.sum(np.minimum(d[keep], c) ** p))
    n_pairs = int(keep.sum())
    missed = (m - n_pairs) * c**p / alpha
    false = (n - n_pairs) * c**p / alpha
    if alpha != 2:
        # Capped pairs stay in ``loc``; only the cardinality difference is penalised.
        missed, false = max(m - n, 0) * c**p / alpha, max(n - m, 0) * c**p / alpha
    pairs = np.column_stack([rows[keep], cols[keep]]).astype(np.int64).reshape(-1, 2)
    total = float((loc + missed + false) ** (1.0 / p))
    return GospaResult(total, loc, float(missed), float(false), pairs)


def _as_tuple(name: str, item: int | Sequence[int] | ArrayLike) -> tuple[int, ...]:
    arr = as_int_array(name, item)
    return tuple(int(v) for v in arr.reshape(-1))


def association_accuracy(
    estimated_tuples: Iterable[int | Sequence[int]],
    true_tuples: Iterable[int | Sequence[int]],
    *,
    ordered: bool = True,
) -> float:
    """Fraction of true tuples that appear exactly among the estimated tuples.

    Parameters
    ----------
    estimated_tuples, true_tuples : iterable of int or sequence of int
        A tuple is whatever identifies one target's association: e.g. the per-sensor
        measurement indices ``(i_1, ..., i_S)`` of METHODS §2 (0 = missed), or the row
        indices of one track. A bare int is a 1-tuple.
    ordered : bool
        If True, ``(1, 2) != (2, 1)`` (per-sensor tuples). If False, tuples are compared
        as sorted multisets (tracks given as unordered sets of rows).

    Returns
    -------
    float
        ``#(true tuples recovered) / #(true tuples)``. Each true tuple counts once per
        occurrence; extra estimated tuples do not lower the score (false tracks are
        measured by GOSPA or pairwise precision instead).

    Raises
    ------
    ValueError
        If ``true_tuples`` is empty (the fraction is undefined).
    """

    def norm(name: str, t: int | Sequence[int]) -> tuple[int, ...]:
        tup = _as_tuple(name, t)
        return tup if ordered else tuple(sorted(tup))

    est = {norm(f"estimated_tuples[{i}]", t) for i, t in enumerate(estimated_tuples)}
    tru = [norm(f"true_tuples[{i}]", t) for i, t in enumerate(true_tuples)]
    if not tru:
        raise ValueError("true_tuples: is empty; accuracy is undefined")
    return sum(t in est for t in tru) / len(tru)


class PairwiseScores(NamedTuple):
    """Precision, recall and F1 over pairwise association decisions, with the counts."""

    precision: float
    recall: float
    f1: float
    tp: int
    fp: int
    fn: int


def pairwise_scores(
    predicted_pairs: Iterable[Hashable],
    true_pairs: Iterable[Hashable],
    *,
    zero_division: float = 1.0,
) -> PairwiseScores:
    """Score predicted pair decisions against the true ones (METHODS §6, paper 002).

    Parameters
    ----------
    predicted_pairs, true_pairs : iterable of hashable
        Each element is one "these two belong together" decision, e.g. ``(i, j)`` with
        ``i < j`` from :func:`same_cluster_pairs`, or ``(local_track, system_track)``.
        Duplicates are ignored (sets are compared). The caller normalises unordered pairs.
    zero_division : float
        Value of precision when nothing is predicted and of recall when nothing is true
        (both 0/0). The default 1.0 reads "no claims, no errors".

    Returns
    -------
    PairwiseScores
        ``f1 = 2PR / (P + R)``, 0 when ``P + R == 0``.
    """
    pred, true = set(predicted_pairs), set(true_pairs)
    tp = len(pred & true)
    fp, fn = len(pred) - tp, len(true) - tp
    precision = tp / (tp + fp) if tp + fp else float(zero_division)
    recall = tp / (tp + fn) if tp + fn else float(zero_division)
    f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
    return PairwiseScores(precision, recall, f1, tp, fp, fn)


def same_cluster_pairs(labels: ArrayLike) -> set[tuple[int, int]]:
    """Unordered index pairs ``(i, j)``, ``i < j``, whose labels are equal.

    Parameters
    ----------
    labels : array_like of int, shape (N,)
        Cluster label per item; -1 means unassociated and is never paired.

    Returns
    -------
    set of tuple of int
    """
    lab = as_int_array("labels", labels, ndim=1)
    if (lab < -1).any():
        i = int(np.flatnonzero(lab < -1)[0])
        raise ValueError(f"labels[{i}] = {lab[i]}; labels must be >= 0 or -1 (unassociated)")
    out: set[tuple[int, int]] = set()
    for value in np.unique(lab[lab >= 0]):
        members = np.flatnonzero(lab == value).tolist()
        out.update((a, b) for k, a in enumerate(members) for b in members[k + 1 :])
    return out
