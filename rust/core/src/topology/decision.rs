//! One scan's pairs from the scores of its candidate pairs (METHODS §4 "Decision").
//!
//! Scores are "higher is better": the closeness W for topology, minus the distance for the
//! nearest-neighbour baseline. A pair needs a score strictly above the threshold; pairs
//! that are not candidates (outside the position gate) are never made.

use super::candidates::Candidates;
use super::options::Decision;
use crate::assign::lap::{solve_sparse, SparseCosts};
use crate::error::{CoreError, CoreResult};

/// `(local row, system row)` pairs, ascending by local row. `pairs` and `scores` are the
/// candidates and their (window-averaged) scores.
pub fn decide(
    pairs: &Candidates,
    scores: &[f64],
    (n_local, n_system): (usize, usize),
    threshold: f64,
    decision: Decision,
) -> CoreResult<Vec<(usize, usize)>> {
    let allowed = scores
        .iter()
        .enumerate()
        .filter(|&(_, &s)| s > threshold)
        .map(|(k, &s)| {
            let (i, j) = pairs.pair(k);
            (i, j, s)
        });
    match decision {
        // The fused decision (fusion.rs) assigns on its own scores through this rule.
        Decision::Assignment | Decision::Fused => max_margin(n_local, n_system, threshold, allowed),
        Decision::PerSystemTrack => Ok(per_system_track(n_local, n_system, allowed)),
    }
}

/// One-to-one pairs maximising the total score above the threshold, `Σ (score − threshold)`
/// (the stop request is polled between building the costs and solving, `Interrupted`):
/// the project's sparse 2-D solver on costs `threshold − score` (< 0 for every allowed
/// pair) with free non-assignment, so only allowed pairs are ever made. For distances this
/// is the usual gated assignment: cost `d − gate`.
fn max_margin(
    n_local: usize,
    n_system: usize,
    threshold: f64,
    allowed: impl Iterator<Item = (usize, usize, f64)>,
) -> CoreResult<Vec<(usize, usize)>> {
    let stop = || match crate::parallel::interrupted() {
        true => Err(CoreError::Interrupted),
        false => Ok(()),
    };
    let triplets: Vec<(usize, usize, f64)> =
        allowed.map(|(i, j, s)| (i, j, threshold - s)).collect();
    stop()?;
    let costs = SparseCosts::from_triplets(n_local, n_system, &triplets)?;
    stop()?;
    let solved = solve_sparse(&costs, &vec![0.0; n_local], &vec![0.0; n_system])?;
    Ok(solved
        .row_to_col
        .iter()
        .enumerate()
        .filter_map(|(i, j)| j.map(|j| (i, j)))
        .collect())
}

/// The paper's rule: every system track takes its best local track above the threshold
/// (ties: the lower row); a local track claimed by several keeps the highest score (ties:
/// the lower column), the others stay unpaired.
fn per_system_track(
    n_local: usize,
    n_system: usize,
    allowed: impl Iterator<Item = (usize, usize, f64)>,
) -> Vec<(usize, usize)> {
    let mut best: Vec<Option<(f64, usize)>> = vec![None; n_system];
    for (i, j, s) in allowed {
        match best[j] {
            Some((held, row)) if held > s || (held == s && row < i) => {}
            _ => best[j] = Some((s, i)),
        }
    }
    let mut claim: Vec<Option<(f64, usize)>> = vec![None; n_local];
    for (j, b) in best.iter().enumerate() {
        if let Some((s, i)) = *b {
            match claim[i] {
                Some((held, _)) if held >= s => {}
                _ => claim[i] = Some((s, j)),
            }
        }
    }
    claim
        .iter()
        .enumerate()
        .filter_map(|(i, c)| c.map(|(_, j)| (i, j)))
        .collect()
}
