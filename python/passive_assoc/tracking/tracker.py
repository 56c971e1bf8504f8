"""The built-in tracker: fuzzy track initiation, then a constant-velocity EKF on the angle
reports, with no library beyond numpy and the package itself.

The rule, step by step over the table's distinct times (the same loop as the Stone Soup
tracker of :mod:`passive_assoc.interop.stonesoup_tracking`):

1. Every live track is predicted to the time (:func:`~passive_assoc.estimation.cv_predict`).
2. The time's reports are taken sensor by sensor (a target gives a sensor at most one report
   at a time). Each report's NIS against each track
   (:func:`~passive_assoc.estimation.angle_innovation`) is gated at ``missed_distance²`` and
   the reports are paired with tracks by gated global nearest neighbour
   (:func:`~passive_assoc.tracking.gating.nearest_neighbour`); each pair updates its track
   (:func:`~passive_assoc.estimation.ekf_update`) before the next sensor's reports are gated.
3. A track that took no report in its last ``delete_after`` steps is deleted.
4. The reports no track took wait for initiation. Reports more than ``window`` seconds old
   are dropped; once the waiting ones span ``window`` seconds,
   :class:`~passive_assoc.FuzzyTrackInitiator` runs on them with ``t0`` the current time
   (on the sensor pairs whose sensors both have two scans among them), and each track it
   initiates starts from its state and covariance there; the reports it holds stop waiting.
5. Every live track's state at the time is recorded.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace
from itertools import combinations
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..data import MeasurementTable, SensorNetwork, TrackTable
from ..estimation import angle_innovation, cv_predict, ekf_update
from ..fti import FuzzyTrackInitiator
from .defaults import DELETE_AFTER, MISSED_DISTANCE, PROCESS_NOISE, WINDOW
from .gating import nearest_neighbour

__all__ = ["track_measurements"]


@dataclass
class _Live:
    """A live track: its id, state and covariance (block order) at ``time``, and how many
    steps in a row it has gone without a report."""

    ident: int
    state: NDArray[np.float64]
    covariance: NDArray[np.float64]
    time: float
    misses: int = 0


def _check(
    measurements: object,
    sensors: object,
    window: object,
    process_noise: object,
    missed_distance: object,
    delete_after: object,
    initiator: object,
) -> None:
    if not isinstance(measurements, MeasurementTable):
        raise TypeError(f"measurements: expected a MeasurementTable, got {type(measurements).__name__}")
    if not isinstance(sensors, SensorNetwork):
        raise TypeError(f"sensors: expected a SensorNetwork, got {type(sensors).__name__}")
    measurements.validate_against(sensors)
    for name, value in (("window", window), ("process_noise", process_noise), ("missed_distance", missed_distance)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value < float("inf"):
            raise ValueError(f"{name}: must be a number > 0, got {value!r}")
    if isinstance(delete_after, bool) or not isinstance(delete_after, int) or delete_after < 1:
        raise ValueError(f"delete_after: must be an int >= 1, got {delete_after!r}")
    if initiator is not None and not isinstance(initiator, FuzzyTrackInitiator):
        raise TypeError(f"initiator: expected a FuzzyTrackInitiator, got {type(initiator).__name__}")


def _initiate(fti: FuzzyTrackInitiator, table: MeasurementTable, sensors: SensorNetwork, now: float) -> list[Any]:
    """The tracks ``fti`` initiates from the waiting reports at ``now``, on the sensor pairs
    (its own, or every pair) whose sensors both have two scans (distinct times) among them:
    the initiation needs each pair's first and last scan, and a quiet sensor is normal here."""
    scans = [len(np.unique(table.time[table.sensor == j])) for j in range(sensors.n_sensors)]
    wanted = combinations(range(sensors.n_sensors), 2) if fti.pairs is None else fti.pairs
    pairs = [(int(a), int(b)) for a, b in wanted if scans[a] >= 2 and scans[b] >= 2]
    if not pairs:
        return []
    with warnings.catch_warnings():  # a window of clutter alone is the tracker's normal case
        warnings.filterwarnings("ignore", message=r"no candidate survived", category=UserWarning)
        result = replace(fti, pairs=pairs).initiate(table, sensors, t0=now, progress=False)
    return list(result.tracks)


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
    """Initiation, then the built-in EKF tracker, over a whole table (module doc).

    Parameters
    ----------
    measurements : MeasurementTable
        Bearings (2-D) or azimuth and elevation (3-D), with their per-report noise and
        sensor positions where the table has them.
    sensors : SensorNetwork
    window : float
        Seconds of unassociated reports an initiation takes.
    process_noise : float
        Acceleration noise density, m²/s³, per axis.
    missed_distance : float
        The gate, as a Mahalanobis distance: a report is a candidate for a track when its NIS
        is at most ``missed_distance²``.
    delete_after : int
        Steps without a report before a track is deleted.
    initiator : FuzzyTrackInitiator, optional
        Default: its defaults.

    Returns
    -------
    tracks : TrackTable
        Every track's state after each step it lived (source 0, one id per track, the
        table's times): position, velocity and covariance, block order.
    labels : ndarray of int, shape (N,)
        Each row's track id (initiated from it, or updated with it), or −1.
    """
    _check(measurements, sensors, window, process_noise, missed_distance, delete_after, initiator)
    fti = FuzzyTrackInitiator() if initiator is None else initiator
    ndim = sensors.ndim
    sigma_az, sigma_el = measurements.report_sigmas(sensors)
    if ndim == 2:
        angles, sigmas = measurements.azimuth[:, None], sigma_az[:, None]
    else:
        angles = np.column_stack([measurements.azimuth, measurements.elevation])
        sigmas = np.column_stack([sigma_az, sigma_el])
    where = sensors.positions[measurements.sensor].astype(np.float64)
    if measurements.sensor_position is not None:
        own = ~np.isnan(measurements.sensor_position[:, 0])
        where[own] = measurements.sensor_position[own]
    time = measurements.time
    order = measurements.time_order()
    labels = np.full(len(measurements), -1, dtype=np.int64)
    live: list[_Live] = []
    pending: list[int] = []
    next_id = 0
    ids: list[int] = []
    stamps: list[float] = []
    states: list[NDArray[np.float64]] = []
    covariances: list[NDArray[np.float64]] = []
    starts = np.flatnonzero(np.r_[True, np.diff(time[order]) != 0])
    for rows in np.split(order, starts[1:]) if len(order) else []:
        now = float(time[rows[0]])
        for track in live:
            track.state, track.covariance = cv_predict(track.state, track.covariance, now - track.time, process_noise)
            track.time = now
        updated: set[int] = set()
        for j in np.unique(measurements.sensor[rows]):
            scan = rows[measurements.sensor[rows] == j]
            found = [
                [angle_innovation(t.state, t.covariance, angles[r], sigmas[r], where[r]) for r in scan] for t in live
            ]
            nis = np.array([[f.nis for f in per] for per in found]).reshape(len(live), len(scan))
            chosen = nearest_neighbour(nis, float(missed_distance) ** 2)
            for k, r in enumerate(scan.tolist()):
                if chosen[k] < 0:
                    pending.append(r)
                    continue
                track = live[int(chosen[k])]
                track.state, track.covariance = ekf_update(track.state, track.covariance, found[int(chosen[k])][k])
                labels[r] = track.ident
                updated.add(track.ident)
        for track in live:
            track.misses = 0 if track.ident in updated else track.misses + 1
        live = [track for track in live if track.misses < delete_after]
        pending = [r for r in pending if now - time[r] <= window]
        if pending and now - min(time[r] for r in pending) >= window:
            waiting = np.array(sorted(pending, key=lambda r: (time[r], r)), dtype=np.int64)
            used: set[int] = set()
            for initiated in _initiate(fti, measurements.select(waiting), sensors, now):
                held = waiting[initiated.measurements]
                labels[held] = next_id
                used.update(held.tolist())
                start = np.asarray(initiated.state, dtype=np.float64)
                live.append(_Live(next_id, start, np.asarray(initiated.covariance, dtype=np.float64), now))
                next_id += 1
            pending = [r for r in pending if r not in used]
        for track in live:
            ids.append(track.ident)
            stamps.append(now)
            states.append(track.state)
            covariances.append(track.covariance)
    state = np.array(states, dtype=np.float64).reshape(-1, 2 * ndim)
    table = TrackTable.from_arrays(
        np.zeros(len(ids), dtype=np.int64),
        ids,
        stamps,
        state[:, :ndim],
        state[:, ndim:],
        covariance=np.array(covariances, dtype=np.float64).reshape(-1, 2 * ndim, 2 * ndim),
        sort=True,
    )
    return table, labels
