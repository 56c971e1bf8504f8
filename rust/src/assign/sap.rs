//! The shortest-augmenting-path cores behind [`super::lap`].
//!
//! Both solvers are the shortest-augmenting-path method of Jonker & Volgenant in the form of
//! Crouse (2016, "On implementing 2D rectangular assignment algorithms"), the algorithm behind
//! `scipy.optimize.linear_sum_assignment`: rows are added one at a time, each by a Dijkstra
//! search over reduced costs `c - u - v` that stays non-negative on already assigned rows, then
//! the duals are updated so they stay feasible. It is hand-rolled rather than taken from a
//! generic crate because the S-D solvers call it hundreds of times per problem: per-call
//! set-up of a generic graph type and allocation in the inner loop would cost more than the
//! solve itself. The inner loops here touch only preallocated flat vectors.

use super::lap::SparseCosts;
use crate::error::{CoreError, CoreResult};
use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;

const NONE: usize = usize::MAX;

/// Crouse's algorithm for `nr <= nc`; returns the column of each row. `cost` has no NaN or
/// `-inf` (checked by the caller); `+inf` entries are forbidden pairs.
pub(super) fn dense(nr: usize, nc: usize, cost: &[f64]) -> CoreResult<Vec<usize>> {
    let mut w = DenseWork::new(nr, nc);
    for cur in 0..nr {
        let Some((sink, min_val)) = w.shortest_path(cur, cost) else {
            return Err(CoreError::ill_posed(
                "costs",
                format!(
                    "row {cur} cannot be assigned: +inf entries forbid every complete assignment"
                ),
            ));
        };
        w.update_duals(cur, min_val);
        augment(sink, cur, &w.path, &mut w.row4col, &mut w.col4row);
    }
    Ok(w.col4row)
}

/// Working state of the dense solver, allocated once per solve.
struct DenseWork {
    nc: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    dist: Vec<f64>,
    path: Vec<usize>,
    col4row: Vec<usize>,
    row4col: Vec<usize>,
    in_sr: Vec<bool>,
    in_sc: Vec<bool>,
    /// Columns not yet scanned by the current search, in `remaining[..n_rem]`.
    remaining: Vec<usize>,
}

impl DenseWork {
    fn new(nr: usize, nc: usize) -> Self {
        Self {
            nc,
            u: vec![0.0; nr],
            v: vec![0.0; nc],
            dist: vec![f64::INFINITY; nc],
            path: vec![NONE; nc],
            col4row: vec![NONE; nr],
            row4col: vec![NONE; nc],
            in_sr: vec![false; nr],
            in_sc: vec![false; nc],
            remaining: vec![0; nc],
        }
    }

    /// Dijkstra from row `cur` to the nearest free column over reduced costs; `None` if every
    /// reachable column is forbidden. The O(nc) scan per step beats a heap on dense rows.
    fn shortest_path(&mut self, cur: usize, cost: &[f64]) -> Option<(usize, f64)> {
        let nc = self.nc;
        // Reversed order, as scipy, so ties resolve to the same columns.
        for (it, r) in self.remaining.iter_mut().enumerate() {
            *r = nc - it - 1;
        }
        self.in_sr.fill(false);
        self.in_sc.fill(false);
        self.dist.fill(f64::INFINITY);
        let (mut i, mut n_rem, mut min_val) = (cur, nc, 0.0);
        loop {
            self.in_sr[i] = true;
            let index;
            (index, min_val) = self.relax_row(i, &cost[i * nc..(i + 1) * nc], n_rem, min_val)?;
            let j = self.remaining[index];
            self.in_sc[j] = true;
            n_rem -= 1;
            self.remaining[index] = self.remaining[n_rem];
            if self.row4col[j] == NONE {
                return Some((j, min_val));
            }
            i = self.row4col[j];
        }
    }

    /// Relaxes every unscanned column through row `i`, reached at distance `reached`; returns
    /// the position in `remaining` of the nearest column and its distance. This loop is the
    /// whole cost of a dense solve, so it reads only flat slices.
    fn relax_row(
        &mut self,
        i: usize,
        row: &[f64],
        n_rem: usize,
        reached: f64,
    ) -> Option<(usize, f64)> {
        let base = reached - self.u[i];
        // Split borrows into plain slices so the optimiser sees they do not alias.
        let (dist, path, v) = (&mut self.dist[..], &mut self.path[..], &self.v[..]);
        let (remaining, row4col) = (&self.remaining[..n_rem], &self.row4col[..]);
        let (mut lowest, mut index) = (f64::INFINITY, NONE);
        for (it, &j) in remaining.iter().enumerate() {
            let r = base + row[j] - v[j];
            if r < dist[j] {
                path[j] = i;
                dist[j] = r;
            }
            let d = dist[j];
            // On ties prefer a free column: the search can stop there.
            if d < lowest || (d == lowest && row4col[j] == NONE) {
                lowest = d;
                index = it;
            }
        }
        (lowest < f64::INFINITY).then_some((index, lowest))
    }

    /// Crouse's dual update: keeps reduced costs of assigned rows non-negative.
    fn update_duals(&mut self, cur: usize, min_val: f64) {
        self.u[cur] += min_val;
        for r in (0..self.u.len()).filter(|&r| self.in_sr[r] && r != cur) {
            self.u[r] += min_val - self.dist[self.col4row[r]];
        }
        for j in (0..self.nc).filter(|&j| self.in_sc[j]) {
            self.v[j] -= min_val - self.dist[j];
        }
    }
}

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

/// Heap key: reduced distance, then free columns first, then column index (determinism).
#[derive(PartialEq)]
struct Key(f64, bool, usize);
impl Eq for Key {}
impl PartialOrd for Key {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Key {
    fn cmp(&self, o: &Self) -> Ordering {
        self.0
            .total_cmp(&o.0)
            .then(o.1.cmp(&self.1))
            .then(self.2.cmp(&o.2))
    }
}

/// The sparse algorithm on validated input; returns the column of each row, where column
/// `n_cols + i` means "row i unassigned". Why this is exact is on [`super::lap::solve_sparse`].
pub(super) fn sparse(costs: &SparseCosts, a: &[f64], b: &[f64]) -> Vec<usize> {
    let mut w = SparseWork::new(costs, a, b);
    for cur in 0..costs.n_rows() {
        let (sink, min_val) = w.shortest_path(cur);
        w.update_duals(cur, min_val);
        augment(sink, cur, &w.path, &mut w.row4col, &mut w.col4row);
        w.reset();
    }
    w.col4row
}

/// Working state of the sparse solver; every vector is allocated once per solve.
struct SparseWork {
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
    heap: BinaryHeap<Reverse<Key>>,
}

impl SparseWork {
    fn new(costs: &SparseCosts, a: &[f64], b: &[f64]) -> Self {
        let (nr, nc) = (costs.n_rows(), costs.n_cols());
        let (mut offs, mut cols, mut vals) = (Vec::with_capacity(nr + 1), Vec::new(), Vec::new());
        offs.push(0);
        for (i, &ai) in a.iter().enumerate() {
            // Only entries beating "both unassigned" can be in an optimum; see `solve_sparse`.
            for (j, c) in costs.row(i) {
                let r = c - ai - b[j];
                if r < 0.0 {
                    cols.push(j);
                    vals.push(r);
                }
            }
            cols.push(nc + i);
            vals.push(0.0);
            offs.push(cols.len());
        }
        let n = nc + nr;
        Self {
            offs,
            cols,
            vals,
            u: vec![0.0; nr],
            v: vec![0.0; n],
            dist: vec![f64::INFINITY; n],
            path: vec![NONE; n],
            col4row: vec![NONE; nr],
            row4col: vec![NONE; n],
            scanned: vec![false; n],
            touched: Vec::new(),
            sr: Vec::new(),
            sc: Vec::new(),
            heap: BinaryHeap::new(),
        }
    }

    /// Dijkstra from row `cur` to the nearest free column; returns it and its distance.
    fn shortest_path(&mut self, cur: usize) -> (usize, f64) {
        let (mut i, mut min_val) = (cur, 0.0);
        loop {
            self.sr.push(i);
            for k in self.offs[i]..self.offs[i + 1] {
                let j = self.cols[k];
                let r = min_val + self.vals[k] - self.u[i] - self.v[j];
                if !self.scanned[j] && r < self.dist[j] {
                    if self.dist[j] == f64::INFINITY {
                        self.touched.push(j);
                    }
                    self.dist[j] = r;
                    self.path[j] = i;
                    self.heap.push(Reverse(Key(r, self.row4col[j] == NONE, j)));
                }
            }
            let j = loop {
                // The dummy column of `cur` is reachable only from `cur` and free until `cur`
                // is assigned, so it was pushed above and the heap cannot run dry first.
                let Some(Reverse(Key(d, _, j))) = self.heap.pop() else {
                    unreachable!("sparse LAP: row {cur} lost its dummy column")
                };
                if !self.scanned[j] && d == self.dist[j] {
                    min_val = d;
                    break j;
                }
            };
            self.scanned[j] = true;
            self.sc.push(j);
            if self.row4col[j] == NONE {
                return (j, min_val);
            }
            i = self.row4col[j];
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
        }
        self.touched.clear();
        self.sr.clear();
        self.sc.clear();
        self.heap.clear();
    }
}
