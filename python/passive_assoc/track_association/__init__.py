"""Track-to-track association (METHODS §4, §5): the result every track associator returns,
the per-scan (streaming) associators' base, and the nearest-neighbour baseline."""

from __future__ import annotations

from .nearest import NearestNeighbourAssociator
from .result import BiasEstimate, TrackAssociation, TrackPairs, UnpairedTracks
from .streaming import StreamingTrackAssociator

__all__ = [
    "BiasEstimate",
    "NearestNeighbourAssociator",
    "StreamingTrackAssociator",
    "TrackAssociation",
    "TrackPairs",
    "UnpairedTracks",
]
