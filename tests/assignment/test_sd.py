"""S-D assignment against an independent exact solver (scipy.optimize.milp) and the LP bound
(issue: static association)."""

from __future__ import annotations

from typing import Literal

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.simulation import static_scan
from passive_assoc.static_los import enumerate_candidates
from scipy.optimize import Bounds, LinearConstraint, linprog, milp
from scipy.sparse import csr_matrix


def random_instance(rng: np.random.Generator, s: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tuples built around a few 'targets' (so candidates overlap as LOS ghosts do) plus
    random clutter tuples; costs mostly negative."""
    sizes = rng.integers(1, 9, size=s)
    rows = set()
    for _ in range(rng.integers(3, 40)):
        t = tuple(int(rng.integers(0, n + 1)) if rng.random() < 0.9 else 0 for n in sizes)
        if sum(v > 0 for v in t) >= 2:
            rows.add(t)
    if not rows:
        rows.add(tuple([1] * s))
    tuples = np.array(sorted(rows), dtype=np.int64)
    costs = -rng.gamma(2.0, 3.0, len(tuples)) + rng.normal(0, 1.0, len(tuples)) * (rng.random(len(tuples)) < 0.2)
    return tuples, costs, sizes


def report_incidence(tuples: np.ndarray, sizes: np.ndarray) -> csr_matrix:
    """One row per report of every sensor, one column per tuple: 1 where the tuple uses it."""
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    used = [np.nonzero(tuples[:, s])[0] for s in range(tuples.shape[1])]
    rows = np.concatenate([offsets[s] + tuples[u, s] - 1 for s, u in enumerate(used)])
    return csr_matrix((np.ones(len(rows)), (rows, np.concatenate(used))), shape=(offsets[-1], len(tuples)))


def milp_optimum(tuples: np.ndarray, costs: np.ndarray, sizes: np.ndarray) -> float:
    a = report_incidence(tuples, sizes)
    res = milp(costs, constraints=LinearConstraint(a, -np.inf, 1), integrality=np.ones(len(costs)), bounds=Bounds(0, 1))
    assert res.status == 0
    return float(res.fun)


def feasible_cost(tuples: np.ndarray, costs: np.ndarray, chosen: np.ndarray) -> float:
    used = set()
    for k in chosen:
        for j, i in enumerate(tuples[k]):
            if i > 0:
                assert (j, i) not in used, "a report is used twice"
                used.add((j, i))
    return float(costs[chosen].sum())


def test_exact_and_lagrangian_against_milp_on_200_instances() -> None:
    rng = np.random.default_rng(20261121)
    hits, n = 0, 0
    for s in (3, 4):
        for _ in range(100):
            tuples, costs, sizes = random_instance(rng, s)
            optimum = milp_optimum(tuples, costs, sizes)
            exact = pa.assign_sd(tuples, costs, sizes, method="exact")
            assert exact.optimal
            assert feasible_cost(tuples, costs, exact.chosen) == pytest.approx(exact.primal_cost, abs=1e-9)
            assert exact.primal_cost == pytest.approx(optimum, rel=1e-9, abs=1e-9)
            lag = pa.assign_sd(tuples, costs, sizes, method="lagrangian")
            assert feasible_cost(tuples, costs, lag.chosen) == pytest.approx(lag.primal_cost, abs=1e-9)
            assert lag.dual_bound <= optimum + 1e-7 * max(1.0, abs(optimum))
            # Within its own reported gap of the optimum.
            assert lag.primal_cost - optimum <= lag.gap * max(1.0, abs(lag.primal_cost)) + 1e-9
            hits += abs(lag.primal_cost - optimum) <= 1e-9 * max(1.0, abs(optimum))
            n += 1
    assert hits / n >= 0.9, f"Lagrangian optimal in {hits}/{n}"


@pytest.mark.parametrize(
    "option", [{"warm_start": "always"}, {"warm_start": "never"}, {"sensor_order": "given"}, {"polish": True}]
)
def test_lagrangian_bounds_hold_under_every_option(option: dict[str, str]) -> None:
    """The inner 2-D solves are exact warm or cold, and any sensor may be the relaxed one: the
    bound stays below the optimum and the answer within its own gap of it, whichever is forced
    (the defaults are checked on 200 instances above)."""
    rng = np.random.default_rng(7)
    for s in (3, 4):
        for _ in range(25):
            tuples, costs, sizes = random_instance(rng, s)
            optimum = milp_optimum(tuples, costs, sizes)
            lag = pa.assign_sd(tuples, costs, sizes, method="lagrangian", **option)
            assert feasible_cost(tuples, costs, lag.chosen) == pytest.approx(lag.primal_cost, abs=1e-9)
            assert lag.dual_bound <= optimum + 1e-7 * max(1.0, abs(optimum))
            assert lag.primal_cost - optimum <= lag.gap * max(1.0, abs(lag.primal_cost)) + 1e-9


def lp_optimum(tuples: np.ndarray, costs: np.ndarray, sizes: np.ndarray) -> float:
    """The LP relaxation (0 <= x <= 1) of the same problem: the value every Lagrangian dual
    bound of it converges to from below, whichever sensors are relaxed."""
    a = report_incidence(tuples, sizes)
    res = linprog(costs, A_ub=a, b_ub=np.ones(a.shape[0]), bounds=(0, 1), method="highs")
    assert res.status == 0
    return float(res.fun)


def test_polish_never_raises_the_primal_on_paper_scans() -> None:
    """The end-of-solve polish starts from the solver's best and only applies improving moves,
    and on these scans it finds some."""
    improved = 0
    for seed in range(4):
        scan = static_scan(seed, n_targets=18, n_sensors=3, ratio=15.0)
        cands = enumerate_candidates(scan.measurements, scan.sensors, n_threads=1)
        tuples, costs, sizes = cands.tuples, cands.costs, cands.sizes
        plain = pa.assign_sd(tuples, costs, sizes, polish=False)
        polished = pa.assign_sd(tuples, costs, sizes)  # the default polishes
        assert feasible_cost(tuples, costs, polished.chosen) == pytest.approx(polished.primal_cost, abs=1e-9)
        assert polished.primal_cost <= plain.primal_cost + 1e-9 * abs(plain.primal_cost)
        assert polished.dual_bound == plain.dual_bound  # the same iterations, the same bound
        improved += polished.primal_cost < plain.primal_cost - 1e-9
    assert improved > 0, "the polish improved no scan: the test exercises nothing"


@pytest.mark.parametrize("sensor_order", ["auto", "given"])
def test_lagrangian_dual_stays_below_the_lp_bound_on_paper_scans(sensor_order: Literal["auto", "given"]) -> None:
    """On reproduce-intensity scans (S = 3, the first two sensors not always the smallest, so
    "auto" really reorders): the dual bound never passes the LP optimum, which no Lagrangian
    bound can, and the primal is feasible and not below it."""
    reordered = 0
    for seed in range(6):
        scan = static_scan(seed, n_targets=10, n_sensors=3, ratio=15.0)
        cands = enumerate_candidates(scan.measurements, scan.sensors, n_threads=1)
        tuples, costs, sizes = cands.tuples, cands.costs, cands.sizes
        lp = lp_optimum(tuples, costs, sizes)
        lag = pa.assign_sd(tuples, costs, sizes, sensor_order=sensor_order)
        assert lag.dual_bound <= lp + 1e-7 * abs(lp)
        assert feasible_cost(tuples, costs, lag.chosen) == pytest.approx(lag.primal_cost, abs=1e-9)
        assert lag.primal_cost >= lp - 1e-7 * abs(lp)
        reordered += int(np.argmax(sizes[::-1]) != 0)  # the last maximum is not sensor 3
    assert reordered > 0, "no scan exercised the reordering"


@pytest.mark.parametrize(
    "call,exc,message",
    [
        (lambda: pa.assign_sd([[1], [1]], [-1.0, -1.0], [1]), ValueError, "at least 2 sensors"),
        (lambda: pa.assign_sd([[1, 1]], [-1.0, -1.0], [1, 1]), ValueError, r"costs: expected shape"),
        (lambda: pa.assign_sd([[1, 3]], [-1.0], [1, 2]), ValueError, r"tuples: row 0 column 1 is 3 but sensor 1 has 2"),
        (lambda: pa.assign_sd([[1, -1]], [-1.0], [1, 2]), ValueError, r"tuples: entry 1 is -1"),
        (lambda: pa.assign_sd([[1, 1]], [np.nan], [1, 1]), ValueError, r"costs: non-finite value at index 0"),
        (lambda: pa.assign_sd([[1, 1]], [-1.0], [1, 10**9]), ValueError, r"sizes: 1000000000 exceeds the cap"),
        (lambda: pa.assign_sd([[1, 1]], [-1.0], [1, 1], method="greedy"), ValueError, "method"),
        (lambda: pa.assign_sd([[1, 1]], [-1.0], [1, 1], warm_start="sometimes"), ValueError, "warm_start"),
        (lambda: pa.assign_sd([[1, 1, 1]], [-1.0], [1, 1, 1], sensor_order="largest"), ValueError, "sensor_order"),
        (lambda: pa.assign_sd([[1, 1, 1]], [-1.0], [1, 1, 1], polish="false"), TypeError, "polish"),
        (lambda: pa.assign_sd([["a", "b"]], [-1.0], [1, 1]), TypeError, "tuples"),
        (lambda: pa.assign_sd([[1, 1]], [-1.0], [1, 1], method="exact", time_limit=-1.0), ValueError, "time_limit"),
    ],
)
def test_sd_assignment_bad_input(call, exc, message) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(exc, match=message):
        call()


@pytest.mark.parametrize("time_limit", [2.0**63, 1e19, 1.8e19])
def test_a_time_limit_past_the_clock_is_no_limit(time_limit: float) -> None:
    """Between ≈ 2⁶³ s and 1.8e19 s a time limit passed validation, then panicked ("overflow
    when adding duration to instant") in both solvers; it now binds nothing."""
    for method in ("lagrangian", "exact"):
        solved = pa.assign_sd([[1, 1, 1], [1, 2, 0]], [-5.0, -3.0], [1, 2, 1], method=method, time_limit=time_limit)
        assert solved.chosen.tolist() == [0] and solved.optimal
    scan = static_scan(1, n_targets=4)
    for method in ("lagrangian", "exact"):
        expected = pa.associate_static(scan.measurements, scan.sensors, method, time_limit=None).labels
        got = pa.associate_static(scan.measurements, scan.sensors, method, time_limit=time_limit).labels
        assert got.tolist() == expected.tolist()
        batch = pa.associate_scans(scan.measurements, scan.sensors, method=method, time_limit=time_limit)
        assert batch.labels.tolist() == expected.tolist()
