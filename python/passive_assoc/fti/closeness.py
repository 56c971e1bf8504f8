"""The fuzzy synthetic closeness R of METHODS §1 (eq. 17–18) and its steepest-ascent search
(eq. 19), exposed on their own: evaluate R and ∂R/∂X0 at many states, or climb to the local
maxima of R from given starts. :class:`~passive_assoc.fti.FuzzyTrackInitiator` uses
the same kernels internally.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace
from typing import Annotated, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._inputs import check_pair
from .._params import POSITIVE, Epoch, Interval, Options, Threads, checked
from .._validation import as_float_array, require_state_range
from ..data import MeasurementTable, SensorNetwork


def _spreads(
    measurements: MeasurementTable, sensors: SensorNetwork, spread_factor: float
) -> tuple[MeasurementTable, SensorNetwork, tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """The checked pair plus the per-sensor spreads (azimuth, elevation)."""
    table, network = check_pair(measurements, sensors)
    sigma_el = sensors.sigma_azimuth if sensors.ndim == 2 else sensors.sigma_elevation
    return table, network, (spread_factor * sensors.sigma_azimuth, spread_factor * np.asarray(sigma_el, dtype=float))


def _epoch(measurements: MeasurementTable, t0: float | None) -> float:
    """``t0`` or the table's earliest time (0 for an empty table)."""
    if t0 is not None:
        return t0
    times = np.asarray(measurements.time)
    return float(times.min()) if times.size else 0.0


@checked
def closeness(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    states: ArrayLike,
    *,
    t0: Epoch = None,
    spread_factor: Annotated[float, POSITIVE] = 2.0,
    n_threads: Threads = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """R and its gradient at each constant-velocity state.

    Parameters
    ----------
    measurements, sensors
        All measurements of all sensors (R is the mean membership over every row).
    states : array_like, shape (P, D)
        X0 at ``t0``; D = 6 (3-D) or 4 (2-D).
    t0 : float, optional
        Epoch of the states; default the earliest measurement time, as
        :meth:`FuzzyTrackInitiator.initiate` and :func:`fit_ml` use (an epoch of 0 with UNIX
        times near 1.7e9 s would leave every predicted position a product of huge numbers).
    spread_factor : float
        Membership spread as a multiple of each sensor's noise std (paper: 2).
    n_threads : int, optional

    Returns
    -------
    (R, gradient) : ndarray (P,), ndarray (P, D)
    """
    d = 2 * sensors.ndim
    x = as_float_array("states", states, shape=(None, d))
    require_state_range("states", x)
    return _core.closeness(*_spreads(measurements, sensors, spread_factor), x, _epoch(measurements, t0), n_threads)


@dataclass(frozen=True)
class ClosenessOptima:
    """Local maxima of R reached by :func:`maximize_closeness`, one per start."""

    states: NDArray[np.float64]
    closeness: NDArray[np.float64]
    iterations: NDArray[np.int64]
    evaluations: NDArray[np.int64]


@checked
def maximize_closeness(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    starts: ArrayLike,
    covariances: ArrayLike,
    *,
    t0: Epoch = None,
    spread_factor: Annotated[float, POSITIVE] = 2.0,
    scaling: Annotated[Literal["whitened", "diagonal"], Options("whitened", "diagonal")] = "whitened",
    max_iter: Annotated[int, Interval(int, 0, None)] = 100,
    n_threads: Threads = None,
) -> ClosenessOptima:
    """Steepest ascent of R with Armijo backtracking from each start (METHODS §1, eq. 19).

    Each search runs in coordinates scaled by its start's covariance (typically the
    candidate fit's): ``"whitened"`` uses the Cholesky factor, ``"diagonal"`` the
    per-component standard deviations.

    Parameters
    ----------
    starts : array_like, shape (P, D)
    covariances : array_like, shape (P, D, D)
        Positive definite.
    t0 : float, optional
        Epoch of the states; default the earliest measurement time (as :func:`closeness`).
    max_iter : int
        Iteration cap per search.

    Returns
    -------
    ClosenessOptima
    """
    d = 2 * sensors.ndim
    x = as_float_array("starts", starts, shape=(None, d))
    require_state_range("starts", x)
    c = as_float_array("covariances", covariances, shape=(x.shape[0], d, d))
    settings = SimpleNamespace(t0=_epoch(measurements, t0), scaling=scaling, max_iter=max_iter, n_threads=n_threads)
    out = _core.maximize_closeness(*_spreads(measurements, sensors, spread_factor), x, c, settings)
    return ClosenessOptima(*out)
