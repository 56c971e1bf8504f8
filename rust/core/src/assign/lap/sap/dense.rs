//! The dense solver: Jonker & Volgenant's start ([`super::init`]), then Crouse's shortest
//! augmenting paths with an O(nc) scan per step, which beats a heap on dense rows.

use super::{augment, init, NONE};
use crate::error::{CoreError, CoreResult};

/// Crouse's algorithm for `nr <= nc`; returns the column of each row. `cost` has no NaN or
/// `-inf` (checked by the caller); `+inf` entries are forbidden pairs; `all_finite` says
/// there are none (the caller has counted).
pub(in crate::assign::lap) fn dense(
    nr: usize,
    nc: usize,
    cost: &[f64],
    all_finite: bool,
) -> CoreResult<Vec<usize>> {
    let mut w = DenseWork::new(nr, nc);
    // Square and finite: Jonker & Volgenant's start assigns most rows cheaply, and the
    // augmenting paths below run only for the rest. `+inf` entries would make its prices
    // infinite, and a rectangular problem needs its free columns' prices at 0.
    let rows = if nr == nc && nr > 1 && all_finite {
        w.seed(init::jv_init(nr, cost), cost)
    } else {
        (0..nr).collect()
    };
    for cur in rows {
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
        }
    }

    /// Starts from `init`'s prices and partial matching, with each assigned row's dual at its
    /// reduced cost (feasible: `init` keeps every assigned row at its cheapest column); returns
    /// the rows still free.
    fn seed(&mut self, init: init::Init, cost: &[f64]) -> Vec<usize> {
        let nc = self.nc;
        for (i, &j) in init.col4row.iter().enumerate() {
            if j != NONE {
                self.u[i] = cost[i * nc + j] - init.v[j];
            }
        }
        (self.v, self.col4row, self.row4col) = (init.v, init.col4row, init.row4col);
        init.free
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
