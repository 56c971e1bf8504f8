"""Track-to-track association: the result every track associator returns, and the base class
of the per-scan associators (topology, nearest neighbour).

A *local* :class:`~passive_assoc.data.TrackTable` holds the tracks of one or more sources
(radars); the *system* table holds the fusion centre's picture. At every scan each local
source's tracks are paired one-to-one with system tracks; every local track of every scan
ends either in a pair or in the unpaired set, and so does every system track, per source.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from .. import _core
from .._params import Constraint, Interval, validate
from .._settings import TopologySettings
from ..data import TrackTable

__all__ = [
    "BiasEstimate",
    "NearestNeighbourAssociator",
    "TrackAssociation",
    "TrackAssociator",
    "TrackPairs",
    "UnpairedTracks",
]


@dataclass(frozen=True)
class TrackPairs:
    """Pairs, one row each: at ``time``, local track ``local_track`` of ``source`` is system
    track ``system_track``, with the (window-averaged) ``score`` that decided it."""

    time: NDArray[np.float64]
    source: NDArray[np.int64]
    local_track: NDArray[np.int64]
    system_track: NDArray[np.int64]
    score: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.time)


@dataclass(frozen=True)
class UnpairedTracks:
    """Tracks left unpaired, one row each: track ``track`` at ``time``, for local ``source``
    (for system tracks: not paired with any track of that source)."""

    time: NDArray[np.float64]
    source: NDArray[np.int64]
    track: NDArray[np.int64]

    def __len__(self) -> int:
        return len(self.time)


@dataclass(frozen=True)
class BiasEstimate:
    """A source's picture relative to the system's: ``p ≈ R(rotation)·q + translation``.

    ``rotation`` is the relative azimuth bias in radians (counter-clockwise), with its
    standard deviation; ``translation`` in metres (zero for a rotation-only fit); ``pairs`` is
    how many associated pairs it was fitted to.
    """

    rotation: float
    rotation_std: float
    translation: tuple[float, float]
    pairs: int

    @property
    def rotation_deg(self) -> float:
        return float(np.degrees(self.rotation))

    @classmethod
    def _from_core(cls, bias: _core.Bias | None) -> BiasEstimate | None:
        if bias is None:
            return None
        return cls(bias.rotation, bias.rotation_std, bias.translation, bias.pairs)


@dataclass(frozen=True)
class TrackAssociation:
    """Output of a track associator over one or more scans.

    Every local track of every scan is in exactly one row of :attr:`pairs` or
    :attr:`unpaired_local`; every system track of a scan is, for each local source, in
    exactly one row of :attr:`pairs` or :attr:`unpaired_system`. :attr:`bias` holds each
    local source's estimated bias relative to the system picture (absent for a source that
    was never paired, or when the associator does not estimate it).
    """

    pairs: TrackPairs
    unpaired_local: UnpairedTracks
    unpaired_system: UnpairedTracks
    bias: dict[int, BiasEstimate] = field(default_factory=dict)


class TrackAssociator(ABC):
    """Base of the per-scan associators: :meth:`associate` runs :meth:`update` on every scan
    of the local table; :meth:`update` pairs one scan and keeps each source's state (the
    window's history, the bias sums) between calls for live use; :meth:`reset` forgets it."""

    def __init__(self) -> None:
        self._states: dict[int, _core.AssociatorState] = {}

    @abstractmethod
    def _settings(self) -> Any:
        """The core's settings object for one source's state."""

    def reset(self) -> None:
        """Forget every source's history."""
        self._states = {}

    def associate(self, local: TrackTable, system: TrackTable) -> TrackAssociation:
        """Associate every scan of ``local`` with the system tracks of the same time, from a
        fresh state. A scan the system table lacks leaves every local track unpaired; at a
        scan where a local source has no track (or only the system table has the scan),
        every system track is unpaired for that source."""
        self.reset()
        sources = local.sources
        times = np.union1d(local.scan_times(), system.scan_times())
        return _merge(self._scan(local.at(t), system.at(t), sources) for t in times)

    def update(self, local: TrackTable, system: TrackTable) -> TrackAssociation:
        """Associate one scan: ``local`` and ``system`` hold the tracks of one time. Every
        source seen so far that has no track in ``local`` leaves the system tracks unpaired."""
        return self._scan(local, system, np.union1d(local.sources, np.fromiter(self._states, np.int64)))

    def _scan(self, local: TrackTable, system: TrackTable, sources: NDArray[np.int64]) -> TrackAssociation:
        """One scan, for each of ``sources`` (a source without tracks in ``local`` pairs none:
        its system tracks are unpaired, and its state is left as it is)."""
        times = np.unique(np.concatenate([local.time, system.time]))
        if len(times) > 1:
            raise ValueError(f"local, system: one scan expected, got {len(times)} distinct times")
        present = set(local.sources.tolist())
        parts = [
            self._update_source(int(source), local.of(int(source)), system)
            if int(source) in present
            else _system_unpaired(int(source), system)
            for source in sources
        ]
        out = _merge(parts)
        bias = {source: b for source in self._states if (b := self.bias(source)) is not None}
        return TrackAssociation(out.pairs, out.unpaired_local, out.unpaired_system, bias)

    def bias(self, source: int) -> BiasEstimate | None:
        """``source``'s bias estimate from every pair so far (rigid fit)."""
        state = self._states.get(source)
        return None if state is None else BiasEstimate._from_core(state.bias())

    def _update_source(self, source: int, local: TrackTable, system: TrackTable) -> TrackAssociation:
        if source not in self._states:
            self._states[source] = _core.AssociatorState(self._settings())
        # The core sees the rows in an order of their own (by position), so that track ids,
        # which carry no meaning, cannot decide between equal scores (formation slots tie).
        local_order, system_order = _by_position(local, "local"), _by_position(system, "system")
        out = self._states[source].update(_side(local, local_order), _side(system, system_order))
        rows, cols = local_order[out.pairs[:, 0]], system_order[out.pairs[:, 1]]
        time = float(local.time[0]) if len(local) else float("nan")
        local_left = np.setdiff1d(np.arange(len(local)), rows)
        system_left = np.setdiff1d(np.arange(len(system)), cols)
        pairs = TrackPairs(
            np.full(len(rows), time), np.full(len(rows), source), local.track[rows], system.track[cols], out.scores
        )
        return TrackAssociation(
            pairs,
            UnpairedTracks(np.full(len(local_left), time), np.full(len(local_left), source), local.track[local_left]),
            UnpairedTracks(
                np.full(len(system_left), time), np.full(len(system_left), source), system.track[system_left]
            ),
        )


def _system_unpaired(source: int, system: TrackTable) -> TrackAssociation:
    """A scan at which ``source`` has no track: every system track is unpaired for it."""
    n = len(system)
    time = np.full(n, float(system.time[0]) if n else np.nan)
    nothing = UnpairedTracks(np.empty(0), np.empty(0, np.int64), np.empty(0, np.int64))
    pairs = TrackPairs(np.empty(0), np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0))
    return TrackAssociation(pairs, nothing, UnpairedTracks(time, np.full(n, source, np.int64), system.track.copy()))


def _by_position(tracks: TrackTable, name: str) -> NDArray[np.int64]:
    """Row order by x, then y (then id, for coincident tracks)."""
    if tracks.ndim < 2:
        raise ValueError(f"{name}: track association needs 2-D or 3-D positions, got ndim={tracks.ndim}")
    return np.lexsort((tracks.track, tracks.position[:, 1], tracks.position[:, 0])).astype(np.int64)


def _side(tracks: TrackTable, order: NDArray[np.int64]) -> _core.ScanSide:
    """The core's view of one scan, rows in ``order``: ids, planar positions, velocities."""
    positions = np.ascontiguousarray(tracks.position[order, :2], dtype=np.float64)
    velocity = None if tracks.velocity is None else np.ascontiguousarray(tracks.velocity[order, :2], dtype=np.float64)
    return np.ascontiguousarray(tracks.track[order], dtype=np.int64), positions, velocity


def _merge(parts: Iterable[TrackAssociation]) -> TrackAssociation:
    """Concatenate per-scan / per-source results in order."""
    items = list(parts)

    def cat(arrays: list[NDArray[Any]], dtype: type) -> NDArray[Any]:
        return np.concatenate(arrays).astype(dtype) if arrays else np.empty(0, dtype)

    def unpaired(get: str) -> UnpairedTracks:
        sides = [getattr(p, get) for p in items]
        return UnpairedTracks(
            cat([s.time for s in sides], np.float64),
            cat([s.source for s in sides], np.int64),
            cat([s.track for s in sides], np.int64),
        )

    pairs = TrackPairs(
        cat([p.pairs.time for p in items], np.float64),
        cat([p.pairs.source for p in items], np.int64),
        cat([p.pairs.local_track for p in items], np.int64),
        cat([p.pairs.system_track for p in items], np.int64),
        cat([p.pairs.score for p in items], np.float64),
    )
    bias = items[-1].bias if items else {}
    return TrackAssociation(pairs, unpaired("unpaired_local"), unpaired("unpaired_system"), bias)


class NearestNeighbourAssociator(TrackAssociator):
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

    _constraints: ClassVar[dict[str, list[Constraint]]] = {
        "gate": [Interval(float, 0.0, None, closed="neither")],
        "window": [Interval(int, 1, None)],
        "n_threads": [Interval(int, 1, None), None],
    }

    def __init__(self, gate: float = 60e3, window: int = 6, n_threads: int | None = None) -> None:
        super().__init__()
        checked = validate(dict(gate=gate, window=window, n_threads=n_threads), self._constraints)
        self.gate: float = checked["gate"]
        self.window: int = checked["window"]
        self.n_threads: int | None = checked["n_threads"]

    def __repr__(self) -> str:
        return f"NearestNeighbourAssociator(gate={self.gate!r}, window={self.window!r})"

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
