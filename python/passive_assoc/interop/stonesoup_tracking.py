"""The fuzzy track initiator as a Stone Soup ``Initiator``, so that a Stone Soup tracker
carries the tracks it initiates on (optional extra ``stonesoup``; importing this module needs
it).

:class:`PassiveInitiator` collects the detections a tracker did not associate; once they span
``window`` seconds it runs :class:`~passive_assoc.FuzzyTrackInitiator` on them and returns
each initiated track as a Stone Soup ``Track`` whose one ``GaussianState`` is the
constant-velocity state (interleaved, ``[x, vx, y, vy(, z, vz)]``) at the current time. The
detections the new tracks hold are forgotten, and so is every detection older than the
window. Each detection needs ``metadata["sensor"]`` and a bearing (or elevation, bearing)
vector, as :func:`~passive_assoc.interop.stonesoup.to_detections` makes them; a detection
whose model is translated away from its sensor's position (a moving platform) is taken from
there.
"""

from __future__ import annotations

import datetime as dt
import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray
from stonesoup.base import Property
from stonesoup.buffered_generator import BufferedGenerator
from stonesoup.feeder.base import DetectionFeeder
from stonesoup.initiator.base import Initiator
from stonesoup.models.measurement.linear import LinearGaussian
from stonesoup.types.detection import Detection
from stonesoup.types.state import GaussianState
from stonesoup.types.track import Track

from ..data import MeasurementTable, SensorNetwork, TrackTable
from ..data.conventions import covariance_from_interleaved, covariance_to_interleaved, from_interleaved, to_interleaved
from ..fti import FuzzyTrackInitiator
from ..static_los import StaticAssociator
from ..tracking.defaults import DELETE_AFTER, MISSED_DISTANCE, PROCESS_NOISE, WINDOW

__all__ = ["PassiveInitiator", "StaticAssociationFeeder", "detections_table", "track_measurements"]


def detections_table(detections: list[Any], sensors: SensorNetwork, epoch: dt.datetime) -> MeasurementTable:
    """Detections as a table, in their order (times in seconds after ``epoch``), with each
    one's sensor position where its model is translated away from the network's (a moving
    platform)."""
    if any("sensor" not in d.metadata for d in detections):
        raise ValueError("detections: every detection needs metadata['sensor'] (the sensor index)")
    vectors = [np.asarray(d.state_vector, dtype=float).ravel() for d in detections]
    sensor = np.array([int(d.metadata["sensor"]) for d in detections], dtype=np.int64)
    where = np.full((len(detections), 3), np.nan)
    for k, d in enumerate(detections):
        offset = getattr(d.measurement_model, "translation_offset", None)
        point = np.zeros(3)
        if offset is not None:
            point[: len(offset)] = np.asarray(offset, dtype=float).ravel()[:3]
            if not np.allclose(point, sensors.positions[sensor[k]]):
                where[k] = point
    if sensors.ndim == 2:
        where[:, 2] = np.where(np.isnan(where[:, 0]), np.nan, 0.0)
    return MeasurementTable.from_arrays(
        sensor,
        [(d.timestamp - epoch).total_seconds() for d in detections],
        [v[-1] for v in vectors],
        [v[0] for v in vectors] if sensors.ndim == 3 else None,
        sensor_position=None if np.isnan(where).all() else where,
    )


class PassiveInitiator(Initiator):  # type: ignore[misc]  # Stone Soup ships no types
    """Stone Soup ``Initiator`` running passive_assoc's fuzzy track initiation over a window
    of unassociated detections (module doc)."""

    sensors: SensorNetwork = Property(doc="The network the detections come from.")
    window: float = Property(default=WINDOW, doc="Seconds of detections an initiation takes.")
    initiator: Any = Property(default=None, doc="A FuzzyTrackInitiator (default: its defaults).")

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if not isinstance(self.sensors, SensorNetwork):
            raise TypeError(f"sensors: expected a SensorNetwork, got {type(self.sensors).__name__}")
        if not (isinstance(self.window, (int, float)) and self.window > 0):
            raise ValueError(f"window: must be > 0 seconds, got {self.window!r}")
        if self.initiator is None:
            self.initiator = FuzzyTrackInitiator()
        elif not isinstance(self.initiator, FuzzyTrackInitiator):
            raise TypeError(f"initiator: expected a FuzzyTrackInitiator, got {type(self.initiator).__name__}")
        self._pending: list[Any] = []
        self._epoch: dt.datetime | None = None
        #: The detections each track returned so far was initiated from.
        self.initiated_from: dict[Any, list[Any]] = {}

    def initiate(self, detections: set[Any], timestamp: dt.datetime, **kwargs: Any) -> set[Any]:
        """New tracks once the pending detections span the window; an empty set before."""
        if self._epoch is None:
            self._epoch = timestamp
        self._pending.extend(detections)
        self._pending = [d for d in self._pending if (timestamp - d.timestamp).total_seconds() <= self.window]
        if not self._pending:
            return set()
        first = min(d.timestamp for d in self._pending)
        if (timestamp - first).total_seconds() < self.window:
            return set()
        ordered = sorted(self._pending, key=lambda d: d.timestamp)
        table = self._table(ordered)
        t0 = (timestamp - self._epoch).total_seconds()
        with warnings.catch_warnings():  # a window of clutter alone is the tracker's normal case
            warnings.filterwarnings("ignore", message=r"no candidate survived", category=UserWarning)
            result = self.initiator.initiate(table, self.sensors, t0=t0, progress=False)
        used = set(np.flatnonzero(result.labels >= 0).tolist())
        self._pending = [d for k, d in enumerate(ordered) if k not in used]
        ndim = self.sensors.ndim
        tracks = set()
        for initiated in result.tracks:
            mean = to_interleaved(initiated.state, ndim=ndim, blocks=2).reshape(-1, 1)
            covar = covariance_to_interleaved(initiated.covariance, ndim=ndim, blocks=2)
            new = Track([GaussianState(mean, covar, timestamp=timestamp)])
            self.initiated_from[new] = [ordered[m] for m in initiated.measurements.tolist()]
            tracks.add(new)
        return tracks

    def _table(self, detections: list[Any]) -> MeasurementTable:
        assert self._epoch is not None
        return detections_table(detections, self.sensors, self._epoch)


def _detection_key(d: Any) -> tuple[Any, ...]:
    return (d.timestamp, int(d.metadata["sensor"]), *np.asarray(d.state_vector, dtype=float).ravel().tolist())


class StaticAssociationFeeder(DetectionFeeder):  # type: ignore[misc]  # Stone Soup ships no types
    """Stone Soup ``DetectionFeeder`` that turns bearings into located targets: it groups its
    reader's ``(time, detections)`` into scans (a scan opens at its first time and takes every
    step up to ``scan_window`` seconds later), associates each scan with
    :class:`~passive_assoc.StaticAssociator`, and yields ``(the scan's last time, one position
    Detection per target)``, each with a ``LinearGaussian`` model of its ML covariance on an
    interleaved constant-velocity state and ``metadata["rows"]``, the detections it holds
    (their ``metadata["row"]`` where they have one). A Stone Soup linear Kalman tracker then
    tracks the targets' positions."""

    sensors: SensorNetwork = Property(doc="The network the bearings come from.")
    scan_window: float = Property(default=0.0, doc="Seconds one scan's bearings may span.")
    associator: Any = Property(default=None, doc="A StaticAssociator (default: its defaults).")

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if not isinstance(self.sensors, SensorNetwork):
            raise TypeError(f"sensors: expected a SensorNetwork, got {type(self.sensors).__name__}")
        if not (isinstance(self.scan_window, (int, float)) and self.scan_window >= 0):
            raise ValueError(f"scan_window: must be >= 0 seconds, got {self.scan_window!r}")
        if self.associator is None:
            self.associator = StaticAssociator(scan_window=float(self.scan_window))
        elif not isinstance(self.associator, StaticAssociator):
            raise TypeError(f"associator: expected a StaticAssociator, got {type(self.associator).__name__}")

    @BufferedGenerator.generator_method  # type: ignore[untyped-decorator]
    def data_gen(self) -> Any:
        pending: list[Any] = []
        start = last = None
        for time, detections in self.reader:
            if start is not None and (time - start).total_seconds() > self.scan_window:
                yield last, self._located(pending, start)
                pending, start = [], None
            if start is None:
                start = time
            pending.extend(detections)
            last = time
        if start is not None:
            yield last, self._located(pending, start)

    def _located(self, detections: list[Any], start: dt.datetime) -> set[Any]:
        # A set's order is its members' addresses': sorted, the answer does not depend on it.
        ordered = sorted(detections, key=_detection_key)
        found = self.associator.associate(detections_table(ordered, self.sensors, start), self.sensors)
        ndim = self.sensors.ndim
        time = ordered[-1].timestamp if ordered else start
        out = set()
        for t in range(len(found.positions)):
            model = LinearGaussian(
                ndim_state=2 * ndim, mapping=tuple(range(0, 2 * ndim, 2)), noise_covar=found.covariances[t]
            )
            held = [ordered[m] for m in found.rows[t][found.rows[t] >= 0].tolist()]
            rows = [d.metadata.get("row") for d in held]
            vector = np.asarray(found.positions[t], dtype=float).reshape(-1, 1)
            out.add(Detection(vector, timestamp=time, measurement_model=model, metadata={"rows": rows}))
        return out


def track_measurements(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    *,
    window: float = WINDOW,
    process_noise: float = PROCESS_NOISE,
    missed_distance: float = MISSED_DISTANCE,
    delete_after: int = DELETE_AFTER,
    initiator: FuzzyTrackInitiator | None = None,
) -> tuple[TrackTable, NDArray[np.int64]]:
    """Initiation, then a Stone Soup tracker, over a whole table.

    The reports go to a Stone Soup ``MultiTargetTracker`` time by time: a constant-velocity
    extended Kalman filter (``process_noise``: the acceleration noise density, m²/s³, per
    axis), global-nearest-neighbour association with a Mahalanobis gate of
    ``missed_distance``, tracks deleted after ``delete_after`` steps without an update, and a
    :class:`PassiveInitiator` over ``window`` seconds for new tracks.

    Returns
    -------
    tracks : TrackTable
        Every track's state after each step it lived (source 0, one id per track, the
        table's times): position, velocity and covariance, block order.
    labels : ndarray of int, shape (N,)
        Each row's track id (initiated from it, or updated with it), or −1.
    """
    from stonesoup.dataassociator.neighbour import GNNWith2DAssignment
    from stonesoup.deleter.time import UpdateTimeStepsDeleter
    from stonesoup.hypothesiser.distance import DistanceHypothesiser
    from stonesoup.measures import Mahalanobis
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity
    from stonesoup.predictor.kalman import ExtendedKalmanPredictor
    from stonesoup.tracker.simple import MultiTargetTracker
    from stonesoup.updater.kalman import ExtendedKalmanUpdater

    from .stonesoup import EPOCH, to_detections

    for name, value in (("process_noise", process_noise), ("missed_distance", missed_distance)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
            raise ValueError(f"{name}: must be a number > 0, got {value!r}")
    if isinstance(delete_after, bool) or not isinstance(delete_after, int) or delete_after < 1:
        raise ValueError(f"delete_after: must be an int >= 1, got {delete_after!r}")
    ndim = sensors.ndim
    steps: dict[dt.datetime, set[Any]] = {}
    for d in to_detections(measurements, sensors, epoch=EPOCH):
        steps.setdefault(d.timestamp, set()).add(d)
    start = EPOCH + dt.timedelta(seconds=float(measurements.time.min())) if len(measurements) else EPOCH
    passive = PassiveInitiator(sensors=sensors, window=window, initiator=initiator)
    passive._epoch = start  # the initiator's t0 in the table's seconds
    transition = CombinedLinearGaussianTransitionModel([ConstantVelocity(process_noise)] * ndim)
    predictor = ExtendedKalmanPredictor(transition)
    updater = ExtendedKalmanUpdater(measurement_model=None)
    hypothesiser = DistanceHypothesiser(predictor, updater, measure=Mahalanobis(), missed_distance=missed_distance)
    tracker = MultiTargetTracker(
        initiator=passive,
        deleter=UpdateTimeStepsDeleter(time_steps_since_update=delete_after),
        detector=sorted(steps.items(), key=lambda item: item[0]),
        data_associator=GNNWith2DAssignment(hypothesiser),
        updater=updater,
    )
    ids: dict[Any, int] = {}
    rows: dict[str, list[Any]] = {"track": [], "time": [], "state": [], "covariance": []}
    labels = np.full(len(measurements), -1, dtype=np.int64)
    for time, tracks in tracker:
        for track in tracks:
            k = ids.setdefault(track, len(ids))
            state = track.state
            rows["track"].append(k)
            rows["time"].append((time - EPOCH).total_seconds())
            rows["state"].append(from_interleaved(np.asarray(state.state_vector, float).ravel(), ndim=ndim, blocks=2))
            rows["covariance"].append(covariance_from_interleaved(np.asarray(state.covar, float), ndim=ndim, blocks=2))
            measurement = getattr(getattr(state, "hypothesis", None), "measurement", None)
            if measurement is not None and "row" in getattr(measurement, "metadata", {}):
                labels[int(measurement.metadata["row"])] = k
    for track, detections in passive.initiated_from.items():
        if track in ids:
            labels[[int(d.metadata["row"]) for d in detections]] = ids[track]
    state = np.array(rows["state"]).reshape(-1, 2 * ndim)
    table = TrackTable.from_arrays(
        np.zeros(len(rows["track"]), dtype=np.int64),
        rows["track"],
        rows["time"],
        state[:, :ndim],
        state[:, ndim:],
        covariance=np.array(rows["covariance"]).reshape(-1, 2 * ndim, 2 * ndim),
        sort=True,
    )
    return table, labels
