"""``passive-assoc reproduce wavelet``: EXPERIMENTS ``wavelet`` (METHODS §5, paper 003).

The paper's 10 maneuvering targets on the x axis, 30 scans of 1 s, seen by a radar and an
ESM with position noise variance 0.5 km² each, ids shuffled, ``n_clutter`` false tracks per
sensor. Each sensor's tracks come from a constant-acceleration Kalman filter on its own
reports (the sensor's report-to-track assignment is given). Per scan k, the
correct-association probability is the fraction of the 10 targets whose radar track is paired
with its own ESM track at k; it is averaged over runs, and over scans 6–30, for the
wavelet-fuzzy method, nearest neighbour and the weighted χ² test on the same tracks, and for
the wavelet-fuzzy method with the paper's literal (unwhitened) coarse statistic. A 2-D radar +
passive (triangulated bearings) demo follows (:mod:`.wavelet_passive`).
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import warnings
from concurrent.futures import Executor, Future, ProcessPoolExecutor
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass, replace
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray
from tqdm import tqdm

from ..data import TrackTable
from ..distributed import current_client
from ..radar_esm import (
    Chi2TrackAssociator,
    NearestNeighbourTrackAssociator,
    RadarEsmAssociation,
    WaveletFuzzyAssociator,
    filter_reports,
)
from ..simulation.radar_esm import PAPER_WAVELET_PHASES, PAPER_WAVELET_TARGETS, paper_wavelet_scenario
from .common import (
    finite_float,
    int_at_least,
    map_runs,
    nonnegative_int,
    output_file,
    positive_int,
    run_seeds,
    seed_int,
    write_json,
)

#: The paper's correct-association probabilities (its §5), as ranges over scans.
PAPER = {"wavelet": (0.88, 0.93), "nearest": (0.72, 0.85)}
#: The ablations: run on the scenes without false tracks (and in the 2-D demo) only, where the
#: acceptance reads them; the clutter sweep compares the three methods.
ABLATIONS = ("wavelet_per_scan", "wavelet_literal")
#: Methods in print order, with their column titles.
METHODS = {
    "wavelet": "wavelet-fuzzy",
    "nearest": "nearest nb.",
    "chi2": "χ² test",
    "wavelet_per_scan": "per-scan Σ",
    "wavelet_literal": "literal stat.",
}
N_TARGETS = len(PAPER_WAVELET_TARGETS)
#: Scans 6–30 (1-based): the mean the paper's range is compared with.
SCORED = slice(5, None)
#: Scans 15–30, where the acceptance wants every scan ≥ 0.88.
LATE = slice(14, None)


def maneuver_power(period: float = 1.0) -> float:
    """The targets' mean squared acceleration change per second, m²/s⁵: the white-jerk
    density whose integral over the run matches the truth's jumps on average (Table 1)."""
    jumps = np.diff(PAPER_WAVELET_TARGETS[:, 1:], axis=1)
    return float(np.mean(np.sum(jumps**2, axis=1)) / (sum(PAPER_WAVELET_PHASES) * period))


#: The trackers' process noise q (≈ 169 m²/s⁵), from :func:`maneuver_power`.
PROCESS_NOISE = maneuver_power()


class Associator(Protocol):
    def associate(self, radar: TrackTable, esm: TrackTable) -> RadarEsmAssociation: ...


@dataclass(frozen=True)
class Settings:
    """What a run needs besides its seed and clutter level."""

    process_noise: float = PROCESS_NOISE
    window: int | None = None
    gate_probability: float = 0.99
    ablations: bool = True


def methods(settings: Settings) -> dict[str, Associator]:
    """The associators compared, one thread each (runs are parallel instead). The
    wavelet-fuzzy method is given the trackers' q, so that its window covariance includes the
    filtered errors' scan-to-scan correlation; the two ablations are without it: Σ diagonal in
    time (whitened), and the paper's literal scalar statistic."""

    def wavelet(whitened: bool, process_noise: float | None) -> WaveletFuzzyAssociator:
        return WaveletFuzzyAssociator(
            window=settings.window,
            gate_probability=settings.gate_probability,
            whitened=whitened,
            process_noise=process_noise,
            n_threads=1,
        )

    compared: dict[str, Associator] = {
        "wavelet": wavelet(whitened=True, process_noise=settings.process_noise),
        "nearest": NearestNeighbourTrackAssociator(),
        "chi2": Chi2TrackAssociator(),
    }
    if settings.ablations:
        compared["wavelet_per_scan"] = wavelet(whitened=True, process_noise=None)
        compared["wavelet_literal"] = wavelet(whitened=False, process_noise=None)
    return compared


@dataclass(frozen=True)
class RunScores:
    """One run: per method, the fraction of targets correctly paired at each scan (NaN at
    scans without tracks), the fraction of true pairs that passed the method's gate, and (the
    wavelet-fuzzy method) the fraction that passed it with a similarity above ε."""

    correct: dict[str, NDArray[np.float64]]
    gate_keeps: dict[str, NDArray[np.float64]]
    above_epsilon: NDArray[np.float64] | None = None


def _truth_of(tracks: TrackTable) -> NDArray[np.int64]:
    """Lookup id → truth label (−2 for ids not in the table)."""
    assert tracks.truth is not None
    lookup = np.full(int(tracks.track.max(initial=-1)) + 1, -2, np.int64)
    lookup[tracks.track] = tracks.truth
    return lookup


def true_pair_fraction(
    pairs_time: NDArray[np.float64],
    local: NDArray[np.int64],
    system: NDArray[np.int64],
    radar: TrackTable,
    esm: TrackTable,
    scan_times: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Per scan, how many of the listed (ESM, radar) pairs are true target pairs, over
    :data:`N_TARGETS`; NaN at scans where the radar has no track."""
    truth_r, truth_e = _truth_of(radar), _truth_of(esm)
    label = truth_r[system]
    true = (label >= 0) & (label == truth_e[local])
    scan = np.searchsorted(scan_times, pairs_time[true])
    out = np.bincount(scan, minlength=len(scan_times)) / N_TARGETS
    return np.where(np.isin(scan_times, radar.time), out, np.nan)


def score(
    result: RadarEsmAssociation, radar: TrackTable, esm: TrackTable, times: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(correct fraction per scan, true pairs kept by the gate per scan) of one result."""
    p, c = result.pairs, result.candidates
    return (
        true_pair_fraction(p.time, p.local_track, p.system_track, radar, esm, times),
        true_pair_fraction(c.time, c.local_track, c.system_track, radar, esm, times),
    )


def run_once(seed: np.random.SeedSequence, n_clutter: int, settings: Settings) -> RunScores:
    scenario = paper_wavelet_scenario(np.random.default_rng(seed), n_clutter=n_clutter)
    tracks = filter_reports(scenario.measurements, settings.process_noise, n_threads=1)
    radar, esm = tracks.of(0), tracks.of(1)
    correct, keeps, above = {}, {}, None
    for name, method in methods(settings).items():
        result = method.associate(radar, esm)
        correct[name], keeps[name] = score(result, radar, esm, scenario.scan_times)
        if name == "wavelet":
            assert isinstance(method, WaveletFuzzyAssociator)
            c = result.candidates
            chosen = c.score > method.config.epsilon
            above = true_pair_fraction(
                c.time[chosen], c.local_track[chosen], c.system_track[chosen], radar, esm, scenario.scan_times
            )
    return RunScores(correct, keeps, above)


def summarise(runs: list[RunScores]) -> dict[str, Any]:
    """Per method: the per-scan mean over runs, its mean over scans 6–30, its minimum over
    scans 15–30, and the share of true pairs the gate kept over scans 6–30."""
    out: dict[str, Any] = {}
    for name in runs[0].correct:
        per_scan = mean_over_runs([r.correct[name] for r in runs])
        kept = mean_over_runs([r.gate_keeps[name] for r in runs])
        out[name] = {
            "per_scan": per_scan,
            "mean_6_30": float(np.mean(per_scan[SCORED])),
            "min_15_30": float(np.min(per_scan[LATE])),
            "gate_keeps_true_6_30": float(np.mean(kept[SCORED])),
        }
        if name == "wavelet" and runs[0].above_epsilon is not None:
            above = mean_over_runs([r.above_epsilon for r in runs if r.above_epsilon is not None])
            out[name]["losses"] = losses(out[name]["per_scan"], kept, above)
    return out


def losses(
    correct: NDArray[np.float64], kept: NDArray[np.float64], above: NDArray[np.float64]
) -> dict[str, dict[str, float]]:
    """Where the targets not correctly paired went, as shares of all targets, over scans 6–14
    and 15–30: true pair gated out; passed the gate with f ≤ ε; above ε but another pair of
    either track was chosen first (the repeated maximum)."""
    parts = {"gated_out": 1.0 - kept, "below_epsilon": kept - above, "beaten": above - correct}
    spans = {"6_14": slice(5, 14), "15_30": LATE}
    return {name: {k: float(np.mean(v[span])) for k, v in parts.items()} for name, span in spans.items()}


def mean_over_runs(values: list[NDArray[np.float64]]) -> NDArray[np.float64]:
    """Per-scan mean over runs, NaN (silently) where no run has a value."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        out: NDArray[np.float64] = np.nanmean(np.array(values), axis=0)
    return out


def run_chunk(task: tuple[str, list[np.random.SeedSequence], int, Settings]) -> list[Any]:
    """Runs of one kind (``"paper"``: :func:`run_once`; ``"passive"``: the 2-D demo's
    :func:`.wavelet_passive.demo_run`) for a list of seeds, in one process."""
    kind, seeds, n_clutter, settings = task
    if kind == "paper":
        return [run_once(s, n_clutter, settings) for s in seeds]
    from .wavelet_passive import demo_run

    return [demo_run(s, settings) for s in seeds]


def worker_pool(workers: int) -> AbstractContextManager[Executor | None]:
    """Worker processes (spawned: the Rust core's thread pool does not survive a fork), or
    None to run in this process. Most of a run is NumPy-sized Python, so threads would queue
    on the GIL."""
    client = current_client()
    if client is not None:  # --scheduler: the cluster's executor
        return nullcontext(client.get_executor())
    if workers <= 1:
        return nullcontext(None)
    return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"))


Submitted = tuple[list[Future[list[Any]]], list[list[int]]]


def submit_seeds(
    pool: Executor, kind: str, seeds: list[np.random.SeedSequence], n_clutter: int, settings: Settings
) -> Submitted:
    """:func:`run_chunk` over every seed, in up to 64 chunks, queued on ``pool``."""
    chunks = [c.tolist() for c in np.array_split(np.arange(len(seeds)), min(len(seeds), 64))]
    futures = [pool.submit(run_chunk, (kind, [seeds[r] for r in chunk], n_clutter, settings)) for chunk in chunks]
    return futures, chunks


def collect(submitted: Submitted, desc: str) -> list[Any]:
    """The results of :func:`submit_seeds`, in seed order, with a progress bar."""
    out: list[Any] = []
    futures, chunks = submitted
    with tqdm(total=sum(map(len, chunks)), desc=desc, unit="run", file=sys.stderr, disable=None, leave=False) as bar:
        for future, chunk in zip(futures, chunks, strict=True):
            out.extend(future.result())
            bar.update(len(chunk))
    return out


def map_seeds(
    pool: Executor | None, kind: str, seeds: list[np.random.SeedSequence], n_clutter: int, settings: Settings, desc: str
) -> list[Any]:
    """:func:`run_chunk` over every seed, in seed order, with a progress bar."""
    if pool is None:
        return map_runs(lambda r: run_chunk((kind, [seeds[r]], n_clutter, settings))[0], len(seeds), 1, desc)
    return collect(submit_seeds(pool, kind, seeds, n_clutter, settings), desc)


def run_experiment(
    pool: Executor | None, runs: int, seed: int, clutter: list[int], settings: Settings
) -> dict[int, Any]:
    """Summaries per clutter level; the same seeds (targets) at every level. With a pool,
    every level is queued at once, so the workers never wait for a level's last chunk."""
    seeds = run_seeds(seed, runs)
    per_level = {n: replace(settings, ablations=n == 0) for n in clutter}
    if pool is None:
        return {
            n: summarise(map_seeds(None, "paper", seeds, n, s, f"wavelet, {n} false tracks"))
            for n, s in per_level.items()
        }
    queued = {n: submit_seeds(pool, "paper", seeds, n, s) for n, s in per_level.items()}
    return {n: summarise(collect(q, f"wavelet, {n} false tracks")) for n, q in queued.items()}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--runs", type=positive_int, default=1000, help="Monte-Carlo runs per clutter level (default 1000)"
    )
    parser.add_argument("--seed", type=seed_int, default=1, help="base seed (default 1)")
    parser.add_argument("--workers", type=positive_int, default=1, help="worker processes (default 1)")
    parser.add_argument(
        "--clutter", type=nonnegative_int, nargs="+", default=[0, 1, 2, 5], help="false tracks per sensor (0 1 2 5)"
    )
    parser.add_argument(
        "--process-noise",
        type=finite_float,
        default=PROCESS_NOISE,
        help=f"trackers' white-jerk density q, m²/s⁵ (default {PROCESS_NOISE:.0f}: the targets' maneuver power)",
    )
    parser.add_argument(
        "--window", type=int_at_least(6), default=None, help="coarse window, scans (default: all so far, at most 32)"
    )
    parser.add_argument(
        "--gate-probability",
        type=finite_float,
        default=0.99,
        help="wavelet-fuzzy coarse gate probability (default 0.99)",
    )
    parser.add_argument(
        "--demo-runs", type=nonnegative_int, default=100, help="runs of the 2-D radar + passive demo (100; 0: none)"
    )
    parser.add_argument(
        "--plot", metavar="FILE", type=output_file, help="save the tracks of one run and P(correct) against scan"
    )
    parser.add_argument("--json", metavar="FILE", type=output_file, help="save every printed figure as JSON")


def main(args: argparse.Namespace) -> int:
    # The counts and the window are checked by their argparse types.
    if args.process_noise < 0:
        raise SystemExit("--process-noise must be >= 0")
    if not 0.0 < args.gate_probability < 1.0:
        raise SystemExit("--gate-probability must be in (0, 1)")
    print(
        f"wavelet (METHODS §5): {args.runs} runs per level, seed {args.seed}, 10 targets, 30 scans, x axis, "
        f"noise variance 0.5 km², CA trackers q = {args.process_noise:g} m²/s⁵"
    )
    from .wavelet_report import print_level, print_losses, print_summary

    with worker_pool(args.workers) as pool:
        settings = Settings(args.process_noise, args.window, args.gate_probability)
        levels = run_experiment(pool, args.runs, args.seed, args.clutter, settings)
        for n_clutter, summary in levels.items():
            print_level(n_clutter, summary)
        print_summary(levels, args.runs)
        print_losses(levels)
        record: dict[str, Any] = {
            "settings": {
                k: getattr(args, k)
                for k in ("runs", "seed", "clutter", "process_noise", "window", "gate_probability", "demo_runs")
            },
            "paper": PAPER,
            "levels": {str(c): s for c, s in levels.items()},
        }
        if args.demo_runs:
            from .wavelet_passive import print_demo, run_demo

            record["passive_2d"] = run_demo(pool, args.demo_runs, args.seed, settings)
            print_demo(record["passive_2d"])
    if args.json:
        write_json(args.json, record)
    if args.plot:
        from ..plots import plot_wavelet
        from .wavelet_passive import ESM_SITES, demo_tracks

        tracks = filter_reports(paper_wavelet_scenario(args.seed).measurements, args.process_noise)
        _, radar_2d, _, passive = demo_tracks(args.seed, args.process_noise)
        plot_wavelet((tracks.of(0), tracks.of(1)), record, args.plot, (radar_2d, passive, ESM_SITES))
    return 0
