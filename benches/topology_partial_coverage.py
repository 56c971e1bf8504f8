"""What limits the topology method in partial coverage (EXPERIMENTS ``topology``): how many
local tracks have no partner in the system picture (a target radar 0 does not see), and how
many of those the topology associator pairs anyway (each one a false positive).

    python benches/topology_partial_coverage.py [--runs 10] [--seed 1]
"""

from __future__ import annotations

import argparse

import numpy as np
from passive_assoc.experiments.topology import SYSTEM_RADAR
from passive_assoc.experiments.topology_tracks import local_tracks
from passive_assoc.simulation.topology import paper_topology_scenario
from passive_assoc.topology import TopologyAssociator


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    for coverage in ("full", "partial"):
        rows = 0
        orphans = 0
        paired_orphans = 0
        for run in range(args.runs):
            rng = np.random.default_rng([args.seed, run])
            scenario = paper_topology_scenario(rng, bias_deg=5.0, coverage=coverage)
            tracks = local_tracks(scenario, rng)
            system = tracks.of(SYSTEM_RADAR)
            local = tracks.select(np.flatnonzero(tracks.source != SYSTEM_RADAR))
            result = TopologyAssociator(n_threads=1).associate(local=local, system=system)
            assert system.truth is not None and local.truth is not None  # simulated tracks carry it
            seen = {(float(t), int(g)) for t, g in zip(system.time, system.truth, strict=True)}
            truth = {
                (float(t), int(s), int(k)): int(g)
                for t, s, k, g in zip(local.time, local.source, local.track, local.truth, strict=True)
            }
            start = float(scenario.scan_times[5])
            orphan = {key for key, g in truth.items() if key[0] >= start and (key[0], g) not in seen}
            rows += sum(1 for key in truth if key[0] >= start)
            orphans += len(orphan)
            p = result.pairs
            paired_orphans += sum(
                (float(t), int(s), int(k)) in orphan for t, s, k in zip(p.time, p.source, p.local_track, strict=True)
            )
        print(
            f"{coverage:>8}: {100 * orphans / rows:.1f} % of local tracks have no system partner;"
            f" topology pairs {100 * paired_orphans / max(orphans, 1):.1f} % of them ({args.runs} runs at ±5°)"
        )


if __name__ == "__main__":
    main()
