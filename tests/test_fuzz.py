"""Fuzzing the public entry points: whatever a caller passes, the answer is a valid result or a
clear ValueError/TypeError. A PanicException (a BaseException) or an abort fails the run.

Each entry point draws mostly *valid* inputs — so the calls reach the compiled core and its
answers are checked (every input row in exactly one output, no NaN where a result promises
finite values, optimality against SciPy where it is cheap) — and, in about one example in
four, replaces one argument with a hostile value: odd dtypes and shapes, empty arrays, NaN,
±inf, ±1e300, 2⁶³, 2⁷⁰, strings, None, bools. Each test counts its valid results and fails
when they fall below :data:`MIN_VALID` of its examples: a fuzz test whose inputs never get
past the argument checks tests nothing (this file once reached a valid result in 0 of 40
examples for several entry points).

The suite runs :data:`EXAMPLES` examples per entry point (11 entry points, 2 200 examples,
about 15 s); a larger budget on demand:

    FUZZ_EXAMPLES=3000 python3 -m pytest -q -W error::RuntimeWarning tests/test_fuzz.py

Each call is bounded: a Hypothesis deadline of 10 s per example (a hang detector — the calls
take milliseconds — not a benchmark), and on Linux the address space is capped at 3 GB above
what the process holds when the module starts, so a call that tried to take the machine's
memory raises MemoryError (or, from an unchecked allocation, aborts the run) instead of
swapping.
"""

from __future__ import annotations

import datetime
import functools
import os
import sys
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import passive_assoc as pa
import pytest
import scipy.sparse as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy.optimize import linear_sum_assignment

#: Examples per entry point.
EXAMPLES = int(os.environ.get("FUZZ_EXAMPLES", "200"))
#: Share of an entry point's examples that must end in a valid (and checked) result.
MIN_VALID = 0.5
FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=datetime.timedelta(seconds=10),
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    derandomize=True,
    database=None,
)
#: Address space each call may add to what the process holds when the module starts.
MEMORY_HEADROOM = 3 << 30


@pytest.fixture(autouse=True, scope="module")
def bounded_memory() -> Any:
    """Caps the soft RLIMIT_AS for this module's tests and restores it after (Linux)."""
    if not sys.platform.startswith("linux"):
        yield
        return
    import resource

    with open("/proc/self/status") as status:
        held = next(int(line.split()[1]) * 1024 for line in status if line.startswith("VmSize:"))
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    cap = held + MEMORY_HEADROOM
    if hard != resource.RLIM_INFINITY:
        cap = min(cap, hard)
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


# ---------------------------------------------------------------------------------- hostility

#: Values that break arithmetic or types.
HOSTILE_NUMBER = st.sampled_from(
    [np.nan, np.inf, -np.inf, 1e300, -1e300, 0.0, -1.0, 2.0**63, 2**63, 2**70, -(2**70), 1e-300, True]
)
HOSTILE = st.one_of(
    HOSTILE_NUMBER,
    st.none(),
    st.text(max_size=3),
    st.lists(HOSTILE_NUMBER, max_size=3),
    hnp.arrays(
        st.sampled_from([np.float64, np.int64, np.bool_, np.complex128]),
        hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=3),
        elements=None,
    ),
)


@st.composite
def mutated(draw: st.DrawFn, valid: dict[str, st.SearchStrategy[Any]], hostile: dict[str, Any]) -> dict[str, Any]:
    """The arguments ``valid`` draws, with (in about one case in four) one of the ``hostile``
    ones replaced by what its strategy there draws. A case records what it replaced."""
    case = {name: draw(strategy) for name, strategy in valid.items()}
    if draw(st.sampled_from([False, False, False, True])):
        name = draw(st.sampled_from(sorted(hostile)))
        case[name] = draw(hostile[name])
        case["_mutated"] = name
    return case


@dataclass
class Tally:
    """Valid results and refusals of one entry point's examples."""

    name: str
    valid: int = 0
    refused: int = 0

    def check(self) -> None:
        total = self.valid + self.refused
        print(f"{self.name}: {self.valid} valid results of {total} examples")
        assert total > 0, f"{self.name}: no example ran"
        assert self.valid >= MIN_VALID * total, (
            f"{self.name}: only {self.valid} of {total} examples reached a valid result; the fuzzing is vacuous"
        )


def fuzz(name: str, cases: st.SearchStrategy[dict[str, Any]], call: Callable[[dict[str, Any]], Any]) -> None:
    """Runs ``call`` on every case: a result (checked by ``call`` itself) or a ValueError or
    TypeError; then asserts the share of valid results."""
    tally = Tally(name)

    @FUZZ
    @given(case=cases)
    def run(case: dict[str, Any]) -> None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # "angles beyond ±2π: degrees?" and the like
            try:
                call(case)
            except (ValueError, TypeError):
                tally.refused += 1
                return
        tally.valid += 1

    run()
    tally.check()


def _partitioned(labels: np.ndarray, clutter: np.ndarray, n_rows: int) -> None:
    """Every input row is in exactly one group or in the clutter."""
    assert len(labels) == n_rows
    assert sorted(clutter.tolist()) == np.flatnonzero(labels < 0).tolist()


# --------------------------------------------------------------------------------- the inputs


@functools.cache
def _network() -> pa.SensorNetwork:
    return pa.SensorNetwork.planar(np.array([[-1e4, 0.0], [0.0, -5e3], [1e4, 0.0]]), 1e-2)


@functools.cache
def _fti() -> pa.Scenario:
    return pa.paper_fti_scenario(1)


@st.composite
def scans(draw: st.DrawFn) -> pa.MeasurementTable:
    """One scan of the 3-sensor network: 1–4 targets seen with small noise, plus a false
    alarm or two, each report with an ``rf`` attribute."""
    n_targets = draw(st.integers(1, 4))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    targets = np.column_stack([rng.uniform(-8e3, 8e3, n_targets), rng.uniform(15e3, 35e3, n_targets)])
    positions = _network().positions[:, :2]
    sensor, azimuth, rf = [], [], []
    for s, p in enumerate(positions):
        for t, target in enumerate(targets):
            if rng.random() < 0.9:
                sensor.append(s)
                azimuth.append(np.arctan2(target[1] - p[1], target[0] - p[0]) + rng.normal(0, 5e-3))
                rf.append(1000.0 * t + rng.normal(0, 5.0))
    for _ in range(draw(st.integers(0, 2))):
        sensor.append(int(rng.integers(0, 3)))
        azimuth.append(rng.uniform(0.3, 2.8))
        rf.append(rng.uniform(0, 4000))
    n = len(sensor)
    return pa.MeasurementTable.from_arrays(np.array(sensor), np.zeros(n), np.array(azimuth), attributes={"rf": rf})


def _costs(draw: st.DrawFn, shape: tuple[int, int]) -> np.ndarray:
    values = draw(hnp.arrays(np.float64, shape, elements=st.floats(-50, 50, allow_nan=False)))
    forbidden = draw(hnp.arrays(np.bool_, shape))
    return np.where(forbidden & (draw(st.integers(0, 2)) == 0), np.inf, values)


# ---------------------------------------------------------------------------------- the tests


@st.composite
def sd_problems(draw: st.DrawFn) -> dict[str, Any]:
    n_sensors = draw(st.integers(2, 4))
    sizes = draw(hnp.arrays(np.int64, n_sensors, elements=st.integers(1, 4)))
    rows = draw(st.integers(0, 12))
    tuples = np.column_stack([draw(hnp.arrays(np.int64, rows, elements=st.integers(0, int(n)))) for n in sizes])
    tuples = tuples[(tuples > 0).sum(axis=1) >= 1] if rows else np.zeros((0, n_sensors), dtype=np.int64)
    costs = draw(hnp.arrays(np.float64, len(tuples), elements=st.floats(-20, 5)))
    return {"tuples": tuples, "costs": costs, "sizes": sizes}


def test_assign_sd() -> None:
    valid = {
        "problem": sd_problems(),
        "method": st.sampled_from(["lagrangian", "exact"]),
        "exact_backend": st.sampled_from(["auto", "branch_bound", "highs"]),
        "time_limit": st.sampled_from([1.0, None]),
        "max_nodes": st.sampled_from([10, 10_000]),
    }
    hostile = {"tuples": HOSTILE, "costs": HOSTILE, "sizes": HOSTILE, "time_limit": HOSTILE, "max_nodes": HOSTILE}

    def call(case: dict[str, Any]) -> None:
        problem = case.pop("problem")
        args = {k: case.pop(k, problem[k]) for k in ("tuples", "costs", "sizes")}
        case.pop("_mutated", None)
        out = pa.assign_sd(args["tuples"], args["costs"], args["sizes"], **case)
        tuples, costs = np.asarray(args["tuples"]), np.asarray(args["costs"], dtype=float)
        chosen = tuples[out.chosen]
        for column in chosen.T:  # each report used at most once
            used = column[column > 0]
            assert len(np.unique(used)) == len(used)
        assert np.isclose(costs[out.chosen].sum(), out.primal_cost, rtol=1e-9, atol=1e-9)
        assert out.dual_bound <= out.primal_cost + 1e-6 * max(1.0, abs(out.primal_cost))

    fuzz("assign_sd", mutated(valid, hostile), call)


def test_linear_assignment() -> None:
    @st.composite
    def costs(draw: st.DrawFn) -> Any:
        shape = (draw(st.integers(1, 5)), draw(st.integers(1, 5)))
        dense = _costs(draw, shape)
        if not draw(st.booleans()):
            return dense
        # Sparse, with duplicates: each stored entry of a pair may be stored again, dearer.
        row, col = np.nonzero(np.isfinite(dense))
        extra = draw(st.integers(0, len(row)))
        row = np.concatenate([row, row[:extra]])
        col = np.concatenate([col, col[:extra]])
        data = np.concatenate([dense[np.isfinite(dense)], dense[np.isfinite(dense)][:extra] + 7.0])
        return sp.coo_array((data, (row, col)), shape=shape)

    huge = st.just(sp.coo_array(([1.0, 2.0], ([0, 1], [3, 10**9 - 1])), shape=(2, 10**9)))
    hostile = {"costs": st.one_of(HOSTILE, huge)}

    def call(case: dict[str, Any]) -> None:
        rows, cols, total = pa.linear_assignment(case["costs"])
        matrix = case["costs"]
        if sp.issparse(matrix) and matrix.shape[1] > 100:
            assert total == 3.0
            return
        if sp.issparse(matrix):  # the cheapest of duplicates counts
            dense = np.full(matrix.shape, np.inf)
            coo = matrix.tocoo()
            np.minimum.at(dense, (coo.row, coo.col), coo.data)
        else:
            dense = np.asarray(matrix, dtype=float)
        r, c = linear_sum_assignment(dense)
        assert np.isclose(total, dense[r, c].sum(), rtol=1e-9, atol=1e-9)
        assert np.isclose(dense[rows, cols].sum(), total, rtol=1e-9, atol=1e-9)

    fuzz("linear_assignment", mutated({"costs": costs()}, hostile), call)


def test_measurement_table() -> None:
    n = st.shared(st.integers(1, 6), key="rows")
    valid = {
        "sensor": n.flatmap(lambda k: hnp.arrays(np.int64, k, elements=st.integers(0, 3))),
        "time": n.flatmap(lambda k: hnp.arrays(np.float64, k, elements=st.floats(-1e6, 1e6))),
        "azimuth": n.flatmap(lambda k: hnp.arrays(np.float64, k, elements=st.floats(-np.pi, np.pi))),
    }
    hostile = dict.fromkeys(valid, HOSTILE)

    def call(case: dict[str, Any]) -> None:
        table = pa.MeasurementTable.from_arrays(case["sensor"], case["time"], case["azimuth"])
        assert len(table) == len(case["sensor"])

    fuzz("MeasurementTable.from_arrays", mutated(valid, hostile), call)


def test_sensor_network() -> None:
    n = st.shared(st.integers(1, 5), key="sensors")
    valid = {
        "positions": n.map(lambda k: np.column_stack([np.arange(k) * 1e3, np.zeros(k)])),
        "sigma": n.flatmap(lambda k: hnp.arrays(np.float64, k, elements=st.floats(1e-6, 0.5))),
    }
    hostile = dict.fromkeys(valid, HOSTILE)

    def call(case: dict[str, Any]) -> None:
        assert pa.SensorNetwork.planar(case["positions"], case["sigma"]).n_sensors == len(case["positions"])

    fuzz("SensorNetwork.planar", mutated(valid, hostile), call)


def test_locate_formation() -> None:
    valid = {
        "table": scans(),
        "std": st.floats(1.0, 100.0),
        "eta": st.floats(0.05, 0.95),
        "one_to_one": st.booleans(),
        "r_max": st.floats(5e4, 3e5),
    }
    hostile = {"std": HOSTILE, "eta": HOSTILE, "one_to_one": HOSTILE, "r_max": HOSTILE, "max_pairs": HOSTILE}

    def call(case: dict[str, Any]) -> None:
        table = case["table"]
        extra = {"max_pairs": case["max_pairs"]} if "max_pairs" in case else {}
        result = pa.locate_formation(
            table,
            _network(),
            attribute_std={"rf": case["std"]},
            eta=case["eta"],
            one_to_one=case["one_to_one"],
            r_max=case["r_max"],
            progress=False,
            **extra,
        )
        _partitioned(result.labels, result.clutter, len(table))
        assert np.isfinite(result.positions[result.associated]).all()
        assert np.isfinite(result.covariances[result.associated]).all()

    fuzz("locate_formation", mutated(valid, hostile), call)


def test_associate_static() -> None:
    valid = {
        "table": scans(),
        "method": st.sampled_from(["intensity", "lagrangian", "exact"]),
        "pd": st.floats(0.5, 0.99),
        "gate_sigmas": st.floats(1.0, 5.0),
        "time_limit": st.just(1.0),
    }
    hostile = {
        "pd": HOSTILE,
        "gate_sigmas": HOSTILE,
        "time_limit": HOSTILE,
        "false_alarm_density": HOSTILE,
        "max_candidates": HOSTILE,
    }

    def call(case: dict[str, Any]) -> None:
        table, method = case.pop("table"), case.pop("method")
        case.pop("_mutated", None)
        result = pa.associate_static(table, _network(), method, **case)
        _partitioned(result.labels, result.clutter, len(table))
        assert np.isfinite(result.positions).all()

    fuzz("associate_static", mutated(valid, hostile), call)


def test_associate_scans() -> None:
    @st.composite
    def two_scans(draw: st.DrawFn) -> pa.MeasurementTable:
        first, second = draw(scans()).to_arrays(), draw(scans()).to_arrays()
        columns = {k: np.concatenate([first[k], second[k]]) for k in first}
        columns["time"] = np.repeat([0.0, 1.0], [len(first["time"]), len(second["time"])])
        return pa.MeasurementTable.from_columns(columns)

    valid = {
        "table": two_scans(),
        "method": st.sampled_from(["intensity", "lagrangian", "exact"]),
        "pd": st.floats(0.5, 0.99),
    }
    hostile = {"pd": HOSTILE, "false_alarm_density": HOSTILE, "n_threads": HOSTILE, "time_limit": HOSTILE}

    def call(case: dict[str, Any]) -> None:
        table, method = case.pop("table"), case.pop("method")
        case.pop("_mutated", None)
        out = pa.associate_scans(table, _network(), method=method, progress=False, **case)
        inside = out.labels >= 0
        assert np.all(out.target_scan[out.labels[inside]] == out.scan[inside])

    fuzz("associate_scans", mutated(valid, hostile), call)


def test_fit_ml() -> None:
    valid = {
        "table": scans(),
        "groups": st.lists(st.lists(st.integers(0, 3), min_size=2, max_size=4, unique=True), min_size=1, max_size=3),
        "t0": st.one_of(st.none(), st.floats(-1e3, 1e3)),
    }
    hostile = {"groups": st.lists(HOSTILE, min_size=1, max_size=2), "t0": HOSTILE, "max_iter": HOSTILE}

    def call(case: dict[str, Any]) -> None:
        hostile_groups = case.get("_mutated") == "groups"
        groups = case["groups"] if hostile_groups else [np.asarray(g) for g in case["groups"]]
        extra = {"max_iter": case["max_iter"]} if "max_iter" in case else {}
        fit = pa.fit_ml(case["table"], _network(), groups, motion="static", t0=case["t0"], **extra)
        assert fit.estimates.shape == (len(groups), 2)

    fuzz("fit_ml", mutated(valid, hostile), call)


def test_closeness() -> None:
    valid = {
        "noise": st.floats(0.0, 500.0),
        "t0": st.one_of(st.none(), st.floats(-100.0, 100.0)),
        "spread": st.floats(0.5, 5.0),
    }
    hostile = {"states": HOSTILE, "t0": HOSTILE, "spread": HOSTILE}

    def call(case: dict[str, Any]) -> None:
        scenario = _fti()
        states = case.get("states", scenario.true_states + case["noise"])
        values, gradients = pa.closeness(
            scenario.measurements, scenario.sensors, states, t0=case["t0"], spread_factor=case["spread"]
        )
        assert np.isfinite(values).all() and np.isfinite(gradients).all()

    fuzz("closeness", mutated(valid, hostile), call)


def test_kalman_filter() -> None:
    n = st.shared(st.integers(3, 8), key="rows")
    valid = {
        "times": n.flatmap(lambda k: hnp.arrays(np.float64, k, elements=st.floats(0.0, 1e3), unique=True)),
        "measurements": n.flatmap(lambda k: hnp.arrays(np.float64, (k, 2), elements=st.floats(-1e5, 1e5))),
        "noise": st.floats(0.1, 100.0),
        "process_noise": st.floats(0.0, 10.0),
        "motion": st.sampled_from(["cv", "ca"]),
    }
    hostile = {"times": HOSTILE, "measurements": HOSTILE, "noise": HOSTILE, "process_noise": HOSTILE}

    def call(case: dict[str, Any]) -> None:
        times = case["times"]
        order = np.argsort(times) if isinstance(times, np.ndarray) and times.ndim == 1 else np.arange(3)
        kf = pa.KalmanFilter(process_noise=case["process_noise"], motion=case["motion"])
        out = kf.filter(times, case["measurements"], order, noise=case["noise"])
        variances = np.diagonal(out.covariances, axis1=1, axis2=2)[out.has_state]
        assert np.isfinite(out.states[out.has_state]).all() and (variances >= 0).all()

    fuzz("KalmanFilter.filter", mutated(valid, hostile), call)


def test_nearest_neighbour_associator() -> None:
    @st.composite
    def pictures(draw: st.DrawFn) -> tuple[pa.TrackTable, pa.TrackTable]:
        n_local, n_system = draw(st.integers(0, 6)), draw(st.integers(1, 6))
        rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))

        def table(source: int, n: int) -> pa.TrackTable:
            cov = np.tile(np.eye(2) * 1e4, (n, 1, 1))
            position = rng.uniform(-5e3, 5e3, (n, 2))
            return pa.TrackTable.from_arrays(np.full(n, source), np.arange(n), np.zeros(n), position, covariance=cov)

        return table(1, n_local), table(0, n_system)

    valid = {
        "pictures": pictures(),
        "gate": st.one_of(st.none(), st.floats(10.0, 1e4)),
        "window": st.integers(1, 3),
        "gate_probability": st.one_of(st.none(), st.floats(0.5, 0.999)),
    }
    hostile = {"gate": HOSTILE, "window": HOSTILE, "gate_probability": HOSTILE, "n_threads": HOSTILE}

    def call(case: dict[str, Any]) -> None:
        local, system = case.pop("pictures")
        case.pop("_mutated", None)
        out = pa.NearestNeighbourAssociator(**case).associate(local=local, system=system, progress=False)
        assert len(out.pairs) + len(out.unpaired_local) == len(local)
        if len(local):  # the system tracks are accounted for per local source: here one
            assert len(out.pairs) + len(out.unpaired_system) == len(system)

    fuzz("NearestNeighbourAssociator", mutated(valid, hostile), call)


def test_the_fuzz_budget_is_large_enough() -> None:
    """11 entry points × EXAMPLES: at least 2 000 examples in the suite."""
    assert 11 * EXAMPLES >= 2000


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS is capped on Linux")
def test_the_memory_cap_is_in_force() -> None:
    """Without the cap a 2·headroom allocation would succeed lazily (untouched pages); under it
    it is refused, so the fuzzed calls above ran bounded."""
    with pytest.raises(MemoryError):
        np.empty(2 * MEMORY_HEADROOM // 8)
