"""Simulated scenarios with truth: the generic constant-velocity simulator, the radar
simulator (:mod:`.radar`), a passive scene of sensors on a ring (:mod:`.ring`), and one
scenario module per method (:mod:`.fti` for fuzzy track initiation, :mod:`.static_los` for
static line-of-sight association, :mod:`.topology` for
track-to-track association by reference topology, :mod:`.radar_esm` for radar/ESM association
with wavelets, :mod:`.formation` for passive location of formation targets with emitter
attributes)."""

from __future__ import annotations

from .formation import (
    PAPER_ATTRIBUTE_NAMES,
    PAPER_ATTRIBUTE_STD,
    PAPER_FORMATION_ATTRIBUTES,
    PAPER_FORMATION_SENSORS,
    PAPER_FORMATION_TARGETS,
    PAPER_SIGMAS_DEG,
    FormationScene,
    formation_scene,
    paper_formation_scene,
)
from .fti import PAPER_FTI_TARGETS, paper_fti_scenario
from .radar import (
    Radar,
    RadarMeasurements,
    line_abreast_formation,
    scattered_targets,
    simulate_radars,
    true_positions,
)
from .radar_esm import PAPER_WAVELET_PHASES, PAPER_WAVELET_TARGETS, RadarEsmScenario, paper_wavelet_scenario
from .ring import ring_scenario
from .scenario import ConstantVelocityTarget, Scenario, bearing_only_2d_scenario, simulate, wrap_angle
from .static_los import StaticScan, static_scan
from .topology import RadarScenario, paper_topology_scenario

__all__ = [
    "PAPER_FTI_TARGETS",
    "ConstantVelocityTarget",
    "Scenario",
    "StaticScan",
    "bearing_only_2d_scenario",
    "paper_fti_scenario",
    "ring_scenario",
    "simulate",
    "static_scan",
    "wrap_angle",
    "Radar",
    "RadarMeasurements",
    "simulate_radars",
    "true_positions",
    "scattered_targets",
    "line_abreast_formation",
    "RadarScenario",
    "paper_topology_scenario",
    "PAPER_WAVELET_TARGETS",
    "PAPER_WAVELET_PHASES",
    "RadarEsmScenario",
    "paper_wavelet_scenario",
    "PAPER_FORMATION_SENSORS",
    "PAPER_FORMATION_TARGETS",
    "PAPER_FORMATION_ATTRIBUTES",
    "PAPER_ATTRIBUTE_NAMES",
    "PAPER_ATTRIBUTE_STD",
    "PAPER_SIGMAS_DEG",
    "FormationScene",
    "paper_formation_scene",
    "formation_scene",
]
