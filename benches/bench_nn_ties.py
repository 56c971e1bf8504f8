"""How often the wavelet reproduction's nearest-neighbour pairing has another optimum of
exactly the same distance (docs/experiments.md, wavelet): per scan, the pairs of
``NearestNeighbourAssociator`` against SciPy's ``linear_sum_assignment`` on the same gated
distance matrix (the most pairs, then the least total distance), 100 runs of the paper
scenario without false tracks. On 1-D positions crossing matchings often tie.

    python3 benches/bench_nn_ties.py [--runs 100]
"""

from __future__ import annotations

import argparse

import numpy as np
import passive_assoc as pa
from passive_assoc.experiments import wavelet_runs as experiment
from passive_assoc.experiments.common import run_seeds
from passive_assoc.radar_esm import filter_reports, position_gate_pairs
from passive_assoc.simulation.radar_esm import paper_wavelet_scenario
from passive_assoc.track_association import TrackPairs
from scipy.optimize import linear_sum_assignment


def by_scan(pairs: TrackPairs, time: float) -> dict[tuple[int, int], float]:
    """The (local, system) pairs of one scan with their scores (minus distances)."""
    at = pairs.time == time
    keys = zip(pairs.local_track[at].tolist(), pairs.system_track[at].tolist(), strict=True)
    return dict(zip(keys, pairs.score[at].tolist(), strict=True))


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--runs", type=int, default=100)
    args = parser.parse_args()
    counts = {"scans": 0, "other pairs, same distance": 0, "ours costlier": 0, "ours cheaper": 0}
    for seed in run_seeds(1, args.runs):
        scenario = paper_wavelet_scenario(np.random.default_rng(seed), n_clutter=0)
        tracks = filter_reports(scenario.measurements, experiment.PROCESS_NOISE, n_threads=1)
        radar, esm = tracks.of(0), tracks.of(1)
        result = pa.NearestNeighbourAssociator(n_threads=1).associate(local=esm, system=radar)
        gated = position_gate_pairs(local=esm, system=radar, gate_probability=0.99)
        for time in np.unique(gated.time):
            allowed = by_scan(gated, float(time))
            local = sorted({a for a, _ in allowed})
            system = sorted({b for _, b in allowed})
            distance = {key: -score for key, score in allowed.items()}
            forbidden = 1.0 + 2.0 * sum(distance.values())
            costs = np.full((len(local), len(system)), forbidden)
            for (a, b), d in distance.items():
                costs[local.index(a), system.index(b)] = d
            rows, cols = linear_sum_assignment(costs)
            theirs = {(local[r], system[c]) for r, c in zip(rows, cols, strict=True) if costs[r, c] < forbidden}
            mine = set(by_scan(result.pairs, float(time)))
            counts["scans"] += 1
            if mine != theirs:
                difference = sum(distance[p] for p in mine) - sum(distance[p] for p in theirs)
                if len(mine) == len(theirs) and abs(difference) <= 1e-9 * max(1.0, sum(distance.values())):
                    counts["other pairs, same distance"] += 1
                else:
                    counts["ours costlier" if difference > 0 else "ours cheaper"] += 1
    print(counts)


if __name__ == "__main__":
    main()
