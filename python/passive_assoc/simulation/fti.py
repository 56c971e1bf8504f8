"""The fuzzy-track-initiation paper's scenario (METHODS §1, EXPERIMENTS ``fti``)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from .._validation import readonly
from ..data import SensorNetwork
from .scenario import (
    ConstantVelocityTarget,
    Scenario,
    Seed,
    _clutter_from_ratio,
    _staggered_times,
    simulate,
)

__all__ = ["PAPER_FTI_TARGETS", "paper_fti_scenario"]

#: METHODS §1 Table 1: (x0, y0, z0, vx, vy, vz) in m and m/s at t0 = 0.
PAPER_FTI_TARGETS: NDArray[np.float64] = readonly(
    np.array(
        [
            [1340.0, 15000.0, 1000.0, 173.2, -100.0, 0.0],
            [1340.0, 5000.0, 1000.0, 173.2, 100.0, 0.0],
            [6000.0, 1000.0, 1000.0, 0.0, 200.0, 0.0],
            [1340.0, 16000.0, 1000.0, 173.2, -100.0, 0.0],
        ]
    )
)


def paper_fti_scenario(
    seed: Seed,
    *,
    pd: float = 1.0,
    clutter_ratio: float = 2.0,
    scan_period: float = 15.0,
    n_scans: int = 8,
    offset: float = 5.0,
    sigma: float = 5e-3,
) -> Scenario:
    """The fuzzy-track-initiation experiment of METHODS §1 / EXPERIMENTS ``fti``.

    Two 3-D sensors at (0, 0, 0) and (20 km, 0, 0) with ``sigma`` on both angles; the four
    targets of :data:`PAPER_FTI_TARGETS` with t0 = 0 (sensor 1's first sample); sensor 1
    scans at ``k * scan_period``, sensor 2 at ``offset + k * scan_period``,
    ``k = 0..n_scans-1``; per sensor and scan ``round(clutter_ratio * 4)`` clutter reports
    with azimuth U[0, pi] and elevation U[0, pi/2].

    Parameters
    ----------
    seed : int or numpy.random.Generator
    pd, clutter_ratio, scan_period, n_scans, offset, sigma
        See above; defaults are the paper's (T = 15 s fixed by EXPERIMENTS.md).

    Returns
    -------
    Scenario
    """
    sensors = SensorNetwork.spatial([[0.0, 0.0, 0.0], [20000.0, 0.0, 0.0]], sigma, sigma)
    targets = [ConstantVelocityTarget(s, t0=0.0) for s in PAPER_FTI_TARGETS]
    times = _staggered_times(2, n_scans, scan_period, offset)
    return simulate(  # t0 = 0 is sensor 1's first sample (EXPERIMENTS fti)
        sensors,
        targets,
        times,
        pd=pd,
        clutter_per_scan=_clutter_from_ratio(clutter_ratio, len(targets)),
        azimuth_window=(0.0, math.pi),
        elevation_window=(0.0, math.pi / 2),
        t0=0.0,
        seed=seed,
    )
