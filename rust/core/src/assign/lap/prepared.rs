//! A dense matrix read once and made ready to solve on its own: what a caller that must not
//! hold the caller's memory during the solve (the Python binding, which releases the GIL)
//! hands to another thread. A mostly forbidden matrix keeps only its allowed entries, gathered
//! for the sparse solver, so its full copy is never made; any other is copied as it is.

use super::{read_dense, DenseAssignment, Entry, Read};
use crate::error::CoreResult;

/// A checked dense assignment problem that owns what its solve needs ([`prepare_dense`]).
pub struct PreparedDense<C> {
    n_rows: usize,
    n_cols: usize,
    read: Read,
    /// The matrix, when the solve is dense; empty otherwise.
    costs: Vec<C>,
}

/// Checks `costs` as [`solve_dense`](super::solve_dense) does, with the same errors, and keeps
/// what its solve needs: the allowed entries when the sparse solver will take it, else a copy
/// of the matrix. `prepare_dense(..)?.solve()` is `solve_dense(..)`, answer for answer.
///
/// ```
/// use passive_assoc_core::assign::lap::{prepare_dense, solve_dense};
/// let costs = [4.0, 1.0, 3.0, 2.0, 0.0, 5.0];
/// let prepared = prepare_dense(2, 3, &costs).unwrap();
/// assert_eq!(prepared.solve().unwrap(), solve_dense(2, 3, &costs).unwrap());
/// ```
pub fn prepare_dense<C: Entry>(
    n_rows: usize,
    n_cols: usize,
    costs: &[C],
) -> CoreResult<PreparedDense<C>> {
    let read = read_dense(n_rows, n_cols, costs)?;
    let costs = match read {
        Read::Dense { .. } => costs.to_vec(),
        Read::Empty | Read::Sparse(_) => Vec::new(),
    };
    Ok(PreparedDense {
        n_rows,
        n_cols,
        read,
        costs,
    })
}

impl<C: Entry> PreparedDense<C> {
    /// The assignment, as [`solve_dense`](super::solve_dense) gives it.
    pub fn solve(&self) -> CoreResult<DenseAssignment> {
        self.read.solve(self.n_rows, self.n_cols, &self.costs)
    }
}
