"""A moving sensor: the Fisher information against finite differences of the bearing model
with the platform's interpolated position, and a two-sensor scene in which one ESM flies
(bearings-only target motion analysis from a ground site and an aircraft) that initiates and
reaches the CRLB."""

from __future__ import annotations

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.evaluation import target_crlbs
from passive_assoc.evaluation.track_truth import track_targets
from passive_assoc.simulation import ConstantVelocityTarget, simulate

SIGMA = 2e-3
#: The aircraft (sensor 1) flies east at 200 m/s, then turns north: three waypoints.
AIRCRAFT = pa.SensorTrack([1, 1, 1], [0.0, 150.0, 300.0], [[-30e3, -20e3], [0.0, -20e3], [0.0, 10e3]])
NETWORK = pa.SensorNetwork.planar([[0.0, 0.0], [-30e3, -20e3]], SIGMA)  # sensor 1's entry: unused
TARGETS = [
    ConstantVelocityTarget([20e3, 40e3, -8.0, -4.0]),
    ConstantVelocityTarget([-25e3, 35e3, 6.0, -3.0]),
]
TIMES = [np.arange(31) * 10.0, np.arange(30) * 10.0 + 3.0]


def scene(seed: int) -> pa.Scenario:
    return simulate(NETWORK, TARGETS, TIMES, pd=1.0, t0=0.0, platforms=AIRCRAFT, seed=seed)


def test_the_track_interpolates_and_refuses_to_extrapolate(tmp_path: object) -> None:
    at = AIRCRAFT.position_at([1, 1, 1], [75.0, 150.0, 225.0])
    np.testing.assert_allclose(at[:, :2], [[-15e3, -20e3], [0.0, -20e3], [0.0, -5e3]])
    with pytest.raises(ValueError, match=r"^time: entry 0 \(301\.0 s\) is outside sensor 1's fixes \[0\.0, 300\.0\]"):
        AIRCRAFT.position_at(1, 301.0)
    with pytest.raises(ValueError, match=r"^sensor: 0 has no fixes in this sensor track"):
        AIRCRAFT.position_at(0, 10.0)
    with pytest.raises(ValueError, match=r"^time: sensor 1 has two fixes at time 0\.0"):
        pa.SensorTrack([1, 1], [0.0, 0.0], [[0.0, 0.0], [1.0, 0.0]])
    leg = pa.SensorTrack.constant_velocity([1], [[-30e3, -20e3]], [[200.0, 0.0]], 0.0, 150.0)
    np.testing.assert_allclose(leg.position_at(1, 75.0), AIRCRAFT.position_at(1, 75.0))


def _bearing(state: np.ndarray, t: np.ndarray, where: np.ndarray) -> np.ndarray:
    x = state[0] + state[2] * t - where[:, 0]
    y = state[1] + state[3] * t - where[:, 1]
    return np.arctan2(y, x)


def test_the_bound_with_a_moving_sensor_is_the_finite_difference_fisher_information() -> None:
    s = scene(0)
    m = s.measurements
    rows = s.true_groups()[0]
    truth = s.true_states[0]
    assert m.sensor_position is not None
    where = np.where(np.isnan(m.sensor_position[rows]), NETWORK.positions[m.sensor[rows]], m.sensor_position[rows])
    t = m.time[rows]
    jacobian = np.empty((len(rows), 4))
    for k, step in enumerate([1.0, 1.0, 1e-3, 1e-3]):
        e = np.zeros(4)
        e[k] = step
        jacobian[:, k] = (_bearing(truth + e, t, where) - _bearing(truth - e, t, where)) / (2 * step)
    expected = jacobian.T @ jacobian / SIGMA**2
    fisher, bound = pa.fisher_and_crlb(
        m.sensor[rows], t, NETWORK, truth, t0=0.0, sensor_position=m.sensor_position[rows]
    )
    np.testing.assert_allclose(fisher, expected, rtol=1e-6)
    np.testing.assert_allclose(bound, target_crlbs(s)[0], rtol=1e-12)
    fixed = pa.fisher_and_crlb(m.sensor[rows], t, NETWORK, truth, t0=0.0)[0]
    assert np.abs(fixed - expected).max() > 0.1 * np.abs(expected).max()  # the platform's motion matters


def test_an_airborne_esm_scene_initiates_at_the_crlb() -> None:
    """500 runs: the initiator finds both targets each time, and the RMS error of its initial
    positions is the CRLB's within ±15 % (measured: see the assertion's figures)."""
    errors: list[list[np.ndarray]] = [[], []]
    bounds = target_crlbs(scene(0))
    for seed in range(500):
        s = scene(seed)
        found = pa.FuzzyTrackInitiator().initiate(s.measurements, NETWORK, t0=0.0)
        assert s.measurements.truth is not None
        which = track_targets(found.labels, s.measurements.truth)
        assert sorted(which.tolist()) == [0, 1], seed
        for track, target in zip(found.tracks, which, strict=True):
            errors[target].append(track.state[:2] - s.true_states[target][:2])
    for target in (0, 1):
        rms = np.sqrt(np.mean(np.sum(np.square(errors[target]), axis=1)))
        bound = np.sqrt(np.trace(bounds[target][:2, :2]))
        assert 0.85 <= rms / bound <= 1.15, (target, rms, bound)
