"""The built-in tracker (initiation, then a constant-velocity EKF on the angle reports with gated
global nearest neighbour) keeps every initiated target tracked on two scenes not from the
papers, gives every input row exactly one answer, and matches the Stone Soup tracker on the
same scenes where Stone Soup is installed.

Measured (seed 0): the coastal scene (2-D, four sites, one airborne, five ships, 1 198 reports)
gives five tracks, one per ship, each held to the last report time; 97.2–100 % of each ship's
reports after its track started land in it, 0–4 other reports per track; 99.75 % of the
ships' reports and 0.78 % of the false ones in a track; last positions 14–107 m from the
ships. The air scene (3-D, three sensors, three aircraft, 844 reports): three tracks,
99.2–100 %, no false report in a track, last positions 5–18 m off. Stone Soup's tracker gives
the same labels (up to track ids) and the same states to 1e-5 m on both."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.evaluation.track_truth import track_targets
from passive_assoc.simulation import Scenario
from passive_assoc.tracking import track_measurements

Figures = Callable[[Scenario, pa.TrackTable, np.ndarray], dict[str, Any]]


def _every_row_once(scene: Scenario, tracks: pa.TrackTable, labels: np.ndarray) -> None:
    """One label per input row, each a track of the answer or −1, and both kinds present."""
    assert labels.shape == (len(scene.measurements),) and labels.dtype == np.int64
    ids = set(np.unique(tracks.track).tolist())
    assert set(labels.tolist()) <= ids | {-1}
    assert all((labels == k).any() for k in ids), "a track with no report"
    assert (labels >= 0).sum() > len(labels) / 2 and (labels < 0).sum() > 0


def test_the_coastal_ships_are_all_tracked_to_the_end(coastal: Scenario, tracker_figures: Figures) -> None:
    tracks, labels = track_measurements(coastal.measurements, coastal.sensors)
    _every_row_once(coastal, tracks, labels)
    found = tracker_figures(coastal, tracks, labels)
    assert len(found["tracks"]) == 5
    assert coastal.measurements.truth is not None
    assert sorted(track_targets(labels, coastal.measurements.truth).tolist()) == [0, 1, 2, 3, 4]
    for k, track in found["tracks"].items():
        assert track["later_share"] > 0.95, (k, track)
        assert track["wrong"] <= 5, (k, track)
        assert track["last_time"] == coastal.measurements.time.max(), (k, track)
        assert track["last_error"] < 250.0, (k, track)
    assert found["true_in_track"] > 0.95 and found["false_in_track"] < 0.1, found


def test_the_aircraft_are_all_tracked_in_azimuth_and_elevation(air: Scenario, tracker_figures: Figures) -> None:
    tracks, labels = track_measurements(air.measurements, air.sensors, window=20.0)
    _every_row_once(air, tracks, labels)
    found = tracker_figures(air, tracks, labels)
    assert len(found["tracks"]) == 3
    assert sorted(track["target"] for track in found["tracks"].values()) == [0, 1, 2]
    for k, track in found["tracks"].items():
        assert track["later_share"] > 0.95 and track["wrong"] <= 2, (k, track)
        assert track["last_time"] == air.measurements.time.max() and track["last_error"] < 100.0, (k, track)
    assert found["true_in_track"] > 0.95 and found["false_in_track"] < 0.1, found
    assert tracks.covariance is not None and tracks.covariance.shape[1:] == (6, 6)


@pytest.mark.parametrize(("scene", "window"), [("coastal", 60.0), ("air", 20.0)])
def test_the_built_in_tracker_answers_as_stone_soup_does(
    scene: str, window: float, request: pytest.FixtureRequest, tracker_figures: Figures
) -> None:
    """One sensor per time step in these scenes, so both trackers pair the same reports: the
    same labels up to the track ids, and the same states."""
    pytest.importorskip("stonesoup")
    from passive_assoc.interop.stonesoup_tracking import track_measurements as stone_soup

    chosen: Scenario = request.getfixturevalue(scene)
    ours, our_labels = track_measurements(chosen.measurements, chosen.sensors, window=window)
    theirs, their_labels = stone_soup(chosen.measurements, chosen.sensors, window=window)
    assert len(ours.track) == len(theirs.track) and len(np.unique(ours.track)) == len(np.unique(theirs.track))
    # Match ids by the reports they hold: then every row carries the same track.
    mapping = {int(a): int(b) for a, b in zip(our_labels, their_labels, strict=True) if a >= 0}
    assert len(set(mapping.values())) == len(mapping)
    np.testing.assert_array_equal([mapping.get(int(a), -1) for a in our_labels], their_labels)
    for a, b in mapping.items():
        here, there = ours.track == a, theirs.track == b
        np.testing.assert_array_equal(ours.time[here], theirs.time[there])
        np.testing.assert_allclose(ours.position[here], theirs.position[there], atol=1e-3)


def test_a_sensor_without_two_scans_in_the_window_is_left_out_of_initiation(coastal: Scenario) -> None:
    """The initiation needs each pair's first and last scan: with one site alone nothing can
    be initiated (and nothing fails); with two sites the five ships are."""
    table = coastal.measurements
    alone = table.select(np.flatnonzero(table.sensor == 0))
    tracks, labels = track_measurements(alone, coastal.sensors)
    assert len(tracks.track) == 0 and (labels == -1).all() and len(labels) == len(alone)
    pair = table.select(np.flatnonzero(table.sensor <= 1))
    tracks, labels = track_measurements(pair, coastal.sensors)
    assert len(np.unique(tracks.track)) == 5 and len(labels) == len(pair)


def test_an_empty_table_gives_no_tracks(coastal: Scenario) -> None:
    empty = pa.MeasurementTable.from_arrays(np.zeros(0, dtype=np.int64), [], [])
    tracks, labels = track_measurements(empty, coastal.sensors)
    assert len(tracks.track) == 0 and len(labels) == 0


@pytest.mark.parametrize(
    ("change", "exc", "message"),
    [
        ({"measurements": "reports.csv"}, TypeError, r"^measurements: expected a MeasurementTable"),
        ({"sensors": [[0.0, 0.0]]}, TypeError, r"^sensors: expected a SensorNetwork"),
        ({"window": 0.0}, ValueError, r"^window: must be a number > 0"),
        ({"window": float("inf")}, ValueError, r"^window: must be a number > 0"),
        ({"process_noise": -1.0}, ValueError, r"^process_noise: must be a number > 0"),
        ({"missed_distance": True}, ValueError, r"^missed_distance: must be a number > 0"),
        ({"delete_after": 0}, ValueError, r"^delete_after: must be an int >= 1"),
        ({"delete_after": 2.0}, ValueError, r"^delete_after: must be an int >= 1"),
        ({"initiator": object()}, TypeError, r"^initiator: expected a FuzzyTrackInitiator"),
    ],
)
def test_bad_input_names_the_argument(
    coastal: Scenario, change: dict[str, Any], exc: type[Exception], message: str
) -> None:
    arguments: dict[str, Any] = {"measurements": coastal.measurements, "sensors": coastal.sensors} | change
    with pytest.raises(exc, match=message):
        track_measurements(**arguments)


def test_a_table_from_another_network_is_refused(coastal: Scenario) -> None:
    other = pa.SensorNetwork.planar([[0.0, 0.0], [1e3, 0.0]], 1e-3)
    with pytest.raises(ValueError, match=r"sensor"):
        track_measurements(coastal.measurements, other)
