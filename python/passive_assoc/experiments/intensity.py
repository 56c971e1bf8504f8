"""``passive-assoc reproduce intensity``: paper 001's experiments (EXPERIMENTS.md ``intensity``).

Table 2 — association accuracy per resolution ratio R for every method; Table 1 — time per
method for M ∈ {6, 12, 18} and well beyond, with the Lagrangian duality gap and the gap to the
exact optimum where branch-and-bound proves one.
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from .._core import Candidates
from ..assignment import assign_sd
from ..evaluation import gospa
from ..simulation.static_los import SQUARE_X, SQUARE_Y, StaticScan, sector, static_scan
from ..static_los import associate_static, enumerate_candidates
from ..static_los.associator import Method
from ..static_los.prior import check_region, prior_costs
from .common import finite_float, fmt, map_runs, output_file, positive_int, print_rows, run_seeds, seed_int, write_json
from .intensity_timing import METHODS, Solvers, print_timing, timing_table

PAPER_ACCURACY = {5: {"lagrangian": 35.0, "intensity": 39.0}, 15: {"lagrangian": 58.0, "intensity": 67.0}}
GOSPA_CUTOFF_M = 1000.0


def true_tuples(scan: StaticScan) -> list[tuple[int, ...]]:
    """The table rows of every observable target's reports (−1 where a sensor missed it)."""
    return [tuple(scan.true_tuples[k].tolist()) for k in np.flatnonzero(scan.observable())]


def truth_cost(scan: StaticScan, cands: Candidates, costs: np.ndarray) -> float:
    """``costs`` (one per candidate) summed over the true association; NaN if a true tuple
    failed the gate."""
    index = {tuple(row): k for k, row in enumerate(cands.rows.tolist())}
    true = true_tuples(scan)
    if any(t not in index for t in true):
        return float("nan")
    return float(sum(costs[index[t]] for t in true))


def ghosts(scan: StaticScan, cands: Candidates) -> int:
    """Candidates every sensor sees (intensity S) that are not a target."""
    full = {
        tuple(row) for row, i in zip(cands.rows.tolist(), cands.intensity, strict=True) if i == scan.sensors.n_sensors
    }
    return len(full) - sum(1 for t in true_tuples(scan) if t in full)


def score(
    scan: StaticScan, cands: Candidates, method: Method, solvers: Solvers, prior: bool = False
) -> dict[str, float]:
    """Accuracy (observable targets whose full tuple, misses included, is exactly recovered)
    and GOSPA of one method on one scan; for the exact method also whether the truth's own
    eq. 2 cost is higher than the proven optimum (then no optimiser of eq. 2 can return it).
    ``cands`` are the scan's enumerated candidates, to price the truth."""
    # The paper's configuration: the intensity method with its valid-airspace step.
    # max_chains=None: the paper's vote over every point of H (the library caps it at 64).
    settings = solvers.kwargs(method)
    if prior:
        settings.update(scenario_prior(scan))
    result = associate_static(scan.measurements, scan.sensors, method, n_threads=1, max_chains=None, **settings)
    found = {tuple(row) for row in result.rows.tolist()}
    hits = [t in found for t in true_tuples(scan)]
    g = gospa(result.positions, scan.targets[scan.observable()], c=GOSPA_CUTOFF_M)
    out = {"accuracy": float(np.mean(hits)) if hits else float("nan"), "gospa": g.total}
    if method == "exact" and not prior:
        out["ghosts"] = ghosts(scan, cands)
        solver = result.diagnostics.solver
        if solver is not None and solver.optimal:
            out["truth_beaten"] = float(truth_cost(scan, cands, cands.costs) > solver.primal_cost + 1e-9)
    return out


def scenario_prior(scan: StaticScan, pd: float = 0.95, p_false: float = 0.05) -> dict[str, Any]:
    """What a user who knows the scenario knows, as ``StaticAssociator`` options: targets
    uniform over the square at density M / area, and each sensor's false-alarm density — the
    simulation's Poisson mean ``p_false / (1 - p_false) · pd · M`` over the sector the square
    covers from it (instead of the default's estimate from the scan)."""
    area = (SQUARE_X[1] - SQUARE_X[0]) * (SQUARE_Y[1] - SQUARE_Y[0])
    mean = p_false / (1 - p_false) * pd * len(scan.targets)
    widths = np.array([high - low for low, high in map(sector, scan.sensors.positions[:, :2])])
    return {
        "region": (*SQUARE_X, *SQUARE_Y),
        "target_density": len(scan.targets) / area,
        "false_alarm_density": mean / widths,
    }


def bayes_map(scan: StaticScan, time_limit: float) -> dict[str, float]:
    """The best any method can expect here: the exact MAP association under the scenario's own
    model, which eq. 2 only approximates — its candidates priced with the scenario's own
    false-alarm density and prior (:func:`scenario_prior`,
    :func:`passive_assoc.static_los.prior.prior_costs`) and solved exactly with ``assign_sd``
    (the associators' options do the same through ``exact``). Returns its accuracy and whether
    the truth's own cost is higher than that MAP's (then no estimator of the association can
    prefer it)."""
    prior = scenario_prior(scan)
    cands = enumerate_candidates(
        scan.measurements, scan.sensors, false_alarm_density=prior["false_alarm_density"], n_threads=1
    )
    cost = prior_costs(cands, check_region(prior["region"], 2), prior["target_density"])
    keep = np.flatnonzero(np.isfinite(cost) & (cost < 0))
    solved = assign_sd(cands.tuples[keep], cost[keep], cands.sizes, method="exact", time_limit=time_limit)
    found = {tuple(cands.rows[keep[k]].tolist()) for k in solved.chosen}
    true = true_tuples(scan)
    out = {"accuracy": float(np.mean([t in found for t in true])) if true else float("nan")}
    # A true tuple costing > 0 would never be chosen: the truth's best price leaves it out.
    truth = truth_cost(scan, cands, np.minimum(cost, 0.0))
    if solved.optimal and np.isfinite(truth):
        out["truth_beaten"] = float(truth > solved.primal_cost + 1e-9)
    return out


def accuracy_table(
    runs: int,
    seed: int,
    ratios: list[float],
    n_targets: int,
    workers: int,
    solvers: Solvers,
    bayes: bool = False,
    prior: bool = False,
) -> dict[str, Any]:
    table: dict[str, Any] = {}
    for ratio in ratios:
        seeds = run_seeds(seed + int(ratio * 1000), runs)

        def work(
            r: int, ratio: float = ratio, seeds: list[np.random.SeedSequence] = seeds
        ) -> dict[str, dict[str, float]]:
            scan = static_scan(np.random.default_rng(seeds[r]), n_targets=n_targets, ratio=ratio)
            cands = enumerate_candidates(scan.measurements, scan.sensors, n_threads=1)
            out: dict[str, dict[str, float]] = {m: score(scan, cands, m, solvers) for m in METHODS}
            if bayes:
                out["bayes"] = bayes_map(scan, solvers.time_limit)
            if prior:
                out.update({f"{m}+prior": score(scan, cands, m, solvers, prior=True) for m in METHODS})
            return out

        per_run = map_runs(work, runs, workers, desc=f"accuracy R={ratio:g}")
        table[f"{ratio:g}"] = {
            m: {
                "accuracy_pct": 100 * float(np.nanmean([p[m]["accuracy"] for p in per_run])),
                "gospa_mean_m": float(np.mean([p[m]["gospa"] for p in per_run])),
            }
            for m in METHODS
        }
        if prior:
            table[f"{ratio:g}"]["with_prior"] = {
                m: {
                    "accuracy_pct": 100 * float(np.nanmean([p[f"{m}+prior"]["accuracy"] for p in per_run])),
                    "gospa_mean_m": float(np.mean([p[f"{m}+prior"]["gospa"] for p in per_run])),
                }
                for m in METHODS
            }
        proven = [p["exact"]["truth_beaten"] for p in per_run if "truth_beaten" in p["exact"]]
        table[f"{ratio:g}"]["truth_costlier_than_optimum_pct"] = (
            100 * float(np.mean(proven)) if proven else float("nan")
        )
        table[f"{ratio:g}"]["exact_proven_runs"] = len(proven)
        table[f"{ratio:g}"]["ghosts_per_scan_median"] = float(np.median([p["exact"]["ghosts"] for p in per_run]))
        if bayes:
            beaten = [p["bayes"]["truth_beaten"] for p in per_run if "truth_beaten" in p["bayes"]]
            table[f"{ratio:g}"]["bayes_map"] = {
                "accuracy_pct": 100 * float(np.nanmean([p["bayes"]["accuracy"] for p in per_run])),
                "truth_costlier_pct": 100 * float(np.mean(beaten)) if beaten else float("nan"),
                "proven_runs": len(beaten),
            }
    return table


def print_accuracy(table: dict[str, Any], runs: int, n_targets: int) -> None:
    print(
        f"Table 2 — association accuracy, M = {n_targets}, {runs} runs per R "
        "(observable targets whose full tuple, misses included, is exactly recovered) | paper"
    )
    out = [
        [
            "R",
            *(f"{m} %" for m in METHODS),
            "paper lagr. %",
            "paper int. %",
            *(f"GOSPA {m[:5]} m" for m in METHODS),
            "truth>opt %",
            "ghosts",
        ]
    ]
    for ratio, cells in table.items():
        paper = PAPER_ACCURACY.get(int(float(ratio)), {})
        out.append(
            [
                ratio,
                *(f"{cells[m]['accuracy_pct']:.1f}" for m in METHODS),
                fmt(paper.get("lagrangian")),
                fmt(paper.get("intensity")),
                *(f"{cells[m]['gospa_mean_m']:.0f}" for m in METHODS),
                fmt(cells["truth_costlier_than_optimum_pct"]),
                fmt(cells["ghosts_per_scan_median"]),
            ]
        )
    print_rows(out, [4, 12, 13, 8, 13, 12, 12, 12, 12, 11, 6])
    print("  truth>opt: scans (with a proven exact optimum) where the true association's own eq. 2 cost is")
    print("  higher than the optimum's — there no method that optimises eq. 2 can return the truth;")
    print("  ghosts: median number of intensity-S candidates per scan that are not targets")
    if any("with_prior" in cells for cells in table.values()):
        print(
            "\nWith what the scenario's user knows (region= the square, target_density= M / area, "
            "false_alarm_density= the simulation's; a project extension)"
        )
        out = [["R", *(f"{m} %" for m in METHODS), *(f"GOSPA {m[:5]} m" for m in METHODS)]]
        for ratio, cells in table.items():
            w = cells["with_prior"]
            out.append(
                [
                    ratio,
                    *(f"{w[m]['accuracy_pct']:.1f}" for m in METHODS),
                    *(f"{w[m]['gospa_mean_m']:.0f}" for m in METHODS),
                ]
            )
        print_rows(out, [4, 12, 13, 8, 13, 12, 12])
    if any("bayes_map" in cells for cells in table.values()):
        print("\nBound — exact MAP under the scenario's own model (uniform prior over the square, Laplace marginal)")
        out = [["R", "MAP accuracy %", "truth costlier than MAP %", "proven runs"]]
        for ratio, cells in table.items():
            b = cells["bayes_map"]
            out.append([ratio, f"{b['accuracy_pct']:.1f}", fmt(b["truth_costlier_pct"]), str(b["proven_runs"])])
        print_rows(out, [4, 15, 26, 12])


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--runs", type=positive_int, default=200, help="Monte-Carlo runs per R (default 200)")
    parser.add_argument("--seed", type=seed_int, default=2026, help="master seed (default 2026)")
    parser.add_argument("--workers", type=positive_int, default=1, help="runs executed concurrently (default 1)")
    parser.add_argument("--targets", type=positive_int, default=10, help="M for the accuracy table (paper: 10)")
    parser.add_argument(
        "--ratios", type=finite_float, nargs="+", default=[5, 10, 15, 20], help="R values (default 5 10 15 20)"
    )
    parser.add_argument(
        "--time-limit", type=finite_float, default=2.0, help="branch-and-bound limit per scan, s (default 2)"
    )
    parser.add_argument(
        "--no-timing", action="store_true", help="skip Table 1 (its timing sweep does not follow --runs; minutes)"
    )
    parser.add_argument(
        "--no-airspace",
        action="store_true",
        help="run the intensity method without its valid-airspace step (the library default)",
    )
    parser.add_argument(
        "--prior",
        action="store_true",
        help="also run every method with what the scenario's user knows: region, target density, false-alarm density",
    )
    parser.add_argument(
        "--bayes-bound",
        action="store_true",
        help="also solve each scan exactly under the scenario's true prior: what any method can expect",
    )
    parser.add_argument(
        "--max-iter",
        type=positive_int,
        default=200,
        help="Lagrangian iteration cap (default 200; MATLAB assignsd: 100)",
    )
    parser.add_argument(
        "--gap-tol",
        type=finite_float,
        default=1e-3,
        help="Lagrangian relative-gap target (default 1e-3; MATLAB assignsd: 0.01)",
    )
    parser.add_argument(
        "--sensor-order",
        choices=("auto", "given"),
        default="auto",
        help="sensors the Lagrangian relaxation keeps as its 2-D problem (default auto: the two "
        "with the fewest reports; given: the first two)",
    )
    parser.add_argument(
        "--polish",
        action="store_true",
        help="end the Lagrangian (and the exact solver's root) with the compound-move polish",
    )
    parser.add_argument(
        "--timing-scans", type=positive_int, default=5, help="scans per Table 1 row, median reported (default 5)"
    )
    parser.add_argument("--max-m", type=positive_int, default=500, help="largest M in Table 1 (default 500)")
    parser.add_argument(
        "--plot",
        metavar="FILE",
        type=output_file,
        help="save a picture of one scan: lines of sight, candidates, accepted targets",
    )
    parser.add_argument("--json", metavar="FILE", type=output_file, help="save every printed figure as JSON")


def main(args: argparse.Namespace) -> int:
    if args.runs < 1 or args.timing_scans < 1 or args.max_iter < 1:
        raise SystemExit("--runs, --timing-scans and --max-iter must be at least 1")
    if not args.gap_tol >= 0:
        raise SystemExit("--gap-tol must be >= 0")
    print(
        "intensity — paper 001: 2-D sensors at (-15,0), (0,-5), (15,0) km; targets uniform in "
        "[-10,10] x [20,40] km; Pd 0.95, P_FA 0.05 (Poisson false bearings over each sensor's sector)\n"
    )
    solvers = Solvers(
        args.time_limit, not args.no_airspace, args.max_iter, args.gap_tol, args.sensor_order, args.polish
    )
    accuracy = accuracy_table(
        args.runs, args.seed, args.ratios, args.targets, args.workers, solvers, args.bayes_bound, args.prior
    )
    print_accuracy(accuracy, args.runs, args.targets)
    timing: list[dict[str, Any]] = []
    if not args.no_timing:
        cases = [(3, m) for m in (6, 12, 18, 50, 100, 200, 500) if m <= args.max_m]
        cases += [(s, m) for s in (4, 5) for m in (18, 50, 100) if m <= args.max_m]
        print(
            f"Table 1: timing {len(cases)} (S, M) cases on {args.timing_scans} scan(s) each (one beyond M = 100); "
            "this sweep does not follow --runs: bound it with --timing-scans and --max-m, or skip it with "
            "--no-timing",
            flush=True,
        )
        timing = timing_table(args.seed, cases, ratio=15.0, solvers=solvers, scans=args.timing_scans)
        print_timing(timing)
    if args.json:
        settings = {k: v for k, v in vars(args).items() if k not in ("run", "command", "experiment")}
        write_json(args.json, {"experiment": "intensity", "settings": settings, "accuracy": accuracy, "timing": timing})
    if args.plot:
        from ..plots import plot_static_scan

        scan = static_scan(args.seed, n_targets=args.targets, ratio=args.ratios[-1])
        plot_static_scan(scan, args.plot)
        print(f"plot saved to {args.plot}")
    return 0
