"""Helpers shared across the test modules.

Each is a plain function, handed to tests by a session-scoped fixture of the same name
(session scope, so that hypothesis tests may use them too).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence

import numpy as np
import passive_assoc as pa
import pytest
from numpy.typing import NDArray
from passive_assoc.simulation import StaticScan, static_scan

# --------------------------------------------------------------------------- partition


def check_partition(
    groups: Sequence[NDArray[np.int64]], rest: NDArray[np.int64], labels: NDArray[np.int64], n_rows: int
) -> None:
    """Every row ``0..n_rows-1`` is in exactly one of ``groups`` or in ``rest``, and ``labels``
    gives each grouped row its group's index."""
    joined = np.concatenate([*groups, rest]).astype(np.int64)
    assert len(np.unique(joined)) == len(joined), "a row is in two places"
    assert np.array_equal(np.sort(joined), np.arange(n_rows)), "a row is lost"
    for k, rows in enumerate(groups):
        assert np.all(labels[rows] == k)


def assert_partition_of(result: pa.InitiationResult | pa.StaticAssociation, n_rows: int) -> None:
    """Every measurement ends in exactly one output: one track (tuple) or the clutter (false
    alarms), for a track initiation or a static association."""
    if isinstance(result, pa.InitiationResult):
        check_partition([t.measurements for t in result.tracks], result.clutter, result.labels, n_rows)
    elif isinstance(result, pa.StaticAssociation):
        groups = [rows[rows >= 0] for rows in result.rows]
        check_partition(groups, result.clutter, result.labels, n_rows)
    else:  # pragma: no cover - a test's mistake
        raise TypeError(f"no partition check for {type(result).__name__}")


@pytest.fixture(scope="session")
def assert_partition() -> Callable[[pa.InitiationResult | pa.StaticAssociation, int], None]:
    return assert_partition_of


# --------------------------------------------------------------------------- noiseless data


def noiseless_table_of(
    sensors: pa.SensorNetwork, state: NDArray[np.float64], times: NDArray[np.float64], which: NDArray[np.int64]
) -> pa.MeasurementTable:
    """Exact angles of a constant-velocity target (t0 = 0) seen by sensor `which[k]` at `times[k]`."""
    d = sensors.ndim
    pos = state[:d] + times[:, None] * state[d:]
    rel = pos - sensors.positions[which, :d]
    az = np.arctan2(rel[:, 1], rel[:, 0])
    el = np.arctan2(rel[:, 2], np.hypot(rel[:, 0], rel[:, 1])) if d == 3 else None
    return pa.MeasurementTable.from_arrays(which, times, az, el)


def scenario_with_nominal_sigma(scenario: pa.Scenario, sigma: float) -> pa.Scenario:
    """The same (noiseless) data seen by a network that believes its noise std is `sigma`."""
    s = scenario.sensors
    sig_el = None if s.ndim == 2 else np.full(s.n_sensors, sigma)
    network = pa.SensorNetwork(s.positions, np.full(s.n_sensors, sigma), sig_el, s.ndim)
    return dataclasses.replace(scenario, sensors=network)


def noiseless_scan(seed: int, n_targets: int, n_sensors: int = 3, sigma: float = 1e-3) -> StaticScan:
    """A static scan with Pd = 1, no false bearings, no noise — seen by a network that believes sigma."""
    raw = static_scan(seed, n_targets=n_targets, n_sensors=n_sensors, pd=1.0, p_false=0.0, sigma=1e-10)
    return dataclasses.replace(raw, sensors=pa.SensorNetwork.planar(raw.sensors.positions[:, :2], sigma))


@pytest.fixture(scope="session")
def noiseless_table() -> Callable[..., pa.MeasurementTable]:
    return noiseless_table_of


@pytest.fixture(scope="session")
def with_nominal_sigma() -> Callable[[pa.Scenario, float], pa.Scenario]:
    return scenario_with_nominal_sigma


@pytest.fixture(scope="session")
def noiseless_static_scan() -> Callable[..., StaticScan]:
    return noiseless_scan
