"""One-scan bearing-only scenarios for static association (METHODS §2, EXPERIMENTS ``intensity``).

The paper gives no geometry; EXPERIMENTS.md fixes it: 2-D sensors at (−15, 0), (0, −5),
(15, 0) km, M targets uniform in x ∈ [−10, 10] km, y ∈ [20, 40] km, Pd = 0.95, P_FA = 0.05,
and the resolution ratio R = Δ/σθ with Δ the angle the square subtends at (0, −5) km divided
by M. Readings chosen here (printed by the experiment):

* S ≠ 3 sensors sit at ``x = linspace(−15, 15, S)`` km, ``y = −5 (1 − |x|/15)`` km, which is
  the paper geometry at S = 3.
* "Each reported bearing is false with probability P_FA": every sensor reports
  Poisson(P_FA/(1 − P_FA) · its expected detections) false bearings, so that on average a
  fraction P_FA of its reports are false; they are uniform over the bearing sector the square
  covers from that sensor.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .._params import Interval, validate
from ..data import MeasurementTable, SensorNetwork

SQUARE_X = (-10e3, 10e3)
SQUARE_Y = (20e3, 40e3)
REFERENCE_SENSOR = np.array([0.0, -5e3])


def sensor_positions(n_sensors: int) -> NDArray[np.float64]:
    """The paper layout at S = 3, generalised along the same shallow arc."""
    if n_sensors < 2:
        raise ValueError(f"n_sensors: need at least 2, got {n_sensors}")
    x = np.linspace(-15e3, 15e3, n_sensors)
    return np.column_stack([x, -5e3 * (1 - np.abs(x) / 15e3)])


def _corners() -> NDArray[np.float64]:
    return np.array([[x, y] for x in SQUARE_X for y in SQUARE_Y])


def sector(position: NDArray[np.float64]) -> tuple[float, float]:
    """Bearing interval (radians) that the surveillance square covers from ``position``."""
    rel = _corners() - position
    bearings = np.arctan2(rel[:, 1], rel[:, 0])
    return float(bearings.min()), float(bearings.max())


def sigma_for_ratio(ratio: float, n_targets: int) -> float:
    """σθ such that R = Δ/σθ, Δ = (angle the square subtends at (0, −5) km) / M."""
    lo, hi = sector(REFERENCE_SENSOR)
    return (hi - lo) / n_targets / ratio


@dataclass(frozen=True)
class StaticScan:
    """One simulated scan with its truth.

    Attributes
    ----------
    sensors : SensorNetwork
    measurements : MeasurementTable
        Bearings; ``truth`` holds the target index or −1 for a false bearing.
    targets : ndarray, shape (M, 2)
        True positions.
    true_tuples : ndarray of int, shape (M, S)
        Table row of each target's report per sensor, −1 where that sensor missed it.
    """

    sensors: SensorNetwork
    measurements: MeasurementTable
    targets: NDArray[np.float64]
    true_tuples: NDArray[np.int64]

    def observable(self) -> NDArray[np.bool_]:
        """Targets seen by at least two sensors: the ones an association can recover."""
        seen: NDArray[np.bool_] = (self.true_tuples >= 0).sum(axis=1) >= 2
        return seen


def _check_scan_arguments(
    n_targets: int, n_sensors: int, ratio: float, pd: float, p_false: float, sigma: float | None
) -> None:
    """ValueError/TypeError naming the argument, before any arithmetic divides by it."""
    validate(
        dict(n_targets=n_targets, n_sensors=n_sensors, ratio=ratio, pd=pd, p_false=p_false, sigma=sigma),
        {
            "n_targets": [Interval(int, 1, None)],
            "n_sensors": [Interval(int, 2, None)],
            "ratio": [Interval(float, 0.0, None, closed="neither")],
            "pd": [Interval(float, 0.0, 1.0, closed="right")],
            "p_false": [Interval(float, 0.0, 1.0, closed="left")],
            "sigma": [Interval(float, 0.0, None, closed="neither"), None],
        },
    )


def static_scan(
    seed: int | np.random.Generator,
    *,
    n_targets: int,
    n_sensors: int = 3,
    ratio: float = 15.0,
    pd: float = 0.95,
    p_false: float = 0.05,
    sigma: float | None = None,
) -> StaticScan:
    """Simulate one scan; ``sigma`` overrides the σθ implied by ``ratio``."""
    _check_scan_arguments(n_targets, n_sensors, ratio, pd, p_false, sigma)
    rng = np.random.default_rng(seed)
    positions = sensor_positions(n_sensors)
    sig = sigma_for_ratio(ratio, n_targets) if sigma is None else float(sigma)
    sensors = SensorNetwork.planar(positions, sig)
    targets = np.column_stack([rng.uniform(*SQUARE_X, n_targets), rng.uniform(*SQUARE_Y, n_targets)])
    columns: list[list[NDArray[np.float64]]] = [[], [], []]  # sensor, bearing, truth
    for s in range(n_sensors):
        rel = targets - positions[s]
        seen = rng.random(n_targets) < pd
        bearing = np.arctan2(rel[:, 1], rel[:, 0]) + sig * rng.standard_normal(n_targets)
        n_false = rng.poisson(p_false / (1 - p_false) * pd * n_targets)
        false = rng.uniform(*sector(positions[s]), n_false)
        order = rng.permutation(int(seen.sum()) + n_false)  # rows in random order within a sensor
        b = np.concatenate([bearing[seen], false])[order]
        t = np.concatenate([np.flatnonzero(seen), np.full(n_false, -1)])[order]
        columns[0].append(np.full(len(b), s))
        columns[1].append(b)
        columns[2].append(t)
    sensor, bearing, truth = (np.concatenate(c) for c in columns)
    table = MeasurementTable.from_arrays(sensor, np.zeros(len(sensor)), bearing, truth=truth)
    tuples = np.full((n_targets, n_sensors), -1, dtype=np.int64)
    rows = np.flatnonzero(truth >= 0)
    tuples[truth[rows], sensor[rows]] = rows
    return StaticScan(sensors, table, targets, tuples)
