"""Passive location of formation targets with emitter attributes (METHODS §3, paper 004).

Several 2-D bearing sensors see a close formation of emitters; each report is a bearing plus
emitter attributes (RF, PRF, PW, antenna scan period...). Bearings alone cannot tell the
members apart (exact ghosts), attributes alone cannot either (similar emitters); together they
can. The modified baseline least-distance method runs in the Rust core: every line of sight of
the baseline sensor is met by every line of every other sensor, meetings whose Dempster-Shafer
attribute support is below η (or that lie out of range or region) are dropped, and the line set
whose pairwise intersections cluster tightest is the report's association, located by ML
triangulation with its covariance.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Annotated, Any, Literal

import numpy as np
from numpy.typing import NDArray

from .. import _core
from .._inputs import check_pair
from .._params import COUNT, Boolean, Configurable, Interval, Options, Threads
from .._progress import ProgressArg, reporting
from ..data import MeasurementTable, SensorNetwork
from ..data.attributes import DEFAULT_ETA, AttributeStd, Combination, Eta, attribute_evidence
from ..outcome import COMPLETED, Outcome

__all__ = ["DEFAULT_MAX_PAIRS", "FormationDiagnostics", "FormationLocator", "FormationResult", "locate_formation"]

#: :attr:`FormationLocator.max_pairs` by default: (baseline report, other report) pairs a
#: location may examine, 5 × 10⁷ (about 10 s of one core; 3 sensors × 16 000 reports would be
#: 5.1 × 10⁸, 90 CPU-s). The core's ``DEFAULT_MAX_PAIRS`` (tests/test_core_defaults.py compares them).
DEFAULT_MAX_PAIRS = 50_000_000


@dataclass(frozen=True)
class FormationDiagnostics:
    """What the location examined: whether attributes gated it, the baseline meetings
    examined, and those pruned as parallel, by attribute support, by range, by region and
    behind a sensor, and the candidate sets scored."""

    attributes: bool
    pairs: int
    parallel: int
    low_support: int
    out_of_range: int
    outside_region: int
    behind: int
    candidates: int


@dataclass(frozen=True)
class FormationResult(Outcome):
    """Output of :meth:`FormationLocator.locate`: one entry per report of the baseline sensor
    (``B`` of them, in table order).

    Attributes
    ----------
    termination, success, message
        As every result (:class:`~passive_assoc.outcome.Outcome`): ``"completed"``.
    baseline_rows : ndarray of int, shape (B,)
        Table row of each baseline report.
    rows : ndarray of int, shape (B, S)
        Chosen table row per sensor (the baseline report itself in the baseline column), −1
        where the report has no association.
    associated : ndarray of bool, shape (B,)
        Whether each baseline report found a set of partners (its row of :attr:`rows` is
        then filled, and its position finite).
    positions, covariances : ndarray, shapes (B, 2) and (B, 2, 2)
        ML triangulation of each chosen set (NaN where none).
    radius : ndarray, shape (B,)
        Cluster radius (eq. 6) of the chosen set, metres.
    support : ndarray, shape (B, S)
        Dempster ``m(assoc)`` of the baseline report with each chosen report (NaN at the
        baseline and where none; 1 without attributes).
    chi2 : ndarray, shape (B,)
        Sum of the squared normalised bearing residuals of the ML triangulation of each
        chosen set (NaN where none).
    labels : ndarray of int, shape (N,)
        The group (baseline index) every input row ends in, or −1: the clutter set. In
        the independent mode a report chosen by several baselines belongs to the one whose set
        clusters tightest (ties: lower index); :attr:`times_chosen` counts them all.
    times_chosen : ndarray of int, shape (N,)
        How many baseline groups chose each row (≤ 1 with ``one_to_one``).
    diagnostics : FormationDiagnostics
        Meetings examined and pruned by support, range, region and direction, candidates scored.
    """

    baseline_rows: NDArray[np.int64]
    rows: NDArray[np.int64]
    associated: NDArray[np.bool_]
    positions: NDArray[np.float64]
    covariances: NDArray[np.float64]
    radius: NDArray[np.float64]
    support: NDArray[np.float64]
    chi2: NDArray[np.float64]
    labels: NDArray[np.int64]
    times_chosen: NDArray[np.int64]
    diagnostics: FormationDiagnostics = field(repr=False)

    @property
    def clutter(self) -> NDArray[np.int64]:
        """Rows in no group (false alarms, missed partners, reports nobody chose), as
        :attr:`InitiationResult.clutter`."""
        return np.flatnonzero(self.labels < 0)


@dataclass(frozen=True)
class FormationLocator(Configurable):
    """The modified baseline least-distance method with emitter attributes (METHODS §3).

    Parameters
    ----------
    attributes : sequence of str, optional
        Attribute columns to use; None uses every attribute column of the table, ``[]`` none
        (azimuth-only association, the paper's Table 2).
    attribute_std : sequence, mapping or array, optional
        Attribute noise stds: one per attribute in name order, or a mapping name -> std or
        name -> one std per sensor (a key that names no attribute column of the table is
        refused). None reads per-report stds from ``<name>_std`` columns.
    eta : float
        Attribute gate: meetings whose ``m(assoc)`` is below η are dropped (paper 0.6).
    combination : {"simple", "two_outcome"}
        Dempster reading: each attribute a simple support function, ``1 − Π(1 − s_k)`` (the
        reading that reproduces the paper), or split between associated and not.
    baseline_sensor : int
        Sensor whose reports are located (paper: the first).
    reference : "smallest" or int
        Subset whose points seed the candidates: the smallest (ties by index) or a sensor.
    cluster_radius : {"2d", "1d"}
        Radius over all pairwise intersections (the paper's modification) or over the
        intersections on the baseline line only (the unmodified method).
    one_to_one : bool
        Never use a line twice (greedy by radius). Default off, as the paper.
    r_max : float
        Detection range, metres: meetings farther from either sensor are dropped.
    region : (x_min, x_max, y_min, y_max), optional
        Surveillance region, metres.
    in_front : bool
        Drop meetings behind either sensor (the paper intersects full lines).
    max_pairs : int
        Most (baseline report, other sensor's report) pairs a location may examine: the work
        (and the one-to-one mode's memory, up to 16 bytes a pair) grows with them, so a larger
        snapshot is refused with a ValueError before any work. Default
        :data:`DEFAULT_MAX_PAIRS`, 5 × 10⁷ (about 10 s of one core); the paper's scene has
        72 pairs.
    n_threads : int, optional
        Threads (None: all cores); results are identical for any value.
    """

    attributes: Sequence[str] | None = None
    attribute_std: AttributeStd | None = None
    eta: Eta = DEFAULT_ETA
    combination: Combination = "simple"
    baseline_sensor: Annotated[int, Interval(int, 0, None)] = 0
    reference: Annotated[Literal["smallest"] | int, Options("smallest"), Interval(int, 0, None)] = "smallest"
    cluster_radius: Annotated[Literal["2d", "1d"], Options("2d", "1d")] = "2d"
    one_to_one: Annotated[bool, Boolean()] = False
    r_max: Annotated[float, Interval(float, 0.0, None, closed="neither")] = 200e3
    region: tuple[float, float, float, float] | None = None
    in_front: Annotated[bool, Boolean()] = False
    max_pairs: Annotated[int, COUNT] = DEFAULT_MAX_PAIRS
    n_threads: Threads = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.region is not None:
            region = tuple(float(v) for v in np.asarray(self.region, dtype=np.float64).ravel())
            if len(region) != 4:
                raise ValueError(f"region: expected (x_min, x_max, y_min, y_max), got {self.region!r}")
            object.__setattr__(self, "region", region)

    def locate(
        self, measurements: MeasurementTable, sensors: SensorNetwork, *, progress: ProgressArg = None
    ) -> FormationResult:
        """Associate and locate one snapshot of 2-D bearings from ≥ 3 sensors.

        Every input row ends in exactly one group of :attr:`FormationResult.labels` or in
        :attr:`FormationResult.clutter`.

        ``progress``: a bar on stderr over the baseline reports decided (stage ``"baseline
        reports"``, then ``"one-to-one"`` with ``one_to_one``): None shows it on a terminal
        once the call has run 2 s, True always, False never; a callable gets the reports
        instead, ``progress(stage, fraction)``, and raising in it stops the call. Ctrl-C
        stops the call within one baseline report's work.
        """
        table, network = check_pair(measurements, sensors)
        if network.ndim != 2:
            raise ValueError("sensors: the formation method takes 2-D bearing sensors (ndim=2)")
        evidence = attribute_evidence(table, network, self.attributes, self.attribute_std, self.eta, self.combination)
        with reporting(progress) as report:
            out = _core.locate_formation(table, network, evidence, self, report)
        return _result(out, evidence is not None)


def locate_formation(
    measurements: MeasurementTable, sensors: SensorNetwork, *, progress: ProgressArg = None, **settings: Any
) -> FormationResult:
    """``FormationLocator(**settings).locate(measurements, sensors, progress=progress)``, for
    one-off calls.

    >>> import passive_assoc as pa
    >>> from passive_assoc.simulation import paper_formation_scene
    >>> scene = paper_formation_scene(0, sigma_deg=0.0)
    >>> result = pa.locate_formation(scene.measurements, scene.sensors, attribute_std=scene.attribute_std)
    >>> bool(result.associated.all()), len(result.clutter)
    (True, 0)
    """
    return FormationLocator(**settings).locate(measurements, sensors, progress=progress)


def _result(out: _core.FormationOutput, with_attributes: bool) -> FormationResult:
    c = out.counts
    diagnostics = FormationDiagnostics(
        with_attributes,
        c.pairs,
        c.parallel,
        c.low_support,
        c.out_of_range,
        c.outside_region,
        c.behind,
        c.candidates,
    )
    return FormationResult(
        out.baseline_rows,
        out.rows,
        ~np.isnan(out.radius),
        out.positions,
        out.covariances,
        out.radius,
        out.support,
        out.chi2,
        out.labels,
        out.times_chosen,
        diagnostics,
        termination=COMPLETED,
        success=True,
        message=f"{int((~np.isnan(out.radius)).sum())} of {len(out.radius)} baseline reports associated",
    )
