"""The settings objects the compiled core reads, one per core entry point.

Each is a frozen dataclass whose field names are the attribute names the binding layer
(``rust/src``) extracts; the public classes and functions build them from their validated
parameters, so a public parameter may be renamed without touching Rust. Pure Python: must not
import the compiled extension.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

Motion = Literal["static", "cv"]
Scaling = Literal["whitened", "diagonal"]
DetectionOrder = Literal["membership", "closeness"]
SdMethod = Literal["lagrangian", "exact"]
WarmStart = Literal["auto", "always", "never"]
SensorOrder = Literal["auto", "given"]
Combination = Literal["simple", "two_outcome"]
ClusterRadius = Literal["2d", "1d"]


@dataclass(frozen=True)
class FitSettings:
    motion: Motion
    t0: float
    max_iter: int
    xtol: float
    step_sigmas: float
    max_halvings: int
    n_threads: int | None


@dataclass(frozen=True)
class SdSettings:
    method: SdMethod
    max_iter: int
    gap_tol: float
    max_nodes: int
    time_limit: float | None
    warm_start: WarmStart
    sensor_order: SensorOrder
    polish: bool


@dataclass(frozen=True)
class InitiationSettings:
    t0: float
    gate_sigmas: float
    n_detect: int | None
    ray_gate_sigmas: float | None
    reject_behind: bool
    v_max: float | None
    chi2_gate: float | None
    one_per_scan: bool
    detection_order: DetectionOrder
    merge_tol: float
    descent_scaling: Scaling
    descent_max_iter: int
    max_candidates: int
    refine_passes: int
    candidate_scans: int
    support_gate: bool
    track_test: float | None
    gate_pd: float | None
    search_stage: int | None
    n_threads: int | None


@dataclass(frozen=True)
class DescentSettings:
    t0: float
    scaling: Scaling
    max_iter: int
    n_threads: int | None


@dataclass(frozen=True)
class EnumerationSettings:
    chi2_gate: float
    min_intensity: int
    max_candidates: int
    n_threads: int | None


@dataclass(frozen=True)
class IntensitySettings:
    vote_fraction: float
    valid_airspace: bool
    max_chains: int | None
    n_threads: int | None


@dataclass(frozen=True)
class TopologySettings:
    scoring: Literal["topology", "distance"]
    rings: int
    sectors: int
    radius: float
    delta: float
    delta_prime: float
    diffusion: Literal["additive", "at_least"]
    reference: Literal["north", "heading"]
    threshold: float
    window: int
    gate: float | None
    chi2_gate: float | None
    decision: Literal["assignment", "per_system_track"]
    n_threads: int | None


KalmanMotion = Literal["cv", "ca"]
KalmanMeasurement = Literal["position", "polar", "polar_converted"]
KalmanInit = Literal["differencing", "single_point"]


@dataclass(frozen=True)
class KalmanSettings:
    motion: KalmanMotion
    measurement: KalmanMeasurement
    process_noise: float
    init: KalmanInit
    init_velocity_std: float
    init_acceleration_std: float
    n_threads: int | None


@dataclass(frozen=True)
class CoarseGateSettings:
    """The radar/ESM coarse gate (METHODS §5 step 2): the χ² threshold, whitened or scalar."""

    threshold: float
    whitened: bool
    n_threads: int | None


@dataclass(frozen=True)
class AttributeEvidence:
    """Per-row emitter attributes and the Dempster-Shafer gate on them (METHODS §3)."""

    values: NDArray[np.float64]  # (K, N): the attribute columns stacked, C-contiguous
    stds: NDArray[np.float64]  # (K, N) per report, or (K, 1) one per attribute
    eta: float
    combination: Combination


@dataclass(frozen=True)
class FormationSettings:
    baseline_sensor: int
    reference: int | None
    cluster_radius: ClusterRadius
    one_to_one: bool
    r_max: float
    region: tuple[float, float, float, float] | None
    in_front: bool
    n_threads: int | None
