//! The swap local search that polishes the Lagrangian's candidate solutions.
//!
//! It runs on every candidate, once per subgradient iteration, over every active tuple, so it
//! is built for speed: tuples are renumbered by scan order ("rank") with their reports laid
//! out flat, a quick bound rejects most tuples without looking at their conflicts, and passes
//! after the first visit only tuples whose neighbourhood changed.

use super::ranked::Ranked;
use crate::assign::csr::csr;
use crate::assign::SdProblem;

const NONE: usize = usize::MAX;

/// Local search state for one problem, reused across calls. It works on ranks (positions in
/// `by_cost`), so the data of the scan lies contiguous in scan order.
pub(super) struct Search {
    /// The scan order, with costs and reports by rank; the `missed` slot is never owned.
    ranked: Ranked,
    /// Per flat report: the ranks of the tuples using it (CSR).
    inc_offs: Vec<usize>,
    inc: Vec<usize>,
    /// Per flat report: the chosen rank using it, or `NONE`.
    owner: Vec<usize>,
    /// Per flat report: its owner's cost, `-inf` when free (and for the `missed` slot).
    owner_cost: Vec<f64>,
    /// Work lists of the swap passes as bit sets over ranks: this pass, and the next.
    now: Vec<u64>,
    next: Vec<u64>,
    any_next: bool,
    conflicts: Vec<usize>,
}

impl Search {
    pub(super) fn new(problem: &SdProblem) -> Self {
        Self::of(Ranked::new(problem))
    }

    /// [`Search::new`] of the problem without the tuples `keep` rejects (per tuple index),
    /// from this search's order ([`Ranked::retain`]).
    pub(super) fn retain(&mut self, keep: &[bool]) {
        let mut ranked = std::mem::replace(&mut self.ranked, Ranked::empty());
        ranked.retain(keep);
        *self = Self::of(ranked);
    }

    fn of(ranked: Ranked) -> Self {
        let (s, missed) = (ranked.s, ranked.missed);
        let reports = ranked.flat.iter().enumerate().filter(|e| *e.1 != missed);
        let (inc_offs, inc) = csr(missed, reports.map(|(at, &f)| (f, at / s)));
        let n = ranked.by_cost.len();
        Self {
            ranked,
            inc_offs,
            inc,
            owner: vec![NONE; missed + 1],
            owner_cost: vec![f64::NEG_INFINITY; missed + 1],
            now: vec![0; n.div_ceil(64)],
            next: vec![0; n.div_ceil(64)],
            any_next: false,
            conflicts: Vec::with_capacity(s),
        }
    }

    /// The scan order this search works in (the polish works in it too).
    pub(super) fn ranked(&self) -> &Ranked {
        &self.ranked
    }

    /// Swap local search from `chosen` (`None` if it is infeasible): bring in any tuple that
    /// is cheaper than the chosen tuples it conflicts with (none: a plain addition), scanning
    /// by ascending cost, until no such tuple is left. Each move strictly lowers the cost, so
    /// it terminates; it catches what the stage-by-stage recovery cannot see. Returns the
    /// solution (ascending) and its cost.
    pub(super) fn improve(
        &mut self,
        problem: &SdProblem,
        chosen: &[usize],
    ) -> Option<(Vec<usize>, f64)> {
        let feasible = self.load(chosen);
        let total: f64 = chosen.iter().map(|&k| problem.costs()[k]).sum();
        let tol = 1e-12 * total.abs().max(1.0);
        if feasible {
            // The first pass looks at every tuple, in scan order.
            let mut from = 0;
            while let Some(rank) = self.find_move(from, tol) {
                self.apply(rank, false);
                from = rank + 1;
            }
            self.swap_passes(tol);
        }
        let ranks = self.chosen_ranks();
        // Leave the buffers clean for the next call.
        self.owner.fill(NONE);
        self.owner_cost.fill(f64::NEG_INFINITY);
        let mut result: Vec<usize> = ranks.iter().map(|&r| self.ranked.by_cost[r]).collect();
        result.sort_unstable();
        feasible.then(|| {
            let cost = result.iter().map(|&k| problem.costs()[k]).sum();
            (result, cost)
        })
    }

    /// The chosen ranks, ascending.
    fn chosen_ranks(&self) -> Vec<usize> {
        let mut ranks: Vec<usize> = self.owner.iter().copied().filter(|&r| r != NONE).collect();
        ranks.sort_unstable();
        ranks.dedup();
        ranks
    }

    /// Swap passes after the first: only tuples with a report whose owner changed since they
    /// were last looked at, in scan order (all others would be rejected again), so this ends
    /// where repeating the full scan until nothing changes would, at a fraction of the cost.
    fn swap_passes(&mut self, tol: f64) {
        while self.any_next {
            std::mem::swap(&mut self.now, &mut self.next);
            self.any_next = false;
            let mut w = 0;
            // Bits set during the pass lie after the current rank, so one sweep finds them.
            while w < self.now.len() {
                if self.now[w] == 0 {
                    w += 1;
                    continue;
                }
                let bit = self.now[w].trailing_zeros() as usize;
                self.now[w] &= !(1 << bit);
                self.try_move(w * 64 + bit, tol);
            }
        }
    }

    /// Brings in `rank` if that lowers the cost by more than `tol`.
    fn try_move(&mut self, rank: usize, tol: f64) {
        let fl = self.ranked.reports(rank);
        if self.helps(self.ranked.cost[rank], fl, tol) {
            self.apply(rank, true);
        }
    }

    /// The first rank from `from` on whose move helps. This is the hot loop of the search,
    /// so common sensor counts get a copy with the count known at compile time (unrolled).
    fn find_move(&self, from: usize, tol: f64) -> Option<usize> {
        match self.ranked.s {
            3 => self.find_move_n::<3>(from, tol),
            4 => self.find_move_n::<4>(from, tol),
            5 => self.find_move_n::<5>(from, tol),
            _ => self.find_move_n::<0>(from, tol),
        }
    }

    /// [`Search::find_move`] for `S` sensors (0: any).
    fn find_move_n<const S: usize>(&self, from: usize, tol: f64) -> Option<usize> {
        let s = if S == 0 { self.ranked.s } else { S };
        let tail = self.ranked.cost[from..]
            .iter()
            .zip(self.ranked.flat[from * s..].chunks_exact(s));
        for (at, (&cost, fl)) in tail.enumerate() {
            if self.helps(cost, fl, tol) {
                return Some(from + at);
            }
        }
        None
    }

    /// Whether a tuple of cost `cost` and reports `fl` is cheaper by more than `tol` than the
    /// distinct chosen tuples it conflicts with. A chosen tuple conflicts only with itself,
    /// so it never is.
    #[inline(always)]
    fn helps(&self, cost: f64, fl: &[usize], tol: f64) -> bool {
        // Quick reject: the freed cost is a sum of negative owner costs, so it is at most the
        // largest of them (0 with no owner). Most tuples fail here.
        let most = fl
            .iter()
            .fold(f64::NEG_INFINITY, |m, &f| m.max(self.owner_cost[f]));
        let most = if most == f64::NEG_INFINITY { 0.0 } else { most };
        if cost >= most - tol {
            return false;
        }
        let mut freed = 0.0;
        for (at, &f) in fl.iter().enumerate() {
            let o = self.owner[f];
            if o != NONE && fl[..at].iter().all(|&g| self.owner[g] != o) {
                freed += self.ranked.cost[o];
            }
        }
        cost < freed - tol
    }

    /// Brings in `rank`, evicting its conflicts, and queues the tuples whose reports changed
    /// owner: still in this pass if after `rank` (only when `queue_now`: the first pass scans
    /// everything anyway), else in the next. Rare next to `helps`, so kept out of its loop.
    #[inline(never)]
    fn apply(&mut self, rank: usize, queue_now: bool) {
        self.conflicts.clear();
        for &f in self.ranked.reports(rank) {
            let o = self.owner[f];
            if o != NONE && !self.conflicts.contains(&o) {
                self.conflicts.push(o);
            }
        }
        let conflicts = std::mem::take(&mut self.conflicts);
        for &j in &conflicts {
            self.set(j, NONE);
        }
        self.set(rank, rank);
        for &j in conflicts.iter().chain([&rank]) {
            self.queue_touching(j, rank, queue_now);
        }
        self.conflicts = conflicts;
    }

    /// Queues every tuple sharing a report with `j` (see [`Search::apply`]).
    fn queue_touching(&mut self, j: usize, rank: usize, queue_now: bool) {
        for &f in self.ranked.reports(j) {
            if f == self.ranked.missed {
                continue;
            }
            for &q in &self.inc[self.inc_offs[f]..self.inc_offs[f + 1]] {
                if q > rank {
                    if queue_now {
                        self.now[q / 64] |= 1 << (q % 64);
                    }
                } else {
                    self.next[q / 64] |= 1 << (q % 64);
                    self.any_next = true;
                }
            }
        }
    }

    /// Sets the owner of `rank`'s real reports to `value` (`NONE`: no longer chosen).
    fn set(&mut self, rank: usize, value: usize) {
        let cost = if value == NONE {
            f64::NEG_INFINITY
        } else {
            self.ranked.cost[value]
        };
        for &f in self.ranked.reports(rank) {
            if f != self.ranked.missed {
                self.owner[f] = value;
                self.owner_cost[f] = cost;
            }
        }
    }

    /// Marks `chosen` as the current solution; false if two of its tuples share a report.
    fn load(&mut self, chosen: &[usize]) -> bool {
        for &k in chosen {
            let rank = self.ranked.rank_of[k];
            for &f in self.ranked.reports(rank) {
                if f != self.ranked.missed {
                    if self.owner[f] != NONE {
                        return false;
                    }
                    self.owner[f] = rank;
                    self.owner_cost[f] = self.ranked.cost[rank];
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assign::test_support::{dense_problem, random_problem};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The search in its plain form: repeat the full scan by ascending cost until a pass
    /// changes nothing.
    fn plain(problem: &SdProblem, chosen: &[usize]) -> Vec<usize> {
        let c = problem.costs();
        let mut by_cost = problem.active().to_vec();
        by_cost.sort_by(|&a, &b| c[a].total_cmp(&c[b]).then(a.cmp(&b)));
        let mut owner: Vec<Vec<usize>> =
            problem.sizes().iter().map(|&n| vec![NONE; n + 1]).collect();
        let reports = |k: usize| (problem.tuple(k).iter().copied().enumerate()).filter(|e| e.1 > 0);
        let mut is_chosen = vec![false; problem.n_tuples()];
        for &k in chosen {
            reports(k).for_each(|(s, i)| owner[s][i] = k);
            is_chosen[k] = true;
        }
        let tol = 1e-12 * chosen.iter().map(|&k| c[k]).sum::<f64>().abs().max(1.0);
        let mut improved = true;
        while improved {
            improved = false;
            for &k in &by_cost {
                if is_chosen[k] {
                    continue;
                }
                let mut conflicts = Vec::new();
                for o in reports(k).map(|(s, i)| owner[s][i]) {
                    if o != NONE && !conflicts.contains(&o) {
                        conflicts.push(o);
                    }
                }
                if c[k] < conflicts.iter().map(|&j| c[j]).sum::<f64>() - tol {
                    for &j in &conflicts {
                        reports(j).for_each(|(s, i)| owner[s][i] = NONE);
                        is_chosen[j] = false;
                    }
                    reports(k).for_each(|(s, i)| owner[s][i] = k);
                    (is_chosen[k], improved) = (true, true);
                }
            }
        }
        (0..problem.n_tuples()).filter(|&k| is_chosen[k]).collect()
    }

    /// A random feasible subset of the active tuples.
    fn random_start(problem: &SdProblem, rng: &mut ChaCha8Rng) -> Vec<usize> {
        let mut used: Vec<Vec<bool>> = problem
            .sizes()
            .iter()
            .map(|&n| vec![false; n + 1])
            .collect();
        let mut start = Vec::new();
        for &k in problem.active() {
            let t = problem.tuple(k);
            if rng.random_bool(0.5) && t.iter().enumerate().all(|(s, &i)| i == 0 || !used[s][i]) {
                t.iter().enumerate().for_each(|(s, &i)| used[s][i] = i > 0);
                start.push(k);
            }
        }
        start
    }

    #[test]
    fn ends_where_the_plain_repeated_scan_ends() {
        for seed in 0..80u64 {
            let s = 3 + seed as usize % 4; // 3..=6: the unrolled scans and the generic one
            let p = if seed % 2 == 0 {
                random_problem(seed, s, 6, 4, 40)
            } else {
                dense_problem(seed, s, 5, 40)
            };
            let mut search = Search::new(&p);
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            for _ in 0..5 {
                let start = random_start(&p, &mut rng);
                let (got, cost) = search.improve(&p, &start).expect("the start is feasible");
                let want = plain(&p, &start);
                assert_eq!(got, want, "seed {seed}");
                assert_eq!(Ok(cost), p.evaluate(&want), "seed {seed}");
            }
        }
    }

    #[test]
    fn rejects_an_infeasible_start_and_stays_usable() {
        let p = SdProblem::new(vec![1, 1, 1, 1, 2, 0], 3, vec![-5.0, -3.0], vec![1, 2, 1]).unwrap();
        let mut search = Search::new(&p);
        assert_eq!(search.improve(&p, &[0, 1]), None);
        assert_eq!(search.improve(&p, &[1]), Some((vec![0], -5.0)));
    }
}
