"""The built-in tracker's EKF step on angle reports: the model's Jacobian against finite
differences, the wrapped azimuth residual, the exact constant-velocity prediction, a
consistent filter on a simulated bearing-only target, and its input checks."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from passive_assoc.estimation import AngleInnovation, angle_innovation, cv_predict, ekf_update

SENSOR = np.array([1e3, -2e3, 100.0])


def _angles(state: np.ndarray, sensor: np.ndarray) -> np.ndarray:
    d = state[: len(state) // 2] - sensor[: len(state) // 2]
    azimuth = np.arctan2(d[1], d[0])
    return np.array([azimuth]) if len(d) == 2 else np.array([azimuth, np.arctan2(d[2], np.hypot(d[0], d[1]))])


@pytest.mark.parametrize("state", [[8e3, 5e3, 10.0, -3.0], [8e3, 5e3, 2e3, 10.0, -3.0, 1.0]])
def test_the_jacobian_is_the_angles_derivative(state: list[float]) -> None:
    x = np.array(state)
    m = len(x) // 2 - 1
    found = angle_innovation(x, np.eye(len(x)), _angles(x, SENSOR), np.full(m, 1e-3), SENSOR)
    numeric = np.zeros((m, len(x)))
    for k in range(len(x)):
        step = np.zeros(len(x))
        step[k] = 1e-3
        numeric[:, k] = (_angles(x + step, SENSOR) - _angles(x - step, SENSOR)) / 2e-3
    np.testing.assert_allclose(found.jacobian, numeric, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(found.residual, 0.0, atol=1e-12)
    assert found.nis == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(found.covariance, found.jacobian @ found.jacobian.T + np.diag(np.full(m, 1e-6)))


def test_the_azimuth_residual_is_wrapped_across_pi() -> None:
    state = np.array([-10e3, 1.0, 0.0, 0.0])  # azimuth just under +pi from the origin
    found = angle_innovation(state, np.eye(4), [-np.pi + 1e-4], [1e-3], [0.0, 0.0])
    assert found.residual[0] == pytest.approx(1e-4 + 1e-4, abs=1e-9)  # not -2π + 2e-4


def test_the_prediction_is_the_exact_constant_velocity_step() -> None:
    p = np.diag([100.0, 200.0, 4.0, 9.0])
    state, cov = cv_predict([1.0, 2.0, 3.0, -4.0], p, 10.0, 0.5)
    np.testing.assert_allclose(state, [31.0, -38.0, 3.0, -4.0])
    q = 0.5 * np.array([[1000 / 3, 50.0], [50.0, 10.0]])
    # x and vx: [[100 + 100·4 + q11, 10·4 + q12], [.., 4 + q22]]
    assert cov[0, 0] == pytest.approx(100 + 100 * 4 + q[0, 0])
    assert cov[0, 2] == pytest.approx(10 * 4 + q[0, 1])
    assert cov[2, 2] == pytest.approx(4 + q[1, 1])
    assert cov[0, 1] == 0.0 and cov[0, 3] == 0.0
    same, unchanged = cv_predict([1.0, 2.0, 3.0, -4.0], p, 0.0, 0.5)
    np.testing.assert_array_equal(same, [1.0, 2.0, 3.0, -4.0])
    np.testing.assert_array_equal(unchanged, p)


def test_the_filter_is_consistent_on_a_bearing_only_target() -> None:
    """Two sites, one target, 60 s of bearings every 2 s, 200 runs started from the truth with
    the initial covariance's noise: the mean NEES at the end is the state's 4 (±10 %) and the
    mean NIS the bearing's 1 (±10 %)."""
    rng = np.random.default_rng(3)
    sites = np.array([[0.0, 0.0], [20e3, 0.0]])
    truth0 = np.array([8e3, 15e3, 12.0, -5.0])
    p0 = np.diag([300.0**2, 300.0**2, 5.0**2, 5.0**2])
    sigma = 2e-3
    nees, nis = [], []
    for _ in range(200):
        state, cov = truth0 + rng.multivariate_normal(np.zeros(4), p0), p0.copy()
        t = 0.0
        for step in range(30):
            now = 2.0 * (step + 1)
            state, cov = cv_predict(state, cov, now - t, 1e-6)
            t = now
            true = truth0[:2] + now * truth0[2:]
            for site in sites:
                z = np.arctan2(*(true - site)[::-1]) + sigma * rng.standard_normal()
                found = angle_innovation(state, cov, [z], [sigma], site)
                nis.append(found.nis)
                state, cov = ekf_update(state, cov, found)
        error = state - np.r_[truth0[:2] + t * truth0[2:], truth0[2:]]
        nees.append(error @ np.linalg.solve(cov, error))
    assert 3.6 < np.mean(nees) < 4.4, np.mean(nees)
    assert 0.9 < np.mean(nis) < 1.1, np.mean(nis)


def test_a_state_on_the_sensor_axis_has_no_innovation() -> None:
    found = angle_innovation([0.0, 0.0, 5e3, 1.0, 1.0, 1.0], np.eye(6), [0.1, 0.2], [1e-3, 1e-3], [0.0, 0.0, 0.0])
    assert found.nis == np.inf and np.isnan(found.residual).all()
    with pytest.raises(ValueError, match=r"^innovation: has no finite residual"):
        ekf_update([0.0, 0.0, 5e3, 1.0, 1.0, 1.0], np.eye(6), found)


GOOD: dict[str, Any] = {
    "state": [8e3, 5e3, 10.0, -3.0],
    "covariance": np.eye(4),
    "angles": [0.5],
    "sigmas": [1e-3],
    "sensor_position": [0.0, 0.0],
}


@pytest.mark.parametrize(
    ("change", "exc", "message"),
    [
        ({"state": [1.0, 2.0, 3.0]}, ValueError, r"^state: expected 4 \(2-D\) or 6"),
        ({"state": [np.nan, 2.0, 3.0, 4.0]}, ValueError, r"^state"),
        ({"state": ["a", "b", "c", "d"]}, TypeError, r"^state"),
        ({"covariance": np.eye(3)}, ValueError, r"^covariance"),
        ({"angles": [0.5, 0.1]}, ValueError, r"^angles"),
        ({"angles": [np.inf]}, ValueError, r"^angles"),
        ({"sigmas": [0.0]}, ValueError, r"^sigmas"),
        ({"sensor_position": [0.0]}, ValueError, r"^sensor_position: expected at least 2"),
        ({"sensor_position": [np.nan, 0.0]}, ValueError, r"^sensor_position"),
    ],
)
def test_angle_innovation_names_a_bad_argument(change: dict[str, Any], exc: type[Exception], message: str) -> None:
    with pytest.raises(exc, match=message):
        angle_innovation(**(GOOD | change))


def test_predict_and_update_name_a_bad_argument() -> None:
    with pytest.raises(ValueError, match=r"^dt: must be >= 0"):
        cv_predict(GOOD["state"], GOOD["covariance"], -1.0, 0.1)
    with pytest.raises(ValueError, match=r"^process_noise: must be >= 0"):
        cv_predict(GOOD["state"], GOOD["covariance"], 1.0, -0.1)
    with pytest.raises(ValueError, match=r"^dt"):
        cv_predict(GOOD["state"], GOOD["covariance"], np.nan, 0.1)
    with pytest.raises(TypeError, match=r"^innovation: expected an AngleInnovation"):
        ekf_update(GOOD["state"], GOOD["covariance"], "nis")  # type: ignore[arg-type]
    three_d = angle_innovation([8e3, 5e3, 1e3, 1.0, 1.0, 1.0], np.eye(6), [0.5, 0.1], [1e-3, 1e-3], [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^innovation: its Jacobian has shape"):
        ekf_update(GOOD["state"], GOOD["covariance"], three_d)
    assert isinstance(three_d, AngleInnovation)
