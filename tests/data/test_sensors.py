"""Tests of SensorNetwork."""

from __future__ import annotations

import numpy as np
import pytest
from passive_assoc.data import SensorNetwork


def test_planar_network() -> None:
    net = SensorNetwork.planar([[0.0, 0.0], [1000.0, 0.0], [0.0, 500.0]], 0.01)
    assert net.ndim == 2 and net.n_sensors == 3
    assert net.positions.shape == (3, 3) and np.all(net.positions[:, 2] == 0.0)
    assert np.all(net.sigma_azimuth == 0.01) and np.all(np.isnan(net.sigma_elevation))
    with pytest.raises(ValueError, match="read-only"):
        net.positions[0, 0] = 1.0
    per_sensor = SensorNetwork.planar([[0.0, 0.0], [1.0, 0.0]], [0.1, 0.2])
    assert per_sensor.sigma_azimuth.tolist() == [0.1, 0.2]


def test_spatial_network_and_position_at() -> None:
    pos = [[0.0, 0.0, 0.0], [20000.0, 0.0, 10.0]]
    net = SensorNetwork.spatial(pos, 5e-3, [1e-3, 2e-3])
    assert net.ndim == 3 and net.sigma_elevation.tolist() == [1e-3, 2e-3]
    assert net.position_at(1, 3.0).tolist() == [20000.0, 0.0, 10.0]
    out = net.position_at([0, 1, 1], [0.0, 1.0, 2.0])
    assert out.shape == (3, 3) and out[2].tolist() == pos[1]
    assert net.position_at(np.array([0, 1]), 7.0).shape == (2, 3)  # time broadcasts
    with pytest.raises(ValueError, match=r"^sensor_index: 2 is not a sensor"):
        net.position_at(2, 0.0)
    with pytest.raises(ValueError, match=r"^time = nan"):
        net.position_at(0, np.nan)
    assert net == SensorNetwork.spatial(pos, 5e-3, [1e-3, 2e-3])
    assert net != SensorNetwork.spatial(pos, 5e-3, 5e-3)


def test_direct_construction_infers_ndim() -> None:
    pos = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    assert SensorNetwork(pos, 0.1).ndim == 2
    assert SensorNetwork(pos, 0.1, 0.2).ndim == 3
    assert SensorNetwork(pos, 0.1, np.nan).ndim == 2


P = SensorNetwork.planar
Z = np.zeros((1, 3))
_BAD_NETWORKS = [
    (lambda: P(np.zeros((0, 2)), 0.1), ValueError, r"^positions: .*at least 1"),
    (lambda: P([[0.0, 0.0, 0.0]], 0.1), ValueError, r"^positions_xy: expected shape"),
    (lambda: SensorNetwork.spatial([[0.0, 0.0]], 0.1, 0.1), ValueError, r"^positions_xyz: expected shape"),
    (lambda: P([[0.0, np.nan]], 0.1), ValueError, r"^positions\[0, 1\] = nan"),
    (lambda: P([[0.0, 0.0]], 0.0), ValueError, r"^sigma_bearing\[0\] = 0\.0; must be > 0"),
    (lambda: P([[0, 0], [1, 0]], [0.1, -0.1]), ValueError, r"^sigma_bearing\[1\] = -0\.1"),
    (lambda: P([[0, 0], [1, 0]], [0.1, 0.1, 0.1]), ValueError, r"^sigma_bearing: expected a scalar or shape \(2,\)"),
    (lambda: P([[0, 0]], np.inf), ValueError, r"^sigma_bearing\[0\] = inf"),
    (lambda: P([[0, 0]], "0.1"), TypeError, r"^sigma_bearing: expected real numbers"),
    (lambda: SensorNetwork.spatial([[0, 0, 0]], 0.1, 0.0), ValueError, r"^sigma_elevation\[0\] = 0\.0"),
    (lambda: SensorNetwork(Z, 0.1, None, 3), ValueError, r"^sigma_elevation: required"),
    (lambda: SensorNetwork(Z, 0.1, 0.1, 2), ValueError, r"^sigma_elevation: must be omitted"),
    (
        lambda: SensorNetwork(np.array([[0, 0, 5.0]]), 0.1, None, 2),
        ValueError,
        r"^positions\[0, 2\] = 5\.0; a 2-D network",
    ),
    (lambda: SensorNetwork(Z, 0.1, 0.1, 4), ValueError, r"^ndim: expected 2 or 3, got 4"),
    (lambda: SensorNetwork(Z, 0.1, 0.1, "3"), TypeError, r"^ndim: expected 2 or 3"),
]


@pytest.mark.parametrize(("call", "exc", "pattern"), _BAD_NETWORKS)
def test_network_rejects_bad_input(call, exc, pattern) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(exc, match=pattern):
        call()


def test_network_rejects_coincident_sensors_naming_both() -> None:
    pos = [[0.0, 0.0], [5.0, 5.0], [1.0, 2.0], [5.0, 5.0 + 1e-12]]
    with pytest.raises(ValueError, match=r"^positions: sensors 1 and 3 are coincident"):
        SensorNetwork.planar(pos, 0.1)
    SensorNetwork.planar([[0.0, 0.0], [1e-6, 0.0]], 0.1)  # close but distinct is fine
