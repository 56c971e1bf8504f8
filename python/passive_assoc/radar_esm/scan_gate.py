"""The coarse gate of every scan (METHODS §5 step 2), as the wavelet-fuzzy associator runs it.

At scan k a pair's window is the scans so far in which both tracks exist, at most the cap;
tracks of one age are tested in one call of the Rust gate. Σ over the window is either

* *per scan* (diagonal in time): each scan's filtered position variance — the gate's
  per-scan-variance form, :func:`gate_diagonal`; or
* *whole* (a process noise per side): the filtered sequence's full covariance with its
  scan-to-scan correlation (:mod:`.window`), each track's ``C = (I ⊗ W) Σ (I ⊗ W)ᵀ`` built in
  NumPy (O(n) per scan) and the O(n²) pair test in Rust, :func:`gate_full`; or
* *reports* (the sequences are raw reports): each report's own covariance, block-diagonal in
  time — exact, since report errors are independent — through the same :func:`gate_full`.

A window shorter than the wavelet allows (6 scans for sym2) is tested at level 0: W = I, the
positions themselves.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Literal, Protocol

import numpy as np
from numpy.typing import NDArray
from scipy.stats import chi2

from .. import _core
from .._settings import CoarseGateSettings
from .coarse import _shortest_window, approximation_operator
from .scans import AlignedTracks
from .window import RollingWindow, coefficient_covariance, filter_transitions

__all__ = ["WINDOW_CAP", "GateConfig", "coarse_by_scan", "gate_diagonal", "gate_full", "level0_gate"]

#: Longest coarse window when ``window=None``: 32 scans, which hold the paper's whole 30-scan
#: run and give 6 approximation coefficients per axis at sym2, 3 levels.
WINDOW_CAP = 32


class GateConfig(Protocol):
    """The associator settings the coarse gate reads."""

    @property
    def wavelet(self) -> str: ...
    @property
    def level(self) -> int: ...
    @property
    def mode(self) -> str: ...
    @property
    def window(self) -> int | None: ...
    @property
    def gate_probability(self) -> float: ...
    @property
    def whitened(self) -> bool: ...
    @property
    def process_noise(self) -> float | str | None: ...
    @property
    def n_threads(self) -> int | None: ...


#: :func:`.coarse.approximation_operator`, cached with its checks done once per argument set.
approximation_operator_cached = functools.lru_cache(maxsize=256)(approximation_operator)


@functools.lru_cache(maxsize=1024)
def chi2_quantile(probability: float, dof: int) -> float:
    """χ²(dof) quantile, cached (scipy's ppf costs ~0.1 ms a call)."""
    return float(chi2.ppf(probability, dof))


def _operator(config: GateConfig, length: int) -> NDArray[np.float64]:
    """W for a window of ``length`` scans: the wavelet's, or I below one level."""
    if length < _shortest_window(config.wavelet):
        return np.eye(length)
    operator, _ = approximation_operator_cached(length, config.wavelet, config.level, config.mode)
    return operator


#: How Σ over one side's window is taken: the filtered sequence's whole covariance with this
#: process noise, or ``"reports"``: each scan's own covariance, block-diagonal in time.
SideSigma = float | Literal["reports"]
#: Σ of both sides (radar, ESM), or ``"per_scan"``: each scan's variances, the gate's
#: per-scan form (:func:`gate_diagonal`, which the literal statistic needs).
Sigma = Literal["per_scan"] | tuple[SideSigma, SideSigma]


def coarse_by_scan(
    config: GateConfig,
    radar: AlignedTracks,
    esm: AlignedTracks,
    times: NDArray[np.float64] | None,
    sigma: Sigma | None = None,
) -> NDArray[np.bool_]:
    """Which (radar, ESM) pairs pass the coarse gate at each scan, ``(K, n_r, n_e)``.
    ``sigma`` (module docs) defaults to the whole covariance with ``config.process_noise`` on
    both sides when it is a number, else per scan."""
    if sigma is None:
        q = config.process_noise
        sigma = (float(q), float(q)) if isinstance(q, float | int) else "per_scan"
    cap = config.window if config.window is not None else WINDOW_CAP
    n_scans = radar.present.shape[1]
    passed = np.zeros((n_scans, len(radar), len(esm)), dtype=bool)
    age_r, age_e = _ages(radar.present, cap), _ages(esm.present, cap)
    if sigma == "per_scan":
        test = _diagonal_tests(config, radar, esm)
    else:
        if times is None and any(not isinstance(side, str) for side in sigma):
            raise ValueError("times: the scan times are needed with process_noise")
        test = _whole_tests(config, (radar, esm), times, cap, sigma)
    for k in range(n_scans):
        for length, rows, cols, exact in _pair_windows(age_r[:, k], age_e[:, k]):
            ok = test(k, length, rows, cols)
            block = np.ix_(rows, cols)
            passed[k][block] = ok if exact is None else np.where(exact, ok, passed[k][block])
    return passed


class _Test(Protocol):
    def __call__(self, k: int, length: int, rows: NDArray[np.intp], cols: NDArray[np.intp]) -> NDArray[np.bool_]: ...


def _diagonal_tests(config: GateConfig, radar: AlignedTracks, esm: AlignedTracks) -> _Test:
    var_r = np.diagonal(radar.block_covariance(0), axis1=2, axis2=3)
    var_e = np.diagonal(esm.block_covariance(0), axis1=2, axis2=3)
    shortest = _shortest_window(config.wavelet)

    def test(k: int, length: int, rows: NDArray[np.intp], cols: NDArray[np.intp]) -> NDArray[np.bool_]:
        span = slice(k - length + 1, k + 1)
        sides = (
            _window(radar.position, rows, span),
            _window(var_r, rows, span),
            _window(esm.position, cols, span),
            _window(var_e, cols, span),
        )
        if length < shortest:
            return level0_gate(*sides, config.gate_probability)
        return gate_diagonal(config, *sides)

    return test


def _whole_tests(
    config: GateConfig,
    sides: tuple[AlignedTracks, AlignedTracks],
    times: NDArray[np.float64] | None,
    cap: int,
    sigma: tuple[SideSigma, SideSigma],
) -> _Test:
    """Each side's coefficients with their full covariance ``C = (I ⊗ W) Σ (I ⊗ W)ᵀ``, Σ as
    ``sigma`` says for that side, and the pair test in Rust."""
    windows: list[Callable[[int, int, NDArray[np.intp], NDArray[np.float64]], NDArray[np.float64]]] = []
    for tracks, side in zip(sides, sigma, strict=True):
        if isinstance(side, str):
            blocks = np.nan_to_num(tracks.block_covariance(0))

            def by_scan(
                k: int,
                length: int,
                which: NDArray[np.intp],
                w: NDArray[np.float64],
                blocks: NDArray[np.float64] = blocks,
            ) -> NDArray[np.float64]:
                # C[x c, y c'] = Σ_t W[c, t] W[c', t] P_t[x, y].
                c = np.einsum("ct,et,ntxy->nxcye", w, w, blocks[which, k - length + 1 : k + 1])
                n, d, m = c.shape[0], c.shape[1], c.shape[2]
                out: NDArray[np.float64] = c.reshape(n, d * m, d * m)
                return out

            windows.append(by_scan)
        else:
            assert times is not None
            rolling = RollingWindow(tracks, filter_transitions(tracks, times, side), cap)

            def whole(
                k: int, length: int, which: NDArray[np.intp], w: NDArray[np.float64], rolling: RollingWindow = rolling
            ) -> NDArray[np.float64]:
                rolling.advance_to(k)
                return coefficient_covariance(rolling.covariance(which, length), w)

            windows.append(whole)

    def test(k: int, length: int, rows: NDArray[np.intp], cols: NDArray[np.intp]) -> NDArray[np.bool_]:
        span = slice(k - length + 1, k + 1)
        operator = _operator(config, length)
        out = []
        for tracks, window, which in zip(sides, windows, (rows, cols), strict=True):
            coefficients = _window(tracks.position, which, span) @ operator.T
            out.append(
                (
                    np.ascontiguousarray(coefficients.reshape(len(which), -1)),
                    np.ascontiguousarray(window(k, length, which, operator)),
                )
            )
        return gate_full(config, out[0], out[1])

    return test


def gate_diagonal(
    config: GateConfig,
    radar_positions: NDArray[np.float64],
    radar_variances: NDArray[np.float64],
    esm_positions: NDArray[np.float64],
    esm_variances: NDArray[np.float64],
) -> NDArray[np.bool_]:
    """:func:`.coarse.coarse_gate` of validated, contiguous windows without its per-call
    checks: the operator and threshold are cached per window length (a test holds the two
    equal). The associator calls it once per scan, so the checks would cost more than the
    gate itself."""
    _, ndim, window = radar_positions.shape
    operator = _operator(config, window)
    threshold = chi2_quantile(config.gate_probability, ndim * operator.shape[0])
    _, passed = _core.wavelet_coarse_gate(
        operator,
        (np.ascontiguousarray(radar_positions @ operator.T), radar_variances),
        (np.ascontiguousarray(esm_positions @ operator.T), esm_variances),
        CoarseGateSettings(threshold, config.whitened, config.n_threads),
    )
    return passed


def gate_full(
    config: GateConfig,
    radar: tuple[NDArray[np.float64], NDArray[np.float64]],
    esm: tuple[NDArray[np.float64], NDArray[np.float64]],
) -> NDArray[np.bool_]:
    """The whitened gate of coefficients ``(n, m)`` with their full covariances ``(n, m, m)``."""
    threshold = chi2_quantile(config.gate_probability, radar[0].shape[1])
    _, passed = _core.wavelet_coarse_gate_coupled(radar, esm, CoarseGateSettings(threshold, True, config.n_threads))
    return passed


def level0_gate(
    radar_positions: NDArray[np.float64],
    radar_variances: NDArray[np.float64],
    esm_positions: NDArray[np.float64],
    esm_variances: NDArray[np.float64],
    gate_probability: float,
) -> NDArray[np.bool_]:
    """The coarse test with W = I and Σ diagonal, for windows too short for one wavelet level:
    ``Σ_t Σ_axis d² / (σ_i² + σ_j²) ≤ χ²(ndim·T, gate_probability)`` (whitened and literal
    statistics coincide here), inputs ``(n, ndim, T)`` as :func:`.coarse.coarse_gate`'s."""
    diff = radar_positions[:, None] - esm_positions[None, :]
    total = radar_variances[:, None] + esm_variances[None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        statistic = np.where(total > 0, diff**2 / total, np.where(diff == 0, 0.0, np.inf)).sum(axis=(2, 3))
    dof = radar_positions.shape[1] * radar_positions.shape[2]
    passed: NDArray[np.bool_] = statistic <= chi2_quantile(gate_probability, dof)
    return passed


def _ages(present: NDArray[np.bool_], cap: int) -> NDArray[np.int64]:
    """Per track and scan, how many consecutive scans up to this one it has existed, ≤ cap."""
    ages = np.zeros(present.shape, dtype=np.int64)
    run = np.zeros(present.shape[0], dtype=np.int64)
    for k in range(present.shape[1]):
        run = np.where(present[:, k], run + 1, 0)
        ages[:, k] = np.minimum(run, cap)
    return ages


def _pair_windows(
    age_r: NDArray[np.int64], age_e: NDArray[np.int64]
) -> list[tuple[int, NDArray[np.intp], NDArray[np.intp], NDArray[np.bool_] | None]]:
    """One scan's coarse tests: per distinct pair window length ℓ = min(age_i, age_j), the
    tracks at least that old and which of their pairs have exactly that window (None: all of
    them — the usual case of tracks all of one age, tested in one call)."""
    rows, cols = np.flatnonzero(age_r), np.flatnonzero(age_e)
    if len(rows) == 0 or len(cols) == 0:
        return []
    ages = np.concatenate([age_r[rows], age_e[cols]])
    if (ages == ages[0]).all():
        return [(int(ages[0]), rows, cols, None)]
    out = []
    for length in np.unique(np.minimum.outer(age_r[rows], age_e[cols])):
        old_r, old_e = np.flatnonzero(age_r >= length), np.flatnonzero(age_e >= length)
        exact = np.minimum(age_r[old_r, None], age_e[None, old_e]) == length
        out.append((int(length), old_r, old_e, exact))
    return out


def _window(values: NDArray[np.float64], rows: NDArray[np.intp], span: slice) -> NDArray[np.float64]:
    """``values[rows, span]`` (n, T, d) as the coarse gate's (n, d, T), contiguous."""
    return np.ascontiguousarray(np.swapaxes(values[rows, span], 1, 2))
