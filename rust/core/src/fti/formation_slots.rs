//! Which scan slots each candidate formation forms, and in what order: the paper's first ×
//! last scans of every sensor pair (witnessed or not), and the rounds formation's (pair,
//! round) slots, best first. The passes that form candidates from them are module
//! `pipeline`'s.

use super::options::InitiationOptions;
use super::problem::Problem;
use super::scans::{Scans, Slot, WitnessNeed};

/// Which scans test the candidates of the paper's slots before their fit (module
/// `witness_gate`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum SlotWitnesses {
    /// None: the paper's formation.
    Untested,
    /// Every scan of the sensors outside the pair, more than half of which must see a
    /// candidate. A ghost of two sensors' bearings passes one scan of a third often in a
    /// cluttered plane, but seldom most of them, while a target at Pd 0.9 is seen in 5 of 8
    /// with probability 0.995 (the choice against 4 and 6 of 8 is measured in CHANGELOG.md).
    OtherSensors,
    /// The pair's own scans outside the slot, of which a candidate needs what detection will:
    /// more than `n_detect` rows with its own four, so at least `n_detect − 3` (and at least
    /// one). A candidate seen in fewer could not become a target; the support gate would drop
    /// it after its fit, and this drops it before. For fewer than three sensors that scan
    /// twice or more, where a third sensor's one scan (if any) is too little to ask.
    OwnScans { n_detect: usize },
}

impl SlotWitnesses {
    /// The witnesses of the witnessed formation, or of the paper's (`witnessed` false), in a
    /// table where `sensors_with_scans` sensors scan twice or more.
    pub(super) fn choose(
        witnessed: bool,
        sensors_with_scans: usize,
        options: &InitiationOptions,
        scans: &Scans,
    ) -> Self {
        match witnessed {
            false => Self::Untested,
            true if sensors_with_scans >= 3 => Self::OtherSensors,
            true => Self::OwnScans {
                n_detect: options.n_detect_for(scans.len()),
            },
        }
    }
}

/// The paper's slots of every pair ([`Scans::scan_slots`]), pair by pair, with the
/// `witnesses` their candidates are tested against.
pub(super) fn paper_slots(
    scans: &Scans,
    pairs: &[[usize; 2]],
    depth: usize,
    inner: bool,
    witnesses: SlotWitnesses,
) -> Vec<Slot> {
    let mut slots = Vec::new();
    for &[a, b] in pairs {
        let others: Vec<usize> = (scans.per_sensor.iter().enumerate())
            .filter(|&(j, _)| witnesses == SlotWitnesses::OtherSensors && j != a && j != b)
            .flat_map(|(_, own)| own.iter().copied())
            .collect();
        let pair_scans = || {
            scans.per_sensor[a]
                .iter()
                .chain(&scans.per_sensor[b])
                .copied()
        };
        slots.extend(scans.scan_slots([a, b], depth, inner).into_iter().map(|s| {
            match witnesses {
                SlotWitnesses::Untested => Slot::untested(s),
                SlotWitnesses::OtherSensors => Slot {
                    witnesses: others.clone(),
                    witness_need: WitnessNeed::Majority,
                    ..Slot::untested(s)
                },
                SlotWitnesses::OwnScans { n_detect } => Slot {
                    witnesses: pair_scans().filter(|k| !s.contains(k)).collect(),
                    witness_need: WitnessNeed::AtLeast(
                        n_detect.saturating_sub(
                            std::env::var("PA_OWN_SUB")
                                .ok()
                                .and_then(|v| v.parse().ok())
                                .unwrap_or(3),
                        ),
                    ),
                    ..Slot::untested(s)
                },
            }
        }));
    }
    slots
}

/// Each scan's time (its rows share one).
fn scan_times(problem: &Problem<'_>, scans: &Scans) -> Vec<f64> {
    (0..scans.len())
        .map(|k| problem.measurements.time(scans.scan(k)[0]))
        .collect()
}

/// Every (pair, round) slot, best first: each pair's most nearly synchronous rounds nearest the
/// middle first; then the pairs' best slots, their second best, and so on.
pub(super) fn ranked_rounds(
    problem: &Problem<'_>,
    scans: &Scans,
    pairs: &[[usize; 2]],
    options: &InitiationOptions,
) -> Vec<Slot> {
    let times = scan_times(problem, scans);
    // Each pair's slots best first; then the pairs' best slots, their second best, and so on.
    let mut ranked: Vec<((usize, f64), Slot)> = Vec::new();
    for &pair in pairs {
        let mut round = scans.round_slots(pair, &times);
        if !options.prefit_gates() {
            round = round.into_iter().map(|s| Slot::untested(s.scans)).collect();
        }
        let middle = round.len() as f64 / 2.0;
        let mut scored: Vec<(f64, Slot)> = (round.into_iter().enumerate())
            .map(|(k, slot)| {
                let [a0, b0, a1, b1] = slot.scans;
                let skew = (times[a0] - times[b0]).abs() + (times[a1] - times[b1]).abs();
                let span = (times[a1] - times[a0]).abs().max(1e-9);
                let off_middle = ((k as f64 + 0.5) - middle).abs() / middle.max(1.0);
                (skew / span + 0.25 * off_middle, slot)
            })
            .collect();
        scored.sort_by(|a, b| a.0.total_cmp(&b.0));
        ranked.extend(
            (scored.into_iter().enumerate()).map(|(rank, (score, slot))| ((rank, score), slot)),
        );
    }
    ranked.sort_by(|a, b| (a.0 .0).cmp(&b.0 .0).then(a.0 .1.total_cmp(&b.0 .1)));
    ranked.into_iter().map(|(_, slot)| slot).collect()
}
