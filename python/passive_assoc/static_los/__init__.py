"""Static line-of-sight association of one scan (METHODS §2)."""

from __future__ import annotations

from .associator import Method, StaticAssociation, StaticAssociator, associate_static
from .batch import ScanAssociation, associate_scans
from .candidates import CHI2_1DOF_99, Candidates, default_false_alarm_density, enumerate_candidates, stage_counts

__all__ = [
    "CHI2_1DOF_99",
    "Candidates",
    "Method",
    "ScanAssociation",
    "StaticAssociation",
    "StaticAssociator",
    "associate_scans",
    "associate_static",
    "default_false_alarm_density",
    "enumerate_candidates",
    "stage_counts",
]
