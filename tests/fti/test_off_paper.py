"""The initiator off the paper's scene: missed detections in the outer scans, more
sensors, few scans, and input that cannot give a track. Each test asserts the number of tracks
and that each track is one target's."""

from __future__ import annotations

import warnings

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.evaluation import track_targets
from passive_assoc.fti import FuzzyTrackInitiator, InitiationResult
from passive_assoc.simulation import Scenario
from passive_assoc.simulation.scenario import ConstantVelocityTarget, simulate


def targets_tracked(result: InitiationResult, scenario: Scenario) -> list[int]:
    """The target each track holds, sorted: at least two thirds of a track's rows must be one
    target's (where two targets' bearings cross, a few rows can go to the other track: 0.70
    is the lowest share on the seeds below, 0.79 at Pd = 1)."""
    truth = scenario.measurements.truth
    assert truth is not None
    found = track_targets(result.labels, truth)
    assert np.all(found >= 0), found
    return sorted(found.tolist())


def test_a_target_missed_in_an_outer_scan_is_initiated_by_the_second_pass() -> None:
    """3 sensors in 2-D at Pd = 0.9: on this seed a target is missed in outer scans, and the
    paper's candidates (first and last scans only) lose it."""
    scenario = pa.bearing_only_2d_scenario(4, pd=0.9)
    paper = FuzzyTrackInitiator(candidates="paper", candidate_scans=1).initiate(scenario.measurements, scenario.sensors)
    assert len(paper.tracks) == 2
    result = FuzzyTrackInitiator().initiate(scenario.measurements, scenario.sensors)
    assert targets_tracked(result, scenario) == [0, 1, 2]


@pytest.mark.parametrize("pd", [1.0, 0.9])
def test_three_sensors_in_2d_give_one_track_per_target(pd: float) -> None:
    """24 scans: the paper's fixed Nd = 9 gave 4-7 tracks for 3 targets on these seeds; the
    default Nd (from the number of scans) gives the 3. Since the coverage test (part of the
    track test) Nd = 9 also gives 3 on the last seed; without the track test and the score
    threshold the paper's formation does not, while the witnessed formation (the default in
    2-D with three sensors) rejects the ghosts before their fit and does."""
    for seed in range(10):
        scenario = pa.bearing_only_2d_scenario(seed, pd=pd)
        result = FuzzyTrackInitiator().initiate(scenario.measurements, scenario.sensors)
        assert targets_tracked(result, scenario) == [0, 1, 2], seed
    bare = {"n_detect": 9, "track_test": None, "min_score": None}
    fixed = FuzzyTrackInitiator(candidates="paper", **bare).initiate(scenario.measurements, scenario.sensors)
    assert len(fixed.tracks) > 3
    witnessed = FuzzyTrackInitiator(**bare).initiate(scenario.measurements, scenario.sensors)
    assert witnessed.diagnostics.candidates == "witnessed"
    assert targets_tracked(witnessed, scenario) == [0, 1, 2]


def test_rows_a_poor_first_pass_track_took_go_back_to_the_second_pass() -> None:
    """Seed 9 at Pd 0.9: target 2 has no first-pass candidate (missed in an outer scan), and a
    poor first-pass optimum 11 km short in range took 12 of its 20 reports; the track test
    dissolves that track, and its rows must reach the second pass, which finds the target (the
    paper's formation; the witnessed default's passes are the same)."""
    scenario = pa.bearing_only_2d_scenario(9, pd=0.9)
    truth = scenario.measurements.truth
    assert truth is not None
    result = FuzzyTrackInitiator(candidates="paper").initiate(scenario.measurements, scenario.sensors)
    own = [t for t in result.tracks if np.mean(truth[t.measurements] == 2) > 0.5]
    assert len(own) == 1
    assert np.sum(truth[own[0].measurements] == 2) == np.sum(truth == 2) == 20
    true_state = scenario.targets[2].initial_state
    assert np.hypot(*(own[0].state[:2] - true_state[:2])) < 500.0


def test_issue_16s_eight_target_2d_scene_gives_one_track_per_target() -> None:
    """``bearing_only_2d_scenario(3, n_targets=8, n_sensors=3, clutter_ratio=2)``: without the
    join of split tracks, two targets are split between two tracks each (10 tracks)."""
    scenario = pa.bearing_only_2d_scenario(3, n_targets=8, n_sensors=3, clutter_ratio=2)
    result = FuzzyTrackInitiator().initiate(scenario.measurements, scenario.sensors)
    assert targets_tracked(result, scenario) == list(range(8))


def test_two_tracks_that_took_each_others_rows_at_one_sensor_are_untangled() -> None:
    """``bearing_only_2d_scenario(1, n_targets=8, pd=0.9)``: targets 0 and 5 fly close, and
    without untangling each of their tracks holds the other's rows of the third sensor, so
    neither holds a target. Untangled, both are found, every row is still in one track or the
    clutter, and one thread gives the same tracks as two."""
    scenario = pa.bearing_only_2d_scenario(1, n_targets=8, pd=0.9)
    args = (scenario.measurements, scenario.sensors)
    tangled = FuzzyTrackInitiator(untangle=False).initiate(*args, t0=scenario.t0)
    untangled = FuzzyTrackInitiator(n_threads=2).initiate(*args, t0=scenario.t0)
    alone = FuzzyTrackInitiator(n_threads=1).initiate(*args, t0=scenario.t0)
    assert np.array_equal(alone.labels, untangled.labels)
    assert all(np.array_equal(a.state, b.state) for a, b in zip(alone.tracks, untangled.tracks, strict=True))
    truth = scenario.measurements.truth
    held_before = set(track_targets(tangled.labels, truth).tolist())
    held_after = set(track_targets(untangled.labels, truth).tolist())
    assert not {0, 5} & held_before
    assert {0, 5} <= held_after
    assert len(held_after - {-1}) > len(held_before - {-1})
    for result in (tangled, untangled):
        in_tracks = sorted(m for track in result.tracks for m in track.measurements)
        assert in_tracks == np.flatnonzero(result.labels >= 0).tolist()
        assert len(result.labels) == len(scenario.measurements)


def test_detection_in_membership_order_leaves_no_ghost_tracks() -> None:
    """Seed 1 of the same scene: in the paper's order (decreasing R over every row) optima
    between targets are detected first and 13 tracks come out for 8 targets; in membership
    order (the default) each target's own optimum comes first, and the 8 are the only
    tracks (both with the paper's formation)."""
    scenario = pa.bearing_only_2d_scenario(1, n_targets=8, n_sensors=3, clutter_ratio=2)
    result = FuzzyTrackInitiator(candidates="paper").initiate(scenario.measurements, scenario.sensors)
    assert targets_tracked(result, scenario) == list(range(8))
    paper = FuzzyTrackInitiator(candidates="paper", detection_order="closeness").initiate(
        scenario.measurements, scenario.sensors
    )
    assert len(paper.tracks) > 8


def test_two_sensors_and_four_scans_give_the_targets() -> None:
    """2 sensors x 4 scans = 8 reports per target: the paper's Nd = 9 cannot be reached (it
    gave 0 tracks and no warning; now it says why)."""
    sensors = pa.SensorNetwork.spatial([[0.0, 0.0, 0.0], [20e3, 0.0, 0.0]], 5e-3, 5e-3)
    states = [[1340.0, 5000.0, 1000.0, 173.2, 100.0, 0.0], [6000.0, 1000.0, 1000.0, 0.0, 200.0, 0.0]]
    times = [15.0 * np.arange(4), 5.0 + 15.0 * np.arange(4)]
    for seed in range(5):
        targets = [ConstantVelocityTarget(np.array(s), t0=0.0) for s in states]
        scenario = simulate(sensors, targets, times, clutter_per_scan=4, t0=0.0, seed=seed)
        result = FuzzyTrackInitiator().initiate(scenario.measurements, scenario.sensors, t0=0.0)
        assert targets_tracked(result, scenario) == [0, 1], seed
        with pytest.warns(UserWarning, match=r"no candidate survived the 'supported' stage .*lower n_detect"):
            fixed = FuzzyTrackInitiator(n_detect=9).initiate(scenario.measurements, scenario.sensors)
        assert fixed.tracks == []


def test_a_scene_where_no_candidate_survives_warns_and_says_why() -> None:
    """Times in kiloseconds: every candidate moves 1000x too fast for v_max."""
    scenario = pa.paper_fti_scenario(3)
    columns = scenario.measurements.to_arrays()
    columns["time"] = columns["time"] / 1000.0
    table = pa.MeasurementTable.from_columns(columns)
    with pytest.warns(
        UserWarning, match=r"no candidate survived the 'v_max' stage .*raise v_max, or check the times"
    ) as caught:
        result = FuzzyTrackInitiator().initiate(table, scenario.sensors)
    assert result.tracks == []
    assert [w.filename for w in caught] == [__file__]  # the caller's line, not the package's
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the paper's own scene does not warn
        assert len(FuzzyTrackInitiator().initiate(scenario.measurements, scenario.sensors).tracks) == 4


def test_the_track_test_dissolves_a_track_threaded_through_clutter() -> None:
    """5 targets, 3 sensors in 2-D, 10 clutter bearings per scan: a search can thread 16 of 24
    scans' clutter (more than Nd = 14). Its refit χ² is far above a target's. (Seed 10 showed
    this until the tracking gate's score removed that track's candidates before any search;
    seeds 8, 14 and 16 of 0-39 still make one with the paper's formation. The witnessed
    formation, the default here, rejects that candidate before its fit.)"""
    scenario = pa.bearing_only_2d_scenario(8, n_targets=5, n_sensors=3, clutter_ratio=2)
    truth = scenario.measurements.truth
    assert truth is not None
    paper = FuzzyTrackInitiator(candidates="paper", track_test=None, min_score=None)
    off = paper.initiate(scenario.measurements, scenario.sensors)
    clutter_only = [t for t in off.tracks if np.all(truth[t.measurements] < 0)]
    assert len(off.tracks) == 6 and len(clutter_only) == 1
    result = FuzzyTrackInitiator(candidates="paper").initiate(scenario.measurements, scenario.sensors)
    assert targets_tracked(result, scenario) == [0, 1, 2, 3, 4]
    assert set(clutter_only[0].measurements) <= set(result.clutter)
    witnessed = FuzzyTrackInitiator(track_test=None, min_score=None).initiate(scenario.measurements, scenario.sensors)
    assert targets_tracked(witnessed, scenario) == [0, 1, 2, 3, 4]


def test_pricing_misses_removes_the_clutter_tracks_of_a_dense_2d_scene() -> None:
    """8 targets, 3 sensors, Pd 0.9, 16 clutter bearings a scan (seed 0), the paper's formation:
    without the score threshold every target is tracked and 5 other tracks are mostly clutter;
    with misses priced at an assumed Pd of 0.9 (``gate_pd``) those candidates' walks miss too
    often to be searched, and the same 8 targets are the only tracks. The witnessed formation
    (the default here) rejects those ghosts before their fit: the 8 targets alone even
    without the score threshold."""
    scenario = pa.bearing_only_2d_scenario(0, n_targets=8, n_sensors=3, clutter_ratio=2, pd=0.9)
    truth = scenario.measurements.truth
    assert truth is not None
    default = FuzzyTrackInitiator(candidates="paper", min_score=None).initiate(scenario.measurements, scenario.sensors)
    held = track_targets(default.labels, truth)
    assert set(held.tolist()) - {-1} == set(range(8)) and len(held) > 8
    priced = FuzzyTrackInitiator(candidates="paper", gate_pd=0.9).initiate(scenario.measurements, scenario.sensors)
    assert targets_tracked(priced, scenario) == list(range(8))
    assert priced.diagnostics.stage_counts["supported"] < default.diagnostics.stage_counts["supported"]
    witnessed = FuzzyTrackInitiator(min_score=None).initiate(scenario.measurements, scenario.sensors)
    assert targets_tracked(witnessed, scenario) == list(range(8))


def scale_scene(n_sensors: int, n_targets: int, seed: int) -> tuple[Scenario, pa.SensorNetwork]:
    """The scale bench's scene (benches/bench_initiation_scale.py): 3-D sensors 20 km apart on a
    line, targets at one altitude at 100-200 m/s, 8 scans, clutter twice the true reports."""
    rng = np.random.default_rng(seed)
    sensors = pa.SensorNetwork.spatial([[20e3 * j, 0.0, 0.0] for j in range(n_sensors)], 5e-3, 5e-3)
    speed, heading = rng.uniform(100, 200, n_targets), rng.uniform(-np.pi, np.pi, n_targets)
    width = 20e3 * (n_sensors - 1)
    states = np.column_stack(
        [
            *(rng.uniform(0, width, n_targets), rng.uniform(1e3, 16e3, n_targets), np.full(n_targets, 1e3)),
            *(speed * np.cos(heading), speed * np.sin(heading), np.zeros(n_targets)),
        ]
    )
    targets = [ConstantVelocityTarget(s, t0=0.0) for s in states]
    times = [5.0 * j + 15.0 * np.arange(8) for j in range(n_sensors)]
    scenario = simulate(
        sensors,
        targets,
        times,
        clutter_per_scan=2 * n_targets,
        azimuth_window=(0, np.pi),
        elevation_window=(0, np.pi / 2),
        t0=0.0,
        seed=seed,
    )
    return scenario, sensors


def test_membership_order_finds_every_target_of_a_16_target_3d_scene() -> None:
    """2 sensors, 16 targets at one altitude (the scale bench's scene, seed 1): in R's order an
    optimum between targets takes rows of two and one target is lost; in membership order
    (the default) each of the 16 has its own track."""
    scenario, sensors = scale_scene(2, 16, seed=1)
    result = FuzzyTrackInitiator().initiate(scenario.measurements, sensors, t0=0.0)
    assert targets_tracked(result, scenario) == list(range(16))
    paper = FuzzyTrackInitiator(detection_order="closeness").initiate(scenario.measurements, sensors, t0=0.0)
    truth = scenario.measurements.truth
    assert truth is not None
    assert len(set(track_targets(paper.labels, truth).tolist()) - {-1}) < 16


def test_many_candidates_are_searched_in_stages_and_find_every_target() -> None:
    """Five 3-D sensors on a line, 8 targets at one altitude, clutter twice the true reports
    (the scale bench's scene): about 1 800 candidates pass the support gate. Searched 256 at a
    time by tracking-gate score, the first stage holds every target's candidates, and no later
    candidate still passes the gate on the rows detection left (the paper's formation: the
    rounds formation fits far fewer)."""
    scenario, sensors = scale_scene(5, 8, seed=1)
    result = FuzzyTrackInitiator(search_stage=256, candidates="paper").initiate(scenario.measurements, sensors)
    assert targets_tracked(result, scenario) == list(range(8))
    counts = result.diagnostics.stage_counts
    assert counts["supported"] > 1000
    assert counts["optima"] < counts["supported"] // 4
