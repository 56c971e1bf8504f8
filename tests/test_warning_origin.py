"""Every warning the package gives points at the caller's line, whichever of the package's
paths it came through (a method behind the argument checker, a one-line convenience, a reader's
helper): the test file here, never a file of the package."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc import MeasurementTable, SensorNetwork
from passive_assoc.simulation import static_scan


def _ring() -> pa.Scenario:
    return pa.ring_scenario(1, n_targets=8)


def _limit_by_method(_: Path) -> object:
    scenario = _ring()
    return pa.FuzzyTrackInitiator(max_candidates=40).initiate(scenario.measurements, scenario.sensors, progress=False)


def _limit_by_function(_: Path) -> object:
    scenario = _ring()
    return pa.initiate_tracks(scenario.measurements, scenario.sensors, progress=False, max_candidates=40)


def _sensor_file(tmp_path: Path) -> object:
    path = tmp_path / "sites.csv"
    path.write_text("name, sensor, x, y, sigma_azimuth_deg\nnorth, 0, 0, 5000, 0.2\nsouth, 1, 0, -5000, 0.1\n")
    return SensorNetwork.from_csv(path)


def _measurement_file(tmp_path: Path) -> object:
    path = tmp_path / "scan.csv"
    path.write_text("sensor, time, azimuth, label\n0, 1.0, 0.5, a\n1, 1.0, -0.5, b\n")
    return MeasurementTable.from_csv(path)


def _one_scan_of_many_times(_: Path) -> object:
    scan = static_scan(0, n_targets=3)
    columns = scan.measurements.to_arrays()
    columns["time"] = columns["time"] + np.linspace(0.0, 0.2, len(columns["time"]))
    return pa.associate_static(MeasurementTable.from_columns(columns), scan.sensors)


@pytest.mark.parametrize(
    ("call", "category", "words"),
    [
        (_limit_by_method, pa.LimitWarning, "stopped at its limit"),
        (_limit_by_function, pa.LimitWarning, "stopped at its limit"),
        (_sensor_file, UserWarning, "ignoring column"),
        (_measurement_file, UserWarning, "ignoring non-numeric column"),
        (_one_scan_of_many_times, UserWarning, "associated as one scan"),
    ],
)
def test_a_warning_points_at_the_callers_line(
    call: Callable[[Path], object], category: type[Warning], words: str, tmp_path: Path
) -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        call(tmp_path)
    mine = [w for w in caught if issubclass(w.category, category) and words in str(w.message)]
    assert len(mine) == 1, [str(w.message) for w in caught]
    assert mine[0].filename == __file__
