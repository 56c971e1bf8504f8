"""Type stubs for the compiled core (``rust/src``). Use the typed wrappers in the package.

The functions take the validated ``SensorNetwork`` / ``MeasurementTable`` objects (read by
attribute) and, where they have several settings, the object that declares them, read by
attribute: a ``FuzzyTrackInitiator``, ``StaticAssociator``, ``FormationLocator`` or
``KalmanFilter``, a function's validated arguments (the ``_…Settings`` protocols below name
what is read), or a derived settings object of ``passive_assoc._settings``. ``crlb``,
``closeness`` and ``assign_2d`` take their few scalars directly. Results are NumPy arrays or
the frozen classes below.
"""

from collections.abc import Callable
from typing import Literal, Protocol, final

import numpy as np
from numpy.typing import NDArray

from ._settings import AttributeEvidence, CoarseGateSettings, TopologySettings
from .data import MeasurementTable, SensorNetwork
from .estimation.kalman import KalmanFilter
from .formation.locator import FormationLocator
from .fti.initiator import FuzzyTrackInitiator
from .static_los.associator import StaticAssociator

__all__ = [
    "AssociatorState",
    "Bias",
    "Candidates",
    "EnumerationStages",
    "FormationCounts",
    "FormationOutput",
    "InitiationOutput",
    "IntensityLevel",
    "IntensityResult",
    "RayNeighbourhood",
    "ScanPairs",
    "SdResult",
    "StageCounts",
    "StageSeconds",
    "__version__",
    "assign_2d",
    "assign_2d_sparse",
    "assign_sd",
    "associate_scans",
    "closeness",
    "crlb",
    "default_false_alarm_density",
    "enumerate_static",
    "fit_batch",
    "initiate",
    "intensity_search",
    "kalman_filter",
    "locate_formation",
    "maximize_closeness",
    "option_defaults",
    "repeated_maximum",
    "topology_vectors",
    "wavelet_coarse_gate",
    "wavelet_coarse_gate_coupled",
]

__version__: str

_Termination = Literal["optimal", "gap_reached", "max_iterations", "stalled", "node_limit", "time_limit"]
_Motion = Literal["static", "cv"]

class _FitSettings(Protocol):
    """What ``fit_batch`` reads: ``fit_ml``'s validated arguments."""

    @property
    def motion(self) -> _Motion: ...
    @property
    def t0(self) -> float: ...
    @property
    def max_iter(self) -> int: ...
    @property
    def xtol(self) -> float: ...
    @property
    def step_sigmas(self) -> float: ...
    @property
    def max_halvings(self) -> int: ...
    @property
    def n_threads(self) -> int | None: ...

class _DescentSettings(Protocol):
    """What ``maximize_closeness`` reads: its Python function's validated arguments."""

    @property
    def t0(self) -> float: ...
    @property
    def scaling(self) -> Literal["whitened", "diagonal"]: ...
    @property
    def max_iter(self) -> int: ...
    @property
    def n_threads(self) -> int | None: ...

class _SdSettings(Protocol):
    """What ``assign_sd`` reads: ``passive_assoc.assignment.sd.SdParameters`` or a view of it."""

    @property
    def max_iter(self) -> int: ...
    @property
    def gap_tol(self) -> float: ...
    @property
    def max_nodes(self) -> int: ...
    @property
    def time_limit(self) -> float | None: ...
    @property
    def warm_start(self) -> Literal["auto", "always", "never"]: ...
    @property
    def sensor_order(self) -> Literal["auto", "given"]: ...
    @property
    def polish(self) -> bool: ...

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
    def termination(self) -> _Termination: ...
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
    def formation(self) -> Literal["paper", "rounds", "witnessed"]: ...
    @property
    def limit(self) -> str | None: ...
    @property
    def limit_slots(self) -> tuple[int, int] | None: ...
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
    settings: _FitSettings,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.uint32], NDArray[np.uint8]]: ...
def crlb(
    sensors: SensorNetwork,
    truth: NDArray[np.float64],
    sensor_index: NDArray[np.int64],
    times: NDArray[np.float64],
    motion: _Motion,
    t0: float,
    sensor_position: NDArray[np.float64] | None = None,
    sigma_azimuth: NDArray[np.float64] | None = None,
    sigma_elevation: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def initiate(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    pairs: NDArray[np.int64],
    spreads: tuple[NDArray[np.float64], NDArray[np.float64]],
    t0: float,
    settings: FuzzyTrackInitiator,
    progress: Callable[[str, float], object] | None = None,
) -> InitiationOutput: ...
@final
class RayNeighbourhood:
    def __new__(
        cls, measurements: MeasurementTable, sensors: SensorNetwork, ray_gate_sigmas: float | None, v_max: float | None
    ) -> RayNeighbourhood: ...
    def of(self, rows: NDArray[np.int64], free: NDArray[np.bool_]) -> NDArray[np.int64]: ...

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
    settings: _DescentSettings,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]: ...
def assign_sd(
    tuples: NDArray[np.int64],
    costs: NDArray[np.float64],
    sizes: NDArray[np.int64],
    method: Literal["lagrangian", "exact"],
    settings: _SdSettings,
) -> SdResult: ...
def assign_2d(
    costs: NDArray[np.float64] | NDArray[np.float32],
) -> tuple[NDArray[np.int64], NDArray[np.int64], float]: ...
def associate_scans(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    rows: NDArray[np.int64],
    offsets: NDArray[np.int64],
    pd: NDArray[np.float64],
    false_alarm_density: NDArray[np.float64] | None,
    associator: StaticAssociator,
    progress: Callable[[str, float], object] | None = None,
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64], list[bool]]: ...
def default_false_alarm_density(
    sensor: NDArray[np.int64],
    azimuth: NDArray[np.float64],
    elevation: NDArray[np.float64] | None,
    n_sensors: int,
    p_false: float,
    sigma: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]: ...
def assign_2d_sparse(
    shape: tuple[int, int], indptr: NDArray[np.int64], indices: NDArray[np.int64], data: NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.int64], float]: ...
def enumerate_static(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    pd: NDArray[np.float64],
    false_alarm_density: NDArray[np.float64] | None,
    settings: StaticAssociator,
    attributes: AttributeEvidence | None = None,
) -> Candidates: ...
def intensity_search(
    tuples: NDArray[np.int64],
    positions: NDArray[np.float64],
    costs: NDArray[np.float64],
    sizes: NDArray[np.int64],
    settings: StaticAssociator,
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
    @property
    def tracks(self) -> int: ...
    @property
    def reliable(self) -> bool: ...

_ScanSide = tuple[
    NDArray[np.int64],
    NDArray[np.float64],
    NDArray[np.float64] | None,
    NDArray[np.float64] | None,
    NDArray[np.float64] | None,
]

@final
class AssociatorState:
    def __new__(cls, settings: TopologySettings) -> AssociatorState: ...
    def update(self, local: _ScanSide, system: _ScanSide) -> ScanPairs: ...
    def bias(self) -> Bias | None: ...
    def bias_about(self, centre: tuple[float, float]) -> Bias | None: ...

def topology_vectors(tracks: _ScanSide, settings: TopologySettings) -> NDArray[np.float64]: ...

def kalman_filter(
    times: NDArray[np.float64],
    measurements: NDArray[np.float64],
    groups: tuple[NDArray[np.int64], NDArray[np.int64]],
    noise: NDArray[np.float64],
    sensor_positions: NDArray[np.float64] | None,
    settings: KalmanFilter,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...

# Radar/ESM association (METHODS §5): the coarse gate.

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
    settings: FormationLocator,
    progress: Callable[[str, float], object] | None = None,
) -> FormationOutput: ...

#: A core default as Python reads it: a number, a flag, a choice, or None.
_OptionValue = bool | int | float | str | tuple[float, ...] | list[tuple[int, int]] | None

def option_defaults(paper: bool = False) -> dict[str, dict[str, _OptionValue]]:
    """Each core options struct's ``recommended()`` values (``paper=True``: its ``paper()``),
    ``{kind: {Python parameter name: value}}``; kinds ``initiation``, ``descent``,
    ``enumeration``, ``intensity``, ``lagrangian``, ``branch_bound``, ``formation``,
    ``topology``, ``decision``, ``fit``, ``kalman``, ``coarse``. Values keep the core's meaning:
    ``decision["threshold"]`` is absolute (λ·rings·sectors), ``time_limit`` in seconds."""
