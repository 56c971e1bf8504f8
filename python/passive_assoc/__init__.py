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

import importlib
from typing import TYPE_CHECKING, Any

from ._core import __version__

#: Where each re-exported name lives, imported on first use (PEP 562 ``__getattr__`` below), so
#: ``import passive_assoc`` loads neither SciPy nor PyWavelets: the names a program uses cost
#: their imports, the others nothing. The same names as the ``TYPE_CHECKING`` imports below
#: (tests/test_lazy_import.py compares them).
_EXPORTS: dict[str, tuple[str, ...]] = {
    "assignment": ("SdAssignment", "assign_sd", "linear_assignment"),
    "data": ("MeasurementTable", "SensorNetwork", "SensorTrack", "TrackTable"),
    "estimation": (
        "TERMINATION_NAMES",
        "FitResult",
        "KalmanFilter",
        "KalmanResult",
        "crlb",
        "fisher_and_crlb",
        "fit_ml",
    ),
    "formation": ("FormationLocator", "FormationResult", "locate_formation"),
    "fti": (
        "ClosenessOptima",
        "FuzzyTrackInitiator",
        "InitiatedTrack",
        "InitiationResult",
        "LimitWarning",
        "closeness",
        "initiate_tracks",
        "maximize_closeness",
    ),
    "radar_esm": ("Chi2TrackAssociator", "WaveletChi2Associator", "WaveletFuzzyAssociator"),
    "simulation": (
        "PAPER_FTI_TARGETS",
        "ConstantVelocityTarget",
        "Scenario",
        "bearing_only_2d_scenario",
        "paper_fti_scenario",
        "ring_scenario",
        "simulate",
    ),
    "static_los": (
        "ScanAssociation",
        "StaticAssociation",
        "StaticAssociator",
        "associate_scans",
        "associate_static",
        "enumerate_candidates",
    ),
    "topology": ("TopologyAssociator",),
    "track_association": ("NearestNeighbourAssociator", "TrackAssociation"),
    "track_methods": ("associate_tracks",),
}
_HOME = {name: module for module, names in _EXPORTS.items() for name in names}
#: Other names a program may use for a re-exported one (none at present).
_ALIASES: dict[str, tuple[str, str]] = {}
#: Subpackages and modules reachable as attributes (``pa.simulation.static_scan``) without
#: importing them first, as when this namespace imported them all.
_SUBMODULES = frozenset({*_EXPORTS, "evidence", "evaluation"})


def __getattr__(name: str) -> Any:
    if name in _HOME:
        value = getattr(importlib.import_module(f".{_HOME[name]}", __name__), name)
    elif name in _ALIASES:
        module, original = _ALIASES[name]
        value = getattr(importlib.import_module(f".{module}", __name__), original)
    elif name in _SUBMODULES:
        value = importlib.import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value  # the next lookup is an ordinary one
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__, *_SUBMODULES})


if TYPE_CHECKING:  # what the names are, for type checkers and readers
    from . import evidence
    from .assignment import SdAssignment, assign_sd, linear_assignment
    from .data import MeasurementTable, SensorNetwork, SensorTrack, TrackTable
    from .estimation import TERMINATION_NAMES, FitResult, KalmanFilter, KalmanResult, crlb, fisher_and_crlb, fit_ml
    from .formation import FormationLocator, FormationResult, locate_formation
    from .fti import (
        ClosenessOptima,
        FuzzyTrackInitiator,
        InitiatedTrack,
        InitiationResult,
        LimitWarning,
        initiate_tracks,
        maximize_closeness,
    )
    from .fti.closeness import closeness  # not from .fti: mypy then reports it defined twice
    from .radar_esm import Chi2TrackAssociator, WaveletChi2Associator, WaveletFuzzyAssociator
    from .simulation import (
        PAPER_FTI_TARGETS,
        ConstantVelocityTarget,
        Scenario,
        bearing_only_2d_scenario,
        paper_fti_scenario,
        ring_scenario,
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


__all__ = [
    "FormationLocator",
    "FormationResult",
    "locate_formation",
    "evidence",
    "NearestNeighbourAssociator",
    "TopologyAssociator",
    "WaveletFuzzyAssociator",
    "WaveletChi2Associator",
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
    "LimitWarning",
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
    "SensorTrack",
    "TrackTable",
    "PAPER_FTI_TARGETS",
    "ConstantVelocityTarget",
    "Scenario",
    "bearing_only_2d_scenario",
    "paper_fti_scenario",
    "ring_scenario",
    "simulate",
    "associate_scans",
    "ScanAssociation",
]
