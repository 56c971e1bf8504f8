"""Geodetic input and output: latitude, longitude and altitude through a local East-North-Up
frame (pymap3d), sensor files and moving platforms in degrees, results in both frames; and
the end-to-end run of a geodetic, moving-sensor, jittered-clock scene from CSV files."""

from __future__ import annotations

import datetime as dt
import json
import math
from pathlib import Path

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.cli import main as cli_main
from passive_assoc.data.geodetic import LocalFrame
from passive_assoc.simulation import ConstantVelocityTarget, simulate

#: A Baltic scene: not a paper's.
ORIGIN = LocalFrame(54.5, 12.0, 0.0)


def test_the_frame_round_trips_and_agrees_with_a_spherical_estimate() -> None:
    points = np.array([[54.6, 12.2, 300.0], [54.4, 11.7, 0.0], [54.5, 12.0, 10e3]])
    enu = ORIGIN.to_enu(points[:, 0], points[:, 1], points[:, 2])
    np.testing.assert_allclose(ORIGIN.to_geodetic(enu), points, rtol=0, atol=1e-7)
    radius = 6.371e6
    east = math.radians(0.2) * radius * math.cos(math.radians(54.55))
    north = math.radians(0.1) * radius
    assert abs(enu[0, 0] - east) < 0.01 * east and abs(enu[0, 1] - north) < 0.01 * north
    assert abs(enu[2, 2] - 10e3) < 1.0  # straight up
    around = LocalFrame.around([54.0, 55.0], [179.5, -179.5])  # across the antimeridian
    assert around.latitude == 54.5 and abs(abs(around.longitude) - 180.0) < 1e-9
    with pytest.raises(ValueError, match=r"^latitude: must be finite in \[-90, 90\], got 91"):
        LocalFrame(91.0, 0.0)
    with pytest.raises(ValueError, match=r"^latitude\[0\] = 95\.0; must lie in \[-90, 90\] degrees"):
        ORIGIN.to_enu([95.0], [0.0])


def test_a_sensor_file_in_degrees_is_placed_in_a_given_or_chosen_frame(tmp_path: Path) -> None:
    path = tmp_path / "net.csv"
    path.write_text("sensor,latitude,longitude,sigma_az_deg\n0,54.6,12.2,0.1\n1,54.4,11.8,0.1\n")
    chosen = pa.SensorNetwork.from_csv(path)
    assert chosen.frame is not None
    assert abs(chosen.frame.latitude - 54.5) < 1e-12 and abs(chosen.frame.longitude - 12.0) < 1e-12
    given = pa.SensorNetwork.from_csv(path, frame=ORIGIN)
    np.testing.assert_allclose(given.positions[:, :2], ORIGIN.to_enu([54.6, 54.4], [12.2, 11.8])[:, :2])
    assert (given.positions[:, 2] == 0).all()  # 2-D: on the tangent plane
    path.write_text("sensor,x,lat,lon,sigma_az\n0,0,54,12,0.01\n")
    with pytest.raises(ValueError, match=r"net\.csv'.*give positions as x, y or as lat, lon, not both"):
        pa.SensorNetwork.from_csv(path)
    path.write_text("sensor,x,y,sigma_az\n0,0,0,0.01\n1,1000,0,0.01\n")
    with pytest.raises(ValueError, match=r"frame: given, but '.*net\.csv' has no 'lat', 'lon' columns"):
        pa.SensorNetwork.from_csv(path, frame=ORIGIN)


def _write_scene(folder: Path) -> tuple[list[str], np.ndarray]:
    """Files a user would bring: a ground ESM and an airborne one in latitude/longitude, the
    aircraft's navigation fixes with ISO times, and compass bearings in degrees with ISO
    timestamps jittered by ±10 ms, the aircraft 0.3 s after the ground site. Returns the files'
    command-line arguments and the targets' true positions at t = 0 (latitude, longitude)."""
    base = dt.datetime(2026, 3, 1, 10, 0, 0, tzinfo=dt.UTC)
    iso = [(base + dt.timedelta(seconds=float(t))).isoformat() for t in (0.0, 150.0, 300.0)]
    ground = ORIGIN.to_geodetic([[0.0, 0.0]]).tolist()
    plane = ORIGIN.to_geodetic([[-30e3, -20e3], [0.0, -20e3], [0.0, 10e3]]).tolist()
    (folder / "sensors.csv").write_text(
        f"sensor_id,lat,lon,sigma_bearing_deg\n0,{ground[0][0]!r},{ground[0][1]!r},0.1\n"
        f"1,{plane[0][0]!r},{plane[0][1]!r},0.1\n"
    )
    (folder / "aircraft.csv").write_text(
        "sensor_id,timestamp,lat,lon\n" + "".join(f"1,{iso[k]},{plane[k][0]!r},{plane[k][1]!r}\n" for k in range(3))
    )
    network = pa.SensorNetwork.from_csv(folder / "sensors.csv")
    assert network.frame is not None
    track = pa.SensorTrack.from_csv(folder / "aircraft.csv", frame=network.frame)
    starts = np.array([[20e3, 40e3], [-25e3, 35e3]])
    truth = ORIGIN.to_geodetic(starts)
    local = network.frame.to_enu(truth[:, 0], truth[:, 1])
    targets = [ConstantVelocityTarget([*local[k, :2], v[0], v[1]]) for k, v in enumerate([(-8.0, -4.0), (6.0, -3.0)])]
    rng = np.random.default_rng(11)
    times = [
        np.arange(30) * 10.0 + rng.uniform(-0.01, 0.01, 30),
        np.arange(30) * 10.0 + 0.3 + rng.uniform(-0.01, 0.01, 30),
    ]
    m = simulate(network, targets, times, t0=0.0, platforms=track, seed=3).measurements
    bearing = np.degrees(np.pi / 2 - m.azimuth) % 360
    lines = [
        f"{s},{(base + dt.timedelta(seconds=float(t))).isoformat()},{b:.4f},0.1"
        for s, t, b in zip(m.sensor, m.time, bearing, strict=True)
    ]
    (folder / "reports.csv").write_text("sensor_id,timestamp,bearing,sigma_bearing\n" + "\n".join(lines) + "\n")
    argv = [
        str(folder / "reports.csv"),
        "--sensors",
        str(folder / "sensors.csv"),
        "--platforms",
        str(folder / "aircraft.csv"),
        "--angle-unit",
        "deg",
        "--azimuth-convention",
        "compass",
        "--out",
        str(folder / "out"),
    ]
    return argv, truth[:, :2]


def test_a_geodetic_moving_sensor_jittered_clock_scene_end_to_end(tmp_path: Path) -> None:
    argv, truth = _write_scene(tmp_path)
    assert cli_main(["initiate", *argv]) == 0
    summary = json.loads((tmp_path / "out" / "reports.initiate.json").read_text())
    assert summary["frame"]["latitude"] == pytest.approx(54.5 - 0.0, abs=0.2)
    found = np.array([t["geodetic"][:2] for t in summary["tracks"]])
    assert len(found) == 2
    for lat, lon in truth:  # each target within ~1 km (0.01°) of its truth
        assert np.min(np.hypot(found[:, 0] - lat, (found[:, 1] - lon) * math.cos(math.radians(lat)))) < 0.01
    assert cli_main(["associate", *argv, "--scan-window", "1.0"]) == 0
    scans = json.loads((tmp_path / "out" / "reports.associate.json").read_text())
    assert scans["scans"] == 30 and len(scans["targets"]) >= 50
    assert all(len(t["geodetic"]) == 3 for t in scans["targets"])
