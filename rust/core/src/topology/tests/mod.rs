//! Tests of §4: the grid, the invariances the method rests on, the decisions, the window,
//! the bias estimate.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

mod bias;
mod caps;
mod fusion;
mod history;

use super::*;
use crate::parallel::with_threads;

/// `n` targets scattered over a 200 km square (the paper's density: about ten neighbours in
/// a 120 km disc) plus a line-abreast formation of 5, 20 km apart: positions and velocities,
/// row-major.
fn scene(seed: u64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut pos, mut vel) = scattered(seed, n);
    for k in 0..5 {
        pos.extend([-40e3 + 20e3 * k as f64, 60e3]);
        vel.extend([0.0, 340.0]);
    }
    (pos, vel)
}

/// `n` targets scattered over a 200 km square, random headings.
fn scattered(seed: u64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut pos, mut vel) = (Vec::new(), Vec::new());
    for _ in 0..n {
        pos.extend([
            rng.random_range(-100e3..100e3),
            rng.random_range(-100e3..100e3),
        ]);
        let heading: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        vel.extend([340.0 * heading.cos(), 340.0 * heading.sin()]);
    }
    (pos, vel)
}

/// Rotates planar points (and vectors, about the origin) by `angle` about `centre`.
fn rotate(points: &[f64], angle: f64, centre: [f64; 2]) -> Vec<f64> {
    let (c, s) = (angle.cos(), angle.sin());
    points
        .chunks_exact(2)
        .flat_map(|p| {
            let (x, y) = (p[0] - centre[0], p[1] - centre[1]);
            [c * x - s * y + centre[0], s * x + c * y + centre[1]]
        })
        .collect()
}

fn ids(n: usize) -> Vec<i64> {
    (0..n as i64).collect()
}

/// The default grid with λ = 0.5, the closeness alone deciding (one-to-one assignment) on
/// every pair: these tests check the topology decision logic, not the threshold (a
/// full-sector rotation brings a true pair's W down to about 0.6·M·N on these scenes) nor the
/// fused decision (`tests/fusion.rs`).
fn topology(window: usize) -> Associator {
    let options = TopologyOptions::default();
    let decision = DecisionOptions::default()
        .with_threshold(0.5 * options.cells() as f64)
        .unwrap()
        .with_window(window)
        .unwrap()
        .with_gate(Gate::Off)
        .unwrap()
        .with_decision(Decision::Assignment);
    Associator::new(Scoring::Topology(options), decision)
}

#[test]
fn a_lone_neighbour_fills_its_cell_and_diffuses() {
    // One neighbour 10 km due north (ring 0 of 4 over 120 km, sector 0).
    let (pos, id) = ([0.0, 0.0, 0.0, 10e3], [1, 2]);
    let tracks = ScanTracks::new("local", &id, &pos, None).unwrap();
    let o = TopologyOptions::default();
    let v = topology_vectors(&tracks, &o);
    let first = &v[..o.cells()];
    assert_eq!(first[0], 1.0);
    assert_eq!(first[12], 0.5, "ring 1, same sector: +Δ");
    assert_eq!(first[1], 0.7, "same ring, sector 1: +Δ′");
    assert_eq!(first[11], 0.7, "sectors wrap: sector 11");
    assert_eq!(first.iter().filter(|&&x| x > 0.0).count(), 4);
    // The other track sees it due south: sector 6.
    assert_eq!(v[o.cells() + 6], 1.0);
}

#[test]
fn additive_clips_at_one_and_at_least_takes_the_maximum() {
    // Neighbours in ring 0 and ring 2 of sector 0: ring 1 gets Δ from both sides.
    let (pos, id) = ([0.0, 0.0, 0.0, 10e3, 0.0, 70e3], [1, 2, 3]);
    let tracks = ScanTracks::new("local", &id, &pos, None).unwrap();
    let o = TopologyOptions::default().with_delta(0.6).unwrap();
    assert_eq!(topology_vectors(&tracks, &o)[12], 1.0, "0.6 + 0.6 clipped");
    let o = o.with_diffusion(Diffusion::AtLeast);
    assert_eq!(topology_vectors(&tracks, &o)[12], 0.6);
}

#[test]
fn complementing_both_vectors_leaves_w_unchanged() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..200 {
        let a: Vec<f32> = (0..48).map(|_| rng.random_range(0.0..1.0)).collect();
        let b: Vec<f32> = (0..48).map(|_| rng.random_range(0.0..1.0)).collect();
        let (ca, cb): (Vec<f32>, Vec<f32>) = (
            a.iter().map(|x| 1.0 - x).collect(),
            b.iter().map(|x| 1.0 - x).collect(),
        );
        assert!((closeness(&a, &b) - closeness(&ca, &cb)).abs() < 1e-4);
    }
    let ones = vec![1.0f32; 10];
    assert_eq!(
        closeness(&ones, &ones),
        10.0,
        "identical 0/1 vectors score M·N"
    );
}

#[test]
fn rotation_within_a_sector_changes_no_decision() {
    let (pos, _) = scene(11, 15);
    let n = pos.len() / 2;
    let id = ids(n);
    let system = ScanTracks::new("system", &id, &pos, None).unwrap();
    let sector = std::f64::consts::TAU / TopologyOptions::default().sectors() as f64;
    let identity: Vec<(usize, usize)> = (0..n).map(|k| (k, k)).collect();
    for (angle, centre) in [
        (0.0, [0.0, 0.0]),
        (sector, [250e3, -30e3]),
        (-sector, [-10e3, 40e3]),
        (0.5 * sector, [1e6, 0.0]),
    ] {
        let turned = rotate(&pos, angle, centre);
        let local = ScanTracks::new("local", &id, &turned, None).unwrap();
        let out = topology(1).update(&local, &system).unwrap();
        assert_eq!(out.pairs, identity, "rotation {angle} about {centre:?}");
    }
}

#[test]
fn heading_reference_is_exactly_rotation_invariant() {
    // Scattered targets only: a line-abreast formation puts neighbours exactly on sector
    // edges (90° off the heading), where rounding decides the side.
    let (pos, vel) = scattered(5, 15);
    let n = pos.len() / 2;
    let id = ids(n);
    let o = TopologyOptions::default().with_reference(Reference::Heading);
    let before = topology_vectors(&ScanTracks::new("s", &id, &pos, Some(&vel)).unwrap(), &o);
    let angle = 0.7; // far beyond a sector
    let (p2, v2) = (
        rotate(&pos, angle, [3e5, 1e5]),
        rotate(&vel, angle, [0.0, 0.0]),
    );
    let after = topology_vectors(&ScanTracks::new("s", &id, &p2, Some(&v2)).unwrap(), &o);
    let moved = before
        .iter()
        .zip(&after)
        .filter(|(a, b)| (*a - *b).abs() > 1e-6)
        .count();
    assert_eq!(moved, 0, "cells changed under a rotation");
    let north = topology_vectors(
        &ScanTracks::new("s", &id, &p2, Some(&v2)).unwrap(),
        &TopologyOptions::default(),
    );
    let north_before = topology_vectors(
        &ScanTracks::new("s", &id, &pos, Some(&vel)).unwrap(),
        &TopologyOptions::default(),
    );
    assert_ne!(
        north, north_before,
        "the north-referenced grid does turn (the test is not vacuous)"
    );
}

#[test]
fn permuted_ids_give_the_same_pairs_by_id() {
    let (pos, _) = scene(21, 12);
    let n = pos.len() / 2;
    let id = ids(n);
    let turned = rotate(&pos, 0.05, [2e5, 0.0]);
    let system = ScanTracks::new("system", &id, &pos, None).unwrap();
    let direct = topology(1)
        .update(
            &ScanTracks::new("local", &id, &turned, None).unwrap(),
            &system,
        )
        .unwrap();
    // Local rows in reverse order with other ids.
    let order: Vec<usize> = (0..n).rev().collect();
    let shuffled: Vec<f64> = order
        .iter()
        .flat_map(|&k| [turned[2 * k], turned[2 * k + 1]])
        .collect();
    let new_ids: Vec<i64> = order.iter().map(|&k| 1000 + k as i64).collect();
    let local = ScanTracks::new("local", &new_ids, &shuffled, None).unwrap();
    let permuted = topology(1).update(&local, &system).unwrap();
    let by_id = |pairs: &[(usize, usize)], local_ids: &[i64]| {
        let mut v: Vec<(i64, i64)> = pairs
            .iter()
            .map(|&(i, j)| (local_ids[i] % 1000, id[j]))
            .collect();
        v.sort_unstable();
        v
    };
    assert_eq!(by_id(&direct.pairs, &id), by_id(&permuted.pairs, &new_ids));
}

#[test]
fn the_window_undoes_a_one_scan_swap() {
    let (pos, _) = scene(8, 10);
    let n = pos.len() / 2;
    let id = ids(n);
    let system = ScanTracks::new("system", &id, &pos, None).unwrap();
    let mut assoc = topology(6);
    for _ in 0..5 {
        let local = ScanTracks::new("local", &id, &pos, None).unwrap();
        assert_eq!(assoc.update(&local, &system).unwrap().pairs.len(), n);
    }
    // One scan in which two local tracks trade ids: the averaged W still pairs by history.
    let mut swapped = id.clone();
    swapped.swap(0, 1);
    let local = ScanTracks::new("local", &swapped, &pos, None).unwrap();
    let out = topology(1).update(&local, &system).unwrap();
    assert!(
        out.pairs.contains(&(0, 0)),
        "without memory the scan alone decides"
    );
    let out = assoc.update(&local, &system).unwrap();
    assert!(
        out.pairs.contains(&(1, 0)) && out.pairs.contains(&(0, 1)),
        "{:?}",
        out.pairs
    );
}

#[test]
fn per_system_track_rule_and_gate() {
    // 2 local × 2 system; local 1 is both system tracks' best.
    let all = Candidates::All {
        n_local: 2,
        n_system: 2,
    };
    let scores = [5.0, 1.0, 6.0, 4.0];
    assert_eq!(
        decide(&all, &scores, (2, 2), 2.0, Decision::PerSystemTrack).unwrap(),
        vec![(1, 0)]
    );
    assert_eq!(
        decide(&all, &scores, (2, 2), 2.0, Decision::Assignment).unwrap(),
        vec![(0, 0), (1, 1)]
    );
    // Pairs outside the gate are not candidates.
    assert_eq!(
        decide(
            &Candidates::Listed(vec![(0, 0), (1, 1)]),
            &[5.0, 1.0],
            (2, 2),
            2.0,
            Decision::Assignment
        )
        .unwrap(),
        vec![(0, 0)]
    );
}

#[test]
fn nearest_neighbour_pairs_within_the_gate() {
    let (pos, _) = scene(2, 8);
    let n = pos.len() / 2;
    let id = ids(n);
    let shifted: Vec<f64> = pos.iter().map(|v| v + 500.0).collect();
    let decision = DecisionOptions::default()
        .with_window(1)
        .unwrap()
        .with_gate(Gate::Distance(5e3))
        .unwrap();
    let threshold = decision.with_threshold(-5e3).unwrap();
    let mut nn = Associator::new(Scoring::Distance, threshold);
    let out = nn
        .update(
            &ScanTracks::new("l", &id, &shifted, None).unwrap(),
            &ScanTracks::new("s", &id, &pos, None).unwrap(),
        )
        .unwrap();
    assert_eq!(out.pairs, (0..n).map(|k| (k, k)).collect::<Vec<_>>());
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let (pos, _) = scene(9, 300);
    let id = ids(pos.len() / 2);
    let turned = rotate(&pos, 0.03, [0.0, -2e5]);
    let run = |threads| {
        with_threads(Some(threads), || {
            let o = TopologyOptions::default();
            let local = ScanTracks::new("l", &id, &turned, None).unwrap();
            let system = ScanTracks::new("s", &id, &pos, None).unwrap();
            let a = topology_vectors(&local, &o);
            let b = topology_vectors(&system, &o);
            let pairs = candidate_pairs(&local, &system, Some(50e3));
            (pair_closeness(&a, &b, o.cells(), &pairs), a)
        })
        .unwrap()
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn bad_input_is_an_error() {
    assert!(
        ScanTracks::new("local", &[1, 1], &[0.0; 4], None).is_err(),
        "duplicate id"
    );
    assert!(
        ScanTracks::new("local", &[1], &[0.0; 3], None).is_err(),
        "shape"
    );
    assert!(
        ScanTracks::new("local", &[1], &[f64::NAN, 0.0], None).is_err(),
        "NaN"
    );
    assert!(TopologyOptions::default().with_rings(0).is_err());
    assert!(TopologyOptions::default().with_sectors(1 << 20).is_err());
    assert!(TopologyOptions::default().with_delta_prime(-0.1).is_err());
    let heading = TopologyOptions::default().with_reference(Reference::Heading);
    let mut assoc = Associator::new(Scoring::Topology(heading), DecisionOptions::default());
    let t = ScanTracks::new("local", &[1], &[0.0, 0.0], None).unwrap();
    assert!(
        assoc.update(&t, &t).is_err(),
        "heading grid without velocities"
    );
    // Empty pictures are a documented empty result.
    let empty = ScanTracks::new("system", &[], &[], None).unwrap();
    assert!(topology(6).update(&t, &empty).unwrap().pairs.is_empty());
}

#[test]
fn chi2_gate_keeps_pairs_within_their_covariances() {
    // Two system tracks; the local one is 300 m from the first (σ 100 m on each side: the
    // summed variance is 2·100², so the statistic is 300²/20 000 = 4.5) and 10 km from the
    // second (5 000).
    let (ids, system_pos) = (vec![0_i64, 1], vec![0.0, 0.0, 10e3, 0.0]);
    let local_pos = vec![300.0, 0.0];
    let cov = |n: usize| -> Vec<f64> { (0..n).flat_map(|_| [1e4, 0.0, 0.0, 1e4]).collect() };
    let (sys_cov, loc_cov) = (cov(2), cov(1));
    let system = ScanTracks::new("system", &ids, &system_pos, None)
        .unwrap()
        .with_covariances("system", &sys_cov)
        .unwrap();
    let local = ScanTracks::new("local", &ids[..1], &local_pos, None)
        .unwrap()
        .with_covariances("local", &loc_cov)
        .unwrap();
    let all = candidate_pairs(&local, &system, None);
    let kept = chi2_gated(&local, &system, &all, 9.21).unwrap();
    assert_eq!(kept, Candidates::Listed(vec![(0, 0)]));
    assert_eq!(chi2_gated(&local, &system, &all, 4.4).unwrap().len(), 0);
    // Without covariances on one side the gate cannot be applied: an error, not a guess.
    let bare = ScanTracks::new("local", &ids[..1], &local_pos, None).unwrap();
    assert!(chi2_gated(&bare, &system, &all, 9.21).is_err());
}

#[test]
fn heights_make_distances_three_dimensional() {
    let ids = vec![0_i64, 1];
    let pos = vec![0.0, 0.0, 0.0, 0.0];
    let heights = vec![1e3, 6e3];
    let system = ScanTracks::new("system", &ids, &pos, None)
        .unwrap()
        .with_heights("system", &heights)
        .unwrap();
    let local_pos = vec![0.0, 0.0];
    let local_height = vec![5.9e3];
    let local = ScanTracks::new("local", &ids[..1], &local_pos, None)
        .unwrap()
        .with_heights("local", &local_height)
        .unwrap();
    // Within a 1 km gate only the track 100 m below is a candidate (a planar tree finds both).
    assert_eq!(
        candidate_pairs(&local, &system, Some(1e3)),
        Candidates::Listed(vec![(0, 1)])
    );
}
