"""The result every track-to-track associator returns (METHODS §4, §5): which local track is
which system track at each scan, which are left unpaired, and each local source's estimated
bias.

A *local* :class:`~passive_assoc.data.TrackTable` holds the tracks of one or more sources
(radars, an ESM); the *system* table holds the fusion centre's picture. At every scan each
local source's tracks are paired one-to-one with system tracks; every local track of every
scan ends either in a pair or in the unpaired set, and so does every system track, per source.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import _core
from ..outcome import COMPLETED, Outcome

__all__ = ["BiasEstimate", "TrackAssociation", "TrackPairs", "UnpairedTracks", "merge", "no_pairs", "no_unpaired"]


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
    """A local source's picture relative to the system's: ``p ≈ R(rotation)·q + translation``,
    ``p`` a local track's position and ``q`` its system partner's (so
    :func:`~passive_assoc.topology.unbias` turns ``p`` back as ``R(−rotation)(p − translation)``).

    ``rotation`` is the relative azimuth bias in radians (counter-clockwise); ``translation``
    in metres. The streaming associators fit it to every scan of the (local, system) track
    pairs they believe are one target after the latest scan (trimmed rigid least squares):
    ``pairs`` is how many positions the fit kept, ``tracks`` how many track pairs they come
    from. ``rotation_std`` is honest: it counts each track pair's scans as one correlated
    sample (cluster-robust), widened for few track pairs (Student's t), so the truth lies
    within 3 standard deviations as often as a normal law's ±3σ (99.7 %). ``reliable`` is
    False for an estimate not to be used: fewer than 3 track pairs, a standard deviation above
    1°, or outside the associator's bias bound.
    """

    rotation: float
    rotation_std: float
    translation: tuple[float, float]
    pairs: int
    tracks: int = 0
    reliable: bool = True

    @property
    def rotation_deg(self) -> float:
        return float(np.degrees(self.rotation))

    @classmethod
    def _from_core(cls, bias: _core.Bias | None) -> BiasEstimate | None:
        if bias is None:
            return None
        return cls(bias.rotation, bias.rotation_std, bias.translation, bias.pairs, bias.tracks, bias.reliable)


@dataclass(frozen=True)
class TrackAssociation(Outcome):
    """Output of a track associator over one or more scans.

    Every local track of every scan is in exactly one row of :attr:`pairs` or
    :attr:`unpaired_local`; every system track of a scan is, for each local source, in
    exactly one row of :attr:`pairs` or :attr:`unpaired_system`. :attr:`bias` holds each
    local source's estimated bias relative to the system picture (absent for a source that
    was never paired, or when the associator does not estimate it).

    :attr:`termination` is ``"completed"`` (:class:`~passive_assoc.outcome.Outcome`).
    """

    pairs: TrackPairs
    unpaired_local: UnpairedTracks
    unpaired_system: UnpairedTracks
    bias: dict[int, BiasEstimate] = field(default_factory=dict)
    termination: str = field(default=COMPLETED, kw_only=True)
    success: bool = field(default=True, kw_only=True)
    message: str = field(default="every scan associated", kw_only=True)


def no_pairs() -> TrackPairs:
    """An empty pair table."""
    return TrackPairs(np.empty(0), np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0))


def no_unpaired() -> UnpairedTracks:
    """An empty unpaired table."""
    return UnpairedTracks(np.empty(0), np.empty(0, np.int64), np.empty(0, np.int64))


def merge(parts: Iterable[TrackAssociation]) -> TrackAssociation:
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
