"""How one initiation's time grows with the number of targets, for 3, 4 and 5 sensors, and
where the time goes: `ring_scenario` (3-D sensors on a ring, targets in a box, Pd 0.9,
clutter 2 N a sensor scan, 8 scans) with the defaults of `FuzzyTrackInitiator` (the rounds
formation). The box grows with √N (``--density``, the default: the targets' density stays the
paper scale's) or stays 40 × 40 km (``--fixed-box``: denser with N). The exponent is the slope
of log median time against log N between the smallest and largest N of at least 20, by least
squares, and the same up to 100 targets; *limit reached* counts the seeds whose formation
stopped at `max_candidates`, and each such run's message (its seconds, scan slots and cost
a candidate) follows the table.

    python3 benches/bench_initiation_scaling.py                       # 10 -> 200 targets, 3/4/5 sensors
    python3 benches/bench_initiation_scaling.py --sensors 5 --targets 20 50 100 200 --seeds 3
    python3 benches/bench_initiation_scaling.py --fixed-box
    python3 benches/bench_initiation_scaling.py --fixed-box --seeds 1 --targets 200 \
        --options '{"max_candidates": 2000000}'                        # FuzzyTrackInitiator keywords
    python3 benches/bench_initiation_scaling.py --targets 50 100 --options '{"regroup": true}'   # + a column
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import sys
from typing import Any

import numpy as np

#: The columns of where the time goes.
STAGES = ("candidates", "fit", "support", "descent", "final", "other")

CASE = r"""
import json, resource, statistics, sys, time, warnings
import numpy as np
import passive_assoc as pa
from passive_assoc.evaluation import track_targets

s, n, seeds, half = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
options = json.loads(sys.argv[5])
rows = []
for seed in range(seeds):
    sc = pa.ring_scenario(seed, n_sensors=s, n_targets=n, half_width=half, radius=1.5 * half)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pa.LimitWarning)
        r = pa.FuzzyTrackInitiator(**options).initiate(sc.measurements, sc.sensors, t0=sc.t0, progress=False)
    seconds = time.perf_counter() - start
    held = track_targets(r.labels, sc.measurements.truth)
    rows.append({
        "seconds": seconds, "found": len(set(held.tolist()) - {-1}), "false": int(np.sum(held < 0)),
        "stages": r.diagnostics.stage_seconds, "fitted": r.diagnostics.stage_counts.get("fitted", 0),
        "limit": r.termination == "candidate_limit", "message": r.message,
    })
print(json.dumps({"rows": rows, "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def run(
    sensors: int, targets: int, seeds: int, half_width: float, cap: float, options: dict[str, Any]
) -> dict[str, Any] | None:
    """The case's figures with `FuzzyTrackInitiator(**options)`, or None past `cap` seconds."""
    try:
        out = subprocess.run(
            [sys.executable, "-c", CASE, str(sensors), str(targets), str(seeds), str(half_width), json.dumps(options)],
            capture_output=True,
            text=True,
            check=True,
            timeout=cap,
        )
    except subprocess.TimeoutExpired:
        return None
    result: dict[str, Any] = json.loads(out.stdout.strip().splitlines()[-1])
    return result


def exponent(ns: list[int], seconds: list[float], up_to: float = math.inf) -> float:
    """Least-squares slope of log time against log N over 20 <= N <= `up_to`."""
    points = [(math.log(n), math.log(t)) for n, t in zip(ns, seconds, strict=True) if 20 <= n <= up_to and t > 0]
    if len(points) < 2:
        return float("nan")
    x, y = np.array(points).T
    return float(np.polyfit(x, y, 1)[0])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sensors", type=int, nargs="+", default=[3, 4, 5])
    parser.add_argument("--targets", type=int, nargs="+", default=[10, 20, 50, 100, 200])
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--cap", type=float, default=600.0, help="seconds per case (all its seeds) before giving up")
    parser.add_argument("--fixed-box", action="store_true", help="keep the 40 x 40 km box at every N")
    parser.add_argument("--options", default="{}", help="FuzzyTrackInitiator keywords as JSON")
    args = parser.parse_args()
    options = json.loads(args.options)
    # With regrouping on, its seconds get a column of their own (before *other*).
    stages = (*STAGES[:-1], "regroup", "other") if options.get("regroup") else STAGES
    print(
        "| sensors | targets | box km | found | false / scene | median s | candidates s | fit s | support s "
        "| descent s | final fit s | "
        + ("regroup s | " if "regroup" in stages else "")
        + "other s | fitted | limit reached | peak RSS MB |"
    )
    print("|---" * (9 + len(stages)) + "|")
    reached = []  # the limit's messages, printed after the table
    for s in args.sensors:
        ns, medians = [], []
        for n in args.targets:
            half = 20e3 if args.fixed_box else 20e3 * math.sqrt(n / 20)
            r = run(s, n, args.seeds, half, args.cap, options)
            if r is None:
                print(
                    f"| {s} | {n} | {2 * half / 1e3:.0f} | over {args.cap:g} s |" + " |" * (5 + len(stages)), flush=True
                )
                break
            rows = r["rows"]
            reached += [f"{s} x {n}, seed {seed}: {x['message']}" for seed, x in enumerate(rows) if x["limit"]]
            med = statistics.median(x["seconds"] for x in rows)
            ns.append(n)
            medians.append(med)
            stage = {k: statistics.median(x["stages"][k] for x in rows) for k in rows[0]["stages"]}
            # Setup, the classifications between passes, the score and building the result
            # (detection is timed in its own stage, which the table leaves out).
            stage["other"] = statistics.median(x["seconds"] - sum(x["stages"].values()) for x in rows)
            print(
                f"| {s} | {n} | {2 * half / 1e3:.0f} | {sum(x['found'] for x in rows)}/{n * len(rows)} | "
                f"{sum(x['false'] for x in rows) / len(rows):.2f} | {med:.3f} | "
                + " | ".join(f"{stage.get(k, 0.0):.3f}" for k in stages)
                + f" | {statistics.median(x['fitted'] for x in rows):.0f}"
                + f" | {sum(x['limit'] for x in rows)}/{len(rows)} | {r['peak_rss_mb']:.0f} |",
                flush=True,
            )
        print(
            f"<!-- {s} sensors: time ~ N^{exponent(ns, medians):.2f} over N >= 20, "
            f"N^{exponent(ns, medians, 100):.2f} over 20 <= N <= 100 -->",
            flush=True,
        )

    for line in reached:
        print(f"\nlimit reached, {line}")


if __name__ == "__main__":
    main()
