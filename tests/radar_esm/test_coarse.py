"""The radar/ESM coarse gate (METHODS §5 step 2): the operator is PyWavelets' transform, the
Rust statistic is the per-pair NumPy one, the whitened gate rejects the nominal share of true
pairs for every boundary mode (the paper's scalar statistic does not), and bad input is
refused by name."""

from __future__ import annotations

import numpy as np
import pytest
import pywt
from numpy.typing import NDArray
from passive_assoc.radar_esm import (
    MAX_WINDOW,
    WaveletFuzzyAssociator,
    approximation_operator,
    coarse_gate,
    coefficients,
)
from passive_assoc.radar_esm.coarse import MODES as ALL_MODES
from scipy.stats import chi2

#: The modes the operator test covers; the false-rejection test runs every PyWavelets mode.
MODES = ["symmetric", "periodization", "zero", "smooth"]


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize(("wavelet", "window"), [("sym2", 6), ("sym2", 16), ("sym2", 30), ("sym2", 45), ("db3", 40)])
def test_operator_is_the_wavelet_transform(wavelet: str, window: int, mode: str) -> None:
    operator, level = approximation_operator(window, wavelet, 3, mode)
    assert level == min(3, pywt.dwt_max_level(window, pywt.Wavelet(wavelet).dec_len))
    x = np.random.default_rng(window).normal(size=(5, window))
    for row in x:
        expected = pywt.wavedec(row, wavelet, mode=mode, level=level)[0]
        np.testing.assert_allclose(operator @ row, expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(coefficients(x[:, None, :], operator)[:, 0], x @ operator.T)


def test_operator_is_cached_read_only_and_reduced_for_short_windows() -> None:
    first, level = approximation_operator(30)
    again, _ = approximation_operator(30, "sym2", 3, "symmetric")
    assert first is again and not first.flags.writeable and level == 3
    assert [approximation_operator(t)[1] for t in (6, 11, 12, 23, 24)] == [1, 1, 2, 2, 3]


def naive_statistic(
    operator: NDArray[np.float64],
    radar: tuple[NDArray[np.float64], NDArray[np.float64]],
    esm: tuple[NDArray[np.float64], NDArray[np.float64]],
    whitened: bool,
) -> NDArray[np.float64]:
    """Per pair and coordinate, the obvious way: build W (Σ_i + Σ_j) Wᵀ and solve."""
    (xr, vr), (xe, ve) = radar, esm
    ar, ae = xr @ operator.T, xe @ operator.T
    out = np.zeros((len(xr), len(xe)))
    for i in range(len(xr)):
        for j in range(len(xe)):
            for k in range(xr.shape[1]):
                d = ar[i, k] - ae[j, k]
                if whitened:
                    s = operator @ np.diag(vr[i, k] + ve[j, k]) @ operator.T
                    out[i, j] += d @ np.linalg.solve(s, d)
                else:
                    out[i, j] += d @ d / (vr[i, k].mean() + ve[j, k].mean())
    return out


@pytest.mark.parametrize("whitened", [True, False])
@pytest.mark.parametrize(("ndim", "window", "mode"), [(1, 30, "symmetric"), (2, 20, "periodization"), (3, 50, "zero")])
def test_statistic_equals_numpy(ndim: int, window: int, mode: str, whitened: bool) -> None:
    rng = np.random.default_rng(ndim)
    radar = (rng.normal(0, 3, (9, ndim, window)), rng.uniform(0.2, 2.0, (9, ndim, window)))
    esm = (rng.normal(0, 3, (7, ndim, window)), rng.uniform(0.2, 2.0, (7, ndim, window)))
    gate = coarse_gate(*radar, *esm, mode=mode, whitened=whitened)
    operator, _ = approximation_operator(window, mode=mode)
    expected = naive_statistic(operator, radar, esm, whitened)
    np.testing.assert_allclose(gate.statistic, expected, rtol=1e-9)
    assert gate.dof == ndim * operator.shape[0]
    assert gate.threshold == pytest.approx(chi2.ppf(0.99, gate.dof))
    assert np.array_equal(gate.passed, gate.statistic <= gate.threshold)
    one_thread = coarse_gate(*radar, *esm, mode=mode, whitened=whitened, n_threads=1)
    assert np.array_equal(one_thread.statistic, gate.statistic)


#: Monte-Carlo size: blocks of independent true pairs (the diagonal of each block's gate),
#: 20 000 pairs in all (binomial σ ≈ 0.07 percentage points at 1 %).
BLOCK, BLOCKS = 50, 400
NOMINAL = 0.01


def true_pair_rejections(
    mode: str, whitened: bool, variances: tuple[NDArray[np.float64], NDArray[np.float64]], seed: int
) -> float:
    """The share of true pairs the gate rejects: each pair is two noisy copies (white noise
    with the given per-scan variances) of one random trajectory; pairs are independent."""
    rng = np.random.default_rng(seed)
    radar_var, esm_var = variances
    window = radar_var.shape[-1]
    rejected = 0
    for _ in range(BLOCKS):
        truth = np.cumsum(rng.normal(0.0, 50.0, (BLOCK, 1, window)), axis=2)
        radar = truth + rng.normal(size=truth.shape) * np.sqrt(radar_var)
        esm = truth + rng.normal(size=truth.shape) * np.sqrt(esm_var)
        rv, ev = np.broadcast_to(radar_var, truth.shape), np.broadcast_to(esm_var, truth.shape)
        gate = coarse_gate(radar, rv, esm, ev, mode=mode, gate_probability=1 - NOMINAL, whitened=whitened)
        rejected += int(np.count_nonzero(~np.diagonal(gate.passed)))
    return rejected / (BLOCK * BLOCKS)


def scalar_rejection_expected(operator: NDArray[np.float64], dof: int) -> float:
    """What the unwhitened statistic should reject with equal, constant variances on both
    sides: it is then ``zᵀ W Wᵀ z`` with z standard normal, a weighted sum of χ²(1) with the
    eigenvalues of W Wᵀ as weights (one Monte-Carlo of 400 000 draws, NumPy only)."""
    weights = np.linalg.eigvalsh(operator @ operator.T)
    z = np.random.default_rng(0).standard_normal((400_000, len(weights)))
    return float(np.mean((z**2) @ weights > chi2.ppf(1 - NOMINAL, dof)))


@pytest.mark.parametrize("mode", ALL_MODES)
def test_whitened_gate_rejects_the_nominal_share_of_true_pairs(mode: str) -> None:
    """20 000 independent true pairs per mode, the paper's noise variance 0.5 on both sides
    over 30 scans: the whitened statistic's false rejection rate is within 1 percentage point
    of the nominal 1 %. The paper's scalar statistic is printed beside it; it rejects what
    the eigenvalues of W Wᵀ say it should, far above nominal wherever the boundary
    coefficients' variance is inflated (METHODS §5: ~24 % in symmetric mode)."""
    variances = (np.full(30, 0.5), np.full(30, 0.5))
    whitened = true_pair_rejections(mode, True, variances, seed=1)
    scalar = true_pair_rejections(mode, False, variances, seed=1)
    operator, _ = approximation_operator(30, mode=mode)
    expected = scalar_rejection_expected(operator, len(operator))
    report = (
        f"{mode}: whitened rejects {whitened:.2%}, unwhitened {scalar:.2%} (expected {expected:.2%}) "
        f"of true pairs at nominal {NOMINAL:.0%}"
    )
    print(report)
    assert abs(whitened - NOMINAL) < 0.01, report
    assert abs(scalar - expected) < 0.015, report
    if np.diag(operator @ operator.T).max() >= 2:
        assert scalar > 5 * NOMINAL, report
    if mode == "symmetric":
        assert 0.2 < scalar < 0.28, report


def test_whitened_gate_holds_with_variances_that_change_over_the_window() -> None:
    """A filter's variance falls over the window after initialisation; the radar's and the
    ESM's differ. The whitened gate still rejects the nominal share."""
    t = np.arange(30)
    variances = (0.5 * (1 + 4 * np.exp(-t / 4)), np.full(30, 2.0))
    rate = true_pair_rejections("symmetric", True, variances, seed=2)
    assert abs(rate - NOMINAL) < 0.01, f"whitened rejects {rate:.2%} of true pairs at nominal {NOMINAL:.0%}"


def tracks(n: int, ndim: int = 1, window: int = 30) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    return np.zeros((n, ndim, window)), np.ones((n, ndim, window))


def test_a_window_too_short_for_one_level_is_refused() -> None:
    with pytest.raises(
        ValueError, match=r"^window: a window of 5 scans is too short for one level of sym2 \(at least 6"
    ):
        approximation_operator(5)
    with pytest.raises(ValueError, match=r"^radar_positions: a window of 5 scans"):
        coarse_gate(*tracks(2, window=5), *tracks(2, window=5))


def test_a_window_beyond_the_cap_is_refused_before_any_work() -> None:
    """A window of 10⁹ scans once reached NumPy as a 10⁹ × 10⁹ identity ("Unable to allocate
    6.94 EiB"): refused by name, with the cap, in every entry point that takes one."""
    too_long = r"a window of 1000000000 scans exceeds the cap of 1024 scans \(MAX_WINDOW\)"
    with pytest.raises(ValueError, match=r"^window: " + too_long):
        approximation_operator(10**9)
    with pytest.raises(ValueError, match=r"^window: " + too_long):
        WaveletFuzzyAssociator(window=10**9)
    assert approximation_operator(MAX_WINDOW)[0].shape == (130, MAX_WINDOW)
    with pytest.raises(ValueError, match=r"^radar_positions: a window of 1025 scans exceeds the cap"):
        coarse_gate(*tracks(1, window=MAX_WINDOW + 1), *tracks(1, window=MAX_WINDOW + 1))


@pytest.mark.parametrize(
    ("argument", "bad", "match"),
    [
        ("radar_positions", np.full((2, 1, 30), np.nan), r"^radar_positions\[0, 0, 0\] = nan"),
        ("esm_positions", np.zeros((3, 1, 29)), r"^esm_positions: expected shape \(\*, 1, 30\)"),
        ("esm_positions", np.zeros((3, 2, 30)), r"^esm_positions: expected shape \(\*, 1, 30\)"),
        ("radar_variances", np.ones((2, 1, 29)), r"^radar_variances: expected shape \(2, 1, 30\)"),
        ("esm_variances", -np.ones((3, 1, 30)), r"^esm_variances\[0, 0, 0\] = -1.0; must be >= 0"),
        ("esm_variances", np.full((3, 1, 30), np.inf), r"^esm_variances\[0, 0, 0\] = inf"),
        ("radar_positions", np.zeros((2, 0, 30)), r"^radar_positions: needs at least one coordinate"),
        ("radar_positions", np.zeros((2, 30)), r"^radar_positions: expected a 3-dimensional array"),
    ],
)
def test_bad_arrays_are_refused_by_name(argument: str, bad: NDArray[np.float64], match: str) -> None:
    (rp, rv), (ep, ev) = tracks(2), tracks(3)
    args = {"radar_positions": rp, "radar_variances": rv, "esm_positions": ep, "esm_variances": ev, argument: bad}
    with pytest.raises(ValueError, match=match):
        coarse_gate(**args)


@pytest.mark.parametrize(
    ("keyword", "bad", "error", "match"),
    [
        ("wavelet", "nope", ValueError, r"^wavelet: 'nope' is not a discrete wavelet"),
        ("wavelet", 3, TypeError, r"^wavelet"),
        ("mode", "mirror", ValueError, r"^mode"),
        ("level", 0, ValueError, r"^level"),
        ("gate_probability", 1.0, ValueError, r"^gate_probability"),
        ("whitened", 1, TypeError, r"^whitened"),
        ("n_threads", 0, ValueError, r"^n_threads"),
    ],
)
def test_bad_settings_are_refused_by_name(keyword: str, bad: object, error: type[Exception], match: str) -> None:
    with pytest.raises(error, match=match):
        coarse_gate(*tracks(2), *tracks(3), **{keyword: bad})


def test_a_pair_without_variance_is_named() -> None:
    (rp, rv), (ep, ev) = tracks(2), tracks(3)
    rv[1], ev[2] = 0.0, 0.0
    for whitened in (True, False):
        with pytest.raises(ValueError, match=r"radar track 1 and ESM track 2, coordinate 0"):
            coarse_gate(rp, rv, ep, ev, whitened=whitened)


def test_coefficients_refuse_a_mismatched_operator() -> None:
    operator, _ = approximation_operator(30)
    with pytest.raises(ValueError, match=r"^positions: expected 30 scans"):
        coefficients(np.zeros((2, 1, 29)), operator)
    with pytest.raises(ValueError, match=r"^positions\[0, 0, 1\] = nan"):
        coefficients(np.array([[[0.0, np.nan] + [0.0] * 28]]), operator)
