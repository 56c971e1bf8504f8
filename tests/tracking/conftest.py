"""Two simulated passive scenes for the trackers (not the papers'), and the figures the tests
read from a tracker's answer, handed to the tests as fixtures."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.data import SensorTrack
from passive_assoc.simulation import ConstantVelocityTarget, Scenario, simulate


def coastal_scene(seed: int) -> Scenario:
    """Four bearing-only ESM sites (0.15–0.3°), one of them airborne at 60 m/s, five ships at
    3–9 m/s; each site reports every 12 s, the sites 0.5 s apart, for 9.5 minutes, Pd 0.85,
    two false bearings per site and scan."""
    sites = [[0.0, 0.0], [30e3, -5e3], [55e3, 10e3], [20e3, 40e3]]
    network = pa.SensorNetwork.planar(sites, np.radians([0.15, 0.2, 0.15, 0.3]))
    ships = [
        ConstantVelocityTarget([10e3, 20e3, 6.0, 2.0]),
        ConstantVelocityTarget([35e3, 25e3, -5.0, -3.0]),
        ConstantVelocityTarget([25e3, 10e3, 3.0, 6.0]),
        ConstantVelocityTarget([40e3, 30e3, 0.0, -8.0]),
        ConstantVelocityTarget([15e3, 5e3, 9.0, 0.5]),
    ]
    aircraft = SensorTrack.constant_velocity([3], [[20e3, 40e3]], [[60.0, 0.0]], 0.0, 600.0)
    times = [np.arange(48) * 12.0 + 0.5 * j for j in range(4)]
    return simulate(network, ships, times, pd=0.85, clutter_per_scan=2, t0=0.0, platforms=aircraft, seed=seed)


def air_scene(seed: int) -> Scenario:
    """Three azimuth-elevation sensors (1 mrad), three aircraft at 90–120 m/s between 1.5 and
    6 km up; each sensor reports every 2 s, 0.3 s apart, for 2 minutes, Pd 0.9, two false
    reports per sensor and scan."""
    network = pa.SensorNetwork.spatial([[0.0, 0.0, 10.0], [25e3, 0.0, 50.0], [10e3, 30e3, 0.0]], 1e-3, 1e-3)
    aircraft = [
        ConstantVelocityTarget([5e3, 15e3, 3e3, 120.0, 10.0, 0.0]),
        ConstantVelocityTarget([20e3, 20e3, 6e3, -90.0, -60.0, 0.0]),
        ConstantVelocityTarget([15e3, 5e3, 1.5e3, 30.0, 110.0, 2.0]),
    ]
    times = [np.arange(60) * 2.0 + 0.3 * j for j in range(3)]
    return simulate(network, aircraft, times, pd=0.9, clutter_per_scan=2, t0=0.0, seed=seed)


def figures(scene: Scenario, tracks: pa.TrackTable, labels: np.ndarray) -> dict[str, Any]:
    """Per track: its target (the one most of its reports come from), the share of that
    target's reports after the track started that went to it, how many of its reports are not
    its target's, its last time and its last position's distance to its target. Overall: the
    share of the targets' reports in a track and of the false ones."""
    truth, time = scene.measurements.truth, scene.measurements.time
    assert truth is not None
    per_track = {}
    for k in np.unique(tracks.track).tolist():
        mine = labels == k
        target = int(np.bincount(truth[mine][truth[mine] >= 0]).argmax())
        lived = tracks.track == k
        later = (truth == target) & (time > tracks.time[lived].min())
        last = int(np.flatnonzero(lived)[np.argmax(tracks.time[lived])])
        where = scene.targets[target].position(np.array([tracks.time[last]]))[0]
        per_track[k] = {
            "target": target,
            "later_share": float(np.mean(labels[later] == k)),
            "wrong": int(np.sum(mine & (truth != target))),
            "last_time": float(tracks.time[last]),
            "last_error": float(np.linalg.norm(tracks.position[last] - where)),
        }
    real = truth >= 0
    return {
        "tracks": per_track,
        "true_in_track": float(np.mean(labels[real] >= 0)),
        "false_in_track": float(np.mean(labels[~real] >= 0)),
    }


@pytest.fixture(scope="package")
def coastal() -> Scenario:
    return coastal_scene(seed=0)


@pytest.fixture(scope="package")
def air() -> Scenario:
    return air_scene(seed=0)


@pytest.fixture(scope="package")
def tracker_figures() -> Callable[[Scenario, pa.TrackTable, np.ndarray], dict[str, Any]]:
    return figures
