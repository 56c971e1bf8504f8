//! The relaxed problem of the Lagrangian solver: given multipliers `u`, `L(u)` is a sparse 2-D
//! assignment between the reports of sensors 0 and 1 (see the parent module). The structure
//! is built once per solve; an evaluation is one pass over flat arrays plus one 2-D solve.

use super::options::{WarmStart, WARM_MIN_SIZE};
use super::reduced::{keep_min, EMPTY};
use crate::assign::lap::{SparseCosts, SparseSolver};
use crate::assign::SdProblem;

/// The fixed structure of the relaxed 2-D problem, built once per solve, and the buffers of
/// its per-iteration evaluation.
pub(super) struct Relaxation {
    /// Unique (sensor 0, sensor 1) report pairs, rows = sensor 0 reports − 1.
    pairs: SparseCosts,
    /// The active tuples in four groups: by pair (`pair_offs`, CSR over pair index, each
    /// pair's tuples ascending), then `(i0 > 0, 0, …)`, `(0, i1 > 0, …)` and `(0, 0, …)`;
    /// `ends` closes the groups.
    tuples: Vec<usize>,
    pair_offs: Vec<usize>,
    ends: [usize; 4],
    /// Per entry of `tuples`: its cost, and the positions in `flat` of its multipliers (one per
    /// sensor from 2 on), so the modified costs are one tight loop per iteration.
    cost: Vec<f64>,
    tail: Vec<usize>,
    /// The multipliers of sensors 2.. laid out flat: sensor `s` report `i` is at
    /// `mult_offs[s − 2] + i`.
    mult_offs: Vec<usize>,
    flat: Vec<f64>,
    /// Per row-only / column-only entry (from `ends[0]`): its sensor-0 / sensor-1 report − 1.
    lone: Vec<usize>,
    /// Per entry of `tuples`: cost minus its multipliers, this iteration.
    modified: Vec<f64>,
    /// Each pair's best tuple, each report's best lone tuple, and the "unassigned" costs
    /// handed to the 2-D solver.
    arg: Vec<usize>,
    rows: Vec<(f64, usize)>,
    cols: Vec<(f64, usize)>,
    a: Vec<f64>,
    b: Vec<f64>,
    lap: SparseSolver,
    /// Warm-start the 2-D solves (see [`WarmStart`]).
    warm: bool,
    /// The 2-D solve's row and column prices, for [`Relaxation::proven_out`].
    alpha: Vec<f64>,
    beta: Vec<f64>,
    /// The last evaluation's `L(u)` beyond its 2-D solve: the free `(0, 0, …)` tuples'
    /// negative modified costs and the multipliers' sum.
    constant: [f64; 2],
}

/// Relative margin by which a tuple's forced bound must exceed the incumbent before
/// [`Relaxation::proven_out`] names it: far above the rounding of the sums involved.
const PROOF_SLACK: f64 = 1e-9;

impl Relaxation {
    pub(super) fn new(problem: &SdProblem, warm_start: WarmStart) -> Self {
        let key = |k: usize| (problem.tuple(k)[0], problem.tuple(k)[1]);
        let pick = |f: &dyn Fn((usize, usize)) -> bool| {
            let active = problem.active().iter().copied();
            active.filter(|&k| f(key(k))).collect::<Vec<_>>()
        };
        let mut tuples = pick(&|(a, b)| a > 0 && b > 0);
        // By pair, each pair's tuples in index order (the index makes every key distinct).
        tuples.sort_unstable_by_key(|&k| (key(k), k));
        let (n0, n1) = (problem.sizes()[0], problem.sizes()[1]);
        let (mut row_offs, mut cols, mut pair_offs) = (vec![0; n0 + 1], Vec::new(), Vec::new());
        for (at, &k) in tuples.iter().enumerate() {
            if at == 0 || key(tuples[at - 1]) != key(k) {
                row_offs[key(k).0] += 1;
                cols.push(key(k).1 - 1);
                pair_offs.push(at);
            }
        }
        pair_offs.push(tuples.len()); // one start per pair, then the end
        for r in 0..n0 {
            row_offs[r + 1] += row_offs[r];
        }
        let mut ends = [tuples.len(); 4];
        tuples.extend(pick(&|(a, b)| a > 0 && b == 0));
        ends[1] = tuples.len();
        tuples.extend(pick(&|(a, b)| a == 0 && b > 0));
        ends[2] = tuples.len();
        tuples.extend(pick(&|(a, b)| a == 0 && b == 0));
        ends[3] = tuples.len();
        let mut mult_offs = vec![0];
        for &n in &problem.sizes()[2..] {
            mult_offs.push(mult_offs.last().copied().unwrap_or(0) + n + 1);
        }
        let lone = (ends[0]..ends[2])
            .map(|x| problem.tuple(tuples[x])[usize::from(x >= ends[1])] - 1)
            .collect();
        let tail = (tuples.iter())
            .flat_map(|&k| problem.tuple(k)[2..].iter().zip(&mult_offs))
            .map(|(&i, &off)| off + i)
            .collect();
        Self {
            pairs: SparseCosts::from_csr_unchecked(
                n0,
                n1,
                row_offs,
                cols.clone(),
                vec![0.0; cols.len()],
            ),
            arg: vec![usize::MAX; pair_offs.len() - 1],
            cost: tuples.iter().map(|&k| problem.costs()[k]).collect(),
            modified: vec![0.0; tuples.len()],
            flat: vec![0.0; mult_offs.last().copied().unwrap_or(0)],
            tuples,
            pair_offs,
            ends,
            lone,
            tail,
            mult_offs,
            rows: vec![EMPTY; n0],
            cols: vec![EMPTY; n1],
            a: Vec::with_capacity(n0),
            b: Vec::with_capacity(n1),
            lap: SparseSolver::default(),
            warm: match warm_start {
                WarmStart::Auto => problem.n_sensors() == 3 && n0 + n1 >= WARM_MIN_SIZE,
                WarmStart::Always => true,
                WarmStart::Never => false,
            },
            alpha: Vec::with_capacity(n0),
            beta: Vec::with_capacity(n1),
            constant: [0.0; 2],
        }
    }

    /// [`Relaxation::new`] of the problem without the tuples `keep` rejects (per tuple
    /// index), by filtering this structure rather than sorting it again: the tuples keep their
    /// order within each group, and a pair left with none leaves the 2-D problem.
    pub(super) fn retain(&mut self, keep: &[bool]) {
        let w = self.mult_offs.len() - 1;
        let (n0, n1) = (self.pairs.n_rows(), self.pairs.n_cols());
        let (mut row_offs, mut cols, mut pair_offs) = (vec![0; n0 + 1], Vec::new(), Vec::new());
        let mut at = 0;
        // Moves entry `x` to position `at` (never after it); `lone` moves with groups 1 and 2.
        let take = |this: &mut Self, x: usize, at: &mut usize| {
            this.tuples[*at] = this.tuples[x];
            this.cost[*at] = this.cost[x];
            this.tail.copy_within(x * w..(x + 1) * w, *at * w);
            *at += 1;
        };
        for r in 0..n0 {
            for p in self.pairs.span(r) {
                let start = at;
                for x in self.pair_offs[p]..self.pair_offs[p + 1] {
                    if keep[self.tuples[x]] {
                        take(self, x, &mut at);
                    }
                }
                if at > start {
                    row_offs[r + 1] += 1;
                    cols.push(self.pairs.col_indices()[p]);
                    pair_offs.push(start);
                }
            }
        }
        pair_offs.push(at);
        let [e0, e1, e2, e3] = self.ends;
        let mut ends = [at; 4];
        for (group, range) in [(1, e0..e1), (2, e1..e2), (3, e2..e3)] {
            for x in range {
                if keep[self.tuples[x]] {
                    if x < e2 {
                        self.lone[at - ends[0]] = self.lone[x - e0];
                    }
                    take(self, x, &mut at);
                }
            }
            ends[group] = at;
        }
        for r in 0..n0 {
            row_offs[r + 1] += row_offs[r];
        }
        self.tuples.truncate(at);
        self.cost.truncate(at);
        self.tail.truncate(at * w);
        self.lone.truncate(ends[2] - ends[0]);
        self.modified.truncate(at);
        self.arg = vec![usize::MAX; cols.len()];
        let zeros = vec![0.0; cols.len()];
        self.pairs = SparseCosts::from_csr_unchecked(n0, n1, row_offs, cols, zeros);
        (self.pair_offs, self.ends) = (pair_offs, ends);
    }

    /// Cost minus multipliers of every entry, summed as [`super::reduced::modified`] does, so the
    /// values are bit-identical to it, and each pair's cheapest tuple. The loop runs over every
    /// tuple each iteration, so common sensor counts get a copy with the width known at
    /// compile time, and the pairs' minima are taken in the same pass.
    fn modify(&mut self, mult: &[Vec<f64>]) {
        for (s, &off) in self
            .mult_offs
            .iter()
            .enumerate()
            .take(mult.len().saturating_sub(2))
        {
            self.flat[off..off + mult[s + 2].len()].copy_from_slice(&mult[s + 2]);
        }
        match self.mult_offs.len() - 1 {
            0 => {
                self.modified.copy_from_slice(&self.cost);
                self.pair_minima();
            }
            1 => self.modify_n::<1>(),
            2 => self.modify_n::<2>(),
            3 => self.modify_n::<3>(),
            _ => self.modify_n::<0>(),
        }
    }

    /// [`Relaxation::modify`] for `W` multipliers per tuple (0: any).
    fn modify_n<const W: usize>(&mut self) {
        let w = if W == 0 { self.mult_offs.len() - 1 } else { W };
        let flat = &self.flat;
        let tails = self.tail.chunks_exact(w);
        let mut entries = (self.modified.iter_mut())
            .zip(&self.cost)
            .zip(tails)
            .zip(&self.tuples);
        let spans = self.pair_offs.windows(2);
        let minima = self.pairs.values_mut().iter_mut().zip(&mut self.arg);
        for ((v, arg), span) in minima.zip(spans) {
            let mut b = EMPTY;
            for (((m, &c), tail), &k) in entries.by_ref().take(span[1] - span[0]) {
                *m = c - tail.iter().map(|&x| flat[x]).sum::<f64>();
                keep_min(&mut b, (*m, k));
            }
            (*v, *arg) = b;
        }
        for (((m, &c), tail), _) in entries {
            *m = c - tail.iter().map(|&x| flat[x]).sum::<f64>();
        }
    }

    /// The pairs' cheapest tuples when no sensor is relaxed: the modified costs are the costs.
    fn pair_minima(&mut self) {
        let (m, tuples) = (&self.modified, &self.tuples);
        let spans = self.pair_offs.windows(2);
        let minima = self.pairs.values_mut().iter_mut().zip(&mut self.arg);
        for ((v, arg), w) in minima.zip(spans) {
            let mut b = EMPTY;
            for (&mx, &k) in m[w[0]..w[1]].iter().zip(&tuples[w[0]..w[1]]) {
                keep_min(&mut b, (mx, k));
            }
            (*v, *arg) = b;
        }
    }

    /// `L(u)`; the tuples chosen by the relaxed problem go into `chosen` (a buffer the
    /// caller keeps across iterations).
    pub(super) fn evaluate(&mut self, mult: &[Vec<f64>], chosen: &mut Vec<usize>) -> f64 {
        self.modify(mult);
        let (m, tuples) = (&self.modified, &self.tuples);
        let [e0, e1, e2, e3] = self.ends;
        self.rows.fill(EMPTY);
        self.cols.fill(EMPTY);
        let lone = m[e0..e2].iter().zip(&tuples[e0..e2]).zip(&self.lone);
        for (x, ((&mx, &k), &r)) in (e0..e2).zip(lone) {
            let slot = if x < e1 {
                &mut self.rows[r]
            } else {
                &mut self.cols[r]
            };
            keep_min(slot, (mx, k));
        }
        self.a.clear();
        self.a.extend(self.rows.iter().map(|r| r.0.min(0.0)));
        self.b.clear();
        self.b.extend(self.cols.iter().map(|c| c.0.min(0.0)));
        let sol = if self.warm {
            self.lap.solve_warm(&self.pairs, &self.a, &self.b)
        } else {
            self.lap.solve(&self.pairs, &self.a, &self.b)
        };
        chosen.clear();
        for (r, c) in sol.row_to_col.iter().enumerate() {
            match c {
                Some(c) => chosen.extend(
                    (self.pairs.span(r))
                        .find(|&p| self.pairs.col_indices()[p] == *c)
                        .map(|p| self.arg[p]),
                ),
                None if self.a[r] < 0.0 => chosen.push(self.rows[r].1),
                None => {}
            }
        }
        chosen.extend(
            (0..self.b.len())
                .filter(|&c| sol.col_to_row[c].is_none() && self.b[c] < 0.0)
                .map(|c| self.cols[c].1),
        );
        let (mut dual, mut free) = (sol.cost, 0.0);
        for x in (e2..e3).filter(|&x| m[x] < 0.0) {
            dual += m[x];
            free += m[x];
            chosen.push(tuples[x]);
        }
        let mult_sum = mult.iter().skip(2).flatten().sum::<f64>();
        self.constant = [free, mult_sum];
        dual + mult_sum
    }

    /// After an [`Relaxation::evaluate`], the tuples that no solution costing less than
    /// `incumbent` can hold, into `out` (unsorted); `false`, with `out` empty, after a
    /// warm 2-D solve, whose prices are not mapped back.
    ///
    /// With the 2-D solve's prices `α` (rows), `β` (columns), feasible for its problem
    /// ([`SparseSolver::input_duals`]), every feasible solution holding tuple `k` costs at
    /// least `B + r_k`: `B` is the prices' sum plus the relaxed constant (the multipliers'
    /// sum and the free `(0, 0, …)` tuples' negative modified costs), a lower bound on `L(u)`
    /// and so on the optimum, and `r_k ≥ 0` is what `k` costs beyond its prices (its modified
    /// cost less `α` of its sensor-0 report and `β` of its sensor-1 report; a free tuple's
    /// positive part). A tuple with `B + r_k` above the incumbent is in no better solution.
    pub(super) fn proven_out(&mut self, incumbent: f64, out: &mut Vec<usize>) -> bool {
        out.clear();
        let Some(base) = self.price_bound() else {
            return false;
        };
        let (alpha, beta) = (&self.alpha, &self.beta);
        let (m, [e0, e1, e2, e3]) = (&self.modified, self.ends);
        let limit = incumbent + PROOF_SLACK * (1.0 + incumbent.abs() + base.abs());
        let cols = self.pairs.col_indices();
        for (r, &ar) in alpha.iter().enumerate() {
            for p in self.pairs.span(r) {
                let price = ar + beta[cols[p]];
                let span = self.pair_offs[p]..self.pair_offs[p + 1];
                out.extend(
                    span.filter(|&x| base + (m[x] - price) > limit)
                        .map(|x| self.tuples[x]),
                );
            }
        }
        for x in e0..e2 {
            let price = match x < e1 {
                true => alpha[self.lone[x - e0]],
                false => beta[self.lone[x - e0]],
            };
            if base + (m[x] - price) > limit {
                out.push(self.tuples[x]);
            }
        }
        out.extend(
            (e2..e3)
                .filter(|&x| base + m[x].max(0.0) > limit)
                .map(|x| self.tuples[x]),
        );
        true
    }

    /// The bound `B` of [`Relaxation::proven_out`] at the last evaluation, with the 2-D
    /// solve's prices left in `alpha` and `beta`; `None` after a warm 2-D solve.
    fn price_bound(&mut self) -> Option<f64> {
        if self.warm {
            return None;
        }
        (self.lap).input_duals(
            &self.pairs,
            &self.a,
            &self.b,
            &mut self.alpha,
            &mut self.beta,
        );
        let [free, mult_sum] = self.constant;
        let base = self.alpha.iter().sum::<f64>() + self.beta.iter().sum::<f64>();
        Some(base + free + mult_sum)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assign::lagrangian::reduced::modified;
    use crate::assign::test_support::{
        brute_force, random_keep, random_multipliers, random_problem,
    };
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn modified_costs_and_pair_minima_are_bit_identical_to_the_reference() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut pairs_checked = 0;
        for seed in 0..40u64 {
            let s = 2 + seed as usize % 6; // every specialised width and the generic one
            let p = random_problem(seed, s, 5, 4, 30);
            let mut relax = Relaxation::new(&p, WarmStart::Auto);
            let mult: Vec<Vec<f64>> = (p.sizes().iter())
                .map(|&n| {
                    let draw = |i| match i {
                        0 => 0.0,
                        _ if rng.random_bool(0.2) => -0.0,
                        _ => -rng.random_range(0.0..3.0),
                    };
                    (0..=n).map(draw).collect()
                })
                .collect();
            relax.modify(&mult);
            for (x, &k) in relax.tuples.iter().enumerate() {
                let want = modified(&p, &mult, k, 2);
                assert_eq!(relax.modified[x].to_bits(), want.to_bits(), "seed {seed}");
            }
            // Each pair's cheapest tuple, taken in the same pass, against a pass of its own.
            for (pair, span) in relax.pair_offs.windows(2).enumerate() {
                let mut want = EMPTY;
                for &k in &relax.tuples[span[0]..span[1]] {
                    keep_min(&mut want, (modified(&p, &mult, k, 2), k));
                }
                let got = (relax.pairs.values()[pair], relax.arg[pair]);
                assert_eq!((got.0.to_bits(), got.1), (want.0.to_bits(), want.1));
                pairs_checked += 1;
            }
        }
        assert!(pairs_checked > 100, "only {pairs_checked} pairs checked");
    }

    /// The prices' bound is `L(u)` itself (the 2-D solve's duals map back exactly), and every
    /// tuple `proven_out` names is in no solution cheaper than the incumbent: on random
    /// problems of 3–5 sensors, at random multipliers and incumbents from the optimum up, the
    /// cheapest solution holding it (brute force over the tuples it does not clash with)
    /// costs more. Warm 2-D solves name none.
    #[test]
    fn proven_out_tuples_are_in_no_cheaper_solution() {
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let (mut proven, mut kept) = (0, 0);
        for seed in 0..120u64 {
            let s = 3 + seed as usize % 3;
            let p = random_problem(seed, s, 4, 3, 8);
            let mut relax = Relaxation::new(&p, WarmStart::Never);
            let scale = rng.random_range(0.1..6.0);
            let mult = random_multipliers(&mut rng, &p, scale);
            let mut chosen = Vec::new();
            let dual = relax.evaluate(&mult, &mut chosen);
            let bound = relax.price_bound().expect("a cold solve");
            assert!(
                (bound - dual).abs() <= 1e-9 * dual.abs().max(1.0),
                "seed {seed}: {bound} against {dual}"
            );
            let optimum = brute_force(&p);
            let mut out = Vec::new();
            for incumbent in [optimum, optimum + 1.0, optimum + 4.0] {
                assert!(relax.proven_out(incumbent, &mut out));
                for &k in &out {
                    let clash = |j: usize| {
                        (p.tuple(j).iter().zip(p.tuple(k))).any(|(&a, &b)| a > 0 && a == b)
                    };
                    let others: Vec<usize> =
                        p.active().iter().copied().filter(|&j| !clash(j)).collect();
                    let holding = p.costs()[k] + brute_force(&p.with_active(others));
                    assert!(
                        holding > incumbent,
                        "seed {seed}: tuple {k} holds {holding} ≤ {incumbent}"
                    );
                }
                proven += out.len();
                kept += p.active().len() - out.len();
            }
            let mut warm = Relaxation::new(&p, WarmStart::Always);
            warm.evaluate(&mult, &mut chosen);
            assert!(!warm.proven_out(optimum, &mut out) && out.is_empty());
        }
        assert!(
            proven > 300 && kept > 300,
            "{proven} proven out, {kept} kept"
        );
    }

    /// Filtering ([`Relaxation::retain`]) builds what [`Relaxation::new`] builds for the
    /// smaller problem: the same groups, pairs and multiplier positions, and at random
    /// multipliers the same `L(u)` and relaxed solution, bit for bit.
    #[test]
    fn retain_builds_what_new_builds_for_the_smaller_problem() {
        let mut rng = ChaCha8Rng::seed_from_u64(23);
        let mut removed = 0;
        for seed in 0..60u64 {
            let s = 3 + seed as usize % 3;
            let p = random_problem(seed, s, 6, 4, 20);
            let (keep, kept) = random_keep(&mut rng, &p, 0.6);
            removed += p.active().len() - kept.len();
            let q = p.with_active(kept);
            let mut filtered = Relaxation::new(&p, WarmStart::Never);
            filtered.retain(&keep);
            let mut fresh = Relaxation::new(&q, WarmStart::Never);
            assert_eq!(filtered.tuples, fresh.tuples, "seed {seed}");
            assert_eq!(
                (&filtered.pair_offs, filtered.ends),
                (&fresh.pair_offs, fresh.ends)
            );
            assert_eq!((&filtered.tail, &filtered.lone), (&fresh.tail, &fresh.lone));
            assert_eq!(filtered.pairs.col_indices(), fresh.pairs.col_indices());
            for r in 0..p.sizes()[0] {
                assert_eq!(filtered.pairs.span(r), fresh.pairs.span(r), "seed {seed}");
            }
            let (mut a, mut b) = (Vec::new(), Vec::new());
            for _ in 0..3 {
                let mult = random_multipliers(&mut rng, &p, 4.0);
                let (da, db) = (
                    filtered.evaluate(&mult, &mut a),
                    fresh.evaluate(&mult, &mut b),
                );
                assert_eq!((da.to_bits(), &a), (db.to_bits(), &b), "seed {seed}");
            }
        }
        assert!(removed > 200, "{removed}");
    }
}
