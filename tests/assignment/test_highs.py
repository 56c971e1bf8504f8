"""The exact S-D method's HiGHS backend: the same optimum as the branch-and-bound and as brute
force, the "auto" hand-over, limits, and validation identical to the core's."""

from __future__ import annotations

import itertools
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import passive_assoc as pa
import pytest
from numpy.typing import NDArray
from passive_assoc.assignment.sd import SdParameters


def _random_problem(
    seed: int, n_sensors: int, n: int, density: float
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.int64]]:
    rng = np.random.default_rng(seed)
    grid = np.stack(np.meshgrid(*[np.arange(n + 1)] * n_sensors, indexing="ij"), -1).reshape(-1, n_sensors)
    grid = grid[(grid > 0).sum(axis=1) >= 2]
    tuples = grid[rng.random(len(grid)) < density]
    return tuples, rng.normal(-5.0, 3.0, len(tuples)), np.full(n_sensors, n)


def _brute_force(tuples: NDArray[np.int64], costs: NDArray[np.float64]) -> float:
    best = 0.0
    for r in range(1, len(tuples) + 1):
        for subset in itertools.combinations(range(len(tuples)), r):
            used = tuples[list(subset)]
            if all(len(set(c[c > 0])) == (c > 0).sum() for c in used.T):
                best = min(best, float(costs[list(subset)].sum()))
    return best


@pytest.mark.parametrize("seed", range(6))
def test_every_backend_finds_the_brute_force_optimum(seed: int) -> None:
    tuples, costs, sizes = _random_problem(seed, 3, 2, 0.5)
    optimum = _brute_force(tuples, costs)
    for backend in ("auto", "branch_bound", "highs"):
        result = pa.assign_sd(tuples, costs, sizes, method="exact", exact_backend=backend)
        assert result.optimal and result.termination == "optimal"
        assert result.primal_cost == pytest.approx(optimum, abs=1e-9)
        assert result.primal_cost == pytest.approx(float(costs[result.chosen].sum()))


def test_auto_hands_a_hard_problem_to_highs_and_proves_it() -> None:
    tuples, costs, sizes = _random_problem(1, 3, 14, 0.15)  # K ≈ 500: beyond 50 000 nodes
    search = pa.assign_sd(tuples, costs, sizes, method="exact", exact_backend="branch_bound", max_nodes=50_000)
    assert not search.optimal
    auto = pa.assign_sd(tuples, costs, sizes, method="exact")
    highs = pa.assign_sd(tuples, costs, sizes, method="exact", exact_backend="highs")
    assert auto.optimal and highs.optimal
    assert auto.primal_cost == pytest.approx(highs.primal_cost, abs=1e-7)
    assert auto.primal_cost <= search.primal_cost + 1e-9
    assert auto.dual_bound <= auto.primal_cost + 1e-9
    for result in (auto, highs):  # a packing: no report used twice
        used = tuples[result.chosen]
        assert all(len(set(col[col > 0])) == (col > 0).sum() for col in used.T)


def test_highs_stopped_by_its_node_cap_gives_the_same_answer_under_load() -> None:
    """The deterministic stop: HiGHS needs 7 nodes to prove this problem (K = 893); capped at
    2, it stops unproven, and the same input gives the same tuples whether it runs alone or
    beside two other solves on the two cores."""
    tuples, costs, sizes = _random_problem(6, 3, 20, 0.1)

    def solve(_: int = 0) -> pa.SdAssignment:
        return pa.assign_sd(tuples, costs, sizes, method="exact", exact_backend="highs", max_nodes=2)

    alone = solve()
    assert alone.termination == "node_limit" and not alone.optimal
    with ThreadPoolExecutor(3) as pool:
        loaded = list(pool.map(solve, range(3)))
    for result in loaded:
        assert result.termination == "node_limit"
        assert np.array_equal(result.chosen, alone.chosen)
        assert result.primal_cost == alone.primal_cost


def test_a_tiny_time_limit_returns_a_feasible_unproven_answer() -> None:
    tuples, costs, sizes = _random_problem(2, 5, 7, 0.02)
    result = pa.assign_sd(tuples, costs, sizes, method="exact", exact_backend="highs", time_limit=1e-3)
    assert result.termination in ("optimal", "time_limit")
    if not result.optimal:
        assert result.primal_cost <= 0.0 and not result.success
    used = tuples[result.chosen]
    assert all(len(set(col[col > 0])) == (col > 0).sum() for col in used.T)


def test_highs_refuses_what_the_core_refuses() -> None:
    with pytest.raises(ValueError, match="tuples: row 0 column 1 is 3"):
        pa.assign_sd([[1, 3, 1]], [-1.0], [1, 2, 1], method="exact", exact_backend="highs")
    with pytest.raises(ValueError, match="exact_backend"):
        pa.assign_sd([[1, 1, 1]], [-1.0], [1, 1, 1], method="exact", exact_backend="cplex")  # type: ignore[arg-type]


def test_the_lagrangian_honours_time_limit() -> None:
    """A solve that reaches it returns its best feasible answer."""
    tuples, costs, sizes = _random_problem(3, 5, 10, 0.01)
    unlimited = pa.assign_sd(tuples, costs, sizes, gap_tol=0.0, time_limit=None)
    assert unlimited.iterations > 1
    # A microsecond is spent before the first iteration: the loop stops at its first check.
    limited = pa.assign_sd(tuples, costs, sizes, gap_tol=0.0, time_limit=1e-6)
    assert limited.termination == "time_limit" and not limited.optimal and not limited.success
    assert limited.iterations < unlimited.iterations
    assert limited.primal_cost == pytest.approx(float(costs[limited.chosen].sum()))
    used = tuples[limited.chosen]
    assert all(len(set(col[col > 0])) == (col > 0).sum() for col in used.T)
    with pytest.raises(ValueError, match="time_limit"):
        pa.assign_sd(tuples, costs, sizes, time_limit=0.0)


def test_what_highs_prints_to_standard_output_is_dropped(
    monkeypatch: pytest.MonkeyPatch, capfd: pytest.CaptureFixture[str]
) -> None:
    """HiGHS writes some messages ("HighsMipSolverData::…") to file descriptor 1 whatever
    ``disp`` says, into library calls' and ``passive-assoc associate --method exact``'s
    output. A stand-in solver writes such a line, and a line of someone else's, straight to
    descriptor 1: HiGHS's is dropped, the other passed on, and the answer is unchanged."""
    import os

    from passive_assoc.assignment import highs

    real = highs.milp

    def chatty(*args: object, **kwargs: object) -> object:
        os.write(1, b"HighsMipSolverData::transformNewIntegerFeasibleSolution tmpSolver.run();\n")
        os.write(1, b"another thread's line\n")
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(highs, "milp", chatty)
    tuples, costs, sizes = _random_problem(1, 3, 4, 0.3)
    print("before", flush=True)
    solved = pa.assign_sd(tuples, costs, sizes, method="exact", exact_backend="highs")
    print("after")
    out = capfd.readouterr().out
    assert out == "before\nanother thread's line\nafter\n"
    assert solved.optimal


def test_the_default_stop_is_the_node_cap_and_gives_the_same_answer_under_load() -> None:
    # Two threads solve the same hard problem while two more load the machine: with the
    # default (no time limit) the search stops on its node cap with one and the same answer,
    # alone and under load; HiGHS, which proves these at its root, gives the same optimum.
    tuples, costs, sizes = _random_problem(1, 3, 14, 0.15)
    assert SdParameters().time_limit is None
    load = pa.assign_sd(*_random_problem(2, 3, 14, 0.15), method="exact")
    for backend, nodes in (("branch_bound", 20_000), ("auto", 1), ("highs", 1)):

        def solve(backend: str = backend, nodes: int = nodes) -> tuple[list[int], float, str]:
            r = pa.assign_sd(tuples, costs, sizes, method="exact", exact_backend=backend, max_nodes=nodes)
            return r.chosen.tolist(), r.primal_cost, r.termination

        alone = solve()
        assert alone[2] == ("node_limit" if backend == "branch_bound" else "optimal"), (backend, alone[2])
        with ThreadPoolExecutor(4) as pool:
            busy = [pool.submit(pa.assign_sd, *_random_problem(2, 3, 14, 0.15), method="exact") for _ in range(2)]
            loaded = [f.result() for f in [pool.submit(solve) for _ in range(2)]]
            if backend == "branch_bound":
                assert all(answer == alone for answer in loaded)
            else:  # an equal-cost optimum may be another set, summed in another order
                assert all(a[1] == pytest.approx(alone[1], abs=1e-9) and a[2] == alone[2] for a in loaded)
            assert all(f.result().primal_cost == pytest.approx(load.primal_cost, abs=1e-9) for f in busy)
