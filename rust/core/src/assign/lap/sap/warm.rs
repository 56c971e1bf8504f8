//! A warm-started sparse assignment, for callers that solve a slowly changing problem every
//! iteration: the Lagrangian relaxation changes each 2-D problem only by one subgradient step.
//!
//! A warm start keeps the previous solve's column duals and matching. In the rectangular form
//! of [`super::sparse`] that fails: a column left unassigned must have dual 0, so freeing a
//! column whose dual is negative forces fix-ups that cascade. Here the problem is made square
//! instead, where duals are free of sign and every row and column is matched:
//!
//! * rows: the real rows `0..nr`, then one *mirror row* per real column (`nr + j`);
//! * columns: the real columns `0..nc`, then one dummy per real row (`nc + i`, as in the
//!   rectangular form);
//! * entries: real row i to column j at the reduced cost `c − a_i − b_j` (only those `< 0`, as
//!   there), row i to its dummy at 0 ("row i unassigned"), mirror row j to column j at 0
//!   ("column j unassigned"), and mirror row j to dummy `nc + i` at 0 for every kept entry
//!   (i, j).
//!
//! The mirror entries complete any matching of the real entries at no cost — (i, j) matched
//! pairs mirror row j with dummy i — so the square optimum is the rectangular one, without
//! the dense zero block a plain square extension would need. A warm solve keeps the previous
//! column duals `v`, sets every row dual to its smallest reduced cost (dual feasible), keeps
//! each previous pair that is still tight, and runs the usual searches only for the rows left
//! without one.

use super::{SparseWork, NONE};
use crate::assign::lap::SparseCosts;

/// What one solve hands the next: the square problem's column duals and matching.
#[derive(Default)]
pub(in crate::assign) struct WarmState {
    shape: (usize, usize),
    v: Vec<f64>,
    col4row: Vec<usize>,
}

/// Solves the rectangular problem of [`super::sparse`] (same input, same meaning of the
/// returned columns for the `nr` real rows), starting from `warm` when it has the same shape,
/// and leaves this solve's state in `warm`.
pub(in crate::assign) fn sparse_warm<'w>(
    w: &'w mut SparseWork,
    warm: &mut WarmState,
    costs: &SparseCosts,
    a: &[f64],
    b: &[f64],
) -> &'w [usize] {
    let shape = (costs.n_rows(), costs.n_cols());
    w.load_mirrored(costs, a, b);
    let previous = if warm.shape == shape {
        w.v.copy_from_slice(&warm.v);
        Some(warm.col4row.as_slice())
    } else {
        None
    };
    w.start_from(previous);
    w.assign_free_rows();
    warm.shape = shape;
    warm.v.clone_from(&w.v);
    warm.col4row.clone_from(&w.col4row);
    &w.col4row[..shape.0]
}

impl SparseWork {
    /// Builds the square problem described in the module docs.
    fn load_mirrored(&mut self, costs: &SparseCosts, a: &[f64], b: &[f64]) {
        let (nr, nc) = (costs.n_rows(), costs.n_cols());
        self.load_rows(costs, a, b);
        // Mirror row j: its own column at 0, then the dummies of the rows with an entry in j.
        let mut per_col = std::mem::take(&mut self.mirror_offs);
        per_col.clear();
        per_col.resize(nc + 1, 0);
        for &j in self.cols.iter().filter(|&&j| j < nc) {
            per_col[j + 1] += 1;
        }
        for j in 0..nc {
            per_col[j + 1] += per_col[j] + 1;
        }
        let base = self.cols.len();
        self.cols.resize(base + per_col[nc], 0);
        self.vals.resize(base + per_col[nc], 0.0);
        let mut fill = std::mem::take(&mut self.mirror_fill);
        fill.clear();
        fill.extend(per_col[..nc].iter().map(|&o| base + o));
        for (j, at) in fill.iter_mut().enumerate() {
            self.cols[*at] = j;
            *at += 1;
        }
        for i in 0..nr {
            for at in self.offs[i]..self.offs[i + 1] - 1 {
                let j = self.cols[at];
                self.cols[fill[j]] = nc + i;
                fill[j] += 1;
            }
        }
        self.offs.extend(per_col[1..].iter().map(|&o| base + o));
        (self.mirror_offs, self.mirror_fill) = (per_col, fill);
        self.size_for(nr + nc, nr + nc);
    }

    /// Row duals = each row's smallest reduced cost `c − v` (so every reduced cost is >= 0);
    /// each row keeps its `previous` column if that entry is still there and tight, then every
    /// row still free takes a free tight column (lowest first). The searches go on from this
    /// state exactly as from an empty one.
    fn start_from(&mut self, previous: Option<&[usize]>) {
        let n = self.col4row.len();
        for i in 0..n {
            let want = previous.map_or(NONE, |p| p[i]);
            let (mut low, mut at_want) = (f64::INFINITY, f64::INFINITY);
            for at in self.offs[i]..self.offs[i + 1] {
                let (j, r) = (self.cols[at], self.vals[at] - self.v[self.cols[at]]);
                low = low.min(r);
                if j == want {
                    at_want = at_want.min(r);
                }
            }
            self.u[i] = low;
            // A previous matching never repeats a column, so no earlier row has taken it.
            if want != NONE && at_want == low {
                self.col4row[i] = want;
                self.row4col[want] = i;
            }
        }
        for i in 0..n {
            if self.col4row[i] != NONE {
                continue;
            }
            let free_tight = (self.offs[i]..self.offs[i + 1])
                .map(|at| (self.cols[at], self.vals[at]))
                .filter(|&(j, c)| self.row4col[j] == NONE && c - self.v[j] == self.u[i])
                .map(|(j, _)| j)
                .min();
            if let Some(j) = free_tight {
                self.col4row[i] = j;
                self.row4col[j] = i;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{sparse_warm, WarmState};
    use crate::assign::lap::sap::SparseWork;
    use crate::assign::lap::{sparse_core, SparseCosts};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The cost of the rectangular solution `col4row` (column `nc + i`: row i unassigned).
    fn cost_of(m: &SparseCosts, a: &[f64], b: &[f64], col4row: &[usize]) -> f64 {
        let mut taken = vec![false; m.n_cols()];
        let mut cost = 0.0;
        for (i, &j) in col4row.iter().enumerate() {
            if j < m.n_cols() {
                assert!(!taken[j], "column {j} taken twice");
                taken[j] = true;
                let entry = m.row(i).filter(|e| e.0 == j).map(|e| e.1);
                cost += entry.fold(f64::INFINITY, f64::min);
            } else {
                assert_eq!(j, m.n_cols() + i, "row {i} took another row's dummy");
                cost += a[i];
            }
        }
        cost + (0..m.n_cols())
            .filter(|&j| !taken[j])
            .map(|j| b[j])
            .sum::<f64>()
    }

    /// Quarter steps keep every sum exact, and integer-heavy costs make ties common: the
    /// warm solve must reach the cold optimum through problems that drift and change shape.
    /// (Sizes below the Lagrangian's `WARM_MIN_SIZE` too: this tests the method, not the policy.)
    #[test]
    fn warm_solves_equal_cold_ones_through_a_changing_problem() {
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        let (mut work, mut warm) = (SparseWork::default(), WarmState::default());
        let quarter =
            |rng: &mut ChaCha8Rng, lo: i32, hi: i32| rng.random_range(lo..hi) as f64 / 4.0;
        for run in 0..40 {
            let (nr, nc) = (rng.random_range(0..40usize), rng.random_range(0..40usize));
            let pattern: Vec<(usize, usize)> = (0..nr * nc)
                .filter(|_| rng.random_bool(0.3))
                .map(|k| (k / nc, k % nc))
                .collect();
            let mut vals: Vec<f64> = pattern.iter().map(|_| quarter(&mut rng, -36, 12)).collect();
            let mut a: Vec<f64> = (0..nr).map(|_| quarter(&mut rng, -16, 8)).collect();
            let mut b: Vec<f64> = (0..nc).map(|_| quarter(&mut rng, -16, 8)).collect();
            for step in 0..25 {
                let big = step % 7 == 6;
                for x in vals.iter_mut().chain(&mut a).chain(&mut b) {
                    if rng.random_bool(if big { 0.8 } else { 0.2 }) {
                        *x += if big {
                            quarter(&mut rng, -20, 20)
                        } else {
                            quarter(&mut rng, -2, 3)
                        };
                    }
                }
                let trip: Vec<(usize, usize, f64)> = pattern
                    .iter()
                    .zip(&vals)
                    .map(|(&(i, j), &c)| (i, j, c))
                    .collect();
                let m = SparseCosts::from_triplets(nr, nc, &trip).unwrap();
                let cold = sparse_core(&m, &a, &b);
                let col4row = sparse_warm(&mut work, &mut warm, &m, &a, &b).to_vec();
                assert_eq!(
                    cost_of(&m, &a, &b, &col4row),
                    cold.cost,
                    "run {run} step {step}"
                );
            }
        }
    }
}
