"""Two sensors' track tables on one scan grid, and the per-scan result every radar/ESM
associator returns.

The radar's tracks are the *system* picture and the ESM's the *local* one, in the terms of
:class:`~passive_assoc.TrackAssociation`: a pair row says that, at ``time``, ESM
track ``local_track`` (of the ESM's ``source``) is radar track ``system_track``.

Tracks are laid out densely, ``(n_tracks, n_scans, ...)`` with NaN where a track has no
state, in an order that never reads track ids (by first scan, then by the first state), so
that ids cannot decide a tie: the associators break exact ties by that order.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..data import TrackTable
from ..track_association import TrackAssociation, TrackPairs, UnpairedTracks

__all__ = [
    "AlignedTracks",
    "RadarEsmAssociation",
    "align",
    "all_unpaired",
    "association",
    "no_pairs",
    "position_distance",
]


@dataclass(frozen=True, eq=False)
class AlignedTracks:
    """One sensor's tracks on the common scan grid.

    ``track[i]`` is the id of row i; ``present[i, k]`` whether it has a state at scan k;
    ``position``, ``velocity``, ``acceleration`` are ``(n, K, ndim)`` and ``covariance``
    ``(n, K, D, D)`` (block order), NaN where absent and None where the table lacks them.
    """

    source: int
    track: NDArray[np.int64]
    present: NDArray[np.bool_]
    position: NDArray[np.float64]
    velocity: NDArray[np.float64] | None
    acceleration: NDArray[np.float64] | None
    covariance: NDArray[np.float64] | None

    def __len__(self) -> int:
        return len(self.track)

    @property
    def ndim(self) -> int:
        return int(self.position.shape[2])

    def block_covariance(self, block: int) -> NDArray[np.float64]:
        """The ``(n, K, ndim, ndim)`` covariance of state block 0 (position), 1 (velocity) or
        2 (acceleration)."""
        assert self.covariance is not None
        d = self.ndim
        return self.covariance[:, :, block * d : (block + 1) * d, block * d : (block + 1) * d]


@dataclass(frozen=True)
class RadarEsmAssociation(TrackAssociation):
    """A :class:`~passive_assoc.TrackAssociation` (radar = system, ESM = local)
    plus :attr:`candidates`: every (ESM, radar) pair of every scan that passed the method's
    gate, with its score (for the wavelet-fuzzy method: the combined similarity f)."""

    candidates: TrackPairs = field(default_factory=lambda: no_pairs())


def align(
    radar: TrackTable, esm: TrackTable, needs: Sequence[str] = ()
) -> tuple[NDArray[np.float64], AlignedTracks, AlignedTracks]:
    """Check the two tables and lay them on their common scan times.

    ``needs`` names the columns the method reads (``"velocity"``, ``"acceleration"``,
    ``"covariance"``). Raises TypeError / ValueError naming the argument: ``system`` (the
    radar) or ``local`` (the ESM).
    """
    for name, table in (("system", radar), ("local", esm)):
        if not isinstance(table, TrackTable):
            raise TypeError(f"{name}: expected a TrackTable, got {type(table).__name__}")
        if len(table.sources) > 1:
            raise ValueError(f"{name}: one sensor's tracks expected, got sources {table.sources.tolist()}")
        missing = [column for column in needs if len(table) and getattr(table, column) is None]
        if missing:
            raise ValueError(
                f"{name}: the method reads the {', '.join(missing)} column(s), which the table lacks "
                "(filter the reports with KalmanFilter(motion='ca') and build it with TrackTable.from_states)"
            )
    if len(radar) and len(esm) and radar.ndim != esm.ndim:
        raise ValueError(f"local: has {esm.ndim}-D positions, system has {radar.ndim}-D")
    times = _common_times(radar, esm)
    return times, _aligned(radar, times), _aligned(esm, times)


def _common_times(radar: TrackTable, esm: TrackTable) -> NDArray[np.float64]:
    """The scan times, which both sensors must share (METHODS §5: tracks are time-aligned)."""
    radar_times, esm_times = radar.scan_times(), esm.scan_times()
    if len(radar) == 0 or len(esm) == 0:
        return np.union1d(radar_times, esm_times)
    for name, mine, other_name, other in (
        ("local", esm_times, "system", radar_times),
        ("system", radar_times, "local", esm_times),
    ):
        extra = np.setdiff1d(mine, other)
        if len(extra):
            raise ValueError(
                f"{name}: time {float(extra[0])!r} s is not a scan time of {other_name} ({len(extra)} such times); "
                "the two sensors' tracks must be time-aligned (predict them to common scan times first)"
            )
    return radar_times


def _aligned(table: TrackTable, times: NDArray[np.float64]) -> AlignedTracks:
    ids, first, row_track = np.unique(table.track, return_index=True, return_inverse=True)
    scan = np.searchsorted(times, table.time)
    present = np.zeros((len(ids), len(times)), dtype=bool)
    present[row_track, scan] = True

    def dense(values: NDArray[np.float64] | None) -> NDArray[np.float64] | None:
        if values is None:
            return None
        out = np.full((len(ids), len(times), *values.shape[1:]), np.nan)
        out[row_track, scan] = values
        return out

    position = dense(table.position)
    assert position is not None
    source = int(table.source[0]) if len(table) else 0
    order = _id_free_order(table, first)
    columns = [position, dense(table.velocity), dense(table.acceleration), dense(table.covariance)]
    p, v, a, c = (None if col is None else col[order] for col in columns)
    assert p is not None
    return AlignedTracks(source, ids[order], present[order], p, v, a, c)


def _id_free_order(table: TrackTable, first: NDArray[np.intp]) -> NDArray[np.int64]:
    """Tracks ordered by their first time, then their first state, component by component
    (``first``: each track's first row). Only tracks identical at their first scan keep the
    table's (id) order between them."""
    keys = np.column_stack([table.time[first], table.state[first]])
    return np.lexsort(keys.T[::-1]).astype(np.int64)


def no_pairs() -> TrackPairs:
    """An empty pair table."""
    return _pairs(np.empty(0), 0, np.empty(0, np.int64), np.empty(0, np.int64), None)


def _pairs(
    time: NDArray[np.float64],
    source: int,
    local: NDArray[np.int64],
    system: NDArray[np.int64],
    score: NDArray[np.float64] | None,
) -> TrackPairs:
    n = len(time)
    return TrackPairs(
        np.asarray(time, np.float64),
        np.full(n, source, np.int64),
        np.asarray(local, np.int64),
        np.asarray(system, np.int64),
        np.zeros(n) if score is None else np.asarray(score, np.float64),
    )


def association(
    times: NDArray[np.float64],
    radar: AlignedTracks,
    esm: AlignedTracks,
    pairs: tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp]],
    score: NDArray[np.float64],
    candidates: NDArray[np.bool_] | None = None,
) -> RadarEsmAssociation:
    """The result of per-scan decisions ``pairs = (scan, radar row, esm row)``.

    ``score`` is ``(K, n_radar, n_esm)``; ``candidates`` the pairs that passed the gate
    (default: none reported). Every present track of every scan ends in exactly one pair or
    one unpaired row.
    """
    scan, r, e = pairs
    order = np.lexsort((radar.track[r], scan))
    scan, r, e = scan[order], r[order], e[order]
    paired_radar = np.zeros_like(radar.present)
    paired_radar[r, scan] = True
    paired_esm = np.zeros_like(esm.present)
    paired_esm[e, scan] = True
    chosen = _pairs(times[scan], esm.source, esm.track[e], radar.track[r], score[scan, r, e])
    if candidates is None:
        listed = no_pairs()
    else:
        ck, cr, ce = np.nonzero(candidates)
        listed = _pairs(times[ck], esm.source, esm.track[ce], radar.track[cr], score[ck, cr, ce])
    return RadarEsmAssociation(
        chosen,
        _unpaired(times, esm.source, esm, esm.present & ~paired_esm),
        _unpaired(times, esm.source, radar, radar.present & ~paired_radar),
        candidates=listed,
    )


def all_unpaired(times: NDArray[np.float64], radar: AlignedTracks, esm: AlignedTracks) -> RadarEsmAssociation | None:
    """The result when one side has no track (every track unpaired), else None."""
    if len(radar) and len(esm):
        return None
    empty = np.empty(0, np.intp)
    return association(times, radar, esm, (empty, empty, empty), np.zeros((len(times), len(radar), len(esm))))


def _unpaired(
    times: NDArray[np.float64], source: int, tracks: AlignedTracks, left: NDArray[np.bool_]
) -> UnpairedTracks:
    """Unpaired rows by scan, then track id."""
    rows, scans = np.nonzero(left)
    order = np.lexsort((tracks.track[rows], scans))
    rows, scans = rows[order], scans[order]
    return UnpairedTracks(times[scans], np.full(len(rows), source, np.int64), tracks.track[rows].astype(np.int64))


def position_distance(radar: AlignedTracks, esm: AlignedTracks) -> NDArray[np.float64]:
    """‖p_i − p_j‖ of every pair at every scan, ``(K, n_r, n_e)`` (NaN where absent)."""
    a = np.swapaxes(radar.position, 0, 1)[:, :, None, :]
    b = np.swapaxes(esm.position, 0, 1)[:, None, :, :]
    out: NDArray[np.float64] = np.linalg.norm(a - b, axis=-1)
    return out
