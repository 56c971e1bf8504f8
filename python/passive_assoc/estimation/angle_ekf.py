"""One step of a constant-velocity extended Kalman filter on angle reports (numpy only).

:class:`~passive_assoc.KalmanFilter` filters whole tracks whose rows are known in advance, on
Cartesian positions or (range, azimuth); a tracker that decides report by report which track
a bearing belongs to needs a filter it can step one angle report at a time, with the
innovation in hand for its gate. These three functions are that step:

* :func:`cv_predict` moves a state ``dt`` seconds on under the constant-velocity model of
  ``KalmanFilter(motion="cv")``: block order ``[x, y(, z), vx, vy(, vz)]``, continuous white
  acceleration of spectral density ``process_noise`` (m²/s³) on every axis, discretised
  exactly.
* :func:`angle_innovation` linearises the report's model at the prediction: the azimuth
  ``atan2(dy, dx)`` (2-D) or the azimuth and elevation ``atan2(dz, hypot(dx, dy))`` (3-D) of
  the state's position seen from the sensor (METHODS §0), with its Jacobian; the azimuth
  residual is wrapped to (−π, π]. ``nis`` is ``νᵀ S⁻¹ ν``, χ² with 1 (2-D) or 2 (3-D)
  degrees of freedom for a consistent filter — the tracker's gate.
* :func:`ekf_update` applies it (Joseph form, so the covariance stays symmetric and positive).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, as_float_scalar, require_finite, require_positive

__all__ = ["AngleInnovation", "angle_innovation", "cv_predict", "ekf_update"]


@dataclass(frozen=True)
class AngleInnovation:
    """A report's innovation against a predicted state.

    Attributes
    ----------
    residual : ndarray, shape (m,)
        Report minus prediction, azimuth wrapped to (−π, π] (m = 1 in 2-D, 2 in 3-D:
        azimuth, elevation); NaN when the state's position is on the sensor's vertical axis,
        where the angles have no derivative.
    covariance : ndarray, shape (m, m)
        ``S = H P Hᵀ + R``.
    jacobian : ndarray, shape (m, D)
        ``H``, the angles' derivative with respect to the state.
    noise : ndarray, shape (m, m)
        ``R``, the report's noise covariance.
    nis : float
        ``νᵀ S⁻¹ ν``; infinite where the residual is NaN.
    """

    residual: NDArray[np.float64]
    covariance: NDArray[np.float64]
    jacobian: NDArray[np.float64]
    noise: NDArray[np.float64]
    nis: float


def _state(state: ArrayLike, covariance: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], int]:
    x = as_float_array("state", state, ndim=1)
    if len(x) not in (4, 6):
        raise ValueError(f"state: expected 4 (2-D) or 6 (3-D) values, got {len(x)}")
    require_finite("state", x)
    p = as_float_array("covariance", covariance, shape=(len(x), len(x)))
    require_finite("covariance", p)
    return x, p, len(x) // 2


def cv_predict(
    state: ArrayLike, covariance: ArrayLike, dt: float, process_noise: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The state and covariance ``dt`` (≥ 0) seconds on, constant velocity (module doc)."""
    x, p, n = _state(state, covariance)
    step = as_float_scalar("dt", dt, finite=True)
    if step < 0:
        raise ValueError(f"dt: must be >= 0 seconds, got {step!r}")
    q = as_float_scalar("process_noise", process_noise, finite=True)
    if q < 0:
        raise ValueError(f"process_noise: must be >= 0, got {q!r}")
    eye = np.eye(n)
    f = np.block([[eye, step * eye], [np.zeros((n, n)), eye]])
    noise = q * np.block([[step**3 / 3 * eye, step**2 / 2 * eye], [step**2 / 2 * eye, step * eye]])
    moved = f @ p @ f.T + noise
    return f @ x, 0.5 * (moved + moved.T)


def angle_innovation(
    state: ArrayLike, covariance: ArrayLike, angles: ArrayLike, sigmas: ArrayLike, sensor_position: ArrayLike
) -> AngleInnovation:
    """The innovation of a report (``angles``: azimuth, or azimuth and elevation, radians;
    ``sigmas``: their noise standard deviations) from a sensor at ``sensor_position`` (its
    first 2 or 3 coordinates are used) against a predicted state (module doc)."""
    x, p, n = _state(state, covariance)
    z = as_float_array("angles", angles, shape=(n - 1,))
    require_finite("angles", z)
    sd = as_float_array("sigmas", sigmas, shape=(n - 1,))
    require_positive("sigmas", sd)
    where = as_float_array("sensor_position", sensor_position, ndim=1)
    if len(where) < n:
        raise ValueError(f"sensor_position: expected at least {n} coordinates, got {len(where)}")
    require_finite("sensor_position", where)
    d = x[:n] - where[:n]
    ground = float(np.hypot(d[0], d[1]))
    noise = np.diag(sd**2)
    h = np.zeros((n - 1, 2 * n))
    if ground == 0.0:
        nan = np.full(n - 1, np.nan)
        return AngleInnovation(nan, noise + np.nan, h + np.nan, noise, float("inf"))
    h[0, :2] = [-d[1] / ground**2, d[0] / ground**2]
    predicted = [np.arctan2(d[1], d[0])]
    if n == 3:
        slant2 = ground**2 + d[2] ** 2
        h[1, :3] = [-d[0] * d[2] / (slant2 * ground), -d[1] * d[2] / (slant2 * ground), ground / slant2]
        predicted.append(np.arctan2(d[2], ground))
    residual = z - np.array(predicted)
    residual[0] = np.pi - np.mod(np.pi - residual[0], 2.0 * np.pi)
    s = h @ p @ h.T + noise
    s = 0.5 * (s + s.T)
    nis = float(residual @ np.linalg.solve(s, residual))
    return AngleInnovation(residual, s, h, noise, nis)


def ekf_update(
    state: ArrayLike, covariance: ArrayLike, innovation: AngleInnovation
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The state and covariance after the report of ``innovation`` (Joseph form)."""
    x, p, _ = _state(state, covariance)
    if not isinstance(innovation, AngleInnovation):
        raise TypeError(f"innovation: expected an AngleInnovation, got {type(innovation).__name__}")
    if innovation.jacobian.shape != (len(innovation.residual), len(x)):
        raise ValueError(f"innovation: its Jacobian has shape {innovation.jacobian.shape}, the state {len(x)} values")
    if not np.isfinite(innovation.nis):
        raise ValueError("innovation: has no finite residual (the state is on the sensor's vertical axis)")
    h = innovation.jacobian
    gain = np.linalg.solve(innovation.covariance, h @ p).T
    x = x + gain @ innovation.residual
    keep = np.eye(len(x)) - gain @ h
    p = keep @ p @ keep.T + gain @ innovation.noise @ gain.T
    return x, 0.5 * (p + p.T)
