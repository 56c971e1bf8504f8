//! The sparse solver for a *complete* assignment: a missing entry is a forbidden pair and every
//! row (every column, when there are more rows) must be assigned, as in the dense solve — what
//! `linear_assignment` on a SciPy sparse matrix asks. The same shortest augmenting paths over
//! the stored entries as the dummy-column form in the parent, without the dummies: a search
//! that reaches no free column proves that no complete assignment exists.

use super::{augment, SparseWork, NONE};
use crate::assign::lap::SparseCosts;

/// The column of each row of an `n_rows ≤ n_cols` problem, or the first row that cannot be
/// assigned once the rows before it are.
pub(in crate::assign::lap) fn sparse_full(
    w: &mut SparseWork,
    costs: &SparseCosts,
) -> Result<Vec<usize>, usize> {
    w.load_full(costs);
    for cur in 0..costs.n_rows() {
        let Some((sink, min_val)) = w.shortest_path(cur) else {
            w.reset();
            return Err(cur);
        };
        w.update_duals(cur, min_val);
        augment(sink, cur, &w.path, &mut w.row4col, &mut w.col4row);
        w.reset();
    }
    Ok(w.col4row.clone())
}

impl SparseWork {
    /// The stored entries as they are (the cheapest of duplicates wins in the search), no
    /// dummy columns, duals at 0.
    fn load_full(&mut self, costs: &SparseCosts) {
        self.offs.clear();
        self.cols.clear();
        self.vals.clear();
        self.offs.push(0);
        for i in 0..costs.n_rows() {
            for (j, c) in costs.row(i) {
                self.cols.push(j);
                self.vals.push(c);
            }
            self.offs.push(self.cols.len());
        }
        self.size_for(costs.n_rows(), costs.n_cols());
        debug_assert!(self.col4row.iter().all(|&j| j == NONE));
    }
}
