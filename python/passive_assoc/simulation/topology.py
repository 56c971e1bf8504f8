"""The reference-topology paper's scenario (METHODS §4, EXPERIMENTS ``topology``).

EXPERIMENTS fixes: 8 radars on a ring of radius U[200, 260] km around the area's centre;
synchronous 10 s scans for 15 minutes; azimuth bias U(±B) per radar; azimuth noise std
U[0.5°, 1°] and range noise std U[500, 1000] m per radar; 5 scattered targets and 3 line-abreast
formations of 5 targets, 20 km spacing, 320–360 m/s; full coverage, or a partial coverage
that leaves some targets unseen by some radars. Readings chosen here:

* The centre is the origin. The radars sit at bearings ``φ + j·45°`` from it (one random
  ``φ`` per run), each at its own radius.
* Target states are referenced to the middle of the run: each scattered target and each
  formation's centre is uniform in the square ±:data:`AREA_HALF_WIDTH` around the centre at
  that time, with a uniform heading. A flight of at most 360 m/s × 450 s = 162 km either way
  then keeps the targets inside the ring for most of the run (at most ~245 km from the
  centre, a formation's wing at worst), crossing each other near the centre. A formation's
  five targets share one speed and heading.
* Partial coverage: every radar sees only :data:`PARTIAL_COVERAGE_RADIUS` = 300 km around
  itself, a little more than the ring's radius, so it misses the far side of the area. Over
  40 seeds about a fifth of the (radar, target, scan) triples are out of coverage, yet every
  target is seen by at least three radars at every scan (radar 0, the system picture in the
  experiment, covers ~80 %).
* Biases are ``B·u`` with ``u ~ U(−1, 1)`` drawn whatever ``B`` is, so runs at different
  bias levels with one seed share everything else.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from .._validation import as_float_scalar, as_int_scalar, readonly
from .radar import Radar, RadarMeasurements, line_abreast_formation, scattered_targets, simulate_radars, true_positions
from .scenario import ConstantVelocityTarget, Seed, _check_seed

__all__ = [
    "RadarScenario",
    "paper_topology_scenario",
    "ring_radar_scenario",
    "AREA_HALF_WIDTH",
    "PARTIAL_COVERAGE_RADIUS",
]

N_RADARS = 8
RING_RADIUS = (200e3, 260e3)  # m, EXPERIMENTS topology
SIGMA_AZIMUTH_DEG = (0.5, 1.0)  # METHODS §4
SIGMA_RANGE = (500.0, 1000.0)  # m, METHODS §4
N_SCATTERED, N_FORMATIONS, FORMATION_SIZE = 5, 3, 5
FORMATION_SPACING = 20e3  # m
SPEED_RANGE = (320.0, 360.0)  # m/s: "sonic speed"
#: Half-width (m) of the square around the centre that holds each scattered target and
#: each formation's centre at mid-run (the project's choice; the paper's figure is not in
#: the text).
AREA_HALF_WIDTH = 30e3
#: Coverage radius (m) of every radar in the partial-coverage setting (the project's choice).
PARTIAL_COVERAGE_RADIUS = 300e3


@dataclass(frozen=True, eq=False)
class RadarScenario:
    """A simulated radar network run with its truth.

    Attributes
    ----------
    radars : tuple of Radar
    targets : list of ConstantVelocityTarget
        Scattered targets first, then the formations' targets, formation by formation.
    scan_times : numpy.ndarray, shape (K,)
    measurements : RadarMeasurements
        Truth labels are indices into :attr:`targets`.
    true_positions : numpy.ndarray, shape (n_targets, K, 2)
        Where each target is at each scan, metres.
    true_biases : numpy.ndarray, shape (n_radars,)
        Each radar's azimuth bias, radians.
    formation : numpy.ndarray of int, shape (n_targets,)
        The formation a target flies in, or −1 for a scattered target.
    in_coverage : numpy.ndarray of bool, shape (n_radars, n_targets, K)
        Whether the radar can see the target at that scan.
    """

    radars: tuple[Radar, ...]
    targets: list[ConstantVelocityTarget]
    scan_times: NDArray[np.float64]
    measurements: RadarMeasurements
    true_positions: NDArray[np.float64]
    true_biases: NDArray[np.float64]
    formation: NDArray[np.int64]
    in_coverage: NDArray[np.bool_]


def _ring(rng: np.random.Generator, n: int, bias_deg: float, coverage_radius: float) -> tuple[Radar, ...]:
    """``n`` radars on the ring, at bearings ``φ + 2πj/n`` from the centre."""
    phase = rng.uniform(0.0, 2 * math.pi / n)
    bearing = phase + 2 * math.pi * np.arange(n) / n
    radius = rng.uniform(*RING_RADIUS, n)
    bias_deg_each = bias_deg * rng.uniform(-1.0, 1.0, n)
    sigma_azimuth_deg = rng.uniform(*SIGMA_AZIMUTH_DEG, n)
    sigma_range = rng.uniform(*SIGMA_RANGE, n)
    positions = radius[:, None] * np.column_stack([np.cos(bearing), np.sin(bearing)])
    return tuple(
        Radar.from_degrees(positions[j], sigma_range[j], sigma_azimuth_deg[j], bias_deg_each[j], coverage_radius)
        for j in range(n)
    )


def _radars(rng: np.random.Generator, bias_deg: float, coverage_radius: float) -> tuple[Radar, ...]:
    return _ring(rng, N_RADARS, bias_deg, coverage_radius)


def _targets(
    rng: np.random.Generator,
    t_mid: float,
    half_width: float = AREA_HALF_WIDTH,
    speed_range: tuple[float, float] = SPEED_RANGE,
) -> tuple[list[ConstantVelocityTarget], NDArray[np.int64]]:
    area = [[-half_width, half_width]] * 2
    targets = scattered_targets(N_SCATTERED, area, speed_range, rng, t0=t_mid)
    formation = [-1] * N_SCATTERED
    for f in range(N_FORMATIONS):
        centre = rng.uniform(-half_width, half_width, 2)
        heading, speed = rng.uniform(-math.pi, math.pi), rng.uniform(*speed_range)
        targets += line_abreast_formation(FORMATION_SIZE, centre, heading, FORMATION_SPACING, speed, t0=t_mid)
        formation += [f] * FORMATION_SIZE
    return targets, np.array(formation, dtype=np.int64)


def paper_topology_scenario(
    seed: Seed,
    *,
    bias_deg: float = 5.0,
    coverage: Literal["full", "partial"] = "full",
    n_scans: int = 90,
    scan_period: float = 10.0,
    pd: float = 1.0,
) -> RadarScenario:
    """The topology experiment: 8 biased radars, 5 scattered targets, 3 formations of 5.

    Parameters
    ----------
    seed : int or numpy.random.Generator
        Required; draws the radars, the targets and the noise, in that order.
    bias_deg : float
        B, degrees: each radar's azimuth bias is uniform in [−B, B] (EXPERIMENTS: 0, 1, 3, 5).
    coverage : {"full", "partial"}
        ``"full"``: every radar sees every target all the time. ``"partial"``: each radar
        sees :data:`PARTIAL_COVERAGE_RADIUS` around itself (see the module docstring).
    n_scans, scan_period : int, float
        90 scans of 10 s: 15 minutes (the paper's).
    pd : float
        Detection probability of a covered target (1 in the paper).

    Returns
    -------
    RadarScenario
        Scan times ``k · scan_period``, ``k = 0..n_scans−1``.
    """
    bias = as_float_scalar("bias_deg", bias_deg, finite=True)
    if bias < 0:
        raise ValueError(f"bias_deg: must be >= 0, got {bias_deg!r}")
    if coverage not in ("full", "partial"):
        raise ValueError(f"coverage: expected 'full' or 'partial', got {coverage!r}")
    n_scans = as_int_scalar("n_scans", n_scans, minimum=1)
    period = as_float_scalar("scan_period", scan_period, finite=True)
    if period <= 0:
        raise ValueError(f"scan_period: must be > 0, got {scan_period!r}")
    rng = _check_seed(seed)
    scan_times = np.arange(n_scans) * period
    radars = _radars(rng, bias, math.inf if coverage == "full" else PARTIAL_COVERAGE_RADIUS)
    targets, formation = _targets(rng, t_mid=float(scan_times[-1]) / 2)
    measurements = simulate_radars(radars, targets, scan_times, rng, pd=pd)
    positions = true_positions(targets, scan_times)
    return RadarScenario(
        radars=radars,
        targets=targets,
        scan_times=readonly(scan_times),
        measurements=measurements,
        true_positions=readonly(positions),
        true_biases=readonly(np.array([radar.azimuth_bias for radar in radars])),
        formation=readonly(formation),
        in_coverage=readonly(np.stack([radar.covers(positions) for radar in radars])),
    )


def ring_radar_scenario(
    seed: Seed,
    *,
    bias_deg: float = 5.0,
    n_radars: int = 8,
    coverage_radius: float = 300e3,
    area_half_width: float = 50e3,
    speed_range: tuple[float, float] = (150.0, 300.0),
    n_scans: int = 90,
    scan_period: float = 10.0,
    pd: float = 1.0,
) -> RadarScenario:
    """A track-to-track scene the topology defaults were not tuned on: a ring of radars that
    each see only part of a wide area, so that radar pairs share all, some or none of their
    targets, and targets enter and leave the pictures.

    ``n_radars`` radars sit on a ring of radius U[200, 260] km (as the paper's, with one
    random phase); each sees ``coverage_radius`` around itself. 5 scattered targets and 3
    line-abreast formations of 5 at 20 km spacing fly straight at ``speed_range``; at mid-run
    each scattered target and each formation's centre is uniform in the square
    ±``area_half_width`` around the ring's centre, with a uniform heading, so over the run
    they cross a good part of the ring (up to 300 m/s × 450 s = 135 km either way). Azimuth
    bias ``B·u``, ``u ~ U(−1, 1)`` per radar (drawn whatever ``bias_deg`` is, so runs at
    different levels share everything else); noise as the paper's (azimuth std U[0.5°, 1°],
    range std U[500, 1000] m per radar).

    Parameters
    ----------
    seed : int or numpy.random.Generator
        Required; draws the radars, the targets and the noise, in that order.
    bias_deg : float
        B, degrees.
    n_radars : int
        Radars on the ring, at least 2.
    coverage_radius : float
        How far every radar sees, metres (> 0; ``inf`` for everywhere).
    area_half_width : float
        Half-width of the square holding the targets at mid-run, metres (> 0).
    speed_range : (float, float)
        Target speeds, m/s.
    n_scans, scan_period, pd
        As :func:`paper_topology_scenario`'s.

    Returns
    -------
    RadarScenario
    """
    bias = as_float_scalar("bias_deg", bias_deg, finite=True)
    if bias < 0:
        raise ValueError(f"bias_deg: must be >= 0, got {bias_deg!r}")
    n_radars = as_int_scalar("n_radars", n_radars, minimum=2)
    coverage = as_float_scalar("coverage_radius", coverage_radius)
    if not coverage > 0:
        raise ValueError(f"coverage_radius: must be > 0 (inf for everywhere), got {coverage_radius!r}")
    half = as_float_scalar("area_half_width", area_half_width, finite=True)
    if half <= 0:
        raise ValueError(f"area_half_width: must be > 0, got {area_half_width!r}")
    n_scans = as_int_scalar("n_scans", n_scans, minimum=1)
    period = as_float_scalar("scan_period", scan_period, finite=True)
    if period <= 0:
        raise ValueError(f"scan_period: must be > 0, got {scan_period!r}")
    rng = _check_seed(seed)
    scan_times = np.arange(n_scans) * period
    radars = _ring(rng, n_radars, bias, coverage)
    targets, formation = _targets(rng, float(scan_times[-1]) / 2, half, speed_range)
    measurements = simulate_radars(radars, targets, scan_times, rng, pd=pd)
    positions = true_positions(targets, scan_times)
    return RadarScenario(
        radars=radars,
        targets=targets,
        scan_times=readonly(scan_times),
        measurements=measurements,
        true_positions=readonly(positions),
        true_biases=readonly(np.array([radar.azimuth_bias for radar in radars])),
        formation=readonly(formation),
        in_coverage=readonly(np.stack([radar.covers(positions) for radar in radars])),
    )
