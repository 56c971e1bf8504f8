"""Stone Soup interop: detections round-trip to the same table; the detections' models predict
our measurements from the truth; initiated tracks and located targets become Gaussian states
with the interleaved order. Skipped without the ``stonesoup`` extra (CI installs it)."""

from __future__ import annotations

import datetime as dt

import numpy as np
import passive_assoc as pa
import pytest

pytest.importorskip("stonesoup")
from passive_assoc.interop.stonesoup import from_detections, target_states, to_detections, track_states
from passive_assoc.simulation import paper_fti_scenario, static_scan


@pytest.mark.parametrize("ndim", [2, 3])
def test_detections_round_trip_and_their_models_agree_with_ours(ndim: int) -> None:
    if ndim == 3:
        scenario = paper_fti_scenario(seed=2)
        table, sensors = scenario.measurements, scenario.sensors
    else:
        scan = static_scan(3, n_targets=4)
        table, sensors = scan.measurements, scan.sensors
    epoch = dt.datetime(2026, 1, 1)
    detections = to_detections(table, sensors, epoch=epoch)
    assert len(detections) == len(table)
    back = from_detections(reversed(detections), epoch=epoch)
    # Stone Soup wraps bearings to (−π, π]: the same directions, compared modulo 2π.
    assert back.sensor.tolist() == table.sensor.tolist() and np.array_equal(back.time, table.time)
    assert np.allclose(np.angle(np.exp(1j * (back.azimuth - table.azimuth))), 0.0, atol=1e-12)
    if ndim == 3:
        np.testing.assert_allclose(back.elevation, table.elevation, rtol=0, atol=1e-12)
    else:
        assert back.ndim == 2
    # The model of each detection, applied to a point, gives our angles to that point.
    point = np.array([3e3, 100.0, 2.5e4, -50.0, 1e3, 0.0][: 2 * ndim])
    for det in detections[:10]:
        j = det.metadata["sensor"]
        predicted = np.asarray(det.measurement_model.function(pa_state(point)), dtype=float).ravel()
        offset = point[::2] - sensors.positions[j][:ndim]
        bearing = np.arctan2(offset[1], offset[0])
        assert predicted[-1] == pytest.approx(bearing)
        if ndim == 3:
            assert predicted[0] == pytest.approx(np.arctan2(offset[2], np.hypot(offset[0], offset[1])))
        noise = np.diag(det.measurement_model.covar())
        assert noise[-1] == pytest.approx(sensors.sigma_azimuth[j] ** 2)


def pa_state(interleaved: np.ndarray) -> object:
    from stonesoup.types.state import State

    return State(interleaved.reshape(-1, 1))


def test_tracks_and_targets_become_gaussian_states() -> None:
    scenario = paper_fti_scenario(seed=1)
    result = pa.FuzzyTrackInitiator().initiate(scenario.measurements, scenario.sensors)
    tracks = track_states(result)
    assert len(tracks) == len(result.tracks) == 4
    for track, initiated in zip(tracks, result.tracks, strict=True):
        state = track.states[0]
        x, y, z, vx, vy, vz = initiated.state
        np.testing.assert_allclose(np.asarray(state.state_vector, dtype=float).ravel(), [x, vx, y, vy, z, vz])
        assert state.covar[1, 1] == pytest.approx(initiated.covariance[3, 3])
        assert state.timestamp == dt.datetime(1970, 1, 1) + dt.timedelta(seconds=result.t0)
    scan = static_scan(1, n_targets=3)
    found = pa.associate_static(scan.measurements, scan.sensors, "lagrangian")
    states = target_states(found.positions, found.covariances, time=5.0)
    assert len(states) == len(found.positions)
    np.testing.assert_allclose(np.asarray(states[0].state_vector, dtype=float).ravel(), found.positions[0])
