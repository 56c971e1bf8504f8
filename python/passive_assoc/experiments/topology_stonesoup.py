"""Stone Soup's track-to-track associators as the ring scene compares them
(:mod:`.topology_ring`, ``--stonesoup``; the extra ``stonesoup``).

Two of Stone Soup's associators, each with a 30 km threshold on the (x, y) distance (the best
threshold found for them on this scene; the bias moves targets by up to ~50 km at ±5°):

* ``TrackToTrackCounting`` (whole tracks at once: a pair is associated over the time range
  its distance stays within the threshold, confirmed after 3 scans, ended after 2 misses),
  not one-to-one; a counting association covers every scan both tracks share in its range;
* ``OneToOneTrackAssociator`` (``linear_sum_assignment`` on the latest states' Euclidean
  distance), called every scan on the tracks up to that scan.

Their results carry the pairs only (what the scores read); the conversions follow
``benches/bench_topology_stonesoup.py``.
"""

from __future__ import annotations

import datetime
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..data import TrackTable
from ..data.conventions import to_interleaved
from ..roles import TrackAssociator
from ..track_association import TrackAssociation, TrackPairs, UnpairedTracks

__all__ = ["STONESOUP", "StoneSoupCounting", "StoneSoupOneToOne"]

EPOCH = datetime.datetime(2000, 1, 1)
#: The threshold of both, metres.
THRESHOLD = 30e3
#: Stone Soup's GaussianState needs a covariance; no measure used here reads it.
NOMINAL_COVAR = np.diag([1e3**2, 10.0**2, 1e3**2, 10.0**2])
POSITION = [0, 2]  # x, y of the interleaved [x, vx, y, vy]


def _tracks(table: TrackTable) -> tuple[list[Any], dict[int, int], dict[datetime.datetime, float]]:
    """The table's tracks as Stone Soup ``Track``s, with ``id(Track)`` → track id and each
    timestamp → our time."""
    from stonesoup.types.state import GaussianState
    from stonesoup.types.track import Track

    assert table.velocity is not None
    states = to_interleaved(table.state[:, :4], ndim=2, blocks=2)
    stamps = {float(t): EPOCH + datetime.timedelta(seconds=float(t)) for t in np.unique(table.time)}
    out, ids = [], {}
    for _, track, rows in table.tracks():
        ss = Track(
            [
                GaussianState(states[r].reshape(4, 1), NOMINAL_COVAR, timestamp=stamps[float(table.time[r])])
                for r in rows
            ]
        )
        out.append(ss)
        ids[id(ss)] = int(track)
    return out, ids, {stamp: t for t, stamp in stamps.items()}


def _association(rows: set[tuple[float, int, int, int]]) -> TrackAssociation:
    table = np.array(sorted(rows), dtype=np.float64).reshape(-1, 4)
    ids = table[:, 1:].astype(np.int64)
    pairs = TrackPairs(table[:, 0], ids[:, 0], ids[:, 1], ids[:, 2], np.full(len(table), np.nan))
    none = UnpairedTracks(np.empty(0), np.empty(0, np.int64), np.empty(0, np.int64))
    return TrackAssociation(pairs, none, none)


@dataclass(frozen=True)
class StoneSoupCounting:
    """Stone Soup's ``TrackToTrackCounting`` (module docs)."""

    threshold: float = THRESHOLD

    def associate(self, *, local: TrackTable, system: TrackTable) -> TrackAssociation:
        from stonesoup.dataassociator.tracktotrack import TrackToTrackCounting
        from stonesoup.measures import Euclidean

        source = int(local.sources[0])
        ss_local, local_ids, _ = _tracks(local)
        ss_system, system_ids, times = _tracks(system)
        counting = TrackToTrackCounting(
            association_threshold=self.threshold,
            consec_pairs_confirm=3,
            consec_misses_end=2,
            measure=Euclidean(mapping=POSITION),
            pos_map=POSITION,
            one_to_one=False,
        )
        rows = set()
        for association in counting.associate_tracks(set(ss_local), set(ss_system)).associations:
            a, b = association.objects
            mine, theirs = (a, b) if id(a) in local_ids else (b, a)
            shared = {s.timestamp for s in mine.states} & {s.timestamp for s in theirs.states}
            span = getattr(association, "time_range", None)
            for stamp in shared:
                if span is None or stamp in span:
                    rows.add((times[stamp], source, local_ids[id(mine)], system_ids[id(theirs)]))
        return _association(rows)


@dataclass(frozen=True)
class StoneSoupOneToOne:
    """Stone Soup's ``OneToOneTrackAssociator`` on the latest states, every scan (module docs)."""

    threshold: float = THRESHOLD

    def associate(self, *, local: TrackTable, system: TrackTable) -> TrackAssociation:
        from stonesoup.dataassociator.tracktotrack import OneToOneTrackAssociator
        from stonesoup.measures import Euclidean

        source = int(local.sources[0])
        associator = OneToOneTrackAssociator(measure=Euclidean(mapping=POSITION), association_threshold=self.threshold)
        rows = set()
        for t in np.union1d(local.scan_times(), system.scan_times()):
            here_local, here_system = local.at(float(t)), system.at(float(t))
            if len(here_local) == 0 or len(here_system) == 0:
                continue
            ss_local, local_ids, _ = _tracks(here_local)
            ss_system, system_ids, _ = _tracks(here_system)
            for association in associator.associate_tracks(set(ss_local), set(ss_system)).associations:
                a, b = association.objects
                mine, theirs = (a, b) if id(a) in local_ids else (b, a)
                rows.add((float(t), source, local_ids[id(mine)], system_ids[id(theirs)]))
        return _association(rows)


STONESOUP: dict[str, Callable[[], TrackAssociator]] = {
    "stone soup counting, 30 km": StoneSoupCounting,
    "stone soup 1:1 per scan, 30 km": StoneSoupOneToOne,
}
