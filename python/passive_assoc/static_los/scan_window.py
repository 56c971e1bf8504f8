"""Scans from real clocks (METHODS §2 takes a scan as reports of one instant).

Real sensors time-stamp with jitter, and sensors of one network report some tenths of a
second apart, so the reports of one scan seldom share a time exactly. The rule that groups
them, given a window ``w`` seconds:

    Sort the reports by time. A scan opens at the earliest report not yet in a scan and holds
    every report whose time is at most ``w`` after that opening time; the next report opens
    the next scan.

A scan therefore never spans more than ``w``, the grouping does not depend on the row order,
and two reports further apart than ``w`` are never in one scan. Its key is its opening time.
Choose ``w`` above the clock jitter and the sensors' offsets, and below the time between
scans.

The static methods take a scan's reports as simultaneous. Targets move while the reports of
one window come in: at speed ``v`` and range ``r`` a report ``Δt`` from the scan's middle sees
its target up to ``v·Δt/r`` radians away from where the others see it. Given the fastest
target ``v_max`` and the nearest range ``min_range``, :func:`motion_inflated` widens each
report's angle noise to ``√(σ² + (v_max·Δt/min_range)²)`` (its own σ, or its sensor's), so
the gates and costs allow that motion; without them nothing is widened.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .._warn import warn_at_caller
from ..data import MeasurementTable, SensorNetwork

__all__ = ["check_one_scan", "motion_inflated", "window_scans"]


def window_scans(time: NDArray[np.float64], window: float) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The scans' opening times and each report's scan index under the rule above.

    >>> keys, scan = window_scans(np.array([0.004, 10.0, -0.003, 10.011, 0.009]), 0.05)
    >>> keys.tolist(), scan.tolist()
    ([-0.003, 10.0], [0, 1, 0, 1, 0])
    """
    if not window >= 0.0:
        raise ValueError(f"scan_window: must be >= 0 seconds, got {window!r}")
    order = np.argsort(time, kind="stable")
    ordered = time[order]
    index = np.empty(len(time), dtype=np.int64)
    keys: list[float] = []
    start = 0
    while start < len(ordered):
        end = int(np.searchsorted(ordered, ordered[start] + window, side="right"))
        index[order[start:end]] = len(keys)
        keys.append(float(ordered[start]))
        start = end
    return np.array(keys, dtype=np.float64), index


def check_one_scan(measurements: MeasurementTable, scan_window: float | None) -> None:
    """What one static association needs of its table's times: within ``scan_window`` when
    one is declared (a ValueError otherwise), and a warning when none is and the times
    differ."""
    if not isinstance(measurements, MeasurementTable) or len(measurements) == 0:
        return  # the pair's own checks name the argument
    span = float(measurements.time.max() - measurements.time.min())
    if scan_window is None:
        if span > 0.0:
            n_times = len(np.unique(measurements.time))
            warn_at_caller(
                f"measurements: {n_times} distinct times over {span:g} s are associated as one scan; "
                "declare the clock's jitter with scan_window= (seconds), or split the table into scans "
                "(associate_scans groups them)"
            )
    elif span > scan_window:
        raise ValueError(
            f"measurements: times span {span:g} s, more than scan_window = {scan_window:g} s: not one scan; "
            "associate_scans splits a table into scans"
        )


def motion_inflated(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    scan: NDArray[np.int64],
    v_max: float,
    min_range: float,
) -> MeasurementTable:
    """``measurements`` with each report's angle noise widened for the targets' motion within
    its scan (module doc); ``scan`` is each row's scan index. Reports at their scan's middle
    time keep their noise."""
    n_scans = int(scan.max()) + 1 if len(scan) else 0
    first = np.full(n_scans, np.inf)
    last = np.full(n_scans, -np.inf)
    np.minimum.at(first, scan, measurements.time)
    np.maximum.at(last, scan, measurements.time)
    dt = np.abs(measurements.time - 0.5 * (first[scan] + last[scan]))
    extra = v_max * dt / min_range
    sigma_az, sigma_el = measurements.report_sigmas(sensors)
    columns = measurements.to_arrays()
    columns["sigma_azimuth"] = np.minimum(np.hypot(sigma_az, extra), np.pi)
    if sensors.ndim == 3:
        columns["sigma_elevation"] = np.minimum(np.hypot(sigma_el, extra), np.pi)
    return MeasurementTable.from_columns(columns, check_angle_unit=False)
