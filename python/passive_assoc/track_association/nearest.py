"""The nearest-neighbour track-to-track baseline (METHODS §4): per scan, the gated
one-to-one pairing of least total (window-averaged) position distance."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

from .._params import POSITIVE, Configurable, Interval, Threads
from .._settings import TopologySettings
from .streaming import StreamingTrackAssociator

__all__ = ["NearestNeighbourAssociator"]


@dataclass(eq=False)
class NearestNeighbourAssociator(StreamingTrackAssociator, Configurable):
    """The baseline: per scan, the one-to-one pairing that minimises the total position
    distance (averaged over the last ``window`` scans) within ``gate`` metres — the gated
    optimal assignment of MATLAB's and Stone Soup's distance-based track-to-track
    associators. Azimuth bias moves far targets by kilometres, so this collapses as the bias
    grows; the topology associator does not.

    Parameters
    ----------
    gate : float
        Largest (window-averaged) distance of a pair, metres.
    window : int
        Scans averaged, the current one included (1 = this scan only).
    n_threads : int, optional
    """

    gate: Annotated[float, POSITIVE] = 60e3
    window: Annotated[int, Interval(int, 1, None)] = 6
    n_threads: Threads = None

    def _settings(self) -> TopologySettings:
        return TopologySettings(
            scoring="distance",
            rings=1,
            sectors=1,
            radius=1.0,
            delta=0.0,
            delta_prime=0.0,
            diffusion="additive",
            reference="north",
            threshold=-self.gate,  # scores are minus distances: a pair needs d < gate
            window=self.window,
            gate=self.gate,
            decision="assignment",
            n_threads=self.n_threads,
        )
