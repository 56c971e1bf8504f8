//! Assignment solvers for METHODS.md §2 (baselines A and B).
//!
//! * [`lap`] — exact 2-D linear assignment: dense (Jonker-Volgenant / Crouse shortest
//!   augmenting path, the algorithm behind `scipy.optimize.linear_sum_assignment`) and sparse with
//!   "leave unassigned" costs for rows and columns.
//! * [`SdProblem`] — the validated S-D assignment input: candidate tuples, their costs, and the
//!   number of reports per sensor.
//! * [`lagrangian`] — baseline A, Lagrangian relaxation with subgradient updates.
//! * [`branch_bound`] — baseline B, exact depth-first branch and bound.
//!
//! Dependencies point one way: `lap` (2-D) ← `lagrangian` (its relaxation solves 2-D problems;
//! its private `recovery` the feasible solutions) ← `branch_bound` (the Lagrangian bounds its
//! root). `csr` is a leaf helper.
//!
//! Both S-D solvers return an [`SdSolution`] whose [`Termination`] says whether the result is
//! proven optimal, within the requested gap, or only the best found before a limit.

pub mod branch_bound;
mod candidates;
mod csr;
pub mod lagrangian;
pub mod lap;
mod sd_problem;

pub use candidates::CandidateSet;

use crate::error::{parse_option, CoreError, CoreResult, UnknownOption};

/// Largest magnitude of a finite cost any solver accepts. The solvers add and subtract costs
/// (dual potentials, path lengths, bounds): within ±1e150 every such sum of up to 1e150 terms
/// stays finite, where ±1e308 can overflow to −inf and be reported optimal. Results are
/// optimal to within floating-point rounding, about n · max|c| · 2⁻⁵², so costs spanning many
/// orders of magnitude lose their small terms (scale them first).
pub const MAX_ABS_COST: f64 = 1e150;

/// A `CoreError` naming `arg` for the first finite value beyond ±[`MAX_ABS_COST`] (`f64`
/// values, or `f32` ones read as the `f64` they equal).
pub fn check_cost_range<T: Copy + Into<f64>>(arg: &'static str, values: &[T]) -> CoreResult<()> {
    let beyond = |c: f64| c.is_finite() && c.abs() > MAX_ABS_COST;
    match values.iter().map(|&c| c.into()).enumerate().find(|&(_, c)| beyond(c)) {
        Some((index, c)) => Err(CoreError::out_of_range(
            arg,
            format!(
                "entry {index} is {c:e}; finite costs must lie within ±{MAX_ABS_COST:e} so that sums of them stay finite"
            ),
        )),
        None => Ok(()),
    }
}
pub use sd_problem::{SdProblem, MAX_REPORTS_PER_SENSOR};

/// Which S-D solver to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SdMethod {
    /// Baseline A, [`lagrangian`]: approximate, with a proven bound.
    #[default]
    Lagrangian,
    /// Baseline B, [`branch_bound`]: exact up to its node and time limits.
    Exact,
}

impl std::str::FromStr for SdMethod {
    type Err = UnknownOption;

    /// `"lagrangian"` or `"exact"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [("lagrangian", Self::Lagrangian), ("exact", Self::Exact)];
        parse_option(value, &choices, "'lagrangian' or 'exact'")
    }
}

/// Why an S-D solver stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Termination {
    /// The primal cost equals the dual bound up to round-off ([`OPTIMAL_RTOL`]): proven optimal.
    Optimal,
    /// The relative gap fell to or below the requested `gap_tol` (not necessarily optimal).
    GapReached,
    /// The iteration cap was reached before the gap closed.
    MaxIterations,
    /// The subgradient step parameter shrank below its floor: the dual bound stopped improving.
    Stalled,
    /// A limit stopped the solver (branch-and-bound nodes or time, the Lagrangian's time); the
    /// solution is the best found, not proven.
    NotProven(Limit),
}

/// Which limit stopped the search.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// `max_nodes` search nodes were expanded.
    Nodes,
    /// The wall-clock `time_limit` passed.
    Time,
}

impl Termination {
    /// A short stable name, e.g. for the Python layer: `"optimal"`, `"gap_reached"`,
    /// `"max_iterations"`, `"stalled"`, `"node_limit"`, `"time_limit"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            Termination::Optimal => "optimal",
            Termination::GapReached => "gap_reached",
            Termination::MaxIterations => "max_iterations",
            Termination::Stalled => "stalled",
            Termination::NotProven(Limit::Nodes) => "node_limit",
            Termination::NotProven(Limit::Time) => "time_limit",
        }
    }

    /// True when the solution is proven optimal.
    pub fn is_optimal(&self) -> bool {
        matches!(self, Termination::Optimal)
    }
}

/// Relative tolerance under which primal and dual are treated as equal (round-off only).
pub const OPTIMAL_RTOL: f64 = 1e-9;

/// The result of an S-D solver.
#[derive(Debug, Clone, PartialEq)]
pub struct SdSolution {
    /// Indices into the problem's tuples, ascending. No two share a real report.
    pub chosen: Vec<usize>,
    /// Sum of the chosen tuples' costs.
    pub primal_cost: f64,
    /// A proven lower bound on the optimal cost.
    pub dual_bound: f64,
    /// `(primal_cost - dual_bound) / max(1, |primal_cost|)`, see [`relative_gap`].
    pub gap: f64,
    /// Subgradient iterations (Lagrangian) or search nodes expanded (branch and bound).
    pub iterations: usize,
    /// Why the solver stopped.
    pub termination: Termination,
}

/// The relative duality gap reported by the S-D solvers:
/// `max(0, primal - dual) / max(1, |primal|)`.
///
/// Relative for large costs, absolute when `|primal| < 1`: costs here are negative
/// log-likelihood ratios, so the empty solution (cost 0) is common and a plain relative gap
/// would divide by zero. Clamped at 0 because round-off can put the bound a hair above the
/// primal when both are optimal.
///
/// ```
/// use passive_assoc_core::assign::relative_gap;
/// assert_eq!(relative_gap(-10.0, -12.0), 0.2);
/// assert_eq!(relative_gap(0.0, -0.5), 0.5);
/// ```
pub fn relative_gap(primal: f64, dual: f64) -> f64 {
    (primal - dual).max(0.0) / primal.abs().max(1.0)
}

/// True when `primal` and `dual` agree to round-off, i.e. the primal is proven optimal.
pub(crate) fn closes_gap(primal: f64, dual: f64) -> bool {
    primal - dual <= OPTIMAL_RTOL * primal.abs().max(1.0)
}

/// When a solve that starts now and may run `limit` must stop; `None` without a limit, and for
/// a limit past what the clock can represent (an `Instant` holds at most 2⁶³ s on Linux, a
/// `Duration` up to 1.8e19 s): such a limit never binds, and adding it panicked.
pub(crate) fn deadline(limit: Option<std::time::Duration>) -> Option<std::time::Instant> {
    limit.and_then(|limit| std::time::Instant::now().checked_add(limit))
}

/// Random instances and an independent exhaustive solver, shared by the solver tests.
#[cfg(test)]
pub(crate) mod test_support {
    use super::SdProblem;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// `n_targets` "true" tuples (each sensor detects with prob. 0.8) with strongly negative
    /// costs, plus `n_clutter` random tuples with costs in [-8, 2): enough structure that the
    /// relaxation is not trivially tight, and random enough to hit corner cases.
    pub fn random_problem(
        seed: u64,
        s: usize,
        max_reports: usize,
        n_targets: usize,
        n_clutter: usize,
    ) -> SdProblem {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let sizes: Vec<usize> = (0..s).map(|_| rng.random_range(0..=max_reports)).collect();
        let (mut tuples, mut costs) = (Vec::new(), Vec::new());
        for t in 0..n_targets + n_clutter {
            let p = if t < n_targets { 0.8 } else { 0.6 };
            for &n in &sizes {
                let hit = n > 0 && rng.random_bool(p);
                tuples.push(if hit { rng.random_range(1..=n) } else { 0 });
            }
            let c = if t < n_targets {
                rng.random_range(-20.0..-5.0)
            } else {
                rng.random_range(-8.0..2.0)
            };
            costs.push(c);
        }
        SdProblem::new(tuples, s, costs, sizes).unwrap()
    }

    /// A hard case: every sensor has `n` reports and `k` random tuples (each sensor present
    /// with prob. 0.85) all have negative costs, so they overlap heavily.
    pub fn dense_problem(seed: u64, s: usize, n: usize, k: usize) -> SdProblem {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut tuples = Vec::with_capacity(k * s);
        for _ in 0..k * s {
            tuples.push(if rng.random_bool(0.85) {
                rng.random_range(1..=n)
            } else {
                0
            });
        }
        let costs = (0..k).map(|_| rng.random_range(-10.0..-0.5)).collect();
        SdProblem::new(tuples, s, costs, vec![n; s]).unwrap()
    }

    /// Optimal cost by enumerating every feasible subset of the active tuples.
    /// Lagrangian multipliers for every report of `p`: 0 for the dummy, `−U(0, scale)` for the
    /// others.
    pub fn random_multipliers(rng: &mut ChaCha8Rng, p: &SdProblem, scale: f64) -> Vec<Vec<f64>> {
        let draw = |rng: &mut ChaCha8Rng, i: usize| match i {
            0 => 0.0,
            _ => -rng.random_range(0.0..scale),
        };
        (p.sizes().iter())
            .map(|&n| (0..=n).map(|i| draw(rng, i)).collect())
            .collect()
    }

    /// Each tuple of `p` kept with probability `share` (per tuple index), and the active
    /// tuples kept, ascending: the problem `p.with_active(kept)`.
    pub fn random_keep(rng: &mut ChaCha8Rng, p: &SdProblem, share: f64) -> (Vec<bool>, Vec<usize>) {
        let keep: Vec<bool> = (0..p.n_tuples()).map(|_| rng.random_bool(share)).collect();
        let kept = p.active().iter().copied().filter(|&k| keep[k]).collect();
        (keep, kept)
    }

    pub fn brute_force(p: &SdProblem) -> f64 {
        fn go(p: &SdProblem, at: usize, used: &mut Vec<Vec<bool>>) -> f64 {
            let Some(&k) = p.active().get(at) else {
                return 0.0;
            };
            let mut best = go(p, at + 1, used);
            let t = p.tuple(k);
            if t.iter().enumerate().all(|(s, &i)| i == 0 || !used[s][i]) {
                t.iter().enumerate().for_each(|(s, &i)| used[s][i] = i > 0);
                best = best.min(p.costs()[k] + go(p, at + 1, used));
                t.iter().enumerate().for_each(|(s, &i)| used[s][i] = false);
            }
            best
        }
        go(
            p,
            0,
            &mut p.sizes().iter().map(|&n| vec![false; n + 1]).collect(),
        )
    }
}
