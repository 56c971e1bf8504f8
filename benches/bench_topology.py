"""The whole topology paper scenario (EXPERIMENTS ``topology``: 8 radars, 20 targets, 90 scans
of 10 s) per run, split into its stages, on one thread: the local trackers (the EKF over every
radar's reports), the topology association of 7 local radars with the system radar, and the
nearest-neighbour baseline on the same tracks. The simulation itself is timed apart.

    python benches/bench_topology.py [--runs 5] [--bias 5]

Prints the median seconds of each stage over the runs.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import passive_assoc as pa
from passive_assoc.experiments.topology import SYSTEM_RADAR
from passive_assoc.experiments.topology_tracks import local_tracks
from passive_assoc.simulation.topology import paper_topology_scenario


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--bias", type=float, default=5.0)
    args = parser.parse_args()
    stages: dict[str, list[float]] = {"simulate": [], "kalman": [], "topology": [], "nearest": []}
    for run in range(args.runs):
        rng = np.random.default_rng(run)
        t = time.perf_counter()
        scenario = paper_topology_scenario(rng, bias_deg=args.bias)
        stages["simulate"].append(time.perf_counter() - t)
        t = time.perf_counter()
        tracks = local_tracks(scenario, rng)
        stages["kalman"].append(time.perf_counter() - t)
        system = tracks.of(SYSTEM_RADAR)
        local = tracks.select(np.flatnonzero(tracks.source != SYSTEM_RADAR))
        for name, method in (
            ("topology", pa.TopologyAssociator(n_threads=1)),
            ("nearest", pa.NearestNeighbourAssociator(n_threads=1)),
        ):
            t = time.perf_counter()
            method.associate(local=local, system=system)
            stages[name].append(time.perf_counter() - t)
    print(f"topology paper scenario, {args.runs} runs, bias ±{args.bias:g}°, median seconds per run:")
    for name, values in stages.items():
        print(f"  {name:>9}: {np.median(values):.4f}")
    whole = np.median(np.sum([stages[k] for k in ("kalman", "topology")], axis=0))
    print(f"  kalman + topology: {whole:.4f}")


if __name__ == "__main__":
    main()
