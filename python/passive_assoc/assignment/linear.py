"""2-D linear assignment, dense or sparse, in the Rust core with the GIL released."""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._validation import as_float_array

__all__ = ["linear_assignment"]


def linear_assignment(costs: ArrayLike | Any) -> tuple[NDArray[np.int64], NDArray[np.int64], float]:
    """Min-cost rectangular 2-D assignment (Jonker-Volgenant shortest augmenting paths).

    Same contract as :func:`scipy.optimize.linear_sum_assignment` — every row is assigned when
    there are at most as many rows as columns, every column otherwise — plus the total cost.

    Parameters
    ----------
    costs : array_like or scipy.sparse matrix
        Dense ``(n_rows, n_cols)`` costs, ``+inf`` forbidding a pair; or a SciPy sparse
        matrix or array (any format), whose *absent* entries are the forbidden pairs (stored
        zeros are allowed pairs of cost 0; the cheapest of duplicate entries counts). The
        sparse solve touches only the stored entries.

    Returns
    -------
    (row_ind, col_ind, total)
        The assigned pairs by increasing row, and the sum of their costs.

    Raises
    ------
    ValueError
        NaN or ``-inf`` costs, costs beyond ±1e150, or forbidden pairs that leave no complete
        assignment (naming the row or column that cannot be assigned).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> linear_assignment([[4.0, 1.0, 3.0], [2.0, 0.0, 5.0]])
    (array([0, 1]), array([1, 0]), 3.0)
    >>> linear_assignment(sp.csr_array(([5.0, 4.0, 1.0], ([0, 1, 1], [1, 0, 1])), shape=(2, 2)))
    (array([0, 1]), array([1, 0]), 9.0)
    """
    if sp.issparse(costs):
        return _sparse(costs)
    matrix = as_float_array("costs", costs, ndim=2)
    return _core.assign_2d(matrix)


def _sparse(costs: Any) -> tuple[NDArray[np.int64], NDArray[np.int64], float]:
    csr = sp.csr_array(costs)
    if csr.ndim != 2:
        raise ValueError(f"costs: expected a 2-dimensional sparse matrix, got shape {csr.shape}")
    if not np.issubdtype(csr.dtype, np.number) or np.issubdtype(csr.dtype, np.complexfloating):
        raise TypeError(f"costs: expected real numeric entries, got dtype {csr.dtype}")
    data = np.asarray(csr.data, dtype=np.float64)
    bad = np.flatnonzero(~np.isfinite(data))
    if len(bad):
        k = int(bad[0])
        row = int(np.searchsorted(csr.indptr, k, side="right")) - 1
        raise ValueError(
            f"costs: the stored entry at ({row}, {int(csr.indices[k])}) is {data[k]}; stored entries must be "
            "finite (leave a forbidden pair out of the sparse matrix)"
        )
    n_rows, n_cols = csr.shape
    return _core.assign_2d_sparse(
        (int(n_rows), int(n_cols)),
        np.ascontiguousarray(csr.indptr, dtype=np.int64),
        np.ascontiguousarray(csr.indices, dtype=np.int64),
        np.ascontiguousarray(csr.data, dtype=np.float64),
    )
