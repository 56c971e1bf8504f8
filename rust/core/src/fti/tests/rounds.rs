//! The rounds formation (a project extension) on a ring of three 3-D sensors: what `Auto`
//! resolves to, what it finds, what a reached limit returns, and that every row ends in one
//! output.

use super::sim::{self, Scenario};
use super::*;
use crate::fti::Formation;

/// Targets held by some track: a track holds the target that owns more than half its rows.
fn targets_held(sc: &Scenario, result: &Initiation) -> (usize, usize) {
    let mut held = vec![false; sc.targets.len()];
    let mut false_tracks = 0;
    for track in &result.tracks {
        let mut counts = vec![0usize; sc.targets.len()];
        for &m in &track.measurements {
            if let Ok(i) = usize::try_from(sc.truth[m]) {
                counts[i] += 1;
            }
        }
        match counts.iter().enumerate().max_by_key(|&(_, c)| *c) {
            Some((i, &c)) if 2 * c > track.measurements.len() => held[i] = true,
            _ => false_tracks += 1,
        }
    }
    (held.iter().filter(|&&h| h).count(), false_tracks)
}

/// Every row is in exactly one track or in clutter, and `labels` says which.
fn assert_partition(sc: &Scenario, result: &Initiation) {
    let mut owner = vec![-1i64; sc.time.len()];
    for (k, track) in result.tracks.iter().enumerate() {
        for &m in &track.measurements {
            assert_eq!(owner[m], -1, "row {m} in two tracks");
            owner[m] = k as i64;
        }
    }
    assert_eq!(owner, result.labels);
}

#[test]
fn auto_resolves_by_space_with_three_scanning_sensors() {
    assert_eq!(
        Formation::Auto.resolve(Space::Spatial, 3),
        Formation::Rounds
    );
    assert_eq!(
        Formation::Auto.resolve(Space::Spatial, 2),
        Formation::Witnessed
    );
    assert_eq!(
        Formation::Auto.resolve(Space::Planar, 5),
        Formation::Witnessed
    );
    assert_eq!(
        Formation::Auto.resolve(Space::Planar, 2),
        Formation::Witnessed
    );
    assert_eq!(
        Formation::Paper.resolve(Space::Spatial, 5),
        Formation::Paper
    );
    assert_eq!(
        Formation::Rounds.resolve(Space::Planar, 2),
        Formation::Rounds
    );
    assert_eq!(InitiationOptions::paper().candidates(), Formation::Paper);
    assert_eq!(
        InitiationOptions::recommended().candidates(),
        Formation::Auto
    );
}

#[test]
fn rounds_find_every_ring_target_and_nothing_else() {
    let sc = sim::ring(3, 8, 1.0, 16, 8);
    let result = run(&sc, &InitiationOptions::recommended()).expect("initiates");
    assert_eq!(result.formation, Formation::Rounds);
    assert_eq!(result.limit, None);
    assert_eq!(targets_held(&sc, &result), (8, 0));
    assert_partition(&sc, &result);
    // The paper's formation on the same scene finds the same targets.
    let paper = InitiationOptions::recommended().with_candidates(Formation::Paper);
    let result = run(&sc, &paper).expect("initiates");
    assert_eq!(result.formation, Formation::Paper);
    assert_eq!(targets_held(&sc, &result), (8, 0));
}

#[test]
fn rounds_survive_misses() {
    let mut found = 0;
    for seed in 0..4 {
        let sc = sim::ring(seed, 8, 0.9, 16, 8);
        let result = run(&sc, &InitiationOptions::recommended()).expect("initiates");
        let (held, false_tracks) = targets_held(&sc, &result);
        assert_eq!(false_tracks, 0, "seed {seed}");
        assert_partition(&sc, &result);
        found += held;
    }
    assert!(found >= 31, "found {found} of 32");
}

#[test]
fn rounds_do_not_depend_on_the_thread_count() {
    let sc = sim::ring(5, 8, 0.9, 16, 8);
    let options = InitiationOptions::recommended();
    let one = with_threads(Some(1), || run(&sc, &options))
        .expect("threads")
        .expect("initiates");
    let two = with_threads(Some(2), || run(&sc, &options))
        .expect("threads")
        .expect("initiates");
    assert_eq!(one.tracks, two.tracks);
    assert_eq!(one.labels, two.labels);
    assert_eq!(one.stage_counts, two.stage_counts);
    assert_eq!(one.descent_iterations, two.descent_iterations);
}

#[test]
fn a_reached_limit_stops_with_what_was_found_or_refuses() {
    let sc = sim::ring(3, 8, 1.0, 16, 8);
    let capped = InitiationOptions::recommended()
        .with_max_candidates(20)
        .expect("valid");
    let result = run(&sc, &capped).expect("stops at the limit");
    let limit = result.limit.clone().expect("the limit is reported");
    assert!(limit.reached.contains("max_candidates"), "{limit:?}");
    // Stopped within the formation: some slots formed in full, not all of them.
    assert!(
        limit.slots_formed < limit.slots && limit.slots > 1,
        "{limit:?}"
    );
    assert_partition(&sc, &result);
    assert!(result.tracks.len() < 8);
    let strict = capped.with_stop_at_limit(false);
    assert!(matches!(
        run(&sc, &strict),
        Err(CoreError::CapExceeded { cap: 20, .. })
    ));
}
