"""Dask's overhead against the work it spreads, on a two-worker LocalCluster of processes
(this machine has 2 cores, so the cluster can only match local threads; the point is the
overhead): tasks per second for empty tasks, ``reproduce fti``'s runs through
``map_runs`` on the cluster against two local threads, and ``associate_scans_on`` against
one local ``associate_scans``. Needs ``pip install 'passive-assoc[dask]'``.

    python3 benches/bench_dask.py [--runs 200] [--scans 2000]
"""

from __future__ import annotations

import argparse
import time

import distributed
import numpy as np
import passive_assoc as pa
from passive_assoc.distributed import associate_scans_on, using
from passive_assoc.experiments.fti import run_experiment
from passive_assoc.simulation import static_scan


def _nothing(x: int) -> int:
    return x


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=200)
    parser.add_argument("--scans", type=int, default=2000)
    args = parser.parse_args()
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    with distributed.Client(cluster) as client:
        client.gather(client.map(_nothing, range(100), pure=False))  # warm up
        start = time.perf_counter()
        client.gather(client.map(_nothing, range(2000), pure=False))
        per_task = (time.perf_counter() - start) / 2000
        print(f"empty tasks: {1 / per_task:.0f} tasks/s, {per_task * 1e3:.2f} ms a task")
        initiator = pa.FuzzyTrackInitiator(n_threads=1)
        start = time.perf_counter()
        run_experiment(args.runs, 1, 2, 1.0, 2.0, initiator)
        local = time.perf_counter() - start
        with using(client):
            start = time.perf_counter()
            run_experiment(args.runs, 1, 2, 1.0, 2.0, initiator)
            remote = time.perf_counter() - start
        print(f"reproduce fti, {args.runs} runs: 2 local threads {local:.2f} s, the cluster {remote:.2f} s")
        parts = [static_scan(seed, n_targets=20).measurements.to_arrays() for seed in range(args.scans)]
        columns = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
        columns["time"] = np.repeat(np.arange(float(args.scans)), [len(p["time"]) for p in parts])
        table, sensors = pa.MeasurementTable.from_columns(columns), static_scan(0, n_targets=20).sensors
        start = time.perf_counter()
        pa.associate_scans(table, sensors, method="intensity")
        local = time.perf_counter() - start
        start = time.perf_counter()
        associate_scans_on(client, table, sensors, method="intensity")
        remote = time.perf_counter() - start
        print(
            f"associate_scans, {args.scans} scans (intensity): one local call {local:.2f} s, the cluster {remote:.2f} s"
        )
    cluster.close()


if __name__ == "__main__":
    main()
