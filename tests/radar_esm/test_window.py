"""The filtered window's covariance (radar_esm.window): the coarse gate built on it rejects true
pairs at its nominal rate on Kalman-filtered tracks, where Σ per scan does not; the rolling
window equals the product formula, gaps included; bad models are refused."""

from __future__ import annotations

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.radar_esm import approximation_operator, coarse_gate
from passive_assoc.radar_esm.scans import AlignedTracks
from passive_assoc.radar_esm.window import RollingWindow, ca_model, filter_transitions
from scipy.stats import chi2

Q, SIGMA, SCANS = 169.0, 707.0, 30


def filtered_tracks(n: int, seed: int) -> tuple[AlignedTracks, np.ndarray]:
    """n 1-D targets moving exactly as the filter's model (white jerk of density Q), reported
    with noise SIGMA each second, and the CA filter's tracks; returns the tracks and their
    position errors ``(n, SCANS)`` (NaN before the filter's first state)."""
    rng = np.random.default_rng(seed)
    f, q = ca_model(1.0, 1, Q)
    state = np.column_stack([rng.normal(0, 1e4, n), rng.normal(0, 300, n), rng.normal(0, 20, n)])
    truth = np.empty((n, SCANS))
    for k in range(SCANS):
        if k:
            state = state @ f.T + rng.multivariate_normal(np.zeros(3), q, n)
        truth[:, k] = state[:, 0]
    reports = truth + rng.normal(0.0, SIGMA, truth.shape)
    times = np.tile(np.arange(SCANS, dtype=float), n)
    groups = np.arange(n * SCANS).reshape(n, SCANS)
    out = pa.KalmanFilter(motion="ca", process_noise=Q).filter(times, reports.ravel(), groups, noise=SIGMA)
    states = out.states.reshape(n, SCANS, 3)
    tracks = AlignedTracks(
        0,
        np.arange(n),
        out.has_state.reshape(n, SCANS),
        states[:, :, :1],
        states[:, :, 1:2],
        states[:, :, 2:],
        out.covariances.reshape(n, SCANS, 3, 3),
    )
    return tracks, states[:, :, 0] - truth


def rejection(errors: np.ndarray, variances: np.ndarray) -> float:
    """The gate's rejection rate of each track against its own truth (zero covariance)."""
    length = errors.shape[1]
    zero = np.zeros((1, 1, length))
    gate = coarse_gate(errors[:, None, :], variances, zero, np.zeros((1, *variances.shape[1:])))
    return float(1.0 - gate.passed.mean())


@pytest.mark.parametrize("length", [4, 12, 28])
def test_the_full_window_gate_rejects_true_pairs_at_the_nominal_rate(length: int) -> None:
    """Level 0 (W = I, 4 scans), level 2 (12 scans) and level 3 (28): within 1 point of the
    nominal 1 %; with Σ per scan the same errors are rejected several times as often."""
    n = 3000
    tracks, errors = filtered_tracks(n, seed=length)
    window = RollingWindow(tracks, filter_transitions(tracks, np.arange(SCANS, dtype=float), Q), cap=32)
    window.advance_to(SCANS - 1)
    sigma = window.covariance(np.arange(n), length)
    tail = errors[:, -length:]
    if length < 6:  # sym2 needs 6 scans; level 0 tests the positions themselves (W = I)
        statistic = np.einsum("ns,ns->n", tail, np.linalg.solve(sigma[:, 0, :, 0, :], tail[..., None])[..., 0])
        full = float(np.mean(statistic > chi2.ppf(0.99, length)))
    else:
        full = rejection(tail, sigma)
    assert abs(full - 0.01) < 0.01, full
    if length >= 6:
        assert tracks.covariance is not None
        per_scan = rejection(tail, tracks.covariance[:, -length:, 0, 0][:, None, :])
        assert per_scan > 0.05, per_scan


def test_the_rolling_window_is_the_product_formula_across_a_gap() -> None:
    tracks, _ = filtered_tracks(3, seed=1)
    present = tracks.present.copy()
    present[1, 10] = False  # track 1 restarts at scan 11: its window never reaches back past it
    gapped = AlignedTracks(
        0,
        tracks.track,
        present,
        *(getattr(tracks, a) for a in ("position", "velocity")),
        tracks.acceleration,
        tracks.covariance,
    )
    times = np.arange(SCANS, dtype=float)
    transitions = filter_transitions(gapped, times, Q)
    assert not transitions[1, 10].any() and not transitions[1, 11].any()
    window = RollingWindow(gapped, transitions, cap=8)
    window.advance_to(15)
    assert gapped.covariance is not None
    for track, length in ((0, 8), (1, 5)):  # track 1 exists at scans 11..15
        got = window.covariance(np.array([track]), length)[0, 0, :, 0, :]
        scans = range(16 - length, 16)
        expected = np.empty((length, length))
        for a, j in enumerate(scans):
            product = gapped.covariance[track, j]
            for b, k in enumerate(scans):
                if k < j:
                    continue
                if k > j:
                    product = transitions[track, k] @ product
                expected[b, a] = expected[a, b] = product[0, 0]
        np.testing.assert_allclose(got, expected, rtol=1e-12)


def test_models_other_than_constant_acceleration_are_refused() -> None:
    tracks, _ = filtered_tracks(2, seed=2)
    assert tracks.covariance is not None
    cv = AlignedTracks(
        0, tracks.track, tracks.present, tracks.position, tracks.velocity, None, tracks.covariance[:, :, :2, :2]
    )
    with pytest.raises(ValueError, match=r"process_noise: .*constant-acceleration"):
        filter_transitions(cv, np.arange(SCANS, dtype=float), Q)


def test_coarse_gate_takes_a_full_window_covariance() -> None:
    """A diagonal full covariance gives the per-scan answer; the literal statistic refuses it;
    a wrong shape is named."""
    rng = np.random.default_rng(4)
    radar, esm = rng.normal(0, 1e3, (2, 5, 2, 20))
    var = rng.uniform(1e4, 1e5, (2, 5, 2, 20))
    per_scan = coarse_gate(radar, var[0], esm, var[1])
    full = np.zeros((2, 5, 40, 40))
    full[:, :, np.arange(40), np.arange(40)] = var.reshape(2, 5, 40)
    as_full = coarse_gate(radar, full[0].reshape(5, 2, 20, 2, 20), esm, var[1])
    np.testing.assert_allclose(as_full.statistic, per_scan.statistic, rtol=1e-10)
    with pytest.raises(ValueError, match="whitened"):
        coarse_gate(radar, full[0].reshape(5, 2, 20, 2, 20), esm, var[1], whitened=False)
    with pytest.raises(ValueError, match="radar_variances: expected shape"):
        coarse_gate(radar, full[0], esm, var[1])
    assert approximation_operator(20)[1] == 2
