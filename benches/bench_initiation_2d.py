"""Fuzzy track initiation of a dense 2-D bearing-only scene: ``bearing_only_2d_scenario(3,
n_targets=N, n_sensors=3, clutter_ratio=2)`` with the default `FuzzyTrackInitiator`, with and
without the support gate. Prints the time, the tracks, how many rows of each track are one
target's, and the stage counts.

    python3 benches/bench_initiation_2d.py [--targets 5 8] [--no-gate-too] [--candidate-scans K]
        [--repeat N] [--threads T] [--passes] [--busy-core]
    python3 benches/bench_initiation_2d.py --targets 5 --pd 0.9 --seeds 20 [--n-detect 9] [--gate-pd 0.9]
        [--search-stage 2048]
"""

from __future__ import annotations

import argparse
import contextlib
import resource
import subprocess
import sys
import time
from collections.abc import Iterator
from typing import Any

import numpy as np
import passive_assoc as pa
from passive_assoc.evaluation import track_targets


def priced(gate_pd: float | None, search_stage: str | None = None, order: str | None = None) -> dict[str, Any]:
    """``gate_pd``, ``search_stage`` and the detection ``order`` only when given, so the bench
    also runs on a build without these options (docs/performance.md's same-run comparisons run
    it on two builds of the package). ``search_stage`` is an integer or "none"."""
    given: dict[str, Any] = {} if gate_pd is None else {"gate_pd": gate_pd}
    if search_stage is not None:
        given["search_stage"] = None if search_stage == "none" else int(search_stage)
    if order is not None:
        given["detection_order"] = order
    return given


def peak_rss_mb() -> float:
    """The process's peak resident memory so far (Linux reports kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def found_over_seeds(
    n: int,
    pd: float,
    seeds: int,
    n_detect: int | None = None,
    gate_pd: float | None = None,
    search_stage: str | None = None,
    order: str | None = None,
) -> None:
    """Targets found (a track holds at least two thirds of its rows from it:
    :func:`passive_assoc.evaluation.track_targets`) and the other tracks, over the seeds."""
    found = extra = 0
    for seed in range(seeds):
        scenario = pa.bearing_only_2d_scenario(seed, n_targets=n, n_sensors=3, clutter_ratio=2, pd=pd)
        initiator = pa.FuzzyTrackInitiator(n_detect=n_detect, **priced(gate_pd, search_stage, order))
        result = initiator.initiate(scenario.measurements, scenario.sensors)
        assert scenario.measurements.truth is not None
        held = track_targets(result.labels, scenario.measurements.truth)
        distinct = len(set(held.tolist()) - {-1})
        found, extra = found + distinct, extra + len(held) - distinct
    nd = "the data's Nd" if n_detect is None else f"Nd {n_detect}"
    pricing = "" if gate_pd is None else f", misses priced at Pd {gate_pd}"
    print(
        f"{n} targets, Pd {pd}, {seeds} seeds, {nd}{pricing}: {found}/{n * seeds} targets found, {extra} other tracks"
    )


class PassClock:
    """A ``progress`` callable that keeps when each stage began and ended, from the call's start
    (the wall time of each pass's candidate formation and search)."""

    def __init__(self) -> None:
        self.start = time.perf_counter()
        self.spans: list[tuple[str, float, float]] = []  # (stage, began, ended)

    def __call__(self, stage: str, fraction: float) -> None:
        now = time.perf_counter() - self.start
        if self.spans and self.spans[-1][0] == stage:
            self.spans[-1] = (stage, self.spans[-1][1], now)
        else:
            self.spans.append((stage, now, now))

    def summary(self) -> str:
        passes, parts = 0, []
        for stage, began, ended in self.spans:
            passes += stage == "candidates"
            parts.append(f"pass {passes} {stage} {ended - began:.3f}")
        return ", ".join(parts)


@contextlib.contextmanager
def busy_core(on: bool) -> Iterator[None]:
    """With ``on``, a second process spins on one core throughout: a shared machine, where one
    of the initiation's threads is now and then descheduled."""
    if not on:
        yield
        return
    spinner = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(0.2)  # let it start before the clock does
        yield
    finally:
        spinner.kill()
        spinner.wait()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--targets", type=int, nargs="+", default=[5, 8])
    parser.add_argument("--no-gate-too", action="store_true", help="also run with support_gate=False (slow)")
    parser.add_argument("--pd", type=float, default=1.0)
    parser.add_argument("--seeds", type=int, default=0, help="instead: targets found over seeds 0..N-1")
    parser.add_argument("--n-detect", type=int, default=None, help="with --seeds: a fixed Nd (default: the data's)")
    parser.add_argument("--candidate-scans", type=int, default=4, help="candidate_scans (1: pass 1 only)")
    parser.add_argument("--repeat", type=int, default=1, help="initiations per case: the median and range are printed")
    parser.add_argument("--threads", type=int, default=None, help="n_threads (default: every core)")
    parser.add_argument("--gate-pd", type=float, default=None, help="gate_pd: price misses (default: not priced)")
    parser.add_argument(
        "--search-stage", default=None, help="search_stage: an integer or 'none' (default: its default)"
    )
    parser.add_argument("--detection-order", default=None, help="detection_order (default: its default)")
    parser.add_argument("--passes", action="store_true", help="also print each pass's stage times (last run)")
    parser.add_argument("--busy-core", action="store_true", help="time it while another process spins on one core")
    args = parser.parse_args()
    if args.seeds:
        for n in args.targets:
            found_over_seeds(
                n, args.pd, args.seeds, args.n_detect, args.gate_pd, args.search_stage, args.detection_order
            )
        return
    with busy_core(args.busy_core):
        timed(args)


def timed(args: argparse.Namespace) -> None:
    """Each case of ``args``, timed and printed."""
    for n in args.targets:
        scenario = pa.bearing_only_2d_scenario(3, n_targets=n, n_sensors=3, clutter_ratio=2)
        for gate in (True, False) if args.no_gate_too else (True,):
            initiator = pa.FuzzyTrackInitiator(
                support_gate=gate,
                candidate_scans=args.candidate_scans,
                n_threads=args.threads,
                **priced(args.gate_pd, args.search_stage, args.detection_order),
            )
            times, rss_before = [], peak_rss_mb()
            for _ in range(args.repeat):
                start, clock = time.perf_counter(), PassClock()
                passes: dict[str, Any] = {"progress": clock} if args.passes else {}  # runs on builds without it too
                result = initiator.initiate(scenario.measurements, scenario.sensors, **passes)
                times.append(time.perf_counter() - start)
            truth = scenario.measurements.truth
            assert truth is not None
            kinds = []
            for track in result.tracks:
                labels, counts = np.unique(truth[track.measurements], return_counts=True)
                kinds.append(f"{int(labels[np.argmax(counts)])}:{counts.max()}/{len(track.measurements)}")
            spread = f" (median of {len(times)}, {min(times):.2f}-{max(times):.2f})" if len(times) > 1 else ""
            print(
                f"{n} targets, {len(scenario.measurements)} rows, support_gate={gate}: "
                f"{float(np.median(times)):.2f} s{spread}, "
                f"{len(result.tracks)} tracks (majority target:rows) {' '.join(kinds)}"
            )
            seconds = ", ".join(f"{k} {v:.3f}" for k, v in result.diagnostics.stage_seconds.items())
            print(f"  stage seconds (last run) {seconds}")
            print(f"  stage counts {result.diagnostics.stage_counts}")
            if args.passes:
                print(f"  seconds by pass and stage (last run, from the progress reports) {clock.summary()}")
            print(f"  peak RSS of the process {rss_before:.0f} MB before the initiations, {peak_rss_mb():.0f} MB after")


if __name__ == "__main__":
    main()
