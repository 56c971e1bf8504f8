"""Candidate enumeration (METHODS §2): brute-force NumPy over all Π(n_s+1) tuples against the
pruned Rust enumeration (`_core.enumerate_static`), in one run, on the same scan.

EXPERIMENTS `intensity` geometry: 2-D sensors at (−15, 0), (0, −5), (15, 0) km, M targets
uniform in x ∈ [−10, 10], y ∈ [20, 40] km, Pd = 0.95, each reported bearing false with
probability 0.05 (uniform over the sensor's sector of the square), σ from R = Δ/σ with
Δ = 0.761 rad / M. Both sides apply the same gate (module docs of `static_assoc`): for every
prefix of ≥ 2 rays in sensor order, the two-ray intersection in front of both sensors, then
Gauss-Newton ML with every normalised squared residual ≤ γ and the point in front. The NumPy
side is fully vectorised over the tuples (fixed 10 Gauss-Newton iterations, no step control),
so a borderline tuple may land on the other side of the gate; the number of such tuples is
printed.

    python benches/bench_enumeration.py [--targets 30] [--r 15] [--repeats 5] [--seed 0]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from types import SimpleNamespace
from typing import Any

import numpy as np
from passive_assoc import _core

SENSORS = np.array([[-15e3, 0.0, 0.0], [0.0, -5e3, 0.0], [15e3, 0.0, 0.0]])
GATE_SIGMAS = 2.5758293035489004  # the two-sided 99 % point per angle
GATE = GATE_SIGMAS**2  # its χ²(1 dof), 6.635: the brute force's gate on squared residuals
SQUARE_WIDTH_RAD = 0.761


def scan(m: int, r: float, seed: int) -> tuple[np.ndarray, np.ndarray, float, np.ndarray]:
    """Rows (sensor, bearing) of one scan, the bearing std and the false-alarm densities."""
    rng = np.random.default_rng(seed)
    sigma = SQUARE_WIDTH_RAD / m / r
    targets = np.column_stack([rng.uniform(-10e3, 10e3, m), rng.uniform(20e3, 40e3, m)])
    corners = np.array([[-10e3, 20e3], [10e3, 20e3], [-10e3, 40e3], [10e3, 40e3]])
    sensor, bearing, density = [], [], []
    for j, p in enumerate(SENSORS):
        seen = rng.uniform(size=m) < 0.95
        true = np.arctan2(targets[seen, 1] - p[1], targets[seen, 0] - p[0]) + sigma * rng.standard_normal(seen.sum())
        sector = np.arctan2(corners[:, 1] - p[1], corners[:, 0] - p[0])
        n_false = rng.binomial(len(true), 0.05 / 0.95)
        false = rng.uniform(sector.min(), sector.max(), n_false)
        rows = np.concatenate([true, false])
        rng.shuffle(rows)
        sensor += [j] * len(rows)
        bearing += list(rows)
        density.append(max(n_false, 0.5) / (sector.max() - sector.min()))
    return np.array(sensor, dtype=np.int64), np.array(bearing), sigma, np.array(density)


def wrap(a: np.ndarray) -> np.ndarray:
    return a - 2 * np.pi * np.ceil((a - np.pi) / (2 * np.pi))


def brute_force(sensor: np.ndarray, bearing: np.ndarray, sigma: float, gate: float) -> np.ndarray:
    """All gated tuples (K, S), 0 = missed, by testing every tuple of Π(n_s + 1)."""
    s_count = len(SENSORS)
    per_sensor = [bearing[sensor == j] for j in range(s_count)]
    sizes = [len(b) for b in per_sensor]
    tuples = np.indices([n + 1 for n in sizes]).reshape(s_count, -1).T  # lexicographic
    used = tuples > 0
    keep = used.sum(axis=1) >= 2
    # θ[t, s] (anything where missed: masked out below).
    theta = np.column_stack([np.concatenate([[0.0], per_sensor[s]])[tuples[:, s]] for s in range(s_count)])
    px, py = SENSORS[:, 0], SENSORS[:, 1]
    # The first two contributing sensors and their closed-form intersection.
    first = np.argmax(used, axis=1)
    rest = used.copy()
    rest[np.arange(len(tuples)), first] = False
    second = np.argmax(rest, axis=1)
    ta, tb = theta[np.arange(len(tuples)), first], theta[np.arange(len(tuples)), second]
    ua = np.column_stack([np.cos(ta), np.sin(ta)])
    ub = np.column_stack([np.cos(tb), np.sin(tb)])
    cross = ua[:, 0] * ub[:, 1] - ua[:, 1] * ub[:, 0]
    wx, wy = px[second] - px[first], py[second] - py[first]
    with np.errstate(divide="ignore", invalid="ignore"):
        ra = (wx * ub[:, 1] - wy * ub[:, 0]) / cross
        rb = (wx * ua[:, 1] - wy * ua[:, 0]) / cross
    keep &= (np.abs(cross) > 1e-12) & (ra > 0) & (rb > 0)
    x = px[first] + ra * ua[:, 0]
    y = py[first] + ra * ua[:, 1]
    # Each further contributing sensor s extends the prefix: Gauss-Newton on the prefix, gate.
    # (Diverging fits go NaN and fail the gate; no warnings for them.)
    with np.errstate(all="ignore"):
        _extend(keep, used, second, theta, x, y, sigma, gate)
    gated: np.ndarray = tuples[keep]
    return gated


def _extend(
    keep: np.ndarray,
    used: np.ndarray,
    second: np.ndarray,
    theta: np.ndarray,
    x: np.ndarray,
    y: np.ndarray,
    sigma: float,
    gate: float,
) -> None:
    s_count = len(SENSORS)
    px, py = SENSORS[:, 0], SENSORS[:, 1]
    for s in range(s_count):
        grows = keep & used[:, s] & (s > second)
        if not grows.any():
            continue
        idx = np.flatnonzero(grows)
        prefix = used[idx] & (np.arange(s_count) <= s)
        th = theta[idx]
        xs, ys = x[idx], y[idx]
        for _ in range(10):
            dx, dy = xs[:, None] - px, ys[:, None] - py
            rho2 = dx**2 + dy**2
            res = np.where(prefix, wrap(th - np.arctan2(dy, dx)) / sigma, 0.0)
            gx, gy = np.where(prefix, -dy / (rho2 * sigma), 0.0), np.where(prefix, dx / (rho2 * sigma), 0.0)
            hxx, hxy, hyy = (gx * gx).sum(1), (gx * gy).sum(1), (gy * gy).sum(1)
            bx, by = (gx * res).sum(1), (gy * res).sum(1)
            det = hxx * hyy - hxy**2
            xs = xs + (hyy * bx - hxy * by) / det
            ys = ys + (hxx * by - hxy * bx) / det
        dx, dy = xs[:, None] - px, ys[:, None] - py
        res = wrap(th - np.arctan2(dy, dx)) / sigma
        ahead = dx * np.cos(th) + dy * np.sin(th) > 0
        ok = np.all(~prefix | ((res**2 <= gate) & ahead), axis=1) & np.isfinite(xs) & np.isfinite(ys)
        keep[idx] = ok
        x[idx], y[idx] = xs, ys


def rust(
    sensor: np.ndarray, bearing: np.ndarray, sigma: float, density: np.ndarray, n_threads: int | None
) -> _core.Candidates:
    s_count = len(SENSORS)
    # The binding reads the table and the network by attribute; these stand in for the
    # validated MeasurementTable / SensorNetwork at no cost.
    table: Any = SimpleNamespace(
        sensor=sensor, time=np.zeros_like(bearing), azimuth=bearing, elevation=np.zeros_like(bearing)
    )
    network: Any = SimpleNamespace(
        positions=SENSORS, sigma_azimuth=np.full(s_count, sigma), sigma_elevation=np.full(s_count, sigma), ndim=2
    )
    settings: Any = SimpleNamespace(
        gate_sigmas=GATE_SIGMAS, min_intensity=2, max_candidates=1_000_000, n_threads=n_threads
    )
    return _core.enumerate_static(table, network, np.full(s_count, 0.95), density, settings)


def median_seconds(run: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--targets", type=int, default=30)
    parser.add_argument("--r", type=float, default=15.0)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    sensor, bearing, sigma, density = scan(args.targets, args.r, args.seed)
    sizes = np.bincount(sensor, minlength=len(SENSORS))
    total = int(np.prod(sizes + 1))
    slow = brute_force(sensor, bearing, sigma, GATE)
    fast = rust(sensor, bearing, sigma, density, 1).tuples

    def as_set(a: np.ndarray) -> set[tuple[int, ...]]:
        return {tuple(int(v) for v in row) for row in a}

    differ = len(as_set(slow) ^ as_set(fast))
    print(
        f"M = {args.targets}, R = {args.r:g}, σ = {1e3 * sigma:.3f} mrad, reports per sensor {sizes.tolist()}, "
        f"{total} tuples in Π(n_s+1)"
    )
    print(f"candidates: numpy {len(slow)}, rust {len(fast)}, differing {differ}")
    t_numpy = median_seconds(lambda: brute_force(sensor, bearing, sigma, GATE), args.repeats)
    t_one = median_seconds(lambda: rust(sensor, bearing, sigma, density, 1), args.repeats)
    t_all = median_seconds(lambda: rust(sensor, bearing, sigma, density, None), args.repeats)
    print(f"{'numpy brute force':>26} {1e3 * t_numpy:9.3f} ms")
    print(f"{'rust, 1 thread':>26} {1e3 * t_one:9.3f} ms   numpy/rust {t_numpy / t_one:7.1f}x")
    print(f"{'rust, all threads':>26} {1e3 * t_all:9.3f} ms   numpy/rust {t_numpy / t_all:7.1f}x")


if __name__ == "__main__":
    main()
