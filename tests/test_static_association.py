"""Static bearing-only association (METHODS §2): exact recovery without noise, the partition
invariant, thread invariance, bad input and a smoke run of `reproduce intensity`."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import passive_assoc as pa
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from passive_assoc.cli import main as cli_main
from passive_assoc.static_association import associate_static, enumerate_candidates
from passive_assoc.static_scenarios import StaticScan, static_scan

METHODS = ("intensity", "lagrangian", "exact")


def noiseless(seed: int, n_targets: int, n_sensors: int = 3, sigma: float = 1e-3) -> StaticScan:
    """Pd = 1, no false bearings, no noise — seen by a network that believes sigma."""
    raw = static_scan(seed, n_targets=n_targets, n_sensors=n_sensors, pd=1.0, p_false=0.0, sigma=1e-10)
    return dataclasses.replace(raw, sensors=pa.SensorNetwork.planar(raw.sensors.positions[:, :2], sigma))


def assert_partition(result: pa.StaticAssociation, n_rows: int) -> None:
    used = result.tuples[result.tuples >= 0]
    assert len(np.unique(used)) == len(used), "a report is in two tuples"
    assert np.array_equal(np.sort(np.concatenate([used, result.false_alarms])), np.arange(n_rows))
    for k, rows in enumerate(result.tuples):
        assert np.all(result.labels[rows[rows >= 0]] == k)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_noiseless_scan_is_recovered_exactly(method: str, seed: int) -> None:
    scan = noiseless(seed, n_targets=6)
    result = pa.associate_static(scan.measurements, scan.sensors, method, pd=0.99)
    assert_partition(result, len(scan.measurements))
    assert sorted(map(tuple, result.tuples.tolist())) == sorted(map(tuple, scan.true_tuples.tolist()))
    order = [int(np.flatnonzero((result.tuples == t).all(axis=1))[0]) for t in scan.true_tuples]
    np.testing.assert_allclose(result.positions[order], scan.targets, atol=1e-3)


def test_four_sensors_noiseless() -> None:
    scan = noiseless(9, n_targets=5, n_sensors=4)
    for method in METHODS:
        result = pa.associate_static(scan.measurements, scan.sensors, method, pd=0.99)
        assert sorted(map(tuple, result.tuples.tolist())) == sorted(map(tuple, scan.true_tuples.tolist()))


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), n_targets=st.integers(1, 8), n_sensors=st.integers(2, 4),
       ratio=st.sampled_from([5.0, 15.0, 60.0]))
def test_every_report_ends_in_one_tuple_or_the_false_alarms(seed: int, n_targets: int, n_sensors: int, ratio: float) -> None:
    scan = static_scan(seed, n_targets=n_targets, n_sensors=n_sensors, ratio=ratio)
    assume(len(scan.measurements) > 0)  # an empty scan is refused (test_bad_inputs)
    for method in METHODS:
        result = pa.associate_static(scan.measurements, scan.sensors, method, time_limit=0.5)
        assert_partition(result, len(scan.measurements))


def test_lagrangian_reports_a_valid_bound_and_exact_is_no_worse() -> None:
    scan = static_scan(5, n_targets=8, ratio=15.0)
    lag = pa.associate_static(scan.measurements, scan.sensors, "lagrangian")
    exact = pa.associate_static(scan.measurements, scan.sensors, "exact", time_limit=5.0)
    assert exact.report["optimal"]
    assert lag.report["dual_bound"] <= exact.report["primal_cost"] + 1e-9
    assert exact.report["primal_cost"] <= lag.report["primal_cost"] + 1e-9
    assert lag.costs.sum() == pytest.approx(lag.report["primal_cost"])


def test_enumeration_is_thread_count_invariant() -> None:
    scan = static_scan(8, n_targets=30, ratio=15.0)
    one = pa.enumerate_candidates(scan.measurements, scan.sensors, n_threads=1)
    two = pa.enumerate_candidates(scan.measurements, scan.sensors, n_threads=2)
    for key in ("tuples", "rows", "positions", "covariances", "costs"):
        np.testing.assert_array_equal(one[key], two[key])


@pytest.mark.parametrize(
    "kwargs,exc,message",
    [
        (dict(method="greedy"), ValueError, "method"),
        (dict(pd=1.0), ValueError, r"pd: sensor 0 has 1.0, must be in \(0.0, 1.0\)"),
        (dict(pd=[0.9, 0.9]), ValueError, "pd: expected a scalar or 3 values"),
        (dict(false_alarm_density=-1.0), ValueError, "false_alarm_density"),
        (dict(gate=float("nan")), ValueError, "gate"),
        (dict(min_intensity=1), ValueError, "min_intensity"),
        (dict(max_chains=0), ValueError, "max_chains"),
        (dict(max_candidates=3), ValueError, "max_candidates|cap"),
    ],
)
def test_bad_arguments(kwargs: dict, exc: type[Exception], message: str) -> None:
    scan = static_scan(1, n_targets=5)
    method = kwargs.pop("method", "intensity")
    with pytest.raises(exc, match=message):
        pa.associate_static(scan.measurements, scan.sensors, method, **kwargs)


def test_bad_inputs() -> None:
    scan = static_scan(1, n_targets=5)
    one_sensor = pa.SensorNetwork.planar([[0.0, 0.0]], 1e-3)
    with pytest.raises(ValueError, match="at least 2 sensors"):
        pa.associate_static(scan.measurements.select(np.flatnonzero(scan.measurements.sensor == 0)), one_sensor)
    with pytest.raises(TypeError, match="measurements"):
        pa.associate_static(scan.measurements.to_arrays(), scan.sensors)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="empty"):
        pa.associate_static(scan.measurements.select(np.array([], dtype=np.int64)), scan.sensors)


def test_solver_settings_reach_assign_sd_through_associate_static() -> None:
    """``associate_static`` hands ``sensor_order`` and ``polish`` to the solver: its report
    equals ``assign_sd`` on the same candidates with the same settings, for every setting, and
    the settings do change the answer here (so the comparison can tell them apart)."""
    scan = static_scan(1, n_targets=18, n_sensors=3, ratio=15.0)
    cands = enumerate_candidates(scan.measurements, scan.sensors, n_threads=1)
    costs = set()
    for order in ("auto", "given"):
        for polish in (False, True):
            direct = pa.assign_sd(cands["tuples"], cands["costs"], cands["sizes"], sensor_order=order, polish=polish)
            result = associate_static(scan.measurements, scan.sensors, "lagrangian", n_threads=1,
                                      sensor_order=order, polish=polish)
            assert result.report["primal_cost"] == direct.primal_cost
            assert result.report["dual_bound"] == direct.dual_bound
            costs.add(direct.primal_cost)
    assert len(costs) > 1


def test_reproduce_intensity_smoke(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out_json, out_png = tmp_path / "intensity.json", tmp_path / "intensity.png"
    argv = ["reproduce", "intensity", "--runs", "2", "--ratios", "15", "--max-m", "12", "--time-limit", "0.5", "--timing-scans", "2",
            "--max-iter", "50", "--sensor-order", "given", "--polish", "--json", str(out_json), "--plot", str(out_png)]
    assert cli_main(argv) == 0
    printed = capsys.readouterr().out
    assert "Table 1" in printed and "Table 2" in printed
    record = json.loads(out_json.read_text())
    cells = record["accuracy"]["15"]
    assert set(cells) == {*METHODS, "truth_costlier_than_optimum_pct", "exact_proven_runs", "ghosts_per_scan_median"}
    assert all(0.0 <= cells[m]["accuracy_pct"] <= 100.0 for m in METHODS)
    assert [row["M"] for row in record["timing"] if row["S"] == 3] == [6, 12]
    assert all(row["scans"] == 2 for row in record["timing"])
    assert all(1 <= row["lagrangian_iterations"] <= 50 for row in record["timing"])  # --max-iter reaches the solver
    assert (record["settings"]["sensor_order"], record["settings"]["polish"]) == ("given", True)
    assert out_png.stat().st_size > 10_000


def test_bayes_bound_recovers_a_noiseless_scan() -> None:
    from passive_assoc.experiments.intensity import bayes_map

    scan = noiseless(4, n_targets=6)
    cands = pa.enumerate_candidates(scan.measurements, scan.sensors)
    assert bayes_map(scan, cands, time_limit=5.0) == {"accuracy": 1.0, "truth_beaten": 0.0}


def test_reproduce_intensity_bayes_bound_smoke(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out_json = tmp_path / "bound.json"
    argv = ["reproduce", "intensity", "--runs", "2", "--ratios", "15", "--no-timing", "--time-limit", "0.5",
            "--bayes-bound", "--json", str(out_json)]
    assert cli_main(argv) == 0
    assert "exact MAP under the scenario's own model" in capsys.readouterr().out
    bound = json.loads(out_json.read_text())["accuracy"]["15"]["bayes_map"]
    assert set(bound) == {"accuracy_pct", "truth_costlier_pct", "proven_runs"}
    assert 0.0 <= bound["accuracy_pct"] <= 100.0
