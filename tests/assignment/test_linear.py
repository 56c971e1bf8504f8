"""The dense 2-D solver against scipy.optimize.linear_sum_assignment (issue: static association)."""

from __future__ import annotations

import numpy as np
import passive_assoc as pa
import pytest
import scipy.sparse as sp
from scipy.optimize import linear_sum_assignment


@pytest.mark.parametrize("shape", [(1, 1), (5, 5), (7, 4), (4, 9), (60, 60)])
def test_linear_assignment_matches_scipy(shape: tuple[int, int]) -> None:
    rng = np.random.default_rng(sum(shape))
    for _ in range(20):
        c = rng.uniform(0, 100, shape)
        if rng.random() < 0.5:
            c = np.round(c / 10)  # ties
        rows, cols, total = pa.linear_assignment(c)
        r_ref, c_ref = linear_sum_assignment(c)
        assert total == pytest.approx(c[r_ref, c_ref].sum(), rel=1e-12)
        assert c[rows, cols].sum() == pytest.approx(total, rel=1e-12)
        assert len(set(rows)) == len(rows) == min(shape) and len(set(cols)) == len(cols)


@pytest.mark.parametrize(
    "call,exc,message",
    [
        (lambda: pa.linear_assignment([[np.nan, 1.0]]), ValueError, "costs"),
        (lambda: pa.linear_assignment([1.0, 2.0]), ValueError, "costs"),
    ],
)
def test_linear_assignment_bad_input(call, exc, message) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(exc, match=message):
        call()


@pytest.mark.parametrize("shape", [(1, 1), (6, 6), (8, 3), (3, 8), (40, 40), (90, 70), (70, 90)])
def test_sparse_and_gated_dense_match_scipy(shape: tuple[int, int]) -> None:
    """A SciPy sparse matrix (absent = forbidden) and the same matrix dense with +inf (which
    the core solves sparse when at most half the entries are allowed) give SciPy's optimum,
    or all three refuse it as infeasible: rectangular both ways, ties, several densities."""
    rng = np.random.default_rng(sum(shape) * 7)
    outcomes = {"solved": 0, "infeasible": 0}
    for trial in range(30):
        density = [0.05, 0.2, 0.45, 0.8][trial % 4]
        c = rng.uniform(0, 100, shape)
        if trial % 3 == 0:
            c = np.round(c / 25)  # ties
        allowed = rng.random(shape) < density
        gated = np.where(allowed, c, np.inf)
        matrix = sp.csr_array((c[allowed], np.nonzero(allowed)), shape=shape)
        try:
            r_ref, c_ref = linear_sum_assignment(gated)
        except ValueError:  # SciPy: "cost matrix is infeasible"
            for costs in (matrix, gated):
                with pytest.raises(ValueError, match="cannot be assigned"):
                    pa.linear_assignment(costs)
            outcomes["infeasible"] += 1
            continue
        expected = gated[r_ref, c_ref].sum()
        for costs in (matrix, gated):
            rows, cols, total = pa.linear_assignment(costs)
            assert total == pytest.approx(expected, rel=1e-12, abs=1e-12)
            assert np.all(allowed[rows, cols]) and np.all(np.diff(rows) > 0)
            assert len(rows) == min(shape) and len(set(cols.tolist())) == len(cols)
        outcomes["solved"] += 1
    assert outcomes["solved"] >= 5
    if min(shape) > 1:
        assert outcomes["infeasible"] >= 1, "the infeasible branch was not exercised"


def test_sparse_input_details() -> None:
    # Stored zeros are allowed pairs; duplicates count at their cheapest (COO sums them, so
    # give CSR parts directly).
    zeros = sp.csr_array((np.array([0.0, 0.0]), np.array([1, 0]), np.array([0, 1, 2])), shape=(2, 2))
    assert pa.linear_assignment(zeros)[2] == 0.0
    dup = sp.csr_array((np.array([5.0, 1.0, 2.0]), np.array([0, 0, 1]), np.array([0, 2, 3])), shape=(2, 2))
    assert pa.linear_assignment(dup)[2] == 3.0
    with pytest.raises(ValueError, match=r"costs: the stored entry at \(0, 0\) is nan"):
        pa.linear_assignment(sp.csr_array(np.array([[np.nan, 1.0], [1.0, 1.0]])))
    with pytest.raises(TypeError, match="complex"):
        pa.linear_assignment(sp.csr_array(np.array([[1j, 1.0], [1.0, 1.0]])))
