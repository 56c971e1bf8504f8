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
from .score import track_scores

__all__ = [
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
