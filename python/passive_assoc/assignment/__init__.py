"""Assignment: sparse S-D assignment and dense 2-D linear assignment in the Rust core, and
track-to-track association (the result type, the per-scan associator base class, and the
nearest-neighbour baseline every track associator is measured against)."""

from __future__ import annotations

from .linear import linear_assignment
from .sd import SdAssignment, assign_sd
from .tracks import (
    BiasEstimate,
    NearestNeighbourAssociator,
    TrackAssociation,
    TrackAssociator,
    TrackPairs,
    UnpairedTracks,
)

__all__ = [
    "BiasEstimate",
    "NearestNeighbourAssociator",
    "SdAssignment",
    "TrackAssociation",
    "TrackAssociator",
    "TrackPairs",
    "UnpairedTracks",
    "assign_sd",
    "linear_assignment",
]
