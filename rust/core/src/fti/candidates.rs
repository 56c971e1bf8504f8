//! Candidate targets (METHODS §1 eq. 20–22): one measurement from each of a-first, b-first,
//! a-last, b-last of a sensor pair (a, b), fitted by Gauss-Newton ML.
//!
//! The product of the four scans is never materialised. The first-scan rays of a and b are
//! paired and the pair-level rules applied; likewise the last-scan rays; then surviving
//! first-pairs × last-pairs are combined under the v_max rule (module `combine`: a grid over
//! the meetings, parallel tests, a cap on the work) and fitted in large batches (module
//! `batch`: in parallel, collected in order). The rounds formation's slots are paired and
//! tested a few at once ([`SLOTS_AT_ONCE`]), then queued for their fits one after another,
//! as one slot at a time would queue them. A candidate and its fit are module
//! `candidate`, its ray pairs and the pair-level rules module `ray_pairs`; this module is the
//! stage's driver. The pruning rules, each optional:
//!
//! * **ray gate** (3-D only; `ray_gate_sigmas` in σ): the two rays' closest-point distance must be
//!   ≤ `ray_gate_sigmas·√((σ_a·r_a)² + (σ_b·r_b)²) + v_max·|t_a − t_b|`. The first term is the
//!   lateral spread of each ray at its range r from angle noise, with σ_j = max(σβ_j, σε_j)
//!   (conservative: never rejects more than the larger angle's noise allows). The second is
//!   how far the target moves between asynchronous samples: without it the gate would reject
//!   the true rays of any moving target seen at different times. When the two times differ
//!   and `v_max` is off the motion is unbounded and the gate passes the pair (the rule is
//!   vacuous there). In 2-D two bearing lines always meet, so the rule does not exist.
//! * **behind-sensor**: the meeting point must be in front of both sensors (positive ranges).
//! * **v_max**: the speed implied by the first and last meeting midpoints (each at the mean
//!   time of its two rays) must be ≤ `v_max`. Give a margin: midpoints carry noise. The
//!   `v_max` count also applies the motion-corrected ray gate (module `motion_gate`).
//! * **χ² gate** (3-D only): after the fit, λ ≤ `chi2_gate` (default χ²(2) 99.9 % = 13.8155:
//!   8 equations, 6 unknowns). In 2-D the 4 bearings give 4 equations for 4 unknowns: the fit
//!   is exact (λ = 0 up to rounding) and the gate has no information, so it is skipped.
//!
//! A ray pair without a unique meeting (parallel rays) fails every enabled geometric rule;
//! with the rules off its candidate starts from the pseudo-linear solution instead.

use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use super::batch::{Batch, ScanPairRays};
use super::combine::Combination;
use super::options::InitiationOptions;
use super::pool::{CandidateSet, Pool};
use super::problem::Problem;
use super::ray_pairs::ray_pairs;
use super::round_gate::{RoundGate, RoundMeetings};
use super::scans::{Scans, Slot};
use super::support::Gate;
use super::witness_gate::Witnesses;
use crate::error::{CoreError, CoreResult};
use crate::progress::{Muted, Progress, Tally};

/// Generates, prunes and fits the candidates of every slot's scan quadruple `[a-first,
/// b-first, a-last, b-last]` (see [`Scans::scan_slots`], [`Scans::round_slots`]), in order,
/// from the rows that are `available` (every row when `None`), testing each against the
/// slot's rounds (module `round_gate`), keeping those the support `gate` keeps (all when
/// `None`).
pub fn generate(
    problem: &Problem<'_>,
    scans: &Scans,
    slots: &[Slot],
    available: Option<&[bool]>,
    options: &InitiationOptions,
    gate: Option<&Gate<'_>>,
) -> CoreResult<CandidateSet> {
    // One batch across the slots (module `batch`).
    let batch = Batch::new(problem, options, gate);
    generate_at_once(problem, scans, slots, available, options, batch, 1)
}

/// [`generate`] in `batch`, one batch across the slots (module `batch`; the tests shrink its
/// limits), forming and testing `at_once` slots together (at least one, [`SLOTS_AT_ONCE`]).
pub(super) fn generate_at_once(
    problem: &Problem<'_>,
    scans: &Scans,
    slots: &[Slot],
    available: Option<&[bool]>,
    options: &InitiationOptions,
    mut batch: Batch<'_>,
    at_once: usize,
) -> CoreResult<CandidateSet> {
    let at_once = at_once.max(1);
    let start = Instant::now();
    let mut set = CandidateSet {
        // Compact past one stage when the gate scores them (module `pool`).
        candidates: Pool::new(options.search_stage().filter(|_| batch.gated())),
        ..CandidateSet::default()
    };
    let rows_of = |k: usize| -> Vec<usize> {
        let rows = scans.scan(k).iter().copied();
        rows.filter(|&m| available.is_none_or(|a| a[m])).collect()
    };
    let tally = Tally::new(problem.progress, "candidates", slots.len() as u64);
    let gate = batch.support();
    let (mut limit, mut slots_formed) = (None, slots.len());
    'slots: for (window, group) in slots.chunks(at_once).enumerate() {
        // A slot alone reports its own progress; slots tested together report as each is
        // queued (their fractions, interleaved, would make the bar jump about).
        let muted = Muted(problem.progress);
        let alone = tally.unit((window * at_once) as u64);
        let progress: &dyn Progress = if group.len() == 1 { &alone } else { &muted };
        let formed: Vec<Formed<'_>> = group
            .par_iter()
            .map(|slot| form_slot(problem, slot, &rows_of, progress, options, gate))
            .collect();
        for (k, formed) in formed.into_iter().enumerate() {
            let index = window * at_once + k;
            // The rest of a slot, tested as it is queued, reports its own progress.
            let unit = tally.unit(index as u64);
            let slot_problem = Problem {
                progress: &unit,
                ..*problem
            };
            match queue_slot(&slot_problem, formed, options, &mut batch, &mut set) {
                Err(reached @ CoreError::CapExceeded { .. }) if options.stop_at_limit() => {
                    (limit, slots_formed) = (Some(reached.to_string()), index);
                    break 'slots;
                }
                other => other?,
            }
            tally.within(index as u64, 1.0);
        }
    }
    (set.limit, set.slots_formed) = (limit, slots_formed);
    if !problem.stopped() {
        batch.flush(&mut set)?;
    }
    set.seconds_enumerate = start.elapsed().as_secs_f64() - set.seconds_fit - set.seconds_support;
    Ok(set)
}

/// Slots of the rounds formation formed and tested at once before they are queued in order:
/// one slot's serial steps (gathering its ray pairs, locating their meetings, queueing) leave
/// the second thread idle, which another slot's tests fill (ring 5 × 100: the candidate stage
/// 5–10 % shorter on two threads). The rounds' slots are many and each is small (two rounds,
/// tested by witnesses; without the tests, `prefit_gates=False`, one at a time). The paper's
/// first × last slots are formed one at a time: they are few and large, and where the limit
/// is reached slots tested together are tested in vain (2-D 3 × 20 at 4× clutter, in a build
/// not kept that formed them four at once, each testing its whole slot ahead: up to a third
/// slower and 35 MB more; CHANGELOG.md).
pub(super) const SLOTS_AT_ONCE: usize = 4;

/// One slot's ray pairs and tests, counted and not yet queued ([`queue_slot`]).
struct Formed<'t> {
    raw: usize,
    rays: CoreResult<Rays<'t>>,
}

/// A slot's ray pairs, what they counted, and their tests (some done ahead).
struct Rays<'t> {
    ray_gate: usize,
    behind: usize,
    tests: CoreResult<Combination<'t>>,
}

/// Forms and tests the candidates of one slot (the combination reports how far through the
/// slot it is to `within`, a fraction of the whole stage).
fn form_slot<'t>(
    problem: &Problem<'_>,
    slot: &Slot,
    rows_of: &(dyn Fn(usize) -> Vec<usize> + Sync),
    within: &dyn Progress,
    options: &InitiationOptions,
    gate: Option<&'t Gate<'t>>,
) -> Formed<'t> {
    let [sa1, sb1, sa2, sb2] = slot.scans.map(rows_of);
    let raw = [sa1.len(), sb1.len(), sa2.len(), sb2.len()]
        .iter()
        .fold(1usize, |p, &n| p.saturating_mul(n));
    let rays = (|| {
        let (firsts, f_ray) = ray_pairs(problem, &sa1, &sb1, options)?;
        let (lasts, l_ray) = ray_pairs(problem, &sa2, &sb2, options)?;
        let (ray_gate, behind) = (
            f_ray.saturating_mul(l_ray),
            firsts.len().saturating_mul(lasts.len()),
        );
        let slot_problem = Problem {
            progress: within,
            ..*problem
        };
        let rays = ScanPairRays {
            firsts: Arc::new(firsts),
            lasts: Arc::new(lasts),
        };
        let round_gate = match slot.is_tested() {
            false => None,
            true => {
                let table = gate.map_or(&[][..], |g| &g.table.scans[..]);
                let witnesses = Witnesses::new(table, &slot.witnesses, slot.witness_need);
                // Witnesses, where there are any, decide alone (module `round_gate`): the
                // pair's other rounds are then never read, so they are not built.
                let mut rounds = Vec::with_capacity(slot.tested.len());
                for &[a, b] in slot.tested.iter().filter(|_| !witnesses.asks()) {
                    let (pairs, _) = ray_pairs(problem, &rows_of(a), &rows_of(b), options)?;
                    rounds.push(RoundMeetings::new(problem.layout.space, &pairs));
                }
                let (space, need) = (problem.layout.space, slot.need);
                let located = [&rays.firsts[..], &rays.lasts[..]];
                Some(RoundGate::new(space, rounds, need, witnesses, located))
            }
        };
        let tests = Combination::new(&slot_problem, rays, round_gate, options).map(|mut c| {
            c.test_ahead(&slot_problem, options);
            c
        });
        Ok(Rays {
            ray_gate,
            behind,
            tests,
        })
    })();
    Formed { raw, rays }
}

/// Counts a formed slot and queues its survivors for their fits, in the order of a plain
/// double loop: the same candidates, counts and errors as forming the slots one at a time.
fn queue_slot(
    problem: &Problem<'_>,
    formed: Formed<'_>,
    options: &InitiationOptions,
    batch: &mut Batch<'_>,
    set: &mut CandidateSet,
) -> CoreResult<()> {
    set.counts.raw = set.counts.raw.saturating_add(formed.raw);
    let rays = formed.rays?;
    set.counts.ray_gate = set.counts.ray_gate.saturating_add(rays.ray_gate);
    set.counts.behind = set.counts.behind.saturating_add(rays.behind);
    rays.tests?.queue(problem, options, batch, set)
}
