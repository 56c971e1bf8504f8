"""Where a run of ``passive-assoc reproduce wavelet`` spends its CPU: per run, the scenario, the
two sensors' Kalman filters, each associator and the scoring, on one thread, over 100 runs of
the paper scenario with 2 false tracks per sensor (docs/experiments.md, wavelet).

    python3 benches/bench_wavelet_steps.py [--runs 100] [--clutter 2]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from passive_assoc.experiments import wavelet_runs as experiment
from passive_assoc.experiments.common import run_seeds
from passive_assoc.radar_esm import filter_reports
from passive_assoc.simulation.radar_esm import paper_wavelet_scenario


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=100)
    parser.add_argument("--clutter", type=int, default=2)
    args = parser.parse_args()
    totals: dict[str, float] = {}

    def timed(step: str, start: float) -> float:
        now = time.perf_counter()
        totals[step] = totals.get(step, 0.0) + now - start
        return now

    methods = experiment.methods(experiment.Settings())
    for seed in run_seeds(1, args.runs):
        start = time.perf_counter()
        scenario = paper_wavelet_scenario(np.random.default_rng(seed), n_clutter=args.clutter)
        start = timed("scenario", start)
        tracks = filter_reports(scenario.measurements, experiment.PROCESS_NOISE, n_threads=1)
        radar, esm = tracks.of(0), tracks.of(1)
        start = timed("Kalman filters", start)
        for name, method in methods.items():
            result = method.associate(local=esm, system=radar)
            start = timed(experiment.METHODS[name], start)
            experiment.score(result, radar, esm, scenario.scan_times)
            start = timed("scoring", start)
    print(f"CPU per run over {args.runs} runs, {args.clutter} false tracks per sensor, one thread:")
    for step, seconds in totals.items():
        print(f"  {step:<16} {seconds / args.runs * 1e3:6.2f} ms")


if __name__ == "__main__":
    main()
