"""A passive scene the papers did not tune: sensors on a ring, targets in a 3-D box.

The scale scenes of the papers put their sensors on one line and their targets at one
altitude; :func:`ring_scenario` puts the sensors around the targets at slightly irregular
angles and heights, with their own noise and their own scan clocks, and the targets anywhere in
a box, climbing or descending.
"""

from __future__ import annotations

import math

import numpy as np

from .._validation import as_float_scalar, as_int_scalar
from ..data import SensorNetwork
from .scenario import ConstantVelocityTarget, Scenario, Seed, _check_seed, simulate

__all__ = ["ring_scenario"]


def ring_scenario(
    seed: Seed,
    *,
    n_sensors: int = 3,
    n_targets: int = 20,
    pd: float = 0.9,
    clutter_ratio: float = 2.0,
    n_scans: int = 8,
    scan_period: float = 15.0,
    radius: float = 30e3,
    half_width: float = 20e3,
) -> Scenario:
    """3-D sensors on a ring around targets in a box, asynchronous, in clutter.

    Sensor j sits at angle ``2πj/n_sensors`` plus U[-0.2, 0.2] rad on a circle of ``radius``
    metres about the origin, at a height U[0, 500] m, with its own angle noise σ_j ~ U[3, 5]
    mrad (azimuth and elevation) and its own clock: it scans at ``o_j + k * scan_period``,
    ``o_j ~ U[0, scan_period)``, ``k = 0..n_scans-1``. Targets start uniformly in
    x, y ∈ [-half_width, half_width], z ∈ [0.5, 10] km, at speeds U[100, 300] m/s, any
    heading, climbing or descending at up to a tenth of their speed; t0 = 0. Each sensor
    detects each target with probability ``pd`` per scan and reports
    ``round(clutter_ratio * n_targets)`` clutter rays uniform over azimuth (-π, π] and
    elevation [0, π/2]. The same ``seed`` draws the scene and the measurements.

    Returns
    -------
    Scenario
    """
    n_s = as_int_scalar("n_sensors", n_sensors, minimum=1)
    n_t = as_int_scalar("n_targets", n_targets, minimum=1)
    ratio = as_float_scalar("clutter_ratio", clutter_ratio, finite=True)
    if ratio < 0:
        raise ValueError(f"clutter_ratio: must be >= 0, got {ratio:g}")
    k = as_int_scalar("n_scans", n_scans, minimum=1)
    period = as_float_scalar("scan_period", scan_period, finite=True)
    r = as_float_scalar("radius", radius, finite=True)
    half = as_float_scalar("half_width", half_width, finite=True)
    for name, value in (("scan_period", period), ("radius", r), ("half_width", half)):
        if value <= 0:
            raise ValueError(f"{name}: must be > 0, got {value:g}")
    rng = _check_seed(seed)
    angle = 2 * math.pi * np.arange(n_s) / n_s + rng.uniform(-0.2, 0.2, n_s)
    positions = np.column_stack([r * np.cos(angle), r * np.sin(angle), rng.uniform(0.0, 500.0, n_s)])
    sigma = rng.uniform(3e-3, 5e-3, n_s)
    sensors = SensorNetwork(positions, sigma, sigma)
    start = np.column_stack(
        [rng.uniform(-half, half, n_t), rng.uniform(-half, half, n_t), rng.uniform(500.0, 10e3, n_t)]
    )
    speed, heading = rng.uniform(100.0, 300.0, n_t), rng.uniform(-math.pi, math.pi, n_t)
    climb = rng.uniform(-0.1, 0.1, n_t)
    velocity = np.column_stack([speed * np.cos(heading), speed * np.sin(heading), speed * climb])
    targets = [ConstantVelocityTarget(np.concatenate([p, v]), t0=0.0) for p, v in zip(start, velocity, strict=True)]
    offsets = rng.uniform(0.0, period, n_s)
    times = [o + period * np.arange(k) for o in offsets]
    return simulate(
        sensors,
        targets,
        times,
        pd=pd,
        clutter_per_scan=round(ratio * n_t),
        azimuth_window=(-math.pi, math.pi),
        elevation_window=(0.0, math.pi / 2),
        t0=0.0,
        seed=rng,
    )
