"""The closeness R and its gradient (METHODS §1 eq. 17–18) at random states over a ring
scene's rows, on one thread: the kernel's time per state where many rows share each scan's
elevations (the 3-D scenes of the initiation-at-scale targets). Prints µs a state, the best
of the repeats, and ΣR (equal between builds that agree to rounding).

    python3 benches/bench_closeness.py [--sensors 4] [--targets 50] [--states 20000]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import passive_assoc as pa
from passive_assoc.fti.closeness import closeness


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sensors", type=int, default=4)
    parser.add_argument("--targets", type=int, default=50)
    parser.add_argument("--states", type=int, default=20_000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    scene = pa.ring_scenario(0, n_sensors=args.sensors, n_targets=args.targets)
    rng = np.random.default_rng(0)
    n = args.states
    states = np.column_stack(
        [
            rng.uniform(-20e3, 20e3, (n, 2)),
            rng.uniform(500.0, 9e3, n),
            rng.uniform(-200.0, 200.0, (n, 2)),
            np.zeros(n),
        ]
    )
    best, values = np.inf, np.zeros(n)
    for _ in range(args.repeats):
        start = time.perf_counter()
        values, _ = closeness(scene.measurements, scene.sensors, states, t0=scene.t0, n_threads=1)
        best = min(best, time.perf_counter() - start)
    print(
        f"ring {args.sensors} x {args.targets} ({len(scene.measurements)} rows), {n} states, 1 thread: "
        f"{1e6 * best / n:.2f} us a state; sum of R {float(np.sum(values)):.12g}"
    )


if __name__ == "__main__":
    main()
