"""How often the wavelet coarse gate rejects true pairs, nominal 1 %, on Kalman-filtered tracks
of targets that move exactly as the filter's model: with the window's whole covariance (the
cross-time terms of ``radar_esm.window``) and with the per-scan variances only. 3000 tracks,
windows of 4 (level 0), 12 (level 2) and 28 scans (level 3); the same simulation as
``tests/radar_esm/test_window.py``, which asserts the bounds (docs/methods.md, §5).

    python3 benches/bench_gate_calibration.py
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
from passive_assoc.radar_esm.window import RollingWindow, filter_transitions
from scipy.stats import chi2

_TEST = Path(__file__).resolve().parents[1] / "tests" / "radar_esm" / "test_window.py"


def main() -> None:
    spec = importlib.util.spec_from_file_location("test_window", _TEST)
    assert spec is not None and spec.loader is not None
    test = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(test)  # the test's simulation, not a copy of it
    n = 3000
    print("window  whole Σ  per-scan Σ   (rejected true pairs, nominal 1 %)")
    for length in (4, 12, 28):
        tracks, errors = test.filtered_tracks(n, seed=length)
        window = RollingWindow(tracks, filter_transitions(tracks, np.arange(test.SCANS, dtype=float), test.Q), cap=32)
        window.advance_to(test.SCANS - 1)
        sigma, tail = window.covariance(np.arange(n), length), errors[:, -length:]
        if length < 6:  # below one sym2 level: the positions themselves
            statistic = np.einsum("ns,ns->n", tail, np.linalg.solve(sigma[:, 0, :, 0, :], tail[..., None])[..., 0])
            print(f"{length:6d}  {np.mean(statistic > chi2.ppf(0.99, length)):7.2%}  {'-':>10}")
            continue
        per_scan = test.rejection(tail, tracks.covariance[:, -length:, 0, 0][:, None, :])
        print(f"{length:6d}  {test.rejection(tail, sigma):7.2%}  {per_scan:10.2%}")


if __name__ == "__main__":
    main()
