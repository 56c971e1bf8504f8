"""Many scans in one call (METHODS §2): :func:`associate_scans`.

A stream of scans associated with :func:`associate_static` one by one pays Python's overhead
and a crossing into Rust per scan, and uses one core per call on a small scan. Here the
whole table crosses once; the core enumerates and solves every scan on its own (the same
functions, so the same answer per scan) and runs the scans in parallel, with the GIL released.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._inputs import check_pair
from .._progress import ProgressArg, reporting
from ..assignment.sd import AUTO_BRANCH_BOUND_NODES
from ..data import MeasurementTable, SensorNetwork
from ..outcome import COMPLETED, Outcome
from .associator import DEFAULT_METHOD, Method, StaticAssociator, _associator
from .candidates import _per_sensor
from .scan_window import motion_inflated, window_scans

__all__ = ["ScanAssociation", "associate_scans", "scan_keys", "scan_rows"]


@dataclass(frozen=True, eq=False)
class ScanAssociation(Outcome):
    """Output of :func:`associate_scans`. Every input row is in exactly one target or is a
    false alarm (label −1).

    Attributes
    ----------
    termination, success, message
        As every result (:class:`~passive_assoc.outcome.Outcome`); ``"completed"`` when every
        scan was associated.
    scan : ndarray of int, shape (N,)
        Each row's scan index (scans ordered by their key).
    keys : ndarray, shape (n_scans,)
        The scan key (time, or the column's value) of each scan.
    labels : ndarray of int, shape (N,)
        Each row's target index over all scans, or −1.
    positions : ndarray, shape (T, ndim)
        Every target's ML position, scan by scan.
    target_scan : ndarray of int, shape (T,)
        The scan of each target.
    """

    scan: NDArray[np.int64]
    keys: NDArray[Any]
    labels: NDArray[np.int64]
    positions: NDArray[np.float64]
    target_scan: NDArray[np.int64]


def associate_scans(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    scan: str | ArrayLike = "time",
    method: Method = DEFAULT_METHOD,
    *,
    progress: ProgressArg = None,
    **settings: Any,
) -> ScanAssociation:
    """Associate every scan of a table in one call: per scan what :func:`associate_static`
    gives with the same settings, the scans in parallel in the core.

    Parameters
    ----------
    measurements, sensors
        The whole table and its network.
    scan : str or array_like
        Rows with equal values form a scan: ``"time"`` (default), the name of an attribute
        column, or one value per row. With ``scan_window`` among the settings and ``"time"``,
        reports within the window form a scan (:func:`window_scans`' rule; a scan's key is its
        opening time).
    method, **settings
        As :class:`StaticAssociator` (``n_threads`` sets the threads over scans). Not
        supported here: emitter ``attributes``, and ``exact_backend="highs"``. With
        ``method="exact"`` each scan takes the path :func:`associate_static` takes: the
        core's branch-and-bound, and with ``exact_backend="auto"`` (the default) a scan it
        does not prove within 50 000 nodes goes to HiGHS as there, so an equal-cost tie is
        broken the same way in both.
    progress : bool or callable, optional
        A progress bar over the scans on stderr: None shows it on a terminal once the call
        has run 2 s, True always, False never; a callable gets the reports instead,
        ``progress("scans", fraction)``, at most one every 0.2 s, on one of the call's threads;
        raising in it stops the call, and is raised.

    Examples
    --------
    >>> import numpy as np, passive_assoc as pa
    >>> from passive_assoc.simulation import static_scan
    >>> scans = [static_scan(seed, n_targets=4).measurements.to_arrays() for seed in (1, 2)]
    >>> columns = {k: np.concatenate([s[k] for s in scans]) for k in scans[0]}
    >>> columns["time"] = np.repeat([0.0, 1.0], [len(s["time"]) for s in scans])
    >>> table = pa.MeasurementTable.from_columns(columns)
    >>> out = pa.associate_scans(table, static_scan(1, n_targets=4).sensors, method="lagrangian")
    >>> out.keys.tolist(), int(out.labels.max()) + 1 == len(out.positions)
    ([0.0, 1.0], True)
    """
    associator = _associator(method, settings)
    table, network = check_pair(measurements, sensors)
    if associator.attributes:
        raise ValueError("attributes: associate_scans does not take emitter attributes; use associate_static")
    if associator.method == "exact" and associator.exact_backend == "highs":
        raise ValueError("exact_backend: associate_scans runs the core's branch-and-bound, not HiGHS")
    keys, scan_index = scan_keys(table, scan, window=associator.scan_window)
    if associator.v_max is not None and associator.min_range is not None and len(table):
        table = motion_inflated(table, network, scan_index, associator.v_max, associator.min_range)
    order, offsets = scan_rows(scan_index, len(keys))
    n = network.n_sensors
    density = None  # each scan's default, computed by the core from its reports
    if associator.false_alarm_density is not None:
        density = np.tile(
            _per_sensor("false_alarm_density", associator.false_alarm_density, n, 0.0, np.inf), (len(keys), 1)
        )
    auto_exact = associator.method == "exact" and associator.exact_backend == "auto"
    # "auto" as associate_static runs it: the branch-and-bound for at most its first nodes,
    # then (below) HiGHS on the scans those nodes do not prove.
    a = replace(associator, max_nodes=min(associator.max_nodes, AUTO_BRANCH_BOUND_NODES)) if auto_exact else associator
    with reporting(progress) as report:
        labels_in_order, per_scan, positions, node_limited = _core.associate_scans(
            table,
            network,
            order,
            offsets,
            _per_sensor("pd", a.pd, n, 0.0, 1.0),
            None if density is None else np.ascontiguousarray(density),
            a,
            report,
        )
    redo = np.flatnonzero(node_limited) if auto_exact else np.zeros(0, dtype=np.int64)
    if len(redo):
        labels_in_order, per_scan, positions = _resolved(
            (table, network, associator), (order, offsets), redo, (labels_in_order, per_scan, positions)
        )
    first_target = np.concatenate([[0], np.cumsum(per_scan)]).astype(np.int64)
    labels = np.full(len(table), -1, dtype=np.int64)
    found = labels_in_order >= 0
    labels[order[found]] = labels_in_order[found] + first_target[scan_index[order[found]]]
    return ScanAssociation(
        termination=COMPLETED,
        success=True,
        message=f"{len(keys)} scan(s) associated",
        scan=scan_index.astype(np.int64),
        keys=keys,
        labels=labels,
        positions=positions,
        target_scan=np.repeat(np.arange(len(keys), dtype=np.int64), per_scan),
    )


def _resolved(
    problem: tuple[MeasurementTable, SensorNetwork, StaticAssociator],
    scans: tuple[NDArray[np.int64], NDArray[np.int64]],
    redo: NDArray[np.int64],
    found: tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]],
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """The batch's answers with the scans ``redo`` associated by :meth:`StaticAssociator.associate`
    (HiGHS after the branch-and-bound's nodes), as :func:`associate_static` answers them."""
    table, network, associator = problem
    order, offsets = scans
    labels, per_scan, positions = found[0].copy(), found[1].copy(), found[2]
    blocks = np.split(positions, np.cumsum(per_scan)[:-1])
    for k in redo.tolist():
        rows = order[offsets[k] : offsets[k + 1]]
        answer = associator.associate(table.select(rows), network)
        labels[offsets[k] : offsets[k + 1]] = answer.labels
        per_scan[k], blocks[k] = len(answer.positions), answer.positions
    return labels, per_scan, np.concatenate(blocks).reshape(-1, positions.shape[1])


def scan_keys(
    table: MeasurementTable, scan: str | ArrayLike, name: str = "scan", window: float | None = None
) -> tuple[NDArray[Any], NDArray[np.int64]]:
    """The scans' keys (sorted) and each row's scan index: rows with equal ``scan`` values —
    ``"time"``, an attribute column's name, or one value per row — form a scan; with a
    ``window`` (seconds) and ``"time"``, the reports :func:`window_scans` groups. ``name`` is
    the argument errors name."""
    if isinstance(scan, str):
        if scan == "time" and window is not None:
            return window_scans(table.time, window)
        if scan == "time":
            values: NDArray[Any] = table.time
        elif scan in table.attributes:
            values = table.attributes[scan]
        else:
            raise ValueError(f"{name}: {scan!r} is not 'time' or an attribute column ({sorted(table.attributes)})")
    else:
        values = np.asarray(scan)
        if values.shape != (len(table),):
            raise ValueError(f"{name}: expected one value per row ({len(table)}), got shape {values.shape}")
    keys, index = np.unique(values, return_inverse=True)
    return keys, index.astype(np.int64)


def scan_rows(scan_index: NDArray[np.int64], n_scans: int) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The rows scan by scan (table order within a scan) and the scans' offsets into them:
    scan k is ``order[offsets[k]:offsets[k + 1]]``."""
    order = np.argsort(scan_index, kind="stable").astype(np.int64)
    offsets = np.searchsorted(scan_index[order], np.arange(n_scans + 1)).astype(np.int64)
    return order, offsets
