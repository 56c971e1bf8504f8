"""The dense 2-D solver against scipy.optimize.linear_sum_assignment (issue: static association)."""

from __future__ import annotations

import numpy as np
import passive_assoc as pa
import pytest
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
