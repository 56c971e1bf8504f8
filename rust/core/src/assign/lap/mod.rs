//! Exact min-cost 2-D linear assignment, dense and sparse: the public types, input
//! validation and result assembly. The algorithms themselves are in `sap.rs` (its child `warm`
//! is the warm-started sparse solve); the CSR cost type in `sparse_costs.rs`.

mod prepared;
mod sap;
mod sparse_costs;

pub use prepared::{prepare_dense, PreparedDense};
pub use sap::Entry;
pub use sparse_costs::SparseCosts;

use crate::error::{CoreError, CoreResult};

/// A dense assignment: `row_to_col[i]` is the column of row `i` (`None` only when there are
/// more rows than columns), `cost` the sum of the assigned entries.
#[derive(Debug, Clone, PartialEq)]
pub struct DenseAssignment {
    pub row_to_col: Vec<Option<usize>>,
    pub cost: f64,
}

/// Solves `min Σ c[i, σ(i)]` over injective maps between rows and columns of the dense
/// `n_rows × n_cols` row-major matrix `costs`; every row is assigned when `n_rows <= n_cols`,
/// every column otherwise (the matrix is transposed internally). `+inf` marks a forbidden pair.
/// The entries are `f64` or `f32` ([`Entry`]); an `f32` matrix is solved exactly, in double
/// precision, and read at half the bytes.
///
/// Errors: `Shape` if `costs.len() != n_rows * n_cols`, `NonFinite` for NaN or `-inf`,
/// `IllPosed` if the forbidden pairs leave no complete assignment.
///
/// ```
/// use passive_assoc_core::assign::lap::solve_dense;
/// let a = solve_dense(2, 3, &[4.0, 1.0, 3.0, 2.0, 0.0, 5.0]).unwrap();
/// assert_eq!(a.row_to_col, vec![Some(1), Some(0)]);
/// assert_eq!(a.cost, 3.0);
/// ```
pub fn solve_dense<C: Entry>(
    n_rows: usize,
    n_cols: usize,
    costs: &[C],
) -> CoreResult<DenseAssignment> {
    read_dense(n_rows, n_cols, costs)?.solve(n_rows, n_cols, costs)
}

/// What one read of a dense matrix decides: nothing to assign, the allowed entries of a
/// mostly forbidden matrix gathered for the sparse solver, or a dense solve (and whether every
/// entry is finite).
enum Read {
    Empty,
    Sparse(SparseCosts),
    Dense { all_finite: bool },
}

impl Read {
    /// The assignment of the matrix read: `costs` is that matrix, needed only by a dense solve.
    fn solve<C: Entry>(
        &self,
        n_rows: usize,
        n_cols: usize,
        costs: &[C],
    ) -> CoreResult<DenseAssignment> {
        match self {
            Read::Empty => Ok(DenseAssignment {
                row_to_col: vec![None; n_rows],
                cost: 0.0,
            }),
            Read::Sparse(sparse) => solve_sparse_complete(sparse),
            Read::Dense { all_finite } => solve_dense_read(n_rows, n_cols, costs, *all_finite),
        }
    }
}

/// Checks `costs` against its shape and its entries (naming the first bad one) in one read,
/// and chooses the solve ([`Read`]).
fn read_dense<C: Entry>(n_rows: usize, n_cols: usize, costs: &[C]) -> CoreResult<Read> {
    let expected = n_rows
        .checked_mul(n_cols)
        .ok_or_else(|| CoreError::shape("costs", format!("{n_rows} × {n_cols} overflows usize")))?;
    if costs.len() != expected {
        return Err(CoreError::shape(
            "costs",
            format!(
                "length {} is not n_rows × n_cols = {n_rows} × {n_cols}",
                costs.len()
            ),
        ));
    }
    if expected == 0 {
        // Nothing to assign: no solve, whose work vectors the other side would size.
        return Ok(Read::Empty);
    }
    let scan = EntryScan::of(costs);
    if scan.bad {
        // Only on bad input: find and name the first offending entry.
        if let Some(index) =
            (costs.iter().map(|c| c.get())).position(|c| c.is_nan() || c == f64::NEG_INFINITY)
        {
            return Err(CoreError::NonFinite {
                arg: "costs",
                index,
            });
        }
        super::check_cost_range("costs", costs)?;
    }
    Ok(match as_sparse(n_rows, n_cols, costs, scan.finite) {
        Some(sparse) => Read::Sparse(sparse),
        None => Read::Dense {
            all_finite: scan.finite == costs.len(),
        },
    })
}

/// The dense solve of a matrix [`read_dense`] has checked (not empty).
fn solve_dense_read<C: Entry>(
    n_rows: usize,
    n_cols: usize,
    costs: &[C],
    all_finite: bool,
) -> CoreResult<DenseAssignment> {
    let mut row_to_col = vec![None; n_rows];
    if n_rows <= n_cols {
        let col4row = sap::dense(n_rows, n_cols, costs, all_finite)?;
        for (i, &j) in col4row.iter().enumerate() {
            row_to_col[i] = Some(j);
        }
    } else {
        let mut t = costs.to_vec();
        for i in 0..n_rows {
            for j in 0..n_cols {
                t[j * n_rows + i] = costs[i * n_cols + j];
            }
        }
        for (j, &i) in sap::dense(n_cols, n_rows, &t, all_finite)?
            .iter()
            .enumerate()
        {
            row_to_col[i] = Some(j);
        }
    }
    let cost = (row_to_col.iter().enumerate())
        .filter_map(|(i, j)| j.map(|j| costs[i * n_cols + j].get()))
        .sum();
    Ok(DenseAssignment { row_to_col, cost })
}

/// Matrices at least this large (entries) are checked for the sparse path.
const SPARSE_MIN_ENTRIES: usize = 64 * 64;
/// Up to this share of allowed (finite) entries a dense matrix of `entries` entries is solved
/// sparse: the sparse search touches only allowed entries, the dense one every entry of every
/// row it scans, but the dense one has Jonker & Volgenant's start (also with `+inf` entries,
/// when every row and column has a finite one), whose worth grows more slowly with the size.
/// The dense solve overtakes the sparse one at about 5–10 % allowed at 300², 20 % at 1000²
/// and 30 % at 3000² (`python3 benches/bench_lap.py --densities --sizes 300 1000 3000`,
/// docs/performance.md): with the side `s = √entries`, `0.07 + 0.23·log₁₀(s / 300)`, which
/// passes through those three, kept within [0.05, 0.3] outside the sizes measured.
fn sparse_max_share(entries: usize) -> f64 {
    let side = (entries as f64).sqrt();
    (0.07 + 0.23 * (side / 300.0).log10()).clamp(0.05, 0.3)
}

/// What one read of a dense matrix tells every later step: how many entries are finite, and
/// whether any is invalid (NaN, `-inf`, or finite beyond ±[`MAX_ABS_COST`](super::MAX_ABS_COST)).
/// The checks, the sparse-path test and the solver's all-finite test share it: a read of the
/// whole matrix for each would be a visible share of a small solve's time.
struct EntryScan {
    finite: usize,
    bad: bool,
}

impl EntryScan {
    fn of<C: Entry>(costs: &[C]) -> Self {
        let (mut finite, mut bad) = (0usize, false);
        // Branch-free so that it vectorises: NaN fails both comparisons, `-inf` and huge
        // finite values fail the first, and only `+inf` passes the second alone.
        for c in costs {
            let c = c.get();
            finite += usize::from(c.abs() < f64::INFINITY);
            let within = c.abs() <= super::MAX_ABS_COST;
            bad |= !within & (c != f64::INFINITY);
        }
        Self { finite, bad }
    }
}

/// The finite entries of a large, mostly forbidden dense matrix (`allowed` of them) as a
/// sparse one (else None).
fn as_sparse<C: Entry>(
    n_rows: usize,
    n_cols: usize,
    costs: &[C],
    allowed: usize,
) -> Option<SparseCosts> {
    if costs.len() < SPARSE_MIN_ENTRIES {
        return None;
    }
    if allowed as f64 > sparse_max_share(costs.len()) * costs.len() as f64 {
        return None;
    }
    let mut row_offsets = Vec::with_capacity(n_rows + 1);
    let (mut col_indices, mut values) = (Vec::with_capacity(allowed), Vec::with_capacity(allowed));
    row_offsets.push(0);
    for row in costs.chunks_exact(n_cols.max(1)).take(n_rows) {
        for (j, c) in row.iter().map(|c| c.get()).enumerate() {
            if !c.is_finite() {
                continue;
            }
            col_indices.push(j);
            values.push(c);
        }
        row_offsets.push(values.len());
    }
    Some(SparseCosts::from_csr_unchecked(
        n_rows,
        n_cols,
        row_offsets,
        col_indices,
        values,
    ))
}

/// Solves the complete assignment of a sparse matrix, where an absent entry is a forbidden
/// pair: [`solve_dense`]'s contract (every row assigned when `n_rows <= n_cols`, every column
/// otherwise) over the stored entries only, so the work follows the entries, not
/// `n_rows × n_cols`. Duplicate entries: the cheapest counts.
///
/// Errors: `OutOfRange` for entries beyond ±[`MAX_ABS_COST`](super::MAX_ABS_COST), `IllPosed`
/// if the stored entries admit no complete assignment (naming the first row, or column, that
/// cannot be assigned).
///
/// ```
/// use passive_assoc_core::assign::lap::{solve_sparse_complete, SparseCosts};
/// // Row 0 may take only column 1, so row 1 takes column 0 although column 1 is cheaper.
/// let c = SparseCosts::from_triplets(2, 2, &[(0, 1, 5.0), (1, 0, 4.0), (1, 1, 1.0)]).unwrap();
/// let a = solve_sparse_complete(&c).unwrap();
/// assert_eq!(a.row_to_col, vec![Some(1), Some(0)]);
/// assert_eq!(a.cost, 9.0);
/// ```
pub fn solve_sparse_complete(costs: &SparseCosts) -> CoreResult<DenseAssignment> {
    super::check_cost_range("costs", costs.values())?;
    let (nr, nc) = (costs.n_rows(), costs.n_cols());
    let mut work = sap::SparseWork::default();
    let mut row_to_col = vec![None; nr];
    if nr <= nc {
        let col4row = sap::sparse_full(&mut work, costs).map_err(|row| unassignable("row", row))?;
        for (i, &j) in col4row.iter().enumerate() {
            row_to_col[i] = Some(j);
        }
    } else {
        let transposed = costs.transposed();
        let row4col =
            sap::sparse_full(&mut work, &transposed).map_err(|col| unassignable("column", col))?;
        for (j, &i) in row4col.iter().enumerate() {
            row_to_col[i] = Some(j);
        }
    }
    // From +0.0: `sum` of no term is −0.0.
    let cost = (row_to_col.iter().enumerate())
        .filter_map(|(i, j)| j.map(|j| costs.cheapest(i, j)))
        .fold(0.0, |total, c| total + c);
    Ok(DenseAssignment { row_to_col, cost })
}

fn unassignable(what: &str, index: usize) -> CoreError {
    CoreError::ill_posed(
        "costs",
        format!(
            "{what} {index} cannot be assigned: the stored entries admit no complete assignment"
        ),
    )
}

/// A sparse assignment: each row has its column or `None` (left unassigned), each column its
/// row or `None`; `cost` counts assigned entries plus the unassigned costs.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SparseAssignment {
    pub row_to_col: Vec<Option<usize>>,
    pub col_to_row: Vec<Option<usize>>,
    pub cost: f64,
}

/// Exact min-cost assignment where each row takes one allowed column or pays
/// `row_unassigned[i]`, and each column not taken pays `col_unassigned[j]`.
///
/// Why it is exact and sparse: the objective equals `Σ a_i + Σ b_j + Σ (c_ij - a_i - b_j)`
/// over the assigned pairs, so only entries with `c_ij - a_i - b_j < 0` are ever worth using
/// (ties are left unassigned). Giving each row a private zero-cost dummy column turns that into
/// a rectangular assignment that always has a solution; shortest augmenting paths with a binary
/// heap then cost O(rows · nnz · log) in the worst case and touch only stored entries.
///
/// Errors: `Shape` for wrong lengths, `NonFinite` for a non-finite unassigned cost.
///
/// ```
/// use passive_assoc_core::assign::lap::{solve_sparse, SparseCosts};
/// let c = SparseCosts::from_triplets(2, 2, &[(0, 0, -5.0), (1, 0, -4.0)]).unwrap();
/// let a = solve_sparse(&c, &[0.0, -1.0], &[0.0, 0.0]).unwrap();
/// assert_eq!(a.row_to_col, vec![Some(0), None]);
/// assert_eq!(a.cost, -6.0);
/// ```
pub fn solve_sparse(
    costs: &SparseCosts,
    row_unassigned: &[f64],
    col_unassigned: &[f64],
) -> CoreResult<SparseAssignment> {
    if row_unassigned.len() != costs.n_rows() {
        let got = row_unassigned.len();
        return Err(CoreError::shape(
            "row_unassigned",
            format!("length {got} is not n_rows = {}", costs.n_rows()),
        ));
    }
    if col_unassigned.len() != costs.n_cols() {
        let got = col_unassigned.len();
        return Err(CoreError::shape(
            "col_unassigned",
            format!("length {got} is not n_cols = {}", costs.n_cols()),
        ));
    }
    crate::error::ensure_finite("row_unassigned", row_unassigned)?;
    crate::error::ensure_finite("col_unassigned", col_unassigned)?;
    super::check_cost_range("row_unassigned", row_unassigned)?;
    super::check_cost_range("col_unassigned", col_unassigned)?;
    Ok(sparse_core(costs, row_unassigned, col_unassigned))
}

/// The sparse solver on validated input (never fails: every row has its dummy column).
pub(crate) fn sparse_core(costs: &SparseCosts, a: &[f64], b: &[f64]) -> SparseAssignment {
    let mut solver = SparseSolver::default();
    solver.solve(costs, a, b);
    solver.result
}

/// [`sparse_core`] with working memory kept between calls, for callers that solve one
/// problem per iteration.
#[derive(Default)]
pub(crate) struct SparseSolver {
    work: sap::SparseWork,
    warm: sap::WarmState,
    result: SparseAssignment,
}

impl SparseSolver {
    /// Solves validated input; the result stays valid until the next call.
    pub(crate) fn solve(&mut self, costs: &SparseCosts, a: &[f64], b: &[f64]) -> &SparseAssignment {
        let col4row = sap::sparse(&mut self.work, costs, a, b);
        finish(costs, a, b, col4row, &mut self.result);
        &self.result
    }

    /// Dual prices of the input problem after a cold [`SparseSolver::solve`] of `costs`, `a`,
    /// `b`: `alpha[i] ≤ a[i]` per row, `beta[j] ≤ b[j]` per column, and `alpha[i] + beta[j] ≤
    /// c_ij` on every stored entry, so that any assignment costs at least their sum plus the
    /// slack `c − alpha − beta` (`a − alpha`, `b − beta` when unassigned) of what it uses.
    ///
    /// The solver works on `c_ij − a_i − b_j` with a zero-cost dummy column per row; its duals
    /// `u` (rows), `v ≤ 0` (columns) map back as `alpha_i = a_i + u_i + v_dummy(i)` and
    /// `beta_j = b_j + v_j`, whose sum is then the optimum's cost. The three inequalities are
    /// enforced once more on the result (each price lowered to what they allow), so the prices
    /// are feasible whatever rounding did; feasible prices give valid bounds.
    pub(crate) fn input_duals(
        &self,
        costs: &SparseCosts,
        a: &[f64],
        b: &[f64],
        alpha: &mut Vec<f64>,
        beta: &mut Vec<f64>,
    ) {
        let (u, v) = self.work.duals();
        let (nr, nc) = (costs.n_rows(), costs.n_cols());
        let dual = |x: &[f64], k: usize| x.get(k).copied().unwrap_or(0.0);
        alpha.clear();
        alpha.extend((0..nr).map(|i| (a[i] + dual(u, i) + dual(v, nc + i)).min(a[i])));
        beta.clear();
        beta.extend((0..nc).map(|j| (b[j] + dual(v, j)).min(b[j])));
        for (i, &ai) in alpha.iter().enumerate() {
            for (j, c) in costs.row(i) {
                beta[j] = beta[j].min(c - ai);
            }
        }
    }

    /// [`SparseSolver::solve`] starting from the previous warm solve's duals and matching when
    /// the shape is the same: the same optimum (possibly another of equal cost), found faster
    /// when the problem changed little. Which callers should use it: see
    /// [`super::lagrangian::WarmStart`].
    pub(crate) fn solve_warm(
        &mut self,
        costs: &SparseCosts,
        a: &[f64],
        b: &[f64],
    ) -> &SparseAssignment {
        let col4row = sap::sparse_warm(&mut self.work, &mut self.warm, costs, a, b);
        finish(costs, a, b, col4row, &mut self.result);
        &self.result
    }
}

/// Converts the internal matching to the public form and totals the cost from the input.
fn finish(
    costs: &SparseCosts,
    a: &[f64],
    b: &[f64],
    col4row: &[usize],
    out: &mut SparseAssignment,
) {
    let (nr, nc) = (costs.n_rows(), costs.n_cols());
    let (row_to_col, col_to_row) = (&mut out.row_to_col, &mut out.col_to_row);
    row_to_col.clear();
    col_to_row.clear();
    row_to_col.resize(nr, None);
    col_to_row.resize(nc, None);
    let mut cost = 0.0;
    for i in 0..nr {
        let j = col4row[i];
        if j < nc {
            row_to_col[i] = Some(j);
            col_to_row[j] = Some(i);
            // The cheapest duplicate is the one the search used.
            cost += costs.cheapest(i, j);
        } else {
            cost += a[i];
        }
    }
    cost += (0..nc)
        .filter(|&j| col_to_row[j].is_none())
        .map(|j| b[j])
        .sum::<f64>();
    out.cost = cost;
}

#[cfg(test)]
mod tests;
