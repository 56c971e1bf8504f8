//! Baseline A of METHODS.md §2: S-D assignment by Lagrangian relaxation (Pattipati et al.
//! 1992, Deb et al. 1997).
//!
//! The "at most once" constraints of sensors 3..S (indices `2..S` here) move into the
//! objective with multipliers `u_s[i] <= 0` (the dummy report 0 has none):
//! `L(u) = min Σ_k (c_k − Σ_{s≥2} u_s[i_s(k)]) x_k + Σ_{s≥2} Σ_i u_s[i]` subject to the
//! constraints of sensors 0 and 1 only. That is a sparse 2-D assignment between the reports of
//! sensors 0 and 1 (each pair keeps its best tuple; tuples missing sensor 0 or 1 become the
//! "unassigned" costs), solved exactly by [`lap`](super::lap), so `L(u)` is a valid lower bound.
//! The bound is raised by projected subgradient ascent with a Polyak step aimed at the best
//! primal; a feasible solution is recovered each iteration by successive 2-D assignments and
//! polished by a local search, and, if asked, the best one once at the end by compound moves
//! (private module `recovery`). Which sensors play 0 and 1 is
//! [`SensorOrder`]'s choice: by default, at S = 3, the two with the fewest reports.
//!
//! Speed: every iteration touches every candidate tuple, so the per-solve structures
//! (`Relaxation`, `Recovery`) are built once and their buffers reused, and work
//! whose result is already known is skipped (a repeated relaxed solution or search start). With
//! cold 2-D solves the result is the same, bit for bit, as a plain implementation of the steps
//! above; warm ones may pick another 2-D optimum of equal cost (see [`WarmStart`]).

use super::recovery::{polish, Recovery};
use super::{closes_gap, relative_gap, SdProblem, SdSolution, Termination};
use crate::error::{CoreError, CoreResult};
pub use order::SensorOrder;
use relaxation::Relaxation;

mod order;
mod relaxation;

/// Options of [`solve`], built with validated `with_*` setters.
///
/// ```
/// use passive_assoc::assign::lagrangian::LagrangianOptions;
/// let o = LagrangianOptions::default().with_max_iter(50).unwrap().with_gap_tol(1e-2).unwrap();
/// assert_eq!(o.max_iter(), 50);
/// assert!(LagrangianOptions::default().with_gap_tol(-1.0).is_err());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct LagrangianOptions {
    max_iter: usize,
    gap_tol: f64,
    step_scale: f64,
    stall_iters: usize,
    warm_start: WarmStart,
    sensor_order: SensorOrder,
    polish: bool,
}

/// Whether each iteration's inner 2-D assignment starts from the previous iteration's duals
/// and pairs (a square, mirrored form; see the private module `sap::warm`). Either way the
/// 2-D solve is exact, so iterations, bounds and answers are those of an exact solve; only the
/// time differs (and, between optima of equal cost, which one is returned).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WarmStart {
    /// Warm for S = 3 problems whose two sensors kept in the 2-D problem (see
    /// [`SensorOrder`]) have at least [`WARM_MIN_SIZE`] reports between them, cold otherwise:
    /// where it measured faster. On `reproduce intensity` scans
    /// (`python benches/bench_warm_start.py`) warm / cold was 0.62 at S = 3, M = 100, 0.89 at
    /// M = 50, 1.11 at M = 18, and 0.99–1.06 at S = 4 (medians of per-scan ratios;
    /// docs/performance.md). A likely reason, not measured: with S >= 4 several multiplier
    /// sets move each iteration, so fewer pairs stay tight, and on small problems the square
    /// form's set-up costs more than the searches it saves. (The synthetic criterion group
    /// `sd_lagrangian_warm` shows the small and S = 4 losses too, but no gain on its S = 3
    /// shape.)
    #[default]
    Auto,
    Always,
    Never,
}

/// Reports of the two sensors kept in the 2-D problem, together, from which
/// [`WarmStart::Auto`] starts warm.
pub const WARM_MIN_SIZE: usize = 50;

impl Default for LagrangianOptions {
    /// `max_iter = 200`, `gap_tol = 1e-3` (0.1 %, tight enough that the recovered solution is
    /// usually the optimum, see the tests), `step_scale = 1`, `stall_iters = 10`.
    fn default() -> Self {
        Self {
            max_iter: 200,
            gap_tol: 1e-3,
            step_scale: 1.0,
            stall_iters: 10,
            warm_start: WarmStart::Auto,
            sensor_order: SensorOrder::Auto,
            polish: false,
        }
    }
}

/// The step parameter floor: below it the multipliers no longer move usefully.
const MIN_STEP_SCALE: f64 = 1e-4;

impl LagrangianOptions {
    /// Subgradient iterations, at least 1.
    pub fn with_max_iter(mut self, max_iter: usize) -> CoreResult<Self> {
        if max_iter == 0 {
            return Err(CoreError::out_of_range(
                "max_iter",
                "must be at least 1, got 0",
            ));
        }
        self.max_iter = max_iter;
        Ok(self)
    }

    /// Stop when the relative gap `(primal − dual) / max(1, |primal|)` is at most this
    /// (finite, `>= 0`; 0 means "only a proven optimum stops early").
    pub fn with_gap_tol(mut self, gap_tol: f64) -> CoreResult<Self> {
        if !(gap_tol.is_finite() && gap_tol >= 0.0) {
            return Err(CoreError::out_of_range(
                "gap_tol",
                format!("must be finite and >= 0, got {gap_tol}"),
            ));
        }
        self.gap_tol = gap_tol;
        Ok(self)
    }

    /// Initial Polyak step parameter α in `(0, 2]`; it is halved whenever the dual bound has
    /// not improved for `stall_iters` iterations.
    pub fn with_step_scale(mut self, step_scale: f64) -> CoreResult<Self> {
        if !(step_scale > 0.0 && step_scale <= 2.0) {
            return Err(CoreError::out_of_range(
                "step_scale",
                format!("must be in (0, 2], got {step_scale}"),
            ));
        }
        self.step_scale = step_scale;
        Ok(self)
    }

    /// Iterations without dual improvement before the step parameter is halved, at least 1.
    pub fn with_stall_iters(mut self, stall_iters: usize) -> CoreResult<Self> {
        if stall_iters == 0 {
            return Err(CoreError::out_of_range(
                "stall_iters",
                "must be at least 1, got 0",
            ));
        }
        self.stall_iters = stall_iters;
        Ok(self)
    }

    /// Warm-started inner 2-D solves: automatic (the default), always or never.
    pub fn with_warm_start(mut self, warm_start: WarmStart) -> Self {
        self.warm_start = warm_start;
        self
    }

    /// Which sensors the relaxation keeps and which it relaxes: automatic (the default) or
    /// as given.
    pub fn with_sensor_order(mut self, sensor_order: SensorOrder) -> Self {
        self.sensor_order = sensor_order;
        self
    }

    /// Whether the best solution gets the compound-move polish at the end (off by default):
    /// a markedly better primal on large scans for a large share of the solve's time
    /// (`python benches/bench_sensor_order.py`, docs/performance.md).
    pub fn with_polish(mut self, polish: bool) -> Self {
        self.polish = polish;
        self
    }

    pub fn polish(&self) -> bool {
        self.polish
    }

    pub fn sensor_order(&self) -> SensorOrder {
        self.sensor_order
    }

    pub fn warm_start(&self) -> WarmStart {
        self.warm_start
    }

    pub fn max_iter(&self) -> usize {
        self.max_iter
    }

    pub fn gap_tol(&self) -> f64 {
        self.gap_tol
    }

    pub fn step_scale(&self) -> f64 {
        self.step_scale
    }

    pub fn stall_iters(&self) -> usize {
        self.stall_iters
    }
}

/// Solves the S-D problem approximately, with a proven lower bound. Deterministic.
///
/// For S = 2 the relaxation is the problem itself, so one exact sparse 2-D assignment answers
/// it (`Termination::Optimal`). For S >= 3 each iteration evaluates `L(u)`, recovers a feasible
/// solution, and stops on a closed gap (`Optimal`), `gap <= gap_tol` (`GapReached`), a vanished
/// step (`Stalled`) or `max_iter` (`MaxIterations`). With `polish` on, after those last two
/// the best solution gets the compound-move polish (not bounded by any time limit: its passes
/// end when no move improves), and the termination becomes `Optimal` or `GapReached` if the
/// polished cost meets that test. The primal never exceeds 0: choosing nothing is
/// feasible.
///
/// ```
/// use passive_assoc::assign::{lagrangian, SdProblem};
/// let tuples = vec![1, 1, 1, 1, 1, 0, 0, 0, 1];
/// let p = SdProblem::new(tuples, 3, vec![-5.0, -3.0, -1.0], vec![1, 1, 1]).unwrap();
/// let s = lagrangian::solve(&p, &Default::default());
/// assert_eq!(s.chosen, vec![0]);
/// assert!(s.dual_bound <= s.primal_cost + 1e-12);
/// ```
pub fn solve(problem: &SdProblem, options: &LagrangianOptions) -> SdSolution {
    // Reordering sensors keeps tuple indices, so the solution needs no mapping back.
    match order::working_order(problem, options.sensor_order) {
        Some(order) => solve_in_order(&problem.reordered(&order), options),
        None => solve_in_order(problem, options),
    }
}

/// [`solve`] with sensors 0 and 1 as the 2-D problem and 2.. relaxed.
fn solve_in_order(problem: &SdProblem, options: &LagrangianOptions) -> SdSolution {
    let mut relax = Relaxation::new(problem, options.warm_start);
    let mut recovery = Recovery::new(problem);
    let mut mult: Vec<Vec<f64>> = problem.sizes().iter().map(|&n| vec![0.0; n + 1]).collect();
    let mut best = (Vec::new(), 0.0); // choosing nothing is feasible
    let (mut dual_bound, mut alpha, mut since) = (f64::NEG_INFINITY, options.step_scale, 0);
    let (mut iterations, mut termination) = (0, Termination::MaxIterations);
    while iterations < options.max_iter {
        iterations += 1;
        let (dual, relaxed) = relax.evaluate(&mult);
        if dual > dual_bound {
            dual_bound = dual;
            since = 0;
        } else {
            since += 1;
        }
        if let Some(cand) = recovery.primal(problem, &mult, &relaxed) {
            if cand.1 < best.1 {
                best = cand;
            }
        }
        if problem.n_sensors() == 2 || closes_gap(best.1, dual_bound) {
            termination = Termination::Optimal;
            break;
        }
        if relative_gap(best.1, dual_bound) <= options.gap_tol {
            termination = Termination::GapReached;
            break;
        }
        if since >= options.stall_iters {
            (alpha, since) = (alpha / 2.0, 0);
        }
        if alpha < MIN_STEP_SCALE || !step(problem, &mut mult, &relaxed, alpha * (best.1 - dual)) {
            termination = Termination::Stalled;
            break;
        }
    }
    // Not after `GapReached`: the caller's precision is met, and the polish is not free.
    let unfinished = matches!(
        termination,
        Termination::MaxIterations | Termination::Stalled
    );
    if options.polish && unfinished {
        // Compound moves the per-iteration search cannot make (module `recovery::polish`).
        best = polish(problem, &best.0);
        if closes_gap(best.1, dual_bound) {
            termination = Termination::Optimal;
        } else if relative_gap(best.1, dual_bound) <= options.gap_tol {
            termination = Termination::GapReached;
        }
    }
    finish(
        problem,
        best.0,
        dual_bound.min(best.1),
        iterations,
        termination,
    )
}

fn finish(
    problem: &SdProblem,
    mut chosen: Vec<usize>,
    dual: f64,
    iterations: usize,
    termination: Termination,
) -> SdSolution {
    chosen.sort_unstable();
    let primal_cost = chosen.iter().map(|&k| problem.costs()[k]).sum();
    // An empty problem never iterates; its bound is trivially 0.
    let dual_bound = if dual.is_finite() { dual } else { primal_cost };
    let gap = relative_gap(primal_cost, dual_bound);
    SdSolution {
        chosen,
        primal_cost,
        dual_bound,
        gap,
        iterations,
        termination,
    }
}

/// One projected subgradient step `u ← min(0, u + t·g / |g|²)` with `g_s[i] = 1 − uses`;
/// `numerator` is `α·(best primal − L(u))`. Returns false when `g` vanishes (nothing to do).
fn step(problem: &SdProblem, mult: &mut [Vec<f64>], relaxed: &[usize], numerator: f64) -> bool {
    let mut g: Vec<Vec<f64>> = mult.iter().map(|m| vec![1.0; m.len()]).collect();
    for &k in relaxed {
        for (s, &i) in problem.tuple(k).iter().enumerate().skip(2) {
            g[s][i] -= 1.0;
        }
    }
    let mut norm2 = 0.0;
    for s in 2..mult.len() {
        g[s][0] = 0.0;
        for (gi, ui) in g[s].iter_mut().zip(&mult[s]) {
            // Projected: a zero multiplier cannot rise, so that component does not count.
            if *ui >= 0.0 && *gi > 0.0 {
                *gi = 0.0;
            }
            norm2 += *gi * *gi;
        }
    }
    if norm2 == 0.0 || numerator <= 0.0 {
        return false;
    }
    let t = numerator / norm2;
    for s in 2..mult.len() {
        for (ui, gi) in mult[s].iter_mut().zip(&g[s]) {
            *ui = (*ui + t * gi).min(0.0);
        }
    }
    true
}

/// Tuple cost minus the multipliers of sensors `from..S`.
pub(super) fn modified(problem: &SdProblem, mult: &[Vec<f64>], k: usize, from: usize) -> f64 {
    let t = problem.tuple(k);
    problem.costs()[k] - (from..t.len()).map(|s| mult[s][t[s]]).sum::<f64>()
}

/// Keeps the cheaper `(cost, tuple)`; ties go to the lower tuple index (determinism).
pub(super) fn keep_min(slot: &mut (f64, usize), cand: (f64, usize)) {
    if cand.0 < slot.0 || (cand.0 == slot.0 && cand.1 < slot.1) {
        *slot = cand;
    }
}

pub(super) const EMPTY: (f64, usize) = (f64::INFINITY, usize::MAX);

#[cfg(test)]
mod tests;
