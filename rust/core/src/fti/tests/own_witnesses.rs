//! The witnessed formation at two sensors (a project extension): the paper's slots, each
//! candidate asked of the pair's own scans outside the slot before its fit, as many of them
//! as detection will need.

use super::{assert_partition, run, sim};
use crate::fti::formation_slots::paper_slots;
use crate::fti::scans::{Scans, WitnessNeed};
use crate::fti::{Formation, InitiationOptions};

#[test]
fn the_need_counts_the_witness_scans() {
    assert_eq!(WitnessNeed::Half.of(5), 3);
    assert_eq!(WitnessNeed::Half.of(4), 2);
    assert_eq!(WitnessNeed::Majority.of(4), 3);
    assert_eq!(WitnessNeed::AtLeast(6).of(12), 6);
    assert_eq!(
        WitnessNeed::AtLeast(0).of(4),
        1,
        "a witness scan asked is needed once"
    );
    assert_eq!(WitnessNeed::AtLeast(9).of(4), 4, "no more than there are");
    for need in [
        WitnessNeed::Half,
        WitnessNeed::Majority,
        WitnessNeed::AtLeast(3),
    ] {
        assert_eq!(need.of(0), 0, "nothing to ask");
    }
}

#[test]
fn two_sensor_slots_ask_the_pairs_other_scans_for_what_detection_needs() {
    let sc = sim::paper(3, true, 8, 8);
    let sensors = sc.sensors();
    let scans = Scans::new(&sc.measurements(&sensors), 2);
    assert_eq!(scans.len(), 16);
    let n_detect = InitiationOptions::default().n_detect_for(scans.len());
    assert_eq!(n_detect, 9);
    let slots = paper_slots(&scans, &[[0, 1]], 2, false, true, n_detect);
    assert_eq!(slots.len(), 4, "first and second × last and second-last");
    for slot in &slots {
        let mut all: Vec<usize> = slot.witnesses.iter().chain(&slot.scans).copied().collect();
        all.sort_unstable();
        assert_eq!(all, (0..16).collect::<Vec<_>>(), "{slot:?}");
        // Its own four rows and six of the twelve others make the ten detection needs.
        assert_eq!(slot.witness_need, WitnessNeed::AtLeast(6));
        assert_eq!(slot.witness_need.of(slot.witnesses.len()), 6);
    }
    let untested = paper_slots(&scans, &[[0, 1]], 2, false, false, n_detect);
    assert!(untested.iter().all(|s| !s.is_tested()));
}

/// The default at two sensors finds the paper's formation's tracks (with the support gate,
/// which drops after their fit the candidates the witnesses drop before), from far fewer
/// fits, at Pd 1 and with a target report in four missed outside the first and last scans.
#[test]
fn two_sensors_find_the_papers_tracks_from_fewer_fits() {
    for (seed, clutter, misses) in [(2024, 8, false), (7, 16, false), (11, 16, true)] {
        let mut sc = sim::paper(seed, true, clutter, 8);
        if misses {
            let keep: Vec<bool> = (0..sc.truth.len())
                .map(|m| sc.truth[m] < 0 || sc.time[m] < 10.0 || sc.time[m] > 100.0 || m % 4 != 1)
                .collect();
            sc.keep_rows(&keep);
        }
        let witnessed = run(&sc, &InitiationOptions::default()).expect("runs");
        let paper_options = InitiationOptions::default().with_candidates(Formation::Paper);
        let paper = run(&sc, &paper_options).expect("runs");
        assert_eq!(witnessed.formation, Formation::Witnessed);
        assert_eq!(paper.formation, Formation::Paper);
        assert_eq!(witnessed.tracks.len(), 4, "seed {seed}");
        assert_eq!(witnessed.labels, paper.labels, "seed {seed}");
        assert_partition(&witnessed, sc.truth.len());
        let (w, p) = (witnessed.stage_counts.fitted, paper.stage_counts.fitted);
        assert!(
            0 < w && 5 * w < p,
            "seed {seed}: {w} fitted against the paper's {p}"
        );
    }
}
