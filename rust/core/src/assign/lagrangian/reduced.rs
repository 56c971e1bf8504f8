//! Reduced tuple costs under the multipliers, shared by the relaxation and the recovery.

use crate::assign::SdProblem;

/// Tuple cost minus the multipliers of sensors `from..S`.
pub(crate) fn modified(problem: &SdProblem, mult: &[Vec<f64>], k: usize, from: usize) -> f64 {
    let t = problem.tuple(k);
    problem.costs()[k] - (from..t.len()).map(|s| mult[s][t[s]]).sum::<f64>()
}

/// Keeps the cheaper `(cost, tuple)`; ties go to the lower tuple index (determinism).
pub(crate) fn keep_min(slot: &mut (f64, usize), cand: (f64, usize)) {
    if cand.0 < slot.0 || (cand.0 == slot.0 && cand.1 < slot.1) {
        *slot = cand;
    }
}

pub(crate) const EMPTY: (f64, usize) = (f64::INFINITY, usize::MAX);
