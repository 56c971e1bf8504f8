"""The two baselines the wavelet paper (METHODS §5 step 5) compares with, with the same
interface as :class:`~passive_assoc.radar_esm.WaveletFuzzyAssociator`: ``associate(local=esm,
system=radar)`` on 1-D, 2-D or 3-D track tables.

* nearest neighbour — :class:`~passive_assoc.NearestNeighbourAssociator`, the one
  nearest-neighbour associator of the library: per scan, the gated optimal assignment on the
  distance between the current positions, with the position χ² gate when the tables carry
  covariances (:func:`position_gate_pairs` lists the pairs that gate passes).
* :class:`Chi2TrackAssociator` — the traditional weighted statistic test: per scan
  ``d = x_i − x_j`` over the state blocks both tables have, ``dᵀ(P_i + P_j)⁻¹d`` gated at
  ``χ²(dim d, gate_probability)``, then pairs one-to-one by increasing statistic (repeated
  minimum, ties to the closer positions).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np
from numpy.typing import NDArray
from scipy.stats import chi2

from .._params import Configurable, Interval, Threads
from .._progress import ProgressArg, reporting
from ..data import TrackTable
from ..track_association import TrackPairs
from .decision import repeated_maximum
from .scans import AlignedTracks, RadarEsmAssociation, align, all_unpaired, association, position_distance

__all__ = ["Chi2TrackAssociator", "chi2_statistic", "position_gate_pairs"]

#: A probability in (0, 1).
Probability = Annotated[float, Interval(float, 0.0, 1.0, closed="neither")]


def chi2_statistic(radar: AlignedTracks, esm: AlignedTracks, blocks: int) -> NDArray[np.float64]:
    """``dᵀ(P_i + P_j)⁻¹d`` over the first ``blocks`` state blocks (1 = position), every pair
    at every scan, ``(K, n_r, n_e)``; NaN where either track is absent, ∞ where the summed
    covariance is singular."""
    d = radar.ndim * blocks
    states_r = _state(radar, blocks)
    states_e = _state(esm, blocks)
    assert radar.covariance is not None and esm.covariance is not None
    diff = np.swapaxes(states_r, 0, 1)[:, :, None, :] - np.swapaxes(states_e, 0, 1)[:, None, :, :]
    cov_r = np.swapaxes(radar.covariance[:, :, :d, :d], 0, 1)[:, :, None]
    cov_e = np.swapaxes(esm.covariance[:, :, :d, :d], 0, 1)[:, None, :]
    total = cov_r + cov_e
    present = np.isfinite(diff).all(axis=-1)
    out = np.full(diff.shape[:3], np.nan)
    if present.any():
        out[present] = _quadratic_form(diff[present], total[present])
    return out


def _state(tracks: AlignedTracks, blocks: int) -> NDArray[np.float64]:
    parts = [tracks.position, tracks.velocity, tracks.acceleration][:blocks]
    return np.concatenate([p for p in parts if p is not None], axis=-1)


def _quadratic_form(diff: NDArray[np.float64], cov: NDArray[np.float64]) -> NDArray[np.float64]:
    """``dᵀ C⁻¹ d`` for stacks (m, d) and (m, d, d); ∞ where C is singular."""
    out = np.full(len(diff), np.inf)
    if diff.shape[1] == 1:  # 1-D positions: a division
        positive = cov[:, 0, 0] > 0
        out[positive] = diff[positive, 0] ** 2 / cov[positive, 0, 0]
        return out
    try:
        z = np.linalg.solve(cov, diff[..., None])[..., 0]
    except np.linalg.LinAlgError:
        # Some C is singular: pair by pair, leaving those at ∞.
        for i in range(len(diff)):
            try:
                out[i] = float(diff[i] @ np.linalg.solve(cov[i], diff[i]))
            except np.linalg.LinAlgError:
                continue
        return out
    out[:] = np.einsum("md,md->m", diff, z)
    return out


def _blocks(radar: TrackTable, esm: TrackTable) -> int:
    """State blocks both tables have (position; + velocity; + acceleration)."""
    return min(len(t.blocks) for t in (radar, esm) if len(t)) if len(radar) and len(esm) else 1


def position_gate_pairs(*, local: TrackTable, system: TrackTable, gate_probability: float) -> TrackPairs:
    """Every (local, system) pair of every scan whose positions pass the χ² gate
    ``Δpᵀ(P_i + P_j)⁻¹Δp ≤ χ²(ndim, gate_probability)`` (every present pair when a table has no
    covariances): the pairs :class:`~passive_assoc.NearestNeighbourAssociator` may make at a
    scan. The score of a pair is minus its distance."""
    times, r, e = align(system, local)
    distance = position_distance(r, e)
    allowed = np.isfinite(distance)
    if r.covariance is not None and e.covariance is not None:
        allowed &= chi2_statistic(r, e, blocks=1) <= chi2.ppf(gate_probability, r.ndim)
    empty = np.empty(0, np.intp)
    return association(times, r, e, (empty, empty, empty), -distance, candidates=allowed).candidates


@dataclass(frozen=True)
class Chi2TrackAssociator(Configurable):
    """The traditional weighted (χ²) track-to-track test, one-to-one by increasing statistic.

    Parameters
    ----------
    gate_probability : float
        The test's probability: pairs with a statistic above ``χ²(dof, gate_probability)``
        are never made.
    n_threads : int, optional
        Threads of the decision; results are identical for any value.
    """

    gate_probability: Probability = 0.99
    n_threads: Threads = None

    def associate(self, *, local: TrackTable, system: TrackTable, progress: ProgressArg = None) -> RadarEsmAssociation:
        """Associate every scan (``local``: the ESM's tracks, ``system``: the radar's); the
        score of a pair is minus its statistic. ``progress`` as
        :meth:`WaveletFuzzyAssociator.associate`'s (stages ``"statistic"`` and ``"decision"``)."""
        times, r, e = align(system, local, needs=("covariance",))
        blocks = _blocks(system, local)
        if (trivial := all_unpaired(times, r, e)) is not None:
            return trivial
        with reporting(progress) as report:
            statistic = chi2_statistic(r, e, blocks)
            allowed = statistic <= chi2.ppf(self.gate_probability, r.ndim * blocks)
            if report is not None:
                report("statistic", 1.0)
            pairs = repeated_maximum(-statistic, allowed, -np.inf, position_distance(r, e), self.n_threads)
            if report is not None:
                report("decision", 1.0)
        return association(times, r, e, pairs, -statistic, candidates=allowed)
