"""Radar/ESM track association of maneuvering targets with wavelets and fuzzy factors
(METHODS §5, paper 003)."""

from __future__ import annotations

from .associator import WaveletFuzzyAssociator
from .baselines import Chi2TrackAssociator, position_gate_pairs
from .bearings import bearing_fixes
from .coarse import MAX_WINDOW, CoarseGate, approximation_operator, coarse_gate, coefficients
from .combined import WaveletChi2Associator
from .scan_gate import WINDOW_CAP
from .scans import RadarEsmAssociation
from .tracks import REPORT_PROCESS_NOISE, filter_reports, process_noise_of

__all__ = [
    "CoarseGate",
    "approximation_operator",
    "coarse_gate",
    "coefficients",
    "WINDOW_CAP",
    "MAX_WINDOW",
    "WaveletFuzzyAssociator",
    "WaveletChi2Associator",
    "Chi2TrackAssociator",
    "position_gate_pairs",
    "RadarEsmAssociation",
    "filter_reports",
    "process_noise_of",
    "bearing_fixes",
    "REPORT_PROCESS_NOISE",
]
