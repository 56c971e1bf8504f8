"""Dense 2-D linear assignment, in the Rust core with the GIL released."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._validation import as_float_array


def linear_assignment(costs: ArrayLike) -> tuple[NDArray[np.int64], NDArray[np.int64], float]:
    """Dense min-cost rectangular 2-D assignment (Jonker-Volgenant shortest augmenting path).

    Same contract as :func:`scipy.optimize.linear_sum_assignment` (``+inf`` forbids a pair),
    plus the total cost. Returns ``(row_ind, col_ind, total)``.
    """
    matrix = as_float_array("costs", costs, ndim=2)
    return _core.assign_2d(matrix)
