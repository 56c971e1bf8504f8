"""The track score: how much likelier a track's measurements are from one target than from
clutter (a project extension; docs/methods.md §1, *Track score*).

For track k with fitted state X̂ and rows R_k, and each sensor j with S_j scans in the window,
clutter density λ_j per scan and unit of angle (per radian of azimuth in 2-D, per square
radian of azimuth × elevation in 3-D) and noise σ_j:

    score_k = Σ_j [ d_kj · (ln Pd − ln λ_j − ln g_j) + (S_j − d_kj) · ln(1 − Pd) ] − χ²_k / 2

where d_kj is the number of the track's rows from sensor j, g_j the normalising constant of
sensor j's angle noise (√(2π)·σ in 2-D, 2π·σ_az·σ_el in 3-D), and χ²_k the final fit's sum of
squared normalised residuals. It is the log-likelihood ratio of two explanations of the
track's rows: one target at X̂, detected with probability Pd in each scan of each sensor and
measured with the sensors' noise, against no target, every row clutter (Blackman and Popoli's
track score, with the state at its fit). Above 0 the target explanation is the likelier.

The density λ_j is estimated from the data: the rows of sensor j that no track holds, per scan,
over the angles the sensor reported in (the arc of azimuth its rows span, the shortest that
holds them all, times their elevation range in 3-D). With no such row it is taken as one.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..data import MeasurementTable, SensorNetwork

#: The default ``min_score`` of :class:`FuzzyTrackInitiator`: no true track scored below it on
#: the calibration scenes (docs/methods.md §1, *Track score*).
MIN_SCORE = 20.0

__all__ = ["track_scores"]


def track_scores(
    labels: NDArray[np.int64],
    chi2: NDArray[np.float64],
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    pd: float,
) -> NDArray[np.float64]:
    """The score (module doc) of each track, for ``labels`` (track index per row, -1 clutter)
    and the tracks' fit ``chi2``; ``pd`` in (0, 1)."""
    n_tracks = len(chi2)
    sensor = np.asarray(measurements.sensor, dtype=np.int64)
    n_sensors = sensors.n_sensors
    planar = sensors.ndim == 2
    score = -0.5 * np.asarray(chi2, dtype=float)
    hit, miss = math.log(pd), math.log1p(-pd)
    for j in range(n_sensors):
        mine = sensor == j
        if not mine.any():
            continue
        times = measurements.time[mine]
        n_scans = len(np.unique(times))
        free = labels[mine] < 0
        area = _azimuth_arc(measurements.azimuth[mine])
        sigma_az = float(sensors.sigma_azimuth[j])
        if planar:
            norm = math.sqrt(2.0 * math.pi) * sigma_az
        else:
            elevation = measurements.elevation[mine]
            area *= max(float(elevation.max() - elevation.min()), 0.0)
            norm = 2.0 * math.pi * sigma_az * float(sensors.sigma_elevation[j])
        # Fewer than one free row, or angles with no extent (one row), still give a density.
        area = max(area, norm)
        density = max(int(free.sum()), 1) / (n_scans * area)
        per_row = hit - math.log(density) - math.log(norm)
        held = labels[mine]
        detected = np.bincount(held[held >= 0], minlength=n_tracks)[:n_tracks]
        missed = np.clip(n_scans - detected, 0, None)
        score += detected * per_row + missed * miss
        # A report with its own noise: its own normalisation in place of the sensor's.
        own_az, own_el = measurements.report_sigmas(sensors)
        ratio = own_az[mine] / sigma_az
        if not planar:
            ratio = ratio * own_el[mine] / float(sensors.sigma_elevation[j])
        taken = held >= 0
        score -= np.bincount(held[taken], weights=np.log(ratio[taken]), minlength=n_tracks)[:n_tracks]
    return score


def _azimuth_arc(azimuth: NDArray[np.float64]) -> float:
    """The shortest arc (radians) that holds every azimuth: 2π less the largest gap."""
    wrapped = np.sort(np.mod(azimuth, 2.0 * math.pi))
    if len(wrapped) < 2:
        return 0.0
    gaps = np.diff(np.concatenate([wrapped, wrapped[:1] + 2.0 * math.pi]))
    return float(2.0 * math.pi - gaps.max())
