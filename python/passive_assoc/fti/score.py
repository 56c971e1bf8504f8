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
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..data import MeasurementTable, SensorNetwork

#: The default ``min_score`` of :class:`FuzzyTrackInitiator`: no true track scored below it on
#: the calibration scenes (docs/methods.md §1, *Track score*).
MIN_SCORE = 20.0

__all__ = ["ScoreTerms", "track_scores"]


def track_scores(
    labels: NDArray[np.int64],
    chi2: NDArray[np.float64],
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    pd: float,
) -> NDArray[np.float64]:
    """The score (module doc) of each track, for ``labels`` (track index per row, -1 clutter)
    and the tracks' fit ``chi2``; ``pd`` in (0, 1)."""
    return ScoreTerms.of(labels, measurements, sensors, pd).scores(labels, chi2)


@dataclass(frozen=True)
class ScoreTerms:
    """The score's terms at one estimate of the clutter densities: what a row adds when a
    track holds it (``per_row``, per row of the table) and what each of a sensor's scans the
    track misses costs (``miss``, with ``n_scans`` scans per sensor). The densities follow the
    rows no track holds, so scores from one ``ScoreTerms`` compare tracks of different
    partitions of the same table (:mod:`passive_assoc.fti.regroup`)."""

    sensor: NDArray[np.int64]
    per_row: NDArray[np.float64]
    n_scans: NDArray[np.int64]
    miss: float

    @classmethod
    def of(
        cls, labels: NDArray[np.int64], measurements: MeasurementTable, sensors: SensorNetwork, pd: float
    ) -> ScoreTerms:
        """The terms with each sensor's density from the rows ``labels`` leaves free (-1)."""
        sensor = np.asarray(measurements.sensor, dtype=np.int64)
        planar = sensors.ndim == 2
        per_row = np.zeros(len(sensor))
        n_scans = np.zeros(sensors.n_sensors, dtype=np.int64)
        hit = math.log(pd)
        own_az, own_el = measurements.report_sigmas(sensors)
        for j in range(sensors.n_sensors):
            mine = sensor == j
            if not mine.any():
                continue
            n_scans[j] = len(np.unique(measurements.time[mine]))
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
            density = max(int(free.sum()), 1) / (n_scans[j] * area)
            # A report with its own noise: its own normalisation in place of the sensor's.
            ratio = own_az[mine] / sigma_az
            if not planar:
                ratio = ratio * own_el[mine] / float(sensors.sigma_elevation[j])
            per_row[mine] = hit - math.log(density) - math.log(norm) - np.log(ratio)
        return cls(sensor, per_row, n_scans, math.log1p(-pd))

    def scores(self, labels: NDArray[np.int64], chi2: NDArray[np.float64]) -> NDArray[np.float64]:
        """The score of each track of ``labels`` (track index per row, -1 free) with fit ``chi2``."""
        n_tracks = len(chi2)
        taken = labels >= 0
        score = -0.5 * np.asarray(chi2, dtype=float)
        score += np.bincount(labels[taken], weights=self.per_row[taken], minlength=n_tracks)[:n_tracks]
        n_sensors = len(self.n_scans)
        detected = np.zeros((n_tracks, n_sensors), dtype=np.int64)
        np.add.at(detected, (labels[taken], self.sensor[taken]), 1)
        missed = np.clip(self.n_scans - detected, 0, None)
        # A sensor with no row in the table has no scan: nothing to miss.
        out: NDArray[np.float64] = score + self.miss * missed.sum(axis=1)
        return out

    def score(self, rows: NDArray[np.int64], chi2: float) -> float:
        """The score of one track holding ``rows`` with fit ``chi2``."""
        detected = np.bincount(self.sensor[rows], minlength=len(self.n_scans))
        missed = np.clip(self.n_scans - detected, 0, None)
        return float(self.per_row[rows].sum() + self.miss * missed.sum() - 0.5 * chi2)


def _azimuth_arc(azimuth: NDArray[np.float64]) -> float:
    """The shortest arc (radians) that holds every azimuth: 2π less the largest gap."""
    wrapped = np.sort(np.mod(azimuth, 2.0 * math.pi))
    if len(wrapped) < 2:
        return 0.0
    gaps = np.diff(np.concatenate([wrapped, wrapped[:1] + 2.0 * math.pi]))
    return float(2.0 * math.pi - gaps.max())
