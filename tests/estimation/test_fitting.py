"""Batched Gauss-Newton ML fitting and the CRLB (issue: foundation)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import passive_assoc as pa
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

#: The conftest fixture: exact angles of a CV target, (sensors, state, times, which) -> table.
NoiselessTable = Callable[[pa.SensorNetwork, np.ndarray, np.ndarray, np.ndarray], pa.MeasurementTable]


def _spatial_pair() -> pa.SensorNetwork:
    return pa.SensorNetwork.spatial([[0, 0, 0], [20e3, 0, 0], [5e3, -8e3, 50]], 5e-3, 5e-3)


@pytest.mark.parametrize("motion", ["cv", "static"])
@pytest.mark.parametrize("ndim", [2, 3])
def test_noiseless_fit_recovers_truth(motion: str, ndim: int, noiseless_table: NoiselessTable) -> None:
    if ndim == 3:
        sensors = _spatial_pair()
        state = np.array([1340.0, 15000.0, 1000.0, 173.2, -100.0, 0.0])
    else:
        sensors = pa.SensorNetwork.planar([[0, 0], [20e3, 0], [5e3, -8e3]], 5e-3)
        state = np.array([1340.0, 15000.0, 173.2, -100.0])
    if motion == "static":
        state[ndim:] = 0.0
    times = np.repeat(np.arange(8) * 15.0, 3) + np.tile([0.0, 5.0, 7.0], 8)
    which = np.tile([0, 1, 2], 8)
    table = noiseless_table(sensors, state, times, which)
    truth = state if motion == "cv" else state[:ndim]
    start = truth * 1.03 + 50.0  # a poor start, not the pseudo-linear one
    for initial in (None, start[None, :]):
        fit = pa.fit_ml(table, sensors, np.arange(len(table)), motion=motion, initial=initial)
        assert fit.termination_names() == ["converged"]
        np.testing.assert_allclose(fit.estimates[0], truth, rtol=1e-8, atol=1e-8 * np.abs(truth).max())
        assert fit.chi2[0] < 1e-10


def test_paper_targets_with_perfect_association() -> None:
    sc = pa.paper_fti_scenario(seed=3)
    fit = pa.fit_ml(sc.measurements, sc.sensors, sc.true_groups())
    assert fit.converged.all()
    err = fit.estimates - sc.true_states
    bounds = np.array([np.sqrt(np.diag(_target_crlb(sc, k))) for k in range(4)])
    assert (np.abs(err) < 5 * bounds).all()


def _target_crlb(sc: pa.Scenario, k: int) -> np.ndarray:
    rows = sc.true_groups()[k]
    m = sc.measurements
    return pa.crlb(m.sensor[rows], m.time[rows], sc.sensors, sc.true_states[k])


def test_monte_carlo_rms_is_within_15_percent_of_crlb() -> None:
    """≥ 200 runs of the paper-000 geometry with perfect association (issue acceptance)."""
    runs = 200
    errors = np.empty((runs, 4, 6))
    for r in range(runs):
        sc = pa.paper_fti_scenario(seed=10_000 + r, clutter_ratio=0.0)
        fit = pa.fit_ml(sc.measurements, sc.sensors, sc.true_groups())
        assert fit.converged.all()
        errors[r] = fit.estimates - sc.true_states
    rms = np.sqrt((errors**2).mean(axis=0))
    sc = pa.paper_fti_scenario(seed=0, clutter_ratio=0.0)
    crlb_std = np.array([np.sqrt(np.diag(_target_crlb(sc, k))) for k in range(4)])
    ratio = rms / crlb_std
    assert np.all(np.abs(ratio - 1.0) <= 0.15), np.array2string(ratio, precision=3)


def test_thread_count_does_not_change_results() -> None:
    sc = pa.paper_fti_scenario(seed=5)
    rng = np.random.default_rng(0)
    groups = rng.integers(0, len(sc.measurements), size=(2000, 4))
    m = sc.measurements
    # Starts near the first group member's line of sight keep most fits meaningful.
    initial = np.tile(sc.true_states[0], (2000, 1)) + rng.normal(0, 100, (2000, 6))
    one = pa.fit_ml(m, sc.sensors, groups, initial=initial, n_threads=1)
    two = pa.fit_ml(m, sc.sensors, groups, initial=initial, n_threads=2)
    for a, b in zip(
        (one.estimates, one.covariances, one.chi2, one.iterations, one.termination),
        (two.estimates, two.covariances, two.chi2, two.iterations, two.termination),
        strict=True,
    ):
        np.testing.assert_array_equal(a, b)


def test_fisher_and_crlb_are_inverse() -> None:
    sc = pa.paper_fti_scenario(seed=1)
    rows = sc.true_groups()[2]
    info, bound = pa.fisher_and_crlb(
        sc.measurements.sensor[rows], sc.measurements.time[rows], sc.sensors, sc.true_states[2]
    )
    np.testing.assert_allclose(info @ bound, np.eye(6), atol=1e-8)
    np.testing.assert_allclose(bound, bound.T, rtol=1e-10)


def test_degenerate_group_gets_a_status_not_an_exception() -> None:
    sensors = _spatial_pair()
    table = pa.MeasurementTable.from_arrays([0, 0, 0], [0.0, 1.0, 2.0], [0.3, 0.3, 0.3], [0.1, 0.1, 0.1])
    fit = pa.fit_ml(table, sensors, [np.arange(3)], motion="static")
    assert fit.termination_names() == ["singular"]
    assert np.isnan(fit.estimates).all()


# --- hypothesis properties -------------------------------------------------------------------

coordinate = st.floats(-30e3, 30e3)


def _random_problem(
    seed: int, noiseless_table: NoiselessTable
) -> tuple[pa.SensorNetwork, pa.MeasurementTable, np.ndarray]:
    rng = np.random.default_rng(seed)
    positions = rng.uniform(-20e3, 20e3, (3, 3)) * [1, 1, 0.01]
    sensors = pa.SensorNetwork.spatial(positions, 2e-3, 2e-3)
    state = np.concatenate(
        [rng.uniform(-15e3, 15e3, 2), [rng.uniform(500, 3000)], rng.uniform(-200, 200, 3) * [1, 1, 0.05]]
    )
    state[:2] += [0, 40e3]  # keep the target away from the sensors
    times = np.repeat(np.arange(6) * 10.0, 3) + np.tile([0.0, 3.0, 6.0], 6)
    which = np.tile([0, 1, 2], 6)
    exact = noiseless_table(sensors, state, times, which)
    az = exact.azimuth + rng.normal(0, 2e-3, len(exact))
    el = exact.elevation + rng.normal(0, 2e-3, len(exact))
    return sensors, pa.MeasurementTable.from_arrays(which, times, az, el), state


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), shift=st.tuples(coordinate, coordinate, st.floats(-500, 500)))
def test_translating_the_geometry_translates_the_estimate(
    seed: int, shift: tuple[float, float, float], noiseless_table: NoiselessTable
) -> None:
    sensors, table, truth = _random_problem(seed, noiseless_table)
    base = pa.fit_ml(table, sensors, [np.arange(len(table))], initial=truth[None])
    moved = pa.SensorNetwork.spatial(sensors.positions + shift, sensors.sigma_azimuth, sensors.sigma_elevation)
    start = truth + np.concatenate([shift, [0, 0, 0]])
    fit = pa.fit_ml(table, moved, [np.arange(len(table))], initial=start[None])
    expected = base.estimates[0] + np.concatenate([shift, [0, 0, 0]])
    np.testing.assert_allclose(fit.estimates[0], expected, rtol=1e-6, atol=1e-4)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), angle=st.floats(-np.pi, np.pi))
def test_rotating_the_geometry_rotates_the_estimate(seed: int, angle: float, noiseless_table: NoiselessTable) -> None:
    sensors, table, truth = _random_problem(seed, noiseless_table)
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    big = np.kron(np.eye(2), rot)
    base = pa.fit_ml(table, sensors, [np.arange(len(table))], initial=truth[None])
    moved = pa.SensorNetwork.spatial(sensors.positions @ rot.T, sensors.sigma_azimuth, sensors.sigma_elevation)
    turned = pa.MeasurementTable.from_arrays(table.sensor, table.time, table.azimuth + angle, table.elevation)
    fit = pa.fit_ml(turned, moved, [np.arange(len(table))], initial=(big @ truth)[None])
    np.testing.assert_allclose(fit.estimates[0], big @ base.estimates[0], rtol=1e-6, atol=1e-4)
    np.testing.assert_allclose(fit.chi2, base.chi2, rtol=1e-6, atol=1e-9)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), perm_seed=st.integers(0, 2**31))
def test_permuting_measurements_changes_nothing(seed: int, perm_seed: int, noiseless_table: NoiselessTable) -> None:
    sensors, table, truth = _random_problem(seed, noiseless_table)
    perm = np.random.default_rng(perm_seed).permutation(len(table))
    base = pa.fit_ml(table, sensors, [np.arange(len(table))], initial=truth[None])
    shuffled = pa.fit_ml(table.select(perm), sensors, [np.arange(len(table))], initial=truth[None])
    regrouped = pa.fit_ml(table, sensors, [perm], initial=truth[None])
    # Summation order differs, so agreement is to rounding within the convergence tolerance:
    # asserted in units of the estimate's own standard deviation.
    sigma = np.sqrt(np.diagonal(base.covariances, axis1=1, axis2=2))
    for other in (shuffled, regrouped):
        assert np.all(np.abs(other.estimates - base.estimates) <= 1e-6 * sigma)
        np.testing.assert_allclose(other.covariances, base.covariances, rtol=1e-6, atol=1e-12)


def test_epoch_times_fit_with_the_default_t0() -> None:
    """UNIX-epoch times: the default epoch is the table's earliest time (an epoch of 0 would
    make the fit singular); the estimates are those of the same data shifted to start at 0."""
    sc = pa.paper_fti_scenario(seed=1)
    rows = [np.flatnonzero(sc.measurements.truth == k) for k in range(4)]
    arrays = sc.measurements.to_arrays()
    arrays["time"] = arrays["time"] + 1.7e9
    shifted = pa.MeasurementTable.from_columns(arrays)
    late = pa.fit_ml(shifted, sc.sensors, rows)
    early = pa.fit_ml(sc.measurements, sc.sensors, rows)
    assert late.t0 == 1.7e9 and early.t0 == 0.0 and bool(late.converged.all())
    np.testing.assert_allclose(late.estimates, early.estimates, rtol=1e-6, atol=1e-3)
