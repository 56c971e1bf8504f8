"""The per-scan track-to-track associators' common machinery (METHODS §4): each local
source's streaming state in the core (the window's scores, the bias sums), a scan at a time.
:class:`~passive_assoc.TopologyAssociator` and :class:`~passive_assoc.NearestNeighbourAssociator`
build on it."""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from .. import _core
from .._progress import ProgressArg, reporting
from ..data import TrackTable
from .result import BiasEstimate, TrackAssociation, TrackPairs, UnpairedTracks, merge, no_pairs, no_unpaired

__all__ = ["ScanSide", "StreamingTrackAssociator"]

#: One side of a scan as the core reads it: track ids, planar positions, and optionally planar
#: velocities, heights and position covariances.
ScanSide = tuple[
    NDArray[np.int64],
    NDArray[np.float64],
    NDArray[np.float64] | None,
    NDArray[np.float64] | None,
    NDArray[np.float64] | None,
]


@dataclass(eq=False)
class StreamingTrackAssociator(ABC):
    """Base of the per-scan associators: :meth:`associate` runs :meth:`update` on every scan
    of the local table; :meth:`update` pairs one scan and keeps each source's state (the
    window's history, the bias sums) between calls for live use; :meth:`reset` forgets it."""

    _states: dict[int, _core.AssociatorState] = field(default_factory=dict, init=False, repr=False)

    #: The fewest position axes a table may have.
    _min_ndim: ClassVar[int] = 2

    @abstractmethod
    def _settings(self, local: TrackTable, system: TrackTable) -> Any:
        """The core's settings object for one source's state, made at the source's first
        scan (``local``, ``system``)."""

    def _side(self, tracks: TrackTable, order: NDArray[np.int64]) -> ScanSide:
        """The core's view of one scan, rows in ``order``: ids, planar positions, velocities."""
        return _planar_side(tracks, order)

    def reset(self) -> None:
        """Forget every source's history."""
        self._states = {}

    def associate(self, *, local: TrackTable, system: TrackTable, progress: ProgressArg = None) -> TrackAssociation:
        """Associate every scan of ``local`` with the system tracks of the same time, from a
        fresh state. A scan the system table lacks leaves every local track unpaired; at a
        scan where a local source has no track (or only the system table has the scan),
        every system track is unpaired for that source.

        ``progress``: a bar over the scans on stderr (None: on a terminal once the call has
        run 2 s; True: always; False: never), or a callable of your own receiving
        ``("scans", fraction)``; raising in it stops the call."""
        _check_tables(local, system, self._min_ndim)
        self.reset()
        sources = local.sources
        times = np.union1d(local.scan_times(), system.scan_times())
        parts = []
        with reporting(progress) as report:
            for k, t in enumerate(times):
                parts.append(self._scan(local.at(t), system.at(t), sources))
                if report is not None:
                    report("scans", (k + 1) / len(times))
        return merge(parts)

    def update(self, *, local: TrackTable, system: TrackTable) -> TrackAssociation:
        """Associate one scan: ``local`` and ``system`` hold the tracks of one time. Every
        source seen so far that has no track in ``local`` leaves the system tracks unpaired."""
        _check_tables(local, system, self._min_ndim)
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
        out = merge(parts)
        bias = {source: b for source in self._states if (b := self.bias(source)) is not None}
        return TrackAssociation(out.pairs, out.unpaired_local, out.unpaired_system, bias)

    def bias(self, source: int) -> BiasEstimate | None:
        """``source``'s bias estimate from every pair so far (rigid fit)."""
        state = self._states.get(source)
        return None if state is None else BiasEstimate._from_core(state.bias())

    def _update_source(self, source: int, local: TrackTable, system: TrackTable) -> TrackAssociation:
        if source not in self._states:
            self._states[source] = _core.AssociatorState(self._settings(local, system))
        # The core sees the rows in an order of their own (by position), so that track ids,
        # which carry no meaning, cannot decide between equal scores (formation slots tie).
        local_order, system_order = _by_position(local), _by_position(system)
        out = self._states[source].update(self._side(local, local_order), self._side(system, system_order))
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
    return TrackAssociation(
        no_pairs(), no_unpaired(), UnpairedTracks(time, np.full(n, source, np.int64), system.track.copy())
    )


def _by_position(tracks: TrackTable) -> NDArray[np.int64]:
    """Row order by x, then y (then id, for coincident tracks)."""
    keys = [tracks.track, *(tracks.position[:, axis] for axis in reversed(range(min(tracks.ndim, 2))))]
    return np.lexsort(keys).astype(np.int64)


def _planar_side(tracks: TrackTable, order: NDArray[np.int64]) -> ScanSide:
    """Ids, planar positions and velocities of the rows in ``order`` (1-D tables on the x axis)."""
    positions = np.zeros((len(order), 2))
    positions[:, : min(tracks.ndim, 2)] = tracks.position[order, :2]
    velocity = None
    if tracks.velocity is not None and tracks.ndim >= 2:
        velocity = np.ascontiguousarray(tracks.velocity[order, :2], dtype=np.float64)
    return np.ascontiguousarray(tracks.track[order], dtype=np.int64), positions, velocity, None, None


def _check_tables(local: Any, system: Any, min_ndim: int) -> None:
    """Both sides are track tables of the same dimension, at least ``min_ndim``."""
    for name, table in (("local", local), ("system", system)):
        if not isinstance(table, TrackTable):
            raise TypeError(f"{name}: expected a TrackTable, got {type(table).__name__}")
        if table.ndim < min_ndim:
            raise ValueError(f"{name}: this track association needs 2-D or 3-D positions, got ndim={table.ndim}")
    if len(system.sources) > 1:
        raise ValueError(f"system: one sensor's tracks expected, got sources {system.sources.tolist()}")
    if len(local) and len(system) and local.ndim != system.ndim:
        raise ValueError(f"system: has {system.ndim}-D positions, local has {local.ndim}-D")
