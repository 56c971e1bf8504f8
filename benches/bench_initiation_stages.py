"""Where one initiation's time goes: ``diagnostics.stage_seconds`` of
``FuzzyTrackInitiator(n_threads=T)`` on ``ring_scenario(seed, n_sensors=S, n_targets=N)``, for
each thread count, with the whole call's wall time (docs/performance.md, *Initiation at
scale*). With ``--threads 1 --seeds 0 --repeat 1`` it is the single initiation that the
instruction counts in CHANGELOG.md were taken on:

    valgrind --tool=callgrind python3 benches/bench_initiation_stages.py --threads 1 --seeds 0 --repeat 1

(``python3`` must be the interpreter itself, as in an active virtual environment: valgrind
follows no child process, so through a shell-script shim such as pyenv's it profiles only the
shell and writes an empty profile.)

    python3 benches/bench_initiation_stages.py [--sensors 5] [--targets 100] [--seeds 0] [--threads 1 2] [--repeat 2]
    python3 benches/bench_initiation_stages.py --options '{"untangle": false}'   # FuzzyTrackInitiator keywords
"""

from __future__ import annotations

import argparse
import json
import time

import passive_assoc as pa


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sensors", type=int, default=5)
    parser.add_argument("--targets", type=int, default=100)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--repeat", type=int, default=2, help="runs of each seed and thread count")
    parser.add_argument("--options", default="{}", help="FuzzyTrackInitiator keywords as JSON")
    args = parser.parse_args()
    options = json.loads(args.options)
    header = False
    for seed in args.seeds:
        sc = pa.ring_scenario(seed, n_sensors=args.sensors, n_targets=args.targets)
        for run in range(args.repeat):
            for threads in args.threads:
                start = time.perf_counter()
                r = pa.FuzzyTrackInitiator(n_threads=threads, **options).initiate(
                    sc.measurements, sc.sensors, t0=sc.t0, progress=False
                )
                call = time.perf_counter() - start
                stages = r.diagnostics.stage_seconds
                if not header:
                    print("| seed | threads | run | call s | " + " | ".join(f"{k} s" for k in stages) + " |")
                    print("|---" * (4 + len(stages)) + "|")
                    header = True
                cells = " | ".join(f"{v:.3f}" for v in stages.values())
                print(f"| {seed} | {threads} | {run + 1} | {call:.3f} | {cells} |")


if __name__ == "__main__":
    main()
