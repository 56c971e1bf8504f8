"""The figure of ``passive-assoc reproduce formation --plot``: one paper-mode run at σθ = 1°
(its lines of sight, the baseline meetings coloured by attribute support, the joint method's
choices) and every method's correct-association rate against σθ."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..evidence import simple_support_assoc
from ..formation import locate_formation
from ..plots import _pyplot
from ..simulation.formation import PAPER_SIGMAS_DEG, FormationScene

#: Length of the drawn lines of sight, metres (the targets are 90–110 km away).
RAY_LENGTH = 160e3
#: The zoomed panel around the formation: (x_min, x_max, y_min, y_max), km.
ZOOM_KM = (-68.0, 8.0, 45.0, 82.0)
ETA = 0.6


def baseline_meetings(scene: FormationScene, baseline: int = 0) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Every intersection of a baseline line of sight with a line of another sensor (full
    lines, as METHODS §3 step 1) and its Dempster ``m(assoc)`` of the two reports' eq. 3
    supports: points (P, 2) in metres and supports (P,). Parallel pairs are left out."""
    m, pos = scene.measurements, scene.sensors.positions[:, :2]
    u = np.column_stack([np.cos(m.azimuth), np.sin(m.azimuth)])
    names = list(scene.attribute_std)
    attrs = np.column_stack([m.attributes[n] for n in names])
    std = np.array([scene.attribute_std[n] for n in names])
    base = np.flatnonzero(m.sensor == baseline)
    other = np.flatnonzero(m.sensor != baseline)
    a, b = np.repeat(base, len(other)), np.tile(other, len(base))
    pa, pb = pos[m.sensor[a]], pos[m.sensor[b]]
    cross = u[a, 0] * u[b, 1] - u[a, 1] * u[b, 0]
    keep = np.abs(cross) > 1e-12
    w = pb - pa
    r = (w[:, 0] * u[b, 1] - w[:, 1] * u[b, 0]) / np.where(keep, cross, 1.0)
    points = pa + r[:, None] * u[a]
    s = np.exp(-((attrs[a] - attrs[b]) ** 2) / (2 * (2 * std**2)))  # eq. 3, both reports with std σ_k
    support = np.array([simple_support_assoc(row) for row in s])
    return points[keep], support[keep]


def _scene_panel(ax: Any, scene: FormationScene, zoom: bool) -> Any:
    """Lines of sight coloured by true target, sensors, targets; in the zoom also the meetings
    and the joint method's chosen positions (wrong ones crossed in red). Returns the meetings'
    scatter (for a colour bar) or None."""
    m, pos = scene.measurements, scene.sensors.positions[:, :2]
    truth = np.asarray(m.truth)  # a simulated scene always carries it
    for row in range(len(m)):
        end = pos[m.sensor[row]] + RAY_LENGTH * np.array([np.cos(m.azimuth[row]), np.sin(m.azimuth[row])])
        xy = np.vstack([pos[m.sensor[row]], end]) / 1e3
        ax.plot(*xy.T, color=f"C{int(truth[row])}", lw=0.6, alpha=0.6, zorder=1)
    ax.plot(*pos.T / 1e3, "k^", ms=9, label="sensors", zorder=5)
    ax.scatter(*scene.targets.T / 1e3, s=120, facecolors="none", edgecolors="k", lw=1.4, label="true targets", zorder=4)
    if not zoom:
        ax.set(xlabel="x (km)", ylabel="y (km)", aspect="equal", title="paper mode, σθ = 1°, one run: lines of sight")
        ax.legend(fontsize=8, loc="upper right")
        return None
    points, support = baseline_meetings(scene)
    kept = support >= ETA
    dots = ax.scatter(*points[kept].T / 1e3, c=support[kept], s=22, vmin=0, vmax=1, cmap="viridis", zorder=3)
    ax.scatter(*points[~kept].T / 1e3, c=support[~kept], s=14, marker="x", lw=0.8, vmin=0, vmax=1, cmap="viridis")
    _chosen(ax, scene)
    x0, x1, y0, y1 = ZOOM_KM
    ax.set(xlim=(x0, x1), ylim=(y0, y1), xlabel="x (km)", ylabel="y (km)", aspect="equal")
    ax.set_title(f"baseline meetings (dots: m(assoc) ≥ η = {ETA:g}, ×: pruned)", fontsize=10)
    ax.legend(fontsize=7, loc="lower left")
    return dots


def _chosen(ax: Any, scene: FormationScene) -> None:
    out = locate_formation(scene.measurements, scene.sensors, attribute_std=scene.attribute_std, n_threads=1)
    true = scene.true_tuples()
    right = np.array([np.array_equal(out.rows[b], true[t]) for t, b in enumerate(out.baseline_rows)])
    ax.plot(*out.positions[right].T / 1e3, "k+", ms=11, mew=1.8, label="joint method: correct", zorder=6)
    ax.plot(*out.positions[~right].T / 1e3, "rx", ms=11, mew=2, label="joint method: wrong", zorder=6)


def _rates_panel(ax: Any, results: dict[str, NDArray[np.float64]], labels: Sequence[str]) -> None:
    for noise, r in results.items():
        style = "-o" if noise == "paper" else "--s"
        for k, label in enumerate(labels):
            mean = r[k].mean(axis=1)
            # Wider lines first: a method drawn later over an identical one leaves it visible.
            width = 2.6 - 0.25 * k
            ax.plot(
                PAPER_SIGMAS_DEG, mean, style, color=f"C{k}", lw=width, ms=4, label=label if noise == "paper" else None
            )
    ax.plot([], [], "k-o", ms=4, label="paper noise")
    ax.plot([], [], "k--s", ms=4, label="realistic noise")
    ax.set(xlabel="σθ (°)", ylabel="correct association, mean over targets (%)", ylim=(0, 101))
    ax.set_title("correct association against σθ", fontsize=10)
    ax.legend(fontsize=7, loc="lower left")


def plot_formation(
    scene: FormationScene, results: dict[str, NDArray[np.float64]], labels: Sequence[str], path: str
) -> None:
    """Save three panels to ``path``: the run's geometry, its baseline meetings around the
    formation, and the rates of every method against σθ (``results``: noise mode -> rates
    (methods, σθ, targets) in %; ``labels``: the methods' titles, in that order)."""
    plt = _pyplot()
    # The whole geometry is tall and narrow: a left column of its own; the zoom and the rates
    # are wide and share the right column.
    fig = plt.figure(figsize=(15, 10), layout="constrained")
    grid = fig.add_gridspec(2, 2, width_ratios=[1.0, 1.7])
    _scene_panel(fig.add_subplot(grid[:, 0]), scene, zoom=False)
    zoom = fig.add_subplot(grid[0, 1])
    dots = _scene_panel(zoom, scene, zoom=True)
    fig.colorbar(dots, ax=zoom, shrink=0.9, label="m(assoc) with the baseline report")
    _rates_panel(fig.add_subplot(grid[1, 1]), results, labels)
    fig.savefig(path, dpi=120)
    plt.close(fig)
