"""Evaluation against simulated truth (METHODS §6): metrics, and the bounds and
perfect-association references every experiment prints beside its own figures."""

from __future__ import annotations

from .metrics import (
    GospaResult,
    PairwiseScores,
    association_accuracy,
    efficiency,
    gospa,
    pairwise_scores,
    rms_per_component,
    same_cluster_pairs,
)
from .references import perfect_association_fit, target_crlbs
from .track_scores import track_association_scores, track_pair_scores
from .track_truth import track_targets

__all__ = [
    "GospaResult",
    "PairwiseScores",
    "association_accuracy",
    "efficiency",
    "gospa",
    "pairwise_scores",
    "perfect_association_fit",
    "rms_per_component",
    "same_cluster_pairs",
    "target_crlbs",
    "track_association_scores",
    "track_pair_scores",
    "track_targets",
]
