"""Fuzzing the public entry points: whatever a caller passes — wrong dtypes and shapes, NaN,
±inf, huge and negative values, empty arrays, strings — the answer is a clear ValueError or
TypeError, or a valid result. A PanicException (a BaseException) or an abort fails the run.

The suite runs a small budget; a large one on demand:

    FUZZ_EXAMPLES=2000 python3 -m pytest -q tests/test_fuzz.py

Each call is bounded: a Hypothesis deadline of 10 s per example (a hang detector — the calls
take milliseconds — not a benchmark), and on Linux the address space is capped at 3 GB above
what the process holds when the module starts, so a call that tried to take the machine's
memory raises MemoryError (or, from an unchecked allocation, aborts the run) instead of
swapping.
"""

from __future__ import annotations

import contextlib
import datetime
import os
import sys
from collections.abc import Callable
from typing import Any

import numpy as np
import passive_assoc as pa
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

EXAMPLES = int(os.environ.get("FUZZ_EXAMPLES", "40"))
FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=datetime.timedelta(seconds=10),
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=True,
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


#: Values that break arithmetic, and plain ones.
SPECIAL = st.sampled_from([0.0, -0.0, 1.0, -1.0, 1e-300, 1e300, -1e300, np.nan, np.inf, -np.inf, 2.0**63])
NUMBER = st.one_of(SPECIAL, st.floats(-1e6, 1e6), st.integers(-(2**70), 2**70))


def arrays(max_dims: int = 2, max_side: int = 4) -> st.SearchStrategy[Any]:
    """Arrays of float or int dtype and odd shapes, and things that are not arrays at all."""
    shapes = hnp.array_shapes(min_dims=0, max_dims=max_dims, min_side=0, max_side=max_side)
    floats = hnp.arrays(np.float64, shapes, elements=st.one_of(SPECIAL, st.floats(-1e4, 1e4)))
    ints = hnp.arrays(np.int64, shapes, elements=st.integers(-3, 5))
    junk = st.one_of(st.none(), st.text(max_size=3), st.lists(NUMBER, max_size=3), NUMBER)
    return st.one_of(floats, ints, junk)


def _accepts(call: Callable[[], Any]) -> None:
    """The call either returns or raises ValueError/TypeError (MemoryError would be a bug
    here too: every input is tiny)."""
    with contextlib.suppress(ValueError, TypeError):
        call()


def _network() -> pa.SensorNetwork:
    return pa.SensorNetwork.planar(np.array([[-1e4, 0.0], [0.0, -5e3], [1e4, 0.0]]), 1e-2)


@FUZZ
@given(tuples=arrays(), costs=arrays(1), sizes=arrays(1), method=st.sampled_from(["lagrangian", "exact"]))
def test_assign_sd(tuples: Any, costs: Any, sizes: Any, method: str) -> None:
    _accepts(lambda: pa.assign_sd(tuples, costs, sizes, method=method, time_limit=1.0))  # type: ignore[arg-type]


@FUZZ
@given(costs=arrays(2, 5))
def test_linear_assignment(costs: Any) -> None:
    _accepts(lambda: pa.linear_assignment(costs))


@FUZZ
@given(sensor=arrays(1, 6), azimuth=arrays(1, 6), time=arrays(1, 6))
def test_measurement_table(sensor: Any, azimuth: Any, time: Any) -> None:
    _accepts(lambda: pa.MeasurementTable.from_arrays(sensor, time, azimuth))


@FUZZ
@given(positions=arrays(2, 4), sigma=arrays(1, 4))
def test_sensor_network(positions: Any, sigma: Any) -> None:
    _accepts(lambda: pa.SensorNetwork.planar(positions, sigma))


@st.composite
def scans(draw: st.DrawFn) -> pa.MeasurementTable:
    """A valid table of one scan of 3 sensors with arbitrary (finite) bearings and attributes."""
    n = draw(st.integers(1, 9))
    sensor = draw(hnp.arrays(np.int64, n, elements=st.integers(0, 2)))
    azimuth = draw(hnp.arrays(np.float64, n, elements=st.floats(-4.0, 4.0)))
    rf = draw(hnp.arrays(np.float64, n, elements=st.floats(-1e6, 1e6)))
    return pa.MeasurementTable.from_arrays(sensor, np.zeros(n), azimuth, attributes={"rf": rf})


@FUZZ
@given(table=scans(), std=NUMBER, eta=NUMBER, one_to_one=st.booleans(), r_max=NUMBER)
def test_locate_formation(table: pa.MeasurementTable, std: Any, eta: Any, one_to_one: bool, r_max: Any) -> None:
    def call() -> None:
        result = pa.locate_formation(
            table, _network(), attribute_std={"rf": std}, eta=eta, one_to_one=one_to_one, r_max=r_max
        )
        assert len(result.clutter) + int((result.labels >= 0).sum()) == len(table)

    _accepts(call)


@FUZZ
@given(table=scans(), method=st.sampled_from(["intensity", "lagrangian", "exact"]), pd=NUMBER, gate=NUMBER)
def test_associate_static(table: pa.MeasurementTable, method: str, pd: Any, gate: Any) -> None:
    def call() -> None:
        result = pa.associate_static(table, _network(), method, pd=pd, gate_sigmas=gate, time_limit=1.0)  # type: ignore[arg-type]
        assert len(result.clutter) + int((result.rows >= 0).sum()) == len(table)

    _accepts(call)


@FUZZ
@given(table=scans(), groups=st.lists(arrays(1, 5), min_size=0, max_size=3), t0=NUMBER)
def test_fit_ml(table: pa.MeasurementTable, groups: list[Any], t0: Any) -> None:
    _accepts(lambda: pa.fit_ml(table, _network(), groups, motion="static", t0=t0))


@FUZZ
@given(states=arrays(2, 4), t0=NUMBER, spread=NUMBER)
def test_closeness(states: Any, t0: Any, spread: Any) -> None:
    scenario = pa.paper_fti_scenario(1)
    _accepts(lambda: pa.closeness(scenario.measurements, scenario.sensors, states, t0=t0, spread_factor=spread))


@pytest.mark.parametrize("budget", [EXAMPLES])
def test_budget_is_positive(budget: int) -> None:
    """FUZZ_EXAMPLES must be a positive count, or the tests above would check nothing."""
    assert budget > 0


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS is capped on Linux")
def test_the_memory_cap_is_in_force() -> None:
    """Without the cap a 2·headroom allocation would succeed lazily (untouched pages); under it
    it is refused, so the fuzzed calls above ran bounded."""
    with pytest.raises(MemoryError):
        np.empty(2 * MEMORY_HEADROOM // 8)
