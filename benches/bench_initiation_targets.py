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

Other 2-D scenes, run only when named (``--scenes``), for the formations' comparison beyond
the targets: ``2d_10`` (10 targets), ``2d_8_4s`` and ``2d_8_5s`` (8 targets, Pd 0.9, 4 and 5
sensors), ``2d_8_async`` (the same, 3 sensors scanning 3 s apart: ``offset=3.0``),
``2d_8_pd08`` (Pd 0.8) and ``2d_5_pd07`` (5 targets, Pd 0.7), all of
`bearing_only_2d_scenario`; and two sensors of the ring, ``2x20``, ``2x50`` and ``2x100``
(`ring_scenario(seed, n_sensors=2, n_targets=N)`).

A target is found when a track holds it (`track_targets`, 2/3 of the track's rows); a false
track holds no target. Each scene runs in a process of its own (peak RSS is that process's),
one initiation at a time on every core.

    python3 benches/bench_initiation_targets.py                      # every scene, default seeds
    python3 benches/bench_initiation_targets.py --scenes 5x100 --seeds 5
    python3 benches/bench_initiation_targets.py --scenes 2d_8 --options '{"candidates": "paper"}'
    python3 benches/bench_initiation_targets.py --scenes 3x20 --then-paper   # a second pass, below

With ``--then-paper`` each scene is initiated a second time, with the paper's formation
(`candidates="paper"`) on the rows the first initiation left as clutter; a target counts as
found when either holds it, and the second pass's time is reported on its own.
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

#: Scenes run only when named → default number of seeds.
OTHER_SCENES = {
    "2d_10": 5,
    "2d_8_4s": 6,
    "2d_8_5s": 6,
    "2d_8_async": 8,
    "2d_8_pd08": 10,
    "2d_5_pd07": 10,
    "paper4_pd1": 10,
    "2x20": 20,
    "2x50": 12,
    "2x100": 2,
}

CASE = r"""
import json, resource, statistics, sys, time, warnings
import numpy as np
import passive_assoc as pa
from passive_assoc.evaluation import track_targets

name, seeds, options = sys.argv[1], int(sys.argv[2]), json.loads(sys.argv[3])
then_paper = sys.argv[4] == "1"

def scene(seed):
    if name == "2d_3x20":
        return pa.bearing_only_2d_scenario(seed, n_targets=20, clutter_ratio=4.0, pd=0.9)
    if name == "2d_6":
        return pa.bearing_only_2d_scenario(seed, n_targets=6, clutter_ratio=4.0)
    if name == "2d_8":
        return pa.bearing_only_2d_scenario(seed, n_targets=8, pd=0.9)
    if name == "paper4":
        return pa.paper_fti_scenario(seed, n_scans=4, pd=0.9)
    if name == "paper4_pd1":
        return pa.paper_fti_scenario(seed, n_scans=4)
    other = {
        "2d_10": dict(n_targets=10),
        "2d_8_4s": dict(n_targets=8, n_sensors=4, pd=0.9),
        "2d_8_5s": dict(n_targets=8, n_sensors=5, pd=0.9),
        "2d_8_async": dict(n_targets=8, pd=0.9, offset=3.0),
        "2d_8_pd08": dict(n_targets=8, pd=0.8),
        "2d_5_pd07": dict(n_targets=5, pd=0.7),
    }
    if name in other:
        return pa.bearing_only_2d_scenario(seed, **other[name])
    s, n = (int(v) for v in name.split("x"))
    return pa.ring_scenario(seed, n_sensors=s, n_targets=n)

found = targets = false = limited = 0
seconds, second, formations = [], [], set()
for seed in range(seeds):
    sc = scene(seed)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pa.LimitWarning)
        r = pa.FuzzyTrackInitiator(**options).initiate(sc.measurements, sc.sensors, t0=sc.t0, progress=False)
    seconds.append(time.perf_counter() - start)
    held = track_targets(r.labels, sc.measurements.truth)
    held_set = set(held.tolist()) - {-1}
    if then_paper:
        rest = sc.measurements.select(np.flatnonzero(r.labels < 0))
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", pa.LimitWarning)
            r2 = pa.FuzzyTrackInitiator(**{**options, "candidates": "paper"}).initiate(
                rest, sc.sensors, t0=sc.t0, progress=False)
        second.append(time.perf_counter() - start)
        held2 = track_targets(r2.labels, rest.truth)
        held_set |= set(held2.tolist()) - {-1}
        false += int(np.sum(held2 < 0))
    found += len(held_set)
    targets += len(sc.targets)
    false += int(np.sum(held < 0))
    limited += r.termination == "candidate_limit"
    formations.add(r.diagnostics.candidates)
print(json.dumps({
    "scene": name, "seeds": seeds, "found": found, "targets": targets, "false": false,
    "limited": limited, "median_s": statistics.median(seconds), "max_s": max(seconds),
    "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    "second_median_s": statistics.median(second) if second else None,
    "candidates": sorted(formations),
}))
"""


def run(name: str, seeds: int, options: dict[str, Any], then_paper: bool) -> dict[str, Any]:
    out = subprocess.run(
        [sys.executable, "-c", CASE, name, str(seeds), json.dumps(options), "1" if then_paper else "0"],
        capture_output=True,
        text=True,
        check=True,
    )
    result: dict[str, Any] = json.loads(out.stdout.strip().splitlines()[-1])
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenes", nargs="+", choices=sorted(SCENES | OTHER_SCENES), default=list(SCENES))
    parser.add_argument("--seeds", type=int, nargs="+", help="seeds per scene, one or one a scene (default: its own)")
    parser.add_argument("--then-paper", action="store_true", help="a second pass (module doc)")
    parser.add_argument("--options", default="{}", help="FuzzyTrackInitiator keywords as JSON")
    parser.add_argument("--json", metavar="FILE", help="also write the rows as JSON")
    args = parser.parse_args()
    options = json.loads(args.options)
    rows = []
    print(
        "| scene | seeds | formation | found | false tracks / scene | limit reached | median s | max s | peak RSS MB |"
    )
    print("|---" * 9 + "|")
    if args.seeds and len(args.seeds) not in (1, len(args.scenes)):
        parser.error("--seeds: give one count, or one per scene")
    for k, name in enumerate(args.scenes):
        seeds = (SCENES | OTHER_SCENES)[name] if not args.seeds else args.seeds[k if len(args.seeds) > 1 else 0]
        r = run(name, seeds, options, args.then_paper)
        rows.append(r)
        print(
            f"| {name} | {r['seeds']} | {'/'.join(r['candidates'])} | {r['found']}/{r['targets']} "
            f"({100 * r['found'] / r['targets']:.1f} %) | {r['false'] / r['seeds']:.2f} | "
            f"{r['limited']} | {r['median_s']:.3f} | {r['max_s']:.3f} | {r['peak_rss_mb']:.0f} |"
            + (f" second pass median {r['second_median_s']:.3f} s" if args.then_paper else ""),
            flush=True,
        )
    if args.json:
        with open(args.json, "x", encoding="utf-8") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
