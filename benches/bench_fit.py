"""fit_ml against a loop of scipy.optimize.least_squares on the same problems, in one run.

The problems are the fuzzy-initiation candidate fit: 4 az/el measurements (two sensors, first
and last scan), 6-D constant-velocity state; both solvers start from the same initial states
and use the same analytic Jacobian. Prints fits/s of each, the ratio, and the agreement.

    python benches/bench_fit.py [--problems 10000] [--scipy-problems 1000]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import passive_assoc as pa
from scipy.optimize import least_squares

SENSORS = pa.SensorNetwork.spatial([[0.0, 0.0, 0.0], [20e3, 0.0, 0.0]], 5e-3, 5e-3)


def schedule(scans: int) -> list[tuple[int, float]]:
    """(sensor, time) of each measurement: sensor 0 at 0 … 105 s, sensor 1 5 s after it."""
    period = 105.0 / (scans - 1)
    return [(s, k * period + 5.0 * s) for k in range(scans) for s in (0, 1)]


def make_problems(n: int, seed: int = 7, scans: int = 2) -> tuple[pa.MeasurementTable, np.ndarray, np.ndarray]:
    """Noisy measurements of n random CV targets; returns (table, groups (n, 2 scans),
    initial (n, 6))."""
    rng = np.random.default_rng(seed)
    truth = np.column_stack(
        [
            rng.uniform(-5e3, 25e3, n),
            rng.uniform(2e3, 30e3, n),
            rng.uniform(500, 3000, n),
            rng.uniform(-250, 250, n),
            rng.uniform(-250, 250, n),
            np.zeros(n),
        ]
    )
    plan = schedule(scans)
    which = np.array([s for s, _ in plan])
    times = np.array([t for _, t in plan])
    pos = truth[:, None, :3] + times[None, :, None] * truth[:, None, 3:]
    rel = pos - SENSORS.positions[which][None]
    m = len(plan)
    az = np.arctan2(rel[..., 1], rel[..., 0]) + rng.normal(0, 5e-3, (n, m))
    el = np.arctan2(rel[..., 2], np.hypot(rel[..., 0], rel[..., 1])) + rng.normal(0, 5e-3, (n, m))
    table = pa.MeasurementTable.from_arrays(np.tile(which, n), np.tile(times, n), az.ravel(), el.ravel())
    initial = truth * 1.01 + 20.0
    return table, np.arange(m * n).reshape(n, m), initial


def scipy_fit(table: pa.MeasurementTable, rows: np.ndarray, x0: np.ndarray, method: str = "trf") -> np.ndarray:
    """What a user without this library writes: residuals and analytic Jacobian in NumPy."""
    s = SENSORS.positions[table.sensor[rows]]
    t, az, el = table.time[rows], table.azimuth[rows], table.elevation[rows]
    sig = 5e-3

    def residual(x: np.ndarray) -> np.ndarray:
        d = x[:3] + t[:, None] * x[3:] - s
        rho = np.hypot(d[:, 0], d[:, 1])
        da = np.angle(np.exp(1j * (az - np.arctan2(d[:, 1], d[:, 0]))))
        de = el - np.arctan2(d[:, 2], rho)
        return np.concatenate([da, de]) / sig

    def jacobian(x: np.ndarray) -> np.ndarray:
        d = x[:3] + t[:, None] * x[3:] - s
        rho2 = d[:, 0] ** 2 + d[:, 1] ** 2
        rho, r2 = np.sqrt(rho2), rho2 + d[:, 2] ** 2
        ga = np.column_stack([-d[:, 1] / rho2, d[:, 0] / rho2, np.zeros_like(rho)])
        ge = np.column_stack([-d[:, 0] * d[:, 2] / (r2 * rho), -d[:, 1] * d[:, 2] / (r2 * rho), rho / r2])
        ja = np.hstack([ga, t[:, None] * ga])
        je = np.hstack([ge, t[:, None] * ge])
        return -np.vstack([ja, je]) / sig

    estimate: np.ndarray = least_squares(residual, x0, jac=jacobian, method=method, xtol=1e-10).x
    return estimate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--problems", type=int, default=10_000)
    parser.add_argument(
        "--scipy-problems",
        type=int,
        default=1_000,
        help="scipy is timed on the first N problems (it is slow) and scaled per fit",
    )
    parser.add_argument("--scans", type=int, default=2, help="scans of each of the two sensors (>= 2)")
    args = parser.parse_args()
    if args.scans < 2:
        parser.error("--scans: at least 2")
    table, groups, initial = make_problems(args.problems, scans=args.scans)

    timings = {}
    for threads in (1, 2):
        best = np.inf
        for _ in range(5):
            start = time.perf_counter()
            fit = pa.fit_ml(table, SENSORS, groups, initial=initial, n_threads=threads)
            best = min(best, time.perf_counter() - start)
        timings[threads] = best
    n_sp = min(args.scipy_problems, args.problems)
    scipy_rates, refs = {}, {}
    for method in ("trf", "lm"):  # trf is least_squares' default; lm (MINPACK) its fastest here
        start = time.perf_counter()
        refs[method] = np.array([scipy_fit(table, groups[k], initial[k], method) for k in range(n_sp)])
        scipy_rates[method] = n_sp / (time.perf_counter() - start)
    ours_1, ours_2 = args.problems / timings[1], args.problems / timings[2]
    sigma = np.sqrt(np.diagonal(fit.covariances[:n_sp], axis1=1, axis2=2))
    ok = fit.converged[:n_sp]
    agree = max(float((np.abs(fit.estimates[:n_sp] - r)[ok] / sigma[ok]).max()) for r in refs.values())
    print(f"problems: {args.problems} ({groups.shape[1]} az/el measurements, 6-D CV state); scipy timed on {n_sp}")
    print(f"passive_assoc.fit_ml, 1 thread    : {ours_1:12,.0f} fits/s")
    print(f"passive_assoc.fit_ml, 2 threads   : {ours_2:12,.0f} fits/s  ({ours_2 / ours_1:.2f}x the 1-thread rate)")
    for method, rate in scipy_rates.items():
        print(
            f"scipy least_squares loop, {method:<4}   : {rate:12,.0f} fits/s"
            f"  -> speed-up {ours_1 / rate:6.0f}x (1 thread), {ours_2 / rate:6.0f}x (2 threads)"
        )
    print(
        f"converged: {fit.converged.mean():.4f}; median iterations {np.median(fit.iterations):.0f}; "
        f"max |ours - scipy| / sigma on converged fits: {agree:.2e}"
    )


if __name__ == "__main__":
    main()
