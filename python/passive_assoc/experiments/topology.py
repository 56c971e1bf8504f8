"""``passive-assoc reproduce topology``: EXPERIMENTS ``topology`` (METHODS §4, paper 002).

8 radars with azimuth biases U(±B), 20 targets (5 scattered, 3 line-abreast formations of 5),
90 scans of 10 s. Each radar's local tracks come from a constant-velocity EKF on its own
(biased) range/azimuth reports, with track ids shuffled; radar 0's tracks are the system
picture and every other radar's tracks are associated with it every scan. Scored per scan
from the first scan at which the window is full: precision, recall and F1 of every
(local, system) decision, and the error of each radar's estimated relative bias, for

* ``paper rule``: the published method, :meth:`TopologyAssociator.paper` (the closeness,
  each system track taking its best local track above λ, every pair scored);
* ``topology``: the closeness with one-to-one assignment, every pair scored — the
  configuration that reproduces the paper's figure (the library's default before the fused
  decision);
* ``fused``: the library's default :class:`TopologyAssociator` (topology, then bias, then
  distance: docs/methods.md §4);
* ``nearest``: nearest neighbour on the same data.

``--scenario ring`` runs the scene the defaults were not tuned on instead (:mod:`.topology_ring`).
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..evaluation.track_scores import track_association_scores
from ..roles import TrackAssociator
from ..simulation.topology import paper_topology_scenario
from ..topology import TopologyAssociator
from ..track_association import NearestNeighbourAssociator
from .common import finite_float, map_runs, output_file, positive_int, print_rows, run_seeds, seed_int, write_json
from .topology_tracks import GROSS_BIAS_DEG, PROCESS_NOISE, local_tracks

#: The paper's precision, recall and F1 (%); its text swaps precision and recall (METHODS §4).
PAPER = {"precision": 99.9034, "recall": 99.5362, "f1": 99.7195}
SYSTEM_RADAR = 0
#: The nearest-neighbour baseline's gate, metres, on the window-averaged distance (no χ² gate).
NEAREST_GATE = 60e3


@dataclass(frozen=True)
class RunScores:
    """One run at one bias level: (precision, recall, F1) per method, and per method and
    local radar the estimated minus the true relative bias (rad) and its standard deviation."""

    scores: dict[str, tuple[float, float, float]]
    bias_error: dict[str, NDArray[np.float64]]
    bias_std: dict[str, NDArray[np.float64]]


@dataclass(frozen=True)
class Settings:
    """What one run needs besides its seed and bias level."""

    coverage: str
    window: int
    threshold: float
    gate: float | None
    process_noise: float


#: The methods compared, in print order (module docs).
METHODS = ("paper rule", "topology", "fused", "nearest")
#: The methods whose bias estimates are printed.
BIAS_METHODS = ("topology", "fused")


def methods(settings: Settings) -> dict[str, TrackAssociator]:
    """The associators compared (module docs), one thread each."""
    threshold, window = settings.threshold, settings.window
    return {
        "paper rule": TopologyAssociator.paper(threshold=threshold, window=window, gate=settings.gate, n_threads=1),
        "topology": TopologyAssociator(
            decision="assignment", gate=settings.gate, threshold=threshold, window=window, n_threads=1
        ),
        "fused": TopologyAssociator(
            threshold=threshold, window=window, gate="auto" if settings.gate is None else settings.gate, n_threads=1
        ),
        "nearest": NearestNeighbourAssociator(
            gate=NEAREST_GATE, window=settings.window, gate_probability=None, n_threads=1
        ),
    }


def run_once(seed: np.random.SeedSequence, bias_deg: float, settings: Settings) -> RunScores:
    rng = np.random.default_rng(seed)
    scenario = paper_topology_scenario(rng, bias_deg=bias_deg, coverage=settings.coverage)  # type: ignore[arg-type]
    tracks = local_tracks(scenario, rng, settings.process_noise)
    system = tracks.of(SYSTEM_RADAR)
    local = tracks.select(np.flatnonzero(tracks.source != SYSTEM_RADAR))
    since = float(scenario.scan_times[settings.window - 1])
    scores: dict[str, tuple[float, float, float]] = {}
    radars = [r for r in range(len(scenario.radars)) if r != SYSTEM_RADAR]
    bias_error = {name: np.full(len(radars), np.nan) for name in BIAS_METHODS}
    bias_std = {name: np.full(len(radars), np.nan) for name in BIAS_METHODS}
    truth = scenario.true_biases - scenario.true_biases[SYSTEM_RADAR]
    for name, method in methods(settings).items():
        result = method.associate(local=local, system=system)
        s = track_association_scores(result, local, system, since=since)
        scores[name] = (s.precision, s.recall, s.f1)
        if name in BIAS_METHODS:
            for k, radar in enumerate(radars):
                if (b := result.bias.get(radar)) is not None:
                    bias_error[name][k] = b.rotation - truth[radar]
                    bias_std[name][k] = b.rotation_std
    return RunScores(scores, bias_error, bias_std)


def run_experiment(
    runs: int, seed: int, workers: int, biases: list[float], settings: Settings
) -> dict[float, list[RunScores]]:
    out = {}
    for bias in biases:
        seeds = run_seeds(seed, runs)  # the same scenes at every bias level (see simulation.topology)

        def work(r: int, bias: float = bias, seeds: list[np.random.SeedSequence] = seeds) -> RunScores:
            return run_once(seeds[r], bias, settings)

        out[bias] = map_runs(work, runs, workers, f"topology B={bias:g}°, {settings.coverage}")
    return out


def summarise(results: dict[float, list[RunScores]]) -> dict[str, Any]:
    rows = []
    for bias, runs in results.items():
        row: dict[str, Any] = {"bias_deg": bias}
        for method in METHODS:
            values = np.array([r.scores[method] for r in runs]) * 100
            row[method] = dict(zip(("precision", "recall", "f1"), values.mean(axis=0).tolist(), strict=True))
        for method in BIAS_METHODS:
            errors = np.degrees(np.array([r.bias_error[method] for r in runs]))
            stds = np.degrees(np.array([r.bias_std[method] for r in runs]))
            found = np.isfinite(errors)
            row[method]["bias_rms_deg"] = np.sqrt(np.nanmean(errors**2, axis=0)).tolist()  # per local radar
            row[method]["bias_median_abs_deg"] = float(np.nanmedian(np.abs(errors)))
            row[method]["bias_gross_fraction"] = float(np.mean(np.abs(errors[found]) > GROSS_BIAS_DEG))
            row[method]["bias_within_3_std"] = float(np.mean(np.abs(errors[found]) <= 3 * stds[found]))
        rows.append(row)
    return {"rows": rows, "paper": PAPER}


def print_report(summary: dict[str, Any], settings: dict[str, Any]) -> None:
    print(
        f"topology (METHODS §4): {settings['runs']} runs, {settings['coverage']} coverage, window {settings['window']}"
    )
    print("precision / recall / F1 in %, scored from the first full window; paper (either order of P and R):")
    print(f"  {PAPER['precision']:.4f} / {PAPER['recall']:.4f} / {PAPER['f1']:.4f}")
    table = [["bias", *(f"{m} F1" for m in METHODS)]]
    for row in summary["rows"]:
        table.append([f"±{row['bias_deg']:g}°", *(f"{row[m]['f1']:.3f}" for m in METHODS)])
    print_rows(table, [6, *(max(10, len(m) + 4) for m in METHODS)])
    table = [["bias", *(f"{m} P/R" for m in METHODS)]]
    for row in summary["rows"]:
        table.append(
            [f"±{row['bias_deg']:g}°", *(f"{row[m]['precision']:.3f}/{row[m]['recall']:.3f}" for m in METHODS)]
        )
    print_rows(table, [6, *(max(15, len(m) + 5) for m in METHODS)])
    table = [["bias", "method", "bias RMS° max", "median |err|°", "gross", "within 3 std"]]
    for row in summary["rows"]:
        for m in BIAS_METHODS:
            r = row[m]
            table.append(
                [
                    f"±{row['bias_deg']:g}°",
                    m,
                    f"{np.nanmax(r['bias_rms_deg']):.3f}",
                    f"{r['bias_median_abs_deg']:.3f}",
                    f"{100 * r['bias_gross_fraction']:.1f} %",
                    f"{100 * r['bias_within_3_std']:.1f} %",
                ]
            )
    print_rows(table, [6, 9, 14, 14, 8, 13])
    print("bias: each radar's estimated minus true rotation relative to the system radar; 'RMS max' is the")
    print(f"largest per-radar RMS over the runs, 'gross' the share of estimates off by more than {GROSS_BIAS_DEG:g}°,")
    print("'within 3 std' the share within three of the estimate's own standard deviations")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--scenario",
        choices=["paper", "ring"],
        default="paper",
        help="the paper's scenario (default), or the ring scene every radar pair is associated on"
        " (simulation.topology.ring_radar_scenario; --runs, --seed, --workers, --bias and --json apply)",
    )
    parser.add_argument(
        "--stonesoup", action="store_true", help="--scenario ring: add Stone Soup's associators (slow; extra stonesoup)"
    )
    parser.add_argument("--scans", type=positive_int, default=90, help="--scenario ring: scans per run (default 90)")
    parser.add_argument("--runs", type=positive_int, default=20, help="Monte-Carlo runs per bias level (default 20)")
    parser.add_argument("--seed", type=seed_int, default=1, help="base seed (default 1)")
    parser.add_argument("--workers", type=positive_int, default=1, help="worker processes (default 1)")
    parser.add_argument(
        "--bias", type=finite_float, nargs="+", default=[0.0, 1.0, 3.0, 5.0], help="bias levels B, degrees (0 1 3 5)"
    )
    parser.add_argument("--coverage", choices=["full", "partial", "both"], default="full", help="radar coverage")
    parser.add_argument("--window", type=positive_int, default=6, help="scans averaged (default 6)")
    parser.add_argument("--threshold", type=finite_float, default=0.7, help="λ as a fraction of M·N (default 0.7)")
    parser.add_argument("--gate", type=finite_float, default=None, help="position gate of the topology method, metres")
    parser.add_argument(
        "--process-noise",
        type=finite_float,
        default=PROCESS_NOISE,
        help=f"local trackers' q, m²/s³ ({PROCESS_NOISE:g})",
    )
    parser.add_argument(
        "--plot", metavar="FILE", type=output_file, help="save the pictures and F1 against bias (PNG/PDF)"
    )
    parser.add_argument("--json", metavar="FILE", type=output_file, help="save every printed figure as JSON")


def main(args: argparse.Namespace) -> int:
    if args.scenario == "ring":
        from . import topology_ring

        return topology_ring.main(args)
    if args.runs < 1:
        raise SystemExit("--runs must be at least 1")
    if args.window < 1 or not 0.0 <= args.threshold <= 1.0 or args.process_noise < 0:
        raise SystemExit("--window must be >= 1, --threshold in [0, 1], --process-noise >= 0")
    coverages = ["full", "partial"] if args.coverage == "both" else [args.coverage]
    record: dict[str, Any] = {}
    for coverage in coverages:
        run_settings = Settings(coverage, args.window, args.threshold, args.gate, args.process_noise)
        results = run_experiment(args.runs, args.seed, args.workers, args.bias, run_settings)
        summary = summarise(results)
        settings = {
            "runs": args.runs,
            "seed": args.seed,
            "coverage": coverage,
            "window": args.window,
            "threshold": args.threshold,
            "gate": args.gate,
            "process_noise": args.process_noise,
        }
        print_report(summary, settings)
        record[coverage] = {"settings": settings, **summary}
    if args.json:
        write_json(args.json, record)
    if args.plot:
        from ..plots import plot_topology

        plot_topology(paper_topology_scenario(args.seed, bias_deg=max(args.bias)), record, args.plot)
    return 0
