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
    if costs.n_rows() == costs.n_cols() {
        w.column_reduction();
    }
    for cur in 0..costs.n_rows() {
        if w.col4row[cur] != NONE {
            continue; // given its column by the column reduction
        }
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

    /// The first phase of Jonker & Volgenant on the stored entries of a square problem: each
    /// column priced at its cheapest entry (`v_j`, row duals staying 0, so every reduced cost
    /// is ≥ 0 and the matched ones 0, the invariant of the searches) and given to that row if
    /// it has no column yet, columns from the last as in the dense start (`init.rs`, on a
    /// dense matrix); the searches then run only for the rows left free. Square only: in a
    /// rectangular problem a column left free must keep dual 0.
    fn column_reduction(&mut self) {
        let n = self.col4row.len();
        let mut cheapest = vec![NONE; n];
        self.v.fill(f64::INFINITY);
        for i in 0..n {
            for p in self.offs[i]..self.offs[i + 1] {
                let (j, c) = (self.cols[p], self.vals[p]);
                if c < self.v[j] {
                    (self.v[j], cheapest[j]) = (c, i);
                }
            }
        }
        for j in (0..n).rev() {
            let i = cheapest[j];
            if i == NONE {
                self.v[j] = 0.0; // no entry: the search reports the column's row infeasible
            } else if self.col4row[i] == NONE {
                (self.col4row[i], self.row4col[j]) = (j, i);
            }
        }
    }
}
