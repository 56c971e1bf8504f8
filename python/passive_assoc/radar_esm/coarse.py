"""The coarse gate of radar/ESM association (METHODS §5 step 2).

Each track's filtered position sequence over the window (T scans, per coordinate) is reduced
to its wavelet approximation coefficients with PyWavelets. The transform is linear, ``a = W
x``, with W (c × T) the *approximation operator*: the transform of the identity's columns.
A (radar i, ESM j) pair passes when ``d = a_i − a_j`` satisfies

    dᵀ (C_i + C_j)⁻¹ d ≤ χ²_{ndim·c}(gate_probability),    C = W Σ Wᵀ,

Σ the track's position covariance over the window: the filter's per-scan variances (diagonal
in time, coordinates independent), or the window's full covariance. On a true pair with
Gaussian noise the statistic is χ² with ndim·c degrees of freedom, so the gate rejects the
nominal 1 − gate_probability of true pairs. ``whitened=False`` is the paper's literal
statistic ``|d|² / (σ_i² + σ_j²)`` (σ² the mean per-scan variance, per coordinate) against the
same threshold, kept as an ablation: the boundary coefficients of white noise have variances
up to 4× the interior ones, so it rejects far more true pairs than nominal (METHODS §5). The
per-pair whitening and test run in the
Rust core, in parallel, with the GIL released.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np
import pywt  # PyWavelets ships no stubs or py.typed
from numpy.typing import ArrayLike, NDArray
from scipy.stats import chi2

from .. import _core
from .._params import Boolean, Constraint, Interval, Options, Threads, constraints_of, validate
from .._settings import CoarseGateSettings
from .._validation import as_float_array, readonly, require_finite, require_nonnegative
from .window import coefficient_covariance

__all__ = ["MAX_WINDOW", "MODES", "CoarseGate", "approximation_operator", "coefficients", "coarse_gate"]

#: PyWavelets' signal extension modes: how the transform treats the window's ends.
MODES: tuple[str, ...] = tuple(pywt.Modes.modes)

_OPERATOR_CONSTRAINTS: dict[str, list[Constraint]] = {
    "window": [Interval(int, 1, None)],
    "level": [Interval(int, 1, None)],
    "mode": [Options(*MODES)],
}
_GATE_CONSTRAINTS: dict[str, list[Constraint]] = {
    "level": [Interval(int, 1, None)],
    "mode": [Options(*MODES)],
    "gate_probability": [Interval(float, 0.0, 1.0, closed="neither")],
    "whitened": [Boolean()],
    "n_threads": constraints_of(Threads),
}


@dataclass(frozen=True, eq=False)
class CoarseGate:
    """The coarse gate of every (radar, ESM) track pair.

    Attributes
    ----------
    statistic : numpy.ndarray
        ``(n_radar, n_esm)`` float64: the whitened (or, as an ablation, scalar) statistic.
    passed : numpy.ndarray
        ``(n_radar, n_esm)`` bool: ``statistic <= threshold``.
    dof : int
        Degrees of freedom, ``ndim · c`` (c approximation coefficients per coordinate).
    threshold : float
        The χ²(dof) quantile at the gate probability.
    level : int
        The decomposition level used: the one asked for, or less for a short window.
    """

    statistic: NDArray[np.float64]
    passed: NDArray[np.bool_]
    dof: int
    threshold: float
    level: int


@functools.cache
def _discrete_wavelets() -> frozenset[str]:
    return frozenset(pywt.wavelist(kind="discrete"))


def _check_wavelet(wavelet: Any) -> str:
    if not isinstance(wavelet, str):
        raise TypeError(f"wavelet: expected a string, got {type(wavelet).__name__} {wavelet!r}")
    if wavelet not in _discrete_wavelets():
        raise ValueError(f"wavelet: {wavelet!r} is not a discrete wavelet (pywt.wavelist(kind='discrete') lists them)")
    return wavelet


def _shortest_window(wavelet: str) -> int:
    """The fewest scans that allow one level: ``pywt.dwt_max_level`` is ≥ 1 from 2·(L − 1)."""
    return 2 * (int(pywt.Wavelet(wavelet).dec_len) - 1)


#: Most scans a coarse window may hold. The operator W is built from the transform of a
#: ``window × window`` identity and a track's full window covariance has ``(ndim·window)²``
#: entries: at 1 024 scans 8 MB and 75 MB (3-D); a window of 10⁹ asked NumPy for exabytes.
#: The paper's whole run is 30 scans.
MAX_WINDOW = 1024


def _level(name: str, window: int, wavelet: str, level: int) -> int:
    """The level used for ``window`` scans: ``level``, reduced to the most the window allows."""
    if window > MAX_WINDOW:
        raise ValueError(f"{name}: a window of {window} scans exceeds the cap of {MAX_WINDOW} scans (MAX_WINDOW)")
    shortest = _shortest_window(wavelet)
    if window < shortest:
        raise ValueError(
            f"{name}: a window of {window} scans is too short for one level of {wavelet} "
            f"(at least {shortest} scans needed)"
        )
    return min(level, int(pywt.dwt_max_level(window, pywt.Wavelet(wavelet).dec_len)))


@functools.lru_cache(maxsize=64)
def _operator(window: int, wavelet: str, level: int, mode: str) -> NDArray[np.float64]:
    """W for an already reduced ``level``, read-only (it is shared by every caller)."""
    columns = pywt.wavedec(np.eye(window), wavelet, mode=mode, level=level, axis=0)[0]
    operator = np.ascontiguousarray(columns, dtype=np.float64)
    rank = int(np.linalg.matrix_rank(operator))
    if rank < operator.shape[0]:
        raise ValueError(
            f"mode: {mode!r} gives {operator.shape[0]} coefficients of rank {rank} for a window of {window} "
            f"scans ({wavelet}, level {level}): W Σ Wᵀ would be singular; use 'periodization' or 'symmetric'"
        )
    return readonly(operator)


def approximation_operator(
    window: int, wavelet: str = "sym2", level: int = 3, mode: str = "symmetric"
) -> tuple[NDArray[np.float64], int]:
    """The approximation operator W of a ``window``-scan sequence, and the level used.

    The discrete wavelet transform is linear, so W (c × window) is the approximation
    coefficients of ``pywt.wavedec`` applied to the identity's columns: a sequence ``x``
    of ``window`` scans has coefficients ``W @ x``.

    Parameters
    ----------
    window : int
        T, the scans of the window.
    wavelet : str
        A PyWavelets discrete wavelet (METHODS §5: ``"sym2"``).
    level : int
        The decomposition level asked for (the paper's 3). A window too short for it gets
        the most it allows, ``pywt.dwt_max_level(window, dec_len)`` (for sym2: level 1 from
        6 scans, 2 from 12, 3 from 24), as the paper reduces it for short windows.
    mode : str
        PyWavelets' signal extension at the window's ends (one of :data:`MODES`).

    Returns
    -------
    (numpy.ndarray, int)
        W, read-only ``(c, window)``, and the level used. Cached per (window, wavelet,
        level, mode).

    Raises
    ------
    ValueError
        If the window is too short for one level (for sym2: fewer than 6 scans) or longer
        than :data:`MAX_WINDOW` (1 024 scans), the wavelet is unknown, or the mode makes W
        rank-deficient for this window.

    Examples
    --------
    >>> W, level = approximation_operator(30)
    >>> W.shape, level
    ((6, 30), 3)
    >>> approximation_operator(16)[0].shape, approximation_operator(16)[1]  # 16 scans: level 2
    ((6, 16), 2)
    >>> approximation_operator(30, mode="periodization")[0].shape
    (4, 30)
    """
    values = validate({"window": window, "level": level, "mode": mode}, _OPERATOR_CONSTRAINTS)
    wavelet = _check_wavelet(wavelet)
    used = _level("window", values["window"], wavelet, values["level"])
    return _operator(values["window"], wavelet, used, values["mode"]), used


def _coefficients(name: str, positions: NDArray[np.float64], operator: NDArray[np.float64]) -> NDArray[np.float64]:
    if positions.shape[2] != operator.shape[1]:
        raise ValueError(
            f"{name}: expected {operator.shape[1]} scans on the last axis (the operator's columns), "
            f"got shape {positions.shape}"
        )
    return np.ascontiguousarray(positions @ operator.T)


def coefficients(positions: ArrayLike, operator: ArrayLike) -> NDArray[np.float64]:
    """The approximation coefficients ``(n, ndim, c)`` of ``positions`` ``(n, ndim, T)``
    under the operator W ``(c, T)`` of :func:`approximation_operator`.

    >>> W, _ = approximation_operator(30)
    >>> x = np.arange(60.0).reshape(1, 2, 30)
    >>> a = coefficients(x, W)
    >>> a.shape, bool(np.allclose(a[0, 0], pywt.wavedec(x[0, 0], "sym2", level=3)[0]))
    ((1, 2, 6), True)
    """
    w = as_float_array("operator", operator, ndim=2)
    require_finite("operator", w)
    x = as_float_array("positions", positions, ndim=3)
    require_finite("positions", x)
    return _coefficients("positions", x, w)


def _side(
    name: str, positions: ArrayLike, variances: ArrayLike, shape: tuple[int | None, ...]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Positions ``(n, ndim, T)`` and either per-scan variances of the same shape or a full
    window covariance ``(n, ndim, T, ndim, T)`` (the core checks its symmetry)."""
    x = as_float_array(f"{name}_positions", positions, shape=shape)
    if x.shape[1] < 1:
        raise ValueError(f"{name}_positions: needs at least one coordinate, got shape {x.shape}")
    require_finite(f"{name}_positions", x)
    v = as_float_array(f"{name}_variances", variances)
    if v.shape not in (x.shape, (*x.shape, *x.shape[1:])):
        n, ndim, window = x.shape
        raise ValueError(
            f"{name}_variances: expected shape {x.shape} (per-scan variances) or "
            f"{(n, ndim, window, ndim, window)} (the window's full covariance), got {v.shape}"
        )
    require_finite(f"{name}_variances", v)
    if v.ndim == 3:
        require_nonnegative(f"{name}_variances", v)
    return x, v


def _full(variances: NDArray[np.float64]) -> NDArray[np.float64]:
    """Per-scan variances ``(n, d, T)`` as the diagonal full covariance ``(n, d, T, d, T)``."""
    if variances.ndim == 5:
        return variances
    n, d, window = variances.shape
    out = np.zeros((n, d * window, d * window))
    out[:, np.arange(d * window), np.arange(d * window)] = variances.reshape(n, d * window)
    return out.reshape(n, d, window, d, window)


def coarse_gate(
    radar_positions: ArrayLike,
    radar_variances: ArrayLike,
    esm_positions: ArrayLike,
    esm_variances: ArrayLike,
    *,
    wavelet: str = "sym2",
    level: int = 3,
    mode: str = "symmetric",
    gate_probability: float = 0.99,
    whitened: bool = True,
    n_threads: int | None = None,
) -> CoarseGate:
    """The coarse gate (METHODS §5 step 2) of every (radar, ESM) track pair.

    Parameters
    ----------
    radar_positions, esm_positions : array_like
        ``(n_radar, ndim, T)`` and ``(n_esm, ndim, T)``: each track's filtered positions over
        the same T scans, per coordinate.
    radar_variances, esm_variances : array_like
        Σ over the window: the filters' per-scan position variances, same shapes as the
        positions, ≥ 0 (Σ diagonal in time); or the window's full covariance ``(n, ndim, T,
        ndim, T)`` (coordinate, scan), symmetric — a filtered track's errors are correlated from
        scan to scan (:mod:`.window` builds it from a constant-acceleration filter's
        covariances). A pair needs some variance on at least one side.
    wavelet, level, mode
        As :func:`approximation_operator` (the level is reduced for a short window; the one
        used is ``CoarseGate.level``).
    gate_probability : float
        In (0, 1): the share of true pairs the gate should keep (default 0.99).
    whitened : bool
        The whitened statistic (default), or the paper's literal scalar one (an ablation that
        rejects far more true pairs than nominal).
    n_threads : int, optional
        Threads for the pair loop (default: all cores); results do not depend on it.

    Returns
    -------
    CoarseGate
        The statistic and pass flags ``(n_radar, n_esm)``, the degrees of freedom, the
        threshold and the level used.

    Raises
    ------
    ValueError
        Mismatched shapes, NaN or infinite values or negative variances (naming the argument
        and the first bad element), a window too short for one level or longer than
        :data:`MAX_WINDOW`, or a pair whose summed covariance is not positive definite (naming
        the pair).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> truth = np.cumsum(rng.normal(0.0, 100.0, (3, 1, 30)), axis=2)  # 3 targets, x only
    >>> var = np.full((3, 1, 30), 0.5)
    >>> radar = truth + rng.normal(0.0, np.sqrt(0.5), truth.shape)
    >>> esm = truth + rng.normal(0.0, np.sqrt(0.5), truth.shape)
    >>> gate = coarse_gate(radar, var, esm, var)
    >>> gate.dof, round(gate.threshold, 2), gate.level
    (6, 16.81, 3)
    >>> gate.passed
    array([[ True, False, False],
           [False,  True, False],
           [False, False,  True]])
    """
    params = validate(
        {
            "level": level,
            "mode": mode,
            "gate_probability": gate_probability,
            "whitened": whitened,
            "n_threads": n_threads,
        },
        _GATE_CONSTRAINTS,
    )
    wavelet = _check_wavelet(wavelet)
    radar_x, radar_v = _side("radar", radar_positions, radar_variances, (None, None, None))
    _, ndim, window = radar_x.shape
    esm_x, esm_v = _side("esm", esm_positions, esm_variances, (None, ndim, window))
    used = _level("radar_positions", window, wavelet, params["level"])
    operator = _operator(window, wavelet, used, params["mode"])
    dof = ndim * operator.shape[0]
    threshold = float(chi2.ppf(params["gate_probability"], dof))
    settings = CoarseGateSettings(threshold, params["whitened"], params["n_threads"])
    radar_a = _coefficients("radar_positions", radar_x, operator)
    esm_a = _coefficients("esm_positions", esm_x, operator)
    if radar_v.ndim == 3 and esm_v.ndim == 3:
        statistic, passed = _core.wavelet_coarse_gate(operator, (radar_a, radar_v), (esm_a, esm_v), settings)
    elif not params["whitened"]:
        raise ValueError("whitened: the literal statistic reads per-scan variances, not a full covariance")
    else:
        statistic, passed = _core.wavelet_coarse_gate_coupled(
            (radar_a.reshape(len(radar_a), -1), coefficient_covariance(_full(radar_v), operator)),
            (esm_a.reshape(len(esm_a), -1), coefficient_covariance(_full(esm_v), operator)),
            settings,
        )
    return CoarseGate(readonly(statistic), readonly(passed), dof, threshold, used)
