"""Scenario simulator: constant-velocity targets seen by passive angle-only sensors, and a
generic 2-D bearing-only scenario (the fuzzy-track-initiation paper's scenario is in
:mod:`passive_assoc.simulation.fti`).

All randomness comes from ``numpy.random.default_rng(seed)`` with an explicit ``seed``, so a
scenario is reproducible from its arguments alone. Geometry follows METHODS §0:
``az = atan2(dy, dx)`` wrapped to (-pi, pi], ``el = atan2(dz, hypot(dx, dy))``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import (
    as_float_array,
    as_float_scalar,
    as_int_scalar,
    as_interval,
    readonly,
    require_finite,
)
from ..data import MeasurementTable, SensorNetwork, SensorTrack

__all__ = [
    "ConstantVelocityTarget",
    "Scenario",
    "simulate",
    "bearing_only_2d_scenario",
    "wrap_angle",
]

Seed = int | np.random.Generator


def wrap_angle(angle: ArrayLike) -> NDArray[np.float64]:
    """Wrap angles to (-pi, pi] (METHODS §0); pi stays pi and -pi maps to pi."""
    a = np.asarray(angle, dtype=np.float64)
    return np.pi - np.mod(np.pi - a, 2.0 * np.pi)


@dataclass(frozen=True, eq=False)
class ConstantVelocityTarget:
    """A target moving in a straight line at constant velocity.

    Parameters
    ----------
    initial_state : array_like, shape (6,) or (4,)
        ``(x0, y0, z0, vx, vy, vz)`` for 3-D or ``(x0, y0, vx, vy)`` for 2-D, at ``t0``.
    t0 : float
        Reference time of ``initial_state``, seconds.
    """

    initial_state: NDArray[np.float64]
    t0: float = 0.0

    def __post_init__(self) -> None:
        state = as_float_array("initial_state", self.initial_state, ndim=1)
        if state.shape not in ((4,), (6,)):
            raise ValueError(f"initial_state: expected shape (6,) for 3-D or (4,) for 2-D, got {state.shape}")
        require_finite("initial_state", state)
        t0 = as_float_scalar("t0", self.t0, finite=True)
        object.__setattr__(self, "initial_state", readonly(state))
        object.__setattr__(self, "t0", t0)

    @property
    def ndim(self) -> int:
        """Spatial dimension, 2 or 3."""
        return int(self.initial_state.shape[0]) // 2

    def position(self, t: ArrayLike) -> NDArray[np.float64]:
        """Position at time(s) ``t``: shape ``t.shape + (ndim,)``, metres."""
        tt = as_float_array("t", t)
        p0, v = self.initial_state[: self.ndim], self.initial_state[self.ndim :]
        return p0 + (tt[..., None] - self.t0) * v

    def state_at(self, t: float) -> NDArray[np.float64]:
        """State ``(position, velocity)`` re-referenced to time ``t``."""
        return np.concatenate([self.position(t), self.initial_state[self.ndim :]])


@dataclass(frozen=True, eq=False)
class Scenario:
    """A simulated run: the network, the truth and what the sensors reported.

    Attributes
    ----------
    sensors : SensorNetwork
    targets : list of ConstantVelocityTarget
    measurements : MeasurementTable
        With the hidden ``truth`` column (target index, -1 clutter).
    scan_times : list of numpy.ndarray
        Scan times of each sensor.
    t0 : float
        Reference time of :attr:`true_states`.
    """

    sensors: SensorNetwork
    targets: list[ConstantVelocityTarget]
    measurements: MeasurementTable
    scan_times: list[NDArray[np.float64]] = field(default_factory=list)
    t0: float = 0.0

    @property
    def true_states(self) -> NDArray[np.float64]:
        """Target states at :attr:`t0`, shape (n_targets, 2 * ndim)."""
        return np.array([tg.state_at(self.t0) for tg in self.targets]).reshape(len(self.targets), 2 * self.sensors.ndim)

    def true_groups(self) -> list[NDArray[np.int64]]:
        """Row indices of each target's measurements (index k for target k)."""
        truth = self.measurements.truth
        assert truth is not None  # a simulated table always carries truth
        return [np.flatnonzero(truth == k) for k in range(len(self.targets))]


def _true_angles(
    sensor_pos: NDArray[np.float64], points: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Noise-free azimuth and elevation of ``points`` (..., 3) seen from ``sensor_pos``."""
    d = points - sensor_pos
    az = np.arctan2(d[..., 1], d[..., 0])
    el = np.arctan2(d[..., 2], np.hypot(d[..., 0], d[..., 1]))
    return az, el


def _clutter_counts(
    rng: np.random.Generator, n_scans: int, per_scan: int | None, rate: float | None
) -> NDArray[np.int64]:
    if per_scan is not None:
        return np.full(n_scans, per_scan, dtype=np.int64)
    if rate is not None:
        return rng.poisson(rate, n_scans).astype(np.int64)
    return np.zeros(n_scans, dtype=np.int64)


def _check_clutter(per_scan: int | None, rate: float | None) -> None:
    if per_scan is not None and rate is not None:
        raise ValueError("clutter_per_scan: give clutter_per_scan or clutter_rate, not both")
    if per_scan is not None:
        as_int_scalar("clutter_per_scan", per_scan, minimum=0)
    if rate is not None and as_float_scalar("clutter_rate", rate, finite=True) < 0:
        raise ValueError(f"clutter_rate: must be >= 0, got {rate!r}")


def _check_targets(targets: Sequence[ConstantVelocityTarget], ndim: int) -> list[ConstantVelocityTarget]:
    out = list(targets)
    for k, tg in enumerate(out):
        if not isinstance(tg, ConstantVelocityTarget):
            raise TypeError(f"targets[{k}]: expected a ConstantVelocityTarget, got {tg!r}")
        if tg.ndim != ndim:
            raise ValueError(f"targets[{k}]: is {tg.ndim}-D but the sensor network is {ndim}-D")
    return out


def _check_scan_times(scan_times: Sequence[ArrayLike], n: int) -> list[NDArray[np.float64]]:
    if len(scan_times) != n:
        raise ValueError(f"scan_times: expected one array per sensor ({n}), got {len(scan_times)}")
    out = []
    for j, st in enumerate(scan_times):
        arr = as_float_array(f"scan_times[{j}]", st, ndim=1)
        require_finite(f"scan_times[{j}]", arr)
        out.append(readonly(arr))
    return out


def _check_seed(seed: Seed) -> np.random.Generator:
    # Reproducibility is the point of the simulator, so an implicit (None) seed is refused.
    if isinstance(seed, np.random.Generator):
        return seed
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed: expected an int or numpy.random.Generator, got {seed!r}")
    return np.random.default_rng(int(seed))


def simulate(
    sensors: SensorNetwork,
    targets: Sequence[ConstantVelocityTarget],
    scan_times: Sequence[ArrayLike],
    *,
    pd: float = 1.0,
    clutter_per_scan: int | None = None,
    clutter_rate: float | None = None,
    azimuth_window: Sequence[float] = (0.0, math.pi),
    elevation_window: Sequence[float] = (0.0, math.pi / 2),
    t0: float | None = None,
    platforms: SensorTrack | None = None,
    seed: Seed,
) -> Scenario:
    """Simulate detections and clutter of a sensor network.

    Each sensor at each of its scan times detects each target independently with
    probability ``pd`` and reports its angles plus zero-mean Gaussian noise with that
    sensor's stds (azimuth wrapped to (-pi, pi]); it also reports clutter drawn uniformly in
    the windows (bearing only for a 2-D network).

    Parameters
    ----------
    sensors : SensorNetwork
    targets : sequence of ConstantVelocityTarget
        Same dimension as the network.
    scan_times : sequence of array_like
        One 1-D array of scan times (s) per sensor.
    pd : float
        Detection probability in [0, 1].
    clutter_per_scan : int, optional
        Exact number of clutter reports per sensor per scan.
    clutter_rate : float, optional
        Poisson mean of clutter reports per sensor per scan (exclusive with the above).
    azimuth_window, elevation_window : (float, float)
        Clutter angle ranges, radians.
    t0 : float, optional
        Reference time of ``Scenario.true_states``; default the earliest scan time.
    platforms : SensorTrack, optional
        Moving sensors: each sensor with fixes in it observes from its interpolated position
        at each scan time (constant velocity: :meth:`SensorTrack.constant_velocity`; more
        fixes: waypoints), and the table carries those positions (``sensor_position``) for
        the methods. The others stay at the network's position.
    seed : int or numpy.random.Generator
        Required; the only source of randomness.

    Returns
    -------
    Scenario
        Measurements sorted by (time, sensor); within a scan the order is random so that
        no algorithm can exploit truth-ordered rows.

    Notes
    -----
    Noise is drawn for every (scan, target) pair whether or not it is detected, so runs that
    differ only in ``pd`` share their measurement noise (common random numbers).
    """
    if not isinstance(sensors, SensorNetwork):
        raise TypeError(f"sensors: expected a SensorNetwork, got {type(sensors).__name__}")
    targets = _check_targets(targets, sensors.ndim)
    times = _check_scan_times(scan_times, sensors.n_sensors)
    pd = as_float_scalar("pd", pd)
    if not 0.0 <= pd <= 1.0:
        raise ValueError(f"pd: must be in [0, 1], got {pd!r}")
    _check_clutter(clutter_per_scan, clutter_rate)
    az_win = as_interval("azimuth_window", azimuth_window)
    el_win = as_interval("elevation_window", elevation_window)
    rng = _check_seed(seed)
    if platforms is not None and not isinstance(platforms, SensorTrack):
        raise TypeError(f"platforms: expected a SensorTrack, got {type(platforms).__name__}")

    parts = [
        _sensor_reports(
            rng,
            sensors,
            j,
            times[j],
            targets,
            pd,
            _clutter_counts(rng, times[j].size, clutter_per_scan, clutter_rate),
            az_win,
            el_win,
            platforms,
        )
        for j in range(sensors.n_sensors)
    ]
    cols = [np.concatenate([p[c] for p in parts]) for c in range(5)]
    sensor, time, az, el, truth = cols
    # The random key shuffles rows within a (time, sensor) scan; lexsort's last key is primary.
    order = np.lexsort((rng.random(sensor.size), sensor, time))
    table = MeasurementTable.from_arrays(
        sensor[order],
        time[order],
        az[order],
        el[order] if sensors.ndim == 3 else None,
        truth=truth[order],
    )
    if platforms is not None:
        table = platforms.attach(table)
    if t0 is None:
        nonempty = [t for t in times if t.size]
        t0 = float(min(t.min() for t in nonempty)) if nonempty else 0.0
    return Scenario(sensors, targets, table, times, as_float_scalar("t0", t0, finite=True))


def _sensor_reports(
    rng: np.random.Generator,
    sensors: SensorNetwork,
    j: int,
    times: NDArray[np.float64],
    targets: list[ConstantVelocityTarget],
    pd: float,
    n_clutter: NDArray[np.int64],
    az_win: tuple[float, float],
    el_win: tuple[float, float],
    platforms: SensorTrack | None,
) -> list[NDArray[np.float64]]:
    """Target and clutter reports of sensor ``j``: [sensor, time, az, el, truth] columns."""
    k, n = times.size, len(targets)
    three_d = sensors.ndim == 3
    pos = np.zeros((k, n, 3))
    for i, tg in enumerate(targets):
        pos[:, i, : tg.ndim] = tg.position(times)
    # The sensor's position at each scan time: its platform's, or the network's.
    moving = platforms is not None and j in platforms.sensors
    where = platforms.position_at(j, times) if moving else sensors.position_at(j, times)  # type: ignore[union-attr]
    az_true, el_true = _true_angles(where[:, None, :], pos)
    detected = rng.random((k, n)) < pd
    az = wrap_angle(az_true + sensors.sigma_azimuth[j] * rng.standard_normal((k, n)))
    if three_d:
        el = el_true + sensors.sigma_elevation[j] * rng.standard_normal((k, n))
    else:
        el = np.full((k, n), np.nan)
    label = np.broadcast_to(np.arange(n), (k, n))
    scan_of = np.broadcast_to(np.arange(k)[:, None], (k, n))

    m = int(n_clutter.sum())
    c_scan = np.repeat(np.arange(k), n_clutter)
    c_az = wrap_angle(rng.uniform(az_win[0], az_win[1], m))
    c_el = rng.uniform(el_win[0], el_win[1], m) if three_d else np.full(m, np.nan)

    scan = np.concatenate([scan_of[detected], c_scan])
    return [
        np.full(scan.size, j, dtype=np.int64),
        times[scan],
        np.concatenate([az[detected], c_az]),
        np.concatenate([el[detected], c_el]),
        np.concatenate([label[detected], np.full(m, -1)]).astype(np.int64),
    ]


def _clutter_from_ratio(clutter_ratio: float, n_targets: int) -> int:
    ratio = as_float_scalar("clutter_ratio", clutter_ratio, finite=True)
    if ratio < 0:
        raise ValueError(f"clutter_ratio: must be >= 0, got {clutter_ratio!r}")
    # Rounded: clutter per scan must be a whole number of reports.
    return round(ratio * n_targets)


def _staggered_times(n_sensors: int, n_scans: int, scan_period: float, offset: float) -> list[NDArray[np.float64]]:
    """Sensor j scans at ``j * offset + k * scan_period``, k = 0..n_scans-1."""
    period = as_float_scalar("scan_period", scan_period, finite=True)
    if period <= 0:
        raise ValueError(f"scan_period: must be > 0, got {scan_period!r}")
    k = np.arange(as_int_scalar("n_scans", n_scans, minimum=1)) * period
    dt = as_float_scalar("offset", offset, finite=True)
    return [np.asarray(j * dt + k, dtype=np.float64) for j in range(n_sensors)]


def bearing_only_2d_scenario(
    seed: Seed,
    *,
    n_targets: int = 3,
    n_sensors: int = 3,
    pd: float = 1.0,
    clutter_ratio: float = 2.0,
    scan_period: float = 10.0,
    n_scans: int = 8,
    offset: float = 0.0,
    sigma: float = 5e-3,
    baseline: float = 30e3,
    speed_range: tuple[float, float] = (100.0, 250.0),
) -> Scenario:
    """A 2-D bearing-only constant-velocity scenario.

    ``n_sensors`` sensors evenly spaced on the x axis over ``baseline`` metres (centred on
    the origin; a single sensor sits at the origin). Targets start uniformly in
    x in [-10, 10] km, y in [20, 40] km with speed uniform in ``speed_range`` and uniform
    heading. Sensor j scans at ``j * offset + k * scan_period``. Clutter per sensor per scan
    is ``round(clutter_ratio * n_targets)`` bearings uniform in [0, pi]. The same ``seed``
    draws the targets and the measurements.

    Returns
    -------
    Scenario
    """
    n_t = as_int_scalar("n_targets", n_targets, minimum=1)
    n_s = as_int_scalar("n_sensors", n_sensors, minimum=1)
    rng = _check_seed(seed)
    xs = np.linspace(-baseline / 2, baseline / 2, n_s) if n_s > 1 else np.zeros(1)
    sensors = SensorNetwork.planar(np.column_stack([xs, np.zeros(n_s)]), sigma)
    lo, hi = as_interval("speed_range", speed_range)
    if lo < 0:
        raise ValueError(f"speed_range: speeds must be >= 0, got {tuple(speed_range)}")
    pos = np.column_stack([rng.uniform(-10e3, 10e3, n_t), rng.uniform(20e3, 40e3, n_t)])
    speed, heading = rng.uniform(lo, hi, n_t), rng.uniform(-math.pi, math.pi, n_t)
    vel = speed[:, None] * np.column_stack([np.cos(heading), np.sin(heading)])
    targets = [ConstantVelocityTarget(np.concatenate(pv)) for pv in zip(pos, vel, strict=True)]
    return simulate(
        sensors,
        targets,
        _staggered_times(n_s, n_scans, scan_period, offset),
        pd=pd,
        clutter_per_scan=_clutter_from_ratio(clutter_ratio, n_t),
        azimuth_window=(0.0, math.pi),
        t0=0.0,
        seed=rng,
    )
