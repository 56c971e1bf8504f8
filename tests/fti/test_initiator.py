"""Fuzzy track initiation (METHODS §1): exactness without noise, the partition invariant on
random scenarios, thread invariance and bad input (`reproduce fti` is smoke-tested in test_cli)."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from itertools import pairwise

import numpy as np
import passive_assoc as pa
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from passive_assoc.fti import FuzzyTrackInitiator, InitiationResult

#: conftest fixtures
PartitionCheck = Callable[[InitiationResult, int], None]
NominalSigma = Callable[[pa.Scenario, float], pa.Scenario]


@pytest.mark.parametrize("planar", [False, True])
def test_noiseless_scenario_gives_exact_targets_and_assignment(
    planar: bool, with_nominal_sigma: NominalSigma, assert_partition: PartitionCheck
) -> None:
    if planar:
        raw = pa.bearing_only_2d_scenario(seed=4, n_targets=3, clutter_ratio=0.0, sigma=1e-9)
    else:
        raw = pa.paper_fti_scenario(seed=4, clutter_ratio=0.0, sigma=1e-9)
    scenario = with_nominal_sigma(raw, 5e-3)
    result = FuzzyTrackInitiator().initiate(scenario.measurements, scenario.sensors, t0=scenario.t0)
    assert len(result.tracks) == len(scenario.targets)
    assert_partition(result, len(scenario.measurements))
    assert len(result.clutter) == 0
    # Exact assignment, up to reports no method can tell apart: where tracks cross, two
    # targets' noiseless reports at the same (sensor, time) coincide to nanoradians.
    m = scenario.measurements
    elevation = np.zeros(len(m)) if planar else m.elevation

    def reports(rows: np.ndarray) -> list[tuple[int, float, float, float]]:
        return sorted(
            (int(m.sensor[r]), float(m.time[r]), round(float(m.azimuth[r]), 6), round(float(elevation[r]), 6))
            for r in rows
        )

    truth_reports = [reports(g) for g in scenario.true_groups()]
    for track in result.tracks:
        k = next(i for i, g in enumerate(truth_reports) if g == reports(track.measurements))
        np.testing.assert_allclose(track.state, scenario.true_states[k], rtol=1e-6, atol=1e-3)


def test_paper_run_with_clutter_finds_the_four_targets(assert_partition: PartitionCheck) -> None:
    scenario = pa.paper_fti_scenario(seed=11)
    result = FuzzyTrackInitiator().initiate(scenario.measurements, scenario.sensors, t0=0.0)
    assert_partition(result, len(scenario.measurements))
    assert len(result.tracks) == 4
    # The right four: each track is mostly one target's measurements (on this run all 16 of
    # its target's and nothing else), the four targets are distinct, and each track's
    # initial state is nearest its target's in position and within 5 of its own standard
    # deviations of it in every component (measured: at most 1.53).
    truth = scenario.measurements.truth
    assert truth is not None
    matched = []
    for track in result.tracks:
        labels, label_counts = np.unique(truth[track.measurements], return_counts=True)
        k = int(labels[np.argmax(label_counts)])
        assert k >= 0 and label_counts.max() >= 0.9 * len(track.measurements), (labels, label_counts)
        distance = np.linalg.norm(scenario.true_states[:, :3] - track.state[:3], axis=1)
        assert int(np.argmin(distance)) == k
        sd = np.sqrt(np.diag(track.covariance))
        assert np.all(np.abs(track.state - scenario.true_states[k]) < 5 * sd)
        matched.append(k)
    assert sorted(matched) == [0, 1, 2, 3]
    counts = result.diagnostics.stage_counts
    assert list(counts) == [
        "raw",
        "ray_gate",
        "behind",
        "v_max",
        "fitted",
        "chi2_gate",
        "supported",
        "optima",
        "merged",
        "detected",
    ]
    # Pass 1 combines the four outer scans (12 rows each); pass 2 the other 15 scan slots of
    # candidate_scans=4 over what pass 1 left: every target row is taken, 8 clutter rows a scan.
    assert counts["raw"] == 12**4 + 15 * 8**4 and counts["detected"] == 4
    assert all(a >= b for a, b in pairwise(list(counts.values())[:6]))  # the pruning stages only remove
    seconds = result.diagnostics.stage_seconds
    assert list(seconds) == ["candidates", "fit", "support", "descent", "detection", "final", "regroup"]
    assert seconds["regroup"] == 0.0 and result.diagnostics.regrouped == 0  # off by default
    assert all(s >= 0.0 for s in seconds.values())


@pytest.mark.parametrize(
    ("scene", "candidates", "formation"),
    [
        ("paper", "paper", "paper"),
        ("paper", "auto", "witnessed"),
        ("ring", "auto", "rounds"),
        ("planar", "auto", "witnessed"),
    ],
)
def test_thread_count_does_not_change_the_result(scene: str, candidates: str, formation: str) -> None:
    """The paper's formation, the witnessed at two sensors (the pair's own scans witness), the
    rounds with their sweep (ring seed 2: the sweep finds a target there) and the witnessed
    formation in 2-D (8 targets, Pd 0.9)."""
    if scene == "paper":
        scenario = pa.paper_fti_scenario(seed=12, clutter_ratio=4.0)
    elif scene == "ring":
        scenario = pa.ring_scenario(2, n_sensors=3, n_targets=20)
    else:
        scenario = pa.bearing_only_2d_scenario(1, n_targets=8, pd=0.9)
    one, two = (
        FuzzyTrackInitiator(n_threads=n, candidates=candidates).initiate(
            scenario.measurements, scenario.sensors, t0=scenario.t0
        )
        for n in (1, 2)
    )
    assert one.diagnostics.candidates == formation
    assert np.array_equal(one.labels, two.labels)
    np.testing.assert_array_equal(one.states, two.states)


def test_all_pruning_off_gives_the_same_targets_on_a_small_case() -> None:
    scenario = pa.paper_fti_scenario(seed=13, clutter_ratio=0.25, n_scans=4)
    pruned = FuzzyTrackInitiator().initiate(scenario.measurements, scenario.sensors)
    unpruned = FuzzyTrackInitiator(ray_gate_sigmas=None, reject_behind=False, v_max=None, chi2_gate=None).initiate(
        scenario.measurements, scenario.sensors
    )
    assert unpruned.diagnostics.stage_counts["fitted"] >= pruned.diagnostics.stage_counts["fitted"]
    assert np.array_equal(pruned.labels, unpruned.labels)


@pytest.mark.filterwarnings("ignore:no candidate survived")  # short random windows may have none
def test_random_scenarios_keep_the_partition_and_never_panic(assert_partition: PartitionCheck) -> None:
    """Random short windows, 2-D and 3-D, with and without clutter and misses: every row ends in
    exactly one track or the clutter, and nothing but a too-short window is refused.

    The partition check says little about a result with no tracks (everything is clutter), so
    the detection threshold follows the window: a target must relate more than half of the
    measurements it can have (sensors x scans), where the paper's fixed 9 leaves most windows
    of 2-6 scans without a track (measured: 70 of 400 examples had one). The examples that end
    with tracks are counted, and most must.
    """
    outcomes: list[str] = []

    @settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
    @given(
        seed=st.integers(0, 2**31),
        n_targets=st.integers(1, 3),
        n_sensors=st.integers(2, 3),
        n_scans=st.integers(2, 6),
        clutter=st.sampled_from([0.0, 0.5, 2.0]),
        pd=st.sampled_from([0.7, 1.0]),
        planar=st.booleans(),
    )
    def check(seed: int, n_targets: int, n_sensors: int, n_scans: int, clutter: float, pd: float, planar: bool) -> None:
        if planar:
            scenario = pa.bearing_only_2d_scenario(
                seed=seed, n_targets=n_targets, n_sensors=n_sensors, n_scans=n_scans, clutter_ratio=clutter, pd=pd
            )
        else:
            scenario = pa.paper_fti_scenario(seed=seed, n_scans=n_scans, clutter_ratio=clutter, pd=pd)
        table = scenario.measurements
        n_detect = max(1, scenario.sensors.n_sensors * n_scans // 2)
        try:
            result = FuzzyTrackInitiator(max_candidates=200_000, n_detect=n_detect).initiate(table, scenario.sensors)
        except ValueError as err:
            # The only acceptable refusal: a sensor without two scans to build candidates from.
            assert "scan" in str(err), err
            outcomes.append("refused")
            return
        assert_partition(result, len(table))
        outcomes.append("tracks" if result.tracks else "no tracks")

    check()
    # Hypothesis draws its examples unevenly (it revisits small and boundary values), so how
    # many end with tracks is checked on a uniform draw in the next test; here at least one.
    assert "tracks" in outcomes, outcomes


def test_most_random_short_windows_end_with_tracks() -> None:
    """The partition check above says little about a result without tracks; on a fixed uniform
    draw of the same windows (60 examples) most must end with tracks. Measured: 49 of 60 here
    (9 without tracks, 2 refused: a sensor with a single scan)."""
    rng = np.random.default_rng(38)
    outcomes: list[str] = []
    for _ in range(60):
        seed, n_targets, n_sensors, n_scans = (
            int(v) for v in (rng.integers(2**31), *rng.integers([1, 2, 2], [4, 4, 7]))
        )
        clutter, pd, planar = (
            float(rng.choice([0.0, 0.5, 2.0])),
            float(rng.choice([0.7, 1.0])),
            bool(rng.random() < 0.5),
        )
        if planar:
            scenario = pa.bearing_only_2d_scenario(
                seed=seed, n_targets=n_targets, n_sensors=n_sensors, n_scans=n_scans, clutter_ratio=clutter, pd=pd
            )
        else:
            scenario = pa.paper_fti_scenario(seed=seed, n_scans=n_scans, clutter_ratio=clutter, pd=pd)
        n_detect = max(1, scenario.sensors.n_sensors * n_scans // 2)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)  # "no candidate survived"
                result = FuzzyTrackInitiator(max_candidates=200_000, n_detect=n_detect).initiate(
                    scenario.measurements, scenario.sensors, progress=False
                )
        except ValueError as err:
            assert "scan" in str(err), err
            outcomes.append("refused")
            continue
        outcomes.append("tracks" if result.tracks else "no tracks")
    assert outcomes.count("tracks") >= 45, outcomes


@pytest.mark.parametrize(
    "kwargs,exc,message",
    [
        (dict(gate_sigmas=0.0), ValueError, "gate_sigmas: must be > 0"),
        (dict(n_detect=0), ValueError, "n_detect"),
        (dict(n_detect=2.5), TypeError, "n_detect"),
        (dict(spread=-1.0), ValueError, "spread: must be > 0"),
        (dict(v_max=float("nan")), ValueError, "v_max"),
        (dict(descent_scaling="newton"), ValueError, "descent_scaling"),
        (dict(detection_order="R"), ValueError, "detection_order"),
        (dict(reject_behind="yes"), TypeError, "reject_behind"),
        (dict(refine_passes=-1), ValueError, "refine_passes"),
        (dict(candidate_scans=0), ValueError, "candidate_scans"),
        (dict(search_stage=0), ValueError, "search_stage"),
        (dict(search_stage=1.5), TypeError, "search_stage"),
        (dict(gate_pd=1.0), ValueError, "gate_pd"),
        (dict(gate_pd=0.0), ValueError, "gate_pd"),
        (dict(pairs=[(0, 0)]), ValueError, "pairs"),
        (dict(pairs=[(0, 5)]), ValueError, "pairs"),
        (dict(max_candidates=10, on_limit="raise"), ValueError, "max_candidates"),
        (dict(on_limit="ignore"), ValueError, "on_limit"),
        (dict(candidates="pairs"), ValueError, "candidates"),
        (dict(score_pd=1.0), ValueError, "score_pd"),
        (dict(min_score=float("nan")), ValueError, "min_score"),
    ],
)
def test_bad_parameters_are_refused(kwargs: dict, exc: type[Exception], message: str) -> None:
    scenario = pa.paper_fti_scenario(seed=1)
    with pytest.raises(exc, match=message):
        FuzzyTrackInitiator(**kwargs).initiate(scenario.measurements, scenario.sensors)


def test_bad_inputs_are_refused() -> None:
    scenario = pa.paper_fti_scenario(seed=1)
    ini = FuzzyTrackInitiator()
    with pytest.raises(TypeError, match="measurements"):
        ini.initiate(scenario.measurements.to_arrays(), scenario.sensors)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="empty"):
        ini.initiate(scenario.measurements.select(np.array([], dtype=np.int64)), scenario.sensors)
    one_scan = scenario.measurements.select(np.flatnonzero(scenario.measurements.time < 10))
    with pytest.raises(ValueError, match="scan"):
        ini.initiate(one_scan, scenario.sensors)
    with pytest.raises(ValueError, match="t0"):
        ini.initiate(scenario.measurements, scenario.sensors, t0=float("inf"))
