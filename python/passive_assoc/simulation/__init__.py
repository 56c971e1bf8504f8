"""Simulated scenarios with truth: the generic constant-velocity simulator and one scenario
module per method (:mod:`.fti` for fuzzy track initiation, :mod:`.static_los` for static
line-of-sight association)."""

from __future__ import annotations

from .fti import PAPER_FTI_TARGETS, paper_fti_scenario
from .scenario import ConstantVelocityTarget, Scenario, bearing_only_2d_scenario, simulate, wrap_angle
from .static_los import StaticScan, static_scan

__all__ = [
    "PAPER_FTI_TARGETS",
    "ConstantVelocityTarget",
    "Scenario",
    "StaticScan",
    "bearing_only_2d_scenario",
    "paper_fti_scenario",
    "simulate",
    "static_scan",
    "wrap_angle",
]
