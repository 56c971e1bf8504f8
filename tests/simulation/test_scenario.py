"""Tests of the scenario simulator (the paper-000 scenario's own spec is in test_fti)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from passive_assoc.data import SensorNetwork
from passive_assoc.simulation import (
    ConstantVelocityTarget,
    bearing_only_2d_scenario,
    paper_fti_scenario,
    simulate,
    wrap_angle,
)


def _bitwise(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> bool:
    return a.keys() == b.keys() and all(a[k].tobytes() == b[k].tobytes() for k in a)


def _geometry(scen) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
    """Noise-free az/el of every target row, computed independently of the simulator."""
    m = scen.measurements
    rows = np.flatnonzero(m.truth >= 0)
    az, el = [], []
    for r in rows:
        tg = scen.targets[m.truth[r]]
        p = np.zeros(3)
        p[: tg.ndim] = tg.position(m.time[r])
        d = p - scen.sensors.positions[m.sensor[r]]
        az.append(math.atan2(d[1], d[0]))
        el.append(math.atan2(d[2], math.hypot(d[0], d[1])))
    return rows, np.array(az), np.array(el)


@given(st.floats(-1e6, 1e6))
def test_wrap_angle_range(x: float) -> None:
    w = float(wrap_angle(x))
    assert -math.pi < w <= math.pi
    assert abs(math.remainder(w - x, 2 * math.pi)) < 1e-6


def test_wrap_angle_edges() -> None:
    out = wrap_angle([math.pi, -math.pi, 0.0, 3 * math.pi]).tolist()
    assert out == [math.pi, math.pi, 0.0, math.pi]


def test_constant_velocity_target() -> None:
    tg = ConstantVelocityTarget([1.0, 2.0, 3.0, 10.0, -1.0, 0.5], t0=2.0)
    assert tg.ndim == 3
    assert tg.position(4.0).tolist() == [21.0, 0.0, 4.0]
    assert tg.position([2.0, 3.0]).shape == (2, 3)
    assert tg.state_at(0.0).tolist() == [-19.0, 4.0, 2.0, 10.0, -1.0, 0.5]
    assert ConstantVelocityTarget([0.0, 0.0, 1.0, 1.0]).position(2.0).tolist() == [2.0, 2.0]
    with pytest.raises(ValueError, match=r"^initial_state: expected shape \(6,\)"):
        ConstantVelocityTarget([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match=r"^initial_state\[1\] = nan"):
        ConstantVelocityTarget([0.0, np.nan, 0.0, 0.0])


def test_rows_sorted_and_shuffled_within_scan() -> None:
    m = paper_fti_scenario(seed=3).measurements
    key = m.time * 10 + m.sensor
    assert np.all(np.diff(key) >= 0)  # sorted by (time, sensor)
    # Within a scan rows must not be truth-ordered (targets first, clutter last) every time.
    scans = set(zip(m.time, m.sensor, strict=True))
    firsts = [m.truth[(m.time == t) & (m.sensor == s)][0] for t, s in scans]
    assert min(firsts) == -1 and max(firsts) >= 0


def test_reproducible_and_seed_dependent() -> None:
    a = paper_fti_scenario(seed=42).measurements.to_arrays()
    b = paper_fti_scenario(seed=42).measurements.to_arrays()
    c = paper_fti_scenario(seed=43).measurements.to_arrays()
    assert _bitwise(a, b)
    assert not np.array_equal(a["azimuth"], c["azimuth"])
    d2 = bearing_only_2d_scenario(seed=7)
    e2 = bearing_only_2d_scenario(seed=7)
    assert _bitwise(d2.measurements.to_arrays(), e2.measurements.to_arrays())
    assert np.array_equal(d2.true_states, e2.true_states)
    assert not np.array_equal(d2.true_states, bearing_only_2d_scenario(seed=8).true_states)


def test_noiseless_angles_match_geometry_3d() -> None:
    scen = paper_fti_scenario(seed=0, sigma=1e-12)
    rows, az, el = _geometry(scen)
    assert rows.size == 64
    assert np.allclose(scen.measurements.azimuth[rows], az, atol=1e-10, rtol=0)
    assert np.allclose(scen.measurements.elevation[rows], el, atol=1e-10, rtol=0)


def test_noiseless_angles_match_geometry_2d() -> None:
    scen = bearing_only_2d_scenario(seed=5, sigma=1e-12, n_targets=4, n_sensors=4, offset=2.0)
    m = scen.measurements
    assert m.ndim == 2 and scen.sensors.ndim == 2 and np.all(np.isnan(m.elevation))
    rows, az, _ = _geometry(scen)
    assert rows.size == 4 * 4 * 8
    assert np.allclose(m.azimuth[rows], az, atol=1e-10, rtol=0)
    assert scen.scan_times[3][0] == 6.0  # sensor j offset by j * offset
    assert np.allclose(scen.sensors.positions[:, 0], [-15e3, -5e3, 5e3, 15e3])
    x0, y0 = scen.true_states[:, 0], scen.true_states[:, 1]
    assert np.all((np.abs(x0) <= 10e3) & (y0 >= 20e3) & (y0 <= 40e3))
    m.validate_against(scen.sensors)


def test_noise_has_the_configured_std() -> None:
    scen = paper_fti_scenario(seed=11, n_scans=200, clutter_ratio=0.0)
    rows, az, el = _geometry(scen)
    res_az = wrap_angle(scen.measurements.azimuth[rows] - az)
    res_el = scen.measurements.elevation[rows] - el
    # 1600 samples: the sample std is within ~2 % of sigma with overwhelming probability.
    for res in (res_az, res_el):
        assert abs(res.std() / 5e-3 - 1) < 0.1 and abs(res.mean()) < 5 * 5e-3 / 40


def test_detection_probability_binomial() -> None:
    scen = paper_fti_scenario(seed=123, pd=0.5, n_scans=100)
    n_trials = 2 * 100 * 4
    k = int(np.sum(scen.measurements.truth >= 0))
    assert abs(k - n_trials / 2) < 5 * math.sqrt(n_trials / 4)  # 5-sigma binomial bound
    # Clutter does not depend on pd.
    assert np.sum(scen.measurements.truth == -1) == 2 * 100 * 8
    assert np.sum(paper_fti_scenario(seed=1, pd=0.0).measurements.truth >= 0) == 0


def test_clutter_rate_poisson_and_fixed_count() -> None:
    net = SensorNetwork.planar([[0, 0], [1000, 0]], 0.01)
    times = [np.arange(500.0), np.arange(500.0)]
    scen = simulate(net, [], times, clutter_rate=3.0, seed=9)
    counts = np.bincount(np.searchsorted(np.arange(500.0), scen.measurements.time), minlength=500)
    assert abs(counts.mean() / 2 - 3.0) < 5 * math.sqrt(3.0 / 1000)
    assert counts.var() > 0  # really random, not a fixed count
    fixed = simulate(net, [], times, clutter_per_scan=2, azimuth_window=(-1.0, -0.5), seed=9)
    assert len(fixed.measurements) == 2 * 500 * 2
    az = fixed.measurements.azimuth
    assert np.all((az >= -1.0) & (az <= -0.5))
    none = simulate(net, [], times, seed=9)
    assert len(none.measurements) == 0


def test_simulate_rejects_bad_arguments() -> None:
    net = SensorNetwork.planar([[0, 0], [1000, 0]], 0.01)
    tg2 = [ConstantVelocityTarget([0, 1e4, 10, 0])]
    times = [np.arange(3.0)] * 2
    with pytest.raises(ValueError, match=r"^clutter_per_scan: give clutter_per_scan or"):
        simulate(net, tg2, times, clutter_per_scan=1, clutter_rate=1.0, seed=0)
    with pytest.raises(ValueError, match=r"^clutter_per_scan: must be >= 0"):
        simulate(net, tg2, times, clutter_per_scan=-1, seed=0)
    with pytest.raises(TypeError, match=r"^clutter_per_scan: expected an int"):
        simulate(net, tg2, times, clutter_per_scan=1.5, seed=0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^clutter_rate: must be >= 0"):
        simulate(net, tg2, times, clutter_rate=-0.1, seed=0)
    with pytest.raises(ValueError, match=r"^clutter_rate = inf; must be finite"):
        simulate(net, tg2, times, clutter_rate=math.inf, seed=0)
    with pytest.raises(ValueError, match=r"^pd: must be in \[0, 1\]"):
        simulate(net, tg2, times, pd=1.5, seed=0)
    with pytest.raises(TypeError, match=r"^seed: expected an int"):
        simulate(net, tg2, times, seed=None)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^scan_times: expected one array per sensor \(2\)"):
        simulate(net, tg2, times[:1], seed=0)
    with pytest.raises(ValueError, match=r"^scan_times\[1\]\[0\] = nan"):
        simulate(net, tg2, [np.arange(3.0), [np.nan]], seed=0)
    with pytest.raises(ValueError, match=r"^targets\[0\]: is 3-D but the sensor network is 2-D"):
        simulate(net, [ConstantVelocityTarget(np.zeros(6))], times, seed=0)
    with pytest.raises(TypeError, match=r"^targets\[0\]: expected a ConstantVelocityTarget"):
        simulate(net, [np.zeros(4)], times, seed=0)  # type: ignore[list-item]
    with pytest.raises(ValueError, match=r"^azimuth_window: expected \(low, high\)"):
        simulate(net, tg2, times, azimuth_window=(1.0, 0.0), seed=0)
    with pytest.raises(TypeError, match=r"^sensors: expected a SensorNetwork"):
        simulate("net", tg2, times, seed=0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^scan_period: must be > 0"):
        paper_fti_scenario(seed=0, scan_period=0.0)
    with pytest.raises(ValueError, match=r"^n_scans: must be >= 1"):
        bearing_only_2d_scenario(seed=0, n_scans=0)


def test_generator_seed_is_accepted() -> None:
    a = paper_fti_scenario(seed=np.random.default_rng(5)).measurements
    b = paper_fti_scenario(seed=5).measurements
    assert _bitwise(a.to_arrays(), b.to_arrays())
