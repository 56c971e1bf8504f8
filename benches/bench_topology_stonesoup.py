"""Topology and nearest neighbour against Stone Soup's track-to-track associators on the same
tracks: the topology paper scenario (EXPERIMENTS ``topology``: 8 radars, 20 targets,
90 scans of 10 s, full coverage, azimuth bias U(±B)); each of the 7 local radars is associated
with the system radar (radar 0) by

* ``topology``: our ``TopologyAssociator`` (default settings: the fused decision, window 6, one
  thread);
* ``nearest``: our ``NearestNeighbourAssociator`` (every scan, the gated optimal one-to-one
  assignment of the 6-scan mean position distance; 60 km gate, no covariance gate; one
  thread);
* ``ss counting``: Stone Soup's ``TrackToTrackCounting`` (the counting technique, whole tracks
  at once: a pair is associated over the time range its position distance stays within the
  threshold) as it comes, ``one_to_one=False`` (a track may hold several partners at a time);
* ``ss counting 1:1``: the same with ``one_to_one=True`` (Stone Soup's
  ``multidimensional_deconfliction``). On these tracks it raises ``TypeError`` in Stone Soup
  1.9.1 (a runner-up association whose time range one winner covers entirely becomes ``None``,
  and subtracting the next winner's range from ``None`` fails); the row then says so;
* ``ss 1:1 mean6``: Stone Soup's ``OneToOneTrackAssociator`` (``linear_sum_assignment``) with
  ``MeanMeasure(RecentStateSequenceMeasure(Euclidean, 6))`` and a 60 km threshold, called every
  scan on the tracks up to that scan: our nearest neighbour's rule in Stone Soup's pieces.

Stone Soup's threshold is our nearest neighbour's 60 km gate (``--threshold``), so every
distance-based method gates alike; 60 km is wider than the ±10° relative bias moves a target
at the ring's ~250 km (≤ 44 km), so the gate itself drops no true pair. Every Stone Soup measure
is ``Euclidean(mapping=[0, 2])``: x and y of the interleaved state [x, vx, y, vy].
``consec_pairs_confirm=3`` and ``consec_misses_end=2`` are Stone Soup's defaults, both small (a
confirmed association is backdated to its first in-threshold scan, so confirmation costs no
recall).

Each method is timed per radar pair (one local radar against the system radar). The tracks are
simulated and filtered once per run; the conversion of our ``TrackTable`` to Stone Soup
``Track``\\ s of ``GaussianState``\\ s with ``datetime`` timestamps (the per-scan truncated tracks
too), and of Stone Soup's associations back to per-scan pairs, happen outside the timed region.
A counting association covers every scan both tracks share inside its time range (inclusive,
as ``TimeRange.__contains__`` is). Every method is scored alike with
``track_association_scores`` from the 6th scan (our window's first full scan); TP, FP and FN
are pooled over all runs and radar pairs.

    python benches/bench_topology_stonesoup.py [--runs 3] [--bias 5]

Prints, per method, the median seconds per radar pair, precision, recall and F1 (%), and each
Stone Soup time ÷ ours. Stone Soup is a benchmark-only dependency (``pip install ".[bench]"``).
"""

from __future__ import annotations

import argparse
import datetime
import time
from collections.abc import Callable

import numpy as np
import passive_assoc as pa
import stonesoup
from numpy.typing import NDArray
from passive_assoc.data.conventions import covariance_to_interleaved, to_interleaved
from passive_assoc.evaluation import track_association_scores
from passive_assoc.experiments.topology import SYSTEM_RADAR
from passive_assoc.experiments.topology_tracks import local_tracks
from passive_assoc.simulation.topology import paper_topology_scenario
from passive_assoc.track_association import TrackPairs, UnpairedTracks
from stonesoup.dataassociator.tracktotrack import OneToOneTrackAssociator, TrackToTrackCounting
from stonesoup.measures import Euclidean
from stonesoup.measures.multi import MeanMeasure, RecentStateSequenceMeasure
from stonesoup.types.association import AssociationSet
from stonesoup.types.state import GaussianState
from stonesoup.types.track import Track

EPOCH = datetime.datetime(2000, 1, 1)
WINDOW = 6  # our associators' window (and the mean6 row's); scoring starts at its first full scan
GATE = 60e3  # m: our nearest neighbour's default gate, and Stone Soup's threshold
#: The local tracks carry no covariance; Stone Soup's GaussianState needs one. No measure used
#: here reads it, so a nominal 1 km / 10 m/s diagonal (interleaved) stands in.
NOMINAL_COVAR = np.diag([1e3**2, 10.0**2, 1e3**2, 10.0**2])

Key = tuple[int, int]  # (source, track id)
Decision = tuple[float, int, int, int]  # time, source, local track, system track
#: Per scan: the datetime, and the local and system tracks up to it (those with a state then).
Scans = list[tuple[datetime.datetime, set[Track], set[Track]]]


def to_stonesoup(tracks: pa.TrackTable) -> tuple[set[Track], dict[int, Key], dict[datetime.datetime, float]]:
    """Our tracks as Stone Soup ``Track``\\ s (interleaved [x, vx, y, vy] states), with the
    way back: ``id(Track)`` → (source, track), and each ``datetime`` → our time."""
    if tracks.velocity is None:
        raise ValueError("tracks: Stone Soup's states need velocities")
    states = to_interleaved(tracks.state[:, :4], ndim=2, blocks=2)
    covars = None if tracks.covariance is None else covariance_to_interleaved(tracks.covariance, ndim=2, blocks=2)
    stamps = {float(t): EPOCH + datetime.timedelta(seconds=float(t)) for t in np.unique(tracks.time)}
    out: set[Track] = set()
    keys: dict[int, Key] = {}
    for source, track, rows in tracks.tracks():
        ss = Track(
            [
                GaussianState(
                    states[r].reshape(4, 1),
                    NOMINAL_COVAR if covars is None else covars[r],
                    timestamp=stamps[float(tracks.time[r])],
                )
                for r in rows
            ]
        )
        out.add(ss)
        keys[id(ss)] = (int(source), int(track))
    return out, keys, {stamp: t for t, stamp in stamps.items()}


def up_to_each_scan(local: set[Track], system: set[Track], keys: dict[int, Key]) -> Scans:
    """For every scan, each track that has a state then, cut after it (for a per-scan
    associator on whole-track inputs); the cut tracks' keys are added to ``keys``."""
    stamps = sorted({s.timestamp for track in local | system for s in track.states})

    def cut(tracks: set[Track], stamp: datetime.datetime) -> set[Track]:
        out = set()
        for track in tracks:
            states = [s for s in track.states if s.timestamp <= stamp]
            if states and states[-1].timestamp == stamp:
                part = Track(states)
                keys[id(part)] = keys[id(track)]
                out.add(part)
        return out

    return [(stamp, cut(local, stamp), cut(system, stamp)) for stamp in stamps]


def decisions(
    associations: AssociationSet, keys: dict[int, Key], times: dict[datetime.datetime, float], at: float | None = None
) -> set[Decision]:
    """Stone Soup's associations as per-scan (time, source, local, system) decisions: at ``at``
    for a single-scan result, else every scan both tracks share inside the association's time
    range (all of them for an association without one)."""
    out: set[Decision] = set()
    for association in associations.associations:
        a, b = association.objects
        local, system = (b, a) if keys[id(a)][0] == SYSTEM_RADAR else (a, b)
        (source, local_id), system_id = keys[id(local)], keys[id(system)][1]
        if at is not None:
            out.add((at, source, local_id, system_id))
            continue
        shared = {s.timestamp for s in local.states} & {s.timestamp for s in system.states}
        span = getattr(association, "time_range", None)
        out.update((times[t], source, local_id, system_id) for t in shared if span is None or t in span)
    return out


def as_association(rows: set[Decision]) -> pa.TrackAssociation:
    """Decisions as a ``TrackAssociation`` (pairs only: all that scoring reads)."""
    table = np.array(sorted(rows), dtype=np.float64).reshape(-1, 4)
    ids = table[:, 1:].astype(np.int64)
    pairs = TrackPairs(table[:, 0], ids[:, 0], ids[:, 1], ids[:, 2], np.full(len(table), np.nan))
    none = UnpairedTracks(np.empty(0), np.empty(0, np.int64), np.empty(0, np.int64))
    return pa.TrackAssociation(pairs, none, none)


def of_ours(result: pa.TrackAssociation) -> set[Decision]:
    p = result.pairs
    return {
        (float(t), int(s), int(a), int(b))
        for t, s, a, b in zip(p.time, p.source, p.local_track, p.system_track, strict=True)
    }


def counts(rows: set[Decision], local: pa.TrackTable, system: pa.TrackTable, since: float) -> NDArray[np.float64]:
    """TP, FP and FN of one run's decisions (METHODS §4), to be pooled over runs."""
    s = track_association_scores(as_association(rows), local, system, since=since)
    return np.array([s.tp, s.fp, s.fn], dtype=np.float64)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--bias", type=float, default=5.0)
    parser.add_argument("--threshold", type=float, default=GATE, help="Stone Soup's distance threshold, m (60e3)")
    parser.add_argument("--confirm", type=int, default=3, help="TrackToTrackCounting's consec_pairs_confirm (3)")
    parser.add_argument("--misses", type=int, default=2, help="TrackToTrackCounting's consec_misses_end (2)")
    args = parser.parse_args()
    position = [0, 2]  # x, y of the interleaved [x, vx, y, vy]

    def counting(one_to_one: bool) -> TrackToTrackCounting:
        return TrackToTrackCounting(
            association_threshold=args.threshold,
            consec_pairs_confirm=args.confirm,
            consec_misses_end=args.misses,
            measure=Euclidean(mapping=position),
            pos_map=position,
            one_to_one=one_to_one,
        )

    ours: dict[str, Callable[[], pa.TopologyAssociator | pa.NearestNeighbourAssociator]] = {
        "topology": lambda: pa.TopologyAssociator(window=WINDOW, n_threads=1),
        "nearest": lambda: pa.NearestNeighbourAssociator(gate=GATE, window=WINDOW, gate_probability=None, n_threads=1),
    }
    whole: dict[str, Callable[[], TrackToTrackCounting]] = {
        "ss counting": lambda: counting(False),
        "ss counting 1:1": lambda: counting(True),
    }
    per_scan = "ss 1:1 mean6"
    names = [*ours, *whole, per_scan]
    seconds: dict[str, list[float]] = {name: [] for name in names}
    totals = {name: np.zeros(3) for name in names}  # TP, FP, FN
    errors: dict[str, list[str]] = {name: [] for name in names}
    pairs = 0
    for run in range(args.runs):
        rng = np.random.default_rng(run)
        scenario = paper_topology_scenario(rng, bias_deg=args.bias, coverage="full")
        tracks = local_tracks(scenario, rng)
        system = tracks.of(SYSTEM_RADAR)
        local = tracks.select(np.flatnonzero(tracks.source != SYSTEM_RADAR))
        since = float(scenario.scan_times[WINDOW - 1])
        ss_system, system_keys, times = to_stonesoup(system)  # conversions: outside the timed regions
        found: dict[str, set[Decision]] = {name: set() for name in names}
        for radar in local.sources:
            pairs += 1
            part = local.of(int(radar))
            ss_local, local_keys = to_stonesoup(part)[:2]
            keys = {**system_keys, **local_keys}
            scans = up_to_each_scan(ss_local, ss_system, keys)
            for name, make in ours.items():
                method = make()
                t = time.perf_counter()
                result = method.associate(local=part, system=system)
                seconds[name].append(time.perf_counter() - t)
                found[name] |= of_ours(result)
            for name, make_ss in whole.items():
                associator = make_ss()
                t = time.perf_counter()
                try:
                    associations = associator.associate_tracks(ss_local, ss_system)
                except TypeError as error:  # Stone Soup 1.9.1's deconfliction on these tracks
                    errors[name].append(f"{type(error).__name__}: {error}")
                    continue
                seconds[name].append(time.perf_counter() - t)
                found[name] |= decisions(associations, keys, times)
            one_to_one = OneToOneTrackAssociator(
                measure=MeanMeasure(RecentStateSequenceMeasure(Euclidean(mapping=position), WINDOW)),
                association_threshold=args.threshold,
            )
            t = time.perf_counter()
            results = [one_to_one.associate_tracks(tl, ts) for _, tl, ts in scans]
            seconds[per_scan].append(time.perf_counter() - t)
            for (stamp, _, _), associations in zip(scans, results, strict=True):
                found[per_scan] |= decisions(associations, keys, times, at=times[stamp])
        for name in names:
            totals[name] += counts(found[name], local, system, since)
    print(
        f"topology paper scenario, full coverage, bias ±{args.bias:g}°, {args.runs} runs × 7 = {pairs} radar pairs;"
        f" Stone Soup {stonesoup.__version__}, threshold {args.threshold / 1e3:g} km on (x, y), counting"
        f" consec_pairs_confirm={args.confirm} consec_misses_end={args.misses}; scored from scan {WINDOW}, pooled"
    )
    print(f"  {'method':<16} {'median s/pair':>13} {'P %':>7} {'R %':>7} {'F1 %':>7}")
    for name in names:
        if errors[name]:
            print(f"  {name:<16} failed on {len(errors[name])}/{pairs} pairs: {errors[name][0]}")
            continue
        tp, fp, fn = totals[name]
        p = tp / (tp + fp) if tp + fp else 0.0
        r = tp / (tp + fn) if tp + fn else 0.0
        f1 = 2 * p * r / (p + r) if p + r else 0.0
        print(f"  {name:<16} {np.median(seconds[name]):>13.4f} {100 * p:>7.2f} {100 * r:>7.2f} {100 * f1:>7.2f}")
    print("Stone Soup time ÷ ours (median seconds per radar pair):")
    for name in [*whole, per_scan]:
        if not errors[name]:
            ratios = ", ".join(f"÷ {mine} {np.median(seconds[name]) / np.median(seconds[mine]):.0f}×" for mine in ours)
            print(f"  {name:<16} {ratios}")


if __name__ == "__main__":
    main()
