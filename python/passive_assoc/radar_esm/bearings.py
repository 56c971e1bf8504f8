"""Raw ESM bearings as the radar/ESM associators take them: an ESM picture is bearings from
several sites, each emitter's bearings grouped by the ESM system (its own report-to-track
assignment, taken as given, as the radar's is). Each scan's bearings of one emitter, from two
sites or more, are one position fix: the maximum-likelihood static position
(:func:`~passive_assoc.fit_ml`, ``motion="static"``) with its covariance — accurate across the
lines of sight, poor along them, and differently for every emitter. The fixes are raw reports:
the associators decompose them in the coarse gate with their own covariances, and filter them
for the fine stage (:mod:`.sides`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .._params import Threads, checked
from .._validation import as_int_array
from ..data import MeasurementTable, SensorNetwork, TrackTable
from ..estimation import fit_ml

__all__ = ["bearing_fixes"]


@checked
def bearing_fixes(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    track: ArrayLike,
    *,
    source: int = 1,
    n_threads: Threads = None,
) -> TrackTable:
    """One position fix per (emitter track, scan time) from its bearings.

    Parameters
    ----------
    measurements : MeasurementTable
        The ESM sites' bearings (2-D: azimuth only), at scan times shared by the sites.
    sensors : SensorNetwork
        The sites (positions and bearing noise).
    track : array_like of int, shape (N,)
        The emitter track of each row, ≥ 0 (the ESM system's grouping), or −1 for a row of
        none (left out).
    source : int
        The ESM picture's source id in the returned table.
    n_threads : int, optional

    Returns
    -------
    TrackTable
        Positions with their covariances (and the rows' truth, where every bearing of a fix
        has the same), one row per (track, time) with bearings from at least two sites; the
        others are left out (one bearing fixes no position).
    """
    if not isinstance(measurements, MeasurementTable):
        raise TypeError(f"measurements: expected a MeasurementTable, got {type(measurements).__name__}")
    if measurements.ndim != 2:
        raise ValueError("measurements: bearing fixes need 2-D bearings (azimuth only)")
    ids = as_int_array("track", track, shape=(len(measurements),))
    keys = np.column_stack([ids, measurements.time])
    rows = np.flatnonzero(ids >= 0)
    order = rows[np.lexsort((measurements.sensor[rows], measurements.time[rows], ids[rows]))]
    groups, fixes = [], []
    start = 0
    while start < len(order):
        stop = start + 1
        while stop < len(order) and (keys[order[stop]] == keys[order[start]]).all():
            stop += 1
        group = order[start:stop]
        if len(np.unique(measurements.sensor[group])) >= 2:
            groups.append(group)
            fixes.append(group[0])
        start = stop
    if not groups:
        return TrackTable.from_arrays(np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0), np.empty((0, 2)))
    fit = fit_ml(measurements, sensors, groups, motion="static", n_threads=n_threads)
    first = np.array(fixes)
    truth = None
    if measurements.truth is not None:
        truth = np.array(
            [
                int(measurements.truth[g[0]]) if (measurements.truth[g] == measurements.truth[g[0]]).all() else -1
                for g in groups
            ]
        )
    return TrackTable.from_arrays(
        np.full(len(groups), source),
        ids[first],
        measurements.time[first],
        fit.estimates,
        covariance=fit.covariances,
        truth=truth,
        sort=True,
    )
