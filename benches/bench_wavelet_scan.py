"""Full wavelet-fuzzy association of 500 radar × 500 ESM tracks (the paper scenario's 10
targets plus 490 false tracks per sensor, 30 scans of 1 s), with the whole-window covariance
and with Σ per scan; prints the time of one ``associate`` call over all scans and its mean
per scan (the cost of fully associating one scan of 500 × 500 tracks).

    python3 benches/bench_wavelet_scan.py [--tracks 500] [--repeat 3]
"""

from __future__ import annotations

import argparse
import time

import passive_assoc as pa
from passive_assoc.experiments.wavelet_runs import PROCESS_NOISE
from passive_assoc.radar_esm import filter_reports
from passive_assoc.simulation import paper_wavelet_scenario


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tracks", type=int, default=500)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    scenario = paper_wavelet_scenario(1, n_clutter=args.tracks - 10)
    tracks = filter_reports(scenario.measurements, PROCESS_NOISE)
    radar, esm = tracks.of(0), tracks.of(1)
    scans = len(scenario.scan_times) - 2  # the CA filter's first state is at the third report
    for label, associator in (
        ("whole-window Σ", pa.WaveletFuzzyAssociator(process_noise=PROCESS_NOISE)),
        ("per-scan Σ", pa.WaveletFuzzyAssociator(process_noise=None)),
    ):
        best = float("inf")
        for _ in range(args.repeat):
            start = time.perf_counter()
            result = associator.associate(local=esm, system=radar)
            best = min(best, time.perf_counter() - start)
        print(
            f"{label:<15} {args.tracks} x {args.tracks} tracks, {scans} scans: {best:.3f} s a call, "
            f"{best / scans * 1e3:.1f} ms a scan ({len(result.pairs)} pairs made)"
        )


if __name__ == "__main__":
    main()
