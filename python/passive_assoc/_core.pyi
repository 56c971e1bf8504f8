"""Type stubs for the compiled core (``rust/src``). Use the typed wrappers in the package.

The functions take the validated ``SensorNetwork`` / ``MeasurementTable`` objects (read by
attribute) and, where they have several settings, one object from ``passive_assoc._settings``;
``crlb``, ``closeness`` and ``assign_2d`` take their few scalars directly. Results are NumPy
arrays or the frozen classes below.
"""

from collections.abc import Callable
from typing import Literal, final

import numpy as np
from numpy.typing import NDArray

from ._settings import (
    DescentSettings,
    EnumerationSettings,
    FitSettings,
    InitiationSettings,
    IntensitySettings,
    KalmanSettings,
    Motion,
    SdSettings,
    TopologySettings,
)
from .data import MeasurementTable, SensorNetwork

__version__: str

Termination = Literal["optimal", "gap_reached", "max_iterations", "stalled", "node_limit", "time_limit"]

@final
class SdResult:
    @property
    def chosen(self) -> NDArray[np.int64]: ...
    @property
    def primal_cost(self) -> float: ...
    @property
    def dual_bound(self) -> float: ...
    @property
    def gap(self) -> float: ...
    @property
    def iterations(self) -> int: ...
    @property
    def termination(self) -> Termination: ...
    @property
    def optimal(self) -> bool: ...

@final
class StageCounts:
    @property
    def raw(self) -> int: ...
    @property
    def ray_gate(self) -> int: ...
    @property
    def behind(self) -> int: ...
    @property
    def v_max(self) -> int: ...
    @property
    def fitted(self) -> int: ...
    @property
    def chi2_gate(self) -> int: ...
    @property
    def supported(self) -> int: ...
    @property
    def optima(self) -> int: ...
    @property
    def merged(self) -> int: ...
    @property
    def detected(self) -> int: ...

@final
class StageSeconds:
    @property
    def candidates(self) -> float: ...
    @property
    def fit(self) -> float: ...
    @property
    def support(self) -> float: ...
    @property
    def descent(self) -> float: ...
    @property
    def detection(self) -> float: ...
    @property
    def final_fit(self) -> float: ...

@final
class InitiationOutput:
    @property
    def estimates(self) -> NDArray[np.float64]: ...
    @property
    def covariances(self) -> NDArray[np.float64]: ...
    @property
    def closeness(self) -> NDArray[np.float64]: ...
    @property
    def chi2(self) -> NDArray[np.float64]: ...
    @property
    def labels(self) -> NDArray[np.int64]: ...
    @property
    def descent_iterations(self) -> NDArray[np.int64]: ...
    @property
    def stage_counts(self) -> StageCounts: ...
    @property
    def stage_seconds(self) -> StageSeconds: ...

@final
class EnumerationStages:
    @property
    def tested(self) -> list[int]: ...
    @property
    def pruned(self) -> list[int]: ...
    @property
    def windowed_out(self) -> int: ...
    @property
    def attribute_pruned(self) -> int: ...
    @property
    def candidates(self) -> int: ...

@final
class Candidates:
    @property
    def tuples(self) -> NDArray[np.int64]: ...
    @property
    def rows(self) -> NDArray[np.int64]: ...
    @property
    def positions(self) -> NDArray[np.float64]: ...
    @property
    def covariances(self) -> NDArray[np.float64]: ...
    @property
    def costs(self) -> NDArray[np.float64]: ...
    @property
    def intensity(self) -> NDArray[np.int64]: ...
    @property
    def chi2(self) -> NDArray[np.float64]: ...
    @property
    def sizes(self) -> NDArray[np.int64]: ...
    @property
    def stages(self) -> EnumerationStages: ...

@final
class IntensityLevel:
    @property
    def intensity(self) -> int: ...
    @property
    def candidates(self) -> int: ...
    @property
    def starts(self) -> int: ...
    @property
    def chains(self) -> int: ...
    @property
    def confirmed(self) -> int: ...

@final
class IntensityResult:
    @property
    def chosen(self) -> NDArray[np.int64]: ...
    @property
    def airspace_radius(self) -> float: ...
    @property
    def ghosts_dropped(self) -> int: ...
    @property
    def chains(self) -> int: ...
    @property
    def levels(self) -> list[IntensityLevel]: ...

def fit_batch(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    indices: NDArray[np.int64],
    offsets: NDArray[np.int64],
    initial: NDArray[np.float64] | None,
    settings: FitSettings,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.uint32], NDArray[np.uint8]]: ...
def crlb(
    sensors: SensorNetwork,
    truth: NDArray[np.float64],
    sensor_index: NDArray[np.int64],
    times: NDArray[np.float64],
    motion: Motion,
    t0: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def initiate(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    pairs: NDArray[np.int64],
    spreads: tuple[NDArray[np.float64], NDArray[np.float64]],
    settings: InitiationSettings,
    progress: Callable[[str, float], object] | None = None,
) -> InitiationOutput: ...
def closeness(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    spreads: tuple[NDArray[np.float64], NDArray[np.float64]],
    states: NDArray[np.float64],
    t0: float,
    n_threads: int | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def maximize_closeness(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    spreads: tuple[NDArray[np.float64], NDArray[np.float64]],
    starts: NDArray[np.float64],
    covariances: NDArray[np.float64],
    settings: DescentSettings,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]: ...
def assign_sd(
    tuples: NDArray[np.int64],
    costs: NDArray[np.float64],
    sizes: NDArray[np.int64],
    settings: SdSettings,
) -> SdResult: ...
def assign_2d(costs: NDArray[np.float64]) -> tuple[NDArray[np.int64], NDArray[np.int64], float]: ...
def associate_scans(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    rows: NDArray[np.int64],
    offsets: NDArray[np.int64],
    pd: NDArray[np.float64],
    false_alarm_density: NDArray[np.float64] | None,
    enumeration: EnumerationSettings,
    method: str,
    sd: SdSettings,
    intensity: IntensitySettings,
    progress: Callable[[str, float], object] | None = None,
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]: ...
def default_false_alarm_density(
    sensor: NDArray[np.int64],
    azimuth: NDArray[np.float64],
    elevation: NDArray[np.float64] | None,
    n_sensors: int,
    p_false: float,
) -> NDArray[np.float64]: ...
def assign_2d_sparse(
    shape: tuple[int, int], indptr: NDArray[np.int64], indices: NDArray[np.int64], data: NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.int64], float]: ...
def enumerate_static(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    pd: NDArray[np.float64],
    false_alarm_density: NDArray[np.float64] | None,
    settings: EnumerationSettings,
    attributes: AttributeEvidence | None = None,
) -> Candidates: ...
def intensity_search(
    tuples: NDArray[np.int64],
    positions: NDArray[np.float64],
    costs: NDArray[np.float64],
    sizes: NDArray[np.int64],
    settings: IntensitySettings,
) -> IntensityResult: ...

@final
class ScanPairs:
    @property
    def pairs(self) -> NDArray[np.int64]: ...
    @property
    def scores(self) -> NDArray[np.float64]: ...

@final
class Bias:
    @property
    def rotation(self) -> float: ...
    @property
    def rotation_std(self) -> float: ...
    @property
    def translation(self) -> tuple[float, float]: ...
    @property
    def pairs(self) -> int: ...

ScanSide = tuple[
    NDArray[np.int64],
    NDArray[np.float64],
    NDArray[np.float64] | None,
    NDArray[np.float64] | None,
    NDArray[np.float64] | None,
]

class AssociatorState:
    def __init__(self, settings: TopologySettings) -> None: ...
    def update(self, local: ScanSide, system: ScanSide) -> ScanPairs: ...
    def bias(self) -> Bias | None: ...
    def bias_about(self, centre: tuple[float, float]) -> Bias | None: ...

def topology_vectors(tracks: ScanSide, settings: TopologySettings) -> NDArray[np.float64]: ...

def kalman_filter(
    times: NDArray[np.float64],
    measurements: NDArray[np.float64],
    groups: tuple[NDArray[np.int64], NDArray[np.int64]],
    noise: NDArray[np.float64],
    sensor_positions: NDArray[np.float64] | None,
    settings: KalmanSettings,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...

# Radar/ESM association (METHODS §5): the coarse gate.
from ._settings import CoarseGateSettings

def wavelet_coarse_gate(
    operator: NDArray[np.float64],
    radar: tuple[NDArray[np.float64], NDArray[np.float64]],
    esm: tuple[NDArray[np.float64], NDArray[np.float64]],
    settings: CoarseGateSettings,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]: ...
def repeated_maximum(
    score: NDArray[np.float64],
    allowed: NDArray[np.bool_],
    tie: NDArray[np.float64],
    threshold: float,
    n_threads: int | None = None,
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]: ...
def wavelet_coarse_gate_coupled(
    radar: tuple[NDArray[np.float64], NDArray[np.float64]],
    esm: tuple[NDArray[np.float64], NDArray[np.float64]],
    settings: CoarseGateSettings,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]: ...

from ._settings import AttributeEvidence, FormationSettings

@final
class FormationCounts:
    @property
    def pairs(self) -> int: ...
    @property
    def parallel(self) -> int: ...
    @property
    def low_support(self) -> int: ...
    @property
    def out_of_range(self) -> int: ...
    @property
    def outside_region(self) -> int: ...
    @property
    def behind(self) -> int: ...
    @property
    def candidates(self) -> int: ...

@final
class FormationOutput:
    @property
    def baseline_rows(self) -> NDArray[np.int64]: ...
    @property
    def rows(self) -> NDArray[np.int64]: ...
    @property
    def support(self) -> NDArray[np.float64]: ...
    @property
    def radius(self) -> NDArray[np.float64]: ...
    @property
    def positions(self) -> NDArray[np.float64]: ...
    @property
    def covariances(self) -> NDArray[np.float64]: ...
    @property
    def chi2(self) -> NDArray[np.float64]: ...
    @property
    def labels(self) -> NDArray[np.int64]: ...
    @property
    def times_chosen(self) -> NDArray[np.int64]: ...
    @property
    def counts(self) -> FormationCounts: ...

def locate_formation(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    attributes: AttributeEvidence | None,
    settings: FormationSettings,
) -> FormationOutput: ...

#: A core default as Python reads it: a number, a flag, a choice, or None.
OptionValue = bool | int | float | str | tuple[float, ...] | list[tuple[int, int]] | None

def option_defaults(paper: bool = False) -> dict[str, dict[str, OptionValue]]:
    """Each core options struct's ``recommended()`` values (``paper=True``: its ``paper()``),
    ``{kind: {Python parameter name: value}}``; kinds ``initiation``, ``descent``,
    ``enumeration``, ``intensity``, ``lagrangian``, ``branch_bound``, ``formation``,
    ``topology``, ``decision``, ``fit``, ``kalman``, ``coarse``. Values keep the core's meaning:
    ``decision["threshold"]`` is absolute (λ·rings·sectors), ``time_limit`` in seconds."""
