"""2-D linear assignment, dense or sparse, in the Rust core with the GIL released (dense: above 16 × 16)."""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._validation import as_float_array

__all__ = ["linear_assignment"]

# The dense entry types the core reads as they are.
_NATIVE = (np.dtype(np.float64), np.dtype(np.float32))


def linear_assignment(costs: ArrayLike | Any) -> tuple[NDArray[np.int64], NDArray[np.int64], float]:
    """Min-cost rectangular 2-D assignment (Jonker-Volgenant shortest augmenting paths).

    Same contract as :func:`scipy.optimize.linear_sum_assignment` — every row is assigned when
    there are at most as many rows as columns, every column otherwise — plus the total cost.

    Parameters
    ----------
    costs : array_like or scipy.sparse matrix
        Dense ``(n_rows, n_cols)`` costs, ``+inf`` forbidding a pair; or a SciPy sparse
        matrix or array (any format), whose *absent* entries are the forbidden pairs (stored
        zeros are allowed pairs of cost 0; of duplicate entries of a pair the cheapest
        counts, in every format — they are not summed as SciPy's conversions sum them). The
        sparse solve touches only the stored entries, and its memory grows with them, not
        with the shape. A float32 matrix is solved as it is, with no float64 copy, and
        exactly: its entries are read as the float64 values they equal, and the sums are
        formed in double precision.

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
    if type(costs) is np.ndarray:
        # The common call, a C-ordered float64 or float32 matrix, goes straight to the core:
        # a small solve is then not mostly Python. The core refuses any other array
        # (TypeError: dtype or dimensions; ValueError: order), which the conversions below
        # then take.
        try:
            return _core.assign_2d(costs)
        except (TypeError, ValueError):
            flags = costs.flags
            if costs.dtype in _NATIVE and costs.ndim == 2 and flags.c_contiguous and flags.aligned:
                raise  # the core's verdict on this very matrix (NaN, no complete assignment)
        if costs.dtype == np.float32 and costs.ndim == 2:
            # Kept in single precision: a C-ordered, aligned copy (a misaligned C-ordered
            # array is copied too, which `ascontiguousarray` would return as it is).
            return _core.assign_2d(np.require(costs, requirements=["C", "A"]))
    if sp.issparse(costs):
        return _sparse(costs)
    matrix = as_float_array("costs", costs, ndim=2)
    return _core.assign_2d(matrix)


def _sparse(costs: Any) -> tuple[NDArray[np.int64], NDArray[np.int64], float]:
    """The sparse solve, sized by the stored entries: duplicates of a pair keep their cheapest
    (SciPy's own conversions would sum them), and the problem handed to the core has only the
    rows and columns the entries use, so a matrix of shape (3, 10⁹) with three entries takes
    a few bytes, not gigabytes."""
    if len(costs.shape) != 2:
        raise ValueError(f"costs: expected a 2-dimensional sparse matrix, got shape {costs.shape}")
    if not np.issubdtype(costs.dtype, np.number) or np.issubdtype(costs.dtype, np.complexfloating):
        raise TypeError(f"costs: expected real numeric entries, got dtype {costs.dtype}")
    row, col, data = _entries(costs)
    bad = np.flatnonzero(~np.isfinite(data))
    if len(bad):
        k = int(bad[0])
        raise ValueError(
            f"costs: the stored entry at ({row[k]}, {col[k]}) is {data[k]}; stored entries must be "
            "finite (leave a forbidden pair out of the sparse matrix)"
        )
    n_rows, n_cols = (int(n) for n in costs.shape)
    # Every row is assigned when n_rows <= n_cols, every column otherwise: that side keeps its
    # indices (and must be covered by the entries); the other keeps only the indices in use.
    if n_rows <= n_cols:
        _every_index_used("row", row, n_rows)
        cols, col = _in_use(col, n_cols)
        rows, shape = None, (n_rows, max(len(cols), n_rows))
    else:
        _every_index_used("column", col, n_cols)
        rows, row = _in_use(row, n_rows)
        cols, shape = None, (max(len(rows), n_cols + 1), n_cols)
    indptr = np.searchsorted(row, np.arange(shape[0] + 1)).astype(np.int64)  # row is sorted
    got_rows, got_cols, total = _core.assign_2d_sparse(
        shape, indptr, np.ascontiguousarray(col, dtype=np.int64), np.ascontiguousarray(data)
    )
    if rows is not None:
        got_rows = rows[got_rows]
    if cols is not None:
        got_cols = cols[got_cols]
    return got_rows, got_cols, total


def _entries(costs: Any) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """The stored entries sorted by row then column, each pair once at its cheapest. A CSR
    matrix in SciPy's canonical format (sorted indices, no duplicates) is that already (unless
    its rows far outnumber its entries: their row numbers would be spelled out); any other
    goes through COO (which keeps duplicates, unlike ``tocsr()``) and a sort."""
    if costs.format == "csr" and costs.has_canonical_format and costs.shape[0] <= 4 * costs.nnz + 1024:
        indptr = np.asarray(costs.indptr, dtype=np.int64)
        row = np.repeat(np.arange(len(indptr) - 1, dtype=np.int64), np.diff(indptr))
        return row, np.asarray(costs.indices, dtype=np.int64), np.asarray(costs.data, dtype=np.float64)
    coo = costs.tocoo()
    row = np.asarray(coo.row, dtype=np.int64)
    col = np.asarray(coo.col, dtype=np.int64)
    data = np.asarray(coo.data, dtype=np.float64)
    order = np.lexsort((data, col, row))  # by row, column, then cost: each pair's cheapest first
    row, col, data = row[order], col[order], data[order]
    first = np.ones(len(row), dtype=bool)
    first[1:] = (row[1:] != row[:-1]) | (col[1:] != col[:-1])
    return row[first], col[first], data[first]


def _in_use(index: NDArray[np.int64], n: int) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The distinct values of ``index`` (in ``[0, n)``), sorted, and each entry's position
    among them, as ``np.unique(index, return_inverse=True)``: by a mask when ``n`` is not much
    larger than the entries (no sort), by ``np.unique`` otherwise (a huge, nearly empty side)."""
    if n > 4 * len(index) + 1024:
        values, inverse = np.unique(index, return_inverse=True)
        return values, inverse.astype(np.int64, copy=False)
    used = np.zeros(n, dtype=bool)
    used[index] = True
    position = np.cumsum(used, dtype=np.int64) - 1
    return np.flatnonzero(used).astype(np.int64, copy=False), position[index]


def _every_index_used(what: str, used: NDArray[np.int64], n: int) -> None:
    """Refuses, as the core would, a side of ``n`` that must all be assigned when an index
    has no stored entry."""
    if len(used) and used[0] == 0 and used[-1] == n - 1 and np.all(used[1:] - used[:-1] <= 1):
        return  # from 0 up to n - 1 in steps of at most one: every index between is there
    present = np.unique(used)
    if len(present) == n:
        return
    gaps = np.flatnonzero(present != np.arange(len(present)))
    missing = int(gaps[0]) if len(gaps) else len(present)
    raise ValueError(f"costs: {what} {missing} cannot be assigned: the stored entries admit no complete assignment")
