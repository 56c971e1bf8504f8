//! Enumeration against brute force, the noiseless truth, thread invariance, input errors.

use super::*;

fn assert_matches_brute_force(scene: &Scene, options: &EnumerateOptions) -> usize {
    let fast = scene.run(options, None).expect("enumerates");
    let slow = scene.brute_force(options);
    assert_eq!(fast.len(), slow.len(), "candidate counts differ");
    let dim = fast.dim;
    for (k, (tuple, e)) in slow.iter().enumerate() {
        assert_eq!(fast.tuple(k), tuple.as_slice(), "tuple {k}");
        assert_eq!(
            &fast.positions[k * dim..(k + 1) * dim],
            &e.point[..dim],
            "position {k}"
        );
        assert_eq!(fast.chi2[k], e.chi2);
        assert_eq!(
            fast.intensity[k] as usize,
            tuple.iter().filter(|&&i| i > 0).count()
        );
    }
    fast.len()
}

#[test]
fn enumeration_equals_brute_force_2d() {
    let mut total = 0;
    for seed in 0..6 {
        let s = scene(Space::Planar, 3, 6, 4e-3, 0.85, 2, true, seed);
        total += assert_matches_brute_force(&s, &EnumerateOptions::default());
        let s4 = scene(Space::Planar, 4, 4, 4e-3, 0.8, 1, true, 100 + seed);
        for min_intensity in [2, 3, 4] {
            assert_matches_brute_force(
                &s4,
                &EnumerateOptions::default()
                    .with_min_intensity(min_intensity)
                    .expect("valid"),
            );
        }
    }
    assert!(total > 100, "the cases should not be trivial: {total}");
}

#[test]
fn enumeration_equals_brute_force_3d() {
    let mut total = 0;
    for seed in 0..6 {
        let s = scene(Space::Spatial, 3, 6, 6e-3, 0.85, 2, true, 200 + seed);
        total += assert_matches_brute_force(&s, &EnumerateOptions::default());
        let s4 = scene(Space::Spatial, 4, 4, 6e-3, 0.8, 1, true, 300 + seed);
        assert_matches_brute_force(
            &s4,
            &EnumerateOptions::default()
                .with_min_intensity(3)
                .expect("valid"),
        );
    }
    assert!(total > 20, "the cases should not be trivial: {total}");
}

#[test]
fn window_is_exact_and_prunes() {
    for (space, seed) in [(Space::Planar, 7), (Space::Spatial, 8)] {
        let s = scene(space, 4, 12, 2e-3, 0.9, 3, true, seed);
        let with = s
            .run(&EnumerateOptions::default(), Some(2))
            .expect("enumerates");
        let without = s
            .run(&EnumerateOptions::default().with_use_window(false), Some(2))
            .expect("enumerates");
        assert!(with.stages.windowed_out > 0);
        assert_eq!(without.stages.windowed_out, 0);
        let strip = |c: &Candidates| Candidates {
            stages: StageCounts::default(),
            ..c.clone()
        };
        assert_eq!(strip(&with), strip(&without), "{space:?}");
    }
}

#[test]
fn noiseless_full_detection_recovers_the_truth() {
    for (space, seed) in [
        (Space::Planar, 11),
        (Space::Planar, 12),
        (Space::Spatial, 13),
    ] {
        // σ tiny so that no three rays of different targets meet by accident.
        let s = scene(space, 3, 18, 1e-6, 1.0, 0, false, seed);
        let c = s
            .run(&EnumerateOptions::default(), None)
            .expect("enumerates");
        let full: Vec<usize> = (0..c.len()).filter(|&k| c.intensity[k] == 3).collect();
        let mut truth = s.truth.clone();
        truth.sort();
        let found: Vec<Vec<i64>> = full.iter().map(|&k| c.tuple(k).to_vec()).collect();
        assert_eq!(
            found, truth,
            "{space:?}: intensity-S candidates are exactly the true tuples"
        );
        for &k in &full {
            let t = s
                .truth
                .iter()
                .position(|t| t.as_slice() == c.tuple(k))
                .expect("a true tuple");
            for d in 0..c.dim {
                assert!(
                    (c.positions[k * c.dim + d] - s.targets[t][d]).abs() < 1e-3,
                    "position of target {t}"
                );
            }
        }
        let sizes = sizes_i64(&c);
        let input =
            intensity_input(&c.tuples, 3, &c.positions, c.dim, &c.costs, &sizes).expect("valid");
        let out = intensity_search(&input, &IntensityOptions::paper()).expect("searches");
        let chosen: Vec<Vec<i64>> = out.chosen.iter().map(|&k| c.tuple(k).to_vec()).collect();
        assert_eq!(
            chosen, truth,
            "{space:?}: the intensity method returns the truth"
        );
        assert!(out.airspace_radius.is_finite());
    }
}

#[test]
fn output_is_identical_for_any_thread_count() {
    for space in [Space::Planar, Space::Spatial] {
        let s = scene(space, 3, 15, 3e-3, 0.9, 3, true, 21);
        let one = s
            .run(&EnumerateOptions::default(), Some(1))
            .expect("enumerates");
        let three = s
            .run(&EnumerateOptions::default(), Some(3))
            .expect("enumerates");
        assert_eq!(one, three);
        // Lexicographic order and costs are what the formula gives.
        for k in 1..one.len() {
            assert!(one.tuple(k - 1) < one.tuple(k), "sorted");
        }
        let sizes = sizes_i64(&one);
        let input = intensity_input(&one.tuples, 3, &one.positions, one.dim, &one.costs, &sizes)
            .expect("valid");
        let a = with_threads(Some(1), || {
            intensity_search(&input, &IntensityOptions::paper())
        })
        .expect("pool");
        let b = with_threads(Some(3), || {
            intensity_search(&input, &IntensityOptions::paper())
        })
        .expect("pool");
        assert_eq!(a, b);
    }
}

#[test]
fn noisy_scene_is_mostly_recovered() {
    // EXPERIMENTS `intensity` with M = 10, Pd = 0.95, one false bearing per sensor, and a
    // small noise (R = 100, σ ≈ 0.76 mrad): most targets come back exactly. (At the paper's
    // R = 15 this geometry is full of ghost triples and every method does far worse; the
    // `intensity` experiment, not a unit test, measures that.)
    let (m, r) = (10, 100.0);
    let sigma = 0.761 / m as f64 / r;
    let (mut correct, mut total) = (0, 0);
    for seed in 0..8 {
        let s = scene(Space::Planar, 3, m, sigma, 0.95, 1, true, 40 + seed);
        let c = s
            .run(&EnumerateOptions::default(), None)
            .expect("enumerates");
        let sizes = sizes_i64(&c);
        let input =
            intensity_input(&c.tuples, 3, &c.positions, 2, &c.costs, &sizes).expect("valid");
        let out = intensity_search(&input, &IntensityOptions::paper()).expect("searches");
        for t in s
            .truth
            .iter()
            .filter(|t| t.iter().filter(|&&i| i > 0).count() >= 2)
        {
            total += 1;
            correct += out.chosen.iter().any(|&k| c.tuple(k) == t.as_slice()) as usize;
        }
    }
    assert!(correct * 2 > total, "{correct}/{total}");
}

#[test]
fn cap_and_bad_input_are_errors() {
    let s = scene(Space::Planar, 3, 5, 3e-3, 1.0, 0, true, 5);
    let err = s
        .run(
            &EnumerateOptions::default()
                .with_max_candidates(3)
                .expect("valid"),
            Some(2),
        )
        .unwrap_err();
    assert!(
        matches!(err, CoreError::CapExceeded { cap: 3, .. }),
        "{err}"
    );
    // Value-only settings are rejected by their setters.
    let defaults = EnumerateOptions::default;
    for (built, arg) in [
        (defaults().with_gate_sigmas(0.0), "gate_sigmas"),
        (defaults().with_gate_sigmas(f64::NAN), "gate_sigmas"),
        (defaults().with_min_intensity(1), "min_intensity"),
        (defaults().with_max_candidates(0), "max_candidates"),
    ] {
        let err = built.unwrap_err();
        assert!(err.to_string().starts_with(arg), "{err}");
    }
    // More than the 3 sensors: only the enumeration, which knows them, can tell.
    let four = defaults().with_min_intensity(4).expect("valid on its own");
    let err = s.run(&four, None).unwrap_err();
    assert!(err.to_string().starts_with("min_intensity"), "{err}");
    // One sensor.
    let one = Sensors::new(Space::Planar, &[0.0; 3], &[1e-3], &[1e-3]).expect("valid");
    let table = Measurements::new(&one, &[0], &[0.0], &[0.3], &[0.0]).expect("valid");
    let detection = DetectionModel::new(&one, &[0.9], &[1.0]).expect("valid");
    let err = enumerate(&one, &table, &detection, &EnumerateOptions::default()).unwrap_err();
    assert!(err.to_string().contains("at least 2 sensors"), "{err}");

    // Intensity input.
    let tuples = [1, 1, 0, 2, 0, 1];
    let positions = [0.0, 1.0, 2.0, 3.0];
    let costs = [-1.0, -2.0];
    let err = intensity_input(&tuples, 3, &positions, 2, &costs, &[1, 1, 1]).unwrap_err();
    assert!(
        err.to_string().starts_with("tuples: row 1 column 0 is 2"),
        "{err}"
    );
    assert!(intensity_input(&tuples, 3, &positions, 2, &costs, &[2, 1]).is_err());
    assert!(intensity_input(&tuples, 3, &positions[..3], 2, &costs, &[2, 1, 1]).is_err());
    assert!(intensity_input(&tuples, 3, &positions, 2, &[-1.0, f64::NAN], &[2, 1, 1]).is_err());
    assert!(intensity_input(&[1, 1], 1, &[0.0], 1, &[-1.0], &[1]).is_err());
    let input = intensity_input(&tuples, 3, &positions, 2, &costs, &[2, 1, 1]).expect("valid");
    for tau in [1.0, -0.1, f64::NAN] {
        let err = IntensityOptions::paper()
            .with_vote_fraction(tau)
            .unwrap_err();
        assert!(err.to_string().starts_with("vote_fraction"), "{err}");
    }
    let err = IntensityOptions::paper()
        .with_lowest_intensity(Some(1))
        .unwrap_err();
    assert!(err.to_string().starts_with("lowest_intensity"), "{err}");
    let err = IntensityOptions::paper()
        .with_max_chains(Some(0))
        .unwrap_err();
    assert!(err.to_string().starts_with("max_chains"), "{err}");
    // Above S = 3: only the search, which knows S, can tell.
    let four = IntensityOptions::paper()
        .with_lowest_intensity(Some(4))
        .expect("valid on its own");
    let err = intensity_search(&input, &four).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("lowest_intensity: 4 must be in 2..=3"),
        "{err}"
    );
}

/// Sensors among the targets (the bearing window's awkward cases: a sensor inside or next to
/// the region of two wedges, rays in every direction), random gates and noise.
#[test]
fn enumeration_equals_brute_force_with_sensors_among_targets() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let mut total = 0;
    for seed in 0..16u64 {
        let space = if seed % 2 == 0 {
            Space::Planar
        } else {
            Space::Spatial
        };
        let sensors = [
            [-5e3, 0.0, 0.0],
            [5e3, 0.0, 30.0],
            [0.0, 8e3, 0.0],
            [0.0, -3e3, 10.0],
        ];
        let n_sensors = if seed % 3 == 0 { 4 } else { 3 };
        let sigma = 10f64.powf(rng.random_range(-3.5..-1.5));
        let mut sensor = vec![];
        let mut azimuth = vec![];
        let mut elevation = vec![];
        for (j, p) in sensors[..n_sensors].iter().enumerate() {
            for _ in 0..rng.random_range(2..7) {
                let t = [
                    rng.random_range(-20e3..20e3),
                    rng.random_range(-20e3..20e3),
                    rng.random_range(500.0..3000.0),
                ];
                let [a, e] = predict(space, p, &t);
                sensor.push(j as i64);
                azimuth.push(a + sigma * gaussian(&mut rng));
                elevation.push(e + sigma * gaussian(&mut rng));
            }
        }
        // Shared targets too: a few points seen by all sensors.
        for _ in 0..3 {
            let t = [
                rng.random_range(-20e3..20e3),
                rng.random_range(-20e3..20e3),
                rng.random_range(500.0..3000.0),
            ];
            for (j, p) in sensors[..n_sensors].iter().enumerate() {
                let [a, e] = predict(space, p, &t);
                sensor.push(j as i64);
                azimuth.push(a + sigma * gaussian(&mut rng));
                elevation.push(e + sigma * gaussian(&mut rng));
            }
        }
        let s = Scene {
            space,
            positions: sensors[..n_sensors].iter().flatten().copied().collect(),
            sigma: vec![sigma; n_sensors],
            time: vec![0.0; sensor.len()],
            sensor,
            azimuth,
            elevation,
            targets: vec![],
            truth: vec![],
        };
        let gate: f64 = rng.random_range(1.0..30.0);
        total += assert_matches_brute_force(
            &s,
            &EnumerateOptions::default()
                .with_gate_sigmas(gate.sqrt())
                .expect("valid"),
        );
    }
    assert!(total > 200, "the cases should not be trivial: {total}");
}
