"""Fuzzy track initiation (METHODS §1): the initiator and the fuzzy closeness it climbs."""

from __future__ import annotations

from .closeness import ClosenessOptima, closeness, maximize_closeness
from .initiator import (
    FuzzyTrackInitiator,
    InitiatedTrack,
    InitiationDiagnostics,
    InitiationResult,
    LimitWarning,
    initiate_tracks,
)
from .score import MIN_SCORE, track_scores

__all__ = [
    "MIN_SCORE",
    "ClosenessOptima",
    "FuzzyTrackInitiator",
    "InitiatedTrack",
    "InitiationDiagnostics",
    "InitiationResult",
    "LimitWarning",
    "closeness",
    "initiate_tracks",
    "maximize_closeness",
    "track_scores",
]
