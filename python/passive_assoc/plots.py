"""Figures for the paper reproductions. matplotlib is an optional dependency
(``pip install passive-assoc[plot]``); it is imported only when a figure is asked for."""

from __future__ import annotations

from typing import Any

import numpy as np

from .fti import InitiationResult
from .simulation import Scenario
from .static_los.associator import Method


def _pyplot() -> Any:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as err:  # pragma: no cover - depends on the environment
        raise ImportError("plots need matplotlib: pip install 'passive-assoc[plot]'") from err
    return plt


def _rays(ax: Any, scenario: Scenario, length: float) -> None:
    """Every measurement's line of sight in the x-y plane: clutter grey, targets coloured."""
    m, pos = scenario.measurements, scenario.sensors.positions
    truth = m.truth if m.truth is not None else np.full(len(m), -1)
    for row in range(len(m)):
        start = pos[m.sensor[row], :2]
        end = start + length * np.array([np.cos(m.azimuth[row]), np.sin(m.azimuth[row])])
        style = (
            dict(color="0.8", lw=0.4, zorder=1)
            if truth[row] < 0
            else dict(color=f"C{truth[row]}", lw=0.5, alpha=0.5, zorder=2)
        )
        ax.plot([start[0], end[0]], [start[1], end[1]], **style)


def plot_fti(scenario: Scenario, result: InitiationResult, summary: dict[str, Any], path: str) -> None:
    """Left: top view of one run — sensors, lines of sight (clutter grey), true tracks (solid)
    and initiated tracks (dashed). Right: per-target RMS with own and perfect association
    against the CRLB std, for x0 and y0."""
    plt = _pyplot()
    fig, (ax, bars) = plt.subplots(1, 2, figsize=(13, 5.5))
    times = np.concatenate(scenario.scan_times)
    span = np.array([times.min(), times.max()]) - scenario.t0
    _rays(ax, scenario, length=30e3)
    for k, state in enumerate(scenario.true_states):
        xy = state[:2] + span[:, None] * state[3:5]
        ax.plot(xy[:, 0], xy[:, 1], color=f"C{k}", lw=2.5, label=f"target {k + 1}", zorder=3)
    for j, track in enumerate(result.tracks):
        xy = track.state[:2] + span[:, None] * track.state[3:5]
        ax.plot(xy[:, 0], xy[:, 1], "k--", lw=1.5, zorder=4, label="initiated" if j == 0 else None)
        ax.plot(*xy[0], "ko", ms=3, zorder=4)
    ax.plot(*scenario.sensors.positions[:, :2].T, "k^", ms=9, label="sensors", zorder=5)
    ax.set(
        xlim=(-3e3, 24e3),
        ylim=(-2e3, 20e3),
        xlabel="x (m)",
        ylabel="y (m)",
        aspect="equal",
        title=f"run 0: {len(result.tracks)} tracks, {len(result.clutter)} clutter of {len(scenario.measurements)}",
    )
    ax.legend(loc="upper right", fontsize=8)
    n = summary["rms_own"].shape[0]
    idx = np.arange(n)
    for c, (comp, shift) in enumerate((("x0", 0.0), ("y0", 0.45))):
        base = idx + shift
        bars.bar(base - 0.14, summary["rms_own"][:, c], 0.14, color=f"C{c}", label=f"{comp} own association")
        bars.bar(
            base, summary["rms_perfect"][:, c], 0.14, color=f"C{c}", alpha=0.5, label=f"{comp} perfect association"
        )
        bars.bar(
            base + 0.14, summary["crlb_std"][:, c], 0.14, color="none", edgecolor=f"C{c}", label=f"{comp} CRLB std"
        )
    bars.set(
        xticks=idx + 0.22,
        xticklabels=[f"target {k + 1}" for k in idx],
        ylabel="RMS (m)",
        title=f"RMS of X0 over {summary['runs']} runs",
    )
    bars.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_static_scan(scan: Any, path: str) -> None:
    """One static scan: every line of sight (false bearings grey), every gated candidate
    coloured by its intensity (lines of sight through it), the true targets, and the points
    each method accepts."""
    from .static_los import associate_static, enumerate_candidates

    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 8))
    m, pos = scan.measurements, scan.sensors.positions
    for row in range(len(m)):
        start = pos[m.sensor[row], :2]
        end = start + 60e3 * np.array([np.cos(m.azimuth[row]), np.sin(m.azimuth[row])])
        ax.plot([start[0], end[0]], [start[1], end[1]], color="0.75" if m.truth[row] < 0 else "0.45", lw=0.5, zorder=1)
    cands = enumerate_candidates(m, scan.sensors)
    for level, marker in ((2, "."), (scan.sensors.n_sensors, "o")):
        sel = cands.intensity == level
        ax.scatter(
            *cands.positions[sel].T,
            s=12 if level == 2 else 22,
            marker=marker,
            label=f"intensity-{level} candidates ({int(sel.sum())})",
            zorder=2,
            alpha=0.7,
        )
    ax.scatter(*scan.targets.T, s=140, facecolors="none", edgecolors="k", lw=1.5, label="true targets", zorder=3)
    methods: tuple[tuple[Method, str], ...] = (("intensity", "x"), ("lagrangian", "+"), ("exact", "1"))
    for k, (method, marker) in enumerate(methods):
        out = associate_static(m, scan.sensors, method, time_limit=2.0)
        ax.scatter(*out.positions.T, s=90, marker=marker, color=f"C{k + 3}", label=f"accepted: {method}", zorder=4)
    ax.plot(*pos[:, :2].T, "k^", ms=9, label="sensors", zorder=5)
    ax.set(
        xlim=(-16e3, 16e3),
        ylim=(-7e3, 45e3),
        xlabel="x (m)",
        ylabel="y (m)",
        aspect="equal",
        title=f"one scan: {len(scan.targets)} targets, {len(m)} bearings, {len(cands.costs)} candidates",
    )
    ax.legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
