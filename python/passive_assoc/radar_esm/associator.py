"""Radar/ESM track association with a wavelet coarse gate and weighted fuzzy factors
(METHODS §5, paper 003).

A radar and a passive (ESM) sensor track the same maneuvering targets; each sensor's tracks
come from its own Kalman filter (constant acceleration, METHODS §5 step 1). At every scan:

1. *Coarse gate* (:mod:`.coarse`): over the window — the scans so far in which both tracks
   exist, at most ``window`` of them (``None``: at most :data:`WINDOW_CAP`) — the wavelet
   approximation coefficients of the two filtered position sequences must agree within the
   χ² gate, with the statistic whitened by ``W (Σ_i + Σ_j) Wᵀ``.
2. *Fine stage* (:mod:`.fuzzy`): memberships of the acceleration, velocity and heading
   differences, combined as ``f = Σ a_l μ_l``.
3. *Decision* (:mod:`.decision`): repeated maximum of f over the gated pairs while it exceeds
   ε, one-to-one.

The radar is the *system* picture and the ESM the *local* one of the returned
:class:`~passive_assoc.assignment.TrackAssociation`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray
from scipy.stats import chi2

from .. import _core
from .._params import Boolean, Constraint, Interval, Options, validate
from .._settings import CoarseGateSettings
from ..data import TrackTable
from .coarse import MODES, _shortest_window, approximation_operator
from .decision import repeated_maximum
from .fuzzy import fuzzy_memberships
from .scans import AlignedTracks, RadarEsmAssociation, align, all_unpaired, association, position_distance

__all__ = ["WaveletFuzzyAssociator", "WINDOW_CAP", "check_weights"]

#: Longest coarse window when ``window=None``: 32 scans, which hold the paper's whole 30-scan
#: run and give 6 approximation coefficients per axis at sym2, 3 levels.
WINDOW_CAP = 32
UNIT = Interval(float, 0.0, 1.0)


def check_weights(weights: Sequence[float]) -> tuple[float, float, float]:
    """Three finite weights >= 0 summing to 1 (so that f and ε lie in [0, 1])."""
    if isinstance(weights, str) or not isinstance(weights, Sequence) or len(weights) != 3:
        raise TypeError(f"weights: expected three numbers (acceleration, velocity, heading), got {weights!r}")
    values = validate({f"weights[{k}]": w for k, w in enumerate(weights)}, {f"weights[{k}]": [UNIT] for k in range(3)})
    out = (values["weights[0]"], values["weights[1]"], values["weights[2]"])
    if not math.isclose(sum(out), 1.0, abs_tol=1e-9):
        raise ValueError(f"weights: must sum to 1, got {weights!r} (sum {sum(out)!r})")
    return out


@dataclass(frozen=True)
class _Config:
    wavelet: str
    level: int
    mode: str
    window: int | None
    gate_probability: float
    weights: tuple[float, float, float]
    tau: float
    epsilon: float
    whitened: bool
    n_threads: int | None


class WaveletFuzzyAssociator:
    """Wavelet-fuzzy radar/ESM track associator (METHODS §5).

    Parameters
    ----------
    wavelet : str
        A discrete PyWavelets wavelet (paper: ``"sym2"``).
    level : int
        Decomposition levels (paper: 3); reduced for windows too short to hold them.
    mode : str
        PyWavelets' boundary extension mode (one of :data:`MODES`).
    window : int, optional
        Most scans in the coarse window; None: all scans so far, at most :data:`WINDOW_CAP`.
    gate_probability : float
        Probability of the χ² coarse gate (its degrees of freedom = coefficients × axes).
    weights : (float, float, float)
        a1, a2, a3 of the acceleration, velocity and heading factors; they sum to 1.
    tau : float
        τ of the memberships ``exp(−τ u²/σ²)``.
    epsilon : float
        ε: a pair needs ``f > ε`` (the paper wants 0.5 ≤ ε ≤ 1).
    whitened : bool
        Whiten the coarse statistic (METHODS); False is the paper's literal scalar-variance
        statistic, kept as an ablation (it rejects true pairs far above the nominal rate).
    n_threads : int, optional
        Threads of the coarse gate; results are identical for any value.

    Examples
    --------
    >>> import passive_assoc as pa
    >>> pa.WaveletFuzzyAssociator(epsilon=0.6).config.epsilon
    0.6
    """

    _constraints: ClassVar[dict[str, list[Constraint]]] = {
        "level": [Interval(int, 1, None)],
        "mode": [Options(*MODES)],
        "window": [Interval(int, 1, None), None],
        "gate_probability": [Interval(float, 0.0, 1.0, closed="neither")],
        "tau": [Interval(float, 0.0, None, closed="neither")],
        "epsilon": [UNIT],
        "whitened": [Boolean()],
        "n_threads": [Interval(int, 1, None), None],
    }

    def __init__(
        self,
        wavelet: str = "sym2",
        level: int = 3,
        mode: str = "symmetric",
        window: int | None = None,
        gate_probability: float = 0.99,
        weights: Sequence[float] = (0.5, 0.3, 0.2),
        tau: float = 0.5,
        epsilon: float = 0.5,
        whitened: bool = True,
        n_threads: int | None = None,
    ) -> None:
        values = dict(
            level=level,
            mode=mode,
            window=window,
            gate_probability=gate_probability,
            tau=tau,
            epsilon=epsilon,
            whitened=whitened,
            n_threads=n_threads,
        )
        checked = validate(values, self._constraints)
        # Checks the wavelet's name, and that the longest window allows at least one level.
        approximation_operator(checked["window"] or WINDOW_CAP, wavelet, checked["level"], checked["mode"])
        self.config = _Config(wavelet=wavelet, weights=check_weights(weights), **checked)

    def __repr__(self) -> str:
        fields = ", ".join(f"{k}={v!r}" for k, v in vars(self.config).items())
        return f"WaveletFuzzyAssociator({fields})"

    def associate(self, radar: TrackTable, esm: TrackTable) -> RadarEsmAssociation:
        """Associate every scan of the two sensors' tracks.

        Both tables hold one sensor's tracks each, with velocity, acceleration and covariance
        columns, at common scan times. Every track of every scan ends in one pair or unpaired.
        """
        times, r, e = align(radar, esm, needs=("velocity", "acceleration", "covariance"))
        if (trivial := all_unpaired(times, r, e)) is not None:
            return trivial
        passed = self.coarse(r, e)
        weights = np.asarray(self.config.weights)
        similarity = np.einsum("l,lkre->kre", weights, fuzzy_memberships(r, e, self.config.tau))
        pairs = repeated_maximum(similarity, passed, self.config.epsilon, position_distance(r, e))
        return association(times, r, e, pairs, similarity, candidates=passed)

    def coarse(self, radar: AlignedTracks, esm: AlignedTracks) -> NDArray[np.bool_]:
        """Which (radar, ESM) pairs pass the coarse gate at each scan, ``(K, n_r, n_e)``.

        A pair's window is the scans so far in which both tracks exist, at most the cap; one
        shorter than the wavelet allows (6 scans for sym2) is tested at level 0 (W = I: the
        positions themselves, :func:`level0_gate`).
        """
        cap = self.config.window if self.config.window is not None else WINDOW_CAP
        shortest = _shortest_window(self.config.wavelet)
        n_scans = radar.present.shape[1]
        passed = np.zeros((n_scans, len(radar), len(esm)), dtype=bool)
        age_r, age_e = _ages(radar.present, cap), _ages(esm.present, cap)
        var_r = np.diagonal(radar.block_covariance(0), axis1=2, axis2=3)
        var_e = np.diagonal(esm.block_covariance(0), axis1=2, axis2=3)
        for k in range(n_scans):
            for length, rows, cols, exact in _pair_windows(age_r[:, k], age_e[:, k]):
                span = slice(k - length + 1, k + 1)
                sides = (
                    _window(radar.position, rows, span),
                    _window(var_r, rows, span),
                    _window(esm.position, cols, span),
                    _window(var_e, cols, span),
                )
                ok = self._gate(*sides) if length >= shortest else level0_gate(*sides, self.config.gate_probability)
                block = np.ix_(rows, cols)
                passed[k][block] = ok if exact is None else np.where(exact, ok, passed[k][block])
        return passed

    def _gate(
        self,
        radar_positions: NDArray[np.float64],
        radar_variances: NDArray[np.float64],
        esm_positions: NDArray[np.float64],
        esm_variances: NDArray[np.float64],
    ) -> NDArray[np.bool_]:
        """:func:`.coarse.coarse_gate` of validated, contiguous windows without its per-call
        checks: the operator and threshold are cached per window length (a test holds the two
        equal). The associator calls it once per scan, so the checks would cost more than the
        gate itself."""
        c = self.config
        _, ndim, window = radar_positions.shape
        operator, _ = approximation_operator_cached(window, c.wavelet, c.level, c.mode)
        threshold = chi2_quantile(c.gate_probability, ndim * operator.shape[0])
        _, passed = _core.wavelet_coarse_gate(
            operator,
            (np.ascontiguousarray(radar_positions @ operator.T), radar_variances),
            (np.ascontiguousarray(esm_positions @ operator.T), esm_variances),
            CoarseGateSettings(threshold, c.whitened, c.n_threads),
        )
        return passed


#: :func:`.coarse.approximation_operator`, cached with its checks done once per argument set.
approximation_operator_cached = functools.lru_cache(maxsize=256)(approximation_operator)


@functools.lru_cache(maxsize=1024)
def chi2_quantile(probability: float, dof: int) -> float:
    """χ²(dof) quantile, cached (scipy's ppf costs ~0.1 ms a call)."""
    return float(chi2.ppf(probability, dof))


def level0_gate(
    radar_positions: NDArray[np.float64],
    radar_variances: NDArray[np.float64],
    esm_positions: NDArray[np.float64],
    esm_variances: NDArray[np.float64],
    gate_probability: float,
) -> NDArray[np.bool_]:
    """The coarse test with W = I, for windows too short for one wavelet level:
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
