"""Regrouping (``FuzzyTrackInitiator(regroup=True)``; docs/methods.md §1, *Regrouping*): the
neighbourhood's geometry, the score terms it compares with, and a dense scene where it finds
the targets ghost tracks hid, with every row still in exactly one output."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.evaluation import track_targets
from passive_assoc.fti import FuzzyTrackInitiator, InitiationResult
from passive_assoc.fti.regroup import Neighbourhood
from passive_assoc.fti.score import ScoreTerms, track_scores

PartitionCheck = Callable[[InitiationResult, int], None]


def test_neighbourhood_keeps_the_rays_that_meet_in_front_of_both_sensors() -> None:
    sensors = pa.SensorNetwork(
        np.array([[0.0, 0.0, 0.0], [30e3, 0.0, 100.0], [0.0, 30e3, 200.0]]), np.full(3, 4e-3), np.full(3, 4e-3)
    )
    target = np.array([12e3, 15e3, 6e3])

    def angles(sensor: int, point: np.ndarray) -> tuple[float, float]:
        d = point - sensors.positions[sensor]
        return math.atan2(d[1], d[0]), math.atan2(d[2], math.hypot(d[0], d[1]))

    rows = [
        (0, 0.0, *angles(0, target)),  # the track's row
        (1, 1.0, *angles(1, target)),  # meets it
        (1, 1.0, *angles(1, target + np.array([0.0, 0.0, 3e3]))),  # passes 3 km above it
        (2, 2.0, *angles(2, target)),  # meets it, 2 s later
        (2, 2.0, *angles(2, 2 * sensors.positions[2] - target)),  # the same line, behind sensor 2
        (1, 40.0, *angles(1, target)),  # meets it, but in a scan after the next
    ]
    sensor, time, az, el = (np.array(c) for c in zip(*rows, strict=True))
    table = pa.MeasurementTable.from_arrays(sensor.astype(np.int64), time, az, el)
    near = Neighbourhood(table, sensors, gate_sigmas=5.0, v_max=500.0)
    free = np.ones(len(rows), dtype=bool)
    free[0] = False
    # Only each other sensor's two scans around the row's time are read (here the first).
    assert near.of(np.array([0]), free).tolist() == [1, 3]
    # Taken rows are not free; without a speed bound rows at other times meet wherever they
    # pass, but not behind a sensor.
    free[1] = False
    assert near.of(np.array([0]), free).tolist() == [3]
    assert Neighbourhood(table, sensors, gate_sigmas=5.0, v_max=None).of(np.array([0]), free).tolist() == [2, 3]


def test_neighbourhood_reads_a_moving_sensors_position() -> None:
    sensors = pa.SensorNetwork(np.array([[0.0, 0.0, 0.0], [30e3, 0.0, 100.0]]), np.full(2, 4e-3), np.full(2, 4e-3))
    target, moved = np.array([12e3, 15e3, 6e3]), np.array([25e3, -8e3, 300.0])

    def angles(origin: np.ndarray) -> tuple[float, float]:
        d = target - origin
        return math.atan2(d[1], d[0]), math.atan2(d[2], math.hypot(d[0], d[1]))

    (az0, el0), (az1, el1) = angles(sensors.positions[0]), angles(moved)
    position = np.array([[np.nan] * 3, moved])
    args = (np.array([0, 1]), np.array([0.0, 1.0]), np.array([az0, az1]), np.array([el0, el1]))
    free = np.array([False, True])
    on_platform = pa.MeasurementTable.from_arrays(*args, sensor_position=position)
    assert Neighbourhood(on_platform, sensors, 5.0, 500.0).of(np.array([0]), free).tolist() == [1]
    # Read from the network's fixed position, sensor 1's ray misses the target by kilometres.
    fixed = pa.MeasurementTable.from_arrays(*args)
    assert Neighbourhood(fixed, sensors, 5.0, 500.0).of(np.array([0]), free).tolist() == []


def test_neighbourhood_names_what_it_refuses() -> None:
    sensors = pa.SensorNetwork(np.array([[0.0, 0.0, 0.0], [30e3, 0.0, 100.0]]), np.full(2, 4e-3), np.full(2, 4e-3))
    table = pa.MeasurementTable.from_arrays(
        np.array([0, 1]), np.array([0.0, 1.0]), np.array([0.5, 2.0]), np.array([0.1, 0.1])
    )
    near = Neighbourhood(table, sensors, 5.0, 500.0)
    free = np.ones(2, dtype=bool)
    with pytest.raises(ValueError, match="rows"):
        near.of(np.array([2]), free)
    with pytest.raises(ValueError, match="rows"):
        near.of(np.array([-1]), free)
    with pytest.raises(ValueError, match="free"):
        near.of(np.array([0]), free[:1])
    with pytest.raises(ValueError, match="ray_gate_sigmas"):
        Neighbourhood(table, sensors, -1.0, 500.0)
    with pytest.raises(ValueError, match="v_max"):
        Neighbourhood(table, sensors, 5.0, 0.0)
    planar = pa.SensorNetwork.planar(np.array([[0.0, 0.0], [30e3, 0.0]]), np.full(2, 4e-3))
    flat = pa.MeasurementTable.from_arrays(np.array([0, 1]), np.array([0.0, 1.0]), np.array([0.5, 2.0]))
    with pytest.raises(ValueError, match="sensors"):
        Neighbourhood(flat, planar, 5.0, 500.0)


def test_score_terms_follow_the_documented_formula() -> None:
    """The score of `passive_assoc.fti.score`'s doc, worked by hand on seven rows."""
    sensors = pa.SensorNetwork(np.array([[0.0, 0.0, 0.0], [1e3, 0.0, 0.0]]), np.full(2, 0.01), np.full(2, 0.01))
    table = pa.MeasurementTable.from_arrays(
        np.array([0, 0, 0, 0, 1, 1, 1]),
        np.array([0.0, 0.0, 1.0, 2.0, 0.0, 1.0, 1.0]),
        np.array([0.0, 0.2, 0.1, 0.4, 1.0, 1.5, 1.1]),
        np.array([0.1, 0.3, 0.2, 0.1, 0.0, 0.5, 0.2]),
    )
    labels = np.array([0, -1, 0, -1, 0, 1, -1])
    chi2 = np.array([2.0, 0.5])
    norm, hit, miss = 2 * math.pi * 0.01 * 0.01, math.log(0.9), math.log(0.1)
    # Sensor 0: 3 scans, azimuth arc 0.4 × elevation 0.2, 2 free rows; sensor 1: 2 scans,
    # 0.5 × 0.5, 1 free row.
    row0 = hit - math.log(2 / (3 * 0.4 * 0.2)) - math.log(norm)
    row1 = hit - math.log(1 / (2 * 0.5 * 0.5)) - math.log(norm)
    want = [2 * row0 + row1 + 2 * miss - 1.0, row1 + 4 * miss - 0.25]
    np.testing.assert_allclose(track_scores(labels, chi2, table, sensors, 0.9), want, rtol=1e-12)
    terms = ScoreTerms.of(labels, table, sensors, 0.9)
    np.testing.assert_allclose(terms.scores(labels, chi2), want, rtol=1e-12)
    one_by_one = [terms.score(np.flatnonzero(labels == k), chi2[k]) for k in (0, 1)]
    np.testing.assert_allclose(one_by_one, want, rtol=1e-12)


def test_score_terms_score_a_scene_track_by_track_as_the_initiator_does() -> None:
    scenario = pa.ring_scenario(3, n_sensors=3, n_targets=10)
    result = FuzzyTrackInitiator(min_score=None).initiate(
        scenario.measurements, scenario.sensors, t0=scenario.t0, progress=False
    )
    chi2 = np.array([t.chi2 for t in result.tracks])
    assert len(chi2) >= 8
    terms = ScoreTerms.of(result.labels, scenario.measurements, scenario.sensors, 0.9)
    scores = terms.scores(result.labels, chi2)
    one_by_one = [terms.score(t.measurements, t.chi2) for t in result.tracks]
    np.testing.assert_allclose(one_by_one, scores, rtol=1e-12)
    np.testing.assert_allclose([t.score for t in result.tracks], scores, rtol=1e-12)


def test_regroup_finds_the_targets_ghosts_hid(assert_partition: PartitionCheck) -> None:
    # Three sensors, 100 targets in an 89 km box (the scaling bench's grown ring): a third
    # sensor's rays confirm ghosts made of several targets' rows (docs/methods.md §1).
    half = 20e3 * math.sqrt(100 / 20)
    scenario = pa.ring_scenario(1, n_sensors=3, n_targets=100, half_width=half, radius=1.5 * half)
    m, sensors = scenario.measurements, scenario.sensors
    plain = FuzzyTrackInitiator().initiate(m, sensors, t0=scenario.t0, progress=False)
    regrouped = FuzzyTrackInitiator(regroup=True).initiate(m, sensors, t0=scenario.t0, progress=False)
    assert_partition(regrouped, len(m))
    assert plain.diagnostics.regrouped == 0 and plain.diagnostics.stage_seconds["regroup"] == 0.0
    assert regrouped.diagnostics.regrouped > 0 and regrouped.diagnostics.stage_seconds["regroup"] > 0.0

    def found_and_false(result: InitiationResult) -> tuple[int, int]:
        held = track_targets(result.labels, m.truth)
        return len(set(held.tolist()) - {-1}), int(np.sum(held < 0))

    (found, false), (found_after, false_after) = found_and_false(plain), found_and_false(regrouped)
    # Measured: 67 found with 8 other tracks, then 86 with 5.
    assert found_after >= found + 12
    assert false_after <= false
    # The result's tracks are scored and thresholded as any other.
    min_score = FuzzyTrackInitiator().min_score
    assert min_score is not None and all(t.score >= min_score for t in regrouped.tracks)


def test_regroup_keeps_a_scene_the_pipeline_solves(assert_partition: PartitionCheck) -> None:
    scenario = pa.ring_scenario(0, n_sensors=3, n_targets=20)
    m = scenario.measurements
    result = FuzzyTrackInitiator(regroup=True).initiate(m, scenario.sensors, t0=scenario.t0, progress=False)
    assert_partition(result, len(m))
    held = track_targets(result.labels, m.truth)
    assert sorted(held.tolist()) == list(range(20))


def test_regroup_reports_its_progress() -> None:
    scenario = pa.ring_scenario(0, n_sensors=3, n_targets=10)
    seen: list[tuple[str, float]] = []
    FuzzyTrackInitiator(regroup=True).initiate(
        scenario.measurements, scenario.sensors, t0=scenario.t0, progress=lambda s, f: seen.append((s, f))
    )
    fractions = [f for s, f in seen if s == "regroup"]
    assert fractions and fractions[-1] == 1.0 and fractions == sorted(fractions)


def test_regroup_refuses_a_planar_network() -> None:
    scenario = pa.bearing_only_2d_scenario(0, n_targets=3)
    with pytest.raises(ValueError, match="regroup: only for 3-D"):
        FuzzyTrackInitiator(regroup=True).initiate(scenario.measurements, scenario.sensors, progress=False)
    with pytest.raises(TypeError, match="regroup"):
        FuzzyTrackInitiator(regroup="yes")  # type: ignore[arg-type]


def test_regroup_gives_the_same_tracks_on_any_number_of_threads() -> None:
    half = 20e3 * math.sqrt(50 / 20)
    scenario = pa.ring_scenario(0, n_sensors=3, n_targets=50, half_width=half, radius=1.5 * half)
    runs = [
        FuzzyTrackInitiator(regroup=True, n_threads=n).initiate(
            scenario.measurements, scenario.sensors, t0=scenario.t0, progress=False
        )
        for n in (1, 2)
    ]
    assert runs[0].diagnostics.regrouped > 0  # it replaced tracks here
    assert runs[0].diagnostics.regrouped == runs[1].diagnostics.regrouped
    np.testing.assert_array_equal(runs[0].labels, runs[1].labels)
    np.testing.assert_array_equal(runs[0].states, runs[1].states)
