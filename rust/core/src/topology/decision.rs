//! One scan's pairs from a score matrix (METHODS §4 "Decision").
//!
//! Scores are "higher is better": the closeness W for topology, minus the distance for the
//! nearest-neighbour baseline. Entries that are NaN are forbidden (outside the position gate,
//! or no score). A pair needs a score strictly above the threshold.

use super::options::Decision;
use crate::assign::lap::{solve_sparse, SparseCosts};
use crate::error::CoreResult;

/// `(local row, system column)` pairs, ascending by row.
pub fn decide(
    scores: &[f64],
    n_local: usize,
    n_system: usize,
    threshold: f64,
    decision: Decision,
) -> CoreResult<Vec<(usize, usize)>> {
    let allowed = |i: usize, j: usize| {
        let s = scores[i * n_system + j];
        (s > threshold).then_some(s)
    };
    match decision {
        Decision::Assignment => max_margin(n_local, n_system, threshold, allowed),
        Decision::PerSystemTrack => Ok(per_system_track(n_local, n_system, allowed)),
    }
}

/// One-to-one pairs maximising the total score above the threshold, `Σ (score − threshold)`:
/// the project's sparse 2-D solver on costs `threshold − score` (< 0 for every allowed
/// pair) with free non-assignment, so only allowed pairs are ever made. For distances this
/// is the usual gated assignment: cost `d − gate`.
fn max_margin(
    n_local: usize,
    n_system: usize,
    threshold: f64,
    allowed: impl Fn(usize, usize) -> Option<f64>,
) -> CoreResult<Vec<(usize, usize)>> {
    let mut triplets = Vec::new();
    for i in 0..n_local {
        for j in 0..n_system {
            if let Some(s) = allowed(i, j) {
                triplets.push((i, j, threshold - s));
            }
        }
    }
    let costs = SparseCosts::from_triplets(n_local, n_system, &triplets)?;
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
    allowed: impl Fn(usize, usize) -> Option<f64>,
) -> Vec<(usize, usize)> {
    let mut claim: Vec<Option<(f64, usize)>> = vec![None; n_local];
    for j in 0..n_system {
        let best = (0..n_local)
            .filter_map(|i| allowed(i, j).map(|s| (s, i)))
            .fold(None, |acc: Option<(f64, usize)>, (s, i)| match acc {
                Some((best, _)) if best >= s => acc,
                _ => Some((s, i)),
            });
        if let Some((s, i)) = best {
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
