"""Tests of the radar simulator and the topology and radar/ESM paper scenarios."""

from __future__ import annotations

import math

import numpy as np
import pytest
from passive_assoc.simulation import (
    PAPER_WAVELET_TARGETS,
    ConstantVelocityTarget,
    Radar,
    RadarMeasurements,
    line_abreast_formation,
    paper_topology_scenario,
    paper_wavelet_scenario,
    scattered_targets,
    simulate_radars,
    true_positions,
    wrap_angle,
)
from passive_assoc.simulation.topology import PARTIAL_COVERAGE_RADIUS


def _columns(m: RadarMeasurements) -> list[np.ndarray]:
    return [m.radar, m.time, m.range, m.azimuth, m.truth]


def _same(a: list[np.ndarray], b: list[np.ndarray]) -> bool:
    return len(a) == len(b) and all(
        x.dtype == y.dtype and x.tobytes() == y.tobytes() for x, y in zip(a, b, strict=True)
    )


def _rotate(points: np.ndarray, centre: np.ndarray, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return centre + (points - centre) @ np.array([[c, s], [-s, c]])  # row vectors: p Rᵀ


TARGETS = [
    ConstantVelocityTarget([10e3, 20e3, 300.0, 0.0]),
    ConstantVelocityTarget([-50e3, 5e3, 0.0, -250.0]),
    ConstantVelocityTarget([0.0, -80e3, 200.0, 200.0]),
]
SCANS = np.arange(12) * 10.0


# --------------------------------------------------------------------------- Radar


def test_radar_from_degrees_and_validation() -> None:
    radar = Radar.from_degrees([1.0, 2.0], 500.0, sigma_azimuth_deg=1.0, azimuth_bias_deg=-5.0)
    assert radar.sigma_azimuth == pytest.approx(math.pi / 180) and radar.azimuth_bias == pytest.approx(-math.pi / 36)
    assert radar.coverage_radius == math.inf and radar.position.tolist() == [1.0, 2.0]
    assert Radar([0, 0], 0.0, 0.0, coverage_radius=5.0).covers([[3.0, 4.0], [3.0, 4.1]]).tolist() == [True, False]
    with pytest.raises(ValueError, match=r"^position: expected shape \(2,\)"):
        Radar([0.0, 0.0, 0.0], 1.0, 1.0)
    with pytest.raises(ValueError, match=r"^sigma_range: must be >= 0"):
        Radar([0.0, 0.0], -1.0, 1.0)
    with pytest.raises(ValueError, match=r"^coverage_radius: must be > 0"):
        Radar([0.0, 0.0], 1.0, 1.0, coverage_radius=0.0)
    with pytest.raises(ValueError, match=r"^azimuth_bias = nan"):
        Radar([0.0, 0.0], 1.0, 1.0, azimuth_bias=math.nan)


# --------------------------------------------------------------------------- simulate_radars


def test_every_target_every_scan_with_full_coverage() -> None:
    radars = [Radar([0.0, 0.0], 100.0, 0.01), Radar([100e3, 0.0], 100.0, 0.01, 0.05)]
    m = simulate_radars(radars, TARGETS, SCANS, seed=1)
    assert len(m) == 2 * 3 * 12
    for j in range(2):
        for t in SCANS:
            assert sorted(m.truth[(m.radar == j) & (m.time == t)].tolist()) == [0, 1, 2]
    # Sorted by (time, radar), shuffled within a scan so that rows do not follow the truth.
    key = m.time * 10 + m.radar
    assert np.all(np.diff(key) >= 0)
    assert any(m.truth[k * 3 : k * 3 + 3].tolist() != [0, 1, 2] for k in range(24))
    assert np.all((m.azimuth > -math.pi) & (m.azimuth <= math.pi))
    assert m.radars == tuple(radars) and m.truth.dtype == np.int64 and m.radar.dtype == np.int64


def test_simulation_is_determined_by_the_seed() -> None:
    radars = [Radar([0.0, 0.0], 500.0, 0.01, 0.02), Radar([50e3, 50e3], 800.0, 0.02)]
    a = simulate_radars(radars, TARGETS, SCANS, seed=7, pd=0.7)
    b = simulate_radars(radars, TARGETS, SCANS, seed=np.random.default_rng(7), pd=0.7)
    c = simulate_radars(radars, TARGETS, SCANS, seed=8, pd=0.7)
    assert _same(_columns(a), _columns(b)) and not _same(_columns(a), _columns(c))
    with pytest.raises(TypeError, match=r"^seed: expected an int"):
        simulate_radars(radars, TARGETS, SCANS, seed=None)  # type: ignore[arg-type]


@pytest.mark.parametrize("bias", [0.0, 0.087, -0.05, 3.0])
def test_bias_rotates_the_picture_about_the_radar(bias: float) -> None:
    radar = Radar([30e3, -20e3], sigma_range=0.0, sigma_azimuth=0.0, azimuth_bias=bias)
    m = simulate_radars([radar], TARGETS, SCANS, seed=3)
    truth = true_positions(TARGETS, SCANS)[m.truth, np.searchsorted(SCANS, m.time)]
    seen = m.to_cartesian()
    np.testing.assert_allclose(_rotate(seen, radar.position, -bias), truth, atol=1e-6)
    # Distances to the radar are kept, positions move with the rotation (unless bias = 0).
    np.testing.assert_allclose(np.linalg.norm(seen - radar.position, axis=1), m.range)
    assert (np.abs(seen - truth).max() > 1e3) == (bias != 0.0)


def test_noise_has_the_radar_stds() -> None:
    radar = Radar([0.0, 0.0], sigma_range=700.0, sigma_azimuth=0.01, azimuth_bias=0.1)
    target = [ConstantVelocityTarget([100e3, 0.0, 0.0, 0.0])]
    m = simulate_radars([radar], target, np.arange(4000.0), seed=5)
    assert m.range.std() == pytest.approx(700.0, rel=0.05) and m.range.mean() == pytest.approx(100e3, abs=40)
    assert m.azimuth.std() == pytest.approx(0.01, rel=0.05) and m.azimuth.mean() == pytest.approx(0.1, abs=1e-3)
    # The converted covariance at azimuth ~0.1: the spread of the Cartesian reports.
    cov = m.cartesian_covariance()
    np.testing.assert_allclose(np.cov(m.to_cartesian().T), cov.mean(axis=0), rtol=0.1, atol=0.05 * cov[0, 1, 1])


def test_cartesian_covariance_along_the_axes() -> None:
    m = RadarMeasurements(
        np.array([0, 0]), np.zeros(2), np.array([1e4, 2e4]), np.array([0.0, math.pi / 2]), np.array([0, 1]),
        (Radar([5.0, 5.0], 100.0, 0.01),),
    )  # fmt: skip
    np.testing.assert_allclose(m.cartesian_covariance()[0], np.diag([100.0**2, (1e4 * 0.01) ** 2]))
    np.testing.assert_allclose(m.cartesian_covariance()[1], np.diag([(2e4 * 0.01) ** 2, 100.0**2]), atol=1e-6)
    np.testing.assert_allclose(m.to_cartesian(), [[1e4 + 5, 5.0], [5.0, 2e4 + 5]], atol=1e-9)
    assert len(m.select([1])) == 1 and m.select(m.truth == 0).range.tolist() == [1e4]
    with pytest.raises(ValueError, match=r"^indices: boolean mask has shape \(1,\)"):
        m.select([True])
    with pytest.raises(ValueError, match=r"^indices: out of range for 2 reports"):
        m.select([2])


def test_coverage_and_detection_probability() -> None:
    radar = Radar([0.0, 0.0], 100.0, 0.01, coverage_radius=60e3)
    m = simulate_radars([radar], TARGETS, SCANS, seed=2)
    truth = true_positions(TARGETS, SCANS)
    covered = radar.covers(truth)
    assert 0 < covered.sum() < covered.size and len(m) == covered.sum()
    for k in range(3):  # each target is reported exactly at the scans it is covered
        assert m.time[m.truth == k].tolist() == SCANS[covered[k]].tolist()
    assert len(simulate_radars([radar], TARGETS, SCANS, seed=2, pd=0.0)) == 0
    many = simulate_radars([Radar([0.0, 0.0], 1.0, 0.01)], TARGETS, np.arange(1000.0), seed=2, pd=0.3)
    assert len(many) == pytest.approx(0.3 * 3000, rel=0.1)


def test_simulate_radars_rejects_bad_input() -> None:
    radar = Radar([0.0, 0.0], 1.0, 0.01)
    with pytest.raises(ValueError, match=r"^radars: need at least 1"):
        simulate_radars([], TARGETS, SCANS, seed=0)
    with pytest.raises(TypeError, match=r"^radars\[0\]: expected a Radar"):
        simulate_radars([object()], TARGETS, SCANS, seed=0)  # type: ignore[list-item]
    with pytest.raises(ValueError, match=r"^targets\[0\]: is 3-D"):
        simulate_radars([radar], [ConstantVelocityTarget(np.zeros(6))], SCANS, seed=0)
    with pytest.raises(ValueError, match=r"^scan_times\[2\] = 1\.0; scan times must increase"):
        simulate_radars([radar], TARGETS, [0.0, 1.0, 1.0], seed=0)
    with pytest.raises(ValueError, match=r"^pd: must be in \[0, 1\]"):
        simulate_radars([radar], TARGETS, SCANS, seed=0, pd=1.5)


# --------------------------------------------------------------------------- targets


def test_line_abreast_formation_geometry() -> None:
    heading = math.radians(30.0)
    formation = line_abreast_formation(5, [1e3, 2e3], heading, spacing=20e3, speed=340.0, t0=100.0)
    positions = true_positions(formation, [100.0, 400.0])  # (5, 2, 2)
    steps = np.diff(positions, axis=0)
    np.testing.assert_allclose(np.linalg.norm(steps, axis=2), 20e3)
    direction = np.array([math.cos(heading), math.sin(heading)])
    np.testing.assert_allclose(steps @ direction, 0.0, atol=1e-9)  # abreast: the line is across the heading
    np.testing.assert_allclose(positions[:, 0].mean(axis=0), [1e3, 2e3])  # centred at t0
    np.testing.assert_allclose(positions[0, 1] - positions[0, 0], 300.0 * 340.0 * direction)
    left = np.array([-direction[1], direction[0]])
    assert (positions[0, 0] - positions[4, 0]) @ left == pytest.approx(80e3)  # left wing first


def test_scattered_targets() -> None:
    targets = scattered_targets(50, [[0.0, 10e3], [-5e3, 5e3]], (320.0, 360.0), rng=4, t0=30.0)
    start = true_positions(targets, [30.0])[:, 0]
    speed = np.array([np.linalg.norm(t.initial_state[2:]) for t in targets])
    assert len(targets) == 50 and np.all((start[:, 0] >= 0) & (start[:, 0] <= 10e3))
    assert np.all(np.abs(start[:, 1]) <= 5e3) and np.all((speed >= 320.0) & (speed <= 360.0))
    again = scattered_targets(50, [[0.0, 10e3], [-5e3, 5e3]], (320.0, 360.0), rng=4, t0=30.0)
    assert all(np.array_equal(a.initial_state, b.initial_state) for a, b in zip(targets, again, strict=True))
    with pytest.raises(ValueError, match=r"^area: expected \[\[x_min, x_max\]"):
        scattered_targets(1, [[1.0, 0.0], [0.0, 1.0]], (1.0, 2.0), rng=0)


# --------------------------------------------------------------------------- topology scenario


def test_topology_scenario_layout() -> None:
    s = paper_topology_scenario(11, bias_deg=5.0)
    positions = np.array([r.position for r in s.radars])
    radius = np.linalg.norm(positions, axis=1)
    assert len(s.radars) == 8 and np.all((radius >= 200e3) & (radius <= 260e3))
    bearing = np.sort(np.arctan2(positions[:, 1], positions[:, 0]))
    np.testing.assert_allclose(np.diff(bearing), math.pi / 4)
    assert np.all(np.abs(s.true_biases) <= math.radians(5.0)) and np.ptp(s.true_biases) > math.radians(1.0)
    sigma_az = np.degrees([r.sigma_azimuth for r in s.radars])
    sigma_r = np.array([r.sigma_range for r in s.radars])
    assert np.all((sigma_az >= 0.5) & (sigma_az <= 1.0)) and np.all((sigma_r >= 500) & (sigma_r <= 1000))
    assert s.scan_times.tolist() == (np.arange(90) * 10.0).tolist()  # 15 minutes of 10 s scans
    assert len(s.targets) == 20 and s.true_positions.shape == (20, 90, 2)
    assert s.formation.tolist() == [-1] * 5 + [0] * 5 + [1] * 5 + [2] * 5
    assert len(s.measurements) == 8 * 20 * 90 and s.in_coverage.all()  # full coverage


def test_topology_formations_fly_abreast() -> None:
    s = paper_topology_scenario(12)
    for f in range(3):
        members = np.flatnonzero(s.formation == f)
        gaps = np.linalg.norm(np.diff(s.true_positions[members], axis=0), axis=2)
        np.testing.assert_allclose(gaps, 20e3)  # 20 km apart at every scan
        velocity = np.array([s.targets[k].initial_state[2:] for k in members])
        assert np.all(velocity == velocity[0]) and 320.0 <= np.linalg.norm(velocity[0]) <= 360.0
    speeds = [np.linalg.norm(s.targets[k].initial_state[2:]) for k in range(5)]
    assert all(320.0 <= v <= 360.0 for v in speeds)


def test_topology_measurements_carry_each_radar_bias_and_noise() -> None:
    s = paper_topology_scenario(13, bias_deg=3.0)
    m = s.measurements
    truth = s.true_positions[m.truth, np.searchsorted(s.scan_times, m.time)]
    for j, radar in enumerate(s.radars):
        rows = m.radar == j
        offset = truth[rows] - radar.position
        azimuth_error = wrap_angle(m.azimuth[rows] - np.arctan2(offset[:, 1], offset[:, 0]))
        range_error = m.range[rows] - np.linalg.norm(offset, axis=1)
        assert rows.sum() == 20 * 90
        # Mean azimuth error = the bias (to 4 standard errors), spread = the radar's noise.
        assert abs(azimuth_error.mean() - radar.azimuth_bias) < 4 * radar.sigma_azimuth / math.sqrt(1800)
        assert azimuth_error.std() == pytest.approx(radar.sigma_azimuth, rel=0.1)
        assert abs(range_error.mean()) < 4 * radar.sigma_range / math.sqrt(1800)
        assert range_error.std() == pytest.approx(radar.sigma_range, rel=0.1)


def test_topology_scenario_is_reproducible_and_shares_draws_across_bias_levels() -> None:
    a, b = paper_topology_scenario(21), paper_topology_scenario(21)
    assert _same(_columns(a.measurements), _columns(b.measurements))
    assert np.array_equal(a.true_positions, b.true_positions) and np.array_equal(a.true_biases, b.true_biases)
    zero = paper_topology_scenario(21, bias_deg=0.0)
    assert np.all(zero.true_biases == 0.0) and np.array_equal(zero.true_positions, a.true_positions)
    np.testing.assert_allclose(paper_topology_scenario(21, bias_deg=1.0).true_biases, a.true_biases / 5.0)
    assert not np.array_equal(paper_topology_scenario(22).true_positions, a.true_positions)


def test_topology_partial_coverage() -> None:
    full = paper_topology_scenario(31)
    s = paper_topology_scenario(31, coverage="partial")
    assert np.array_equal(s.true_positions, full.true_positions)  # the same run, fewer reports
    assert all(r.coverage_radius == PARTIAL_COVERAGE_RADIUS for r in s.radars)
    covered = s.in_coverage
    assert 0.6 < covered.mean() < 0.95 and len(s.measurements) == covered.sum() < len(full.measurements)
    assert (~covered).any(axis=2).any(axis=0).sum() >= 5  # several targets go unseen by some radar
    assert covered.sum(axis=0).min() >= 1  # yet every target is seen by someone at every scan
    m = s.measurements
    truth = s.true_positions[m.truth, np.searchsorted(s.scan_times, m.time)]
    radar_xy = np.array([r.position for r in s.radars])[m.radar]
    assert np.all(np.linalg.norm(truth - radar_xy, axis=1) <= PARTIAL_COVERAGE_RADIUS)


def test_topology_scenario_rejects_bad_options() -> None:
    with pytest.raises(ValueError, match=r"^coverage: expected 'full' or 'partial'"):
        paper_topology_scenario(0, coverage="some")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^bias_deg: must be >= 0"):
        paper_topology_scenario(0, bias_deg=-1.0)
    with pytest.raises(ValueError, match=r"^scan_period: must be > 0"):
        paper_topology_scenario(0, scan_period=0.0)


# --------------------------------------------------------------------------- radar/ESM scenario


def test_wavelet_accelerations_per_phase() -> None:
    s = paper_wavelet_scenario(1)
    a, v, x = s.true_acceleration[..., 0], s.true_velocity[..., 0], s.true_position[..., 0]
    assert a.shape == (10, 30) and s.scan_times.tolist() == list(np.arange(30.0))
    assert np.all(a[:, :5] == 0.0)  # scans 1–5
    assert np.all(a[:, 5:20] == PAPER_WAVELET_TARGETS[:, [2]])  # scans 6–20
    assert np.all(a[:, 20:] == PAPER_WAVELET_TARGETS[:, [3]])  # scans 21–30
    assert a[0, 5] == 10.0 and a[5, 29] == -80.0  # T1 in phase 2, T6 in phase 3
    np.testing.assert_allclose(v[:, 5], PAPER_WAVELET_TARGETS[:, 0])  # no acceleration before scan 6
    np.testing.assert_allclose(v[:, 20], PAPER_WAVELET_TARGETS[:, 0] + 15 * PAPER_WAVELET_TARGETS[:, 2])
    np.testing.assert_allclose(np.diff(x, axis=1), v[:, :-1] + 0.5 * a[:, :-1])  # exact kinematics, T = 1 s
    assert np.all((x[:, 0] >= 0.0) & (x[:, 0] <= 20e3))


@pytest.mark.parametrize("n_clutter", [0, 2, 5])
def test_wavelet_measurements(n_clutter: int) -> None:
    s = paper_wavelet_scenario(2, n_clutter=n_clutter)
    m = s.measurements
    n_tracks = 10 + n_clutter
    assert len(m) == 2 * n_tracks * 30 and m.ndim == 1 and m.sources.tolist() == [0, 1]
    assert m.truth is not None and np.sum(m.truth == -1) == 2 * n_clutter * 30
    tracks = list(m.tracks())
    assert len(tracks) == 2 * n_tracks and all(rows.size == 30 for _, _, rows in tracks)
    # Ids are shuffled: within a source they are 0..n-1 but not the truth order.
    labels = [int(m.truth[rows[0]]) for _, _, rows in tracks]
    assert labels != sorted(labels) and sorted(t for s_, t, _ in tracks if s_ == 0) == list(range(n_tracks))
    for _, _, rows in tracks:
        assert np.all(m.truth[rows] == m.truth[rows[0]])  # one label per track
    target_rows = np.flatnonzero(m.truth >= 0)
    error = m.position[target_rows, 0] - s.true_position[m.truth[target_rows], m.time[target_rows].astype(int), 0]
    assert error.std() == pytest.approx(math.sqrt(0.5e6), rel=0.1)  # 0.5 km² = 5e5 m²
    assert m.covariance is not None and np.all(m.covariance == 0.5e6)


def test_wavelet_scenario_is_reproducible() -> None:
    a, b = paper_wavelet_scenario(5, n_clutter=2), paper_wavelet_scenario(5, n_clutter=2)
    assert a.measurements == b.measurements and np.array_equal(a.true_position, b.true_position)
    assert a.measurements != paper_wavelet_scenario(6, n_clutter=2).measurements


def test_wavelet_in_two_dimensions() -> None:
    s = paper_wavelet_scenario(3, ndim=2, n_clutter=1)
    assert s.ndim == 2 and s.measurements.ndim == 2 and s.true_position.shape == (10, 30, 2)
    speed0 = np.linalg.norm(s.true_velocity[:, 0], axis=1)
    np.testing.assert_allclose(speed0, np.abs(PAPER_WAVELET_TARGETS[:, 0]))
    accel = s.true_acceleration[:, 10]
    np.testing.assert_allclose(np.linalg.norm(accel, axis=1), np.abs(PAPER_WAVELET_TARGETS[:, 2]))
    cross = s.true_velocity[:, 10, 0] * accel[:, 1] - s.true_velocity[:, 10, 1] * accel[:, 0]
    np.testing.assert_allclose(cross, 0.0, atol=1e-6)  # accelerating along the track's line
    with pytest.raises(ValueError, match=r"^ndim: expected 1 \(the paper's x axis\) or 2"):
        paper_wavelet_scenario(0, ndim=3)
    with pytest.raises(ValueError, match=r"^noise_variance: must be >= 0"):
        paper_wavelet_scenario(0, noise_variance=-1.0)
