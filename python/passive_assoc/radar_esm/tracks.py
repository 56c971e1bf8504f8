"""Each sensor's own tracks (METHODS §5 step 1): its position reports, already grouped into
tracks by the sensor, filtered by a constant-acceleration Kalman filter into the states the
associators read (position, velocity, acceleration and their covariance)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .._params import Threads, checked
from .._validation import as_float_array
from ..data import TrackTable
from ..estimation import KalmanFilter

__all__ = ["filter_reports"]


@checked
def filter_reports(
    reports: TrackTable,
    process_noise: float,
    *,
    noise: ArrayLike | None = None,
    n_threads: Threads = None,
) -> TrackTable:
    """Filter every track of a table of position reports with ``KalmanFilter(motion="ca",
    measurement="position")``.

    Parameters
    ----------
    reports : TrackTable
        Position reports, one track per (source, track) — the sensors' own report-to-track
        assignment, taken as given — sorted by time within each track (as a TrackTable is).
    process_noise : float
        Spectral density of the white jerk, m²/s⁵ (see :class:`~passive_assoc.KalmanFilter`).
    noise : array_like, optional
        Measurement noise as :meth:`KalmanFilter.filter` takes it (stds, or a covariance per
        row); default: the reports' ``covariance`` column (each report's own covariance,
        e.g. a triangulated fix's).
    n_threads : int, optional

    Returns
    -------
    TrackTable
        Same sources, ids and truth; rows from each track's first filtered state on (the
        filter starts from three reports, so a track's first two rows have none).
    """
    if not isinstance(reports, TrackTable):
        raise TypeError(f"reports: expected a TrackTable, got {type(reports).__name__}")
    if noise is None:
        if reports.covariance is None:
            raise ValueError("reports: no covariance column; give the measurement noise as noise=")
        d = reports.ndim
        noise = reports.covariance[:, :d, :d]
    else:
        noise = as_float_array("noise", noise)
    groups = [rows for _, _, rows in reports.tracks()]
    if not groups:
        return reports
    kf = KalmanFilter(motion="ca", measurement="position", process_noise=process_noise, n_threads=n_threads)
    out = kf.filter(reports.time, reports.position, groups, noise=noise)
    keep = np.flatnonzero(out.has_state)
    return TrackTable.from_states(
        reports.source[keep],
        reports.track[keep],
        reports.time[keep],
        out.states[keep],
        reports.ndim,
        covariance=out.covariances[keep],
        truth=None if reports.truth is None else reports.truth[keep],
    )
