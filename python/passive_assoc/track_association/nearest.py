"""The nearest-neighbour track-to-track associator (METHODS §4 and §5's baseline): per scan,
the gated one-to-one pairing of least total (window-averaged) position distance."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np
from numpy.typing import NDArray

from .._params import COUNT, POSITIVE, Configurable, Interval, Threads
from .._settings import TopologySettings
from ..data import TrackTable
from .streaming import ScanSide, StreamingTrackAssociator, _planar_side

__all__ = ["NearestNeighbourAssociator"]


@dataclass(eq=False)
class NearestNeighbourAssociator(StreamingTrackAssociator, Configurable):
    """The nearest-neighbour baseline: per scan, the one-to-one pairing of least total
    position distance (averaged over the last ``window`` scans) among the pairs that pass the
    gates — the gated optimal assignment of MATLAB's and Stone Soup's distance-based
    track-to-track associators, and the baseline both track association papers compare with.
    Azimuth bias moves far targets by kilometres, so this collapses as the bias grows; the
    topology associator does not.

    Distances are taken in the tables' own dimension (1-D, 2-D or 3-D positions).

    Parameters
    ----------
    gate : float, optional
        Largest (window-averaged) distance of a pair, metres. Given, the pairing maximises
        ``Σ (gate − distance)`` over the pairs it makes; None (default): it makes as many
        pairs as the gates allow, then the least total distance.
    gate_probability : float, optional
        The position χ² gate: a pair needs ``Δpᵀ(P_i + P_j)⁻¹Δp ≤ χ²(ndim, gate_probability)``
        at the current scan, P the tracks' position covariances. Applied when both tables
        carry covariance columns; None switches it off. With neither gate (or neither table
        carrying covariances) every pair may be made.
    window : int
        Scans averaged, the current one included (1, the default: this scan only).
    n_threads : int, optional
        Threads; results are identical for any value.
    """

    gate: Annotated[float | None, POSITIVE, None] = None
    gate_probability: Annotated[float | None, Interval(float, 0.0, 1.0, closed="neither"), None] = 0.99
    window: Annotated[int, COUNT] = 1
    n_threads: Threads = None

    _min_ndim = 1

    def _gated(self, local: TrackTable, system: TrackTable) -> bool:
        """Whether the χ² gate applies to these tables."""
        return self.gate_probability is not None and local.covariance is not None and system.covariance is not None

    def _settings(self, local: TrackTable, system: TrackTable) -> TopologySettings:
        chi2_gate = None
        if self._gated(local, system):
            from scipy.stats import chi2

            chi2_gate = float(chi2.ppf(self.gate_probability, max(local.ndim, system.ndim)))
        return TopologySettings(
            scoring="distance",
            rings=1,
            sectors=1,
            radius=1.0,
            delta=0.0,
            delta_prime=0.0,
            diffusion="additive",
            reference="north",
            # Scores are minus distances: a pair needs d < gate. Without a gate the core
            # makes the most pairs, then the least total distance.
            threshold=-self.gate if self.gate is not None else 0.0,
            window=self.window,
            gate=self.gate,
            auto_gate=False,
            chi2_gate=chi2_gate,
            decision="assignment",
            # The bias bound of the reported bias estimate's reliability (TopologyAssociator's).
            max_bias_deg=5.0,
            max_range=400e3,
            gate_probability=0.999,
            topology_weight=0.0,
            n_threads=self.n_threads,
        )

    def _side(self, tracks: TrackTable, order: NDArray[np.int64]) -> ScanSide:
        """Planar positions, and the heights of 3-D tracks; with the χ² gate, the position
        covariances (a 1-D table's padded to 2 × 2 on the empty axis, where the difference
        is 0)."""
        ids, positions, _, _, _ = _planar_side(tracks, order)
        heights = np.ascontiguousarray(tracks.position[order, 2]) if tracks.ndim == 3 else None
        covariances = None
        if tracks.covariance is not None and self.gate_probability is not None:
            d = tracks.ndim
            block = tracks.covariance[order, :d, :d]
            if d == 1:
                padded = np.zeros((len(order), 2, 2))
                padded[:, 0, 0], padded[:, 1, 1] = block[:, 0, 0], 1.0
                block = padded
            covariances = np.ascontiguousarray(block, dtype=np.float64)
        return ids, positions, None, heights, covariances
