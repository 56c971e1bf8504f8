"""How often the wavelet reproduction's nearest-neighbour assignments have another optimum of
exactly the same distance (docs/experiments.md, wavelet): per scan, our assignment against
SciPy's on the same gated matrix, 100 runs of the paper scenario without false tracks.

    python3 benches/bench_nn_ties.py [--runs 100]
"""

from __future__ import annotations

import argparse
from unittest import mock

import numpy as np
import passive_assoc.radar_esm.decision as decision
from passive_assoc.assignment import linear_assignment
from passive_assoc.experiments import wavelet_runs as experiment
from passive_assoc.experiments.common import run_seeds
from passive_assoc.radar_esm import NearestNeighbourTrackAssociator, filter_reports
from passive_assoc.simulation.radar_esm import paper_wavelet_scenario
from scipy.optimize import linear_sum_assignment


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=100)
    args = parser.parse_args()
    counts = {"assignments": 0, "other pairs, same distance": 0, "ours costlier": 0, "ours cheaper": 0}

    def compare(costs: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        rows, cols, total = linear_assignment(costs)
        r, c = linear_sum_assignment(costs)
        forbidden = costs.max()
        mine = {(a, b) for a, b in zip(rows, cols, strict=True) if costs[a, b] < forbidden}
        theirs = {(a, b) for a, b in zip(r, c, strict=True) if costs[a, b] < forbidden}
        counts["assignments"] += 1
        if mine != theirs:
            # Same distance to rounding: the sums add the same kind of terms in another order.
            difference = sum(costs[a, b] for a, b in mine) - sum(costs[a, b] for a, b in theirs)
            if abs(difference) <= 1e-9 * max(1.0, float(costs[costs < forbidden].sum())):
                counts["other pairs, same distance"] += 1
            else:
                counts["ours costlier" if difference > 0 else "ours cheaper"] += 1
        return rows, cols, total

    # The associator looks linear_assignment up in the decision module, so it calls compare.
    with mock.patch.object(decision, "linear_assignment", compare):
        for seed in run_seeds(1, args.runs):
            scenario = paper_wavelet_scenario(np.random.default_rng(seed), n_clutter=0)
            tracks = filter_reports(scenario.measurements, experiment.PROCESS_NOISE, n_threads=1)
            NearestNeighbourTrackAssociator().associate(local=tracks.of(1), system=tracks.of(0))
    print(counts)


if __name__ == "__main__":
    main()
