"""Figures of a user's own result (``passive-assoc initiate/associate --plot``): the sensors,
every report's line of sight in the x-y plane (coloured by its track or target, grey for
clutter), and the tracks or targets found. matplotlib is an optional dependency
(``pip install passive-assoc[plot]``), imported only when a figure is asked for."""

from __future__ import annotations

import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .data import MeasurementTable, SensorNetwork
from .fti import InitiationResult
from .plots import _pyplot

__all__ = ["plot_association", "plot_initiation"]


def _extent(sensors: SensorNetwork, points: NDArray[np.float64]) -> float:
    """A ray length that crosses the scene: twice its span, at least 10 km."""
    xy = np.vstack([sensors.positions[:, :2], points.reshape(-1, 2)]) if points.size else sensors.positions[:, :2]
    return float(max(2.0 * np.ptp(xy, axis=0).max(), 1e4))


def _rays(ax: Any, table: MeasurementTable, sensors: SensorNetwork, labels: NDArray[np.int64], length: float) -> None:
    start = sensors.positions[table.sensor, :2]
    end = start + length * np.column_stack([np.cos(table.azimuth), np.sin(table.azimuth)])
    for row in range(len(table)):
        label = int(labels[row])
        style = dict(color="0.75", lw=0.5) if label < 0 else dict(color=f"C{label % 10}", lw=0.8, alpha=0.6)
        ax.plot(*np.column_stack([start[row], end[row]]) / 1e3, **style)


def _finish(ax: Any, fig: Any, sensors: SensorNetwork, path: str | os.PathLike[str], title: str) -> None:
    ax.plot(*sensors.positions[:, :2].T / 1e3, "k^", ms=9, label="sensors")
    ax.plot([], [], color="0.75", lw=0.5, label="clutter / false alarms")
    ax.set(xlabel="x (km, east)", ylabel="y (km, north)", aspect="equal", title=title)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def plot_initiation(
    table: MeasurementTable, sensors: SensorNetwork, result: InitiationResult, path: str | os.PathLike[str]
) -> None:
    """Each initiated track's constant-velocity path over the file's times, on its rays."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 7))
    times = np.array([table.time.min(), table.time.max()]) - result.t0 if len(table) else np.zeros(2)
    paths = []
    for state in (t.state for t in result.tracks):
        half = len(state) // 2
        paths.append(state[None, :2] + times[:, None] * state[None, half : half + 2])
    points = np.array(paths) if paths else np.empty((0, 2, 2))
    length = _extent(sensors, points)
    _rays(ax, table, sensors, result.labels, length)
    for k, xy in enumerate(paths):
        ax.plot(*xy.T / 1e3, "-", color=f"C{k % 10}", lw=2.5, label=f"track {k}" if k < 10 else None)
        ax.plot(*xy[0] / 1e3, "o", color=f"C{k % 10}", ms=5)
    if len(paths):
        span = np.concatenate([points.reshape(-1, 2), sensors.positions[:, :2]]) / 1e3
        pad = 0.1 * max(np.ptp(span, axis=0).max(), 1.0)
        ax.set_xlim(span[:, 0].min() - pad, span[:, 0].max() + pad)
        ax.set_ylim(span[:, 1].min() - pad, span[:, 1].max() + pad)
    _finish(ax, fig, sensors, path, f"{len(paths)} track(s), {len(result.clutter)} clutter of {len(table)}")
    plt.close(fig)


def plot_association(
    table: MeasurementTable,
    sensors: SensorNetwork,
    labels: NDArray[np.int64],
    targets: list[dict[str, Any]],
    path: str | os.PathLike[str],
) -> None:
    """Every scan's located targets on their rays (all scans in one figure)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 7))
    points = np.array([t["position"][:2] for t in targets]) if targets else np.empty((0, 2))
    _rays(ax, table, sensors, labels, _extent(sensors, points))
    if len(points):
        ax.scatter(*points.T / 1e3, c=[f"C{k % 10}" for k in range(len(points))], s=40, zorder=3, label="targets")
        span = np.concatenate([points, sensors.positions[:, :2]]) / 1e3
        pad = 0.1 * max(np.ptp(span, axis=0).max(), 1.0)
        ax.set_xlim(span[:, 0].min() - pad, span[:, 0].max() + pad)
        ax.set_ylim(span[:, 1].min() - pad, span[:, 1].max() + pad)
    false_alarms = int(np.sum(labels < 0))
    _finish(ax, fig, sensors, path, f"{len(targets)} target(s), {false_alarms} false alarm(s) of {len(table)}")
    plt.close(fig)
