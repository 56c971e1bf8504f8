"""Fuzzy track initiation (METHODS §1): the initiator and the fuzzy closeness it climbs."""

from __future__ import annotations

from .closeness import ClosenessOptima, closeness, maximize_closeness
from .initiator import FuzzyTrackInitiator, InitiatedTrack, InitiationDiagnostics, InitiationResult, initiate_tracks

__all__ = [
    "ClosenessOptima",
    "FuzzyTrackInitiator",
    "InitiatedTrack",
    "InitiationDiagnostics",
    "InitiationResult",
    "closeness",
    "initiate_tracks",
    "maximize_closeness",
]
