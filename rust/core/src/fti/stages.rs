//! The search and detection of one pass, in stages where the candidates are many (a project
//! extension, not in the paper; option `search_stage`).
//!
//! The paper descends every candidate, then runs detection (eq. 23) over all the optima by
//! decreasing R. Where the candidates are at most `search_stage` (the paper's scene: about
//! twenty a run) this module does exactly that. Where they number in the tens of thousands
//! (dense scenes, more sensors) most are ghosts made of rows of several targets: searching
//! them all would be most of the initiation's time, although detection rejects nearly all of
//! their optima because the targets accepted before them have taken their rows.
//!
//! **Stages.** Above `search_stage` candidates, they are ordered by the tracking gate's score
//! (decreasing; ties: lower index): how much likelier the rows a candidate's walk took are
//! from it than from clutter (module `tracking_gate`). The first `search_stage` are searched
//! and detection runs over their optima (on the 5-sensor scenes of the scale bench, few of
//! the candidates after them pass the gate again). Each later stage
//! searches the next `search_stage` candidates that still pass the support gate (both
//! parts) *on the rows detection has left*, as pass 2's candidates must; a candidate whose
//! support was rows that accepted targets now hold is their ghost or their duplicate, and
//! is not searched. After each stage detection starts again over every optimum so far, in
//! the detection order, on the rows free before the pass; so the one thing that differs from
//! detection's rule is which candidates are searched. With the support gate off a later stage
//! searches the candidates whose own four rows are all free. A candidate a stage's
//! re-gating drops is not reconsidered, even if a later detection frees the rows it lacked.
//!
//! Past one stage the candidates arrive compact (module `pool`): each stage refits the ones
//! it searches or re-gates, the same candidates bit for bit.

use std::time::Instant;

use rayon::prelude::*;

use super::candidate::Candidate;
use super::closeness::{closeness, Precomputed};
use super::descent::{descend_all, Optimum};
use super::detection_order::detect;
use super::merge::merge;
use super::options::InitiationOptions;
use super::pool::Pool;
use super::problem::Problem;
use super::scans::Scans;
use super::support::{Gate, SupportTable};
use crate::progress::Tally;

/// What one pass's search and detection produced.
pub(super) struct Searched {
    /// Every optimum, in the order searched.
    pub(super) optima: Vec<Optimum>,
    /// Indices into `optima` of those detection accepted, in acceptance order.
    pub(super) accepted: Vec<usize>,
    /// Optima left after merging all of them.
    pub(super) merged: usize,
    /// Time spent in detection, within the whole call's.
    pub(super) seconds_detection: f64,
    /// Time spent re-gating the candidates between stages, within the whole call's.
    pub(super) seconds_regate: f64,
}

/// Searches `candidates` and runs detection on the rows still `available`, with the
/// support `gate` of the pass when it is on (module doc).
pub(super) fn search_and_detect(
    problem: &Problem<'_>,
    pre: &Precomputed,
    scans: &Scans,
    candidates: &Pool,
    options: &InitiationOptions,
    gate: Option<&Gate<'_>>,
    available: &mut [bool],
) -> Searched {
    let dim = problem.layout.dim();
    let stage = options.search_stage().unwrap_or(usize::MAX).max(1);
    let free_before = available.to_vec();
    let mut out = Searched {
        optima: Vec::new(),
        accepted: Vec::new(),
        merged: 0,
        seconds_detection: 0.0,
        seconds_regate: 0.0,
    };
    let mut queue = search_order(problem, pre, candidates, stage);
    let mut batch: Vec<usize> = queue.drain(..stage.min(queue.len())).collect();
    let mut searched = 0u64;
    (problem.progress).report("search", 0.0);
    while !batch.is_empty() && !problem.stopped() {
        // Of the candidates searched and those still queued (re-gating shrinks the queue).
        let all = searched + (batch.len() + queue.len()) as u64;
        let tally = Tally::resumed(problem.progress, "search", searched, all);
        searched += batch.len() as u64;
        let taken = candidates.get_all(problem, &batch);
        let starts: Vec<&Candidate> = taken.iter().map(|c| c.as_ref()).collect();
        let optima = descend_all(pre, &starts, options.descent(), &tally);
        tally.finish();
        drop(taken);
        // Moved, not copied, on the first stage: a one-stage pass holds them once.
        match out.optima.is_empty() {
            true => out.optima = optima,
            false => out.optima.extend(optima),
        }
        if problem.stopped() {
            break; // the pipeline raises; the descents' partial output is not merged
        }
        let order = merge(&out.optima, dim, options.merge_tol());
        let clock = Instant::now();
        available.copy_from_slice(&free_before);
        out.accepted = detect(problem, scans, &out.optima, &order, options, available);
        out.seconds_detection += clock.elapsed().as_secs_f64();
        out.merged = order.len();
        let clock = Instant::now();
        queue = still_kept(problem, scans, candidates, queue, gate, available);
        out.seconds_regate += clock.elapsed().as_secs_f64();
        batch = queue.drain(..stage.min(queue.len())).collect();
    }
    (problem.progress).report("search", 1.0);
    out
}

/// The candidates of `queue` (in its order) that pass the support `gate` on the rows still
/// `available`, or, with the gate off, whose own rows all are.
fn still_kept(
    problem: &Problem<'_>,
    scans: &Scans,
    candidates: &Pool,
    queue: Vec<usize>,
    gate: Option<&Gate<'_>>,
    available: &[bool],
) -> Vec<usize> {
    if queue.is_empty() {
        return queue;
    }
    let Some(gate) = gate else {
        let free = |i: &usize| candidates.rows(*i).iter().all(|&m| available[m]);
        return queue.into_iter().filter(free).collect();
    };
    let table = SupportTable::of_rows(problem, scans, Some(available));
    let gate = Gate {
        table: &table,
        ..*gate
    };
    let keep: Vec<bool> = (queue.par_iter())
        .map(|&i| (candidates.get(problem, i)).is_some_and(|c| gate.keeps(problem, &c).is_some()))
        .collect();
    queue
        .into_iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(i, _)| i)
        .collect()
}

/// Candidate indices in search order: as given when they fit in one `stage`, else by
/// decreasing tracking-gate score (ties: lower index), or by decreasing R at their estimates
/// when the support gate is off (no scores).
fn search_order(
    problem: &Problem<'_>,
    pre: &Precomputed,
    candidates: &Pool,
    stage: usize,
) -> Vec<usize> {
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    if candidates.len() <= stage {
        return order;
    }
    let scores: Option<Vec<f64>> = (0..candidates.len()).map(|i| candidates.score(i)).collect();
    let key: Vec<f64> = match scores {
        Some(scores) => scores,
        // No gate, no scores: the pool is whole (module `pool`), so no refit happens here.
        None => (0..candidates.len())
            .into_par_iter()
            .map(|i| {
                let c = candidates.get(problem, i);
                c.map_or(f64::NAN, |c| closeness(pre, &c.estimate[..pre.dim()]))
            })
            .collect(),
    };
    // A NaN key (a non-finite estimate) goes last.
    let key: Vec<f64> = (key.into_iter())
        .map(|v| if v.is_nan() { f64::NEG_INFINITY } else { v })
        .collect();
    order.sort_by(|&i, &j| key[j].total_cmp(&key[i]).then(i.cmp(&j)));
    order
}

#[cfg(test)]
mod tests {
    use crate::fti::options::InitiationOptions;
    use crate::fti::tests::run;
    use crate::fti::tests::sim;
    use crate::parallel::with_threads;

    /// Within one stage the search is the paper's; in stages of 4 the same targets are found
    /// from fewer searches, on one thread as on all, with the support gate on (later stages re-gated on the free rows)
    /// and off (later stages need their own rows free), and every row still ends in one track
    /// or in clutter.
    #[test]
    fn stages_find_the_targets_from_fewer_searches() {
        for (seed, support_gate) in [(2024, true), (7, true), (2024, false)] {
            let sc = sim::paper(seed, true, 16, 8);
            let base = InitiationOptions::default().with_support_gate(support_gate);
            let staged = |stage| base.clone().with_search_stage(stage).expect("valid");
            let paper = run(&sc, &staged(None)).expect("runs");
            let one_stage = run(&sc, &staged(Some(usize::MAX))).expect("runs");
            let in_fours = run(&sc, &staged(Some(4))).expect("runs");
            let on_one_thread = with_threads(Some(1), || run(&sc, &staged(Some(4))))
                .expect("threads")
                .expect("runs");
            assert_eq!(on_one_thread.labels, in_fours.labels);
            assert_eq!(on_one_thread.stage_counts, in_fours.stage_counts);
            assert_eq!(one_stage.labels, paper.labels);
            assert_eq!(one_stage.stage_counts, paper.stage_counts);

            let (searched, all) = (in_fours.stage_counts.optima, paper.stage_counts.optima);
            assert!(searched < all && searched >= 4, "{searched} of {all}");
            assert_eq!(in_fours.tracks.len(), 4, "seed {seed}");
            // Each track holds at least two thirds of its rows from one target, and no two
            // tracks the same target.
            let mut owners: Vec<i64> = (in_fours.tracks.iter())
                .map(|track| {
                    let rows = &track.measurements;
                    let from = |o: i64| rows.iter().filter(|&&m| sc.truth[m] == o).count();
                    let owner = (0..4).max_by_key(|&o| from(o)).unwrap_or(-1);
                    assert!(3 * from(owner) >= 2 * rows.len(), "seed {seed}: {rows:?}");
                    owner
                })
                .collect();
            owners.sort_unstable();
            assert_eq!(owners, [0, 1, 2, 3], "seed {seed}, gate {support_gate}");
            assert_eq!(in_fours.labels.len(), sc.truth.len());
            let labelled = (in_fours.labels.iter()).filter(|&&l| l >= 0).count();
            let held: usize = in_fours.tracks.iter().map(|t| t.measurements.len()).sum();
            assert_eq!(labelled, held);
        }
    }
}
