"""The dense 2-D solver against scipy.optimize.linear_sum_assignment (issue: static association)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import passive_assoc as pa
import pytest
import scipy.sparse as sp
from passive_assoc import _core
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
        (lambda: pa.linear_assignment(np.ones(3)), ValueError, "costs"),
        (lambda: pa.linear_assignment(np.array([[np.inf, 1.0], [np.inf, 2.0]])), ValueError, "cannot be assigned"),
    ],
)
def test_linear_assignment_bad_input(call, exc, message) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(exc, match=message):
        call()


@pytest.mark.parametrize("n", [3, 16, 17, 40])  # solved holding the GIL up to 16 × 16, copied beyond
def test_every_dense_input_path_gives_the_same_answer(n: int) -> None:
    # A C-ordered float64 array goes straight to the core; lists, other dtypes and Fortran
    # order through the general conversion: all the same answer, the caller's array untouched.
    c = np.round(np.random.default_rng(n).uniform(0, 10, (n, n)))  # ties
    kept = c.copy()
    direct = pa.linear_assignment(c)
    for other in (c.tolist(), np.asfortranarray(c), c.astype(np.float32).astype(np.int64), c[:, ::1]):
        got = pa.linear_assignment(other)
        assert np.array_equal(got[0], direct[0]) and np.array_equal(got[1], direct[1]) and got[2] == direct[2]
    assert np.array_equal(c, kept)
    bad = c.copy()
    bad[1, 2] = np.nan
    with pytest.raises(ValueError, match="costs"):
        pa.linear_assignment(bad)


@pytest.mark.parametrize("shape", [(3, 3), (16, 16), (40, 40), (30, 50), (50, 30), (100, 100)])
def test_a_float32_matrix_is_solved_exactly_without_a_float64_copy(shape: tuple[int, int]) -> None:
    # Entries near 1000 on float32's grid there: their sums are exact in float64, not in
    # float32. The answer is the float64 answer of the same values, from the array as given
    # (C order, Fortran order and a strided view alike), and SciPy's optimum.
    rng = np.random.default_rng(shape[0] * 7 + shape[1])
    c32 = (1000 + 2.0**-14 * rng.integers(0, 64, shape)).astype(np.float32)
    if shape == (100, 100):
        # Mostly forbidden (about 4 % allowed, the diagonal among them): the sparse path.
        c32[rng.random(shape) < 0.97] = np.inf
        np.fill_diagonal(c32, 1000)
    c64 = c32.astype(np.float64)
    kept = c32.copy()
    want = pa.linear_assignment(c64)
    wide = np.zeros((shape[0], 2 * shape[1]), dtype=np.float32)
    wide[:, ::2] = c32
    for given in (c32, np.asfortranarray(c32), wide[:, ::2]):
        got = pa.linear_assignment(given)
        assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1]) and got[2] == want[2]
    # The core itself reads the float32 array (no conversion on the way): the same answer.
    direct = _core.assign_2d(c32)
    assert np.array_equal(direct[1], want[1]) and direct[2] == want[2]
    assert np.array_equal(c32, kept)
    if shape != (100, 100):
        r, c = linear_sum_assignment(c64)
        assert want[2] == c64[r, c].sum()
    bad = c32.copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValueError, match="costs"):
        pa.linear_assignment(bad)


@pytest.mark.parametrize("shape", [(1, 1), (6, 6), (8, 3), (3, 8), (40, 40), (90, 70), (70, 90)])
def test_sparse_and_gated_dense_match_scipy(shape: tuple[int, int]) -> None:
    """A SciPy sparse matrix (absent = forbidden) and the same matrix dense with +inf (which
    the core solves sparse when few enough entries are allowed) give SciPy's optimum,
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
    # Stored zeros are allowed pairs; duplicates count at their cheapest.
    zeros = sp.csr_array((np.array([0.0, 0.0]), np.array([1, 0]), np.array([0, 1, 2])), shape=(2, 2))
    assert pa.linear_assignment(zeros)[2] == 0.0
    dup = sp.csr_array((np.array([5.0, 1.0, 2.0]), np.array([0, 0, 1]), np.array([0, 2, 3])), shape=(2, 2))
    assert pa.linear_assignment(dup)[2] == 3.0
    with pytest.raises(ValueError, match=r"costs: the stored entry at \(0, 0\) is nan"):
        pa.linear_assignment(sp.csr_array(np.array([[np.nan, 1.0], [1.0, 1.0]])))
    with pytest.raises(TypeError, match="complex"):
        pa.linear_assignment(sp.csr_array(np.array([[1j, 1.0], [1.0, 1.0]])))


@pytest.mark.parametrize("fmt", ["coo", "csr", "csc"])
def test_duplicate_entries_count_at_their_cheapest_in_every_format(fmt: str) -> None:
    """(0, 0) stored as −7 and 20: the pair costs −7, as the docstring says, not their sum
    (SciPy's conversion to CSR sums duplicates; 278 of 6 000 fuzzed sparse cases were wrong)."""
    parts = (np.array([-7.0, 20.0, 3.0]), np.array([0, 0, 1]), np.array([0, 2, 3]))  # CSR/CSC parts keep duplicates
    matrix = {
        "coo": sp.coo_array(([-7.0, 20.0, 3.0], ([0, 0, 1], [0, 0, 1])), shape=(2, 2)),
        "csr": sp.csr_array(parts, shape=(2, 2)),
        "csc": sp.csc_array(parts, shape=(2, 2)),
    }[fmt]
    rows, cols, total = pa.linear_assignment(matrix)
    assert (rows.tolist(), cols.tolist(), total) == ([0, 1], [0, 1], -4.0)


def test_canonical_csr_and_every_other_form_give_the_same_answer() -> None:
    """A canonical CSR matrix is read as it is stored; COO, CSC and a CSR with unsorted
    indices go through the sort. Same pairs and total, bit for bit, square and rectangular."""
    rng = np.random.default_rng(38)
    checked = 0
    for shape in [(60, 60), (40, 70), (70, 40), (200, 200)]:
        c = rng.uniform(-5, 5, shape)
        allowed = rng.random(shape) < 0.1
        np.fill_diagonal(allowed, True)
        canonical = sp.csr_array((c[allowed], np.nonzero(allowed)), shape=shape)
        assert canonical.has_canonical_format
        reversed_rows = canonical.copy()
        for i in range(shape[0]):  # each row's entries stored in reverse column order
            span = slice(reversed_rows.indptr[i], reversed_rows.indptr[i + 1])
            reversed_rows.indices[span] = reversed_rows.indices[span][::-1].copy()
            reversed_rows.data[span] = reversed_rows.data[span][::-1].copy()
        reversed_rows.has_sorted_indices = False
        assert not reversed_rows.has_canonical_format
        expected = pa.linear_assignment(canonical)
        for other in (sp.coo_array(canonical), sp.csc_array(canonical), reversed_rows):
            got = pa.linear_assignment(other)
            assert np.array_equal(got[0], expected[0]) and np.array_equal(got[1], expected[1])
            assert got[2] == expected[2]
            checked += 1
    assert checked == 12


def test_sparse_matches_the_dense_minimum_of_duplicates() -> None:
    """Random COO matrices with many duplicates against SciPy on the dense matrix of each
    pair's cheapest entry: the same optimum, or both infeasible."""
    rng = np.random.default_rng(36)
    for _ in range(400):
        n_rows, n_cols = (int(n) for n in rng.integers(1, 6, 2))
        k = int(rng.integers(1, 3 * n_rows * n_cols))
        row, col = rng.integers(0, n_rows, k), rng.integers(0, n_cols, k)
        value = rng.integers(-20, 20, k).astype(float)
        dense = np.full((n_rows, n_cols), np.inf)
        np.minimum.at(dense, (row, col), value)
        try:
            r, c = linear_sum_assignment(dense)
        except ValueError:
            with pytest.raises(ValueError, match="cannot be assigned"):
                pa.linear_assignment(sp.coo_array((value, (row, col)), shape=(n_rows, n_cols)))
            continue
        assert pa.linear_assignment(sp.coo_array((value, (row, col)), shape=(n_rows, n_cols)))[2] == dense[r, c].sum()


_WIDE_SCRIPT = """
import resource
import numpy as np, scipy.sparse as sp, passive_assoc as pa

resource.setrlimit(resource.RLIMIT_AS, (3 << 29, 3 << 29))  # 1.5 GB of address space
for shape, (row, col) in [((3, 10**9), ([0, 1, 2], [5, 7, 10**9 - 1])), ((10**9, 3), ([5, 7, 10**9 - 1], [2, 1, 0]))]:
    rows, cols, total = pa.linear_assignment(sp.coo_array(([1.0, 2.0, 3.0], (row, col)), shape=shape))
    print(rows.tolist(), cols.tolist(), total)
try:
    pa.linear_assignment(sp.coo_array(([1.0], ([0], [0])), shape=(10**9, 10**9 + 1)))
except ValueError as err:
    print(err)
"""


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_AS is how the test bounds memory")
def test_a_huge_sparse_shape_is_sized_by_its_entries() -> None:
    """Shape (3, 10⁹) with 3 entries once allocated 8e9 bytes and aborted the interpreter."""
    done = subprocess.run([sys.executable, "-c", _WIDE_SCRIPT], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.splitlines() == [
        "[0, 1, 2] [5, 7, 999999999] 6.0",
        "[5, 7, 999999999] [2, 1, 0] 6.0",
        "costs: row 1 cannot be assigned: the stored entries admit no complete assignment",
    ]


_EMPTY_SCRIPT = """
import resource
import numpy as np, passive_assoc as pa

resource.setrlimit(resource.RLIMIT_AS, (3 << 29, 3 << 29))  # 1.5 GB of address space
for shape in [(0, 10**9), (10**9, 0)]:
    rows, cols, total = pa.linear_assignment(np.empty(shape))
    print(shape, rows.tolist(), cols.tolist(), total)
"""


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_AS is how the test bounds memory")
def test_an_empty_matrix_of_a_huge_side_needs_no_memory() -> None:
    """(0, 10⁹) once sized the solve's work vectors by its 10⁹ columns and aborted the process."""
    done = subprocess.run([sys.executable, "-c", _EMPTY_SCRIPT], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.splitlines() == ["(0, 1000000000) [] [] 0.0", "(1000000000, 0) [] [] 0.0"]


@pytest.mark.parametrize("shape", [(0, 0), (0, 3), (3, 0)])
def test_an_empty_matrix_assigns_nothing_at_cost_zero(shape: tuple[int, int]) -> None:
    for costs in (np.zeros(shape), sp.csr_array(shape), sp.coo_array(shape)):
        rows, cols, total = pa.linear_assignment(costs)
        assert rows.dtype == np.int64 and cols.dtype == np.int64 and len(rows) == len(cols) == 0
        assert total == 0.0 and not np.signbit(total)
    assert linear_sum_assignment(np.zeros(shape))[0].size == 0  # SciPy agrees there is nothing


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_a_misaligned_matrix_is_converted_not_refused(dtype: type) -> None:
    c = np.random.default_rng(3).uniform(0, 10, (20, 20)).astype(dtype)
    raw = np.zeros(c.nbytes + 1, dtype=np.uint8)
    misaligned = np.frombuffer(raw.data, dtype=dtype, count=c.size, offset=1).reshape(c.shape)
    misaligned.flags.writeable = True
    misaligned[...] = c
    assert not misaligned.flags.aligned and misaligned.flags.c_contiguous
    got, expected = pa.linear_assignment(misaligned), pa.linear_assignment(c)
    assert np.array_equal(got[1], expected[1]) and got[2] == expected[2]
