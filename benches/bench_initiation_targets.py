"""Fuzzy track initiation with its defaults on the scenes of the initiation-at-scale targets:
targets found, false tracks a scene, time of one initiation and peak memory.

Scenes (all with `FuzzyTrackInitiator()` defaults, clutter as stated, t0 = the scene's):
- ``ring SxN``: `ring_scenario(seed, n_sensors=S, n_targets=N)`: 3-D sensors on a 30 km ring
  (not colinear, 0-500 m high), targets in a 40 × 40 × 9.5 km box, σ 3-5 mrad, 8 scans of
  15 s on asynchronous clocks, Pd 0.9, clutter 2 N rays per sensor scan over the whole sky;
- ``2d_3x20``: `bearing_only_2d_scenario(seed, n_targets=20, clutter_ratio=4, pd=0.9)`;
- ``2d_6``: `bearing_only_2d_scenario(seed, n_targets=6, clutter_ratio=4)`;
- ``2d_8``: `bearing_only_2d_scenario(seed, n_targets=8, pd=0.9)`;
- ``paper4``: `paper_fti_scenario(seed, n_scans=4, pd=0.9)` (2 sensors, 3-D, 4 scans).

A target is found when a track holds it (`track_targets`, 2/3 of the track's rows); a false
track holds no target. Each scene runs in a process of its own (peak RSS is that process's),
one initiation at a time on every core.

    python3 benches/bench_initiation_targets.py                      # every scene, default seeds
    python3 benches/bench_initiation_targets.py --scenes 5x100 --seeds 5
    python3 benches/bench_initiation_targets.py --scenes 2d_8 --options '{"candidates": "paper"}'
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from typing import Any

#: Scene name → default number of seeds.
SCENES = {
    "5x100": 5,
    "4x50": 10,
    "3x20": 30,
    "2d_3x20": 5,
    "2d_6": 30,
    "2d_8": 50,
    "paper4": 100,
}

CASE = r"""
import json, resource, statistics, sys, time, warnings
import numpy as np
import passive_assoc as pa
from passive_assoc.evaluation import track_targets

name, seeds, options = sys.argv[1], int(sys.argv[2]), json.loads(sys.argv[3])

def scene(seed):
    if name == "2d_3x20":
        return pa.bearing_only_2d_scenario(seed, n_targets=20, clutter_ratio=4.0, pd=0.9)
    if name == "2d_6":
        return pa.bearing_only_2d_scenario(seed, n_targets=6, clutter_ratio=4.0)
    if name == "2d_8":
        return pa.bearing_only_2d_scenario(seed, n_targets=8, pd=0.9)
    if name == "paper4":
        return pa.paper_fti_scenario(seed, n_scans=4, pd=0.9)
    s, n = (int(v) for v in name.split("x"))
    return pa.ring_scenario(seed, n_sensors=s, n_targets=n)

found = targets = false = limited = 0
seconds, formations = [], set()
for seed in range(seeds):
    sc = scene(seed)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pa.LimitWarning)
        r = pa.FuzzyTrackInitiator(**options).initiate(sc.measurements, sc.sensors, t0=sc.t0, progress=False)
    seconds.append(time.perf_counter() - start)
    held = track_targets(r.labels, sc.measurements.truth)
    found += len(set(held.tolist()) - {-1})
    targets += len(sc.targets)
    false += int(np.sum(held < 0))
    limited += r.termination == "candidate_limit"
    formations.add(r.diagnostics.candidates)
print(json.dumps({
    "scene": name, "seeds": seeds, "found": found, "targets": targets, "false": false,
    "limited": limited, "median_s": statistics.median(seconds), "max_s": max(seconds),
    "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    "candidates": sorted(formations),
}))
"""


def run(name: str, seeds: int, options: dict[str, Any]) -> dict[str, Any]:
    out = subprocess.run(
        [sys.executable, "-c", CASE, name, str(seeds), json.dumps(options)],
        capture_output=True,
        text=True,
        check=True,
    )
    result: dict[str, Any] = json.loads(out.stdout.strip().splitlines()[-1])
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenes", nargs="+", choices=sorted(SCENES), default=list(SCENES))
    parser.add_argument("--seeds", type=int, help="seeds per scene (default: the scene's own)")
    parser.add_argument("--options", default="{}", help="FuzzyTrackInitiator keywords as JSON")
    parser.add_argument("--json", metavar="FILE", help="also write the rows as JSON")
    args = parser.parse_args()
    options = json.loads(args.options)
    rows = []
    print(
        "| scene | seeds | formation | found | false tracks / scene | limit reached | median s | max s | peak RSS MB |"
    )
    print("|---" * 9 + "|")
    for name in args.scenes:
        r = run(name, args.seeds or SCENES[name], options)
        rows.append(r)
        print(
            f"| {name} | {r['seeds']} | {'/'.join(r['candidates'])} | {r['found']}/{r['targets']} "
            f"({100 * r['found'] / r['targets']:.1f} %) | {r['false'] / r['seeds']:.2f} | "
            f"{r['limited']} | {r['median_s']:.3f} | {r['max_s']:.3f} | {r['peak_rss_mb']:.0f} |",
            flush=True,
        )
    if args.json:
        with open(args.json, "x", encoding="utf-8") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
