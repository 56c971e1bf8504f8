"""Radar/ESM track association of maneuvering targets with wavelets and fuzzy factors
(METHODS §5, paper 003)."""

from __future__ import annotations

from .associator import WINDOW_CAP, WaveletFuzzyAssociator
from .baselines import Chi2TrackAssociator, NearestNeighbourTrackAssociator
from .coarse import CoarseGate, approximation_operator, coarse_gate, coefficients
from .scans import RadarEsmAssociation
from .tracks import filter_reports

__all__ = [
    "CoarseGate",
    "approximation_operator",
    "coarse_gate",
    "coefficients",
    "WINDOW_CAP",
    "WaveletFuzzyAssociator",
    "Chi2TrackAssociator",
    "NearestNeighbourTrackAssociator",
    "RadarEsmAssociation",
    "filter_reports",
]
