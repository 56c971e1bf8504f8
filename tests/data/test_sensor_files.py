"""Sensor files: CSV and pandas round trips, degrees, ids in any order, and clear errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from passive_assoc import SensorNetwork


def test_round_trips_are_exact(tmp_path: Path) -> None:
    planar = SensorNetwork.planar([[-2e4, 0.0], [2e4, 1e3], [0.0, 3e4]], [5e-3, 4e-3, 1e-3 / 3])
    spatial = SensorNetwork.spatial([[0.0, 0.0, 10.0], [1e4, 0.0, 20.0]], 2e-3, [3e-3, 1e-3 / 7])
    for net in (planar, spatial):
        path = tmp_path / f"{net.ndim}d.csv"
        net.to_csv(path)
        assert SensorNetwork.from_csv(path) == net


def test_degrees_ids_in_any_order_and_extra_columns(tmp_path: Path) -> None:
    path = tmp_path / "sites.csv"
    path.write_text(
        "name, sensor, x, y, z, sigma_azimuth_deg, sigma_elevation_deg\n"
        "north, 1, 0, 5000, 100, 0.2, 0.4\n"
        "south, 0, 0, -5000, 50, 0.1, 0.3\n"
    )
    with pytest.warns(UserWarning, match=r"ignoring column\(s\) \['name'\]"):
        net = SensorNetwork.from_csv(path)
    assert net.ndim == 3
    assert net.positions.tolist() == [[0.0, -5000.0, 50.0], [0.0, 5000.0, 100.0]]
    np.testing.assert_allclose(net.sigma_azimuth, np.radians([0.1, 0.2]))
    np.testing.assert_allclose(net.sigma_elevation, np.radians([0.3, 0.4]))


@pytest.mark.parametrize(
    "text,message",
    [
        ("x,y\n0,0\n", r"missing column 'sigma_azimuth'"),
        ("x,sigma_azimuth\n0,0.01\n", r"missing column 'y'"),
        ("sensor,x,y,sigma_azimuth\n0,0,0,0.01\n2,1,0,0.01\n", r"'sensor' must hold the ids 0 … 1"),
        ("x,y,z,sigma_azimuth\n0,0,5,0.01\n", r"heights \(column 'z'\) but no elevation std"),
        ("x,y,sigma_azimuth\n0,abc,0.01\n", r"^y: line 2 has 'abc', not a number \(file '.*bad.csv'\)"),
        ("x,y,sigma_azimuth,sigma_azimuth_deg\n0,0,0.01,1\n", r"not both"),
        ("x,y,sigma_azimuth\n", r"header but no sensor rows"),
        ("", r"is empty"),
        ("x,y,sigma_azimuth\n0,0,5\n", r"sigma_azimuth\[0\] = 5.0 rad"),
    ],
)
def test_bad_sensor_files_name_the_problem(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        SensorNetwork.from_csv(path)


def test_pandas_round_trip() -> None:
    pytest.importorskip("pandas")
    net = SensorNetwork.spatial([[0.0, 0.0, 10.0], [1e4, 0.0, 20.0]], 2e-3, 3e-3)
    assert SensorNetwork.from_pandas(net.to_pandas()) == net
    with pytest.raises(TypeError, match="df"):
        SensorNetwork.from_pandas({"x": [0.0]})


def test_pickled_tables_and_networks_come_back_equal_and_usable() -> None:
    """Rebuilt through their constructors: a transport (Dask) may hand back unaligned arrays."""
    import pickle

    import passive_assoc as pa
    from passive_assoc.simulation import static_scan

    scan = static_scan(4, n_targets=3)
    table, net = pickle.loads(pickle.dumps(scan.measurements)), pickle.loads(pickle.dumps(scan.sensors))
    assert table == scan.measurements and net == scan.sensors
    assert table.azimuth.flags.c_contiguous and table.azimuth.flags.aligned
    assert len(pa.associate_static(table, net, "lagrangian").labels) == len(table)
