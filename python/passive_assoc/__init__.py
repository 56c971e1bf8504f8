"""passive_assoc: data association and track initiation for passive (angle-only) sensor
networks, with the numerical hot paths in Rust.

Angles are radians, positions metres, times seconds (METHODS §0).

Subpackages, each depending only on those before it: :mod:`.evidence` (Dempster-Shafer
combination), :mod:`.data` (measurements, sensors, tracks),
:mod:`.estimation` (ML fitting, CRLB, Kalman filtering), :mod:`.assignment` (S-D and 2-D solvers), :mod:`.fti`
(fuzzy track initiation), :mod:`.static_los` (static line-of-sight association), :mod:`.formation` (formation targets
with emitter attributes) and
:mod:`.topology` (track-to-track association under azimuth bias), :mod:`.radar_esm` (radar/ESM
association with wavelets and fuzzy factors),
:mod:`.simulation` (scenarios with truth), :mod:`.evaluation` (metrics, reference fits),
:mod:`.experiments` (paper reproductions). This namespace re-exports the main entry points.
"""

from __future__ import annotations

from . import evidence
from ._core import __version__
from .assignment import SdAssignment, assign_sd, linear_assignment
from .data import MeasurementTable, SensorNetwork, TrackTable
from .estimation import TERMINATION_NAMES, FitResult, KalmanFilter, KalmanResult, crlb, fisher_and_crlb, fit_ml
from .formation import FormationLocator, FormationResult, locate_formation
from .fti import (
    ClosenessOptima,
    FuzzyTrackInitiator,
    InitiatedTrack,
    InitiationResult,
    closeness,
    initiate_tracks,
    maximize_closeness,
)
from .radar_esm import Chi2TrackAssociator, WaveletFuzzyAssociator
from .simulation import (
    PAPER_FTI_TARGETS,
    ConstantVelocityTarget,
    Scenario,
    bearing_only_2d_scenario,
    paper_fti_scenario,
    simulate,
)
from .static_los import (
    ScanAssociation,
    StaticAssociation,
    StaticAssociator,
    associate_scans,
    associate_static,
    enumerate_candidates,
)
from .topology import TopologyAssociator
from .track_association import NearestNeighbourAssociator, TrackAssociation
from .track_methods import associate_tracks

#: The fuzzy initiator's track under its pre-subpackage name (``passive_assoc.fti.InitiatedTrack``).
Track = InitiatedTrack

__all__ = [
    "FormationLocator",
    "FormationResult",
    "locate_formation",
    "evidence",
    "NearestNeighbourAssociator",
    "TopologyAssociator",
    "WaveletFuzzyAssociator",
    "Chi2TrackAssociator",
    "TrackAssociation",
    "StaticAssociation",
    "StaticAssociator",
    "associate_static",
    "enumerate_candidates",
    "ClosenessOptima",
    "closeness",
    "maximize_closeness",
    "FuzzyTrackInitiator",
    "initiate_tracks",
    "associate_tracks",
    "InitiationResult",
    "InitiatedTrack",
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
    "KalmanFilter",
    "KalmanResult",
    "MeasurementTable",
    "SensorNetwork",
    "TrackTable",
    "PAPER_FTI_TARGETS",
    "ConstantVelocityTarget",
    "Scenario",
    "bearing_only_2d_scenario",
    "paper_fti_scenario",
    "simulate",
    "associate_scans",
    "ScanAssociation",
]
