//! Primal recovery for the Lagrangian solver: turn a relaxed (infeasible) solution into a
//! feasible one by successive 2-D assignments, then polish it with a swap local search
//! ([`search`]); once per solve, the best solution gets a compound-move polish ([`polish`]).
//!
//! This runs once per subgradient iteration, so [`Recovery`] indexes the tuples once per solve
//! and keeps its buffers (an iteration allocates little beyond the solutions it returns), and
//! each stage looks only at the tuples still choosable, not at every candidate.

use super::reduced::{keep_min, modified, EMPTY};
use crate::assign::lap::{SparseCosts, SparseSolver};
use crate::assign::SdProblem;
use rustc_hash::FxHashSet;
use search::Search;

mod polish;
mod ranked;
mod search;

const NONE: usize = usize::MAX;
/// Prefix marker: all zeros so far (sensors 0..s all missed).
const ZERO: usize = usize::MAX;
/// Prefix marker: the prefix was not kept, so the tuple can no longer be chosen.
const DEAD: usize = usize::MAX - 1;

/// Recovery state for one problem.
pub(super) struct Recovery {
    /// Per tuple index: id of its (sensor 0, sensor 1) report pair, `ZERO` for (0, 0).
    pair: Vec<usize>,
    /// Per pair id: its row in the first stage, `DEAD` when the relaxed solution lacks it.
    row_of_pair: Vec<usize>,
    /// Each pair's active tuples, ascending (CSR), and the active tuples of no pair.
    pair_offs: Vec<usize>,
    pair_members: Vec<usize>,
    unpaired: Vec<usize>,
    /// The tuples still choosable in the current stage, with their prefix row or `ZERO`.
    live: Vec<(usize, usize)>,
    stage: Stage,
    search: Search,
    /// Pair sets (S = 3, in the relaxed solution's order) and local-search starts (sorted)
    /// already handled. Both are looked up every iteration: with SipHash instead of Fx that
    /// took about 1 % more of a solve's instructions (`lagrangian_profile`).
    seen_pairs: FxHashSet<Vec<usize>>,
    seen_starts: FxHashSet<Vec<usize>>,
    /// The pair set or start being looked up: stored only when new.
    key: Vec<usize>,
}

impl Recovery {
    pub(super) fn new(problem: &SdProblem) -> Self {
        let key = |k: usize| (problem.tuple(k)[0], problem.tuple(k)[1]);
        // By pair, each pair's tuples ascending (the index makes every key distinct).
        let mut sorted: Vec<(usize, usize, usize)> = problem
            .active()
            .iter()
            .map(|&k| (key(k).0, key(k).1, k))
            .collect();
        sorted.sort_unstable();
        let sorted: Vec<usize> = sorted.into_iter().map(|e| e.2).collect();
        let (mut pair, mut pair_offs) = (vec![ZERO; problem.n_tuples()], vec![]);
        let (mut pair_members, mut unpaired) = (vec![], vec![]);
        for (at, &k) in sorted.iter().enumerate() {
            if key(k) == (0, 0) {
                unpaired.push(k);
                continue;
            }
            if at == 0 || key(sorted[at - 1]) != key(k) {
                pair_offs.push(pair_members.len());
            }
            pair[k] = pair_offs.len() - 1;
            pair_members.push(k);
        }
        pair_offs.push(pair_members.len());
        Self {
            pair,
            row_of_pair: vec![DEAD; pair_offs.len() - 1],
            pair_offs,
            pair_members,
            unpaired,
            live: Vec::new(),
            stage: Stage::default(),
            search: Search::new(problem),
            seen_pairs: FxHashSet::default(),
            seen_starts: FxHashSet::default(),
            key: Vec::new(),
        }
    }

    /// [`Recovery::new`] of the problem without the tuples `keep` rejects (per tuple index),
    /// by filtering this recovery's pairs and scan order rather than sorting them again; the
    /// caches of what was already tried start empty, as in a new one.
    pub(super) fn retain(&mut self, keep: &[bool]) {
        let (mut offs, mut members) = (Vec::new(), Vec::new());
        for p in 0..self.pair_offs.len().saturating_sub(1) {
            let start = members.len();
            for &k in &self.pair_members[self.pair_offs[p]..self.pair_offs[p + 1]] {
                self.pair[k] = ZERO;
                if keep[k] {
                    self.pair[k] = offs.len();
                    members.push(k);
                }
            }
            if members.len() > start {
                offs.push(start);
            }
        }
        offs.push(members.len());
        self.row_of_pair = vec![DEAD; offs.len() - 1];
        (self.pair_offs, self.pair_members) = (offs, members);
        self.unpaired.retain(|&k| keep[k]);
        self.live.clear();
        self.search.retain(keep);
        self.seen_pairs.clear();
        self.seen_starts.clear();
        self.key.clear();
    }

    /// The best feasible solution derivable from the relaxed one, and its cost: the relaxed
    /// solution itself if feasible, and the successive-assignment recovery, both polished.
    /// `None` when every candidate was already produced by an earlier call: the caller has
    /// compared it with its incumbent then.
    pub(super) fn primal(
        &mut self,
        problem: &SdProblem,
        mult: &[Vec<f64>],
        relaxed: &[usize],
    ) -> Option<(Vec<usize>, f64)> {
        // With S = 3 the single recovery stage costs tuples by their own costs, so the result
        // depends only on the relaxed solution's (sensor 0, sensor 1) pairs, in their order
        // (which numbers the stage's rows). Late iterations often repeat a pair set.
        let fresh = problem.n_sensors() > 3 || {
            self.key.clear();
            let pairs = relaxed.iter().map(|&k| self.pair[k]);
            self.key.extend(pairs.filter(|&p| p != ZERO));
            first_time(&mut self.seen_pairs, &self.key)
        };
        let recovered = if fresh {
            self.recover(problem, mult, relaxed)
        } else {
            None
        };
        let mut best: Option<(Vec<usize>, f64)> = None;
        for chosen in [Some(relaxed), recovered.as_deref()].into_iter().flatten() {
            // The local search is deterministic: a start seen before ends where it did then.
            self.key.clear();
            self.key.extend_from_slice(chosen);
            self.key.sort_unstable();
            if !first_time(&mut self.seen_starts, &self.key) {
                continue;
            }
            if let Some(cand) = self.search.improve(problem, chosen) {
                if best.as_ref().is_none_or(|b| cand.1 < b.1) {
                    best = Some(cand);
                }
            }
        }
        best
    }

    /// The compound-move polish of feasible `chosen` ([`polish`]), in the scan order the
    /// per-iteration search already built.
    pub(super) fn polish(&self, problem: &SdProblem, chosen: &[usize]) -> (Vec<usize>, f64) {
        polish::polish_ranked(problem, self.search.ranked(), chosen)
    }

    /// Feasible recovery by successive 2-D assignments: keep the sensor-0/1 pairs of the
    /// relaxed solution as prefixes, then for each later sensor s assign prefixes to its
    /// reports, costing each by its best tuple with the multipliers of sensors after s still
    /// applied (so those sensors are anticipated, not ignored). Every stage is feasible, so the
    /// result is. `None` for S = 2, where the relaxed solution is already the answer.
    fn recover(
        &mut self,
        problem: &SdProblem,
        mult: &[Vec<f64>],
        relaxed: &[usize],
    ) -> Option<Vec<usize>> {
        let mut n_rows = 0;
        self.live.clear();
        for &k in relaxed {
            let p = self.pair[k];
            if p != ZERO && self.row_of_pair[p] == DEAD {
                self.row_of_pair[p] = n_rows;
                let members = &self.pair_members[self.pair_offs[p]..self.pair_offs[p + 1]];
                self.live.extend(members.iter().map(|&m| (m, n_rows)));
                n_rows += 1;
            }
        }
        self.live.extend(self.unpaired.iter().map(|&m| (m, ZERO)));
        for &k in relaxed {
            if self.pair[k] != ZERO {
                self.row_of_pair[self.pair[k]] = DEAD;
            }
        }
        for s in 2..problem.n_sensors() {
            let best = self.stage.run(problem, mult, s, &self.live, n_rows);
            if s + 1 == problem.n_sensors() {
                return Some(best);
            }
            let st = &self.stage;
            self.live.retain_mut(|(k, r)| {
                let i = problem.tuple(*k)[s];
                *r = match *r {
                    ZERO if i == 0 => ZERO,
                    ZERO => st.zero_start[i - 1],
                    r if st.next_report[r] == i => st.next_id[r],
                    _ => DEAD,
                };
                *r != DEAD
            });
            n_rows = best.len();
        }
        None
    }
}

/// Whether `key` is new to `seen`, which then holds it. Looks up before storing, so that a key
/// seen before costs no allocation (late iterations mostly repeat).
fn first_time(seen: &mut FxHashSet<Vec<usize>>, key: &[usize]) -> bool {
    !seen.contains(key) && seen.insert(key.to_vec())
}

/// Buffers of one recovery stage, reused across stages and iterations.
#[derive(Default)]
struct Stage {
    /// Per prefix row: its cheapest tuple that continues with 0 at this sensor.
    rows: Vec<(f64, usize)>,
    /// Per report: its cheapest tuple that starts a new all-zero prefix.
    cols: Vec<(f64, usize)>,
    /// Per live tuple: its cost at this stage (edges only).
    cost: Vec<f64>,
    /// Edges `(report − 1, cost, tuple)` bucketed by row (`offs`), duplicates included.
    offs: Vec<usize>,
    edges: Vec<(usize, f64, usize)>,
    /// The cheapest edge per (row, report) in CSR, and its tuple.
    m_offs: Vec<usize>,
    m_cols: Vec<usize>,
    m_vals: Vec<f64>,
    m_tuple: Vec<usize>,
    /// Per report: its position in `m_*` within the row being deduplicated, else `NONE`.
    slot: Vec<usize>,
    a: Vec<f64>,
    b: Vec<f64>,
    /// The stage's result per old row: report taken (0 = none, `DEAD` = row dropped) and
    /// the new prefix id; per report, the new prefix id it starts (`DEAD` if none).
    next_report: Vec<usize>,
    next_id: Vec<usize>,
    zero_start: Vec<usize>,
    lap: SparseSolver,
}

impl Stage {
    /// Assigns the prefixes to the reports of sensor `s`; returns the best tuple of each new
    /// prefix and leaves the old → new prefix map in `next_*` and `zero_start`.
    fn run(
        &mut self,
        problem: &SdProblem,
        mult: &[Vec<f64>],
        s: usize,
        live: &[(usize, usize)],
        n_rows: usize,
    ) -> Vec<usize> {
        self.costs(problem, mult, s, live, n_rows);
        let n = problem.sizes()[s];
        // Options costing >= 0 are never taken: dropping the prefix (or report) costs 0.
        self.a.clear();
        self.a.extend(self.rows.iter().map(|r| r.0.min(0.0)));
        self.b.clear();
        self.b.extend(self.cols.iter().map(|c| c.0.min(0.0)));
        let parts = (
            std::mem::take(&mut self.m_offs),
            std::mem::take(&mut self.m_cols),
            std::mem::take(&mut self.m_vals),
        );
        let matrix = SparseCosts::from_csr_unchecked(n_rows, n, parts.0, parts.1, parts.2);
        let sol = self.lap.solve(&matrix, &self.a, &self.b);
        (self.m_offs, self.m_cols, self.m_vals) = matrix.into_parts();
        let mut best = Vec::new();
        self.next_report.clear();
        self.next_id.clear();
        for (r, c) in sol.row_to_col.iter().enumerate() {
            let (report, k) = match *c {
                Some(c) => {
                    // The solver only assigns stored pairs, so the search always succeeds.
                    let span = self.m_offs[r]..self.m_offs[r + 1];
                    let p = span
                        .clone()
                        .find(|&p| self.m_cols[p] == c)
                        .unwrap_or(span.start);
                    (c + 1, self.m_tuple[p])
                }
                None if self.a[r] < 0.0 => (0, self.rows[r].1),
                None => (DEAD, NONE),
            };
            self.next_report.push(report);
            self.next_id
                .push(if report == DEAD { DEAD } else { best.len() });
            if report != DEAD {
                best.push(k);
            }
        }
        self.zero_start.clear();
        self.zero_start.resize(n, DEAD);
        for c in (0..n).filter(|&c| sol.col_to_row[c].is_none() && self.b[c] < 0.0) {
            self.zero_start[c] = best.len();
            best.push(self.cols[c].1);
        }
        best
    }

    /// Candidate costs of the stage: per (prefix, report) edge, per prefix "continue with 0",
    /// per report "start a new all-zero prefix"; each keeps its cheapest tuple (ties: lower
    /// index). Edges are bucketed by row with a counting sort, then deduplicated per row.
    fn costs(
        &mut self,
        problem: &SdProblem,
        mult: &[Vec<f64>],
        s: usize,
        live: &[(usize, usize)],
        n_rows: usize,
    ) {
        let n = problem.sizes()[s];
        self.rows.clear();
        self.rows.resize(n_rows, EMPTY);
        self.cols.clear();
        self.cols.resize(n, EMPTY);
        self.cost.resize(live.len(), 0.0);
        self.offs.clear();
        self.offs.resize(n_rows + 1, 0);
        for (pos, &(k, r)) in live.iter().enumerate() {
            let i = problem.tuple(k)[s];
            if r == ZERO && i == 0 {
                continue;
            }
            let c = modified(problem, mult, k, s + 1);
            match r {
                ZERO => keep_min(&mut self.cols[i - 1], (c, k)),
                r if i == 0 => keep_min(&mut self.rows[r], (c, k)),
                r => {
                    self.offs[r + 1] += 1;
                    self.cost[pos] = c;
                }
            }
        }
        for r in 0..n_rows {
            self.offs[r + 1] += self.offs[r];
        }
        self.edges.resize(self.offs[n_rows], (0, 0.0, 0));
        let mut fill = self.offs.clone();
        for (pos, &(k, r)) in live.iter().enumerate() {
            let i = problem.tuple(k)[s];
            if r != ZERO && i > 0 {
                self.edges[fill[r]] = (i - 1, self.cost[pos], k);
                fill[r] += 1;
            }
        }
        self.dedup(n_rows, n);
    }

    /// Keeps the cheapest edge per (row, report) in `m_*`.
    fn dedup(&mut self, n_rows: usize, n: usize) {
        self.slot.clear();
        self.slot.resize(n, NONE);
        self.m_offs.clear();
        self.m_cols.clear();
        self.m_vals.clear();
        self.m_tuple.clear();
        self.m_offs.push(0);
        for r in 0..n_rows {
            let start = self.m_cols.len();
            for &(c, v, k) in &self.edges[self.offs[r]..self.offs[r + 1]] {
                match self.slot[c] {
                    NONE => {
                        self.slot[c] = self.m_cols.len();
                        self.m_cols.push(c);
                        self.m_vals.push(v);
                        self.m_tuple.push(k);
                    }
                    p => {
                        let mut best = (self.m_vals[p], self.m_tuple[p]);
                        keep_min(&mut best, (v, k));
                        (self.m_vals[p], self.m_tuple[p]) = best;
                    }
                }
            }
            for &c in &self.m_cols[start..] {
                self.slot[c] = NONE;
            }
            self.m_offs.push(self.m_cols.len());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assign::test_support::{random_keep, random_multipliers, random_problem};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Filtering ([`Recovery::retain`]) builds what [`Recovery::new`] builds for the smaller
    /// problem: the same pairs and scan order, and from the same relaxed solutions and
    /// multipliers the same recovered solutions, and the same polish.
    #[test]
    fn retain_builds_what_new_builds_for_the_smaller_problem() {
        let mut rng = ChaCha8Rng::seed_from_u64(29);
        let mut recovered = 0;
        for seed in 0..60u64 {
            let s = 3 + seed as usize % 3;
            let p = random_problem(seed, s, 6, 4, 20);
            let (keep, kept) = random_keep(&mut rng, &p, 0.6);
            let q = p.with_active(kept.clone());
            let mut filtered = Recovery::new(&p);
            filtered.retain(&keep);
            let mut fresh = Recovery::new(&q);
            assert_eq!(filtered.pair_offs, fresh.pair_offs, "seed {seed}");
            assert_eq!(filtered.pair_members, fresh.pair_members, "seed {seed}");
            assert_eq!(filtered.unpaired, fresh.unpaired, "seed {seed}");
            for &k in &kept {
                assert_eq!(filtered.pair[k], fresh.pair[k], "seed {seed}");
            }
            let (a, b) = (filtered.search.ranked(), fresh.search.ranked());
            assert_eq!(
                (&a.by_cost, &a.flat, &a.cost),
                (&b.by_cost, &b.flat, &b.cost)
            );
            for &k in &kept {
                assert_eq!(a.rank_of[k], b.rank_of[k]);
            }
            for _ in 0..4 {
                let mult = random_multipliers(&mut rng, &p, 4.0);
                // A relaxed solution: kept tuples taken greedily with no shared report of
                // sensors 0 and 1 (sensors 2.. are the relaxed ones).
                let mut used = [vec![false; p.sizes()[0] + 1], vec![false; p.sizes()[1] + 1]];
                let mut relaxed = Vec::new();
                for &k in kept.iter().filter(|_| rng.random_bool(0.5)) {
                    let t = p.tuple(k);
                    if (t[0] == 0 || !used[0][t[0]]) && (t[1] == 0 || !used[1][t[1]]) {
                        (used[0][t[0]], used[1][t[1]]) = (t[0] > 0, t[1] > 0);
                        relaxed.push(k);
                    }
                }
                let got = filtered.primal(&q, &mult, &relaxed);
                assert_eq!(got, fresh.primal(&q, &mult, &relaxed), "seed {seed}");
                if let Some((chosen, _)) = got {
                    recovered += 1;
                    assert_eq!(filtered.polish(&q, &chosen), fresh.polish(&q, &chosen));
                }
            }
        }
        assert!(recovered > 100, "{recovered}");
    }
}
