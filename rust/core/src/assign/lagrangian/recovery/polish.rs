//! Ejection-chain polish of the Lagrangian's final solution.
//!
//! The per-iteration swap search ([`super::search`]) only makes moves that pay for themselves
//! at once: bring in a tuple cheaper than the chosen tuples it conflicts with. Two crossed
//! associations, `(1, 14, 2) + (4, 5, 12)` against `(1, 5, 12) + (4, 14, 2)`, need a move that
//! first loses (bring in one tuple, evict two) and then wins back more (refill the reports the
//! evicted tuples freed). This module makes that compound move: bring in `a`, evict its
//! conflicts `C`, then greedily add the cheapest tuples that fit the freed reports; keep it if
//! the whole is cheaper. When asked (`LagrangianOptions::with_polish`), it runs once per
//! solve, on the best solution found.
//!
//! A refill tuple may only use reports that are free or owned by `C`, so the candidates are
//! the tuples whose set of chosen owners is a non-empty subset of `C`. Tuples are indexed by
//! that owner set, so a move looks up at most 2^|C| − 1 short lists instead of scanning every
//! tuple through the freed reports (hundreds per report on large scans); the index changes
//! only when a move is applied, which is rare. Before that lookup, a floor on what the refill
//! can cost, read from a price per report (`Polish::price_reports`), rejects the moves that
//! cannot pay: at five sensors most of them, with their hundreds of candidates.

use crate::assign::csr::csr;
use crate::assign::SdProblem;
use rustc_hash::FxHashMap;

use super::ranked::Ranked;

const NONE: usize = usize::MAX;

/// Moves whose tuple conflicts with more chosen tuples than this are skipped: a move looks up
/// 2^|C| − 1 owner sets, and |C| can reach the number of sensors.
const MAX_CONFLICTS: usize = 6;

/// The polished solution (ascending) and its cost; never costlier than `chosen` (beyond
/// round-off in the sum), which must be feasible.
#[cfg(test)]
fn polish(problem: &SdProblem, chosen: &[usize]) -> (Vec<usize>, f64) {
    polish_ranked(problem, &Ranked::new(problem), chosen)
}

/// [`polish`] in the scan order `ranked` of `problem` (the per-iteration search's). `chosen`
/// must be feasible and hold active tuples only (those have a rank), as every solution the
/// Lagrangian keeps does.
pub(super) fn polish_ranked(
    problem: &SdProblem,
    ranked: &Ranked,
    chosen: &[usize],
) -> (Vec<usize>, f64) {
    let start: f64 = chosen.iter().map(|&k| problem.costs()[k]).sum();
    let tol = 1e-12 * start.abs().max(1.0);
    let mut state = Polish::new(problem, ranked, chosen);
    // First improvement, in ascending cost: a full pass, then passes over the tuples whose
    // reports changed owner in the pass before, until one changes nothing. (Not a fixpoint:
    // a move can also gain through a conflict's refill list changing; catching that would
    // take a full pass per round.) Every applied move lowers the cost by more than `tol`, so
    // the loop ends.
    loop {
        let mut moved = false;
        let todo: Vec<usize> = (state.ranked.by_cost)
            .iter()
            .copied()
            .filter(|&k| state.dirty[k])
            .collect();
        state.dirty.fill(false);
        for a in todo {
            moved |= state.try_move(a, tol);
        }
        if !moved {
            break;
        }
    }
    let out: Vec<usize> = (0..problem.n_tuples())
        .filter(|&k| state.chosen[k])
        .collect();
    let total = out.iter().map(|&k| problem.costs()[k]).sum();
    (out, total)
}

/// The polish's indexes and current solution. Candidates of a move are handled as ranks
/// (positions in the scan order), whose costs and reports lie in flat arrays, so the refill's
/// sort compares plain integers and its fit tests read contiguous memory.
struct Polish<'p> {
    problem: &'p SdProblem,
    /// The scan order, with costs and reports by rank; its `missed` slot is never owned nor
    /// used.
    ranked: &'p Ranked,
    /// Per flat report ([`SdProblem::flat_reports`]): the active tuples using it (CSR).
    inc_offs: Vec<usize>,
    inc: Vec<usize>,
    /// Per flat report: the chosen tuple using it; per tuple: whether chosen.
    owner: Vec<usize>,
    chosen: Vec<bool>,
    /// The ranks of the unchosen active tuples by their sorted set of chosen owners (never
    /// empty). A list keeps the order in which its tuples were added.
    by_owners: FxHashMap<Vec<usize>, Vec<usize>>,
    /// Tuples to look at in the next pass: those whose reports changed owner in this one.
    dirty: Vec<bool>,
    /// Buffers of one move: conflicts and keys are tuples, candidates and refill ranks.
    conflicts: Vec<usize>,
    key: Vec<usize>,
    candidates: Vec<usize>,
    refill: Vec<usize>,
    used: Vec<bool>,
    /// One bit per rank, all clear between moves: [`ascending`]'s scratch.
    bits: Vec<u64>,
    /// Per flat report owned by a chosen tuple: the least `cost / owned` over the unchosen
    /// tuples using it, `owned` being how many of a tuple's reports chosen tuples own
    /// ([`Polish::price_reports`]); 0 for the others.
    price: Vec<f64>,
}

impl<'p> Polish<'p> {
    fn new(problem: &'p SdProblem, ranked: &'p Ranked, chosen: &[usize]) -> Self {
        let n_reports = problem.n_reports();
        let pairs = problem
            .active()
            .iter()
            .flat_map(|&k| problem.flat_reports(k).map(move |r| (r, k)));
        let (inc_offs, inc) = csr(n_reports, pairs);
        let mut state = Self {
            problem,
            ranked,
            inc_offs,
            inc,
            owner: vec![NONE; n_reports + 1],
            chosen: vec![false; problem.n_tuples()],
            by_owners: FxHashMap::default(),
            dirty: vec![true; problem.n_tuples()],
            conflicts: Vec::new(),
            key: Vec::new(),
            candidates: Vec::new(),
            refill: Vec::new(),
            used: vec![false; n_reports + 1],
            bits: vec![0; ranked.cost.len().div_ceil(64)],
            price: vec![0.0; n_reports + 1],
        };
        for &k in chosen {
            debug_assert!(ranked.rank_of[k] != NONE, "tuple {k} is not active");
            state.set_chosen(k, true);
        }
        state.price_reports();
        for &k in &ranked.by_cost {
            state.index(k, true);
        }
        state
    }

    /// Prices the owned reports for the refill floor of [`Polish::try_move`]. A refill tuple's
    /// owned reports are all freed by the move's conflicts (its owners are among them) and
    /// none is `a`'s (it fits beside `a`), and the refill's tuples share no report. So
    /// spreading each refill tuple's cost over its owned reports, and taking at each freed
    /// report the least such share any unchosen tuple has there, bounds the refill's cost from
    /// below by the sum over the freed reports. Ownership changes only when a move is applied,
    /// which is rare: then this runs again.
    fn price_reports(&mut self) {
        self.price.fill(f64::INFINITY);
        let (ranked, owner) = (self.ranked, &self.owner);
        for (r, &k) in ranked.by_cost.iter().enumerate() {
            let owned = |f: &&usize| **f != ranked.missed && owner[**f] != NONE;
            let reports = ranked.reports(r);
            let n = reports.iter().filter(owned).count();
            if self.chosen[k] || n == 0 {
                continue;
            }
            let share = ranked.cost[r] / n as f64;
            for &f in reports.iter().filter(owned) {
                self.price[f] = self.price[f].min(share);
            }
        }
        // Only the negative shares can lower a refill's cost.
        self.price.iter_mut().for_each(|p| *p = p.min(0.0));
    }

    /// The least a refill beside `a` can cost ([`Polish::price_reports`]): the prices of the
    /// conflicts' reports that `a` does not use.
    fn refill_floor(&self, a: usize) -> f64 {
        let (ranked, mine) = (self.ranked, self.ranked.reports(self.ranked.rank_of[a]));
        let mut floor = 0.0;
        for &c in &self.conflicts {
            for &f in ranked.reports(ranked.rank_of[c]) {
                if f != ranked.missed && !mine.contains(&f) {
                    floor += self.price[f];
                }
            }
        }
        floor
    }

    /// Makes `k` chosen, the owner of its reports, or unchosen and its reports free.
    fn set_chosen(&mut self, k: usize, chosen: bool) {
        self.chosen[k] = chosen;
        let value = if chosen { k } else { NONE };
        for &f in self.ranked.reports(self.ranked.rank_of[k]) {
            if f != self.ranked.missed {
                self.owner[f] = value;
            }
        }
    }

    /// Distinct chosen owners of `k`'s reports, sorted, into `key`.
    fn owners_into_key(&mut self, k: usize) {
        self.key.clear();
        for &f in self.ranked.reports(self.ranked.rank_of[k]) {
            let o = self.owner[f];
            if o != NONE && !self.key.contains(&o) {
                self.key.push(o);
            }
        }
        self.key.sort_unstable();
    }

    /// Adds unchosen `k` to (or removes it from) the list of its current owner set.
    fn index(&mut self, k: usize, add: bool) {
        if self.chosen[k] {
            return;
        }
        self.owners_into_key(k);
        if self.key.is_empty() {
            return;
        }
        let r = self.ranked.rank_of[k];
        match self.by_owners.get_mut(self.key.as_slice()) {
            Some(list) if add => list.push(r),
            Some(list) => {
                if let Some(at) = list.iter().position(|&x| x == r) {
                    list.swap_remove(at);
                }
            }
            None if add => {
                self.by_owners.insert(self.key.clone(), vec![r]);
            }
            None => {}
        }
    }

    /// Tries the compound move that brings in unchosen tuple `a`; true if applied.
    fn try_move(&mut self, a: usize, tol: f64) -> bool {
        if self.chosen[a] {
            return false;
        }
        self.owners_into_key(a);
        std::mem::swap(&mut self.conflicts, &mut self.key);
        if self.conflicts.len() > MAX_CONFLICTS {
            return false;
        }
        let costs = self.problem.costs();
        let mut delta = costs[a] - self.conflicts.iter().map(|&c| costs[c]).sum::<f64>();
        // A floor on the refill that needs no candidates: at five sensors it rejects most
        // moves before their hundreds of candidates are gathered and sorted. The slack keeps
        // a rounding of the floor's sum from rejecting a move the refill would keep.
        let floor = self.refill_floor(a);
        let scale = costs[a].abs() + self.conflicts.iter().map(|&c| costs[c].abs()).sum::<f64>();
        if delta + floor >= -tol + 1e-9 * (scale - floor) {
            return false;
        }
        self.gather_candidates(a);
        // The refill is a subset of the candidates, so their negative costs bound what it can
        // win too. Past the floor above this rarely decides, but it is one pass over them.
        let bound: f64 = self
            .candidates
            .iter()
            .map(|&b| self.ranked.cost[b].min(0.0))
            .sum();
        if delta + bound >= -tol {
            return false;
        }
        delta += self.plan_refill(a);
        let keep = delta < -tol;
        if keep {
            self.apply(a);
        } else {
            self.unmark(a);
        }
        keep
    }

    /// The ranks of the unchosen tuples (other than `a`) whose chosen owners are a non-empty
    /// subset of the conflicts, into `candidates`.
    fn gather_candidates(&mut self, a: usize) {
        self.candidates.clear();
        let n = self.conflicts.len();
        let rank_a = self.ranked.rank_of[a];
        for mask in 1..(1usize << n) {
            // A subset of the sorted conflicts is sorted too.
            self.key.clear();
            self.key.extend(
                (0..n)
                    .filter(|b| mask >> b & 1 == 1)
                    .map(|b| self.conflicts[b]),
            );
            if let Some(list) = self.by_owners.get(self.key.as_slice()) {
                self.candidates
                    .extend(list.iter().filter(|&&b| b != rank_a));
            }
        }
    }

    /// Sets the `used` mark of rank `r`'s reports.
    fn mark(&mut self, r: usize, value: bool) {
        for &f in self.ranked.reports(r) {
            if f != self.ranked.missed {
                self.used[f] = value;
            }
        }
    }

    /// Greedily picks, cheapest first (ties by index: by rank), the candidates that fit
    /// beside `a` and each other, into `refill`; returns their summed cost. Leaves `used`
    /// marking the reports of `a` and of the refill.
    fn plan_refill(&mut self, a: usize) -> f64 {
        self.mark(self.ranked.rank_of[a], true);
        ascending(&mut self.candidates, &mut self.bits);
        self.refill.clear();
        let mut added = 0.0;
        for at in 0..self.candidates.len() {
            let b = self.candidates[at];
            if self.ranked.reports(b).iter().all(|&f| !self.used[f]) {
                self.mark(b, true);
                self.refill.push(b);
                added += self.ranked.cost[b];
            }
        }
        added
    }

    /// Clears the `used` marks of `a` and the planned refill.
    fn unmark(&mut self, a: usize) {
        self.mark(self.ranked.rank_of[a], false);
        for at in 0..self.refill.len() {
            self.mark(self.refill[at], false);
        }
    }

    /// Evicts the conflicts, brings in `a` and the refill, and re-indexes every tuple whose
    /// owner set changed (those sharing a report with a tuple that moved).
    fn apply(&mut self, a: usize) {
        self.unmark(a);
        let added: Vec<usize> = std::iter::once(a)
            .chain(self.refill.iter().map(|&b| self.ranked.by_cost[b]))
            .collect();
        let evicted = std::mem::take(&mut self.conflicts);
        let mut touched = Vec::new();
        for &k in added.iter().chain(&evicted) {
            for r in self.problem.flat_reports(k) {
                touched.extend_from_slice(&self.inc[self.inc_offs[r]..self.inc_offs[r + 1]]);
            }
        }
        touched.sort_unstable();
        touched.dedup();
        for &k in &touched {
            self.index(k, false);
        }
        evicted.into_iter().for_each(|c| self.set_chosen(c, false));
        added.into_iter().for_each(|k| self.set_chosen(k, true));
        for &k in &touched {
            self.index(k, true);
            self.dirty[k] = true;
        }
        self.price_reports();
    }
}

/// Puts `ranks` (distinct, each below `64 · bits.len()`) in ascending order: a short list by
/// sorting, a longer one by setting a bit per rank in `bits` (all clear on entry, and again on
/// return) and reading them back in order. The refill's lists run to hundreds of ranks at five
/// sensors, where sorting them was 9 % of the instructions of `python3
/// benches/bench_associate_scans.py --sensors 5 --scans 40` under callgrind.
fn ascending(ranks: &mut Vec<usize>, bits: &mut [u64]) {
    const SORTED_UP_TO: usize = 32;
    if ranks.len() <= SORTED_UP_TO {
        ranks.sort_unstable();
        return;
    }
    let (mut low, mut high) = (usize::MAX, 0);
    for &r in ranks.iter() {
        bits[r / 64] |= 1 << (r % 64);
        (low, high) = (low.min(r / 64), high.max(r / 64));
    }
    ranks.clear();
    for (w, word) in bits.iter_mut().enumerate().take(high + 1).skip(low) {
        let mut set = std::mem::take(word);
        while set != 0 {
            ranks.push(w * 64 + set.trailing_zeros() as usize);
            set &= set - 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assign::test_support::{brute_force, random_problem};

    /// The cheapest tuples first, each kept if it fits: a feasible, often poor start.
    fn greedy(p: &SdProblem) -> Vec<usize> {
        let mut order = p.active().to_vec();
        order.sort_by(|&x, &y| p.costs()[x].total_cmp(&p.costs()[y]));
        let mut chosen: Vec<usize> = Vec::new();
        for k in order {
            chosen.push(k);
            if p.evaluate(&chosen).is_err() {
                chosen.pop();
            }
        }
        chosen
    }

    /// Both paths of [`ascending`] give the sorted list, over short and long lists of ranks
    /// packed close together or spread wide, and leave the bits clear for the next call.
    #[test]
    fn ascending_sorts_short_and_long_lists_and_clears_its_bits() {
        use rand::{seq::SliceRandom, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut bits = vec![0u64; 20_000usize.div_ceil(64)];
        let mut long = 0;
        for (len, span) in [
            (0, 10),
            (1, 10),
            (5, 40),
            (32, 40),
            (33, 40),
            (300, 320),
            (500, 20_000),
        ] {
            for _ in 0..20 {
                let mut pool: Vec<usize> = (0..span).collect();
                pool.shuffle(&mut rng);
                let mut ranks = pool[..len].to_vec();
                let mut expected = ranks.clone();
                expected.sort_unstable();
                ascending(&mut ranks, &mut bits);
                assert_eq!(ranks, expected, "{len} ranks below {span}");
                assert!(bits.iter().all(|&w| w == 0));
                long += usize::from(len > 32);
            }
        }
        assert_eq!(long, 60, "the bit path ran");
    }

    /// The refill floor is never above what a move's refill costs, from every move of
    /// greedy starts on random problems of three to five sensors; and it decides some moves
    /// (a floor of zero would pass the first assertion too).
    #[test]
    fn the_refill_floor_never_exceeds_a_refill() {
        let (mut moves, mut decided) = (0, 0);
        for seed in 0..150 {
            let p = random_problem(seed, 3 + seed as usize % 3, 5, 4, 30);
            let ranked = Ranked::new(&p);
            let mut state = Polish::new(&p, &ranked, &greedy(&p));
            for &a in &ranked.by_cost {
                state.owners_into_key(a);
                std::mem::swap(&mut state.conflicts, &mut state.key);
                if state.chosen[a] || state.conflicts.len() > MAX_CONFLICTS {
                    continue;
                }
                let floor = state.refill_floor(a);
                state.gather_candidates(a);
                let refill = state.plan_refill(a);
                state.unmark(a);
                assert!(
                    refill >= floor - 1e-12 * floor.abs(),
                    "seed {seed}, tuple {a}: refill {refill} below its floor {floor}"
                );
                let delta =
                    p.costs()[a] - state.conflicts.iter().map(|&c| p.costs()[c]).sum::<f64>();
                moves += 1;
                decided += usize::from(delta + floor >= 0.0);
            }
        }
        assert!(
            moves > 2_000 && decided > moves / 10,
            "{decided} of {moves} moves decided"
        );
    }

    #[test]
    fn undoes_a_crossed_pair_the_swap_search_cannot() {
        // (1,1,1) + (2,2,2) at -6 each; the crossed (1,2,2) + (2,1,1) at -7 each. Bringing in
        // either crossed tuple alone evicts both chosen ones: -7 against -12, a loss.
        let tuples = vec![1, 1, 1, 2, 2, 2, 1, 2, 2, 2, 1, 1];
        let p = SdProblem::new(tuples, 3, vec![-6.0, -6.0, -7.0, -7.0], vec![2, 2, 2]).unwrap();
        assert_eq!(polish(&p, &[0, 1]), (vec![2, 3], -14.0));
    }

    #[test]
    fn stays_feasible_and_never_worsens() {
        let mut improved = 0;
        for seed in 0..200 {
            let p = random_problem(seed, 3 + seed as usize % 2, 4, 3, 10);
            let start = greedy(&p);
            let before = p.evaluate(&start).unwrap();
            let (after, cost) = polish(&p, &start);
            assert_eq!(p.evaluate(&after), Ok(cost), "seed {seed}");
            // Summed in another order than `evaluate`'s: equal up to round-off at worst.
            assert!(
                cost <= before + 1e-12 * before.abs(),
                "seed {seed}: {cost} > {before}"
            );
            assert!(cost >= brute_force(&p) - 1e-9, "seed {seed}");
            improved += usize::from(cost < before - 1e-9);
        }
        assert!(
            improved > 0,
            "no start was improved: the test exercises nothing"
        );
    }
}
