"""The user's own files: angle conventions declared once, header aliases, ISO times, per-report
noise columns, and errors that name the file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from passive_assoc import MeasurementTable, SensorNetwork
from passive_assoc.data.angles import to_user_azimuth


def test_a_compass_bearing_in_degrees_is_read_as_the_library_convention(tmp_path: Path) -> None:
    """North 0°, east 90°, south-west 225° (clockwise from north) are π/2, 0 and −3π/4 rad
    counter-clockwise from east; the same file in radians gives the same table."""
    path = tmp_path / "esm.csv"
    path.write_text("sensor,time,bearing\n0,0,0\n1,0,90\n2,0,225\n")
    table = MeasurementTable.from_csv(path, angle_unit="deg", azimuth_convention="compass")
    np.testing.assert_allclose(np.cos(table.azimuth), [0.0, 1.0, -np.sqrt(0.5)], atol=1e-15)
    np.testing.assert_allclose(np.sin(table.azimuth), [1.0, 0.0, -np.sqrt(0.5)], atol=1e-15)
    path.write_text(f"sensor,time,bearing\n0,0,0\n1,0,{np.pi / 2!r}\n2,0,{float(np.radians(225))!r}\n")
    same = MeasurementTable.from_csv(path, azimuth_convention="compass")
    np.testing.assert_allclose(same.azimuth, table.azimuth, atol=1e-15)
    np.testing.assert_allclose(to_user_azimuth(table.azimuth, "deg", "compass"), [0.0, 90.0, 225.0], atol=1e-12)
    with pytest.raises(ValueError, match=r"^azimuth_convention: must be 'math' or 'compass', got 'north'"):
        MeasurementTable.from_csv(path, azimuth_convention="north")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^angle_unit: must be 'rad' or 'deg', got 'grad'"):
        MeasurementTable.from_arrays([0], [0.0], [0.1], angle_unit="grad")  # type: ignore[arg-type]


def test_degrees_in_a_file_read_as_radians_is_an_error_naming_the_file(tmp_path: Path) -> None:
    path = tmp_path / "deg.csv"
    path.write_text("sensor,time,azimuth\n0,0,45\n1,0,135\n")
    with pytest.raises(ValueError, match=r"^'.*deg\.csv': azimuth\[0\] = 45\.0 rad is beyond ±2π"):
        MeasurementTable.from_csv(path)
    assert MeasurementTable.from_csv(path, check_angle_unit=False).azimuth.tolist() == [45.0, 135.0]


def test_the_headers_other_tools_write_are_read(tmp_path: Path) -> None:
    """``sensor_id,t,bearing,sigma_bearing`` gave an error listing attr_sensor_id, attr_t,
    attr_bearing and no file name."""
    path = tmp_path / "tool.csv"
    path.write_text("Sensor_ID,t,Bearing,sigma_bearing,snr\n1,0.5,10,0.5,7\n0,0.5,20,,8\n")
    table = MeasurementTable.from_csv(path, angle_unit="deg")
    assert table.sensor.tolist() == [1, 0] and table.time.tolist() == [0.5, 0.5]
    np.testing.assert_allclose(table.azimuth, np.radians([10.0, 20.0]))
    assert table.sigma_azimuth is not None
    np.testing.assert_allclose(table.sigma_azimuth, [np.radians(0.5), np.nan])  # empty: the sensor's
    assert list(table.attributes) == ["snr"]
    path.write_text("sensor_id,timestamp,az,el,sigma_az,sigma_el\n0,1.0,0.1,0.2,0.01,0.02\n")
    table = MeasurementTable.from_csv(path)
    assert table.elevation.tolist() == [0.2] and table.sigma_elevation is not None
    path.write_text("sensor,time,bearing,azimuth\n0,0,0.1,0.1\n")
    with pytest.raises(ValueError, match=r"'.*tool\.csv' has both 'bearing' and 'azimuth', which both mean 'azimuth'"):
        MeasurementTable.from_csv(path)
    path.write_text("sensor_id,when,bearing\n0,0,0.1\n")
    with pytest.raises(ValueError, match=r"^'.*tool\.csv': missing required column 'time' \(got \['sensor', 'when'"):
        MeasurementTable.from_csv(path)


def test_sensor_files_take_the_aliases_and_name_the_file_in_every_error(tmp_path: Path) -> None:
    path = tmp_path / "net.csv"
    path.write_text("sensor_id,x,y,sigma_bearing_deg\n1,5000,0,0.5\n0,0,3000,0.25\n")
    net = SensorNetwork.from_csv(path)
    np.testing.assert_allclose(net.sigma_azimuth, np.radians([0.25, 0.5]))
    assert net.positions[:, 0].tolist() == [0.0, 5000.0]
    path.write_text("sensor,x,y,sigma_az\n0,0,0,0.01\n1,0,0,0.01\n")
    with pytest.raises(ValueError, match=r"^'.*net\.csv': positions: sensors 0 and 1 are coincident"):
        SensorNetwork.from_csv(path)
    path.write_text("sensor,x,y,sigma_az,sigma_bearing\n0,0,0,0.01,0.01\n")
    with pytest.raises(ValueError, match=r"net\.csv'.*two columns mean 'sigma_azimuth'"):
        SensorNetwork.from_csv(path)


def test_iso_times_become_seconds_after_the_earliest_or_a_given_origin(tmp_path: Path) -> None:
    path = tmp_path / "iso.csv"
    path.write_text(
        "sensor,timestamp,bearing\n0,2026-03-01T10:00:00.250Z,0.1\n1,2026-03-01T10:00:00Z,0.2\n"
        "0,2026-03-01T10:01:00.250+00:00,0.3\n"
    )
    assert MeasurementTable.from_csv(path).time.tolist() == [0.25, 0.0, 60.25]
    later = MeasurementTable.from_csv(path, time_origin="2026-03-01T09:59:00Z")
    assert later.time.tolist() == [60.25, 60.0, 120.25]
    path.write_text("sensor,time,bearing\n0,2026-03-01T10:00:00Z,0.1\n1,2026-03-01T10:00:01,0.2\n")
    with pytest.raises(ValueError, match=r"some date-times have a time zone and some do not \(file '.*iso\.csv'\)"):
        MeasurementTable.from_csv(path)
    path.write_text("sensor,time,bearing\n0,2026-03-01T10:00:00Z,0.1\n1,yesterday,0.2\n")
    with pytest.raises(ValueError, match=r"^time: line 3 has 'yesterday', neither a number of seconds nor an ISO"):
        MeasurementTable.from_csv(path)
    with pytest.raises(ValueError, match=r"^time_origin: 'noon' is not an ISO 8601 date-time"):
        MeasurementTable.from_csv(tmp_path / "iso.csv", time_origin="noon")


def test_per_report_noise_columns_are_checked_kept_and_round_trip(tmp_path: Path) -> None:
    table = MeasurementTable.from_arrays(
        [0, 1, 1], [0.0, 0.0, 0.0], [0.1, 0.2, 0.3], sigma_azimuth=[0.5, np.nan, 1.0], angle_unit="deg"
    )
    assert table.sigma_azimuth is not None
    np.testing.assert_allclose(table.sigma_azimuth, np.radians([0.5, np.nan, 1.0]))
    assert table.select([2, 0]).sigma_azimuth.tolist() == [np.radians(1.0), np.radians(0.5)]  # type: ignore[union-attr]
    table.to_csv(tmp_path / "n.csv")
    assert MeasurementTable.from_csv(tmp_path / "n.csv") == table
    with pytest.raises(ValueError, match=r"^sigma_azimuth\[1\] = 0\.0 rad; a report's angle std must lie in"):
        MeasurementTable.from_arrays([0, 1], [0.0, 0.0], [0.1, 0.2], sigma_azimuth=[0.01, 0.0])
    with pytest.raises(ValueError, match=r"^sigma_azimuth: has length 1 but sensor has length 2"):
        MeasurementTable.from_arrays([0, 1], [0.0, 0.0], [0.1, 0.2], sigma_azimuth=[0.01])
    with pytest.raises(ValueError, match=r"^sigma_elevation: a 2-D table \(no elevation\) has no elevation noise"):
        MeasurementTable.from_arrays([0, 1], [0.0, 0.0], [0.1, 0.2], sigma_elevation=[0.01, 0.01])
