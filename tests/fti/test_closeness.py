"""The public closeness API (METHODS §1 eq. 17–19)."""

from __future__ import annotations

import numpy as np
import passive_assoc as pa
import pytest


@pytest.fixture(scope="module")
def scenario() -> pa.Scenario:
    return pa.paper_fti_scenario(seed=21)


def test_closeness_matches_eq_17_18_and_its_gradient(scenario: pa.Scenario) -> None:
    m, sensors = scenario.measurements, scenario.sensors
    x = scenario.true_states + np.array([30.0, -40.0, 20.0, 0.5, -0.3, 0.1])
    r, g = pa.closeness(m, sensors, x)
    # eq. 17-18 written out directly.
    for k in range(len(x)):
        s = sensors.positions[m.sensor]
        d = x[k, :3] + m.time[:, None] * x[k, 3:] - s
        da = np.angle(np.exp(1j * (m.azimuth - np.arctan2(d[:, 1], d[:, 0])))) / 0.01
        de = np.angle(np.exp(1j * (m.elevation - np.arctan2(d[:, 2], np.hypot(d[:, 0], d[:, 1]))))) / 0.01
        assert r[k] == pytest.approx(np.mean(0.5 * np.exp(-(da**2)) + 0.5 * np.exp(-(de**2))), rel=1e-12)
        for c in range(6):
            h = 1e-3 * max(1.0, abs(x[k, c])) * 1e-2
            up, down = x[k].copy(), x[k].copy()
            up[c] += h
            down[c] -= h
            numeric = (pa.closeness(m, sensors, up[None])[0][0] - pa.closeness(m, sensors, down[None])[0][0]) / (2 * h)
            assert g[k, c] == pytest.approx(numeric, rel=1e-4, abs=1e-12)


def test_search_climbs_to_a_maximum_near_each_target(scenario: pa.Scenario) -> None:
    m, sensors = scenario.measurements, scenario.sensors
    fit = pa.fit_ml(m, sensors, scenario.true_groups())
    starts = fit.estimates + np.sqrt(np.diagonal(fit.covariances, axis1=1, axis2=2))  # one sd off
    one = pa.maximize_closeness(m, sensors, starts, fit.covariances, n_threads=1)
    two = pa.maximize_closeness(m, sensors, starts, fit.covariances, n_threads=2)
    np.testing.assert_array_equal(one.states, two.states)
    assert np.all(one.closeness > pa.closeness(m, sensors, starts)[0])
    _, grad = pa.closeness(m, sensors, one.states)
    lower = np.linalg.cholesky(fit.covariances)
    scaled = np.einsum("kji,kj->ki", lower, grad)  # gradient in whitened coordinates
    assert np.all(np.abs(scaled) < 1e-2 * one.closeness[:, None])
    sd = np.sqrt(np.diagonal(fit.covariances, axis1=1, axis2=2))
    assert np.all(np.abs(one.states - scenario.true_states) < 4 * sd)


def test_closeness_bad_input(scenario: pa.Scenario) -> None:
    m, sensors = scenario.measurements, scenario.sensors
    with pytest.raises(ValueError, match="states: expected shape"):
        pa.closeness(m, sensors, np.zeros((2, 4)))
    with pytest.raises(ValueError, match="states"):
        pa.closeness(m, sensors, np.full((1, 6), np.nan))
    with pytest.raises(ValueError, match="spread_factor"):
        pa.closeness(m, sensors, scenario.true_states, spread_factor=0.0)
    with pytest.raises(ValueError, match="covariances: matrix 0 is not positive definite"):
        pa.maximize_closeness(m, sensors, scenario.true_states[:1], -np.eye(6)[None])
    with pytest.raises(ValueError, match="covariances: expected shape"):
        pa.maximize_closeness(m, sensors, scenario.true_states[:2], np.eye(6)[None])
    with pytest.raises(ValueError, match="scaling"):
        pa.maximize_closeness(m, sensors, scenario.true_states[:1], np.eye(6)[None], scaling="newton")


def test_the_default_epoch_is_the_earliest_time() -> None:
    """UNIX-epoch times: states at the first scan give the R they give on the same table with
    times from 0 (t0 from the data, as everywhere)."""
    scenario = pa.paper_fti_scenario(seed=2)
    columns = scenario.measurements.to_arrays()
    columns["time"] = columns["time"] + 1.7e9
    shifted = pa.MeasurementTable.from_columns(columns)
    r0, g0 = pa.closeness(scenario.measurements, scenario.sensors, scenario.true_states)
    r1, g1 = pa.closeness(shifted, scenario.sensors, scenario.true_states)
    np.testing.assert_allclose(r1, r0, rtol=1e-9)
    np.testing.assert_allclose(g1, g0, rtol=1e-6, atol=1e-12)
    away = scenario.true_states + np.array([1000.0, 0, 0, 0, 0, 0])
    assert np.all(r0 > pa.closeness(shifted, scenario.sensors, away)[0])  # R falls away from the truth
