"""passive_assoc: data association and track initiation for passive (angle-only) sensor
networks, with the numerical hot paths in Rust.

Angles are radians, positions metres, times seconds (METHODS §0).
"""

from __future__ import annotations

from ._core import __version__
from .assignment import SdAssignment, assign_sd, linear_assignment
from .closeness import ClosenessOptima, closeness, maximize_closeness
from .fitting import TERMINATION_NAMES, FitResult, crlb, fisher_and_crlb, fit_ml
from .initiation import FuzzyTrackInitiator, InitiationResult, Track
from .measurements import MeasurementTable
from .sensors import SensorNetwork
from .simulate import (
    PAPER_FTI_TARGETS,
    ConstantVelocityTarget,
    Scenario,
    bearing_only_2d_scenario,
    paper_fti_scenario,
    simulate,
)
from .static_association import StaticAssociation, associate_static, enumerate_candidates

__all__ = [
    "StaticAssociation",
    "associate_static",
    "enumerate_candidates",
    "ClosenessOptima",
    "closeness",
    "maximize_closeness",
    "FuzzyTrackInitiator",
    "InitiationResult",
    "Track",
    "SdAssignment",
    "assign_sd",
    "linear_assignment",
    "__version__",
    "TERMINATION_NAMES",
    "FitResult",
    "crlb",
    "fisher_and_crlb",
    "fit_ml",
    "MeasurementTable",
    "SensorNetwork",
    "PAPER_FTI_TARGETS",
    "ConstantVelocityTarget",
    "Scenario",
    "bearing_only_2d_scenario",
    "paper_fti_scenario",
    "simulate",
]
