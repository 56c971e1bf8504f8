//! The dense solver: Jonker & Volgenant's start ([`super::init`]), then Crouse's shortest
//! augmenting paths with an O(nc) scan per step, which beats a heap on dense rows.

use std::cell::RefCell;

use super::{augment, init, refill, NONE};
use crate::error::{CoreError, CoreResult};

/// Sides up to which a thread keeps its workspace between solves: a small solve's dozen
/// allocations cost about as much as the solve (a 10 × 10 call is about a microsecond), and
/// the kept vectors are O(n), a few hundred kilobytes at this size.
const KEEP_SIDE: usize = 4096;

thread_local! {
    static KEPT: RefCell<DenseWork> = RefCell::new(DenseWork::default());
}

/// Crouse's algorithm for `nr <= nc`; returns the column of each row. `cost` has no NaN or
/// `-inf` (checked by the caller); `+inf` entries are forbidden pairs; `all_finite` says
/// there are none (the caller has counted).
pub(in crate::assign::lap) fn dense(
    nr: usize,
    nc: usize,
    cost: &[f64],
    all_finite: bool,
) -> CoreResult<Vec<usize>> {
    if nr > KEEP_SIDE || nc > KEEP_SIDE {
        return DenseWork::default().solve(nr, nc, cost, all_finite);
    }
    KEPT.with(|kept| match kept.try_borrow_mut() {
        Ok(mut w) => w.solve(nr, nc, cost, all_finite),
        Err(_) => DenseWork::default().solve(nr, nc, cost, all_finite),
    })
}

/// Working state of the dense solver; [`DenseWork::solve`] refills every vector, so one
/// workspace serves many solves.
#[derive(Default)]
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
    /// Jonker & Volgenant's start, and its buffers.
    init: init::Init,
}

impl DenseWork {
    fn solve(
        &mut self,
        nr: usize,
        nc: usize,
        cost: &[f64],
        all_finite: bool,
    ) -> CoreResult<Vec<usize>> {
        self.nc = nc;
        refill(&mut self.u, nr, 0.0);
        refill(&mut self.dist, nc, f64::INFINITY);
        refill(&mut self.path, nc, NONE);
        refill(&mut self.in_sr, nr, false);
        refill(&mut self.in_sc, nc, false);
        // Square and finite: Jonker & Volgenant's start assigns most rows cheaply, and the
        // augmenting paths below run only for the rest. `+inf` entries would make its prices
        // infinite, and a rectangular problem needs its free columns' prices at 0.
        let free = if nr == nc && nr > 1 && all_finite {
            init::jv_init(nr, cost, &mut self.init);
            self.seed(cost);
            Some(std::mem::take(&mut self.init.free))
        } else {
            refill(&mut self.v, nc, 0.0);
            refill(&mut self.col4row, nr, NONE);
            refill(&mut self.row4col, nc, NONE);
            None
        };
        let rows: &[usize] = free.as_deref().unwrap_or(&[]);
        let all = (free.is_none()).then_some(0..nr).into_iter().flatten();
        for cur in rows.iter().copied().chain(all) {
            let Some((sink, min_val)) = self.shortest_path(cur, cost) else {
                return Err(CoreError::ill_posed(
                    "costs",
                    format!(
                        "row {cur} cannot be assigned: +inf entries forbid every complete assignment"
                    ),
                ));
            };
            self.update_duals(cur, min_val);
            augment(sink, cur, &self.path, &mut self.row4col, &mut self.col4row);
        }
        if let Some(free) = free {
            self.init.free = free; // its allocation, for the next solve
        }
        Ok(self.col4row.clone())
    }

    /// Starts from the start's prices and partial matching, with each assigned row's dual at
    /// its reduced cost (feasible: the start keeps every assigned row at its cheapest column).
    /// The vectors are swapped, not moved, so both keep their allocations.
    fn seed(&mut self, cost: &[f64]) {
        let nc = self.nc;
        std::mem::swap(&mut self.v, &mut self.init.v);
        std::mem::swap(&mut self.col4row, &mut self.init.col4row);
        std::mem::swap(&mut self.row4col, &mut self.init.row4col);
        for (i, &j) in self.col4row.iter().enumerate() {
            if j != NONE {
                self.u[i] = cost[i * nc + j] - self.v[j];
            }
        }
    }

    /// Dijkstra from row `cur` to the nearest free column over reduced costs; `None` if every
    /// reachable column is forbidden. The O(nc) scan per step beats a heap on dense rows.
    fn shortest_path(&mut self, cur: usize, cost: &[f64]) -> Option<(usize, f64)> {
        let nc = self.nc;
        self.in_sr.fill(false);
        self.in_sc.fill(false);
        self.dist.fill(f64::INFINITY);
        let (mut i, mut min_val) = (cur, 0.0);
        loop {
            self.in_sr[i] = true;
            let j;
            (j, min_val) = self.relax_row(i, &cost[i * nc..(i + 1) * nc], min_val)?;
            self.in_sc[j] = true;
            if self.row4col[j] == NONE {
                return Some((j, min_val));
            }
            i = self.row4col[j];
        }
    }

    /// Relaxes every unscanned column through row `i`, reached at distance `reached`; returns
    /// the nearest unscanned column and its distance (ties: see [`preferred`]). This loop is
    /// the whole cost of a dense solve, so it walks the row and the per-column arrays in order
    /// (no gather through a list of remaining columns: sequential reads let the prefetcher keep
    /// up), with four lanes (columns `j ≡ k mod 4`) whose updates are selects, not branches:
    /// the comparisons of one lane do not wait on another's, and none is mispredicted.
    fn relax_row(&mut self, i: usize, row: &[f64], reached: f64) -> Option<(usize, f64)> {
        let base = reached - self.u[i];
        // Split borrows into plain slices so the optimiser sees they do not alias.
        let nc = self.nc;
        let (dist, path) = (&mut self.dist[..nc], &mut self.path[..nc]);
        let (v, row4col, scanned) = (&self.v[..nc], &self.row4col[..nc], &self.in_sc[..nc]);
        let row = &row[..nc];
        let mut relax = |j: usize, (low, at): (f64, usize)| {
            let r = base + row[j] - v[j];
            let open = !scanned[j];
            let closer = open & (r < dist[j]);
            path[j] = if closer { i } else { path[j] };
            dist[j] = if closer { r } else { dist[j] };
            let d = if open { dist[j] } else { f64::INFINITY };
            // Within a lane, from the last column: a tie goes to a free column, the
            // sequential rule that [`preferred`] extends to merging lanes.
            let take = d < low || (d == low && row4col[j] == NONE);
            if take {
                (d, j)
            } else {
                (low, at)
            }
        };
        let body = nc - nc % 4;
        let mut best = (f64::INFINITY, NONE);
        for j in (body..nc).rev() {
            best = relax(j, best);
        }
        let mut lanes = [(f64::INFINITY, NONE); 4];
        for chunk in (0..body).step_by(4).rev() {
            for (k, lane) in lanes.iter_mut().enumerate() {
                *lane = relax(chunk + k, *lane);
            }
        }
        for lane in lanes {
            if preferred(lane, best, row4col) {
                best = lane;
            }
        }
        (best.0 < f64::INFINITY).then_some((best.1, best.0))
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

/// Whether column `a.1` at distance `a.0` beats `b`: the nearer; on a tie a free column (the
/// search can stop there), the lowest such; else the highest column. This is what one scan
/// from the last column keeping the first minimum, or a later free one, picks, so lanes
/// merged by it pick the same column as that scan, which scipy's first search resembles.
fn preferred(a: (f64, usize), b: (f64, usize), row4col: &[usize]) -> bool {
    let free = |j: usize| j != NONE && row4col[j] == NONE;
    if a.0 != b.0 {
        return a.0 < b.0; // `==`, not a total order: −0.0 ties with 0.0, as in one scan
    }
    match (free(a.1), free(b.1)) {
        (true, true) => a.1 < b.1,
        (true, false) => true,
        (false, true) => false,
        (false, false) => b.1 == NONE || (a.1 != NONE && a.1 > b.1),
    }
}
