"""Scores of track-to-track association against the truth labels of simulated tracks
(METHODS §4/§6: TP = associated and the same target, FP = associated and different targets,
FN = the same target not associated)."""

from __future__ import annotations

import numpy as np

from ..data import TrackTable
from ..track_association import TrackAssociation
from .metrics import PairwiseScores, pairwise_scores

__all__ = ["track_association_scores", "track_pair_scores"]

Decision = tuple[float, int, int, int]  # time, local source, local track, system track


def track_association_scores(
    association: TrackAssociation, local: TrackTable, system: TrackTable, *, since: float | None = None
) -> PairwiseScores:
    """Precision, recall and F1 of every (local track, system track) decision of every scan
    at or after ``since``, from the tables' ``truth`` columns.

    A true pair is a local and a system track of the same time with the same target label
    (≥ 0); false tracks (label −1) are never a true pair, so pairing one is a false positive.
    """
    for name, table in (("local", local), ("system", system)):
        if table.truth is None:
            raise ValueError(f"{name}: scoring needs the truth column of simulated tracks")
    start = -np.inf if since is None else float(since)
    local_truth = _labels(local)
    system_truth = _labels(system)
    predicted: set[Decision] = set()
    p = association.pairs
    for t, src, a, b in zip(p.time, p.source, p.local_track, p.system_track, strict=True):
        if t >= start:
            predicted.add((float(t), int(src), int(a), int(b)))
    true: set[Decision] = set()
    by_scan: dict[float, dict[int, int]] = {}
    for (t, _, track), label in system_truth.items():
        if label >= 0 and t >= start:
            by_scan.setdefault(t, {})[label] = track
    for (t, src, track), label in local_truth.items():
        match = by_scan.get(t, {}).get(label) if label >= 0 else None
        if match is not None:
            true.add((t, src, track, match))
    return pairwise_scores(predicted, true)


def track_pair_scores(
    association: TrackAssociation, local: TrackTable, system: TrackTable, *, min_share: float = 0.5
) -> PairwiseScores:
    """Precision, recall and F1 of whole-track decisions: a (local track, system track) pair is
    *declared* when the association paired the two on at least ``min_share`` of the scans at
    which both have a state, and *true* when their truth labels (≥ 0) agree on most of those
    scans. Pairs of tracks that never share a scan are neither.

    The per-scan score (:func:`track_association_scores`) counts every scan of a long pair; this
    one counts the pair once, as an operator reading the fused picture would.
    """
    for name, table in (("local", local), ("system", system)):
        if table.truth is None:
            raise ValueError(f"{name}: scoring needs the truth column of simulated tracks")
    if not 0.0 < min_share <= 1.0:
        raise ValueError(f"min_share: must be in (0, 1], got {min_share}")
    system_at: dict[float, list[tuple[int, int]]] = {}
    for t, k, label in zip(system.time, system.track, _truth(system), strict=True):
        system_at.setdefault(float(t), []).append((int(k), int(label)))
    common: dict[tuple[int, int, int], int] = {}
    agree: dict[tuple[int, int, int], int] = {}
    for t, src, a, label in zip(local.time, local.source, local.track, _truth(local), strict=True):
        for b, other in system_at.get(float(t), ()):
            key = (int(src), int(a), b)
            common[key] = common.get(key, 0) + 1
            if label >= 0 and label == other:
                agree[key] = agree.get(key, 0) + 1
    paired: dict[tuple[int, int, int], int] = {}
    p = association.pairs
    for src, a, b in zip(p.source, p.local_track, p.system_track, strict=True):
        key = (int(src), int(a), int(b))
        paired[key] = paired.get(key, 0) + 1
    declared = {key for key, n in paired.items() if key in common and n >= min_share * common[key]}
    true = {key for key, n in agree.items() if 2 * n > common[key]}
    return pairwise_scores(declared, true)


def _truth(table: TrackTable) -> list[int]:
    return (table.truth if table.truth is not None else np.full(len(table), -1)).tolist()


def _labels(table: TrackTable) -> dict[tuple[float, int, int], int]:
    """(time, source, track) → truth label (the caller checked the column exists)."""
    truth = table.truth if table.truth is not None else np.full(len(table), -1)
    return {
        (float(t), int(s), int(k)): int(label)
        for t, s, k, label in zip(table.time, table.source, table.track, truth, strict=True)
    }
