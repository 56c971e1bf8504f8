"""Static bearing-only association (METHODS §2): exact recovery without noise, the partition
invariant, thread invariance and bad input (`reproduce intensity` is smoke-tested in test_cli)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import passive_assoc as pa
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from passive_assoc.simulation import StaticScan, static_scan
from passive_assoc.static_los import associate_static, enumerate_candidates

METHODS = ("intensity", "lagrangian", "exact")

#: conftest fixtures
PartitionCheck = Callable[[pa.StaticAssociation, int], None]
NoiselessScan = Callable[..., StaticScan]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_noiseless_scan_is_recovered_exactly(
    method: str, seed: int, noiseless_static_scan: NoiselessScan, assert_partition: PartitionCheck
) -> None:
    scan = noiseless_static_scan(seed, n_targets=6)
    result = pa.associate_static(scan.measurements, scan.sensors, method, pd=0.99)
    assert_partition(result, len(scan.measurements))
    assert sorted(map(tuple, result.rows.tolist())) == sorted(map(tuple, scan.true_tuples.tolist()))
    order = [int(np.flatnonzero((result.rows == t).all(axis=1))[0]) for t in scan.true_tuples]
    np.testing.assert_allclose(result.positions[order], scan.targets, atol=1e-3)


def test_four_sensors_noiseless(noiseless_static_scan: NoiselessScan) -> None:
    scan = noiseless_static_scan(9, n_targets=5, n_sensors=4)
    for method in METHODS:
        result = pa.associate_static(scan.measurements, scan.sensors, method, pd=0.99)
        assert sorted(map(tuple, result.rows.tolist())) == sorted(map(tuple, scan.true_tuples.tolist()))


@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 2**31),
    n_targets=st.integers(1, 8),
    n_sensors=st.integers(2, 4),
    ratio=st.sampled_from([5.0, 15.0, 60.0]),
)
def test_every_report_ends_in_one_tuple_or_the_false_alarms(
    seed: int, n_targets: int, n_sensors: int, ratio: float, assert_partition: PartitionCheck
) -> None:
    scan = static_scan(seed, n_targets=n_targets, n_sensors=n_sensors, ratio=ratio)
    assume(len(scan.measurements) > 0)  # an empty scan is refused (test_bad_inputs)
    for method in METHODS:
        result = pa.associate_static(scan.measurements, scan.sensors, method, time_limit=0.5)
        assert_partition(result, len(scan.measurements))


def test_lagrangian_reports_a_valid_bound_and_exact_is_no_worse() -> None:
    scan = static_scan(5, n_targets=8, ratio=15.0)
    lag = pa.associate_static(scan.measurements, scan.sensors, "lagrangian")
    exact = pa.associate_static(scan.measurements, scan.sensors, "exact", time_limit=5.0)
    assert exact.diagnostics.solver.optimal
    assert lag.diagnostics.solver.dual_bound <= exact.diagnostics.solver.primal_cost + 1e-9
    assert exact.diagnostics.solver.primal_cost <= lag.diagnostics.solver.primal_cost + 1e-9
    assert lag.costs.sum() == pytest.approx(lag.diagnostics.solver.primal_cost)


def test_enumeration_is_thread_count_invariant() -> None:
    scan = static_scan(8, n_targets=30, ratio=15.0)
    one = pa.enumerate_candidates(scan.measurements, scan.sensors, n_threads=1)
    two = pa.enumerate_candidates(scan.measurements, scan.sensors, n_threads=2)
    for key in ("tuples", "rows", "positions", "covariances", "costs"):
        np.testing.assert_array_equal(getattr(one, key), getattr(two, key))


@pytest.mark.parametrize(
    "kwargs,exc,message",
    [
        (dict(method="greedy"), ValueError, "method"),
        (dict(pd=1.0), ValueError, r"pd: sensor 0 has 1.0, must be in \(0.0, 1.0\)"),
        (dict(pd=[0.9, 0.9]), ValueError, "pd: expected a scalar or 3 values"),
        (dict(false_alarm_density=-1.0), ValueError, "false_alarm_density"),
        (dict(gate_sigmas=float("nan")), ValueError, "gate_sigmas"),
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
            direct = pa.assign_sd(cands.tuples, cands.costs, cands.sizes, sensor_order=order, polish=polish)
            result = associate_static(
                scan.measurements, scan.sensors, "lagrangian", n_threads=1, sensor_order=order, polish=polish
            )
            assert result.diagnostics.solver.primal_cost == direct.primal_cost
            assert result.diagnostics.solver.dual_bound == direct.dual_bound
            costs.add(direct.primal_cost)
    assert len(costs) > 1


def test_the_default_vote_is_bounded_and_the_papers_rule_is_an_option() -> None:
    """Where ghosts are dense every point ties for the most exclusive rays, so the paper's
    vote starts a chain from each (quadratic); the default starts at most 64 per level."""
    scan = static_scan(2, n_targets=20, ratio=2.0)
    bounded = pa.associate_static(scan.measurements, scan.sensors, "intensity")
    paper = pa.associate_static(scan.measurements, scan.sensors, "intensity", max_chains=None)
    assert all(level.starts <= 64 for level in bounded.diagnostics.intensity.levels)
    assert max(level.starts for level in paper.diagnostics.intensity.levels) > 64
    for result in (bounded, paper):  # either way every row is in one tuple or clutter
        assert len(result.clutter) + int((result.rows >= 0).sum()) == len(scan.measurements)
