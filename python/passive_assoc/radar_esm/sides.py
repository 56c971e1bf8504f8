"""What the radar/ESM associators read of their two inputs: filtered tracks for the fine stage,
the sequences the coarse gate decomposes, and the covariance of those sequences over a window.

Each side may be given as

* **filtered tracks** (velocity, acceleration and covariance columns: a constant-acceleration
  Kalman filter's output, e.g. :func:`.tracks.filter_reports`'s). The coarse gate reads their
  positions; Σ over the window is the filtered sequence's whole covariance, rebuilt with the
  filter's process noise q (:mod:`.window`): the associator's ``process_noise`` when a number,
  read back from the tracks' covariances with ``"auto"`` (:func:`.tracks.process_noise_of`;
  where they are not one constant-acceleration filter's, Σ falls back to per scan), per scan
  with None;
* **raw reports** (positions with each report's covariance, no velocity: what a radar
  reports, or ESM fixes, e.g. triangulated bearings, :func:`.bearings.bearing_fixes`), as
  the paper's coarse gate reads them. The gate decomposes the reports themselves, with Σ their
  own covariances, block-diagonal in time (exact: report errors are independent), and the fine
  stage reads the reports filtered here by :func:`.tracks.filter_reports` (a prior start, q the
  associator's ``process_noise`` when a number, else :data:`.tracks.REPORT_PROCESS_NOISE`).

Both sides are one or the other independently.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..data import TrackTable
from .scan_gate import Sigma
from .scans import AlignedTracks, align
from .tracks import REPORT_PROCESS_NOISE, filter_reports, process_noise_of

__all__ = ["Sides", "prepare"]


@dataclass(frozen=True)
class Sides:
    """The two inputs laid on their common scans: ``radar``, ``esm`` the filtered tracks (the
    fine stage's), ``coarse_radar``, ``coarse_esm`` the sequences the gate decomposes (the
    same tables, or the raw reports, rows in the same order), and ``sigma`` how Σ is taken
    (:data:`.scan_gate.Sigma`)."""

    times: NDArray[np.float64]
    radar: AlignedTracks
    esm: AlignedTracks
    coarse_radar: AlignedTracks
    coarse_esm: AlignedTracks
    sigma: Sigma
    #: The filtered tables (the inputs themselves where they were tracks).
    radar_tracks: TrackTable
    esm_tracks: TrackTable


def is_reports(table: TrackTable) -> bool:
    """A table of raw position reports: no velocity column."""
    return len(table) > 0 and table.velocity is None


def prepare(local: TrackTable, system: TrackTable, process_noise: float | str | None, n_threads: int | None) -> Sides:
    """The two sides (module docs); ``local`` is the ESM's, ``system`` the radar's."""
    for name, table in (("system", system), ("local", local)):
        if isinstance(table, TrackTable) and is_reports(table) and table.covariance is None:
            raise ValueError(
                f"{name}: raw reports (no velocity column) need each report's covariance (its measurement noise)"
            )
    q_filter = float(process_noise) if isinstance(process_noise, float | int) else REPORT_PROCESS_NOISE
    filtered = {
        name: filter_reports(table, q_filter, n_threads=n_threads) if is_reports(table) else table
        for name, table in (("system", system), ("local", local))
        if isinstance(table, TrackTable)
    }
    radar_tracks = filtered.get("system", system)
    esm_tracks = filtered.get("local", local)
    times, r, e = align(radar_tracks, esm_tracks, needs=("velocity", "acceleration", "covariance"))
    raw = [is_reports(t) for t in (system, local)]
    coarse = []
    for table, tracks, was_raw in ((system, r, raw[0]), (local, e, raw[1])):
        if not was_raw:
            coarse.append(tracks)
            continue
        _, sequences, _ = align(table, table)
        coarse.append(_in_order(sequences, tracks.track))
    sigma: Sigma
    if process_noise is None and not any(raw):
        sigma = "per_scan"
    else:
        sides: list[float | str] = []
        for filtered_table, was_raw in ((radar_tracks, raw[0]), (esm_tracks, raw[1])):
            if was_raw:
                sides.append("reports")
            elif isinstance(process_noise, float | int):
                sides.append(float(process_noise))
            else:
                # "auto" reads the filter's q back; None (or tracks of no one CA filter): the
                # filtered side per scan, block-diagonal in time.
                q = process_noise_of(filtered_table) if process_noise == "auto" else None
                sides.append("reports" if q is None else q)
        if all(side == "reports" for side in sides) and not any(raw):
            sigma = "per_scan"
        else:
            sigma = (sides[0], sides[1])  # type: ignore[assignment]
    return Sides(times, r, e, coarse[0], coarse[1], sigma, radar_tracks, esm_tracks)


def _in_order(sequences: AlignedTracks, ids: NDArray[np.int64]) -> AlignedTracks:
    """``sequences`` with its rows in the order of ``ids`` (the filtered tracks')."""
    where = {int(t): k for k, t in enumerate(sequences.track)}
    order = np.array([where[int(t)] for t in ids], dtype=np.intp)

    def pick(values: NDArray[np.float64] | None) -> NDArray[np.float64] | None:
        return None if values is None else values[order]

    position = pick(sequences.position)
    assert position is not None
    return AlignedTracks(
        sequences.source,
        sequences.track[order],
        sequences.present[order],
        position,
        pick(sequences.velocity),
        pick(sequences.acceleration),
        pick(sequences.covariance),
    )
