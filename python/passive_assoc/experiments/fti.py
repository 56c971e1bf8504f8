"""``passive-assoc reproduce fti``: paper 000's Monte-Carlo experiment (EXPERIMENTS.md ``fti``).

Per run: simulate the paper scenario, initiate tracks with :class:`FuzzyTrackInitiator`,
match tracks to targets, and fit every target from its true measurements as the
perfect-association reference. Reports Table 3 (RMS of X0) with, per cell, our RMS with our
own association, our RMS with perfect association, the CRLB std and the paper's two figures,
and ends with a one-line :func:`verdict` against the paper.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from .._params import Options, field_defaults
from ..evaluation import perfect_association_fit, target_crlbs
from ..fti import FuzzyTrackInitiator, InitiationResult
from ..simulation import Scenario, paper_fti_scenario
from .common import (
    finite_float,
    fmt,
    map_runs,
    nonnegative_int,
    output_file,
    positive_int,
    print_rows,
    run_seeds,
    seed_int,
    write_json,
)

COMPONENTS = ("x0", "y0", "z0", "vx", "vy", "vz")
#: Paper Table 2: one run's estimated X0 (all four targets found).
PAPER_TABLE2 = np.array(
    [
        [1281, 15035, 991, 174, -100, 0],
        [1353, 5025, 1004, 173, 99, 0],
        [6011, 1013, 1002, -1, 200, 0],
        [1354, 16008, 996, 173, -99, 0],
    ],
    dtype=float,
)
#: Paper Table 3: RMS with the paper's association, and with perfect association.
PAPER_RMS = np.array(
    [
        [58.6, 85.9, 28.3, 0.81, 1.07, 0.16],
        [27.1, 51.9, 7.64, 0.48, 0.97, 0.11],
        [60.2, 28.2, 6.88, 1.07, 1.08, 0.12],
        [56.6, 80.2, 12.0, 0.65, 1.09, 0.18],
    ]
)
PAPER_RMS_PERFECT = np.array(
    [
        [42.7, 74.7, 7.8, 0.43, 0.97, 0.12],
        [26.9, 49.6, 6.9, 0.48, 0.97, 0.11],
        [61.9, 28.0, 6.95, 1.10, 1.08, 0.10],
        [46.2, 80.1, 6.49, 0.51, 1.08, 0.13],
    ]
)
#: The verdict's lines (docs/experiments.md's acceptance lines for paper 000): all targets found
#: in at least this share of the runs, and at most this many false tracks per run ...
FOUND_SHARE, FALSE_TRACKS_PER_RUN = 0.95, 0.05
#: ... the price of association (own RMS / perfect-association RMS) of x0, y0, vx, vy no worse
#: than the paper's, nor above this where the paper's is lower ...
PRICE_COMPONENTS, PRICE_FLOOR = (0, 1, 3, 4), 1.10
#: ... and the perfect-association RMS within this of the CRLB in every cell, widened to
#: CRLB_SIGMAS Monte-Carlo standard errors (1/sqrt(2 runs) of an RMS) when that is wider: 21 %
#: at the paper's 100 runs, where sampling alone puts 2 of 24 cells beyond 15 %. The paper's
#: z0 and vz columns lie below the bound of its own model, so every cell is judged against the
#: bound, not against the paper's perfect-association figure (EXPERIMENTS.md).
CRLB_TOLERANCE, CRLB_SIGMAS = 0.15, 3.0
#: Runs behind the paper's Table 3; fewer give a verdict "at N runs" only.
PAPER_RUNS = 100
#: The paper's settings; with others its figures do not apply.
PAPER_SETTINGS = {"pd": 1.0, "clutter_ratio": 2.0}
#: A track matches a target when its X0 lies within this squared Mahalanobis distance of the
#: truth, measured with the target's CRLB (i.e. within 10 best-case standard deviations).
MATCH_GATE = 100.0


@dataclass(frozen=True)
class FtiRun:
    """What one run contributes to the report."""

    found: int
    false_tracks: int
    correct_fraction: float
    own_errors: NDArray[np.float64]  # (n_targets, 6), NaN where the target was not found
    perfect_errors: NDArray[np.float64]  # (n_targets, 6)
    seconds: float
    stage_counts: dict[str, int]
    mean_descent_iterations: float


def match_tracks(result: InitiationResult, truth: NDArray[np.float64], crlbs: NDArray[np.float64]) -> NDArray[np.int64]:
    """Track → target index (−1 for a false track), by optimal assignment on the squared
    Mahalanobis distance under each target's CRLB, gated at :data:`MATCH_GATE`."""
    states = result.states
    match = np.full(len(result.tracks), -1, dtype=np.int64)
    if len(states) == 0:
        return match
    info = np.linalg.inv(crlbs)
    diff = states[:, None, :] - truth[None, :, :]
    d2 = np.einsum("tki,kij,tkj->tk", diff, info, diff)
    rows, cols = linear_sum_assignment(np.minimum(d2, 1e12))
    ok = d2[rows, cols] <= MATCH_GATE
    match[rows[ok]] = cols[ok]
    return match


def correct_fraction(result: InitiationResult, truth_labels: NDArray[np.int64], match: NDArray[np.int64]) -> float:
    """Fraction of measurements that went where they belong: clutter to clutter, a target's
    measurement to the track matched to that target."""
    assigned_target = np.where(result.labels >= 0, match[np.maximum(result.labels, 0)], -1)
    assigned_target = np.where(result.labels >= 0, np.where(assigned_target >= 0, assigned_target, -2), -1)
    return float(np.mean(assigned_target == truth_labels))


def run_once(
    scenario: Scenario, initiator: FuzzyTrackInitiator, crlbs: NDArray[np.float64]
) -> tuple[FtiRun, InitiationResult]:
    start = time.perf_counter()
    # No bar of its own: the runs have theirs, and its reports would be in the timed call.
    result = initiator.initiate(scenario.measurements, scenario.sensors, t0=scenario.t0, progress=False)
    seconds = time.perf_counter() - start
    truth = scenario.true_states
    match = match_tracks(result, truth, crlbs)
    own = np.full_like(truth, np.nan)
    for track_index, target in enumerate(match):
        if target >= 0:
            own[target] = result.tracks[track_index].state - truth[target]
    perfect = perfect_association_fit(scenario, n_threads=initiator.n_threads).estimates - truth
    assert scenario.measurements.truth is not None
    iterations = result.diagnostics.descent_iterations
    run = FtiRun(
        int((match >= 0).sum()),
        int((match < 0).sum()),
        correct_fraction(result, scenario.measurements.truth, match),
        own,
        perfect,
        seconds,
        result.diagnostics.stage_counts,
        float(iterations.mean()) if len(iterations) else 0.0,
    )
    return run, result


def rms(errors: NDArray[np.float64]) -> NDArray[np.float64]:
    """RMS over runs, ignoring runs where the target was missed (NaN)."""
    with np.errstate(invalid="ignore"):
        value: NDArray[np.float64] = np.sqrt(np.nanmean(errors**2, axis=0))
    return value


def run_experiment(
    runs: int, seed: int, workers: int, pd: float, clutter_ratio: float, initiator: FuzzyTrackInitiator
) -> tuple[list[FtiRun], Scenario, InitiationResult, NDArray[np.float64]]:
    """All runs; returns them with run 0's scenario and result (for the plot) and the CRLBs."""
    seeds = run_seeds(seed, runs)
    reference = paper_fti_scenario(seed=0, pd=1.0, clutter_ratio=0.0)
    crlbs = target_crlbs(reference)  # full-detection geometry: the same in every run at Pd = 1
    first: list[Any] = []

    def work(r: int) -> FtiRun:
        scenario = paper_fti_scenario(seed=np.random.default_rng(seeds[r]), pd=pd, clutter_ratio=clutter_ratio)
        run, result = run_once(scenario, initiator, crlbs)
        if r == 0:
            first.extend([scenario, result])
        return run

    results = map_runs(work, runs, workers, desc="fti runs")
    if not first:  # run 0 ran on a Dask worker: repeat it here for the plot (same seed, same run)
        work(0)
    return results, first[0], first[1], crlbs


def summarise(runs: list[FtiRun], crlbs: NDArray[np.float64]) -> dict[str, Any]:
    own = rms(np.stack([r.own_errors for r in runs]))
    perfect = rms(np.stack([r.perfect_errors for r in runs]))
    return {
        "runs": len(runs),
        "found_per_run": [r.found for r in runs],
        "false_tracks_per_run": [r.false_tracks for r in runs],
        "correct_measurement_fraction_per_run": [r.correct_fraction for r in runs],
        "all_found_runs": int(sum(r.found == len(r.own_errors) for r in runs)),
        "mean_false_tracks": float(np.mean([r.false_tracks for r in runs])),
        "mean_correct_fraction": float(np.mean([r.correct_fraction for r in runs])),
        "median_seconds_per_run": float(np.median([r.seconds for r in runs])),
        "mean_stage_counts": {k: float(np.mean([r.stage_counts[k] for r in runs])) for k in runs[0].stage_counts},
        "mean_descent_iterations": float(np.mean([r.mean_descent_iterations for r in runs])),
        "rms_own": own,
        "rms_perfect": perfect,
        "crlb_std": np.sqrt(np.diagonal(crlbs, axis1=1, axis2=2)),
        "price_of_association": own / perfect,
        "paper_price_of_association": PAPER_RMS / PAPER_RMS_PERFECT,
        "paper_rms": PAPER_RMS,
        "paper_rms_perfect": PAPER_RMS_PERFECT,
    }


def run0_table(result: InitiationResult, truth: NDArray[np.float64], crlbs: NDArray[np.float64]) -> NDArray[np.float64]:
    """Run 0's estimate of each target's X0 (NaN rows for targets not found)."""
    table = np.full_like(truth, np.nan)
    for track_index, target in enumerate(match_tracks(result, truth, crlbs)):
        if target >= 0:
            table[target] = result.tracks[track_index].state
    return table


def print_table2(table: NDArray[np.float64], truth: NDArray[np.float64]) -> None:
    print("Table 2 — one run (run 0): estimated X0, ours | paper | truth")
    rows = [["target", "", *COMPONENTS]]
    for k in range(len(truth)):
        for label, values in (("ours", table[k]), ("paper", PAPER_TABLE2[k]), ("truth", truth[k])):
            rows.append(
                [
                    str(k + 1) if label == "ours" else "",
                    label,
                    *(f"{v:.0f}" if np.isfinite(v) else "missed" for v in values),
                ]
            )
    print_rows(rows, [6, 5, 7, 7, 7, 6, 6, 6])
    print()


def print_report(summary: dict[str, Any], settings: dict[str, Any]) -> None:
    n = summary["runs"]
    print(
        f"fti — paper 000, {n} runs, seed {settings['seed']}, Pd {settings['pd']}, "
        f"clutter {settings['clutter_ratio']}x true measurements per sensor and scan, "
        f"candidates {settings['candidates']}"
    )
    print(
        f"all 4 targets found in {summary['all_found_runs']}/{n} runs; "
        f"false tracks per run {summary['mean_false_tracks']:.3f}; "
        f"measurements correctly assigned {100 * summary['mean_correct_fraction']:.2f} %; "
        f"median {1e3 * summary['median_seconds_per_run']:.1f} ms per initiation"
    )
    stages = ", ".join(f"{k} {v:.0f}" for k, v in summary["mean_stage_counts"].items())
    print(
        f"candidates after each stage (mean per run): {stages}; "
        f"{summary['mean_descent_iterations']:.1f} descent iterations per search\n"
    )
    print(
        "Table 3 — RMS of X0 per cell: ours (own association) / ours (perfect association) / CRLB std"
        " | paper (paper perfect);  price = own / perfect, ours vs paper"
    )
    rows = [["target", "comp", "ours own", "ours perfect", "CRLB std", "paper", "(perfect)", "price", "paper price"]]
    for k in range(summary["rms_own"].shape[0]):
        for c, name in enumerate(COMPONENTS):
            rows.append(
                [
                    str(k + 1) if c == 0 else "",
                    name,
                    fmt(summary["rms_own"][k, c]),
                    fmt(summary["rms_perfect"][k, c]),
                    fmt(summary["crlb_std"][k, c]),
                    fmt(PAPER_RMS[k, c]),
                    f"({fmt(PAPER_RMS_PERFECT[k, c])})",
                    fmt(summary["price_of_association"][k, c]),
                    fmt(summary["paper_price_of_association"][k, c]),
                ]
            )
    print_rows(rows, [6, 4, 9, 12, 9, 7, 9, 6, 11])
    print(
        f"\nMonte-Carlo spread: each RMS over {n} runs has a relative standard error of about "
        f"1/sqrt(2 x runs) = {100 / np.sqrt(2 * n):.1f} % (Gaussian errors), so a ratio to the CRLB within "
        f"+-{200 / np.sqrt(2 * n):.0f} % is consistent with an efficient estimator."
    )
    print(
        "Note: the paper's z0 and vz columns lie several times below the CRLB of its own 5 mrad model"
        " (no unbiased estimator reaches them); judge those columns against the bound."
    )


def verdict(summary: dict[str, Any], settings: dict[str, Any]) -> dict[str, Any]:
    """Whether the run reproduces paper 000, from its own figures against the paper's stated
    ones and the CRLB (the lines above): ``{"reproduces": bool | None, "failures": [...],
    "line": "verdict: ..."}``; None when the settings are not the paper's."""
    changed = [f"--{k.replace('_', '-')} {settings[k]:g}" for k, v in PAPER_SETTINGS.items() if settings[k] != v]
    if changed:
        line = (
            f"verdict: not judged against paper 000 — {', '.join(changed)} differs from the paper's setting "
            "(Pd 1, clutter 2x), for which its figures are stated"
        )
        return {"reproduces": None, "failures": [], "line": line}
    runs = summary["runs"]
    failures = []
    if summary["all_found_runs"] < FOUND_SHARE * runs:
        failures.append(f"all 4 targets found in {summary['all_found_runs']}/{runs} runs (< {FOUND_SHARE:.0%})")
    if summary["mean_false_tracks"] > FALSE_TRACKS_PER_RUN:
        failures.append(f"{summary['mean_false_tracks']:.3f} false tracks per run (> {FALSE_TRACKS_PER_RUN})")
    price, paper_price = summary["price_of_association"], summary["paper_price_of_association"]
    bound = np.maximum(paper_price, PRICE_FLOOR)
    worst_price = (0.0, "")
    for k in range(price.shape[0]):
        for c in PRICE_COMPONENTS:
            cell = f"target {k + 1} {COMPONENTS[c]}"
            if not np.isfinite(price[k, c]) or price[k, c] > bound[k, c]:
                failures.append(
                    f"Table 3 price of association, {cell} {price[k, c]:.3f} > {bound[k, c]:.2f} "
                    f"(paper's {paper_price[k, c]:.2f})"
                )
            elif price[k, c] / bound[k, c] > worst_price[0]:
                worst_price = (price[k, c] / bound[k, c], f"{cell} {price[k, c]:.3f} against {bound[k, c]:.2f}")
    tolerance = max(CRLB_TOLERANCE, CRLB_SIGMAS / np.sqrt(2 * runs))
    off = np.abs(summary["rms_perfect"] / summary["crlb_std"] - 1.0)
    for k, c in zip(*np.nonzero(~(off <= tolerance)), strict=True):
        ours, crlb = fmt(summary["rms_perfect"][k, c]), fmt(summary["crlb_std"][k, c])
        failures.append(
            f"Table 3 perfect-association RMS, target {k + 1} {COMPONENTS[c]} {ours} is "
            f"{fmt(100 * off[k, c], 2)} % off the CRLB {crlb} (allowed {100 * tolerance:.0f} %)"
        )
    at = "" if runs >= PAPER_RUNS else f" at {runs} runs (the paper's figures are over {PAPER_RUNS})"
    if failures:
        shown = "; ".join(failures[:3]) + (f"; and {len(failures) - 3} more" if len(failures) > 3 else "")
        return {
            "reproduces": False,
            "failures": failures,
            "line": f"verdict: does NOT reproduce paper 000{at}: {shown}",
        }
    paper_ratio = PAPER_RMS_PERFECT / summary["crlb_std"]
    line = (
        f"verdict: {'reproduces' if not at else 'consistent with'} paper 000{at} — all 4 targets found in "
        f"{summary['all_found_runs']}/{runs} runs, {summary['mean_false_tracks']:.3f} false tracks per run; "
        f"price of association within the paper's (or {PRICE_FLOOR:.2f}) in x0, y0, vx, vy of every target "
        f"(closest: {worst_price[1]}); perfect-association RMS within {100 * off.max():.1f} % of the CRLB "
        f"for every target and component (allowed {100 * tolerance:.0f} % at {runs} runs; paper: "
        f"{paper_ratio[:, PRICE_COMPONENTS].min():.2f}-{paper_ratio[:, PRICE_COMPONENTS].max():.2f}x the CRLB "
        f"in x0, y0, vx, vy, {paper_ratio[:, [2, 5]].min():.2f}-{paper_ratio[:, [2, 5]].max():.2f}x in z0, vz)"
    )
    return {"reproduces": True, "failures": [], "line": line}


def _default(name: str) -> Any:
    """The initiator's declared default of ``name``: the options below restate none."""
    return field_defaults(FuzzyTrackInitiator)[name]


def _choices(name: str) -> tuple[str, ...]:
    """The words the initiator declares for ``name``."""
    return next(c.choices for c in FuzzyTrackInitiator._constraints[name] if isinstance(c, Options))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--runs", type=positive_int, default=100, help="Monte-Carlo runs (default 100)")
    parser.add_argument("--seed", type=seed_int, default=2026, help="master seed (default 2026)")
    parser.add_argument("--workers", type=positive_int, default=1, help="runs executed concurrently (default 1)")
    parser.add_argument("--pd", type=finite_float, default=1.0, help="detection probability (paper: 1)")
    parser.add_argument(
        "--clutter-ratio",
        type=finite_float,
        default=2.0,
        help="clutter points per true measurement, per sensor and scan (paper: 2)",
    )
    parser.add_argument(
        "--candidates",
        choices=_choices("candidates"),
        default="paper",
        help="candidate formation (default %(default)s: the paper's first and last scans; "
        "auto = the initiator's default, witnessed by the pair's own scans at two sensors)",
    )
    parser.add_argument(
        "--refine-passes",
        type=nonnegative_int,
        default=_default("refine_passes"),
        help="classify-and-refit passes after the final fit (default %(default)s; 0 = the paper's pipeline)",
    )
    parser.add_argument(
        "--candidate-scans",
        type=positive_int,
        default=_default("candidate_scans"),
        help="scans at each end of the window that form candidates "
        "(default %(default)s; 1 = the paper's first and last)",
    )
    parser.add_argument(
        "--descent-scaling",
        choices=_choices("descent_scaling"),
        default=_default("descent_scaling"),
        help="coordinates of the closeness search (default %(default)s; diagonal = METHODS wording)",
    )
    parser.add_argument(
        "--detection-order",
        choices=_choices("detection_order"),
        default=_default("detection_order"),
        help="order in which detection visits the optima (default %(default)s; closeness = the paper's)",
    )
    parser.add_argument(
        "--gate-pd",
        type=finite_float,
        default=_default("gate_pd"),
        help="detection probability the tracking gate assumes to price misses (default %(default)s: not priced)",
    )
    parser.add_argument(
        "--plot", metavar="FILE", type=output_file, help="save the run-0 picture and RMS-vs-CRLB bars (PNG/PDF)"
    )
    parser.add_argument("--json", metavar="FILE", type=output_file, help="save every printed figure as JSON")


def main(args: argparse.Namespace) -> int:
    if args.runs < 1:
        raise SystemExit("--runs must be at least 1")
    initiator = FuzzyTrackInitiator(
        n_threads=1 if args.workers > 1 else None,
        candidates=args.candidates,
        refine_passes=args.refine_passes,
        candidate_scans=args.candidate_scans,
        descent_scaling=args.descent_scaling,
        detection_order=args.detection_order,
        gate_pd=args.gate_pd,
    )
    runs, scenario, result, crlbs = run_experiment(
        args.runs, args.seed, args.workers, args.pd, args.clutter_ratio, initiator
    )
    summary = summarise(runs, crlbs)
    summary["run0_estimates"] = run0_table(result, scenario.true_states, crlbs)
    summary["paper_table2"] = PAPER_TABLE2
    settings = {
        "seed": args.seed,
        "pd": args.pd,
        "clutter_ratio": args.clutter_ratio,
        "workers": args.workers,
        "candidates": args.candidates,
        "refine_passes": args.refine_passes,
        "candidate_scans": args.candidate_scans,
        "descent_scaling": args.descent_scaling,
        "detection_order": args.detection_order,
        "gate_pd": args.gate_pd,
    }
    print_table2(summary["run0_estimates"], scenario.true_states)
    print_report(summary, settings)
    judged = verdict(summary, settings)
    if args.json:
        write_json(args.json, {"experiment": "fti", "settings": settings, **summary, "verdict": judged})
    if args.plot:
        from ..plots import plot_fti

        plot_fti(scenario, result, summary, args.plot)
        print(f"plot saved to {args.plot}")
    print(judged["line"])
    return 0
