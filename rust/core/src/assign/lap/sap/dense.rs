//! The dense solver: Jonker & Volgenant's start ([`super::init`]), then Crouse's shortest
//! augmenting paths with an O(nc) scan per step, which beats a heap on dense rows.

use std::cell::RefCell;

use super::{augment, init, refill, Entry, NONE};
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
pub(in crate::assign::lap) fn dense<C: Entry>(
    nr: usize,
    nc: usize,
    cost: &[C],
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
    /// The distance at which each scanned column was reached (read only for those).
    dist: Vec<f64>,
    /// The open columns' tentative distances, `+inf` once scanned (the search's keys).
    key: Vec<f64>,
    /// `v` with `-inf` on the scanned columns, so that a relaxation never reaches them.
    vs: Vec<f64>,
    /// The row through which each column on the augmenting path was reached ([`Self::trace`];
    /// the other columns' entries are stale).
    path: Vec<usize>,
    /// The search's rows in the order scanned, and each one's `reached − u[i]`.
    scan_rows: Vec<usize>,
    scan_base: Vec<f64>,
    /// For each scanned column, how many rows had been scanned when it was.
    seen: Vec<usize>,
    col4row: Vec<usize>,
    row4col: Vec<usize>,
    /// Jonker & Volgenant's start, and its buffers.
    init: init::Init,
}

impl DenseWork {
    fn solve<C: Entry>(
        &mut self,
        nr: usize,
        nc: usize,
        cost: &[C],
        all_finite: bool,
    ) -> CoreResult<Vec<usize>> {
        self.nc = nc;
        refill(&mut self.u, nr, 0.0);
        refill(&mut self.dist, nc, f64::INFINITY);
        refill(&mut self.path, nc, NONE);
        refill(&mut self.seen, nc, 0);
        // Square: Jonker & Volgenant's start assigns most rows cheaply, and the augmenting
        // paths below run only for the rest. It needs a finite entry in every row and column
        // (else a price would be infinite; such a square problem has no complete assignment
        // anyway, which the paths then report), and a rectangular problem needs its free
        // columns' prices at 0.
        let free = if nr == nc && nr > 1 && (all_finite || init::startable(nr, cost)) {
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
            if !self.trace(sink, cur, cost) {
                return Err(CoreError::ill_posed(
                    "costs",
                    format!("internal error: the search from row {cur} could not be traced back; please report it with the matrix"),
                ));
            }
            self.update_duals(sink, min_val);
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
    fn seed<C: Entry>(&mut self, cost: &[C]) {
        let nc = self.nc;
        std::mem::swap(&mut self.v, &mut self.init.v);
        std::mem::swap(&mut self.col4row, &mut self.init.col4row);
        std::mem::swap(&mut self.row4col, &mut self.init.row4col);
        for (i, &j) in self.col4row.iter().enumerate() {
            if j != NONE {
                self.u[i] = cost[i * nc + j].get() - self.v[j];
            }
        }
    }

    /// Dijkstra from row `cur` to the nearest free column over reduced costs; `None` if every
    /// reachable column is forbidden. The O(nc) scan per step beats a heap on dense rows.
    fn shortest_path<C: Entry>(&mut self, cur: usize, cost: &[C]) -> Option<(usize, f64)> {
        let nc = self.nc;
        refill(&mut self.key, nc, f64::INFINITY);
        self.vs.clear();
        self.vs.extend_from_slice(&self.v[..nc]);
        self.scan_rows.clear();
        self.scan_base.clear();
        let (mut i, mut min_val) = (cur, 0.0);
        loop {
            let base = min_val - self.u[i];
            self.scan_rows.push(i);
            self.scan_base.push(base);
            let j;
            (j, min_val) = self.relax_row(base, &cost[i * nc..(i + 1) * nc])?;
            self.seen[j] = self.scan_rows.len();
            self.dist[j] = min_val;
            self.key[j] = f64::INFINITY;
            self.vs[j] = f64::NEG_INFINITY;
            if self.row4col[j] == NONE {
                return Some((j, min_val));
            }
            i = self.row4col[j];
        }
    }

    /// Relaxes every unscanned column through the row `row`, whose `reached − u[i]` is `base`;
    /// returns the nearest unscanned column and its distance. On a tie, the lowest free column
    /// (the search can stop there), else the highest column: what one scan from the last
    /// column picks when it keeps the first minimum or a later free one, which scipy's first
    /// search resembles (`==`, not a total order: −0.0 ties with 0.0).
    ///
    /// These loops are the whole cost of a dense solve. They walk the row and the per-column
    /// arrays in order (no gather through a list of remaining columns: sequential reads let
    /// the prefetcher keep up), in two passes:
    /// - the relaxation, `key ← min(key, base + c − vs)`, with four running minima of the keys
    ///   (columns `j ≡ l mod 4`), written out lane by lane so that the compiler packs them
    ///   (`minpd`): a scanned column needs no test, as `vs` makes its reduced cost `+inf`, and
    ///   no row is recorded (the path's rows are found afterwards, [`Self::trace`]);
    /// - the column of the least key: eight keys compared with it at once, branch-free (a
    ///   plain loop that stops at the first equal key cannot be packed, and took 18 % of a
    ///   3000² solve), and only a block holding it looked into, its owners read on a tie.
    ///
    /// At 3000² the per-column arrays no longer fit the first level of cache, so each pass
    /// over them costs: the minima in a pass of their own took 15 % longer at 1000² and 12 %
    /// at 3000². Choosing the column inside the relaxation, with the tie rule in each lane,
    /// took 36–42 % longer at 100² and 1000² (the core alone, when the scan still stored each
    /// closer column's row; CHANGELOG.md, *2-D (linear assignment)*).
    fn relax_row<C: Entry>(&mut self, base: f64, row: &[C]) -> Option<(usize, f64)> {
        // Split borrows into plain slices so the optimiser sees they do not alias.
        let nc = self.nc;
        let key = &mut self.key[..nc];
        let (vs, row) = (&self.vs[..nc], &row[..nc]);
        let mut lanes = [f64::INFINITY; 4];
        let mut k4 = key.chunks_exact_mut(4);
        let (mut r4, mut v4) = (row.chunks_exact(4), vs.chunks_exact(4));
        for ((k, c), w) in (&mut k4).zip(&mut r4).zip(&mut v4) {
            let r = [
                base + c[0].get() - w[0],
                base + c[1].get() - w[1],
                base + c[2].get() - w[2],
                base + c[3].get() - w[3],
            ];
            let nk = [
                if r[0] < k[0] { r[0] } else { k[0] },
                if r[1] < k[1] { r[1] } else { k[1] },
                if r[2] < k[2] { r[2] } else { k[2] },
                if r[3] < k[3] { r[3] } else { k[3] },
            ];
            k.copy_from_slice(&nk);
            lanes = [
                if nk[0] < lanes[0] { nk[0] } else { lanes[0] },
                if nk[1] < lanes[1] { nk[1] } else { lanes[1] },
                if nk[2] < lanes[2] { nk[2] } else { lanes[2] },
                if nk[3] < lanes[3] { nk[3] } else { lanes[3] },
            ];
        }
        let mut low = lanes
            .into_iter()
            .fold(f64::INFINITY, |a, b| if b < a { b } else { a });
        let tail = (k4.into_remainder().iter_mut()).zip(r4.remainder().iter().zip(v4.remainder()));
        for (k, (c, w)) in tail {
            let r = base + c.get() - w;
            *k = if r < *k { r } else { *k };
            low = if *k < low { *k } else { low };
        }
        if low == f64::INFINITY {
            return None;
        }
        // Ties: the lowest free column, else the highest. Eight keys are tested at once,
        // branch-free, and only a block holding the least is looked into.
        let row4col = &self.row4col[..nc];
        let mut highest = NONE;
        let k8 = key.chunks_exact(8);
        let tail = nc - k8.remainder().len();
        let blocks = k8
            .enumerate()
            .map(|(b, k)| (8 * b, k.iter().fold(false, |a, &x| a | (x == low))));
        let hits = blocks.filter(|&(_, any)| any).map(|(at, _)| at..at + 8);
        for j in hits.flatten().chain(tail..nc) {
            if key[j] == low {
                if row4col[j] == NONE {
                    return Some((j, key[j]));
                }
                highest = j;
            }
        }
        key.get(highest).map(|&k| (highest, k))
    }

    /// Sets `path` on the augmenting path that ends at `sink`: for each of its columns, the row
    /// through which the search reached it, back to `cur`. The scan keeps no such record (one
    /// store a column and a row, of which only the path's few are ever read); the row is the
    /// first scanned, before the column was, whose relaxation gives the column's distance,
    /// as the scan's strict `<` kept the first. The sums are the scan's own, the same
    /// operations on the same values (no contraction into fused multiply-adds), so they equal
    /// it bit for bit; `false` would mean they did not, and the solve then fails loudly rather
    /// than augment along a wrong path. Before the duals change.
    fn trace<C: Entry>(&mut self, sink: usize, cur: usize, cost: &[C]) -> bool {
        let nc = self.nc;
        let mut j = sink;
        loop {
            let rows = self.scan_rows[..self.seen[j]].iter();
            let found = (rows.zip(&self.scan_base))
                .find(|&(&s, &base)| base + cost[s * nc + j].get() - self.v[j] == self.dist[j]);
            debug_assert!(found.is_some(), "column {j} reached by no scanned row");
            let Some((&i, _)) = found else {
                return false;
            };
            self.path[j] = i;
            if i == cur {
                return true;
            }
            j = self.col4row[i];
        }
    }

    /// Crouse's dual update: keeps reduced costs of assigned rows non-negative. The search's
    /// rows are `scan_rows` (its start first), and its columns are the other rows' columns
    /// (through which they were reached) and the `sink`.
    fn update_duals(&mut self, sink: usize, min_val: f64) {
        let Some((&cur, reached)) = self.scan_rows.split_first() else {
            return; // no search ran
        };
        self.u[cur] += min_val;
        for &r in reached {
            let j = self.col4row[r];
            self.u[r] += min_val - self.dist[j];
            self.v[j] -= min_val - self.dist[j];
        }
        self.v[sink] -= min_val - self.dist[sink];
    }
}
