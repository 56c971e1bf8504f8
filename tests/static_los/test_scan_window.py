"""Scans from real clocks: reports of one scan a few milliseconds (jitter) or tenths of a
second (sensor offsets) apart, grouped by ``scan_window``; a multi-time table passed as one
scan warns; the command line no longer answers "0 targets" on jittered times."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import passive_assoc as pa
import pytest
from numpy.typing import NDArray
from passive_assoc.cli import main as cli_main
from passive_assoc.static_los import window_scans

#: Four sensors of a coastal network (not a paper's layout), metres.
SENSORS = np.array([[-30e3, -5e3], [25e3, -12e3], [4e3, 28e3], [-8e3, -31e3]])
SIGMA = np.radians(0.1)


def jittered_scene(seed: int, n_targets: int = 5, n_scans: int = 3) -> tuple[pa.MeasurementTable, NDArray[np.float64]]:
    """Targets drifting at 10 m/s; each scan's report times are its nominal time plus a sensor
    offset of 0.1 s per sensor and a ±10 ms jitter per report."""
    rng = np.random.default_rng(seed)
    start = rng.uniform(-15e3, 15e3, (n_targets, 2))
    velocity = rng.normal(0.0, 10.0, (n_targets, 2))
    sensor, time, azimuth, truth = [], [], [], []
    for k in range(n_scans):
        for j, p in enumerate(SENSORS):
            for target in rng.permutation(n_targets):
                t = 10.0 * k + 0.1 * j + rng.uniform(-0.01, 0.01)
                d = start[target] + velocity[target] * t - p
                sensor.append(j)
                time.append(t)
                azimuth.append(np.arctan2(d[1], d[0]) + SIGMA * rng.standard_normal())
                truth.append(target)
    table = pa.MeasurementTable.from_arrays(sensor, time, azimuth, truth=truth)
    return table, start


def network() -> pa.SensorNetwork:
    return pa.SensorNetwork.planar(SENSORS, SIGMA)


def test_the_window_rule_opens_a_scan_at_the_earliest_report_and_ignores_row_order() -> None:
    times = np.array([0.0, 0.3, 0.31, 0.6, 0.61, 5.0])
    keys, scan = window_scans(times, 0.3)
    assert keys.tolist() == [0.0, 0.31, 5.0] and scan.tolist() == [0, 0, 1, 1, 1, 2]
    order = np.random.default_rng(0).permutation(len(times))
    keys2, scan2 = window_scans(times[order], 0.3)
    assert keys2.tolist() == keys.tolist() and scan2.tolist() == scan[order].tolist()
    assert window_scans(times, 0.0)[0].tolist() == times.tolist()  # 0: exact times, as without a window
    with pytest.raises(ValueError, match=r"^scan_window: must be >= 0 seconds"):
        window_scans(times, -1.0)


@pytest.mark.parametrize("method", ["lagrangian", "exact"])
def test_jittered_scans_are_associated_with_a_window(method: str) -> None:
    table, _ = jittered_scene(4)
    assert len(np.unique(table.time)) == len(table)  # no two reports share a time
    out = pa.associate_scans(table, network(), method=method, scan_window=0.5)
    columns = table.to_arrays()
    columns["time"] = 10.0 * np.round(columns["time"] / 10.0)  # the nominal scan times
    exact = pa.associate_scans(pa.MeasurementTable.from_columns(columns), network(), method=method)
    assert out.labels.tolist() == exact.labels.tolist() and out.scan.tolist() == exact.scan.tolist()
    assert out.keys.shape == (3,) and np.bincount(out.scan).tolist() == [20, 20, 20]
    assert table.truth is not None
    for k in range(3):
        rows = np.flatnonzero(out.scan == k)
        labels, truth = out.labels[rows], table.truth[rows]
        assert (labels >= 0).all()
        # Same partition as the truth: each target's four reports form one target.
        pairs = {(int(a), int(b)) for a, b in zip(labels, truth, strict=True)}
        assert len(pairs) == 5 and len({a for a, _ in pairs}) == 5
    without = pa.associate_scans(table, network(), method=method)
    assert len(without.keys) == len(table) and len(without.positions) == 0  # what exact times give


def test_a_multi_time_table_as_one_scan_warns_and_a_window_says_how_far_apart() -> None:
    table, _ = jittered_scene(5, n_scans=1)
    with pytest.warns(UserWarning, match=r"^measurements: 20 distinct times over 0\.3\d* s are associated as one scan"):
        pa.associate_static(table, network())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        found = pa.associate_static(table, network(), scan_window=0.5)
    assert len(found.positions) == 5 and len(found.clutter) == 0
    with pytest.raises(ValueError, match=r"^measurements: times span 0\.3\d* s, more than scan_window = 0\.1 s"):
        pa.associate_static(table, network(), scan_window=0.1)
    with pytest.raises(ValueError, match=r"scan_window"):
        pa.StaticAssociator(scan_window=-0.5)


def test_the_command_refuses_jittered_times_and_groups_them_with_scan_window(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    table, _ = jittered_scene(7)
    meas, sensors = tmp_path / "m.csv", tmp_path / "s.csv"
    table.to_csv(meas)
    network().to_csv(sensors)
    argv = ["associate", str(meas), "--sensors", str(sensors), "--out", str(tmp_path / "out")]
    with pytest.raises(SystemExit) as stop:
        cli_main(argv)
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.count("none with reports of two sensors") == 1 and "--scan-window" in err
    assert cli_main([*argv, "--scan-window", "0.5"]) == 0
    assert "3 scan(s), 15 target(s), 0 of 60 reports false alarms" in capsys.readouterr().out
    summary = json.loads((tmp_path / "out" / "m.associate.json").read_text())
    assert summary["scans"] == 3 and len(summary["targets"]) == 15


def fast_scene(seed: int) -> pa.MeasurementTable:
    """Five aircraft at 250-300 m/s, 15-25 km from the sites, the sites reporting 0.4 s
    apart with 0.05° noise: within one scan a target moves 25-30 σ of bearing."""
    rng = np.random.default_rng(seed)
    sigma = np.radians(0.05)
    start = rng.uniform(-8e3, 8e3, (5, 2))
    heading = rng.uniform(-np.pi, np.pi, 5)
    velocity = rng.uniform(250.0, 300.0, (5, 1)) * np.column_stack([np.cos(heading), np.sin(heading)])
    sensor, time, azimuth, truth = [], [], [], []
    for j, p in enumerate(SENSORS):
        for target in range(5):
            t = 0.4 * j
            d = start[target] + velocity[target] * t - p
            sensor.append(j)
            time.append(t)
            azimuth.append(np.arctan2(d[1], d[0]) + sigma * rng.standard_normal())
            truth.append(target)
    return pa.MeasurementTable.from_arrays(sensor, time, azimuth, truth=truth)


def test_the_motion_within_a_window_is_allowed_for_when_v_max_and_min_range_are_given() -> None:
    """Ten scenes of five fast aircraft: a target is found *whole* when its four reports, and
    only they, make one target."""
    network = pa.SensorNetwork.planar(SENSORS, np.radians(0.05))
    whole = {"plain": 0, "moving": 0}
    declared = {"plain": 0, "moving": 0}
    for seed in range(10):
        table = fast_scene(seed)
        assert table.truth is not None
        for name, settings in (("plain", {}), ("moving", {"v_max": 300.0, "min_range": 10e3})):
            out = pa.associate_static(table, network, scan_window=1.5, method="exact", **settings)  # type: ignore[arg-type]
            declared[name] += len(out.positions)
            for target in range(5):
                labels = out.labels[table.truth == target]
                whole[name] += int(
                    labels[0] >= 0 and (out.labels == labels[0]).sum() == 4 and (labels == labels[0]).all()
                )
    # Taken as simultaneous: 14 of 50 whole, 66 targets declared (ghosts and splits); with the
    # motion allowed for: 48 of 50 whole, 50 declared.
    assert whole["plain"] <= 20 and declared["plain"] >= 60, (whole, declared)
    assert whole["moving"] >= 46 and declared["moving"] <= 52, (whole, declared)
    inflated = pa.static_los.motion_inflated(fast_scene(0), network, np.zeros(20, dtype=np.int64), 300.0, 10e3)
    assert inflated.sigma_azimuth is not None
    np.testing.assert_allclose(inflated.sigma_azimuth[:5], np.hypot(np.radians(0.05), 300.0 * 0.6 / 10e3))
    with pytest.raises(ValueError, match=r"^v_max, min_range: give both"):
        pa.StaticAssociator(v_max=300.0)
