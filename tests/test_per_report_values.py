"""Per-report sensor positions and noise stds reach every method, the Rust core included.

Each test builds one table two ways on a scene of its own (three sensors on an irregular
triangle, four crossing targets): once with a network whose third sensor has a given noise
(or position), once with a network where it has another and the reports carry the first as
their own ``sigma_azimuth`` (or ``sensor_position``). Every method must answer the same: the
per-report value replaces the sensor's in weights, gates, costs and bounds. A last test gives
one report a huge noise of its own and checks that the fit then ignores it.
"""

from __future__ import annotations

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.simulation import ConstantVelocityTarget, simulate

POSITIONS = np.array([[-20e3, 0.0], [15e3, -5e3], [0.0, 25e3]])
MOVED = np.array([3e3, 28e3])  # where the third sensor "really" is in the position tests
SIGMA = np.array([1e-3, 1e-3, 3e-3])


def _scene(network: pa.SensorNetwork, seed: int = 2) -> pa.Scenario:
    targets = [
        ConstantVelocityTarget([-8e3, 12e3, 150.0, 20.0]),
        ConstantVelocityTarget([6e3, 9e3, -120.0, 60.0]),
        ConstantVelocityTarget([2e3, 16e3, 30.0, -140.0]),
        ConstantVelocityTarget([-3e3, 5e3, 90.0, 110.0]),
    ]
    times = [np.arange(6) * 10.0] * 3
    return simulate(network, targets, times, pd=1.0, clutter_per_scan=1, t0=0.0, seed=seed)


def _with(table: pa.MeasurementTable, **columns: object) -> pa.MeasurementTable:
    return pa.MeasurementTable.from_arrays(
        table.sensor,
        table.time,
        table.azimuth,
        None,
        table.attributes,
        table.truth,
        **columns,  # type: ignore[arg-type]
    )


def noise_pair() -> tuple[pa.Scenario, pa.MeasurementTable, pa.SensorNetwork]:
    """The scene seen by the true network, and the same reports carrying the third sensor's
    noise themselves, for a network that says 1 mrad everywhere."""
    truth = pa.SensorNetwork.planar(POSITIONS, SIGMA)
    scene = _scene(truth)
    m = scene.measurements
    own = np.where(m.sensor == 2, SIGMA[2], np.nan)
    return scene, _with(m, sigma_azimuth=own), pa.SensorNetwork.planar(POSITIONS, 1e-3)


def position_pair() -> tuple[pa.Scenario, pa.MeasurementTable, pa.SensorNetwork]:
    """The scene seen from the moved third sensor, and the same reports carrying that
    position themselves, for a network that still has the sensor where it was."""
    moved = POSITIONS.copy()
    moved[2] = MOVED
    scene = _scene(pa.SensorNetwork.planar(moved, SIGMA))
    m = scene.measurements
    where = np.where((m.sensor == 2)[:, None], np.append(MOVED, 0.0), np.nan)
    return scene, _with(m, sensor_position=where), pa.SensorNetwork.planar(POSITIONS, SIGMA)


PAIRS = {"noise": noise_pair, "position": position_pair}


@pytest.mark.parametrize("kind", PAIRS)
def test_the_fit_and_the_bound_read_the_reports_values(kind: str) -> None:
    scene, table, network = PAIRS[kind]()
    groups = scene.true_groups()
    a = pa.fit_ml(scene.measurements, scene.sensors, groups, t0=0.0)
    b = pa.fit_ml(table, network, groups, t0=0.0)
    np.testing.assert_allclose(b.estimates, a.estimates, rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(b.covariances, a.covariances, rtol=1e-7, atol=1e-9)
    rows = groups[0]
    m = table
    expected = pa.crlb(
        scene.measurements.sensor[rows], scene.measurements.time[rows], scene.sensors, scene.true_states[0]
    )
    got = pa.crlb(
        m.sensor[rows],
        m.time[rows],
        network,
        scene.true_states[0],
        sensor_position=None if m.sensor_position is None else m.sensor_position[rows],
        sigma_azimuth=None if m.sigma_azimuth is None else m.sigma_azimuth[rows],
    )
    np.testing.assert_allclose(got, expected, rtol=1e-10)
    plain = pa.crlb(m.sensor[rows], m.time[rows], network, scene.true_states[0])
    assert not np.allclose(plain, expected, rtol=1e-3)  # without the reports' values: another bound


@pytest.mark.parametrize("kind", PAIRS)
def test_static_association_reads_the_reports_values(kind: str) -> None:
    scene, table, network = PAIRS[kind]()
    scan = np.flatnonzero(table.time == 30.0)
    settings = {"false_alarm_density": 0.5, "method": "exact"}
    a = pa.associate_static(scene.measurements.select(scan), scene.sensors, **settings)
    b = pa.associate_static(table.select(scan), network, **settings)
    assert len(a.positions) >= 4 and b.labels.tolist() == a.labels.tolist()
    np.testing.assert_allclose(b.positions, a.positions, rtol=1e-9)
    np.testing.assert_allclose(b.costs, a.costs, rtol=1e-9, atol=1e-9)
    ca = pa.enumerate_candidates(scene.measurements.select(scan), scene.sensors, false_alarm_density=0.5)
    cb = pa.enumerate_candidates(table.select(scan), network, false_alarm_density=0.5)
    assert cb.tuples.tolist() == ca.tuples.tolist()
    np.testing.assert_allclose(cb.costs, ca.costs, rtol=1e-9, atol=1e-9)
    batch_a = pa.associate_scans(scene.measurements, scene.sensors, **settings)
    batch_b = pa.associate_scans(table, network, **settings)
    assert batch_b.labels.tolist() == batch_a.labels.tolist()
    wrong = pa.associate_static(_with(table.select(scan)), network, **settings)  # the sensor's values
    assert wrong.costs.tolist() != a.costs.tolist()


@pytest.mark.parametrize("kind", PAIRS)
def test_formation_location_reads_the_reports_values(kind: str) -> None:
    scene, table, network = PAIRS[kind]()
    scan = np.flatnonzero(table.time == 20.0)
    a = pa.locate_formation(scene.measurements.select(scan), scene.sensors)
    b = pa.locate_formation(table.select(scan), network)
    assert b.labels.tolist() == a.labels.tolist()
    np.testing.assert_allclose(b.positions, a.positions, rtol=1e-9, atol=1e-6)


@pytest.mark.parametrize("kind", PAIRS)
def test_initiation_reads_the_reports_values(kind: str) -> None:
    scene, table, network = PAIRS[kind]()
    a = pa.FuzzyTrackInitiator().initiate(scene.measurements, scene.sensors, t0=0.0)
    b = pa.FuzzyTrackInitiator().initiate(table, network, t0=0.0)
    assert len(a.tracks) == 4 and b.labels.tolist() == a.labels.tolist()
    np.testing.assert_allclose([t.state for t in b.tracks], [t.state for t in a.tracks], rtol=1e-8, atol=1e-6)
    np.testing.assert_allclose([t.score for t in b.tracks], [t.score for t in a.tracks], rtol=1e-9, atol=1e-9)


def test_a_report_with_a_huge_noise_of_its_own_has_no_weight() -> None:
    scene, _, _ = noise_pair()
    m = scene.measurements
    rows = scene.true_groups()[1]
    bad = rows[3]
    azimuth = m.azimuth.copy()
    azimuth[bad] += 0.05  # a 50 mrad error: 17 σ of its sensor
    own = np.full(len(m), np.nan)
    own[bad] = 3.0  # the report says it is worthless
    table = pa.MeasurementTable.from_arrays(m.sensor, m.time, azimuth, sigma_azimuth=own)
    weighted = pa.fit_ml(table, scene.sensors, [rows], t0=0.0).estimates[0]
    without = pa.fit_ml(m, scene.sensors, [np.setdiff1d(rows, [bad])], t0=0.0).estimates[0]
    trusting = pa.fit_ml(_with(table), scene.sensors, [rows], t0=0.0).estimates[0]
    assert np.abs(weighted[:2] - without[:2]).max() < 5.0  # metres
    assert np.abs(trusting[:2] - without[:2]).max() > 50.0
