"""Track-to-track association under azimuth bias by reference topology (METHODS §4)."""

from __future__ import annotations

from .associator import TopologyAssociator, topology_vectors, unbias

__all__ = ["TopologyAssociator", "topology_vectors", "unbias"]
