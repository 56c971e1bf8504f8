"""Maximum-likelihood fitting of angle measurements (METHODS §1 "Final estimate", §6).

:func:`fit_ml` fits many independent problems in one call: each problem is a group of rows
of one shared :class:`~passive_assoc.data.MeasurementTable`. The work runs in the
Rust core, in parallel and with the GIL released; results do not depend on the thread count.
:func:`crlb` gives the Cramér-Rao bound of a true state for the same model.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Annotated, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._inputs import check_network, check_pair
from .._params import POSITIVE, Epoch, Interval, Options, Threads, checked
from .._validation import as_float_array, as_int_array, require_state_range
from ..data import MeasurementTable, SensorNetwork

#: The fitted state: constant velocity at ``t0``, or a static position; declared once for
#: :func:`fit_ml`, :func:`crlb` and :func:`fisher_and_crlb`.
Motion = Annotated[Literal["static", "cv"], Options("cv", "static")]

#: Step halvings per Gauss-Newton line search before the fit reports ``stalled``.
MAX_HALVINGS = 30

#: Why one fit stopped.
FitTermination = Literal["converged", "max_iterations", "stalled", "singular", "non_finite"]

#: Names of the termination codes in :attr:`FitResult.termination`, by code.
TERMINATION_NAMES: tuple[FitTermination, ...] = ("converged", "max_iterations", "stalled", "singular", "non_finite")

#: Each termination in words (:attr:`FitResult.message`).
FIT_MESSAGES: dict[FitTermination, str] = {
    "converged": "converged: the step fell below xtol or step_sigmas",
    "max_iterations": "max_iter reached before convergence",
    "stalled": "no step-halving lowered the cost: at a minimum to rounding",
    "singular": "the Fisher information is singular: the state is not observable from these measurements",
    "non_finite": "a prediction or the cost became non-finite (e.g. a target on a sensor's vertical axis)",
}


@dataclass(frozen=True)
class FitResult:
    """Per-problem results of :func:`fit_ml`.

    Attributes
    ----------
    estimates : ndarray, shape (P, D)
        ML state estimates; D is 2/3 (static, 2-D/3-D) or 4/6 (constant velocity).
    covariances : ndarray, shape (P, D, D)
        Inverse Fisher information at each estimate (NaN where singular); on convergence,
        evaluated before the final step, which is below ``step_sigmas`` standard deviations.
    chi2 : ndarray, shape (P,)
        Sum of squared normalised residuals at the estimate (likewise).
    iterations : ndarray, shape (P,)
        Gauss-Newton iterations taken.
    termination : ndarray of uint8, shape (P,)
        Why each fit stopped; see :data:`TERMINATION_NAMES`.
    t0 : float
        The epoch of the constant-velocity states, seconds.
    """

    estimates: NDArray[np.float64]
    covariances: NDArray[np.float64]
    chi2: NDArray[np.float64]
    iterations: NDArray[np.uint32]
    termination: NDArray[np.uint8]
    t0: float = 0.0

    @property
    def success(self) -> NDArray[np.bool_]:
        """True where the fit converged (or stalled at a minimum to rounding), per problem
        (as SciPy's ``OptimizeResult.success``)."""
        done: NDArray[np.bool_] = (self.termination == 0) | (self.termination == 2)
        return done

    @property
    def converged(self) -> NDArray[np.bool_]:
        """The same as :attr:`success`: a fit succeeds by converging."""
        return self.success

    @property
    def message(self) -> list[str]:
        """Why each fit stopped, in words."""
        return [FIT_MESSAGES[name] for name in self.termination_names()]

    def termination_names(self) -> list[FitTermination]:
        """The termination of each problem as a name."""
        return [TERMINATION_NAMES[int(code)] for code in self.termination]


def _groups_to_csr(groups: ArrayLike | Sequence[ArrayLike]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Problem groups → (indices, offsets). Accepts a (P, k) integer array (equal-size groups,
    the fast path), a single 1-D index array (one problem), or a sequence of 1-D arrays."""
    if isinstance(groups, np.ndarray) and groups.ndim == 2:
        dense = as_int_array("groups", groups, ndim=2)
        offsets = np.arange(dense.shape[0] + 1, dtype=np.int64) * dense.shape[1]
        return dense.ravel(), offsets
    if isinstance(groups, np.ndarray) and groups.ndim == 1 and groups.dtype != object:
        groups = [groups]
    if not isinstance(groups, Sequence | np.ndarray):
        raise TypeError(f"groups: expected an integer array or a sequence of index arrays, got {type(groups).__name__}")
    parts = [as_int_array(f"groups[{p}]", g, ndim=1) for p, g in enumerate(groups)]
    if not parts:
        raise ValueError("groups: no problems given")
    sizes = np.fromiter((len(p) for p in parts), dtype=np.int64, count=len(parts))
    offsets = np.concatenate(([0], np.cumsum(sizes)))
    return np.concatenate(parts), offsets


@checked
def fit_ml(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    groups: ArrayLike | Sequence[ArrayLike],
    *,
    initial: ArrayLike | None = None,
    motion: Motion = "cv",
    t0: Epoch = None,
    max_iter: Annotated[int, Interval(int, 1, None)] = 50,
    xtol: Annotated[float, POSITIVE] = 1e-10,
    step_sigmas: Annotated[float, Interval(float, 0.0, None)] = 1e-6,
    n_threads: Threads = None,
) -> FitResult:
    """Fit one state per group of measurements by Gauss-Newton maximum likelihood.

    Parameters
    ----------
    measurements : MeasurementTable
        The shared measurement table.
    sensors : SensorNetwork
        Positions and noise stds; its ``ndim`` selects bearing-only (2) or az/el (3).
    groups : array_like
        Rows of ``measurements`` per problem: a (P, k) integer array, one 1-D index array,
        or a sequence of 1-D index arrays of any lengths.
    initial : array_like, shape (P, D), optional
        Starting states. Default: the linear least-squares ("pseudo-linear") line-of-sight
        solution of each group.
    motion : {"cv", "static"}
        Constant-velocity initial state at ``t0`` (D = 4 or 6) or a static position (D = 2, 3).
    t0 : float, optional
        Epoch of the constant-velocity state, seconds. Default: the table's earliest time, as
        :class:`~passive_assoc.FuzzyTrackInitiator` takes it, so that UNIX-epoch times work (an
        epoch of 0 with times near 1.7e9 s leaves the fit singular). :attr:`FitResult.t0`
        records the one used.
    max_iter, xtol
        Iteration cap and relative step tolerance.
    step_sigmas : float
        Also converged when the Gauss-Newton step is shorter than this many standard
        deviations of the estimate (its Mahalanobis length): the statistically meaningful
        test, which ends the zig-zag of barely-determined problems along flat valleys.
    n_threads : int, optional
        Threads to use; default all cores. Results are identical for any value.

    Returns
    -------
    FitResult

    Examples
    --------
    >>> import numpy as np, passive_assoc as pa
    >>> sc = pa.paper_fti_scenario(seed=1)
    >>> rows = [np.flatnonzero(sc.measurements.truth == k) for k in range(4)]
    >>> fit = pa.fit_ml(sc.measurements, sc.sensors, rows)
    >>> fit.estimates.shape, bool(fit.converged.all())
    ((4, 6), True)
    """
    table, network = check_pair(measurements, sensors)
    if t0 is None:
        t0 = float(table.time.min()) if len(table) else 0.0
    indices, offsets = _groups_to_csr(groups)
    dim = network.ndim * (2 if motion == "cv" else 1)
    start = None if initial is None else as_float_array("initial", initial, shape=(len(offsets) - 1, dim))
    settings = SimpleNamespace(
        motion=motion,
        t0=t0,
        max_iter=max_iter,
        xtol=xtol,
        step_sigmas=step_sigmas,
        max_halvings=MAX_HALVINGS,
        n_threads=n_threads,
    )
    out = _core.fit_batch(table, network, indices, offsets, start, settings)
    return FitResult(*out, t0=t0)


def crlb(
    sensor_index: ArrayLike,
    times: ArrayLike,
    sensors: SensorNetwork,
    truth: ArrayLike,
    *,
    motion: Motion = "cv",
    t0: Epoch = 0.0,
    sensor_position: ArrayLike | None = None,
    sigma_azimuth: ArrayLike | None = None,
    sigma_elevation: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """Cramér-Rao lower bound of a true state observed once per (sensor, time) pair.

    The arguments come in :func:`fit_ml`'s order: what is observed (here the schedule, as
    ``measurements.sensor`` and ``measurements.time`` would give it), the network, then what
    is estimated (here its true value).

    Parameters
    ----------
    sensor_index : array_like of int, shape (N,)
        Which sensor takes each measurement.
    times : array_like of float, shape (N,)
        When.
    sensors : SensorNetwork
    truth : array_like, shape (D,)
        The true state (position, or constant-velocity ``X0`` at ``t0``).
    motion, t0
        As in :func:`fit_ml`, but ``t0`` defaults to 0 here: it is the epoch of ``truth``,
        which the caller knows (None: the earliest of ``times``).
    sensor_position : array_like, shape (N, 3), optional
        Where each measurement's sensor is (a moving platform, as a table's
        ``sensor_position``; a NaN row: the network's position).
    sigma_azimuth, sigma_elevation : array_like, shape (N,), optional
        Each measurement's own noise stds (NaN: the sensor's), as a table's.

    Returns
    -------
    ndarray, shape (D, D)
        The bound: the inverse Fisher information. ``sqrt(diag)`` is the best achievable
        per-component RMS of an unbiased estimator.
    """
    return fisher_and_crlb(
        sensor_index,
        times,
        sensors,
        truth,
        motion=motion,
        t0=t0,
        sensor_position=sensor_position,
        sigma_azimuth=sigma_azimuth,
        sigma_elevation=sigma_elevation,
    )[1]


@checked
def fisher_and_crlb(
    sensor_index: ArrayLike,
    times: ArrayLike,
    sensors: SensorNetwork,
    truth: ArrayLike,
    *,
    motion: Motion = "cv",
    t0: Epoch = 0.0,
    sensor_position: ArrayLike | None = None,
    sigma_azimuth: ArrayLike | None = None,
    sigma_elevation: ArrayLike | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The Fisher information and its inverse; see :func:`crlb`."""
    network = check_network(sensors)
    state = as_float_array("truth", truth, ndim=1)
    require_state_range("truth", state)
    when = as_float_array("times", times, ndim=1)
    if t0 is None:  # None: the earliest time, as fit_ml's default
        t0 = float(when.min()) if len(when) else 0.0
    position = None if sensor_position is None else as_float_array("sensor_position", sensor_position, shape=(None, 3))
    sigmas = [
        None if s is None else as_float_array(name, s, ndim=1)
        for name, s in (("sigma_azimuth", sigma_azimuth), ("sigma_elevation", sigma_elevation))
    ]
    index = as_int_array("sensor_index", sensor_index, ndim=1)
    return _core.crlb(network, state, index, when, motion, t0, position, *sigmas)
