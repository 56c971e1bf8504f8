"""The Lagrangian solver's sensor orders and end-of-solve polish against SciPy's LP bound.

On the `reproduce intensity` scans (EXPERIMENTS.md geometry, S = 3, R = 15), the same
enumerated candidates go to ``assign_sd(..., sensor_order="auto")`` (relax the sensor with the
most reports) and ``"given"`` (relax sensor 3), both with ``polish=False`` (the configuration of
docs/performance.md's sensor-order table), interleaved, best of the repeats per scan. The
dual of either relaxation converges to the optimum of the LP relaxation, which
``scipy.optimize.linprog`` (HiGHS) computes exactly; so "dual below LP" measures how far the
subgradient ascent got, and "primal above LP" bounds the primal's distance from the optimum
(the optimum lies between the LP bound and every primal). Where sensor 3 already has the most
reports the two orders are the same problem; "reordered" counts the scans where they differ,
and the ratio column is over those only. Printed per M, over the scans: the median time of
each order, the median of the per-scan ratios auto / given, the mean of
(LP − dual) / |LP| and (primal − LP) / |LP| in %, the median iterations, and HiGHS's LP time.
The last three columns run ``sensor_order="auto"`` with ``polish=True`` (``assign_sd``'s
default; docs/performance.md's polish table): its time, the median per-scan ratio of that time
to the unpolished ``auto``'s (over all scans), and its primal's distance from the LP. This is
the evidence for ``sensor_order="auto"``, and what the polish costs and gains.

    python benches/bench_sensor_order.py [--scans 10] [--repeats 3] [--targets 10 18 50 100]
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np
import passive_assoc as pa
import scipy.sparse as sp
from passive_assoc.simulation import static_scan
from passive_assoc.static_los import Candidates, enumerate_candidates
from scipy.optimize import linprog

CONFIGS: dict[str, dict[str, Any]] = {
    "auto": {"sensor_order": "auto", "polish": False},
    "given": {"sensor_order": "given", "polish": False},
    "polish": {"sensor_order": "auto", "polish": True},
}


def lp_bound(cands: Candidates) -> tuple[float, float]:
    """The LP relaxation's optimum (every report at most once, 0 <= x <= 1) and its time, s."""
    tuples, costs, sizes = cands.tuples, cands.costs, cands.sizes
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    rows, cols = [], []
    for s in range(tuples.shape[1]):
        used = np.nonzero(tuples[:, s])[0]
        rows.append(offsets[s] + tuples[used, s] - 1)
        cols.append(used)
    start = time.perf_counter()
    a = sp.csr_matrix(
        (np.ones(sum(map(len, rows))), (np.concatenate(rows), np.concatenate(cols))), shape=(offsets[-1], len(costs))
    )
    res = linprog(costs, A_ub=a, b_ub=np.ones(offsets[-1]), bounds=(0, 1), method="highs")
    if res.status != 0:
        raise RuntimeError(f"linprog failed: {res.message}")
    return float(res.fun), time.perf_counter() - start


def best_of(cands: Candidates, config: dict[str, Any], repeats: int) -> tuple[float, pa.SdAssignment]:
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = pa.assign_sd(cands.tuples, cands.costs, cands.sizes, **config)
        times.append(time.perf_counter() - start)
    assert result is not None
    return float(np.min(times)), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scans", type=int, default=10)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--targets", type=int, nargs="+", default=[10, 18, 50, 100])
    args = parser.parse_args()
    print(
        f"S = 3, R = 15, {args.scans} scans per M; times: median of per-scan bests; "
        "dual/primal: mean % of |LP|; iterations: median"
    )
    print(
        f"{'M':>4} {'reordered':>9} {'auto ms':>9} {'given ms':>9} {'auto/given':>11} "
        f"{'LP-dual auto':>13} {'given':>7} "
        f"{'primal-LP auto':>15} {'given':>7} {'it. auto':>9} {'given':>6} {'HiGHS LP ms':>12} "
        f"{'polish ms':>10} {'polish/auto':>12} {'primal-LP polish':>17}"
    )
    for n_targets in args.targets:
        rec: dict[str, dict[str, list[float]]] = {o: {"t": [], "dual": [], "primal": [], "it": []} for o in CONFIGS}
        ratio, polish_ratio, lp_times = [], [], []
        for k in range(args.scans):
            scan = static_scan(4000 + 7 * n_targets + 1000 * k, n_targets=n_targets, n_sensors=3, ratio=15.0)
            cands = enumerate_candidates(scan.measurements, scan.sensors)
            lp, lp_time = lp_bound(cands)
            lp_times.append(lp_time)
            best: dict[str, float] = {o: np.inf for o in CONFIGS}
            found: dict[str, pa.SdAssignment] = {}
            for _ in range(2):  # interleaved, so both see the same machine
                for o, config in CONFIGS.items():
                    t, found[o] = best_of(cands, config, args.repeats)
                    best[o] = min(best[o], t)
            polish_ratio.append(best["polish"] / best["auto"])
            for o in CONFIGS:
                t, r = best[o], found[o]
                rec[o]["t"].append(t)
                rec[o]["dual"].append(100 * (lp - r.dual_bound) / abs(lp))
                rec[o]["primal"].append(100 * (r.primal_cost - lp) / abs(lp))
                rec[o]["it"].append(r.iterations)
            sizes = list(cands.sizes)
            if max(range(3), key=lambda s: (sizes[s], s)) != 2:  # auto relaxes another sensor
                ratio.append(best["auto"] / best["given"])
        a, g = rec["auto"], rec["given"]
        print(
            f"{n_targets:>4} {len(ratio):>9} {1e3 * np.median(a['t']):>9.2f} {1e3 * np.median(g['t']):>9.2f} "
            f"{np.median(ratio) if ratio else np.nan:>11.2f} {np.mean(a['dual']):>13.3f} {np.mean(g['dual']):>7.3f} "
            f"{np.mean(a['primal']):>15.3f} {np.mean(g['primal']):>7.3f} {np.median(a['it']):>9.0f} "
            f"{np.median(g['it']):>6.0f} {1e3 * np.median(lp_times):>12.1f} "
            f"{1e3 * np.median(rec['polish']['t']):>10.2f} {np.median(polish_ratio):>12.2f} "
            f"{np.mean(rec['polish']['primal']):>17.3f}"
        )


if __name__ == "__main__":
    main()
