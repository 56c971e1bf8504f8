"""Batched Kalman filtering into local tracks (issues #13, #14): exact on noiseless tracks,
consistent on noisy ones, the same for any thread count, row order and noise spelling."""

from __future__ import annotations

import dataclasses

import numpy as np
import passive_assoc as pa
import pytest
from numpy.typing import NDArray


def _cv_tracks(
    rng: np.random.Generator, n_tracks: int, steps: int, q: float, ndim: int = 2
) -> tuple[NDArray[np.float64], NDArray[np.float64], list[NDArray[np.int64]]]:
    """CV tracks with exact process noise, rows track after track: (times, truth, groups)."""
    times, truth, groups = [], [], []
    for k in range(n_tracks):
        t = np.cumsum(np.concatenate(([rng.uniform(0, 10)], rng.uniform(0.5, 2.0, steps - 1))))
        x = np.concatenate((rng.uniform(-5e3, 5e3, ndim), rng.uniform(-150, 150, ndim)))
        states = [x]
        for dt in np.diff(t):
            f = np.block([[np.eye(ndim), dt * np.eye(ndim)], [np.zeros((ndim, ndim)), np.eye(ndim)]])
            q1 = q * np.array([[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
            w = rng.multivariate_normal(np.zeros(2), q1, size=ndim).T.reshape(-1)
            x = f @ x + w
            states.append(x)
        groups.append(np.arange(k * steps, (k + 1) * steps))
        times.append(t)
        truth.append(np.array(states))
    return np.concatenate(times), np.concatenate(truth), groups


def _nees(result: pa.KalmanResult, truth: NDArray[np.float64]) -> NDArray[np.float64]:
    rows = result.has_state
    err = result.states[rows] - truth[rows]
    return np.einsum("ni,ni->n", err, np.linalg.solve(result.covariances[rows], err[..., None])[..., 0])


def test_noiseless_cv_tracks_are_reproduced_after_the_first_row() -> None:
    rng = np.random.default_rng(1)
    times, truth, groups = _cv_tracks(rng, 4, 12, q=0.0)
    result = pa.KalmanFilter(process_noise=2.0).filter(times, truth[:, :2], groups, noise=10.0)
    firsts = [g[0] for g in groups]
    assert not result.has_state[firsts].any()
    assert result.has_state.sum() == len(times) - len(groups)
    np.testing.assert_allclose(result.states[result.has_state], truth[result.has_state], rtol=1e-9, atol=1e-7)
    assert np.nanmax(result.nis) < 1e-12
    assert result.states.shape == (len(times), 4) and result.covariances.shape == (len(times), 4, 4)


def test_covariance_is_honest_on_noisy_tracks() -> None:
    rng = np.random.default_rng(2)
    q, sigma = 0.5, 20.0
    times, truth, groups = _cv_tracks(rng, 300, 30, q=q)
    z = truth[:, :2] + sigma * rng.standard_normal((len(times), 2))
    result = pa.KalmanFilter(process_noise=q).filter(times, z, groups, noise=sigma)
    nees = _nees(result, truth)
    # Mean of ~8700 NEES values of χ²(4), correlated along each track: well within ±5 %.
    assert abs(nees.mean() / 4 - 1) < 0.05, nees.mean()
    nis = result.nis[np.isfinite(result.nis)]
    assert abs(nis.mean() / 2 - 1) < 0.05, nis.mean()
    # A filter told a tenth of the process noise is overconfident, and it shows.
    tight = pa.KalmanFilter(process_noise=q / 10).filter(times, z, groups, noise=sigma)
    assert _nees(tight, truth).mean() > 1.2 * 4


def test_constant_acceleration_tracks_the_paper_target() -> None:
    """METHODS §5 target T1 on the x axis: 220 m/s, then 10 and −30 m/s² (scans of 1 s),
    measured with variance 0.5; the CA filter's acceleration follows each phase."""
    t = np.arange(30.0)
    accel = np.where(t < 5, 0.0, np.where(t < 20, 10.0, -30.0))
    v = 220 + np.concatenate(([0.0], np.cumsum(accel[:-1])))
    x = np.concatenate(([0.0], np.cumsum(v[:-1] + 0.5 * accel[:-1])))
    rng = np.random.default_rng(5)
    z = x + np.sqrt(0.5) * rng.standard_normal(30)
    result = pa.KalmanFilter(motion="ca", process_noise=50.0).filter(t, z, np.arange(30), noise=np.sqrt(0.5))
    assert result.states.shape == (30, 3)
    assert not result.has_state[:2].any() and result.has_state[2:].all()
    for phase, a in ((slice(15, 20), 10.0), (slice(26, 30), -30.0)):
        got = result.states[phase, 2]
        sd = np.sqrt(result.covariances[phase, 2, 2])
        assert np.all(np.abs(got - a) < 4 * sd + 1.0), (got, a)


@pytest.mark.parametrize("measurement", ["polar", "polar_converted"])
def test_polar_tracks_across_the_negative_x_axis(measurement: str) -> None:
    """A target crossing the −x axis (azimuth jumps from π to −π) seen from one sensor."""
    t = np.arange(20.0)
    pos = np.column_stack([-20e3 + 5 * t, -950 + 100 * t])
    sensor = np.array([100.0, 0.0])
    rel = pos - sensor
    z = np.column_stack([np.hypot(rel[:, 0], rel[:, 1]), np.arctan2(rel[:, 1], rel[:, 0])])
    assert z[0, 1] < -3 and z[-1, 1] > 3
    kf = pa.KalmanFilter(measurement=measurement, process_noise=1.0)  # type: ignore[arg-type]
    result = kf.filter(t, z, [np.arange(20)], noise=[10.0, 1e-3], sensor_positions=sensor)
    truth = np.column_stack([pos, np.tile([5.0, 100.0], (20, 1))])
    np.testing.assert_allclose(result.states[1:], truth[1:], rtol=1e-9, atol=1e-6)


def test_ekf_and_linear_filter_agree_on_the_same_truth() -> None:
    rng = np.random.default_rng(3)
    times, truth, groups = _cv_tracks(rng, 50, 25, q=0.5)
    truth[:, 0] += 20e3
    sensor = np.zeros(2)
    rng_, az = np.hypot(truth[:, 0], truth[:, 1]), np.arctan2(truth[:, 1], truth[:, 0])
    sr, sa = 20.0, 1e-3
    n_r, n_a = sr * rng.standard_normal(len(times)), sa * rng.standard_normal(len(times))
    polar = np.column_stack([rng_ + n_r, az + n_a])
    # The same noise draws mapped through the Jacobian at the truth, with matching covariances.
    jac = np.stack(
        [np.column_stack([np.cos(az), -rng_ * np.sin(az)]), np.column_stack([np.sin(az), rng_ * np.cos(az)])], 1
    )
    cart = truth[:, :2] + np.einsum("nij,nj->ni", jac, np.column_stack([n_r, n_a]))
    cov = jac @ np.diag([sr**2, sa**2]) @ jac.transpose(0, 2, 1)
    ekf = pa.KalmanFilter(measurement="polar", process_noise=0.5).filter(
        times, polar, groups, noise=[sr, sa], sensor_positions=sensor
    )
    linear = pa.KalmanFilter(process_noise=0.5).filter(times, cart, groups, noise=cov)
    rows = ekf.has_state
    diff = np.sqrt(np.mean((ekf.states[rows, :2] - linear.states[rows, :2]) ** 2))
    err = np.sqrt(np.mean((linear.states[rows, :2] - truth[rows, :2]) ** 2))
    assert diff < 0.05 * err, (diff, err)


def test_results_do_not_depend_on_threads_row_order_or_noise_spelling() -> None:
    rng = np.random.default_rng(4)
    times, truth, groups = _cv_tracks(rng, 60, 15, q=1.0, ndim=3)
    z = truth[:, :3] + 15.0 * rng.standard_normal((len(times), 3))
    kf = pa.KalmanFilter(process_noise=1.0)
    base = kf.filter(times, z, groups, noise=15.0)
    for other in (
        dataclasses.replace(kf, n_threads=1).filter(times, z, groups, noise=15.0),
        dataclasses.replace(kf, n_threads=3).filter(times, z, groups, noise=[15.0] * 3),
        kf.filter(times, z, groups, noise=np.full((len(times), 3), 15.0)),
        kf.filter(times, z, groups, noise=np.tile(np.eye(3) * 225.0, (len(times), 1, 1))),
    ):
        np.testing.assert_array_equal(other.states, base.states)
        np.testing.assert_array_equal(other.covariances, base.covariances)
        np.testing.assert_array_equal(other.nis, base.nis)
    # Rows shuffled (the groups follow them) and one row left out of every track.
    perm = rng.permutation(len(times))
    where = np.argsort(perm)
    shuffled_groups = [where[g[:-1]] for g in groups]
    shuffled = kf.filter(times[perm], z[perm], shuffled_groups, noise=15.0)
    short = kf.filter(times, z, [g[:-1] for g in groups], noise=15.0)
    np.testing.assert_array_equal(shuffled.states[where], short.states)
    assert np.isnan(short.states[[g[-1] for g in groups]]).all()


def test_single_point_start_and_one_axis() -> None:
    t = np.array([0.0, 1.0, 3.0])
    kf = pa.KalmanFilter(init="single_point", init_velocity_std=100.0, process_noise=0.0)
    result = kf.filter(t, [5.0, 15.0, 35.0], [np.arange(3)], noise=[1.0, 1.0, 2.0])
    assert result.states.shape == (3, 2) and result.has_state.all()
    assert result.states[0].tolist() == [5.0, 0.0]
    assert result.covariances[0].tolist() == [[1.0, 0.0], [0.0, 100.0**2]]
    assert abs(result.states[2, 1] - 10.0) < 0.1


def test_parameters_are_checked() -> None:
    with pytest.raises(ValueError, match=r"process_noise: must be >= 0, got -1.0"):
        pa.KalmanFilter(process_noise=-1.0)
    with pytest.raises(ValueError, match=r"motion: must be 'cv' or 'ca', got 'singer'"):
        pa.KalmanFilter(motion="singer", process_noise=1.0)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="process_noise"):
        pa.KalmanFilter()  # type: ignore[call-arg]
    with pytest.raises(ValueError, match="init_velocity_std"):
        pa.KalmanFilter(process_noise=1.0, init_velocity_std=0.0)
    kf = pa.KalmanFilter(process_noise=np.float32(0.5), n_threads=np.int64(2))
    assert type(kf.process_noise) is float and type(kf.n_threads) is int
    with pytest.raises(dataclasses.FrozenInstanceError):
        kf.motion = "ca"  # type: ignore[misc]


@pytest.mark.parametrize("bad", [-1e300, 1e13, np.inf])
def test_times_beyond_the_epoch_bound_are_refused(bad: float) -> None:
    """Times within ±1e12 s, as every epoch t0: a time of −1e300 once gave negative
    variances on rows reported as having a state."""
    times = np.array([bad, 0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match=r"times\[0\] = .*(within ±1e\+12 s|must be finite)"):
        pa.KalmanFilter(process_noise=1e3).filter(times, np.arange(8.0).reshape(4, 2), np.arange(4), noise=1.0)


@pytest.mark.parametrize("motion", ["cv", "ca"])
@pytest.mark.parametrize("init", ["differencing", "single_point"])
def test_no_row_with_a_state_has_a_negative_variance_at_the_time_bound(motion: str, init: str) -> None:
    """A step of 2e12 s at the bound keeps no digits in the update: the filter reports those
    rows as a numerical failure (NaN) instead of negative variances."""
    times = np.array([-1e12, 1e12 - 2, 1e12 - 1, 1e12])
    z = np.column_stack([10.0 * np.arange(4), np.arange(4.0)])
    for q in (0.0, 1.0, 1e3):
        kf = pa.KalmanFilter(process_noise=q, motion=motion, init=init)  # type: ignore[arg-type]
        out = kf.filter(times, z, np.arange(4), noise=1.0)
        variances = np.diagonal(out.covariances, axis1=1, axis2=2)[out.has_state]
        assert np.isfinite(variances).all() and (variances >= 0).all(), (q, variances.min())
