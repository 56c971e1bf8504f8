"""The radar/ESM coarse gate (METHODS §5 step 2) over 500 radar × 500 ESM tracks against
NumPy, same inputs, same run.

x axis only, a 30-scan window, sym2 at 3 levels in symmetric mode (6 approximation
coefficients per track), per-scan variances that differ by track and scan. Timed:

* ``passive_assoc``: ``passive_assoc.radar_esm.coarse_gate`` end to end (coefficients, χ²
  threshold, the Rust pair loop on all threads), and the Rust pair loop alone
  (``_core.wavelet_coarse_gate``) on all threads and on one;
* ``numpy per pair``: what a NumPy user writes first — ``C = W diag(v) Wᵀ`` per track
  (vectorised), then a Python loop over pairs with ``np.linalg.solve``;
* ``numpy batched``: the same with one batched ``np.linalg.solve`` over all 250 000 pairs.

Prints the seconds of each (best of ``--repeat``; the per-pair loop runs once), the ratios and
the largest relative difference of the statistics.

    python benches/bench_coarse_gate.py [--tracks 500] [--repeat 20]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray
from passive_assoc import _core
from passive_assoc._settings import CoarseGateSettings
from passive_assoc.radar_esm import approximation_operator, coarse_gate
from scipy.stats import chi2

WINDOW = 30


def make_inputs(n: int, seed: int = 3) -> tuple[NDArray[np.float64], ...]:
    """Positions and per-scan variances (n, 1, T) of n radar and n ESM tracks."""
    rng = np.random.default_rng(seed)
    truth = np.cumsum(rng.normal(0.0, 300.0, (n, 1, WINDOW)), axis=2) + rng.uniform(0, 20e3, (n, 1, 1))
    radar_var = rng.uniform(0.3e6, 0.7e6, (n, 1, WINDOW))
    esm_var = rng.uniform(0.3e6, 0.7e6, (n, 1, WINDOW))
    radar = truth + rng.normal(size=truth.shape) * np.sqrt(radar_var)
    esm = truth[rng.permutation(n)] + rng.normal(size=truth.shape) * np.sqrt(esm_var)
    return radar, radar_var, esm, esm_var


def numpy_covariances(operator: NDArray[np.float64], variances: NDArray[np.float64]) -> NDArray[np.float64]:
    """C = W diag(v) Wᵀ of every track (n, c, c), x axis only."""
    covariances: NDArray[np.float64] = np.einsum("at,nt,bt->nab", operator, variances[:, 0], operator)
    return covariances


def numpy_per_pair(operator: NDArray[np.float64], inputs: tuple[NDArray[np.float64], ...]) -> NDArray[np.float64]:
    radar, radar_var, esm, esm_var = inputs
    a_r, a_e = radar[:, 0] @ operator.T, esm[:, 0] @ operator.T
    c_r, c_e = numpy_covariances(operator, radar_var), numpy_covariances(operator, esm_var)
    out = np.empty((len(a_r), len(a_e)))
    for i in range(len(a_r)):
        for j in range(len(a_e)):
            d = a_r[i] - a_e[j]
            out[i, j] = d @ np.linalg.solve(c_r[i] + c_e[j], d)
    return out


def numpy_batched(operator: NDArray[np.float64], inputs: tuple[NDArray[np.float64], ...]) -> NDArray[np.float64]:
    radar, radar_var, esm, esm_var = inputs
    a_r, a_e = radar[:, 0] @ operator.T, esm[:, 0] @ operator.T
    c_r, c_e = numpy_covariances(operator, radar_var), numpy_covariances(operator, esm_var)
    d = a_r[:, None, :] - a_e[None, :, :]
    x = np.linalg.solve(c_r[:, None] + c_e[None, :], d[..., None])[..., 0]
    statistic: NDArray[np.float64] = np.einsum("ijc,ijc->ij", d, x)
    return statistic


def best(func: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    times, result = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        result = func()
        times.append(time.perf_counter() - t)
    return min(times), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tracks", type=int, default=500)
    parser.add_argument("--repeat", type=int, default=20)
    args = parser.parse_args()
    n = args.tracks
    inputs = make_inputs(n)
    radar, radar_var, esm, esm_var = inputs
    operator, _ = approximation_operator(WINDOW)
    threshold = float(chi2.ppf(0.99, operator.shape[0]))
    sides = ((radar @ operator.T, radar_var), (esm @ operator.T, esm_var))

    def core(threads: int | None) -> Callable[[], Any]:
        settings = CoarseGateSettings(threshold, True, threads)
        return lambda: _core.wavelet_coarse_gate(operator, *sides, settings)[0]

    timings: dict[str, float] = {}
    timings["passive_assoc coarse_gate"], gate = best(lambda: coarse_gate(radar, radar_var, esm, esm_var), args.repeat)
    timings["passive_assoc core, all threads"], _ = best(core(None), args.repeat)
    timings["passive_assoc core, 1 thread"], _ = best(core(1), args.repeat)
    timings["numpy batched solve"], batched = best(lambda: numpy_batched(operator, inputs), args.repeat)
    timings["numpy per-pair solve"], per_pair = best(lambda: numpy_per_pair(operator, inputs), 1)

    print(f"coarse gate, {n} x {n} tracks, x only, {WINDOW} scans, {operator.shape[0]} coefficients (sym2, level 3):")
    for name, seconds in timings.items():
        print(f"  {name:>32}: {seconds * 1e3:9.2f} ms")
    ours = timings["passive_assoc coarse_gate"]
    for name in ("numpy per-pair solve", "numpy batched solve"):
        print(f"  {name} / passive_assoc coarse_gate: {timings[name] / ours:8.1f}x")
    for name, other in (("per-pair", per_pair), ("batched", batched)):
        diff = np.max(np.abs(gate.statistic - other) / np.maximum(np.abs(other), 1.0))
        print(f"  largest relative difference vs numpy {name}: {diff:.1e}")
    print(f"  pairs passing: {int(gate.passed.sum())} of {gate.passed.size} (true pairs: {n})")


if __name__ == "__main__":
    main()
