"""The default false-alarm density on a scan the paper's numbers are not tuned on: three
well-separated targets seen by the paper's three sensors, and one false alarm.

With ``p_false · n / span`` alone the density would be 0.23 per radian here (0.05 x 4 reports
over the sector they span), so eq. 2 would price the false alarm as a target: Lagrangian and
exact would return a ghost at it and split a true target. The default also counts a sensor's
reports beyond the median sensor's as false alarms (docs/methods.md §2)."""

from __future__ import annotations

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc import _core
from passive_assoc.static_los import associate_scans
from passive_assoc.static_los.candidates import default_false_alarm_density

SENSORS = pa.SensorNetwork.planar([[-15e3, 0.0], [0.0, -5e3], [15e3, 0.0]], 2e-3)
TARGETS = np.array([[-5e3, 25e3], [0.0, 35e3], [6e3, 30e3]])
FALSE_ALARM = 1.30  # rad, sensor 1: outside its three target bearings (1.401 ... 1.736)


def hand_written_scan() -> pa.MeasurementTable:
    rows = [(j, np.arctan2(*(t - p)[::-1])) for j, p in enumerate(SENSORS.positions[:, :2]) for t in TARGETS]
    rows.append((1, FALSE_ALARM))
    sensor, bearing = np.array(rows).T
    return pa.MeasurementTable.from_arrays(sensor.astype(int), np.zeros(len(rows)), bearing)


@pytest.mark.parametrize("method", ["lagrangian", "exact", "intensity"])
def test_three_targets_and_the_false_alarm_as_clutter(method: str) -> None:
    table = hand_written_scan()
    result = pa.associate_static(table, SENSORS, method)
    assert len(result.rows) == 3
    assert np.all(result.rows >= 0)  # three full targets, none split
    assert result.clutter.tolist() == [9]  # the false alarm, the last row
    order = np.argsort(result.positions[:, 0])
    np.testing.assert_allclose(result.positions[order], TARGETS, atol=1.0)


def test_the_batch_path_uses_the_same_default() -> None:
    """Two copies of the scan at two times through ``associate_scans``: each is associated as
    the single scan is."""
    one = hand_written_scan()
    two = pa.MeasurementTable.from_arrays(
        np.concatenate([one.sensor, one.sensor]),
        np.repeat([0.0, 1.0], len(one)),
        np.concatenate([one.azimuth, one.azimuth]),
    )
    batch = associate_scans(two, SENSORS, method="lagrangian")
    assert len(batch.positions) == 6
    assert np.flatnonzero(batch.labels < 0).tolist() == [9, 19]
    for k in (0, 1):
        rows = batch.labels[10 * k : 10 * k + 9]
        assert len(np.unique(rows)) == 3 and np.all(np.bincount(rows - rows.min()) == 3)


def test_the_default_density_counts_the_excess_report() -> None:
    """Sensor 1 has 4 reports where the others have 3: at least one false alarm over its span."""
    table = hand_written_scan()
    density = default_false_alarm_density(table, 3)
    bearings = table.azimuth[table.sensor == 1]
    assert density[1] == pytest.approx(1.0 / (bearings.max() - bearings.min()))
    others = table.azimuth[table.sensor == 0]
    assert density[0] == pytest.approx(0.05 * 3 / (others.max() - others.min()))


def numpy_reference(sensor: np.ndarray, angles: list[np.ndarray], n_sensors: int, p_false: float) -> np.ndarray:
    """The rule written in NumPy (the expressions of a NumPy ``default_false_alarm_density``,
    ``expected_false_alarms``, ``_median_last_axis`` and ``_spans``, inlined): the core must
    give the same densities to the bit."""

    def spans(sensor: np.ndarray, values: np.ndarray, counts: np.ndarray) -> np.ndarray:
        order = np.lexsort((values, sensor))
        ends = np.cumsum(counts)
        present = counts > 0
        out = np.full(len(counts), np.pi)
        ordered = values[order]
        out[present] = ordered[ends[present] - 1] - ordered[ends[present] - counts[present]]
        return out

    def median_last_axis(counts: np.ndarray) -> np.ndarray:
        ordered = np.sort(counts, axis=-1)
        n = ordered.shape[-1]
        middle = ordered[..., n // 2 : n // 2 + 1].astype(np.float64)
        if n % 2 == 0 and n > 0:
            middle = 0.5 * (middle + ordered[..., n // 2 - 1 : n // 2])
        return middle

    ours = sensor < n_sensors
    sensor = sensor[ours]
    counts = np.bincount(sensor, minlength=n_sensors)
    area = np.maximum(spans(sensor, angles[0][ours], counts), 1e-3)
    if len(angles) == 2:
        heights = np.maximum(spans(sensor, angles[1][ours], counts), 1e-3)
        area = np.where(counts > 0, area * heights, area)
    expected = np.maximum(p_false * np.maximum(counts, 1), counts - median_last_axis(counts))
    return np.maximum(expected / area, 1e-12)


@pytest.mark.parametrize("ndim", [2, 3])
def test_the_core_density_equals_the_numpy_rule(ndim: int) -> None:
    rng = np.random.default_rng(ndim)
    with_excess = 0
    for _ in range(300):
        n_sensors, n = int(rng.integers(1, 6)), int(rng.integers(0, 14))
        sensor = rng.integers(0, n_sensors + 1, n)  # some rows of a sensor beyond the network
        # Some repeated angles, so zero spans (clamped to 10⁻³) occur too.
        angles = [rng.choice([0.5, 0.5, *rng.uniform(-np.pi, np.pi, 3)], n) for _ in range(ndim - 1)]
        p_false = float(rng.choice([0.0, 0.05, 0.3]))
        elevation = angles[1] if ndim == 3 else None
        got = _core.default_false_alarm_density(sensor, angles[0], elevation, n_sensors, p_false)
        assert np.array_equal(got, numpy_reference(sensor, angles, n_sensors, p_false))
        counts = np.bincount(sensor[sensor < n_sensors], minlength=n_sensors)
        with_excess += int(np.any(counts - np.median(counts) > p_false * np.maximum(counts, 1)))
    assert with_excess > 50  # the excess rule was exercised, not only the P_FA fraction


def test_the_density_helper_rejects_bad_input() -> None:
    table = hand_written_scan()
    with pytest.raises(ValueError, match="p_false"):
        default_false_alarm_density(table, 3, p_false=1.5)
    with pytest.raises(ValueError, match="n_sensors"):
        default_false_alarm_density(table, -1)
    with pytest.raises(ValueError, match="n_sensors"):  # the result's length bounds its memory
        default_false_alarm_density(table, 10**12)
    with pytest.raises(ValueError, match="n_sensors: 1099511627776 exceeds the maximum"):
        _core.default_false_alarm_density(table.sensor, table.azimuth, None, 2**40, 0.05)
    with pytest.raises(ValueError, match="elevation: has 2 values"):
        _core.default_false_alarm_density(table.sensor, table.azimuth, np.zeros(2), 3, 0.05)
    with pytest.raises(ValueError, match="sensor: row 0 names sensor -1"):
        _core.default_false_alarm_density(np.array([-1]), np.zeros(1), None, 3, 0.05)


def test_the_default_equals_the_density_passed_explicitly() -> None:
    """``false_alarm_density=None`` (computed in the core, per scan in the batch path) and the
    helper's densities passed in give the same candidates and the same answers."""
    scan = pa.simulation.static_scan(3, n_targets=6, n_sensors=3)
    table, sensors = scan.measurements, scan.sensors
    density = default_false_alarm_density(table, 3)
    implicit, explicit = (pa.enumerate_candidates(table, sensors, false_alarm_density=d) for d in (None, density))
    assert np.array_equal(implicit.costs, explicit.costs) and len(implicit.costs) > 6
    for method in ("intensity", "lagrangian"):
        batch = associate_scans(table, sensors, method=method)
        single = pa.associate_static(table, sensors, method, false_alarm_density=density)
        assert np.array_equal(batch.labels, single.labels)


@pytest.mark.parametrize("sigma", [1e-2, 3e-2, 1e-4])
@pytest.mark.parametrize("method", ["lagrangian", "exact", "intensity"])
def test_a_lone_noiseless_target_is_a_target(method: str, sigma: float) -> None:
    """One report per sensor, each at the target's exact bearing: with the 10⁻³ rad floor
    alone the default density was 50 per radian, above a perfect report's likelihood at
    σ = 10 mrad (40 per radian), and the S-D methods called the target clutter. A tiny scan's
    span is now at least the default gate's width on the sensor's angle."""
    network = pa.SensorNetwork.planar(SENSORS.positions[:, :2], sigma)
    target = np.array([2e3, 25e3])
    bearings = np.arctan2(target[1] - network.positions[:, 1], target[0] - network.positions[:, 0])
    scan = pa.MeasurementTable.from_arrays(np.arange(3), np.zeros(3), bearings)
    result = pa.associate_static(scan, network, method)
    assert result.labels.tolist() == [0, 0, 0]
    np.testing.assert_allclose(result.positions, [target], atol=1e-3)
    width = 2 * 2.5758293035489004 * sigma
    expected = 0.05 / max(width, 1e-3)
    density = default_false_alarm_density(scan, 3, sensors=network)
    np.testing.assert_allclose(density, expected, rtol=1e-12)
    batch = associate_scans(scan, network, method=method)
    assert batch.labels.tolist() == [0, 0, 0]


def test_the_density_helper_reads_the_network_stds_in_3d() -> None:
    network = pa.SensorNetwork.spatial([[0.0, 0.0, 0.0], [1e4, 0.0, 0.0]], [1e-2, 2e-2], [3e-2, 1e-5])
    table = pa.MeasurementTable.from_arrays([0, 1], [0.0, 0.0], [0.5, 1.0], elevation=[0.1, 0.2])
    density = default_false_alarm_density(table, 2, sensors=network)
    width = 2 * 2.5758293035489004
    np.testing.assert_allclose(density, [0.05 / (width * 1e-2 * width * 3e-2), 0.05 / (width * 2e-2 * 1e-3)])
    with pytest.raises(ValueError, match="sensors: has 2 sensors, n_sensors is 3"):
        default_false_alarm_density(table, 3, sensors=network)
