//! The fused decision (topology, then bias, then distance), the believed pairs it is fitted
//! to, and the honesty of the bias estimate's standard deviation.

use super::*;

/// Isotropic position covariances of `sigma` metres, `(n, 2, 2)` row-major.
fn covariances(n: usize, sigma: f64) -> Vec<f64> {
    (0..n)
        .flat_map(|_| [sigma * sigma, 0.0, 0.0, sigma * sigma])
        .collect()
}

/// `n` points moved by their velocities for `dt` seconds.
fn moved(pos: &[f64], vel: &[f64], dt: f64) -> Vec<f64> {
    pos.iter().zip(vel).map(|(p, v)| p + v * dt).collect()
}

/// Gaussian noise of `sigma` on every coordinate.
fn noisy(points: &[f64], sigma: f64, rng: &mut ChaCha8Rng) -> Vec<f64> {
    points
        .iter()
        .map(|p| {
            // Box-Muller.
            let (u, v): (f64, f64) = (rng.random_range(1e-12..1.0), rng.random_range(0.0..1.0));
            p + sigma * (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        })
        .collect()
}

/// The recommended (fused) associator.
fn fused() -> Associator {
    Associator::new(
        Scoring::Topology(TopologyOptions::default()),
        DecisionOptions::default(),
    )
}

#[test]
fn fused_pairs_every_target_a_rotation_moves_kilometres() {
    // 8° relative rotation about a radar 250 km away moves the targets by up to 50 km, more
    // than twice the formation's spacing: distance alone pairs the formation wrongly.
    let (pos0, vel) = scene(5, 15);
    let n = pos0.len() / 2;
    let id = ids(n);
    let (angle, radar) = (8f64.to_radians(), [250e3, 30e3]);
    let cov = covariances(n, 400.0);
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut assoc = fused();
    let mut last = None;
    for scan in 0..12 {
        let pos = moved(&pos0, &vel, 10.0 * scan as f64);
        let local_pos = noisy(&rotate(&pos, angle, radar), 300.0, &mut rng);
        let system_pos = noisy(&pos, 300.0, &mut rng);
        let local = ScanTracks::new("local", &id, &local_pos, None)
            .unwrap()
            .with_covariances("local", &cov)
            .unwrap();
        let system = ScanTracks::new("system", &id, &system_pos, None)
            .unwrap()
            .with_covariances("system", &cov)
            .unwrap();
        last = Some(assoc.update(&local, &system).unwrap());
    }
    let pairs = last.unwrap().pairs;
    assert_eq!(pairs, (0..n).map(|k| (k, k)).collect::<Vec<_>>());
    let bias = assoc.bias().unwrap();
    assert!(bias.reliable, "{bias:?}");
    assert_eq!(bias.clusters, n);
    assert!(
        (bias.rotation - angle).abs() <= 3.0 * bias.rotation_std,
        "{bias:?}"
    );
    assert!(bias.rotation_std < 0.2f64.to_radians(), "{bias:?}");
}

#[test]
fn a_track_without_partner_stays_unpaired() {
    // The local radar sees five more targets, 30-70 km from the rest, that the system does
    // not: the old decision paired them with whatever looked alike.
    let (pos0, vel) = scene(8, 12);
    let n = pos0.len() / 2;
    let extra = [
        150e3, 150e3, 190e3, 120e3, -150e3, 160e3, 170e3, -160e3, -170e3, -140e3,
    ];
    let (angle, radar) = (3f64.to_radians(), [-240e3, 60e3]);
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut assoc = fused();
    let local_ids: Vec<i64> = (0..(n + 5) as i64).collect();
    let system_ids = ids(n);
    let (cov_l, cov_s) = (covariances(n + 5, 400.0), covariances(n, 400.0));
    let mut last = None;
    for scan in 0..10 {
        let pos = moved(&pos0, &vel, 10.0 * scan as f64);
        let mut seen = pos.clone();
        seen.extend(extra);
        let local_pos = noisy(&rotate(&seen, angle, radar), 300.0, &mut rng);
        let system_pos = noisy(&pos, 300.0, &mut rng);
        let local = ScanTracks::new("local", &local_ids, &local_pos, None)
            .unwrap()
            .with_covariances("local", &cov_l)
            .unwrap();
        let system = ScanTracks::new("system", &system_ids, &system_pos, None)
            .unwrap()
            .with_covariances("system", &cov_s)
            .unwrap();
        last = Some(assoc.update(&local, &system).unwrap());
    }
    let pairs = last.unwrap().pairs;
    assert_eq!(pairs, (0..n).map(|k| (k, k)).collect::<Vec<_>>());
}

#[test]
fn pictures_sharing_no_target_make_no_pair() {
    // Two pictures of different targets over the same area, each track within the bias
    // bound's gate of several of the other's: the old decision paired them by topology.
    let (pos, _) = scattered(3, 15);
    let (other, _) = scattered(17, 15);
    let n = pos.len() / 2;
    let id = ids(n);
    let shifted = other;
    let cov = covariances(n, 400.0);
    let mut assoc = fused();
    for _ in 0..6 {
        let local = ScanTracks::new("local", &id, &shifted, None)
            .unwrap()
            .with_covariances("local", &cov)
            .unwrap();
        let system = ScanTracks::new("system", &id, &pos, None)
            .unwrap()
            .with_covariances("system", &cov)
            .unwrap();
        let out = assoc.update(&local, &system).unwrap();
        assert!(out.pairs.is_empty(), "{:?}", out.pairs);
    }
    assert!(assoc.bias().is_none());
}

#[test]
fn fused_pairs_do_not_depend_on_ids() {
    let (pos0, vel) = scene(13, 12);
    let n = pos0.len() / 2;
    let id = ids(n);
    let renamed: Vec<i64> = (0..n as i64).map(|k| 7000 - 3 * k).collect();
    let cov = covariances(n, 500.0);
    let run = |local_ids: &[i64]| {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut assoc = fused();
        let mut all = Vec::new();
        for scan in 0..8 {
            let pos = moved(&pos0, &vel, 10.0 * scan as f64);
            let local_pos = noisy(&rotate(&pos, 0.07, [0.0, 260e3]), 400.0, &mut rng);
            let local = ScanTracks::new("local", local_ids, &local_pos, None)
                .unwrap()
                .with_covariances("local", &cov)
                .unwrap();
            let system = ScanTracks::new("system", &id, &pos, None)
                .unwrap()
                .with_covariances("system", &cov)
                .unwrap();
            all.push(assoc.update(&local, &system).unwrap().pairs);
        }
        (all, assoc.bias().unwrap().rotation)
    };
    assert_eq!(run(&id), run(&renamed));
}

#[test]
fn the_standard_deviation_counts_track_pairs_not_scans() {
    // Each of 6 track pairs is seen for 40 scans with an error that drifts slowly (one
    // offset per track pair plus a little white noise): 240 points, 6 independent samples.
    // Over 400 runs the truth must lie within 3 standard deviations in ≥ 99 % of them; the
    // points taken as independent would claim a far smaller spread.
    let (angle, mut rng) = (0.02_f64, ChaCha8Rng::seed_from_u64(11));
    let (mut inside, mut naive_inside, runs) = (0, 0, 400);
    for _ in 0..runs {
        let (mut clustered, mut naive) = (BiasAccumulator::default(), BiasAccumulator::default());
        for track in 0..6u64 {
            let start = [rng.random_range(-80e3..80e3), rng.random_range(-80e3..80e3)];
            let offset = noisy(&[0.0, 0.0], 1500.0, &mut rng);
            for scan in 0..40 {
                let q = [start[0] + 300.0 * scan as f64, start[1]];
                let p = rotate(&q, angle, [0.0, 0.0]);
                let white = noisy(&[0.0, 0.0], 100.0, &mut rng);
                let p = [p[0] + offset[0] + white[0], p[1] + offset[1] + white[1]];
                clustered.add_in(track, p, q);
                naive.add(p, q);
            }
        }
        let fit = clustered.rigid().unwrap();
        assert!(fit.clusters >= 5, "{fit:?}");
        inside += usize::from((fit.rotation - angle).abs() <= 3.0 * fit.rotation_std);
        let fit = naive.rigid().unwrap();
        naive_inside += usize::from((fit.rotation - angle).abs() <= 3.0 * fit.rotation_std);
    }
    assert!(inside as f64 >= 0.99 * runs as f64, "{inside}/{runs}");
    assert!(
        (naive_inside as f64) < 0.9 * runs as f64,
        "points as independent samples: {naive_inside}/{runs}"
    );
}

#[test]
fn an_estimate_of_two_track_pairs_is_not_reliable() {
    let mut sums = BiasAccumulator::default();
    for (track, q) in [[10e3, 0.0], [-30e3, 40e3]].iter().enumerate() {
        for scan in 0..20 {
            let q = [q[0] + 100.0 * scan as f64, q[1]];
            let p = rotate(&q, 0.01, [0.0, 0.0]);
            sums.add_in(track as u64, [p[0], p[1] + (scan % 3) as f64], q);
        }
    }
    let fit = sums.rigid().unwrap();
    assert_eq!(fit.clusters, 2);
    assert!(!fit.reliable && !reliable(&fit, &DecisionOptions::default()));
    assert!(fit.rotation_std.is_finite());
}

#[test]
fn student_quantiles_meet_the_expansion() {
    // The table's last entry and the expansion agree (both SciPy's to 2e-6).
    assert!((student_3sigma(30) - 3.270334).abs() < 2e-6);
    assert!((student_3sigma(31) - 3.260942).abs() < 1e-5);
    assert!(student_3sigma(1000) > 3.0 && student_3sigma(1000) < 3.01);
    assert!(student_3sigma(0).is_infinite());
}
