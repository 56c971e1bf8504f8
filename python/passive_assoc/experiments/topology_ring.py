"""``passive-assoc reproduce topology --scenario ring``: track-to-track association on a scene
the topology defaults were not tuned on (:func:`~passive_assoc.simulation.topology.ring_radar_scenario`).

8 radars on a ring each see 300 km around themselves, so radar pairs share all, most or few of
their targets, and targets enter and leave the pictures. Each radar's local tracks come from a
constant-velocity EKF on its own biased range/azimuth reports (with the filter's covariances),
ids shuffled, as in the paper's experiment (:func:`.topology_tracks.local_tracks`). *Every* radar pair
(i, j), i < j, is associated: radar i's tracks against radar j's picture, 28 pairs a run, every
scan. Scores, pooled over the radar pairs and runs at each bias level:

* pair-level precision, recall and F1: a (local track, system track) pair is declared when
  associated on at least half of the scans both exist, true when they are one target
  (:func:`~passive_assoc.evaluation.track_pair_scores`);
* scan-level F1 of every (local, system) decision of every scan
  (:func:`~passive_assoc.evaluation.track_association_scores`);
* each radar pair's final bias estimate against the truth: the RMS error, the gross ones
  (> 1°), how many lie within 3 of their own standard deviations, how many are flagged
  unreliable.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..evaluation.track_scores import track_association_scores, track_pair_scores
from ..roles import TrackAssociator
from ..simulation.topology import ring_radar_scenario
from ..topology import TopologyAssociator
from ..track_association import NearestNeighbourAssociator, TrackAssociation
from .common import map_runs, print_rows, run_seeds, write_json
from .topology_tracks import GROSS_BIAS_DEG, local_tracks

#: The associators compared, by row title. "topology" is the library's default; the paper's
#: rule, the former default (the closeness alone, one-to-one, every pair scored) and the best
#: plain position gate found for it stand beside it, with nearest neighbour as it comes and
#: without its covariance gate.
METHODS: dict[str, Callable[[], TrackAssociator]] = {
    "topology (default)": lambda: TopologyAssociator(n_threads=1),
    "topology, paper's rule": lambda: TopologyAssociator.paper(n_threads=1),
    "topology, assignment": lambda: TopologyAssociator(decision="assignment", gate=None, n_threads=1),
    "topology, assignment, 60 km gate": lambda: TopologyAssociator(decision="assignment", gate=60e3, n_threads=1),
    "nearest (default)": lambda: NearestNeighbourAssociator(n_threads=1),
    "nearest, no gate": lambda: NearestNeighbourAssociator(gate_probability=None, n_threads=1),
}


@dataclass
class Counts:
    """TP, FP, FN of one method, pair-level and scan-level, and its bias estimates' errors
    (estimate − truth, rad), standard deviations and reliability flags."""

    pair: NDArray[np.int64] = field(default_factory=lambda: np.zeros(3, np.int64))
    scan: NDArray[np.int64] = field(default_factory=lambda: np.zeros(3, np.int64))
    error: list[float] = field(default_factory=list)
    std: list[float] = field(default_factory=list)
    reliable: list[bool] = field(default_factory=list)

    def add(self, other: Counts) -> None:
        self.pair += other.pair
        self.scan += other.scan
        self.error += other.error
        self.std += other.std
        self.reliable += other.reliable


def run_once(seed: np.random.SeedSequence, bias_deg: float, names: list[str], n_scans: int = 90) -> dict[str, Counts]:
    """One scene at one bias level: every radar pair by every method in ``names``."""
    rng = np.random.default_rng(seed)
    scenario = ring_radar_scenario(rng, bias_deg=bias_deg, n_scans=n_scans)
    tracks = local_tracks(scenario, rng)
    out = {name: Counts() for name in names}
    makers = {**METHODS, **_stonesoup_methods(names)}
    for j in range(1, len(scenario.radars)):
        system = tracks.of(j)
        for i in range(j):
            local = tracks.of(i)
            if len(local) == 0 or len(system) == 0:
                continue
            truth = float(scenario.true_biases[i] - scenario.true_biases[j])
            for name in names:
                result = makers[name]().associate(local=local, system=system)
                out[name].add(_counts(result, local, system, i, truth))
    return out


def _counts(result: TrackAssociation, local: Any, system: Any, source: int, truth: float) -> Counts:
    pair = track_pair_scores(result, local, system)
    scan = track_association_scores(result, local, system)
    counts = Counts(np.array([pair.tp, pair.fp, pair.fn]), np.array([scan.tp, scan.fp, scan.fn]))
    b = result.bias.get(source)
    if b is not None:
        counts.error.append(b.rotation - truth)
        counts.std.append(b.rotation_std)
        counts.reliable.append(b.reliable)
    return counts


def _stonesoup_methods(names: list[str]) -> dict[str, Callable[[], TrackAssociator]]:
    if not any(name.startswith("stone soup") for name in names):
        return {}
    from .topology_stonesoup import STONESOUP

    return STONESOUP


def _scores(tp_fp_fn: NDArray[np.int64]) -> tuple[float, float, float]:
    tp, fp, fn = (float(v) for v in tp_fp_fn)
    p = tp / (tp + fp) if tp + fp else 1.0
    r = tp / (tp + fn) if tp + fn else 1.0
    return p, r, 2 * p * r / (p + r) if p + r else 0.0


def summarise(counts: Counts) -> dict[str, Any]:
    """Pair- and scan-level P, R, F1, and the bias estimates' figures (degrees)."""
    p, r, f1 = _scores(counts.pair)
    out: dict[str, Any] = {"pair": {"precision": p, "recall": r, "f1": f1}, "scan_f1": _scores(counts.scan)[2]}
    if counts.error:
        error, std = np.degrees(counts.error), np.degrees(counts.std)
        out["bias"] = {
            "estimates": len(error),
            "rms_deg": float(np.sqrt(np.mean(error**2))),
            "max_abs_deg": float(np.max(np.abs(error))),
            "gross": int(np.sum(np.abs(error) > GROSS_BIAS_DEG)),
            "within_3_std": float(np.mean(np.abs(error) <= 3 * std)),
            "unreliable": int(np.sum(~np.array(counts.reliable))),
            "median_std_deg": float(np.median(std)),
        }
    return out


def run_experiment(
    runs: int, seed: int, workers: int, biases: list[float], names: list[str], n_scans: int = 90
) -> dict[float, Any]:
    seeds = run_seeds(seed, runs)
    out = {}
    for bias in biases:

        def work(r: int, bias: float = bias) -> dict[str, Counts]:
            return run_once(seeds[r], bias, names, n_scans)

        total = {name: Counts() for name in names}
        for one in map_runs(work, runs, workers, f"ring scene B={bias:g}°"):
            for name in names:
                total[name].add(one[name])
        out[bias] = {name: summarise(total[name]) for name in names}
    return out


def print_report(record: dict[float, Any], runs: int, seed: int) -> None:
    biases = list(record)
    names = list(record[biases[0]])
    print(
        f"ring scene (simulation.topology.ring_radar_scenario): {runs} runs × 28 radar pairs = {28 * runs} pairs per "
        f"bias level, seed {seed}; a pair is declared when associated on >= 50 % of its common scans"
    )
    table = [["pair F1", *(f"±{b:g}°" for b in biases), "scan F1 (±0° … ±max)"]]
    for name in names:
        cells = [f"{record[b][name]['pair']['f1']:.4f}" for b in biases]
        scan = f"{record[biases[0]][name]['scan_f1']:.4f} … {record[biases[-1]][name]['scan_f1']:.4f}"
        table.append([name, *cells, scan])
    print_rows(table, [34, *([8] * len(biases)), 22])
    print("pair precision / recall:")
    table = [["", *(f"±{b:g}°" for b in biases)]]
    for name in names:
        table.append(
            [
                name,
                *(
                    f"{record[b][name]['pair']['precision']:.4f}/{record[b][name]['pair']['recall']:.4f}"
                    for b in biases
                ),
            ]
        )
    print_rows(table, [34, *([15] * len(biases))])
    print(f"bias estimates (each radar pair's final estimate; gross: off by more than {GROSS_BIAS_DEG:g}°):")
    table = [["", "bias", "RMS °", "max |err| °", "gross", "within 3 std", "unreliable", "median std °"]]
    for name in names:
        for b in biases:
            est = record[b][name].get("bias")
            if est is None:
                continue
            table.append(
                [
                    name,
                    f"±{b:g}°",
                    f"{est['rms_deg']:.3f}",
                    f"{est['max_abs_deg']:.2f}",
                    f"{est['gross']}/{est['estimates']}",
                    f"{est['within_3_std']:.3f}",
                    str(est["unreliable"]),
                    f"{est['median_std_deg']:.3f}",
                ]
            )
    print_rows(table, [34, 6, 7, 12, 8, 13, 11, 13])


def main(args: argparse.Namespace) -> int:
    names = list(METHODS)
    if args.stonesoup:
        try:
            import stonesoup  # noqa: F401
        except ImportError:
            raise SystemExit("--stonesoup needs Stone Soup: pip install 'passive-assoc[stonesoup]'") from None
        names += list(_stonesoup_methods(["stone soup"]))
    record = run_experiment(args.runs, args.seed, args.workers, args.bias, names, args.scans)
    print_report(record, args.runs, args.seed)
    if args.json:
        settings = {"scenario": "ring", "runs": args.runs, "seed": args.seed, "scans": args.scans}
        write_json(args.json, {"settings": settings, "levels": record})
    return 0
