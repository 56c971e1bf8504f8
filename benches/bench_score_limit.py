"""How much evidence a target's own rows hold, against what the initiation's false tracks reach
(docs/methods.md §1, *Track score*): the information limit of a 2-D scene.

For each scene and seed, every target's true rows are fitted alone (``fit_ml``) and scored
with the track score as the initiation computes it (``track_scores``), the clutter density
taken from the rows no target holds: the score a perfect association would give each target.
Then ``FuzzyTrackInitiator(min_score=None, on_limit="warn")`` runs on the scene, and the scores
of its tracks that hold no target (2/3 of their rows, ``track_targets``) are collected, with
the targets its tracks hold. Where
the true rows score below the default ``min_score`` or below the false tracks the search finds,
no threshold on the score, and no association that judges a track by its own rows, separates
the targets from the clutter.

Scenes: ``bearing_only_2d_scenario(seed, n_targets=20, clutter_ratio=4, pd=0.9)`` (the
2-D 3 × 20 target scene of the initiation tables), the same with 16 scans, and with clutter
ratios 2 and 1; and the 8-target Pd 0.9 scene for contrast. ``--no-search`` skips the
initiation (the true rows' scores only).

    python3 benches/bench_score_limit.py [--seeds 5] [--no-search]
"""

from __future__ import annotations

import argparse
import warnings
from typing import Any

import numpy as np
import passive_assoc as pa
from passive_assoc.evaluation import track_targets
from passive_assoc.fti.score import MIN_SCORE, track_scores

#: Scene name → `bearing_only_2d_scenario` keywords.
SCENES: dict[str, dict[str, Any]] = {
    "3 × 20, 4× clutter": dict(n_targets=20, clutter_ratio=4.0, pd=0.9),
    "3 × 20, 4× clutter, 16 scans": dict(n_targets=20, clutter_ratio=4.0, pd=0.9, n_scans=16),
    "3 × 20, 2× clutter": dict(n_targets=20, clutter_ratio=2.0, pd=0.9),
    "3 × 20, 1× clutter": dict(n_targets=20, clutter_ratio=1.0, pd=0.9),
    "3 × 8, Pd 0.9 (2× clutter)": dict(n_targets=8, pd=0.9),
}


def true_scores(sc: pa.Scenario) -> np.ndarray:
    """Each target's score from its own rows, fitted alone (module doc)."""
    m = sc.measurements
    truth = np.asarray(m.truth)
    targets = [k for k in range(len(sc.targets)) if np.any(truth == k)]
    fit = pa.fit_ml(m, sc.sensors, [np.flatnonzero(truth == k) for k in targets], t0=sc.t0)
    labels = np.full(len(truth), -1, dtype=np.int64)
    for i, k in enumerate(targets):
        labels[truth == k] = i
    return track_scores(labels, fit.chi2, m, sc.sensors, 0.9)


def false_scores(sc: pa.Scenario) -> tuple[np.ndarray, int, bool]:
    """The scores of the initiation's tracks that hold no target, the targets its tracks hold,
    and whether it hit a limit."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pa.LimitWarning)
        r = pa.FuzzyTrackInitiator(min_score=None, on_limit="warn").initiate(
            sc.measurements, sc.sensors, t0=sc.t0, progress=False
        )
    held = track_targets(r.labels, np.asarray(sc.measurements.truth))
    scores = np.array([t.score for t in r.tracks])
    found = len(set(held.tolist()) - {-1})
    return scores[held < 0], found, r.termination == "candidate_limit"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--no-search", action="store_true", help="the true rows' scores only")
    args = parser.parse_args()
    print(f"default min_score = {MIN_SCORE:g}")
    print(
        "| scene | seeds | targets | true rows' score: median | 10–90 % | below min_score "
        "| found (every track kept) | false tracks a run | highest false score "
        "| false above the true median a run | limit reached |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, keywords in SCENES.items():
        trues, falses, limited, found = [], [], 0, 0
        for seed in range(args.seeds):
            sc = pa.bearing_only_2d_scenario(seed, **keywords)
            trues.append(true_scores(sc))
            if not args.no_search:
                scores, held, hit = false_scores(sc)
                falses.append(scores)
                found += held
                limited += hit
        t = np.concatenate(trues)
        median = float(np.median(t))
        lo, hi = np.percentile(t, [10, 90])
        below = int(np.sum(t < MIN_SCORE))
        if args.no_search:
            search = "– | – | – | – | –"
        else:
            f = np.concatenate(falses)
            top = f"{f.max():.1f}" if len(f) else "–"
            above = float(np.sum(f > median)) / args.seeds
            search = f"{found}/{len(t)} | {len(f) / args.seeds:.1f} | {top} | {above:.1f} | {limited}/{args.seeds}"
        print(f"| {name} | {args.seeds} | {len(t)} | {median:.1f} | {lo:.1f}–{hi:.1f} | {below}/{len(t)} | {search} |")


if __name__ == "__main__":
    main()
