"""Past one machine with Dask (optional extra ``dask``).

* ``passive-assoc reproduce ... --scheduler ADDRESS`` (or ``--scheduler local`` for a
  :class:`distributed.LocalCluster` of processes) runs an experiment's Monte-Carlo runs on a
  Dask cluster. Every run is seeded by its index (:func:`..experiments.common.run_seeds`),
  so a distributed run prints what a local run with the same seed prints.
* :func:`associate_scans_on` spreads :func:`~passive_assoc.associate_scans` over a cluster,
  a block of scans per task, and returns what one local call returns.
* :func:`associate_parquet` associates a folder of Parquet partitions (each holding whole
  scans) partition by partition and writes one result file per partition; a worker reads
  and writes its own partition, so memory is bounded by a partition's size.

Runs are sent in chunks (default 8 per task) so that a task's scheduling overhead, about a
millisecond, is small beside its work.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from .data import MeasurementTable, SensorNetwork
from .outcome import COMPLETED
from .static_los.batch import ScanAssociation, associate_scans, scan_keys, scan_rows

__all__ = ["associate_parquet", "associate_scans_on", "client_for", "current_client", "map_on_client", "using"]

R = TypeVar("R")

#: The client experiments' runs go to (None: run here).
_CLIENT: contextvars.ContextVar[Any | None] = contextvars.ContextVar("passive_assoc_dask_client", default=None)

#: Runs per Dask task.
RUNS_PER_TASK = 8


def _distributed() -> Any:
    try:
        import distributed
    except ImportError as err:
        raise ImportError("--scheduler needs Dask: pip install 'passive-assoc[dask]'") from err
    return distributed


def client_for(address: str) -> Any:
    """A Dask client: ``"local"`` starts a :class:`distributed.LocalCluster` of processes,
    anything else is a scheduler address (``tcp://host:8786``)."""
    distributed = _distributed()
    if address == "local":
        return distributed.Client(distributed.LocalCluster(processes=True, dashboard_address=None))
    return distributed.Client(address)


@contextlib.contextmanager
def using(client: Any | None) -> Iterator[Any | None]:
    """Within the block, experiments' runs go to ``client`` (None: run here)."""
    token = _CLIENT.set(client)
    try:
        yield client
    finally:
        _CLIENT.reset(token)


def current_client() -> Any | None:
    return _CLIENT.get()


def _run_chunk(work: Callable[[int], R], chunk: list[int]) -> list[R]:
    return [work(r) for r in chunk]


def map_on_client(
    client: Any, work: Callable[[int], R], runs: int, progress: Callable[[int], None] | None = None
) -> list[R]:
    """``[work(r) for r in range(runs)]`` on the cluster, in run order."""
    chunks = [list(range(start, min(start + RUNS_PER_TASK, runs))) for start in range(0, runs, RUNS_PER_TASK)]
    futures = [client.submit(_run_chunk, work, chunk, pure=False) for chunk in chunks]
    out: list[R] = []
    for future, chunk in zip(futures, chunks, strict=True):
        out.extend(future.result())
        if progress is not None:
            progress(len(chunk))
    return out


def associate_scans_on(
    client: Any,
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    scan: Any = "time",
    scans_per_task: int = 256,
    **settings: Any,
) -> ScanAssociation:
    """:func:`~passive_assoc.associate_scans` with its scans spread over ``client``,
    ``scans_per_task`` a task; the same result as one local call."""
    keys, scan_index = scan_keys(measurements, scan)
    order, offsets = scan_rows(scan_index, len(keys))
    starts = range(0, len(keys), scans_per_task)
    blocks = [np.arange(start, min(start + scans_per_task, len(keys))) for start in starts]
    parts = []
    for block in blocks:
        rows = order[offsets[block[0]] : offsets[block[-1] + 1]]
        task = client.submit(associate_scans, measurements.select(rows), sensors, scan_index[rows], **settings)
        parts.append((rows, task))
    labels = np.full(len(measurements), -1, dtype=np.int64)
    positions, target_scan = [], []
    first_target = 0
    for (rows, future), block in zip(parts, blocks, strict=True):
        part: ScanAssociation = future.result()
        inside = part.labels >= 0
        labels[rows[inside]] = part.labels[inside] + first_target
        positions.append(part.positions)
        target_scan.append(block[part.target_scan])
        first_target += len(part.positions)
    return ScanAssociation(
        termination=COMPLETED,
        success=True,
        message=f"{len(keys)} scan(s) associated",
        scan=scan_index,
        keys=keys,
        labels=labels,
        positions=np.concatenate(positions) if positions else np.empty((0, sensors.ndim)),
        target_scan=np.concatenate(target_scan).astype(np.int64) if target_scan else np.empty(0, np.int64),
    )


def associate_parquet(
    folder: str | os.PathLike[str],
    sensors: SensorNetwork,
    out: str | os.PathLike[str],
    *,
    client: Any | None = None,
    scan: str = "time",
    **settings: Any,
) -> list[dict[str, Any]]:
    """Associates every ``*.parquet`` partition of ``folder`` (each holding whole scans:
    a scan split over two files would be two scans), on ``client`` or here, and writes
    ``out/<name>.parquet``: every input row once, with ``row``, ``scan`` (the scan's key) and
    ``target`` (its target within the partition, −1 for a false alarm); and
    ``out/<name>.targets.parquet``: each target's scan key and position. Returns per
    partition its name and row, scan and target counts."""
    paths = sorted(Path(folder).glob("*.parquet"))
    if not paths:
        raise ValueError(f"folder: no *.parquet files in {os.fspath(folder)!r}")
    target = Path(out)
    target.mkdir(parents=True, exist_ok=True)
    jobs = [(path, target / path.name, target / f"{path.stem}.targets.parquet") for path in paths]
    if client is None:
        return [_associate_partition(*job, sensors, scan, settings) for job in jobs]
    futures = [client.submit(_associate_partition, *job, sensors, scan, settings, pure=False) for job in jobs]
    return [future.result() for future in futures]


def _associate_partition(
    source: Path, rows_out: Path, targets_out: Path, sensors: SensorNetwork, scan: str, settings: dict[str, Any]
) -> dict[str, Any]:
    from .data._io import write_atomically
    from .data.measurement_files import write_parquet

    table = MeasurementTable.from_parquet(source)
    found = associate_scans(table, sensors, scan, **{**settings, "progress": False})  # a worker: no bar
    columns = {
        "row": np.arange(len(table), dtype=np.int64),
        "sensor": table.sensor,
        "time": table.time,
        "azimuth": table.azimuth,
        "scan": found.keys[found.scan],
        "target": found.labels,
    }
    if table.ndim == 3:
        columns["elevation"] = table.elevation
    write_atomically(rows_out, lambda p: write_parquet(p, columns))
    axes = "xyz"[: found.positions.shape[1]]
    positions = {axis: found.positions[:, k] for k, axis in enumerate(axes)}
    targets = {"target": np.arange(len(found.positions)), "scan": found.keys[found.target_scan], **positions}
    write_atomically(targets_out, lambda p: write_parquet(p, targets))
    return {"partition": source.name, "rows": len(table), "scans": len(found.keys), "targets": len(found.positions)}
