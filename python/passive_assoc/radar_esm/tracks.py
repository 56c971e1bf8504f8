"""Each sensor's own tracks (METHODS §5 step 1): its position reports, already grouped into
tracks by the sensor, filtered by a constant-acceleration Kalman filter into the states the
associators read (position, velocity, acceleration and their covariance); and the filter's
process noise read back from tracks it made.

The filter starts every track from a prior at its first report (``init="single_point"``: the
report's position, zero-mean velocity and acceleration with standard deviations
``init_velocity_std`` = 500 m/s and ``init_acceleration_std`` = 50 m/s²), so a track has a
state from its first scan and its acceleration settles within a few scans. Starting from the
polynomial through the first three reports (``init="differencing"``, the former default) leaves
the first two scans without a state and the acceleration at the noise of a second difference of
three reports (σ·√6/T², 1.7 km/s² for the paper's 707 m reports): the wavelet-fuzzy method's
fine stage, which weighs the acceleration most, then needs 10 more scans to separate the
targets (docs/experiments.md, wavelet).
"""

from __future__ import annotations

from typing import Annotated

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._params import POSITIVE, Interval, Options, Threads, checked
from .._settings import KalmanInit
from .._validation import as_float_array
from ..data import TrackTable
from ..estimation import KalmanFilter

__all__ = ["REPORT_PROCESS_NOISE", "filter_reports", "process_noise_of"]


@checked
def filter_reports(
    reports: TrackTable,
    process_noise: Annotated[float, Interval(float, 0.0, None)],
    *,
    noise: ArrayLike | None = None,
    init: Annotated[KalmanInit, Options("differencing", "single_point")] = "single_point",
    init_velocity_std: Annotated[float, POSITIVE] = 500.0,
    init_acceleration_std: Annotated[float, POSITIVE] = 50.0,
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
        Spectral density of the white jerk, m²/s⁵ (see :class:`~passive_assoc.KalmanFilter`):
        the targets' maneuver power where it is known, else :data:`REPORT_PROCESS_NOISE`.
    noise : array_like, optional
        Measurement noise as :meth:`KalmanFilter.filter` takes it (stds, or a covariance per
        row); default: the reports' ``covariance`` column (each report's own covariance,
        e.g. a triangulated fix's).
    init : {"single_point", "differencing"}
        How a track starts (module docs): from a prior at its first report (default), or
        from its first three reports.
    init_velocity_std, init_acceleration_std : float
        The prior's standard deviations (m/s, m/s²), for ``init="single_point"``.
    n_threads : int, optional

    Returns
    -------
    TrackTable
        Same sources, ids and truth; rows from each track's first filtered state on (with
        ``"differencing"`` a track's first two rows have none).
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
    kf = KalmanFilter(
        motion="ca",
        measurement="position",
        process_noise=process_noise,
        init=init,
        init_velocity_std=init_velocity_std,
        init_acceleration_std=init_acceleration_std,
        n_threads=n_threads,
    )
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


#: The white-jerk density (m²/s⁵) of the filter the radar/ESM associators run on raw reports
#: when not told: an acceleration change of the prior's size (``init_acceleration_std`` =
#: 50 m/s²) every 10 s, 50²/10. Raw reports cannot say it themselves where the noise swamps
#: the maneuvers (the paper's scene: 707 m reports, accelerations of tens of m/s²).
REPORT_PROCESS_NOISE = 250.0


#: How far apart (relative) the process noise of one table's filter steps may be, for
#: :func:`process_noise_of` to read them as one filter's.
CONSISTENT = 0.01
#: Filter steps :func:`process_noise_of` reads at most (evenly spread over the table), and the
#: bisections per step: 50 halvings of the 24 decades searched leave 2e-14 of a decade.
MAX_STEPS, BISECTIONS = 64, 50


def process_noise_of(tracks: TrackTable) -> float | None:
    """The white-jerk density q of the constant-acceleration Kalman filter that made
    ``tracks``, read back from their covariances, or None when the table cannot say.

    Between two scans of a track the filter predicts ``P⁻ = F P_{k−1} Fᵀ + q Q₁`` and its
    update adds information on the position only, ``P_k⁻¹ = P⁻⁻¹ + Hᵀ R⁻¹ H``: so the
    velocity and acceleration blocks of ``P_k⁻¹`` and ``P⁻⁻¹`` are equal, whatever R was. Their
    traces fall as q grows, so each step's q is found by bisection, and the median over every
    step is returned. None: no covariances of a constant-acceleration state (3·ndim values), no
    two consecutive scans of a track, or steps disagreeing by more than :data:`CONSISTENT`
    (relative, between their 10th and 90th percentiles: not one CA filter's tracks).
    """
    d = tracks.ndim
    if tracks.covariance is None or tracks.covariance.shape[1] != 3 * d or len(tracks) < 2:
        return None
    same = (tracks.source[1:] == tracks.source[:-1]) & (tracks.track[1:] == tracks.track[:-1])
    step = np.flatnonzero(same)
    if len(step) == 0:
        return None
    step = step[:: max(1, len(step) // MAX_STEPS)]  # a few dozen steps say it as well as all
    dt = tracks.time[step + 1] - tracks.time[step]
    before, after = tracks.covariance[step], tracks.covariance[step + 1]
    transition, unit = _ca_model(dt, d)
    predicted = transition @ before @ np.swapaxes(transition, 1, 2)
    try:
        target = _moments(np.asarray(np.linalg.inv(after), dtype=np.float64), d)
    except np.linalg.LinAlgError:
        return None

    def moments(log_q: NDArray[np.float64]) -> NDArray[np.float64]:
        inverse = np.linalg.inv(predicted + np.exp(log_q)[:, None, None] * unit)
        return _moments(np.asarray(inverse, dtype=np.float64), d)

    low, high = np.full(len(step), np.log(1e-12)), np.full(len(step), np.log(1e12))
    try:
        if not (np.all(moments(low) >= target) and np.all(moments(high) <= target)):
            return None
        for _ in range(BISECTIONS):
            middle = (low + high) / 2
            above = moments(middle) > target
            low, high = np.where(above, middle, low), np.where(above, high, middle)
    except np.linalg.LinAlgError:
        return None
    q = np.exp((low + high) / 2)
    spread = np.percentile(q, 90) / np.percentile(q, 10) - 1.0
    return float(np.median(q)) if spread <= CONSISTENT else None


def _moments(information: NDArray[np.float64], d: int) -> NDArray[np.float64]:
    """The trace of the velocity and acceleration blocks of each information matrix."""
    out: NDArray[np.float64] = np.trace(information[:, d:, d:], axis1=1, axis2=2)
    return out


def _ca_model(dt: NDArray[np.float64], d: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """F and Q₁ (unit density) of the constant-acceleration model for each step, block order."""
    one, zero = np.ones_like(dt), np.zeros_like(dt)
    f1 = np.stack(
        [np.stack([one, dt, dt * dt / 2], -1), np.stack([zero, one, dt], -1), np.stack([zero, zero, one], -1)], -2
    )
    q1 = np.stack(
        [
            np.stack([dt**5 / 20, dt**4 / 8, dt**3 / 6], -1),
            np.stack([dt**4 / 8, dt**3 / 3, dt**2 / 2], -1),
            np.stack([dt**3 / 6, dt**2 / 2, dt], -1),
        ],
        -2,
    )
    eye = np.eye(d)
    return np.einsum("nij,kl->nikjl", f1, eye).reshape(len(dt), 3 * d, 3 * d), np.einsum(
        "nij,kl->nikjl", q1, eye
    ).reshape(len(dt), 3 * d, 3 * d)
