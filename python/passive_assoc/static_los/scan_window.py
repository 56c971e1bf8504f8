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
"""

from __future__ import annotations

import warnings

import numpy as np
from numpy.typing import NDArray

from ..data import MeasurementTable

__all__ = ["check_one_scan", "window_scans"]


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
            warnings.warn(
                f"measurements: {n_times} distinct times over {span:g} s are associated as one scan; "
                "declare the clock's jitter with scan_window= (seconds), or split the table into scans "
                "(associate_scans groups them)",
                UserWarning,
                stacklevel=3,
            )
    elif span > scan_window:
        raise ValueError(
            f"measurements: times span {span:g} s, more than scan_window = {scan_window:g} s: not one scan; "
            "associate_scans splits a table into scans"
        )
