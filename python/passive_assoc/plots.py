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


def plot_topology(scenario: Any, record: dict[str, Any], path: str) -> None:
    """EXPERIMENTS ``topology``: the radars and two biased local pictures against the truth,
    one track's ring/sector grid with its neighbours, and F1 against bias for every method."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.6))
    _biased_pictures(axes[0], scenario)
    _one_grid(axes[1], scenario)
    for coverage, entry in record.items():
        rows = entry["rows"]
        bias = [row["bias_deg"] for row in rows]
        styles = {"paper rule": ":^", "topology": "-o", "fused": "-D", "nearest": "--s"}
        for method, style in styles.items():
            if method in rows[0]:
                axes[2].plot(bias, [row[method]["f1"] for row in rows], style, label=f"{method}, {coverage}")
    axes[2].axhline(99.7195, color="0.5", lw=0.8, ls=":", label="paper F1 (topology)")
    axes[2].set(xlabel="azimuth bias bound B (°)", ylabel="F1 (%)", title="F1 against bias", ylim=(0, 101))
    axes[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _biased_pictures(ax: Any, scenario: Any) -> None:
    """Truth trajectories, the radars, and one mid-run scan as the system radar and the radar
    whose bias differs most from it report it: the same targets, turned about each radar."""
    for track in scenario.true_positions:
        ax.plot(*track.T / 1e3, color="0.85", lw=0.8, zorder=1)
    positions = np.array([r.position for r in scenario.radars]) / 1e3
    ax.plot(*positions.T, "k^", ms=7, label="radars", zorder=3)
    mid = scenario.scan_times[len(scenario.scan_times) // 2]
    ax.plot(*scenario.true_positions[:, len(scenario.scan_times) // 2, :].T / 1e3, "kx", ms=6, label="truth at mid-run")
    m = scenario.measurements
    xy = m.to_cartesian() / 1e3
    relative = scenario.true_biases - scenario.true_biases[0]
    for k, radar in enumerate((0, int(np.argmax(np.abs(relative))))):
        rows = (m.radar == radar) & (m.time == mid)
        bias = np.degrees(scenario.true_biases[radar])
        ax.plot(*xy[rows].T, "o", ms=4, mfc="none", color=f"C{k}", label=f"radar {radar} (bias {bias:+.1f}°)", zorder=2)
    ax.set(xlabel="x (km)", ylabel="y (km)", aspect="equal", title="one scan in two biased pictures vs truth")
    ax.legend(fontsize=7, loc="center left", framealpha=0.7)


def _one_grid(ax: Any, scenario: Any) -> None:
    """The reference-topology grid of the first formation's lead target at mid-run, from the
    truth positions of that scan (the default associator's rings and sectors)."""
    from .data import TrackTable
    from .topology import TopologyAssociator, topology_vectors

    associator = TopologyAssociator()
    c = associator
    mid = scenario.true_positions.shape[1] // 2
    points = scenario.true_positions[:, mid, :]
    lead = int(np.flatnonzero(scenario.formation >= 0)[0])
    n = len(points)
    table = TrackTable.from_arrays(np.zeros(n, np.int64), np.arange(n), np.zeros(n), points)
    values = topology_vectors(table, associator)[lead].reshape(c.rings, c.sectors)
    centre = points[lead] / 1e3
    radius = c.radius / 1e3
    # Cells as wedges shaded by their value; sector 0 starts at north, clockwise.
    from matplotlib.patches import Wedge

    for ring in range(c.rings):
        for sector in range(c.sectors):
            theta1 = 90 - (sector + 1) * 360 / c.sectors  # matplotlib: counter-clockwise from +x
            wedge = Wedge(
                tuple(centre),
                (ring + 1) * radius / c.rings,
                theta1,
                theta1 + 360 / c.sectors,
                width=radius / c.rings,
                facecolor=plt_gray(values[ring, sector]),
                edgecolor="0.6",
                lw=0.5,
            )
            ax.add_patch(wedge)
    others = np.delete(points, lead, axis=0) / 1e3
    ax.plot(*others.T, "k.", ms=5, label="other targets")
    ax.plot(*centre, "r*", ms=10, label="the track")
    ax.set(
        xlim=(centre[0] - 1.1 * radius, centre[0] + 1.1 * radius),
        ylim=(centre[1] - 1.1 * radius, centre[1] + 1.1 * radius),
        aspect="equal",
        xlabel="x (km)",
        ylabel="y (km)",
        title=f"{c.rings} rings × {c.sectors} sectors, Δ={c.delta}, Δ′={c.delta_prime} (darker = higher)",
    )
    ax.legend(fontsize=7, loc="lower left")


def plt_gray(value: float) -> str:
    """A matplotlib grey for a cell value in [0, 1]: 1 = dark."""
    return str(round(1.0 - 0.8 * float(value), 3))


def plot_wavelet(
    tracks: tuple[Any, Any], record: dict[str, Any], path: str, passive: tuple[Any, Any, Any] | None = None
) -> None:
    """EXPERIMENTS ``wavelet``: one run's radar (solid) and ESM (dashed) tracks of the ten
    targets, x against time; the correct-association probability against scan for the three
    methods (no clutter solid, the most clutter dotted; the paper's ranges shaded); and, given
    ``passive = (radar, passive tracks, ESM sites)``, the 2-D demo's tracks in the plane."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 3 if passive is not None else 2, figsize=(17 if passive is not None else 12, 5.4))
    _wavelet_tracks(axes[0], *tracks)
    levels = record["levels"]
    first, last = min(levels, key=int), max(levels, key=int)
    ax = axes[1]
    for (lo, hi), colour in ((record["paper"]["wavelet"], "C0"), (record["paper"]["nearest"], "C1")):
        ax.fill_between([6, 30], lo, hi, color=colour, alpha=0.12, lw=0)  # the paper's range, scans 6-30
    for k, (method, label) in enumerate(
        (("wavelet", "wavelet-fuzzy"), ("nearest", "nearest neighbour"), ("chi2", "χ² test"))
    ):
        for level, style in ((first, "-"), (last, ":")) if first != last else ((first, "-"),):
            values = np.asarray(levels[level][method]["per_scan"], dtype=float)
            ax.plot(np.arange(1, len(values) + 1), values, style, color=f"C{k}", label=f"{label}, {level} false")
    ax.set(xlabel="scan", ylabel="P(correct association)", ylim=(0, 1.02), title="correct association per scan")
    ax.legend(fontsize=7, loc="lower right")
    if passive is not None:
        _wavelet_plane(axes[2], *passive)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _wavelet_tracks(ax: Any, radar: Any, esm: Any) -> None:
    for table, style, name in ((radar, "-", "radar"), (esm, "--", "ESM")):
        for _, _, rows in table.tracks():
            label = int(table.truth[rows[0]])
            colour = f"C{label % 10}" if label >= 0 else "0.6"
            ax.plot(table.time[rows], table.position[rows, 0] / 1e3, style, color=colour, lw=1.2)
        ax.plot([], [], style, color="k", label=f"{name} tracks")
    ax.set(xlabel="time (s)", ylabel="x (km)", title="one run: the ten targets' tracks from both sensors")
    ax.legend(fontsize=8)


def _wavelet_plane(ax: Any, radar: Any, passive: Any, sites: Any) -> None:
    for table, style in ((radar, "-"), (passive, "--")):
        for _, _, rows in table.tracks():
            colour = f"C{int(table.truth[rows[0]]) % 10}"
            ax.plot(*table.position[rows].T / 1e3, style, color=colour, lw=1.2)
    ax.plot(*np.asarray(sites).T / 1e3, "k^", ms=8, label="ESM sites")
    ax.plot([], [], "k-", label="radar tracks")
    ax.plot([], [], "k--", label="passive tracks (bearing fixes)")
    ax.set(xlabel="x (km)", ylabel="y (km)", aspect="equal", title="2-D demo: radar against passive tracks")
    ax.legend(fontsize=7)
