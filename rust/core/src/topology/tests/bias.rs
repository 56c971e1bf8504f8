//! The bias estimate: a known rotation recovered, wrong pairs trimmed, extreme positions.

use super::*;

#[test]
fn bias_estimate_recovers_a_known_rotation() {
    let (pos, _) = scene(4, 20);
    let id = ids(pos.len() / 2);
    let (angle, radar) = (0.05, [230e3, -40e3]);
    let local_pos = rotate(&pos, angle, radar);
    let system = ScanTracks::new("system", &id, &pos, None).unwrap();
    let local = ScanTracks::new("local", &id, &local_pos, None).unwrap();
    let mut assoc = topology(1);
    assoc.update(&local, &system).unwrap();
    let rigid = assoc.bias().unwrap();
    assert!((rigid.rotation - angle).abs() < 1e-9, "{rigid:?}");
    assert!(rigid.rotation_std < 1e-6);
    let about = assoc.bias_about(radar).unwrap();
    // Rotating about the radar is a rigid move with this translation, for both fits.
    let (c, s) = (angle.cos(), angle.sin());
    let t = [
        radar[0] - (c * radar[0] - s * radar[1]),
        radar[1] - (s * radar[0] + c * radar[1]),
    ];
    for fit in [rigid, about] {
        assert!((fit.rotation - angle).abs() < 1e-9, "{fit:?}");
        assert!(
            (fit.translation[0] - t[0]).abs() < 1e-3 && (fit.translation[1] - t[1]).abs() < 1e-3,
            "{fit:?}"
        );
    }
}

#[test]
fn trimming_keeps_wrong_pairs_out_of_the_bias() {
    let (pos, _) = scene(12, 40);
    let (angle, radar) = (0.04, [240e3, 30e3]);
    let turned = rotate(&pos, angle, radar);
    let mut sums = BiasAccumulator::default();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for (p, q) in turned.chunks_exact(2).zip(pos.chunks_exact(2)) {
        let noise = [
            rng.random_range(-300.0..300.0),
            rng.random_range(-300.0..300.0),
        ];
        sums.add([p[0] + noise[0], p[1] + noise[1]], [q[0], q[1]]);
    }
    // Five wrong pairs, each a target matched with one 40-90 km away.
    for k in 0..5 {
        let q = [pos[2 * k], pos[2 * k + 1]];
        sums.add(
            [turned[2 * k] + 40e3 + 10e3 * k as f64, turned[2 * k + 1]],
            q,
        );
    }
    let fit = sums.rigid().unwrap();
    assert_eq!(
        fit.pairs,
        pos.len() / 2,
        "exactly the wrong pairs are trimmed"
    );
    assert!(
        (fit.rotation - angle).abs() < 3.0 * fit.rotation_std + 1e-4,
        "{fit:?}"
    );
}

#[test]
fn bias_of_absurdly_large_positions_is_finite() {
    // Squares of 1e200 overflowed: the fit was NaN, with a standard deviation of 0.
    let (angle, mut sums) = (0.03_f64, BiasAccumulator::default());
    for q in [
        [-2e299, 5e299],
        [-1e299, 3e299],
        [0.0, 1e299],
        [1e299, -1e299],
        [2e299, -3e299],
    ] {
        sums.add(rotate(&q, angle, [0.0, 0.0]).try_into().unwrap(), q);
    }
    for fit in [sums.rigid().unwrap(), sums.about([0.0, 0.0]).unwrap()] {
        assert!(
            (fit.rotation - angle).abs() < 1e-9 && fit.rotation_std.is_finite(),
            "{fit:?}"
        );
    }
}
