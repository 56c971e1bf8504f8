//! The paper's intensity-ordered search (METHODS §2, steps 1–4). Eq. 11 is garbled in the
//! paper; this is the project's reading, stated rule by rule so it can be checked:
//!
//! 1. **Valid airspace (eq. 12–13).** `P_1..P_M` are the points of *all* intensity-S candidates
//!    of the input, `δ_bj` their distances, `d = (1/M) Σ_j (min_{b≠j} δ_bj + max_{b≠j} δ_bj)/2`.
//!    A candidate is a ghost and is dropped when its distance to the nearest *other* intensity-S
//!    point exceeds `d` (strictly). This is applied to every candidate of a searched level — the
//!    intensity-S points and the lower-intensity ones (paper: "establish the valid airspace,
//!    then form Z3, Z2") — always against the same reference set `P_1..P_M` (ghosts included,
//!    as in eq. 12 where j runs over all M points). With fewer than two intensity-S points `d`
//!    is undefined: nothing is dropped and the radius is reported as NaN. `valid_airspace =
//!    false` switches the step off.
//! 2. **Probability-intensity chain.** Within a level (the working set: the surviving candidates
//!    of one intensity), a candidate's *exclusive rays* `m` are its measurements used by no
//!    other candidate of the working set. A chain starts by accepting its start point; every
//!    accepted candidate deletes itself and every working candidate sharing a measurement with
//!    it, `m` is recomputed for the rest, and the next accepted is the one with the largest `m`
//!    (ties: smaller cost, then smaller index into the input), until the working set is empty.
//!    A chain therefore accepts a maximal conflict-free set.
//! 3. **Vote.** `H` is the set of working candidates of maximal `m` at the start of the level;
//!    one chain starts from each point of `H`. A candidate accepted by more than
//!    `vote_fraction · |H|` chains (strictly) is confirmed. `max_chains` (not in the paper;
//!    default `None` = every point of H) caps the chains per level for large scans: then the
//!    `max_chains` best points of H by (cost, index) start chains and the threshold is τ times
//!    that many. Each chain costs O(candidates of the level), and when ghosts abound every
//!    candidate has m = 0 and H is the whole level, so the full vote is quadratic. The paper's
//!    threshold is "the vast majority" with no number; the default τ = 0.5 (a strict majority)
//!    also guarantees that the confirmed set is conflict-free, since two candidates each in
//!    more than half of the chains share a chain. With τ < 0.5 conflicts are possible and are
//!    resolved greedily by votes (more first), then cost, then index.
//!
//!    With τ >= 0.5 the chains run in fixed batches and stop as soon as every candidate is
//!    either confirmed or can no longer reach the threshold with the chains left: the
//!    confirmed set is exactly the full vote's, and the remaining chains are skipped. The
//!    batches are fixed, so the chains run do not depend on the thread count.
//! 4. **Levels.** Every candidate that uses a measurement of a confirmed point is removed; the
//!    search repeats on intensity S − 1 (paper: Z3 then Z2), and on lower intensities down to
//!    `lowest_intensity` if asked (default S − 1, at least 2; the paper has S = 3). Result
//!    `T = T_S ∪ T_{S−1}`. Input tuples of other intensities are ignored.
//!
//! Everything is deterministic: chains run in parallel blocks whose vote counts are summed,
//! and integer sums do not depend on the order.

use super::airspace::PointIndex;
use super::chains::Level;
pub use super::intensity_input::IntensityInput;
use super::measurement_ids::MeasurementIds;
pub use super::options::IntensityOptions;
use crate::error::CoreResult;

/// One searched level.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelReport {
    pub intensity: usize,
    /// Working candidates at the start of the level.
    pub candidates: usize,
    /// |H|, or `max_chains` of it: the chains the vote is over.
    pub starts: usize,
    /// Chains actually run: fewer than `starts` when the vote was decided early (τ >= 0.5).
    pub chains: usize,
    pub confirmed: usize,
}

/// The chosen tuples (ascending indices into the input) and diagnostics.
#[derive(Clone, Debug, PartialEq)]
pub struct IntensityOutcome {
    pub chosen: Vec<usize>,
    /// `d` of eq. 13 (NaN when not computed).
    pub airspace_radius: f64,
    /// Candidates of the searched levels dropped as ghosts by the airspace test.
    pub ghosts_dropped: usize,
    /// Chains run, over all levels.
    pub chains: usize,
    pub levels: Vec<LevelReport>,
}

/// Runs the intensity-ordered search on enumerated candidates.
/// Whether the search over `candidates` candidate tuples runs on the calling thread alone:
/// every level's vote is then at most one block of chains (so a caller can skip the pool).
pub fn searches_sequentially(candidates: usize) -> bool {
    candidates <= super::chain_block::LANES
}

pub fn intensity_search(
    input: &IntensityInput,
    options: &IntensityOptions,
) -> CoreResult<IntensityOutcome> {
    let tau = options.vote_fraction();
    let s_count = input.n_sensors();
    let lowest = options.lowest_for(s_count)?;
    let k = input.len();
    let intensity: Vec<usize> = (0..k).map(|c| input.intensity(c)).collect();
    let searched: Vec<bool> = intensity.iter().map(|&i| i >= lowest).collect();
    let full: Vec<usize> = (0..k).filter(|&c| intensity[c] == s_count).collect();

    let mut alive = searched.clone();
    let (mut airspace_radius, mut ghosts_dropped) = (f64::NAN, 0);
    if options.valid_airspace() && full.len() >= 2 {
        let index = PointIndex::new(input, &full);
        let d = index.radius();
        airspace_radius = d;
        for (c, keep) in alive.iter_mut().enumerate() {
            if *keep && !index.has_neighbour_within(c, d) {
                *keep = false;
                ghosts_dropped += 1;
            }
        }
    }

    let (meas, n_meas) = MeasurementIds::new(input, &searched)?;
    let mut used = vec![false; n_meas];

    let mut chosen = Vec::new();
    let mut levels = Vec::new();
    let mut chains = 0;
    for level_intensity in (lowest..=s_count).rev() {
        let members: Vec<usize> = (0..k)
            .filter(|&c| {
                alive[c] && intensity[c] == level_intensity && meas.of(c).all(|m| !used[m as usize])
            })
            .collect();
        let level = Level::new(input, &members, level_intensity, n_meas, &meas);
        let starts = level.start_points(options.max_chains());
        let threshold = tau * starts.len() as f64;
        // With τ >= 0.5 the confirmed set is conflict-free, so only membership matters and the
        // vote may stop once it is decided; below 0.5 conflicts are settled by vote counts.
        let (votes, run) = level.vote(&starts, threshold, tau >= 0.5);
        let mut confirmed: Vec<usize> = (0..members.len())
            .filter(|&c| votes[c] as f64 > threshold)
            .collect();
        confirmed.sort_by(|&a, &b| {
            votes[b]
                .cmp(&votes[a])
                .then(level.costs[a].total_cmp(&level.costs[b]))
                .then(a.cmp(&b))
        });
        let mut count = 0;
        for c in confirmed {
            let mine = level.ids(c);
            if mine.iter().all(|&m| !used[m as usize]) {
                for &m in mine {
                    used[m as usize] = true;
                }
                chosen.push(members[c]);
                count += 1;
            }
        }
        chains += run;
        levels.push(LevelReport {
            intensity: level_intensity,
            candidates: members.len(),
            starts: starts.len(),
            chains: run,
            confirmed: count,
        });
    }
    chosen.sort_unstable();
    Ok(IntensityOutcome {
        chosen,
        airspace_radius,
        ghosts_dropped,
        chains,
        levels,
    })
}
