"""Whether two builds' Lagrangian S-D solves agree: dumps every solve's iterations, primal
cost, dual bound, gap, chosen tuples and termination on the static-association paper's scans
(150 at S = 3, M = 20; 60 at M = 10; 30 at S = 4, M = 10; 10 at M = 50), with and without the
polish and under every warm-start setting, then compares with another build's dump. A change
that claims to leave the solver's answers the same (the same primal costs and gaps) is checked
this way: run it on the old build with ``--out``, on the new one with ``--against``.

    PYTHONPATH=<old package> python3 benches/lagrangian_identity.py --out old.pkl
    python3 benches/lagrangian_identity.py --against old.pkl
"""

from __future__ import annotations

import argparse
import pickle
from typing import Any

import numpy as np
import passive_assoc as pa
from passive_assoc.simulation import static_scan

CASES = [(20, 3, 150), (10, 3, 60), (10, 4, 30), (50, 3, 10)]  # targets, sensors, scans


def solves() -> list[tuple[Any, ...]]:
    out = []
    for n_targets, n_sensors, n_scans in CASES:
        for seed in range(n_scans):
            scan = static_scan(seed, n_targets=n_targets, n_sensors=n_sensors)
            c = pa.enumerate_candidates(scan.measurements, scan.sensors)
            for polish in (True, False):
                for warm in ("auto", "always", "never"):
                    r = pa.assign_sd(c.tuples, c.costs, c.sizes, polish=polish, warm_start=warm, time_limit=None)
                    chosen = tuple(np.asarray(r.chosen).tolist())
                    key = (n_targets, n_sensors, seed, polish, warm)
                    out.append((key, r.iterations, r.primal_cost, r.dual_bound, r.gap, chosen, str(r.termination)))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write this build's solves here")
    parser.add_argument("--against", help="compare this build's solves with a dump")
    args = parser.parse_args()
    mine = solves()
    if args.out:
        with open(args.out, "wb") as f:
            pickle.dump(mine, f)
        print(f"{len(mine)} solves written to {args.out}")
    if args.against:
        with open(args.against, "rb") as f:
            theirs = pickle.load(f)
        differ = [(a, b) for a, b in zip(theirs, mine, strict=True) if a != b]
        primal = sum(a[2] != b[2] for a, b in differ)
        print(f"{len(mine)} solves: {len(differ)} differ ({primal} in the primal cost)")
        for a, b in differ[:3]:
            print(f"  {a[0]}: dual bound {a[3]:.6f} -> {b[3]:.6f}, primal {a[2]:.6f} -> {b[2]:.6f}")


if __name__ == "__main__":
    main()
