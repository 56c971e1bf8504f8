//! The shortest-augmenting-path cores behind [`super`]: the sparse solver here, the dense one in
//! the child `dense`, the complete sparse assignment in `full`, the warm-started one in `warm`.
//!
//! Both solvers are the shortest-augmenting-path method of Jonker & Volgenant in the form of
//! Crouse (2016, "On implementing 2D rectangular assignment algorithms"), the algorithm behind
//! `scipy.optimize.linear_sum_assignment`: rows are added one at a time, each by a Dijkstra
//! search over reduced costs `c - u - v` that stays non-negative on already assigned rows, then
//! the duals are updated so they stay feasible. It is hand-rolled rather than taken from a
//! generic crate because the S-D solvers call it hundreds of times per problem: per-call
//! set-up of a generic graph type and allocation in the inner loop would cost more than the
//! solve itself. The inner loops here touch only preallocated flat vectors.

use super::SparseCosts;

mod dense;
mod full;
mod init;
mod warm;
pub(super) use dense::dense;
pub(super) use full::sparse_full;
pub(super) use warm::{sparse_warm, WarmState};

use std::cmp::Reverse;
use std::collections::BinaryHeap;

const NONE: usize = usize::MAX;

/// An entry type of a dense cost matrix: `f64`, or `f32` read as the `f64` it equals exactly,
/// so that a single-precision matrix is solved in double precision (the answer is the
/// optimum of the matrix given, not of its rounding) at half the bytes read. Sealed: only
/// these two.
pub trait Entry: Copy + Into<f64> + Send + Sync + 'static + sealed::Sealed {
    /// The entry as the `f64` it equals.
    fn get(self) -> f64;
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for f64 {}
    impl Sealed for f32 {}
}

impl Entry for f64 {
    #[inline(always)]
    fn get(self) -> f64 {
        self
    }
}

impl Entry for f32 {
    #[inline(always)]
    fn get(self) -> f64 {
        f64::from(self)
    }
}

/// Up to this many columns a search picks its next column by scanning the open ones instead of
/// popping a heap. Both pick the least [`key`], so the result is the same bit for bit. On the
/// Lagrangian's relaxed problems at M = 20 (about 40 columns with the dummies) the scan saves
/// the heap's sifting and stale entries; at M = 50 (about 95) the heap does better, and a
/// limit of 64 rather than 128 takes 5 % fewer instructions there (CHANGELOG.md, *2-D (linear
/// assignment)*).
const LINEAR_MAX_COLS: usize = 64;

/// Flips the alternating path ending at column `sink` back to row `cur`.
fn augment(mut j: usize, cur: usize, path: &[usize], row4col: &mut [usize], col4row: &mut [usize]) {
    loop {
        let i = path[j];
        row4col[j] = i;
        std::mem::swap(&mut col4row[i], &mut j);
        if i == cur {
            break;
        }
    }
}

/// Heap key of column `j` at distance `d`, packed into one integer so that comparing keys is
/// a single compare: the distance in `f64::total_cmp` order, then free columns first, then
/// the column index (determinism).
fn key(d: f64, free: bool, j: usize) -> u128 {
    (u128::from(ordered(d)) << 64) | (u128::from(!free) << 63) | j as u128
}

/// `d` as an unsigned integer in `f64::total_cmp` order: every bit of negatives flipped, only
/// the sign bit of positives.
#[inline(always)]
fn ordered(d: f64) -> u64 {
    let bits = d.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    }
}

/// Inverse of [`key`]: the distance and the column.
fn unkey(k: u128) -> (f64, usize) {
    let ordered = (k >> 64) as u64;
    let bits = if ordered >> 63 == 1 {
        ordered & !(1 << 63)
    } else {
        !ordered
    };
    (f64::from_bits(bits), (k as u64 & !(1 << 63)) as usize)
}

/// The sparse algorithm on validated input; returns the column of each row, where column
/// `n_cols + i` means "row i unassigned". Why this is exact is on [`super::lap::solve_sparse`].
/// `w` is working memory, reused across calls.
pub(super) fn sparse<'w>(
    w: &'w mut SparseWork,
    costs: &SparseCosts,
    a: &[f64],
    b: &[f64],
) -> &'w [usize] {
    w.load(costs, a, b);
    w.assign_free_rows();
    &w.col4row
}

/// Working state of the sparse solver. The S-D solvers call it every iteration, so it keeps
/// its vectors between calls: a solve allocates nothing once they have grown.
#[derive(Default)]
pub(super) struct SparseWork {
    /// Reduced CSR keeping only profitable entries; column `nc + i` is row i's private dummy.
    offs: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
    u: Vec<f64>,
    v: Vec<f64>,
    dist: Vec<f64>,
    path: Vec<usize>,
    col4row: Vec<usize>,
    row4col: Vec<usize>,
    scanned: Vec<bool>,
    touched: Vec<usize>,
    sr: Vec<usize>,
    sc: Vec<usize>,
    heap: BinaryHeap<Reverse<u128>>,
    /// With few columns (`linear`), instead of the heap: the reached and unscanned columns,
    /// their distances as [`ordered`] integers, and each column's position in `open`.
    open: Vec<usize>,
    open_dist: Vec<u64>,
    slot: Vec<usize>,
    linear: bool,
    /// Only tests set this: the heap at any size, to compare the two.
    heap_only: bool,
    /// Distance of the nearest free column reached by the current search (`reset` sets it).
    free_dist: f64,
    /// Buffers of the square form's mirror rows (see `warm`), kept between calls.
    mirror_offs: Vec<usize>,
    mirror_fill: Vec<usize>,
}

impl SparseWork {
    /// The duals of the last solve: `u` per row, `v` per column of the reduced form (the
    /// input's columns, then each row's dummy). Read by [`super::SparseSolver::input_duals`].
    pub(super) fn duals(&self) -> (&[f64], &[f64]) {
        (&self.u, &self.v)
    }
}

/// Clears `v` and refills it with `n` copies of `x`, keeping its allocation.
fn refill<T: Clone>(v: &mut Vec<T>, n: usize, x: T) {
    v.clear();
    v.resize(n, x);
}

impl SparseWork {
    /// Sets up the solve of `costs` with unassigned costs `a` (rows) and `b` (columns).
    fn load(&mut self, costs: &SparseCosts, a: &[f64], b: &[f64]) {
        let (nr, nc) = (costs.n_rows(), costs.n_cols());
        self.load_rows(costs, a, b);
        self.size_for(nr, nc + nr);
    }

    /// The reduced CSR of the real rows: entries beating "both unassigned", then each row's
    /// private dummy column `nc + i` at 0.
    fn load_rows(&mut self, costs: &SparseCosts, a: &[f64], b: &[f64]) {
        let nc = costs.n_cols();
        self.offs.clear();
        self.cols.clear();
        self.vals.clear();
        self.offs.push(0);
        for (i, &ai) in a.iter().enumerate() {
            // Only entries beating "both unassigned" can be in an optimum; see `solve_sparse`.
            for (j, c) in costs.row(i) {
                let r = c - ai - b[j];
                if r < 0.0 {
                    self.cols.push(j);
                    self.vals.push(r);
                }
            }
            self.cols.push(nc + i);
            self.vals.push(0.0);
            self.offs.push(self.cols.len());
        }
    }

    /// Empty duals, paths and matching for `rows` rows and `cols` columns.
    fn size_for(&mut self, rows: usize, cols: usize) {
        refill(&mut self.u, rows, 0.0);
        refill(&mut self.v, cols, 0.0);
        refill(&mut self.dist, cols, f64::INFINITY);
        refill(&mut self.path, cols, NONE);
        refill(&mut self.col4row, rows, NONE);
        refill(&mut self.row4col, cols, NONE);
        refill(&mut self.scanned, cols, false);
        refill(&mut self.slot, cols, NONE);
        self.linear = cols <= LINEAR_MAX_COLS && !self.heap_only;
        self.reset();
    }

    /// Crouse's outer loop: every row without a column, in order, gets one by a shortest
    /// augmenting path (all rows after a cold `load`; those a warm start left free).
    fn assign_free_rows(&mut self) {
        for cur in 0..self.col4row.len() {
            if self.col4row[cur] != NONE {
                continue;
            }
            // Row `cur`'s dummy column is reachable only from `cur` and free until `cur` is
            // assigned, so the search always ends at a free column.
            let Some((sink, min_val)) = self.shortest_path(cur) else {
                unreachable!("sparse LAP: row {cur} lost its dummy column")
            };
            self.update_duals(cur, min_val);
            augment(sink, cur, &self.path, &mut self.row4col, &mut self.col4row);
            self.reset();
        }
    }

    /// Dijkstra from row `cur` to the nearest free column; returns it and its distance, or
    /// `None` if no free column is reachable.
    fn shortest_path(&mut self, cur: usize) -> Option<(usize, f64)> {
        let (mut i, mut min_val) = (cur, 0.0);
        loop {
            self.sr.push(i);
            self.relax(i, min_val);
            let j;
            (min_val, j) = self.nearest()?;
            self.scanned[j] = true;
            self.sc.push(j);
            if self.row4col[j] == NONE {
                return Some((j, min_val));
            }
            i = self.row4col[j];
        }
    }

    /// The reached, unscanned column of least [`key`] (distance, then free first, then
    /// index) and its distance; `None` when every reached column is scanned.
    fn nearest(&mut self) -> Option<(f64, usize)> {
        if self.linear {
            self.nearest_in_list()
        } else {
            self.nearest_in_heap()
        }
    }

    /// [`SparseWork::nearest`] from the heap, skipping stale entries (the column was scanned,
    /// or reached again at a shorter distance).
    fn nearest_in_heap(&mut self) -> Option<(f64, usize)> {
        loop {
            let Reverse(k) = self.heap.pop()?;
            let (d, j) = unkey(k);
            if !self.scanned[j] && d == self.dist[j] {
                return Some((d, j));
            }
        }
    }

    /// [`SparseWork::nearest`] by one pass over the open columns, which it then leaves.
    fn nearest_in_list(&mut self) -> Option<(f64, usize)> {
        let (mut best, mut best_d) = (0, *self.open_dist.first()?);
        for (at, &d) in self.open_dist.iter().enumerate().skip(1) {
            // Only equal distances need the rest of the key.
            if d < best_d || (d == best_d && self.ties_first(self.open[at], self.open[best])) {
                (best, best_d) = (at, d);
            }
        }
        let j = self.open.swap_remove(best);
        self.open_dist.swap_remove(best);
        if let Some(&moved) = self.open.get(best) {
            self.slot[moved] = best;
        }
        self.slot[j] = NONE;
        Some((self.dist[j], j))
    }

    /// Whether column `x` comes before column `y` at the same distance in [`key`] order.
    fn ties_first(&self, x: usize, y: usize) -> bool {
        let (fx, fy) = (self.row4col[x] == NONE, self.row4col[y] == NONE);
        (fx && !fy) || (fx == fy && x < y)
    }

    /// Relaxes the stored entries of row `i`, reached at distance `min_val`. The inner loop
    /// of the solver: it works on split borrows so the optimiser sees they do not alias.
    ///
    /// A column farther than the nearest free column already reached can never be scanned in
    /// this search (that free column ends it first), so it is skipped outright: its distance
    /// is never read, and a later, shorter path to it is compared against a value that is
    /// at least as large. This keeps most entries out of the heap without changing the result.
    fn relax(&mut self, i: usize, min_val: f64) {
        let span = self.offs[i]..self.offs[i + 1];
        let (cols, vals) = (&self.cols[span.clone()], &self.vals[span]);
        let (dist, path, scanned) = (&mut self.dist[..], &mut self.path[..], &self.scanned[..]);
        let (v, row4col, ui) = (&self.v[..], &self.row4col[..], self.u[i]);
        for (&j, &c) in cols.iter().zip(vals) {
            let r = min_val + c - ui - v[j];
            if r > self.free_dist || scanned[j] || r >= dist[j] {
                continue;
            }
            let first_reach = dist[j] == f64::INFINITY;
            if first_reach {
                self.touched.push(j);
            }
            dist[j] = r;
            path[j] = i;
            let free = row4col[j] == NONE;
            if free {
                self.free_dist = r;
            }
            if !self.linear {
                self.heap.push(Reverse(key(r, free, j)));
            } else if first_reach {
                self.slot[j] = self.open.len();
                self.open.push(j);
                self.open_dist.push(ordered(r));
            } else {
                self.open_dist[self.slot[j]] = ordered(r);
            }
        }
    }

    /// Crouse's dual update: keeps reduced costs of assigned rows non-negative.
    fn update_duals(&mut self, cur: usize, min_val: f64) {
        self.u[cur] += min_val;
        for &r in self.sr.iter().filter(|&&r| r != cur) {
            self.u[r] += min_val - self.dist[self.col4row[r]];
        }
        for &j in &self.sc {
            self.v[j] -= min_val - self.dist[j];
        }
    }

    /// Clears only what this search touched, so a search costs O(its own size).
    fn reset(&mut self) {
        for &j in &self.touched {
            self.dist[j] = f64::INFINITY;
            self.scanned[j] = false;
            self.slot[j] = NONE;
        }
        self.touched.clear();
        self.sr.clear();
        self.sc.clear();
        self.heap.clear();
        self.open.clear();
        self.open_dist.clear();
        self.free_dist = f64::INFINITY;
    }
}

#[cfg(test)]
impl SparseWork {
    /// A solver that always takes the heap (the tests compare it with the flat list).
    pub(super) fn heap_only() -> Self {
        Self {
            heap_only: true,
            ..Self::default()
        }
    }

    /// Whether the last solve picked its columns from the flat list.
    pub(super) fn took_list(&self) -> bool {
        self.linear
    }
}
