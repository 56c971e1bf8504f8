"""A small built-in tracker for when Stone Soup is not installed: the fuzzy track initiation,
then a constant-velocity EKF on the angle reports with gated global-nearest-neighbour
association (:func:`track_measurements`)."""

from __future__ import annotations

from .gating import nearest_neighbour
from .tracker import track_measurements

__all__ = ["nearest_neighbour", "track_measurements"]
