"""The wavelet paper's radar/ESM scenario (METHODS §5, EXPERIMENTS ``wavelet``).

Ten maneuvering targets on the x axis over 30 scans of 1 s, with piecewise-constant
accelerations (:data:`PAPER_WAVELET_TARGETS`), seen by two sensors — a radar (source 0) and
an ESM (source 1) — that each report a noisy position per target per scan, already grouped
into tracks. Units are SI throughout: positions in metres, so EXPERIMENTS' noise variance of
0.5 km² is ``noise_variance = 0.5e6`` m² (std ≈ 707 m) per axis. Readings chosen here:

* Scan k (1-based) is at ``(k − 1)·scan_period``; the table's acceleration for scan k's
  phase holds from scan k to scan k + 1, so the true acceleration *at* scan k is the table's
  and positions and velocities follow exactly (``x += v·T + a·T²/2``, ``v += a·T``).
* Initial positions are uniform in [0, 20] km (EXPERIMENTS); false tracks ("clutter",
  EXPERIMENTS' reading) are constant-acceleration tracks over the same 30 scans, with
  initial position in the same interval, initial velocity uniform in [−310, 610] m/s and
  acceleration uniform in [−80, 50] m/s² — the ranges the paper's targets span, so a false
  track moves like a target. Each sensor has its own ``n_clutter`` false tracks.
* Track ids are a fresh random permutation per sensor, so an id says nothing of the truth
  (METHODS §5: a tie-break by index would leak it).
* ``ndim = 2`` (not the paper's): each target, and each false track, flies along its own
  uniformly random direction; the table's speeds and accelerations are along it, initial
  positions are uniform in the [0, 20] km square, and the noise is per axis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .._validation import as_float_scalar, as_int_scalar, readonly
from ..data import TrackTable
from .scenario import Seed, _check_seed

__all__ = ["PAPER_WAVELET_TARGETS", "PAPER_WAVELET_PHASES", "RadarEsmScenario", "paper_wavelet_scenario"]

#: METHODS §5 Table 1, one row per target T1–T10: initial velocity v0 (m/s), then the
#: acceleration (m/s²) in scans 1–5, 6–20 and 21–30.
PAPER_WAVELET_TARGETS: NDArray[np.float64] = readonly(
    np.array(
        [
            [220.0, 0.0, 10.0, -30.0],
            [400.0, 0.0, 15.0, -50.0],
            [-150.0, 0.0, 20.0, -40.0],
            [450.0, 0.0, -35.0, 40.0],
            [305.0, 0.0, 40.0, -20.0],
            [550.0, 0.0, 20.0, -80.0],
            [610.0, 0.0, -10.0, 30.0],
            [-240.0, 0.0, -15.0, 45.0],
            [460.0, 0.0, 50.0, -30.0],
            [-310.0, 0.0, -25.0, 30.0],
        ]
    )
)
#: Number of scans in each acceleration phase of :data:`PAPER_WAVELET_TARGETS` (1–5, 6–20, 21–30).
PAPER_WAVELET_PHASES = (5, 15, 10)
INITIAL_POSITION_RANGE = (0.0, 20e3)  # m, EXPERIMENTS wavelet
CLUTTER_VELOCITY_RANGE = (-310.0, 610.0)  # m/s: the table's v0 span
CLUTTER_ACCELERATION_RANGE = (-80.0, 50.0)  # m/s²: the table's acceleration span
SOURCES = ("radar", "esm")


@dataclass(frozen=True, eq=False)
class RadarEsmScenario:
    """A simulated radar/ESM run with its truth.

    Attributes
    ----------
    scan_times : numpy.ndarray, shape (K,)
    true_position, true_velocity, true_acceleration : numpy.ndarray, shape (n_targets, K, ndim)
        Each target's state at each scan (m, m/s, m/s²); the acceleration is the one that
        holds from that scan to the next.
    measurements : TrackTable
        Noisy positions only: source 0 the radar, 1 the ESM; ``covariance`` the measurement
        noise ``noise_variance · I``; ``truth`` the target index or −1 for a false track.
    noise_variance : float
        Position noise variance per axis, m², both sensors.
    """

    scan_times: NDArray[np.float64]
    true_position: NDArray[np.float64]
    true_velocity: NDArray[np.float64]
    true_acceleration: NDArray[np.float64]
    measurements: TrackTable
    noise_variance: float

    @property
    def ndim(self) -> int:
        """Number of spatial axes, 1 or 2."""
        return int(self.true_position.shape[2])


def _phase_accelerations(table: NDArray[np.float64]) -> NDArray[np.float64]:
    """Acceleration ``(n_targets, K)`` of each target from each scan to the next."""
    return np.repeat(table[:, 1:], PAPER_WAVELET_PHASES, axis=1)


def _integrate(
    x0: NDArray[np.float64], v0: NDArray[np.float64], accel: NDArray[np.float64], period: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Exact positions and velocities ``(n, K)`` under accelerations held between scans."""
    k = accel.shape[1]
    position, velocity = np.empty((x0.size, k)), np.empty((x0.size, k))
    position[:, 0], velocity[:, 0] = x0, v0
    for j in range(1, k):
        a = accel[:, j - 1]
        position[:, j] = position[:, j - 1] + velocity[:, j - 1] * period + 0.5 * a * period**2
        velocity[:, j] = velocity[:, j - 1] + a * period
    return position, velocity


def _directions(rng: np.random.Generator, n: int, ndim: int) -> NDArray[np.float64]:
    if ndim == 1:
        return np.ones((n, 1))
    heading = rng.uniform(-np.pi, np.pi, n)
    return np.column_stack([np.cos(heading), np.sin(heading)])


def _trajectories(
    rng: np.random.Generator, speed_table: NDArray[np.float64], ndim: int, period: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Positions, velocities, accelerations ``(n, K, ndim)`` of tracks along random directions."""
    n = speed_table.shape[0]
    start = rng.uniform(*INITIAL_POSITION_RANGE, (n, ndim))
    direction = _directions(rng, n, ndim)
    accel = _phase_accelerations(speed_table)
    along, speed = _integrate(np.zeros(n), speed_table[:, 0], accel, period)
    u = direction[:, None, :]
    return start[:, None, :] + along[..., None] * u, speed[..., None] * u, accel[..., None] * u


def _clutter_table(rng: np.random.Generator, n_clutter: int) -> NDArray[np.float64]:
    """Rows like :data:`PAPER_WAVELET_TARGETS` for false tracks: one acceleration throughout."""
    v0 = rng.uniform(*CLUTTER_VELOCITY_RANGE, n_clutter)
    a = rng.uniform(*CLUTTER_ACCELERATION_RANGE, n_clutter)
    return np.column_stack([v0, a, a, a])


def _sensor_tracks(
    rng: np.random.Generator,
    source: int,
    positions: NDArray[np.float64],
    truth: NDArray[np.int64],
    scan_times: NDArray[np.float64],
    noise_variance: float,
) -> dict[str, NDArray[np.float64] | NDArray[np.int64]]:
    """One sensor's noisy position reports of ``positions (n, K, ndim)``, ids shuffled."""
    n, k, ndim = positions.shape
    noisy = positions + np.sqrt(noise_variance) * rng.standard_normal(positions.shape)
    track_id = rng.permutation(n)
    return {
        "source": np.full(n * k, source, dtype=np.int64),
        "track": np.repeat(track_id, k),
        "time": np.tile(scan_times, n),
        "position": noisy.reshape(n * k, ndim),
        "covariance": np.broadcast_to(noise_variance * np.eye(ndim), (n * k, ndim, ndim)),
        "truth": np.repeat(truth, k),
    }


def paper_wavelet_scenario(
    seed: Seed,
    *,
    n_clutter: int = 0,
    ndim: int = 1,
    scan_period: float = 1.0,
    noise_variance: float = 0.5e6,
) -> RadarEsmScenario:
    """The wavelet experiment: the paper's 10 targets seen by a radar and an ESM.

    Parameters
    ----------
    seed : int or numpy.random.Generator
        Required; draws the targets, then the false tracks, then each sensor's noise and ids.
    n_clutter : int
        False tracks per sensor (EXPERIMENTS sweeps 0, 1, 2, 5).
    ndim : {1, 2}
        1 is the paper's x axis; 2 gives each track a random direction (module docstring).
    scan_period : float
        Seconds between the 30 scans (1 in the paper).
    noise_variance : float
        Position noise variance per axis, **m²**; the default 0.5e6 m² is EXPERIMENTS'
        0.5 km².

    Returns
    -------
    RadarEsmScenario
    """
    n_clutter = as_int_scalar("n_clutter", n_clutter, minimum=0)
    ndim = as_int_scalar("ndim", ndim, minimum=1)
    if ndim > 2:
        raise ValueError(f"ndim: expected 1 (the paper's x axis) or 2, got {ndim}")
    period = as_float_scalar("scan_period", scan_period, finite=True)
    variance = as_float_scalar("noise_variance", noise_variance, finite=True)
    if period <= 0:
        raise ValueError(f"scan_period: must be > 0, got {scan_period!r}")
    if variance < 0:
        raise ValueError(f"noise_variance: must be >= 0, got {noise_variance!r}")
    rng = _check_seed(seed)
    scan_times = np.asarray(np.arange(sum(PAPER_WAVELET_PHASES)) * period, dtype=np.float64)
    position, velocity, acceleration = _trajectories(rng, PAPER_WAVELET_TARGETS, ndim, period)
    n_targets = position.shape[0]
    parts = []
    for source in range(len(SOURCES)):
        clutter, _, _ = _trajectories(rng, _clutter_table(rng, n_clutter), ndim, period)
        tracks = np.concatenate([position, clutter])
        truth = np.concatenate([np.arange(n_targets), np.full(n_clutter, -1)])
        parts.append(_sensor_tracks(rng, source, tracks, truth, scan_times, variance))
    columns = {name: np.concatenate([part[name] for part in parts]) for name in parts[0]}
    return RadarEsmScenario(
        scan_times=readonly(scan_times),
        true_position=readonly(position),
        true_velocity=readonly(velocity),
        true_acceleration=readonly(acceleration),
        measurements=TrackTable.from_arrays(**columns, sort=True),
        noise_variance=variance,
    )
