"""The static candidate enumeration (METHODS §2) bit for bit between two builds, and its time.

480 scans of the simulator's static scene (`static_scan`): S = 3, M = 20 (300 seeds); S = 5,
M = 20 (100); S = 3, M = 50 (30); S = 4, M = 30 (50). Each scan's enumerated tuples, costs and
sizes are kept as bytes, so two builds agree only if every candidate and every cost is the same
to the bit. Then, for each S = 3 and S = 5 (M = 20, the first 60 scans), the best of five
passes of `enumerate_candidates` over the already simulated scans, in ms an enumeration.

    python3 benches/enumeration_identity.py --out before.pkl      # on the older build
    python3 benches/enumeration_identity.py --against before.pkl  # on the newer one
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import passive_assoc as pa
from build_dump import dump_and_compare
from passive_assoc.simulation import static_scan

#: (sensors, targets, seeds) of the identity set.
CASES = ((3, 20, 300), (5, 20, 100), (3, 50, 30), (4, 30, 50))


def enumerations() -> list[tuple[bytes, bytes, bytes]]:
    out = []
    for n_sensors, n_targets, seeds in CASES:
        for seed in range(seeds):
            sc = static_scan(seed, n_targets=n_targets, n_sensors=n_sensors)
            c = pa.enumerate_candidates(sc.measurements, sc.sensors)
            arrays = (np.asarray(c.tuples), np.asarray(c.costs), np.asarray(c.sizes))
            out.append((arrays[0].tobytes(), arrays[1].tobytes(), arrays[2].tobytes()))
    return out


def timing(n_sensors: int, scans: int = 60, passes: int = 5) -> float:
    """Best of `passes` over `scans` enumerations, in ms an enumeration."""
    simulated = [static_scan(seed, n_targets=20, n_sensors=n_sensors) for seed in range(scans)]
    best = float("inf")
    for _ in range(passes):
        start = time.perf_counter()
        for sc in simulated:
            pa.enumerate_candidates(sc.measurements, sc.sensors)
        best = min(best, time.perf_counter() - start)
    return best / scans * 1e3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write this build's enumerations here")
    parser.add_argument("--against", help="compare this build's enumerations with such a file")
    args = parser.parse_args()
    mine = enumerations()
    print(f"{len(mine)} enumerations, {sum(len(m[1]) // 8 for m in mine)} candidates")
    for n_sensors in (3, 5):
        print(f"S = {n_sensors}, M = 20: {timing(n_sensors):.3f} ms an enumeration")
    dump_and_compare(mine, args.out, args.against, "enumerations", "tuples, costs or sizes")


if __name__ == "__main__":
    main()
