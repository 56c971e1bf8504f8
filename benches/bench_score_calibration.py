"""Calibration of the initiation's track score (docs/methods.md §1, *Track score*): the score of
every track that holds a target and of every track that does not, with ``min_score=None`` so
no track is dropped, on simulated scenes the defaults must serve; then, against the threshold,
the true tracks a threshold would drop and the false tracks a scene it would keep.

Scenes: the 2-D simulator at 6 targets, 4x clutter and at 8 targets, Pd 0.9; the paper's at
Pd 1 and 0.9 and with 4 scans at Pd 0.9; rings of 3 × 20 and 4 × 50 sensors × targets (3-D,
Pd 0.9). A track holds a target when 2/3 of its rows are that target's (`track_targets`).

    python3 benches/bench_score_calibration.py --json scores.json --plot docs/score_calibration.png
    python3 benches/bench_score_calibration.py --from-json scores.json --plot docs/score_calibration.png
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from typing import Any

import numpy as np
import passive_assoc as pa
from passive_assoc.evaluation import track_targets

#: Scene → seeds.
SCENES = {"2d_6": 30, "2d_8": 30, "paper": 20, "paper_pd09": 20, "paper4": 40, "ring_3x20": 15, "ring_4x50": 6}
THRESHOLDS = (0.0, 10.0, 15.0, 20.0, 25.0, 30.0, 40.0)


def scene(name: str, seed: int) -> pa.Scenario:
    if name == "2d_6":
        return pa.bearing_only_2d_scenario(seed, n_targets=6, clutter_ratio=4.0)
    if name == "2d_8":
        return pa.bearing_only_2d_scenario(seed, n_targets=8, pd=0.9)
    if name == "paper":
        return pa.paper_fti_scenario(seed)
    if name == "paper_pd09":
        return pa.paper_fti_scenario(seed, pd=0.9)
    if name == "paper4":
        return pa.paper_fti_scenario(seed, n_scans=4, pd=0.9)
    s, n = (int(v) for v in name.removeprefix("ring_").split("x"))
    return pa.ring_scenario(seed, n_sensors=s, n_targets=n)


def collect(seeds: int | None) -> list[dict[str, Any]]:
    rows = []
    for name, default_seeds in SCENES.items():
        for seed in range(seeds or default_seeds):
            sc = scene(name, seed)
            result = pa.FuzzyTrackInitiator(min_score=None, on_limit="warn").initiate(
                sc.measurements, sc.sensors, t0=sc.t0, progress=False
            )
            truth = sc.measurements.truth
            assert truth is not None  # simulated tables carry their truth
            held = track_targets(result.labels, truth)
            rows += [
                {"scene": name, "seed": seed, "true": bool(h >= 0), "score": t.score}
                for t, h in zip(result.tracks, held, strict=True)
            ]
            rows.append({"scene": name, "seed": seed, "true": None, "score": None})  # one run
        print(f"{name}: done", flush=True)
    return rows


def report(rows: list[dict[str, Any]]) -> None:
    by_scene: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        by_scene[r["scene"]].append(r)
    print("| scene | runs | true tracks | lowest true score | false tracks / run | highest false score |")
    print("|---" * 6 + "|")
    for name, rs in by_scene.items():
        runs = sum(r["true"] is None for r in rs)
        true = [r["score"] for r in rs if r["true"]]
        false = [r["score"] for r in rs if r["true"] is False]
        print(
            f"| {name} | {runs} | {len(true)} | {min(true, default=float('nan')):.1f} | "
            f"{len(false) / runs:.2f} | {max(false, default=float('nan')):.1f} |"
        )
    print()
    print("| threshold | " + " | ".join(f"{n}: true lost, false / run" for n in by_scene) + " |")
    print("|---" * (len(by_scene) + 1) + "|")
    for th in THRESHOLDS:
        cells = []
        for rs in by_scene.values():
            runs = sum(r["true"] is None for r in rs)
            lost = sum(1 for r in rs if r["true"] and r["score"] < th)
            kept_false = sum(1 for r in rs if r["true"] is False and r["score"] >= th)
            cells.append(f"{lost}, {kept_false / runs:.2f}")
        print(f"| {th:g} | " + " | ".join(cells) + " |")


def plot(rows: list[dict[str, Any]], path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    true = np.array([r["score"] for r in rows if r["true"]])
    false = np.array([r["score"] for r in rows if r["true"] is False])
    runs = sum(r["true"] is None for r in rows)
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.8))
    bins = np.linspace(min(true.min(), false.min(), 0.0), max(true.max(), false.max()), 40)
    left.hist(true, bins=bins, alpha=0.6, label=f"holds a target ({len(true)})")
    left.hist(false, bins=bins, alpha=0.6, label=f"holds none ({len(false)})")
    left.axvline(pa.fti.MIN_SCORE, color="k", ls="--", lw=1, label="default min_score")
    left.set_xlabel("track score")
    left.set_ylabel("tracks")
    left.legend(fontsize=8)
    grid = np.linspace(bins[0], bins[-1], 200)
    right.plot(grid, [(false >= g).sum() / runs for g in grid], label="false tracks kept / run")
    right.plot(grid, [(true < g).sum() / len(true) for g in grid], label="true tracks dropped (share)")
    right.axvline(pa.fti.MIN_SCORE, color="k", ls="--", lw=1)
    right.set_xlabel("threshold")
    right.set_yscale("symlog", linthresh=0.01)
    right.set_ylim(bottom=0.0)
    right.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, help="seeds per scene (default: each scene's own)")
    parser.add_argument("--json", metavar="FILE", help="write every track's score (a new file)")
    parser.add_argument("--from-json", metavar="FILE", help="report and plot a saved run instead of running")
    parser.add_argument("--plot", metavar="FILE", help="histogram and threshold curves (PNG)")
    args = parser.parse_args()
    if args.from_json:
        with open(args.from_json, encoding="utf-8") as f:
            rows = json.load(f)
    else:
        rows = collect(args.seeds)
        if args.json:
            with open(args.json, "x", encoding="utf-8") as f:
                json.dump(rows, f)
    report(rows)
    if args.plot:
        plot(rows, args.plot)


if __name__ == "__main__":
    main()
