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
from concurrent.futures import Executor
from dataclasses import replace
from typing import Any

from ..radar_esm import filter_reports
from ..simulation.radar_esm import paper_wavelet_scenario
from .common import (
    finite_float,
    int_at_least,
    nonnegative_int,
    output_file,
    positive_int,
    run_seeds,
    seed_int,
    write_json,
)
from .wavelet_passive import ESM_SITES, demo_tracks, print_demo, run_demo
from .wavelet_report import print_level, print_losses, print_summary
from .wavelet_runs import (
    PAPER,
    PROCESS_NOISE,
    Settings,
    collect,
    map_seeds,
    run_once,
    submit_seeds,
    summarise,
    worker_pool,
)


def run_experiment(
    pool: Executor | None, runs: int, seed: int, clutter: list[int], settings: Settings
) -> dict[int, Any]:
    """Summaries per clutter level; the same seeds (targets) at every level. With a pool,
    every level is queued at once, so the workers never wait for a level's last chunk."""
    seeds = run_seeds(seed, runs)
    per_level = {n: replace(settings, ablations=n == 0) for n in clutter}
    if pool is None:
        return {
            n: summarise(map_seeds(None, run_once, seeds, (n, s), f"wavelet, {n} false tracks"))
            for n, s in per_level.items()
        }
    queued = {n: submit_seeds(pool, run_once, seeds, (n, s)) for n, s in per_level.items()}
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
        "--init",
        choices=["single_point", "differencing"],
        default="single_point",
        help="how the trackers start a track: from a prior at its first report (default), or from its first"
        " three reports (the former default)",
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
        f"noise variance 0.5 km², CA trackers q = {args.process_noise:g} m²/s⁵, started by {args.init}"
    )
    with worker_pool(args.workers) as pool:
        settings = Settings(args.process_noise, args.window, args.gate_probability, init=args.init)
        levels = run_experiment(pool, args.runs, args.seed, args.clutter, settings)
        for n_clutter, summary in levels.items():
            print_level(n_clutter, summary)
        print_summary(levels, args.runs)
        print_losses(levels)
        record: dict[str, Any] = {
            "settings": {
                k: getattr(args, k)
                for k in ("runs", "seed", "clutter", "process_noise", "init", "window", "gate_probability", "demo_runs")
            },
            "paper": PAPER,
            "levels": {str(c): s for c, s in levels.items()},
        }
        if args.demo_runs:
            record["passive_2d"] = run_demo(pool, args.demo_runs, args.seed, settings)
            print_demo(record["passive_2d"])
    if args.json:
        write_json(args.json, record)
    if args.plot:
        from ..plots import plot_wavelet

        tracks = filter_reports(paper_wavelet_scenario(args.seed).measurements, args.process_noise, init=args.init)
        _, radar_2d, _, passive = demo_tracks(args.seed, args.process_noise, args.init)
        plot_wavelet((tracks.of(0), tracks.of(1)), record, args.plot, (radar_2d, passive, ESM_SITES))
    return 0
