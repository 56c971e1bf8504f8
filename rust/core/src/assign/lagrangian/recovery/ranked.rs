//! The scan order both local searches share ([`super::search`] each iteration, [`super::polish`]
//! once at the end), built once per solve: the active tuples by ascending cost, ties by index,
//! with their costs and reports laid out by rank so that a scan reads contiguous memory.

use crate::assign::SdProblem;

const NONE: usize = usize::MAX;

pub(super) struct Ranked {
    /// Active tuples by ascending cost (ties by index): the scan order. A tuple's position in
    /// it is its rank.
    pub(super) by_cost: Vec<usize>,
    /// Per tuple: its rank (`usize::MAX` for inactive tuples).
    pub(super) rank_of: Vec<usize>,
    /// The number of sensors: reports per rank in `flat`.
    pub(super) s: usize,
    /// Per rank: its cost, and the flat index of its report of each sensor (`s` entries per
    /// rank): report `i > 0` of sensor `t` is `Σ_{t' < t} sizes[t'] + i − 1`, and "missed" is
    /// the slot `missed`, one past the last report, so a scan needs no special case.
    pub(super) cost: Vec<f64>,
    pub(super) flat: Vec<usize>,
    pub(super) missed: usize,
}

impl Ranked {
    pub(super) fn new(problem: &SdProblem) -> Self {
        let by_cost = problem.active_by_cost();
        let base = problem.report_offsets();
        let missed = problem.n_reports();
        let flat = (by_cost.iter())
            .flat_map(|&k| problem.tuple(k).iter().zip(base))
            .map(|(&i, &b)| if i == 0 { missed } else { b + i - 1 })
            .collect();
        let mut rank_of = vec![NONE; problem.n_tuples()];
        by_cost
            .iter()
            .enumerate()
            .for_each(|(r, &k)| rank_of[k] = r);
        Self {
            cost: by_cost.iter().map(|&k| problem.costs()[k]).collect(),
            by_cost,
            rank_of,
            s: problem.n_sensors(),
            flat,
            missed,
        }
    }

    /// An order of nothing, a placeholder while another is filtered.
    pub(super) fn empty() -> Self {
        Self {
            by_cost: Vec::new(),
            rank_of: Vec::new(),
            s: 0,
            cost: Vec::new(),
            flat: Vec::new(),
            missed: 0,
        }
    }

    /// [`Ranked::new`] of the problem without the tuples `keep` rejects (per tuple index), by
    /// filtering this order rather than sorting again: the same order, costs and reports.
    pub(super) fn retain(&mut self, keep: &[bool]) {
        let (s, mut at) = (self.s, 0);
        for r in 0..self.by_cost.len() {
            let k = self.by_cost[r];
            if keep[k] {
                self.by_cost[at] = k;
                self.cost[at] = self.cost[r];
                self.flat.copy_within(r * s..(r + 1) * s, at * s);
                at += 1;
            }
            self.rank_of[k] = NONE;
        }
        self.by_cost.truncate(at);
        self.cost.truncate(at);
        self.flat.truncate(at * s);
        for (r, &k) in self.by_cost.iter().enumerate() {
            self.rank_of[k] = r;
        }
    }

    /// The flat reports of rank `r`, `missed` where it has none.
    pub(super) fn reports(&self, r: usize) -> &[usize] {
        &self.flat[r * self.s..(r + 1) * self.s]
    }
}
