"""Kalman filtering of measurements into local tracks (shared by METHODS §4 and §5).

:class:`KalmanFilter` filters many independent tracks in one call: each track is a group of
rows of one shared measurement table, sorted by time. The filter runs in the Rust core, in
parallel and with the GIL released; results do not depend on the thread count. It is our own
few dozen lines of fixed-size linear algebra rather than a Python filter library, whose
per-call overhead would dominate when thousands of tracks are filtered per scan.

Models:

* ``motion``: ``"cv"`` (constant velocity) or ``"ca"`` (constant acceleration) in as many axes
  as the measurements have (1 to 3; polar: 2). The state is in block order
  ``[x, y, z, vx, vy, vz, ax, ay, az]`` (fewer axes drop their entries). Process noise is
  continuous white acceleration (CV) or jerk (CA) with spectral density ``process_noise``
  (m²/s³ resp. m²/s⁵) on every axis, discretised exactly for each time step, which may vary.
* ``measurement``: ``"position"`` (Cartesian, linear); ``"polar"`` (2-D range and azimuth from
  a per-row sensor position, azimuth counter-clockwise from +x, METHODS §0; an extended Kalman
  filter with the azimuth residual wrapped to (−π, π]); ``"polar_converted"`` (the same rows
  converted to Cartesian positions with the linearised covariance, then filtered linearly;
  biased when ``range · σθ² / σr`` exceeds about 0.4, where the EKF is not).
* ``init``: ``"differencing"`` (default) starts a track from the polynomial through its first
  two (CV) or three (CA) measurements, with the exact covariance (measurement noise and the
  process noise between the points): no prior to guess, honest from the first state on, but
  the first one (CV) or two (CA) rows of a track get no state. ``"single_point"`` starts at the
  first row from its position and a zero-mean velocity (and acceleration) prior of standard
  deviation ``init_velocity_std`` (``init_acceleration_std``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Annotated

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._params import POSITIVE, Configurable, Interval, Options, Threads
from .._settings import KalmanInit, KalmanMeasurement, KalmanMotion
from .._validation import as_float_array, require_time_range
from .fitting import _groups_to_csr

__all__ = ["KalmanFilter", "KalmanResult"]


@dataclass(frozen=True)
class KalmanResult:
    """Output of :meth:`KalmanFilter.filter`, aligned to the input rows.

    Rows of no track, rows before their track's first state (one row for ``"cv"``, two for
    ``"ca"`` with ``"differencing"``) and rows after a numerical failure (a polar prediction
    on its sensor, or overflow or a negative variance from absurd values) are NaN: a row
    with a state has a finite state and no negative variance.

    Attributes
    ----------
    states : ndarray, shape (n, D)
        Filtered state at each row's time, block order ``[positions, velocities(,
        accelerations)]``; D = 2 or 3 times the number of axes.
    covariances : ndarray, shape (n, D, D)
        Its covariance.
    nis : ndarray, shape (n,)
        Normalised innovation squared of the row's update, ``νᵀ S⁻¹ ν`` (χ² with as many
        degrees of freedom as measurement columns for a consistent filter); NaN also at the
        row that starts the track.
    """

    states: NDArray[np.float64]
    covariances: NDArray[np.float64]
    nis: NDArray[np.float64]

    @property
    def has_state(self) -> NDArray[np.bool_]:
        """True at the rows that have a filtered state."""
        # A row's state is all NaN or all finite.
        rows: NDArray[np.bool_] = ~np.isnan(self.states[:, 0])
        return rows


@dataclass(frozen=True, kw_only=True)
class KalmanFilter(Configurable):
    """Batched Kalman filter; see the module documentation for the models.

    Parameters
    ----------
    motion : {"cv", "ca"}
        Constant velocity or constant acceleration.
    measurement : {"position", "polar", "polar_converted"}
        Cartesian positions, or 2-D (range, azimuth) rows by EKF or by conversion.
    process_noise : float
        Spectral density ``q`` (≥ 0) of the white acceleration (CV, m²/s³) or jerk (CA,
        m²/s⁵) on every axis; required, as it depends on the targets.
    init : {"differencing", "single_point"}
        How a track starts (see the module documentation).
    init_velocity_std, init_acceleration_std : float
        Prior standard deviations of ``"single_point"`` (m/s, m/s²).
    n_threads : int, optional
        Threads; default all cores. Results are identical for any value.

    Examples
    --------
    >>> import numpy as np, passive_assoc as pa
    >>> t = np.arange(5.0)
    >>> z = np.column_stack([100 + 10 * t, 50 - 5 * t])  # one target, exact positions
    >>> out = pa.KalmanFilter(process_noise=0.1).filter(t, z, np.arange(5), noise=1.0)
    >>> out.states[-1].round(6)
    array([140.,  30.,  10.,  -5.])
    >>> out.has_state.tolist()
    [False, True, True, True, True]
    """

    motion: Annotated[KalmanMotion, Options("cv", "ca")] = "cv"
    measurement: Annotated[KalmanMeasurement, Options("position", "polar", "polar_converted")] = "position"
    process_noise: Annotated[float, Interval(float, 0.0, None)]
    init: Annotated[KalmanInit, Options("differencing", "single_point")] = "differencing"
    init_velocity_std: Annotated[float, POSITIVE] = 500.0
    init_acceleration_std: Annotated[float, POSITIVE] = 50.0
    n_threads: Threads = None

    def filter(
        self,
        times: ArrayLike,
        measurements: ArrayLike,
        groups: ArrayLike | Sequence[ArrayLike],
        *,
        noise: ArrayLike,
        sensor_positions: ArrayLike | None = None,
    ) -> KalmanResult:
        """Filter every track.

        Parameters
        ----------
        times : array_like, shape (n,)
            Time of each measurement row, seconds, within ±1e12 (as every epoch ``t0``).
        measurements : array_like, shape (n, m)
            Positions (m = 1 to 3; a 1-D array is one axis) or, for the polar models,
            (range, azimuth) rows (m = 2).
        groups : array_like or sequence of array_like
            The rows of each track, sorted by time within the track: a sequence of 1-D index
            arrays, a (P, k) integer array, or one 1-D index array (one track). A row belongs
            to at most one track; rows of no track get NaN.
        noise : float or array_like
            Measurement noise: one standard deviation for every value, one per column (m,),
            one per row and column (n, m), or a full covariance per row (n, m, m). Polar
            columns are (σr, σθ) in metres and radians.
        sensor_positions : array_like, shape (n, 2) or (2,), optional
            The sensor of each polar row (one position for all rows); polar models only.

        Returns
        -------
        KalmanResult
        """
        t = as_float_array("times", times, ndim=1)
        require_time_range("times", t)
        z = as_float_array("measurements", measurements)
        if z.ndim == 1:
            z = z[:, None]
        if z.ndim != 2:
            raise ValueError(f"measurements: expected a 1- or 2-dimensional array, got shape {z.shape}")
        if len(z) != len(t):
            raise ValueError(f"measurements: has {len(z)} rows, times has {len(t)}")
        if isinstance(groups, Sequence) and len(groups) == 0:
            raise ValueError("groups: no tracks given")
        indices, offsets = _groups_to_csr(groups)
        sensors = None
        if sensor_positions is not None:
            sensors = as_float_array("sensor_positions", sensor_positions)
            if sensors.shape == (2,):
                sensors = np.tile(sensors, (len(t), 1))
            if sensors.ndim != 2:
                raise ValueError(f"sensor_positions: expected shape (n, 2) or (2,), got {sensors.shape}")
        out = _core.kalman_filter(t, z, (indices, offsets), _noise(noise, *z.shape), sensors, self)
        return KalmanResult(*out)


def _noise(noise: ArrayLike, n: int, m: int) -> NDArray[np.float64]:
    """``noise`` as (n, m) standard deviations or (n, m, m) covariances."""
    values = as_float_array("noise", noise)
    if values.ndim == 0 or values.shape == (m,):
        return np.ascontiguousarray(np.broadcast_to(values, (n, m)))
    if m == 1 and values.shape == (n,):
        return values[:, None]
    if values.shape in ((n, m), (n, m, m)):
        return values
    raise ValueError(f"noise: expected a scalar or shape ({m},), ({n}, {m}) or ({n}, {m}, {m}), got {values.shape}")
