"""Planar radars with an azimuth bias, and what they report (METHODS §4, §5).

A radar at ``p`` measures each target's range and azimuth (METHODS §0: counter-clockwise from
+x, ``atan2(y − y_p, x − x_p)``) with zero-mean Gaussian noise, and its azimuth is off by a
fixed ``azimuth_bias``, so its whole picture is the truth rotated by the bias about the radar
(METHODS §4). Targets are the 2-D :class:`ConstantVelocityTarget` of :mod:`.scenario`; the
paper scenarios built on this module are in :mod:`.topology` and :mod:`.radar_esm`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, as_float_scalar, as_int_array, as_int_scalar, readonly, require_finite
from .scenario import ConstantVelocityTarget, Seed, _check_seed, wrap_angle

__all__ = [
    "Radar",
    "RadarMeasurements",
    "simulate_radars",
    "true_positions",
    "scattered_targets",
    "line_abreast_formation",
]


def _nonnegative(name: str, value: float) -> float:
    out = as_float_scalar(name, value, finite=True)
    if out < 0:
        raise ValueError(f"{name}: must be >= 0, got {value!r}")
    return out


@dataclass(frozen=True, eq=False)
class Radar:
    """A fixed 2-D radar.

    Parameters
    ----------
    position : array_like, shape (2,)
        Where the radar is, metres.
    sigma_range : float
        Range noise standard deviation, metres, >= 0 (0: noiseless).
    sigma_azimuth : float
        Azimuth noise standard deviation, radians, >= 0.
    azimuth_bias : float
        Added to every azimuth the radar reports, radians: its picture is rotated by this
        angle (counter-clockwise if positive) about :attr:`position`.
    coverage_radius : float
        The radar sees targets at most this far away, metres, > 0; ``inf`` (default) is
        everywhere.

    Notes
    -----
    Use :meth:`from_degrees` to give the angles in degrees.
    """

    position: NDArray[np.float64]
    sigma_range: float
    sigma_azimuth: float
    azimuth_bias: float = 0.0
    coverage_radius: float = math.inf

    def __post_init__(self) -> None:
        position = as_float_array("position", self.position, shape=(2,))
        require_finite("position", position)
        coverage = as_float_scalar("coverage_radius", self.coverage_radius)
        if not coverage > 0:
            raise ValueError(f"coverage_radius: must be > 0 (inf for everywhere), got {self.coverage_radius!r}")
        object.__setattr__(self, "position", readonly(position))
        object.__setattr__(self, "sigma_range", _nonnegative("sigma_range", self.sigma_range))
        object.__setattr__(self, "sigma_azimuth", _nonnegative("sigma_azimuth", self.sigma_azimuth))
        object.__setattr__(self, "azimuth_bias", as_float_scalar("azimuth_bias", self.azimuth_bias, finite=True))
        object.__setattr__(self, "coverage_radius", coverage)

    @classmethod
    def from_degrees(
        cls,
        position: ArrayLike,
        sigma_range: float,
        sigma_azimuth_deg: float,
        azimuth_bias_deg: float = 0.0,
        coverage_radius: float = math.inf,
    ) -> Radar:
        """A radar whose azimuth noise std and bias are given in degrees."""
        sigma_azimuth = math.radians(as_float_scalar("sigma_azimuth_deg", sigma_azimuth_deg, finite=True))
        bias = math.radians(as_float_scalar("azimuth_bias_deg", azimuth_bias_deg, finite=True))
        return cls(np.asarray(position, dtype=np.float64), sigma_range, sigma_azimuth, bias, coverage_radius)

    def covers(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether each point ``(..., 2)`` is within :attr:`coverage_radius`."""
        offsets = as_float_array("points", points) - self.position
        return np.asarray(np.hypot(offsets[..., 0], offsets[..., 1]) <= self.coverage_radius)


@dataclass(frozen=True, eq=False)
class RadarMeasurements:
    """Columnar radar reports, sorted by (time, radar), random order within a scan.

    Attributes
    ----------
    radar : numpy.ndarray of int, shape (N,)
        Index into :attr:`radars` of the reporting radar.
    time : numpy.ndarray, shape (N,)
        Scan time, seconds.
    range : numpy.ndarray, shape (N,)
        Measured range, metres: true range plus Gaussian noise (not clipped at 0).
    azimuth : numpy.ndarray, shape (N,)
        Measured azimuth, radians in (−π, π]: true azimuth + the radar's bias + noise.
    truth : numpy.ndarray of int, shape (N,)
        Hidden truth: the target's index. No algorithm may read it.
    radars : tuple of Radar
        The radars that made the reports.
    """

    radar: NDArray[np.int64]
    time: NDArray[np.float64]
    range: NDArray[np.float64]
    azimuth: NDArray[np.float64]
    truth: NDArray[np.int64]
    radars: tuple[Radar, ...]

    def __post_init__(self) -> None:
        for name in ("radar", "time", "range", "azimuth", "truth"):
            object.__setattr__(self, name, readonly(np.array(getattr(self, name))))
        object.__setattr__(self, "radars", tuple(self.radars))

    def __len__(self) -> int:
        return int(self.radar.shape[0])

    def select(self, indices: ArrayLike) -> RadarMeasurements:
        """The given rows (indices or a boolean mask), in the given order."""
        arr = np.asarray(indices)
        if arr.dtype.kind == "b" and arr.shape != (len(self),):
            raise ValueError(f"indices: boolean mask has shape {arr.shape}, expected ({len(self)},)")
        rows = arr if arr.dtype.kind == "b" else as_int_array("indices", arr, ndim=1)
        if rows.dtype.kind == "i" and ((rows < 0) | (rows >= len(self))).any():
            raise ValueError(f"indices: out of range for {len(self)} reports")
        return RadarMeasurements(
            self.radar[rows], self.time[rows], self.range[rows], self.azimuth[rows], self.truth[rows], self.radars
        )

    def _radar_positions(self) -> NDArray[np.float64]:
        positions = np.array([radar.position for radar in self.radars]).reshape(-1, 2)
        return positions[self.radar]

    def to_cartesian(self) -> NDArray[np.float64]:
        """Each report's position ``(N, 2)`` in its radar's own (biased) frame:
        ``radar.position + range · (cos azimuth, sin azimuth)``."""
        direction = np.column_stack([np.cos(self.azimuth), np.sin(self.azimuth)])
        offsets: NDArray[np.float64] = self.range[:, None] * direction
        return self._radar_positions() + offsets

    def cartesian_covariance(self) -> NDArray[np.float64]:
        """The noise covariance ``(N, 2, 2)`` of :meth:`to_cartesian`, to first order:
        ``J diag(σr², σaz²) Jᵀ`` with J the Jacobian of the polar-to-Cartesian map at the
        measured (range, azimuth). The bias is not noise and is not in it."""
        sigma_r = np.array([radar.sigma_range for radar in self.radars])[self.radar]
        sigma_az = np.array([radar.sigma_azimuth for radar in self.radars])[self.radar]
        c, s = np.cos(self.azimuth), np.sin(self.azimuth)
        jacobian = np.stack([np.column_stack([c, -self.range * s]), np.column_stack([s, self.range * c])], axis=1)
        noise = np.zeros((len(self), 2, 2))
        noise[:, 0, 0], noise[:, 1, 1] = sigma_r**2, sigma_az**2
        return np.asarray(jacobian @ noise @ jacobian.transpose(0, 2, 1))


def true_positions(targets: Sequence[ConstantVelocityTarget], times: ArrayLike) -> NDArray[np.float64]:
    """Positions ``(n_targets, n_times, ndim)`` of the targets at the times, metres."""
    t = as_float_array("times", times, ndim=1)
    if not targets:
        return np.zeros((0, t.size, 2))
    return np.asarray(np.stack([target.position(t) for target in targets]), dtype=np.float64)


def _check_planar_targets(targets: Sequence[ConstantVelocityTarget]) -> list[ConstantVelocityTarget]:
    out = list(targets)
    for k, target in enumerate(out):
        if not isinstance(target, ConstantVelocityTarget):
            raise TypeError(f"targets[{k}]: expected a ConstantVelocityTarget, got {target!r}")
        if target.ndim != 2:
            raise ValueError(f"targets[{k}]: is {target.ndim}-D; radars here are 2-D")
    return out


def _check_radars(radars: Sequence[Radar]) -> tuple[Radar, ...]:
    out = tuple(radars)
    if not out:
        raise ValueError("radars: need at least 1 radar, got 0")
    for j, radar in enumerate(out):
        if not isinstance(radar, Radar):
            raise TypeError(f"radars[{j}]: expected a Radar, got {radar!r}")
    return out


def _check_scan_times(scan_times: ArrayLike) -> NDArray[np.float64]:
    times = as_float_array("scan_times", scan_times, ndim=1)
    require_finite("scan_times", times)
    if (times[1:] <= times[:-1]).any():
        i = int(np.flatnonzero(times[1:] <= times[:-1])[0]) + 1
        raise ValueError(f"scan_times[{i}] = {float(times[i])!r}; scan times must increase strictly")
    return times


def simulate_radars(
    radars: Sequence[Radar],
    targets: Sequence[ConstantVelocityTarget],
    scan_times: ArrayLike,
    seed: Seed,
    *,
    pd: float = 1.0,
) -> RadarMeasurements:
    """What each radar reports at each (synchronous) scan.

    At every scan time each radar detects each target inside its coverage independently
    with probability ``pd``, and reports range + N(0, σr²) and azimuth + bias + N(0, σaz²)
    (wrapped to (−π, π]). No clutter.

    Parameters
    ----------
    radars : sequence of Radar
    targets : sequence of 2-D ConstantVelocityTarget
    scan_times : array_like, shape (K,)
        Common scan times, seconds, strictly increasing.
    seed : int or numpy.random.Generator
        Required; the only source of randomness.
    pd : float
        Detection probability in [0, 1].

    Returns
    -------
    RadarMeasurements
        Sorted by (time, radar); within a scan the order is random, so that no algorithm can
        exploit truth-ordered rows.

    Notes
    -----
    Noise is drawn for every (radar, scan, target) whether or not it is detected or covered,
    so runs that differ only in ``pd`` or the coverage share their noise.
    """
    radars = _check_radars(radars)
    targets = _check_planar_targets(targets)
    times = _check_scan_times(scan_times)
    pd = as_float_scalar("pd", pd)
    if not 0.0 <= pd <= 1.0:
        raise ValueError(f"pd: must be in [0, 1], got {pd!r}")
    rng = _check_seed(seed)
    truth_xy = true_positions(targets, times)  # (n, k, 2)
    parts = [_radar_reports(rng, j, radar, truth_xy, times, pd) for j, radar in enumerate(radars)]
    radar, time, ranges, azimuth, truth = (np.concatenate([p[c] for p in parts]) for c in range(5))
    # The random key shuffles rows within a (time, radar) scan; lexsort's last key is primary.
    order = np.lexsort((rng.random(radar.size), radar, time))
    return RadarMeasurements(
        radar[order].astype(np.int64),
        time[order],
        ranges[order],
        azimuth[order],
        truth[order].astype(np.int64),
        radars,
    )


def _radar_reports(
    rng: np.random.Generator,
    index: int,
    radar: Radar,
    truth_xy: NDArray[np.float64],
    times: NDArray[np.float64],
    pd: float,
) -> list[NDArray[np.float64]]:
    """[radar, time, range, azimuth, truth] columns of one radar's detections."""
    n, k = truth_xy.shape[:2]
    offsets = truth_xy - radar.position
    true_range = np.hypot(offsets[..., 0], offsets[..., 1])
    true_azimuth = np.arctan2(offsets[..., 1], offsets[..., 0])
    detected = (rng.random((n, k)) < pd) & (true_range <= radar.coverage_radius)
    measured_range = true_range + radar.sigma_range * rng.standard_normal((n, k))
    measured_azimuth = wrap_angle(true_azimuth + radar.azimuth_bias + radar.sigma_azimuth * rng.standard_normal((n, k)))
    target, scan = np.nonzero(detected)
    return [
        np.full(target.size, index, dtype=np.float64),
        times[scan],
        measured_range[target, scan],
        measured_azimuth[target, scan],
        target.astype(np.float64),
    ]


def scattered_targets(
    n: int,
    area: ArrayLike,
    speed_range: ArrayLike,
    rng: Seed,
    *,
    t0: float = 0.0,
) -> list[ConstantVelocityTarget]:
    """``n`` independent 2-D targets: position at ``t0`` uniform in ``area``
    (``[[x_min, x_max], [y_min, y_max]]``, metres), speed uniform in ``speed_range`` (m/s),
    heading uniform in (−π, π]."""
    n = as_int_scalar("n", n, minimum=0)
    box = as_float_array("area", area, shape=(2, 2))
    require_finite("area", box)
    if not (box[:, 0] < box[:, 1]).all():
        raise ValueError(f"area: expected [[x_min, x_max], [y_min, y_max]] with min < max, got {box.tolist()}")
    low, high = _speeds(speed_range)
    gen = _check_seed(rng)
    position = gen.uniform(box[:, 0], box[:, 1], (n, 2))
    speed, heading = gen.uniform(low, high, n), gen.uniform(-math.pi, math.pi, n)
    velocity = speed[:, None] * np.column_stack([np.cos(heading), np.sin(heading)])
    return [ConstantVelocityTarget(np.concatenate(pv), t0=t0) for pv in zip(position, velocity, strict=True)]


def _speeds(speed_range: ArrayLike) -> tuple[float, float]:
    low, high = (float(v) for v in as_float_array("speed_range", speed_range, shape=(2,)))
    if not 0 <= low <= high < math.inf:
        raise ValueError(f"speed_range: expected finite (low, high) with 0 <= low <= high, got {(low, high)}")
    return low, high


def line_abreast_formation(
    n: int,
    centre: ArrayLike,
    heading: float,
    spacing: float,
    speed: float,
    *,
    t0: float = 0.0,
) -> list[ConstantVelocityTarget]:
    """``n`` targets flying side by side: at ``t0`` they sit on the line through ``centre``
    perpendicular to ``heading`` (radians, counter-clockwise from +x), ``spacing`` metres
    apart and centred on it, all with velocity ``speed · (cos heading, sin heading)``.
    Targets are ordered from the left wing to the right wing."""
    n = as_int_scalar("n", n, minimum=1)
    middle = as_float_array("centre", centre, shape=(2,))
    require_finite("centre", middle)
    h = as_float_scalar("heading", heading, finite=True)
    gap, v = _nonnegative("spacing", spacing), _nonnegative("speed", speed)
    left = np.array([-math.sin(h), math.cos(h)])  # the heading turned +90°
    offsets = ((n - 1) / 2 - np.arange(n))[:, None] * gap * left
    velocity = v * np.array([math.cos(h), math.sin(h)])
    return [ConstantVelocityTarget(np.concatenate([middle + offset, velocity]), t0=t0) for offset in offsets]
