"""Static line-of-sight association of one scan (METHODS §2)."""

from __future__ import annotations

from .associator import Method, StaticAssociation, StaticAssociator, associate_static, enumerate_candidates
from .batch import ScanAssociation, associate_scans
from .candidates import DEFAULT_GATE_SIGMAS, Candidates, default_false_alarm_density
from .diagnostics import IntensityDiagnostics, IntensityLevel, SolverDiagnostics, StaticDiagnostics, stage_counts
from .scan_window import motion_inflated, window_scans

__all__ = [
    "DEFAULT_GATE_SIGMAS",
    "Candidates",
    "IntensityDiagnostics",
    "IntensityLevel",
    "Method",
    "ScanAssociation",
    "SolverDiagnostics",
    "StaticAssociation",
    "StaticAssociator",
    "StaticDiagnostics",
    "associate_scans",
    "associate_static",
    "default_false_alarm_density",
    "enumerate_candidates",
    "motion_inflated",
    "stage_counts",
    "window_scans",
]
