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

The radar is the *system* picture and the ESM the *local* one, in the arguments and in the
returned :class:`~passive_assoc.TrackAssociation`. Either may be filtered tracks or raw
reports, filtered here (:mod:`.sides`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Annotated, Literal

import numpy as np
from numpy.typing import NDArray

from .._params import COUNT, POSITIVE, Boolean, Configurable, Interval, Options, Threads, validate
from .._progress import ProgressArg, reporting
from ..data import TrackTable
from .coarse import MODES, approximation_operator
from .decision import repeated_maximum
from .fuzzy import fuzzy_memberships
from .scan_gate import WINDOW_CAP, Sigma, coarse_by_scan
from .scans import AlignedTracks, RadarEsmAssociation, all_unpaired, association, position_distance
from .sides import prepare

__all__ = ["WaveletFuzzyAssociator", "check_weights"]

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
class WaveletFuzzyAssociator(Configurable):
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
        Most scans in the coarse window, at most :data:`~passive_assoc.radar_esm.MAX_WINDOW`
        (1 024); None: all scans so far, at most :data:`WINDOW_CAP` (32).
    gate_probability : float
        Probability of the χ² coarse gate (its degrees of freedom = coefficients × axes).
    weights : (float, float, float)
        a1, a2, a3 of the acceleration, velocity and heading factors; they sum to 1.
    tau : float
        τ of the memberships ``exp(−τ u²/σ²)``. The default 0.1 lets a true pair clear
        ε = 0.5: its u²/σ² is at most χ²₁(0.99) = 6.63 in 99 % of scans, and
        ``exp(−0.1 · 6.63) = 0.52``; METHODS' reading τ = 0.5 (:meth:`paper`) puts 9 % of true
        pairs' memberships under 0.5 and loses them to ε early in a track, where the filter's
        velocity and acceleration are uncertain (docs/experiments.md, wavelet).
    epsilon : float
        ε: a pair needs ``f > ε`` (the paper wants 0.5 ≤ ε ≤ 1).
    whitened : bool
        Whiten the coarse statistic (METHODS); False is the paper's literal scalar-variance
        statistic, kept as an ablation (it rejects true pairs far above the nominal rate).
    process_noise : float or "auto", optional
        The white-jerk density q (m²/s⁵) of the constant-acceleration Kalman filter that made
        the tracks. ``"auto"`` (default): read back from each side's covariances
        (:func:`.tracks.process_noise_of`, exact for tracks such a filter made). Known, Σ over
        the window is the filtered sequence's whole covariance, its scan-to-scan correlation
        rebuilt from the tracks' covariances and q (:mod:`.window`), and the gate keeps true
        pairs at the nominal rate. None, or tracks that are not one such filter's: Σ is
        diagonal in time (per-scan covariances only), which on filtered tracks rejects many
        more true pairs than nominal (docs/experiments.md). For raw reports a number is also
        the q they are filtered with (:mod:`.sides`). Whitened only.
    n_threads : int, optional
        Threads of the coarse gate; results are identical for any value.

    The published method, as METHODS reads it, is :meth:`paper` (τ = 0.5).

    Examples
    --------
    >>> import passive_assoc as pa
    >>> pa.WaveletFuzzyAssociator(epsilon=0.6).epsilon
    0.6
    """

    wavelet: str = "sym2"
    level: Annotated[int, COUNT] = 3
    mode: Annotated[str, Options(*MODES)] = "symmetric"
    window: Annotated[int | None, COUNT, None] = None
    gate_probability: Annotated[float, Interval(float, 0.0, 1.0, closed="neither")] = 0.99
    weights: Sequence[float] = (0.5, 0.3, 0.2)
    tau: Annotated[float, POSITIVE] = 0.1
    epsilon: Annotated[float, UNIT] = 0.5
    whitened: Annotated[bool, Boolean()] = True
    process_noise: Annotated[float | Literal["auto"] | None, Options("auto"), Interval(float, 0.0, None), None] = "auto"
    n_threads: Threads = None

    @classmethod
    def paper(cls, **changes: object) -> WaveletFuzzyAssociator:
        """The published method as METHODS §5 reads it: sym2, 3 levels, the whitened coarse
        gate at 0.99, weights (0.5, 0.3, 0.2), τ = 0.5, ε = 0.5. ``changes`` override any
        parameter."""
        settings: dict[str, object] = {"tau": 0.5, **changes}
        return cls(**settings)  # type: ignore[arg-type]

    def __post_init__(self) -> None:
        super().__post_init__()
        if isinstance(self.process_noise, float) and not self.whitened:
            raise ValueError("process_noise: the cross-time covariance is for the whitened statistic (whitened=True)")
        # Checks the wavelet's name, and that the longest window allows at least one level.
        approximation_operator(self.window or WINDOW_CAP, self.wavelet, self.level, self.mode)
        object.__setattr__(self, "weights", check_weights(self.weights))

    def associate(self, *, local: TrackTable, system: TrackTable, progress: ProgressArg = None) -> RadarEsmAssociation:
        """Associate every scan of the two sensors' tracks: ``local`` the ESM's, ``system``
        the radar's.

        Both tables hold one sensor's tracks each at common scan times: filtered tracks (with
        velocity, acceleration and covariance columns) or raw position reports with their
        covariances, which are filtered here and whose coarse gate reads the reports
        themselves (:mod:`.sides`). Every track of every scan ends in one pair or unpaired.
        ``progress`` as :meth:`TopologyAssociator.associate`'s (stages ``"coarse"`` and
        ``"fine"``).
        """
        sides = prepare(local, system, self.process_noise if self.whitened else None, self.n_threads)
        times, r, e = sides.times, sides.radar, sides.esm
        if (trivial := all_unpaired(times, r, e)) is not None:
            return trivial
        with reporting(progress) as report:
            passed = self.coarse(sides.coarse_radar, sides.coarse_esm, times, sides.sigma)
            if report is not None:
                report("coarse", 1.0)
            weights = np.asarray(self.weights)
            similarity = np.einsum("l,lkre->kre", weights, fuzzy_memberships(r, e, self.tau))
            pairs = repeated_maximum(similarity, passed, self.epsilon, position_distance(r, e), self.n_threads)
            if report is not None:
                report("fine", 1.0)
        return association(times, r, e, pairs, similarity, candidates=passed)

    def coarse(
        self,
        radar: AlignedTracks,
        esm: AlignedTracks,
        times: NDArray[np.float64] | None = None,
        sigma: Sigma | None = None,
    ) -> NDArray[np.bool_]:
        """Which (radar, ESM) pairs pass the coarse gate at each scan, ``(K, n_r, n_e)``
        (:func:`.scan_gate.coarse_by_scan`); ``times``, the scan times, are needed with a
        process noise; ``sigma`` says how Σ is taken (default: the whole covariance with
        ``process_noise`` when it is a number, else per scan)."""
        return coarse_by_scan(self, radar, esm, times, sigma)
