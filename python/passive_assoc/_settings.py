"""The settings objects the compiled core reads where they are not a method's own declared
parameters.

The binding layer (``rust/src``) reads a method's settings by attribute from the object that
declares them: :class:`~passive_assoc.FuzzyTrackInitiator`,
:class:`~passive_assoc.StaticAssociator`, :class:`~passive_assoc.FormationLocator`,
:class:`~passive_assoc.KalmanFilter`, or a function's validated arguments. The dataclasses here
are the settings *derived* from the declared parameters (the topology grid's absolute
threshold, the nearest neighbour's χ² threshold, the coarse gate's χ² quantile) and the
attribute evidence built from the data. Pure Python: must not import the compiled extension.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

Combination = Literal["simple", "two_outcome"]


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
    auto_gate: bool
    chi2_gate: float | None
    decision: Literal["fused", "assignment", "per_system_track"]
    max_bias_deg: float
    max_range: float
    gate_probability: float
    topology_weight: float
    n_threads: int | None


KalmanMotion = Literal["cv", "ca"]
KalmanMeasurement = Literal["position", "polar", "polar_converted"]
KalmanInit = Literal["differencing", "single_point"]


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
