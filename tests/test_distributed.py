"""Dask: a distributed run equals a local run with the same seed (``reproduce fti --runs 20``
on a two-worker LocalCluster of processes), and ``associate_scans_on`` equals one local
``associate_scans``. Skipped without the ``dask`` extra (CI installs it)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")

import passive_assoc as pa  # noqa: E402
from passive_assoc.cli import main as cli_main  # noqa: E402
from passive_assoc.distributed import associate_scans_on  # noqa: E402
from passive_assoc.simulation import static_scan  # noqa: E402


@pytest.fixture(scope="module")
def client() -> Iterator[Any]:
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    with distributed.Client(cluster) as dask_client:
        yield dask_client
    cluster.close()


def test_reproduce_fti_on_a_cluster_equals_the_local_run(tmp_path: Path, client: Any) -> None:
    local, remote = tmp_path / "local.json", tmp_path / "remote.json"
    args = ["reproduce", "fti", "--runs", "20", "--seed", "3"]
    assert cli_main([*args, "--json", str(local)]) == 0
    assert cli_main([*args, "--json", str(remote), "--scheduler", client.scheduler.address]) == 0
    a, b = json.loads(local.read_text()), json.loads(remote.read_text())
    for record in (a, b):
        record.pop("median_seconds_per_run")  # wall time differs, nothing else may
    assert a == b and a["runs"] == 20 and len(a["found_per_run"]) == 20


def test_associate_scans_on_a_cluster_equals_one_local_call(client: Any) -> None:
    scans = [static_scan(seed, n_targets=5).measurements.to_arrays() for seed in range(30)]
    columns = {k: np.concatenate([s[k] for s in scans]) for k in scans[0]}
    columns["time"] = np.repeat(np.arange(30.0), [len(s["time"]) for s in scans])
    table, sensors = pa.MeasurementTable.from_columns(columns), static_scan(0, n_targets=5).sensors
    local = pa.associate_scans(table, sensors, method="lagrangian")
    remote = associate_scans_on(client, table, sensors, scans_per_task=7, method="lagrangian")
    np.testing.assert_array_equal(remote.labels, local.labels)
    np.testing.assert_array_equal(remote.positions, local.positions)
    np.testing.assert_array_equal(remote.target_scan, local.target_scan)
    np.testing.assert_array_equal(remote.scan, local.scan)


def test_a_parquet_folder_is_associated_partition_by_partition(tmp_path: Path, client: Any) -> None:
    """Three partitions of whole scans: every input row once in its partition's output, the
    same files whether the partitions ran here or on the cluster."""
    pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq
    from passive_assoc.distributed import associate_parquet

    sensors = static_scan(0, n_targets=5).sensors
    inputs = tmp_path / "in"
    inputs.mkdir()
    for part in range(3):
        scans = [static_scan(10 * part + k, n_targets=5).measurements.to_arrays() for k in range(4)]
        columns = {k: np.concatenate([s[k] for s in scans]) for k in scans[0]}
        columns["time"] = np.repeat(np.arange(4.0) + 4 * part, [len(s["time"]) for s in scans])
        pa.MeasurementTable.from_columns(columns).to_parquet(inputs / f"part{part}.parquet")
    here = associate_parquet(inputs, sensors, tmp_path / "here", method="lagrangian")
    there = associate_parquet(inputs, sensors, tmp_path / "there", client=client, method="lagrangian")
    assert here == there and [p["scans"] for p in here] == [4, 4, 4]
    for part in range(3):
        rows = pq.read_table(tmp_path / "here" / f"part{part}.parquet").to_pydict()
        again = pq.read_table(tmp_path / "there" / f"part{part}.parquet").to_pydict()
        assert rows == again
        n = len(pa.MeasurementTable.from_parquet(inputs / f"part{part}.parquet"))
        assert (rows["row"] == list(range(n)) and min(rows["target"]) == -1) or len(set(rows["target"])) > 1
        targets = pq.read_table(tmp_path / "here" / f"part{part}.targets.parquet").to_pydict()
        assert set(rows["target"]) - {-1} == set(targets["target"])
