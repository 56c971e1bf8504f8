"""``reproduce intensity``'s solver settings, shared by every table, and its Table 1: the time
of every static-association method per scan (METHODS §2; the accuracy tables are in
:mod:`.intensity`)."""

from __future__ import annotations

import sys
import time
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np
from tqdm import tqdm

from ..simulation.static_los import StaticScan, static_scan
from ..static_los import associate_static
from ..static_los.associator import Method
from .common import fmt, print_rows

METHODS: tuple[Method, ...] = ("intensity", "lagrangian", "exact")
PAPER_SECONDS = {
    6: {"exact": 16.6, "lagrangian": 0.4, "intensity": 0.3},
    12: {"lagrangian": 3.2, "intensity": 1.5},
    18: {"lagrangian": 11.7, "intensity": 3.1},
}


@dataclass(frozen=True)
class Solvers:
    """The solver settings every table's calls share (see :func:`associate_static`)."""

    time_limit: float = 2.0
    valid_airspace: bool = True
    max_iter: int = 200
    gap_tol: float = 1e-3
    sensor_order: Literal["auto", "given"] = "auto"
    polish: bool = False
    #: The documented Table 1 and accuracy figures are the core's branch-and-bound's; the
    #: library's default ("auto") hands hard problems to HiGHS.
    exact_backend: Literal["auto", "branch_bound", "highs"] = "branch_bound"

    def kwargs(self, method: str) -> dict[str, Any]:
        """The settings as keyword arguments of :func:`associate_static` (one per field).
        ``time_limit`` binds the exact method only: the documented figures are of Lagrangian
        solves that end on ``max_iter`` or the gap, and the largest scans take longer than the
        limit."""
        settings = asdict(self)
        if method != "exact":
            settings["time_limit"] = None
        return settings


#: Largest M timed with the paper's full vote; beyond it the intensity method starts at most
#: MAX_CHAINS chains (see associate_static's max_chains), and Table 1 says so.
FULL_VOTE_MAX_M = 18
MAX_CHAINS = 64


def _timed(scan: StaticScan, method: Method, solvers: Solvers, repeats: int) -> tuple[float, Any]:
    best, result = np.inf, None
    max_chains = None if len(scan.targets) <= FULL_VOTE_MAX_M else MAX_CHAINS
    for _ in range(repeats):
        start = time.perf_counter()
        result = associate_static(
            scan.measurements, scan.sensors, method, n_threads=1, max_chains=max_chains, **solvers.kwargs(method)
        )
        best = min(best, time.perf_counter() - start)
    return best, result


def _time_scan(scan: StaticScan, solvers: Solvers) -> dict[str, Any]:
    """Every method on one scan: best-of-repeats seconds and the solver reports."""
    repeats = 3 if len(scan.targets) <= 50 else 1
    out: dict[str, Any] = {}
    for method in METHODS:
        if method == "exact" and len(scan.targets) > 100:
            continue  # far beyond what branch-and-bound can prove
        seconds, result = _timed(scan, method, solvers, repeats)
        out[f"{method}_s"] = seconds
        out["candidates"] = result.diagnostics.candidates
        solver = result.diagnostics.solver
        if solver is not None:
            out[f"{method}_cost"] = solver.primal_cost
        if solver is not None and method == "lagrangian":
            out["lagrangian_gap"] = solver.gap
            out["lagrangian_iterations"] = solver.iterations
        if solver is not None and method == "exact":
            out["exact_proven"] = solver.optimal
    if out.get("exact_proven"):
        out["lagrangian_gap_to_optimum"] = (out["lagrangian_cost"] - out["exact_cost"]) / max(
            1.0, abs(out["exact_cost"])
        )
    return out


def timing_table(
    seed: int, cases: list[tuple[int, int]], ratio: float, solvers: Solvers, scans: int = 5
) -> list[dict[str, Any]]:
    """Per (S, M): the median over ``scans`` random scans (one beyond M = 100) of each
    method's time, of the candidate count and of the gaps — a single scan's figure depends on
    how many ghosts it happens to have."""
    rows = []
    bar = tqdm(cases, desc="Table 1 timing", unit="case", file=sys.stderr, disable=None, leave=False)
    for n_sensors, n_targets in bar:
        bar.set_postfix_str(f"S={n_sensors}, M={n_targets}")
        per_scan = []
        for k in range(scans if n_targets <= 100 else 1):
            scan = static_scan(
                seed + 7 * n_targets + n_sensors + 1000 * k, n_targets=n_targets, n_sensors=n_sensors, ratio=ratio
            )
            per_scan.append((len(scan.measurements), _time_scan(scan, solvers)))

        def median(key: str) -> float | None:
            values = [t[key] for _, t in per_scan if t.get(key) is not None]  # noqa: B023 - called in this iteration only
            return float(np.median(values)) if values else None

        row: dict[str, Any] = {
            "S": n_sensors,
            "M": n_targets,
            "scans": len(per_scan),
            "reports": int(np.median([n for n, _ in per_scan])),
        }
        for key in (
            "candidates",
            "intensity_s",
            "lagrangian_s",
            "exact_s",
            "lagrangian_gap",
            "lagrangian_iterations",
            "lagrangian_gap_to_optimum",
        ):
            row[key] = median(key)
        row["candidates"] = int(row["candidates"])
        row["exact_proven"] = (
            sum(bool(t.get("exact_proven")) for _, t in per_scan) if row["exact_s"] is not None else None
        )
        rows.append(row)
    return rows


def print_timing(rows: list[dict[str, Any]]) -> None:
    print(
        "\nTable 1 — seconds per scan on one thread, enumeration included, median over the scans"
        " | paper (2000 hardware)"
    )
    out = [
        [
            "S",
            "M",
            "reports",
            "cand.",
            "intensity",
            "lagrangian",
            "exact",
            "lagr. gap",
            "lagr. it.",
            "gap to opt.",
            "paper i/l/e",
        ]
    ]
    for r in rows:
        paper = PAPER_SECONDS.get(r["M"], {}) if r["S"] == 3 else {}
        proven = "" if r.get("exact_proven") == r["scans"] else f"*{r.get('exact_proven')}/{r['scans']}"
        exact = "-" if r.get("exact_s") is None else fmt(r["exact_s"]) + proven
        out.append(
            [
                str(r["S"]),
                str(r["M"]),
                str(r["reports"]),
                str(r["candidates"]),
                fmt(r["intensity_s"]),
                fmt(r["lagrangian_s"]),
                exact,
                fmt(r["lagrangian_gap"]),
                f"{r['lagrangian_iterations']:.0f}",
                fmt(r.get("lagrangian_gap_to_optimum")),
                "/".join(fmt(paper.get(m)) for m in METHODS) if paper else "",
            ]
        )
    print_rows(out, [2, 4, 8, 7, 10, 11, 11, 10, 10, 12, 16])
    print(
        f"  median over {rows[0]['scans'] if rows else 0} scans per row (1 beyond M = 100); reports, candidates,"
        " gaps and Lagrangian iterations (cap 200): medians too"
    )
    print("  *p/n exact: time limit reached on some scans, optimum proven on p of n; '-': not attempted")
    print(
        f"  intensity for M > {FULL_VOTE_MAX_M}: at most {MAX_CHAINS} chains (max_chains); the paper's full vote is"
        " quadratic where every ghost has 0 exclusive rays"
    )
