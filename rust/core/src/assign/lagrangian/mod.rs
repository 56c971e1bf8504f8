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
//! (private module `recovery`). Every few iterations the relaxed 2-D solve's prices prove
//! some tuples out of every solution better than the incumbent, and those leave the problem
//! (`prove_out`). Which sensors play 0 and 1 is
//! [`SensorOrder`]'s choice: by default, at S = 3, the two with the fewest reports.
//!
//! Speed: every iteration touches every candidate tuple, so the per-solve structures
//! (`Relaxation`, `Recovery`) are built once (and filtered when tuples leave) and their
//! buffers reused, and work whose result is already known is skipped (a repeated relaxed
//! solution or search start). With
//! cold 2-D solves the result is the same, bit for bit, as a plain implementation of the steps
//! above; warm ones may pick another 2-D optimum of equal cost (see [`WarmStart`]).

mod options;
mod order;
mod recovery;
pub(crate) mod reduced;
mod relaxation;

pub use options::{LagrangianOptions, WarmStart, WARM_MIN_SIZE};
pub use order::SensorOrder;

use options::{DEFLECTION, MIN_STEP_SCALE};
use recovery::Recovery;
use relaxation::Relaxation;

use crate::assign::{closes_gap, relative_gap, Limit, SdProblem, SdSolution, Termination};
use std::time::Instant;

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
/// use passive_assoc_core::assign::{lagrangian, SdProblem};
/// let tuples = vec![1, 1, 1, 1, 1, 0, 0, 0, 1];
/// let p = SdProblem::new(tuples, 3, vec![-5.0, -3.0, -1.0], vec![1, 1, 1]).unwrap();
/// let s = lagrangian::solve(&p, &Default::default());
/// assert_eq!(s.chosen, vec![0]);
/// assert!(s.dual_bound <= s.primal_cost + 1e-12);
/// ```
pub fn solve(problem: &SdProblem, options: &LagrangianOptions) -> SdSolution {
    // Reordering sensors keeps tuple indices, so the solution needs no mapping back.
    match order::working_order(problem, options.sensor_order()) {
        Some(order) => solve_in_order(&problem.reordered(&order), options),
        None => solve_in_order(problem, options),
    }
}

/// [`solve`] with sensors 0 and 1 as the 2-D problem and 2.. relaxed.
fn solve_in_order(problem: &SdProblem, options: &LagrangianOptions) -> SdSolution {
    let mut relax = Relaxation::new(problem, options.warm_start());
    let mut recovery = Recovery::new(problem);
    // The problem without the tuples proven out so far (`None`: none yet); see `prove_out`.
    let mut reduced: Option<SdProblem> = None;
    let (mut out, mut keep) = (Vec::new(), vec![false; problem.n_tuples()]);
    let mut mult: Vec<Vec<f64>> = problem.sizes().iter().map(|&n| vec![0.0; n + 1]).collect();
    let mut best = (Vec::new(), 0.0); // choosing nothing is feasible
    let (mut dual_bound, mut alpha, mut since) = (f64::NEG_INFINITY, options.step_scale(), 0);
    let (mut iterations, mut termination) = (0, Termination::MaxIterations);
    let deadline = crate::assign::deadline(options.time_limit());
    // Per-iteration buffers, allocated once: the relaxed solution and the step direction (the
    // deflected subgradient, which keeps the previous direction).
    let mut relaxed = Vec::new();
    let mut direction: Vec<Vec<f64>> = mult.iter().map(|m| vec![0.0; m.len()]).collect();
    while iterations < options.max_iter() && !crate::parallel::interrupted() {
        if deadline.is_some_and(|d| Instant::now() >= d) {
            termination = Termination::NotProven(Limit::Time);
            break;
        }
        let current = reduced.as_ref().unwrap_or(problem);
        iterations += 1;
        let dual = relax.evaluate(&mult, &mut relaxed);
        if dual > dual_bound {
            dual_bound = dual;
            since = 0;
        } else {
            since += 1;
        }
        if let Some(cand) = recovery.primal(current, &mult, &relaxed) {
            if cand.1 < best.1 {
                best = cand;
            }
        }
        if problem.n_sensors() == 2 || closes_gap(best.1, dual_bound) {
            termination = Termination::Optimal;
            break;
        }
        if relative_gap(best.1, dual_bound) <= options.gap_tol() {
            termination = Termination::GapReached;
            break;
        }
        // Every few iterations, the tuples the relaxation's prices prove out of any solution
        // better than the incumbent leave the problem (`prove_out`).
        if iterations % PROVE_EVERY == 0 && relax.proven_out(best.1, &mut out) {
            if let Some(next) = prove_out(current, &mut out, &best.0) {
                #[cfg(test)]
                tests::REDUCTIONS.with(|n| n.set(n.get() + 1));
                // The structures of `next`, filtered from those of `current` (no new sort).
                keep.fill(false);
                next.active().iter().for_each(|&k| keep[k] = true);
                relax.retain(&keep);
                recovery.retain(&keep);
                reduced = Some(next);
            }
        }
        let current = reduced.as_ref().unwrap_or(problem);
        if since >= options.stall_iters() {
            (alpha, since) = (alpha / 2.0, 0);
        }
        let numerator = alpha * (best.1 - dual);
        if alpha < MIN_STEP_SCALE || !step(current, &mut mult, &relaxed, numerator, &mut direction)
        {
            termination = Termination::Stalled;
            break;
        }
    }
    let problem = reduced.as_ref().unwrap_or(problem);
    // Not after `GapReached`: the caller's precision is met, and the polish is not free.
    let unfinished = matches!(
        termination,
        Termination::MaxIterations | Termination::Stalled
    );
    if options.polish() && unfinished {
        // Compound moves the per-iteration search cannot make (module `recovery::polish`).
        best = recovery.polish(problem, &best.0);
        if closes_gap(best.1, dual_bound) {
            termination = Termination::Optimal;
        } else if relative_gap(best.1, dual_bound) <= options.gap_tol() {
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

/// Iterations between two looks for tuples proven out of every solution better than the
/// incumbent ([`Relaxation::proven_out`]).
const PROVE_EVERY: usize = 10;

/// `current` without the tuples of `out` (proven out; sorted here), or `None` when they are
/// fewer than a tenth of its active ones: filtering the per-solve structures costs about an
/// iteration, so a smaller cut does not pay (a twentieth, or a look every 5 iterations, took
/// more instructions; CHANGELOG.md). The incumbent's tuples stay whatever `out` says (they
/// cannot be in it but for rounding).
///
/// Why the solve stays exact: every solution better than the incumbent avoids the tuples
/// proven out, so the reduced problem has the same optimum as `current`, and its relaxation's
/// `L(u)`, a bound on that optimum, bounds the original's too. The iterates do change: the
/// reduced relaxation is tighter (its `L(u)` at least the original's), and the recovery and
/// the polish choose among fewer tuples.
fn prove_out(current: &SdProblem, out: &mut [usize], incumbent: &[usize]) -> Option<SdProblem> {
    if out.len() * 10 < current.active().len() {
        return None;
    }
    out.sort_unstable();
    let kept: Vec<usize> = (current.active().iter().copied())
        .filter(|k| out.binary_search(k).is_err() || incumbent.contains(k))
        .collect();
    Some(current.with_active(kept))
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

/// One projected, deflected subgradient step `u ← min(0, u + t·d / |d|²)` with the
/// subgradient `g_s[i] = 1 − uses` and the direction `d = g + β·d_prev` ([`DEFLECTION`]),
/// projected; `numerator` is `α·(best primal − L(u))`; `d` is the caller's buffer, shaped as
/// `mult`, holding the previous direction on entry (zeros at first) and this one on return.
/// Returns false when `d` vanishes (nothing to do).
fn step(
    problem: &SdProblem,
    mult: &mut [Vec<f64>],
    relaxed: &[usize],
    numerator: f64,
    d: &mut [Vec<f64>],
) -> bool {
    for row in d.iter_mut().skip(2) {
        for di in row.iter_mut() {
            *di = 1.0 + DEFLECTION * *di;
        }
    }
    for &k in relaxed {
        for (s, &i) in problem.tuple(k).iter().enumerate().skip(2) {
            d[s][i] -= 1.0;
        }
    }
    let mut norm2 = 0.0;
    for s in 2..mult.len() {
        d[s][0] = 0.0;
        for (gi, ui) in d[s].iter_mut().zip(&mult[s]) {
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
        for (ui, gi) in mult[s].iter_mut().zip(&d[s]) {
            *ui = (*ui + t * gi).min(0.0);
        }
    }
    true
}

#[cfg(test)]
mod tests;
