"""Fuzzy track initiation at scale: time, peak memory and where the time goes, against the
number of targets and of sensors.

The scene is the paper's, grown: 3-D sensors 20 km apart on the x axis (2 of them: the paper's
pair), targets at random in x ∈ [0, 20] km, y ∈ [1, 16] km, z = 1 km with the paper's speeds
(100-200 m/s, random heading in the plane), 8 scans of 15 s, sensor j sampling 5 s after
sensor j − 1, σ = 5 mrad, clutter twice the true reports per sensor and scan (the paper's
ratio) over the paper's azimuth [0, π] × elevation [0, π/2]. Each case runs in its own process
(peak RSS is per process) with a wall-clock cap; the defaults of `FuzzyTrackInitiator`.

    python3 benches/bench_initiation_scale.py [--targets 4 8 16] [--sensors 2 3] [--cap 120]
    python3 benches/bench_initiation_scale.py --area-km 200 --v-max 250   # a wide scene
    python3 benches/bench_initiation_scale.py --targets 32 --max-candidates 5000000   # past the default cap
    python3 benches/bench_initiation_scale.py --gate-pd 0.9   # misses priced (opt-in)
    python3 benches/bench_initiation_scale.py --search-stage none   # every candidate searched first
    python3 benches/bench_initiation_scale.py --adjacent-pairs   # pairs (0, 1), (1, 2), ... only
    python3 benches/bench_initiation_scale.py --detection-order closeness   # the paper's order
    python3 benches/bench_initiation_scale.py --candidates paper   # the paper's candidate formation
    python3 benches/bench_initiation_scale.py --no-sweep   # the rounds formation without its sweep
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from typing import Any

CASE = r"""
import json, resource, sys, time
import numpy as np
import passive_assoc as pa
from passive_assoc.evaluation import track_targets
from passive_assoc.simulation.scenario import ConstantVelocityTarget, simulate

n_targets, n_sensors, seed = (int(v) for v in sys.argv[1:4])
area, v_max, max_candidates = float(sys.argv[4]) * 1e3, float(sys.argv[5]), int(sys.argv[6])
gate_pd = float(sys.argv[7]) if sys.argv[7] != "None" else None
search_stage = sys.argv[8] if len(sys.argv) > 8 else "default"
adjacent = len(sys.argv) > 9 and sys.argv[9] == "adjacent"
order = sys.argv[10] if len(sys.argv) > 10 else "default"
formation = sys.argv[11] if len(sys.argv) > 11 else "default"
no_sweep = len(sys.argv) > 12 and sys.argv[12] == "nosweep"
rng = np.random.default_rng(seed)
sensors = pa.SensorNetwork.spatial([[20e3 * j, 0.0, 0.0] for j in range(n_sensors)], 5e-3, 5e-3)
speed, heading = rng.uniform(100, 200, n_targets), rng.uniform(-np.pi, np.pi, n_targets)
states = np.column_stack([
    rng.uniform(0, max(20e3 * (n_sensors - 1), area), n_targets), rng.uniform(1e3, max(16e3, area), n_targets),
    np.full(n_targets, 1e3), speed * np.cos(heading), speed * np.sin(heading), np.zeros(n_targets),
])
targets = [ConstantVelocityTarget(s, t0=0.0) for s in states]
times = [5.0 * j + 15.0 * np.arange(8) for j in range(n_sensors)]
scenario = simulate(sensors, targets, times, clutter_per_scan=2 * n_targets, azimuth_window=(0, np.pi),
                    elevation_window=(0, np.pi / 2), t0=0.0, seed=seed)
start = time.perf_counter()
options = {"max_candidates": max_candidates} if max_candidates else {}
if gate_pd is not None:  # only when given, so builds without the option run the same case
    options["gate_pd"] = gate_pd
if search_stage != "default":  # likewise
    options["search_stage"] = None if search_stage == "none" else int(search_stage)
if order != "default":  # likewise
    options["detection_order"] = order
if formation != "default":  # likewise
    options["candidates"] = formation
if no_sweep:  # likewise
    options["sweep"] = False
if adjacent:  # candidates from neighbouring sensors only (j, j + 1)
    options["pairs"] = [(j, j + 1) for j in range(n_sensors - 1)]
result = pa.FuzzyTrackInitiator(v_max=v_max, **options).initiate(scenario.measurements, sensors, t0=0.0)
seconds = time.perf_counter() - start
held = track_targets(result.labels, scenario.measurements.truth)
found = set(held.tolist()) - {-1}
closeness = np.array([t.closeness for t in result.tracks])
r_range = lambda r: [float(r.min()), float(r.max())] if len(r) else None
print(json.dumps({
    "closeness_held": r_range(closeness[held >= 0]), "closeness_other": r_range(closeness[held < 0]),
    "first_eight_held": int(np.sum(held[:8] >= 0)),
    "rows": len(scenario.measurements), "seconds": seconds, "tracks": len(result.tracks), "found": len(found),
    "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    "stages": result.diagnostics.stage_seconds, "counts": result.diagnostics.stage_counts,
}))
"""


def run_case(
    n_targets: int,
    n_sensors: int,
    seed: int,
    cap: float,
    area: float = 0.0,
    v_max: float = 500.0,
    max_candidates: int = 0,
    gate_pd: float | None = None,
    search_stage: str = "default",
    pairs: str = "all",
    order: str = "default",
    formation: str = "default",
    sweep: bool = True,
) -> dict[str, Any] | str | None:
    """The case's figures; its error's last line and how long the refusal took when it fails;
    None past the cap."""
    start = time.perf_counter()
    try:
        out = subprocess.run(
            [
                sys.executable,
                "-c",
                CASE,
                *map(str, (n_targets, n_sensors, seed, area, v_max, max_candidates, gate_pd)),
                *(search_stage, pairs, order, formation, "sweep" if sweep else "nosweep"),
            ],
            capture_output=True,
            text=True,
            timeout=cap,
            check=True,
        )
    except subprocess.TimeoutExpired:
        return None
    except subprocess.CalledProcessError as err:
        return f"after {time.perf_counter() - start:.2f} s (process included): {err.stderr.strip().splitlines()[-1]}"
    figures: dict[str, Any] = json.loads(out.stdout.strip().splitlines()[-1])
    return figures


def seconds(value: float) -> str:
    """Three significant digits, or whole seconds from 1 000 on (``3.3e+03`` hid a minute)."""
    return f"{value:.0f}" if value >= 1000 else f"{value:.3g}"


def r_text(r: list[float] | None) -> str:
    """A closeness range as printed."""
    return "none" if r is None else f"{r[0]:.3f}-{r[1]:.3f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--targets", type=int, nargs="+", default=[4, 8, 16, 32])
    parser.add_argument("--sensors", type=int, nargs="+", default=[2, 3])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--cap", type=float, default=120.0, help="seconds per case before giving up")
    parser.add_argument("--area-km", type=float, default=0.0, help="spread targets over this square instead (km)")
    parser.add_argument("--v-max", type=float, default=500.0, help="the initiator's v_max (m/s); default its default")
    parser.add_argument("--max-candidates", type=int, default=0, help="the initiator's max_candidates (0: its default)")
    parser.add_argument("--gate-pd", type=float, default=None, help="the initiator's gate_pd (default: not priced)")
    parser.add_argument(
        "--adjacent-pairs", action="store_true", help="candidates from neighbouring sensors only (default: every pair)"
    )
    parser.add_argument(
        "--search-stage",
        default="default",
        help="the initiator's search_stage: an integer or 'none' (default: its default)",
    )
    parser.add_argument(
        "--detection-order", default="default", help="the initiator's detection_order (default: its default)"
    )
    parser.add_argument(
        "--candidates", default="default", help="the initiator's candidates (formation; default: its default)"
    )
    parser.add_argument("--no-sweep", action="store_true", help="sweep=False: the rounds formation without its sweep")
    args = parser.parse_args()
    print(
        "| sensors | targets | rows | time s | peak MB | tracks | targets found | candidates fitted | supported | "
        "searched | time in candidates / fit / support gate / search / detection |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    ranges = []  # each case's figures, for the closeness lines after the table
    for n_sensors in args.sensors:
        for n_targets in args.targets:
            case = run_case(
                n_targets,
                n_sensors,
                args.seed,
                args.cap,
                args.area_km,
                args.v_max,
                args.max_candidates,
                args.gate_pd,
                args.search_stage,
                "adjacent" if args.adjacent_pairs else "all",
                args.detection_order,
                args.candidates,
                not args.no_sweep,
            )
            if case is None or isinstance(case, str):
                what = f"> {args.cap:g}" if case is None else f"refused: {case}"
                print(f"| {n_sensors} | {n_targets} | | {what} | | | | | | | |")
                continue
            st, c = case["stages"], case["counts"]
            shares = " / ".join(
                f"{100 * st.get(k, 0.0) / case['seconds']:.0f} %" if case["seconds"] > 0 else "-"
                for k in ("candidates", "fit", "support", "descent", "detection")
            )
            print(
                f"| {n_sensors} | {n_targets} | {case['rows']} | {seconds(case['seconds'])} | {case['peak_mb']:.0f} | "
                f"{case['tracks']} | {case['found']}/{n_targets} | {c['fitted']} | {c['supported']} | "
                f"{c['optima']} | {shares} |"
            )
            sys.stdout.flush()
            ranges.append((f"{n_sensors} x {n_targets}", case))
    for name, case in ranges:  # tracks are in the order detection accepted them
        print(
            f"{name}: R of the tracks holding a target {r_text(case.get('closeness_held'))}, of the others "
            f"{r_text(case.get('closeness_other'))}; of the first 8 accepted, {case.get('first_eight_held')} hold one"
        )


if __name__ == "__main__":
    main()
