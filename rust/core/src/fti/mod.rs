//! Fuzzy track initiation (METHODS §1, paper 000) for ≥ 2 passive sensors, any number of
//! scans, asynchronous sampling and missed detections, in 3-D (azimuth/elevation, 6-D X0) and
//! 2-D (bearing only, 4-D X0) from the same code.
//!
//! The pipeline ([`initiate`]), one private module per stage, from the bottom up; the public
//! API is what this module re-exports, and this module holds nothing else:
//!
//! 0. `problem` ([`Problem`]): the data of one call, as every stage reads it; `output`
//!    ([`Initiation`]): what the call returns, with the per-stage counts and times.
//! 1. `scans` ([`Scans`]): a scan is the rows of one sensor with one exact time value; each
//!    sensor's first and last scan in the table feed the candidates (and, in a second pass on
//!    the rows the first pass's detection left, the next-outermost scans: `candidate_scans`).
//! 2. `candidates` ([`generate_candidates`]): for each sensor pair (a, b), one measurement
//!    from each of a-first, b-first, a-last, b-last (eq. 20–22). The product is never
//!    materialised: first-scan ray pairs and last-scan ray pairs are formed and pruned
//!    separately (`ray_pairs`), then combined (`combine`, with the motion-corrected ray gate
//!    of `motion_gate`) and fitted by Gauss-Newton in parallel batches (`batch`). One
//!    candidate and its fit are `candidate` ([`Candidate`]); the fitted candidates wait in a
//!    `pool` ([`Pool`]). Every pruning rule is optional; with all off every 4-tuple is
//!    fitted, which is the paper's unpruned algorithm.
//! 3. `closeness` ([`closeness`]): the fuzzy synthetic closeness R(X0) (eq. 17–18) and its
//!    gradient.
//! 4. `support`: candidates fewer than Nd scans support are dropped (project extension): the
//!    fixed gate there, then the walk of `tracking_gate`.
//! 5. `descent` ([`descend`]): steepest ascent of R from each surviving candidate (eq. 19);
//!    `merge` merges the optima, and `stages` searches in stages when there are many.
//! 6. `detection` and `detection_order`: detection (eq. 23) and ambiguity resolution
//!    (eq. 24).
//! 7. `pipeline` ([`initiate`]): the driver, forming candidates in passes over the slots of
//!    `formation_slots`; the end of the pipeline is the Gauss-Newton
//!    refit of each track (`refit`), the join of split tracks (`track_join`), the exchange of
//!    rows between tangled tracks (`track_swap`) and the track test (`track_quality`, with
//!    the coverage test of `coverage`; its levels come from `quantiles`).
//!
//! The settings are `options` ([`InitiationOptions`]) and `descent_options`
//! ([`DescentOptions`]); the tests of the whole initiation and their simulator are `tests`.
//!
//! Parallel stages (fits, descents, final fits) run on rayon and collect in input order; the
//! sequential stages are order-defined, so results are bit-identical for any thread count.

mod angle_index;
mod batch;
mod candidate;
mod candidates;
mod closeness;
mod combine;
mod coverage;
mod descent;
mod descent_options;
mod detection;
mod detection_order;
mod formation_choice;
mod formation_slots;
mod meeting;
mod merge;
mod motion_gate;
mod neighbourhood;
mod options;
mod output;
mod pipeline;
mod pool;
mod problem;
mod quantiles;
mod ray_pairs;
mod reach_grid;
mod refit;
mod round_gate;
mod row_window;
mod scans;
mod stages;
mod support;
mod track_join;
mod track_quality;
mod track_swap;
mod tracking_gate;
mod witness_gate;

#[cfg(test)]
mod tests;

pub use candidate::Candidate;
pub use candidates::generate as generate_candidates;
pub use closeness::{closeness, closeness_and_gradient, closeness_batch, Precomputed, Spreads};
pub use descent::{descend, descend_from};
pub use descent_options::{DescentOptions, Scaling};
pub use formation_choice::Formation;
pub use neighbourhood::Neighbourhood;
pub use options::{DetectionOrder, InitiationOptions, CHI2_2DOF_999, TRACK_TEST};
pub use output::{FormationLimit, Initiation, StageCounts, StageSeconds, Track};
pub use pipeline::{initiate, initiate_reporting};
pub use pool::{CandidateSet, Pool};
pub use problem::Problem;
pub use quantiles::{chi2_quantile, normal_quantile};
pub use scans::{resolve_pairs, Scans, Slot};
