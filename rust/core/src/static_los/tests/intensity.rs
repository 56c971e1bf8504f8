//! The intensity search's rules, each on a hand-made or random case.

use super::*;

#[test]
fn airspace_drops_the_far_point() {
    // Five intensity-3 points on distinct reports: a unit square and (10, 10).
    let tuples = [1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4, 5, 5, 5];
    let positions = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0, 10.0, 10.0];
    let costs = [-5.0; 5];
    let input = intensity_input(&tuples, 3, &positions, 2, &costs, &[5, 5, 5]).expect("valid");
    let out = intensity_search(&input, &IntensityOptions::paper()).expect("searches");
    // d = mean over j of (min_b δ_bj + max_b δ_bj)/2, by hand.
    let (r200, r181, r162) = (200f64.sqrt(), 181f64.sqrt(), 162f64.sqrt());
    let d = ((1.0 + r200) + 2.0 * (1.0 + r181) + (1.0 + r162) + (r162 + r200)) / 10.0;
    assert!(
        (out.airspace_radius - d).abs() < 1e-12,
        "{} vs {d}",
        out.airspace_radius
    );
    assert_eq!(out.ghosts_dropped, 1);
    assert_eq!(out.chosen, vec![0, 1, 2, 3]);
    let off = intensity_search(
        &input,
        &IntensityOptions::paper().with_valid_airspace(false),
    )
    .expect("searches");
    assert!(off.airspace_radius.is_nan());
    assert_eq!(off.chosen, vec![0, 1, 2, 3, 4]);
    // A single intensity-S point: no airspace, nothing dropped.
    let single = intensity_input(&tuples[..3], 3, &positions[..2], 2, &costs[..1], &[5, 5, 5])
        .expect("valid");
    let out = intensity_search(&single, &IntensityOptions::paper()).expect("searches");
    assert!(out.airspace_radius.is_nan());
    assert_eq!(out.chosen, vec![0]);
}

#[test]
fn exclusive_rays_outrank_cost() {
    // 0 = (1,1,1) −5, 1 = (1,2,2) −50, 2 = (2,2,2) −5. Uses: s0r1 {0,1}, s1r2 {1,2},
    // s2r2 {1,2}, the rest single ⇒ m = [2, 0, 1], H = {0}. The chain accepts 0 (deleting 1),
    // then 2: the cheapest candidate loses because it has no exclusive ray.
    let tuples = [1, 1, 1, 1, 2, 2, 2, 2, 2];
    let input =
        intensity_input(&tuples, 3, &[0.0; 6], 2, &[-5.0, -50.0, -5.0], &[2, 2, 2]).expect("valid");
    let out = intensity_search(
        &input,
        &IntensityOptions::paper().with_valid_airspace(false),
    )
    .expect("searches");
    assert_eq!(out.chosen, vec![0, 2]);
    assert_eq!((out.chains, out.levels[0].chains), (1, 1));
}

#[test]
fn vote_needs_a_majority_and_conflicts_go_to_the_cheaper() {
    // 0 = (1,1,1) −5, 1 = (2,2,2) −5, 2 = (1,2,1) −50, 3 = (2,1,3) −6. m = [0, 1, 0, 1],
    // H = {1, 3}: chain 1 accepts {1, 0}, chain 3 accepts {3, 2}; one vote each of two chains.
    let tuples = [1, 1, 1, 2, 2, 2, 1, 2, 1, 2, 1, 3];
    let costs = [-5.0, -5.0, -50.0, -6.0];
    let input = intensity_input(&tuples, 3, &[0.0; 8], 2, &costs, &[2, 2, 3]).expect("valid");
    let no_airspace = IntensityOptions::paper().with_valid_airspace(false);
    let out = intensity_search(&input, &no_airspace).expect("searches");
    assert_eq!(
        out.chosen,
        Vec::<usize>::new(),
        "no strict majority at τ = 0.5"
    );
    // τ = 0.4 confirms all four; greedy by cost keeps 2 (−50) and 3 (−6), which are disjoint.
    let out = intensity_search(&input, &no_airspace.with_vote_fraction(0.4).expect("valid"))
        .expect("searches");
    assert_eq!(out.chosen, vec![2, 3]);
    // Identical tuples: m = [0, 0], each chain keeps its own start; τ = 0.4 → the cheaper one.
    let same = intensity_input(
        &[1, 1, 1, 1, 1, 1],
        3,
        &[0.0; 4],
        2,
        &[-1.0, -2.0],
        &[1, 1, 1],
    )
    .expect("valid");
    assert!(intensity_search(&same, &IntensityOptions::paper())
        .expect("searches")
        .chosen
        .is_empty());
    let out = intensity_search(
        &same,
        &IntensityOptions::paper()
            .with_vote_fraction(0.4)
            .expect("valid"),
    )
    .expect("searches");
    assert_eq!(out.chosen, vec![1]);
}

#[test]
fn lower_level_fills_in_missed_targets() {
    // Target A seen by all three sensors, target B only by sensors 0 and 2.
    let tuples = [1, 1, 1, 2, 0, 2, 1, 0, 2, 2, 1, 0];
    let positions = [0.0, 0.0, 1.0, 1.0, 3.0, 3.0, 4.0, 4.0];
    let costs = [-20.0, -8.0, -1.0, -1.0];
    let input = intensity_input(&tuples, 3, &positions, 2, &costs, &[2, 1, 2]).expect("valid");
    let out = intensity_search(
        &input,
        &IntensityOptions::paper().with_valid_airspace(false),
    )
    .expect("searches");
    // Level 3 confirms 0; level 2 loses 2 and 3 (they use A's reports) and confirms 1.
    assert_eq!(out.chosen, vec![0, 1]);
    assert_eq!(out.levels.len(), 2);
    assert_eq!(out.levels[1].candidates, 1);
}

#[test]
fn airspace_index_matches_the_quadratic_definition() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    // The large cases put some pairs beside the crowd, far off in y only: their x-window holds
    // more points than the sweep looks at, so the R*-tree answers for them.
    for (dim, n_full, n_pairs) in [
        (2, 40, 60),
        (3, 25, 30),
        (2, 2, 5),
        (2, 1200, 200),
        (3, 900, 100),
    ] {
        // Clustered intensity-3 points plus scattered far ones; pairs anywhere.
        let mut positions = Vec::new();
        let mut tuples = Vec::new();
        for k in 0..n_full + n_pairs {
            let spread = if k % 7 == 0 { 50.0 } else { 5.0 };
            for axis in 0..dim {
                let beside = k >= n_full && n_full > 500 && k % 4 == 0 && axis == 1;
                positions.push(if beside {
                    if k % 8 == 0 {
                        75.0
                    } else {
                        -75.0
                    }
                } else {
                    rng.random_range(-spread..spread)
                });
            }
            let i = (k + 1) as i64;
            tuples.extend(if k < n_full { [i, i, i] } else { [i, i, 0] });
        }
        let n = n_full + n_pairs;
        let costs = vec![-1.0; n];
        let sizes = [n as i64; 3];
        let input = intensity_input(&tuples, 3, &positions, dim, &costs, &sizes).expect("valid");
        let out = intensity_search(&input, &IntensityOptions::paper()).expect("searches");
        let dist = |a: usize, b: usize| {
            (0..dim)
                .map(|d| (positions[a * dim + d] - positions[b * dim + d]).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        let mut total = 0.0;
        for j in 0..n_full {
            let others: Vec<f64> = (0..n_full)
                .filter(|&b| b != j)
                .map(|b| dist(b, j))
                .collect();
            total += 0.5
                * (others.iter().cloned().fold(f64::INFINITY, f64::min)
                    + others.iter().cloned().fold(0.0, f64::max));
        }
        let d = total / n_full as f64;
        assert!(
            (out.airspace_radius - d).abs() <= 1e-12 * d,
            "{} vs {d}",
            out.airspace_radius
        );
        let ghosts = (0..n)
            .filter(|&c| {
                (0..n_full)
                    .filter(|&b| b != c)
                    .map(|b| dist(b, c))
                    .fold(f64::INFINITY, f64::min)
                    > d
            })
            .count();
        assert_eq!(out.ghosts_dropped, ghosts, "dim {dim}");
    }
}

/// The intensity search written the slow, obvious way (airspace off): m recomputed from
/// scratch at every step.
fn naive_intensity(tuples: &[i64], n_sensors: usize, costs: &[f64], tau: f64) -> Vec<usize> {
    let k = costs.len();
    let tuple = |c: usize| &tuples[c * n_sensors..(c + 1) * n_sensors];
    let ids = |c: usize| -> Vec<(usize, i64)> {
        tuple(c)
            .iter()
            .enumerate()
            .filter(|(_, &t)| t > 0)
            .map(|(s, &t)| (s, t))
            .collect()
    };
    let conflict = |a: usize, b: usize| ids(a).iter().any(|x| ids(b).contains(x));
    let intensity = |c: usize| ids(c).len();
    let m_of = |c: usize, alive: &[usize]| {
        ids(c)
            .iter()
            .filter(|x| !alive.iter().any(|&o| o != c && ids(o).contains(x)))
            .count()
    };
    let mut used: Vec<(usize, i64)> = Vec::new();
    let mut chosen = Vec::new();
    for level in (n_sensors.saturating_sub(1).max(2)..=n_sensors).rev() {
        let members: Vec<usize> = (0..k)
            .filter(|&c| intensity(c) == level && ids(c).iter().all(|x| !used.contains(x)))
            .collect();
        let m0: Vec<usize> = members.iter().map(|&c| m_of(c, &members)).collect();
        let best = m0.iter().copied().max().unwrap_or(0);
        let h: Vec<usize> = members
            .iter()
            .zip(&m0)
            .filter(|(_, &m)| m == best)
            .map(|(&c, _)| c)
            .collect();
        let mut votes = vec![0usize; k];
        for &start in &h {
            let mut alive = members.clone();
            let mut pick = Some(start);
            while let Some(c) = pick {
                votes[c] += 1;
                alive.retain(|&o| !conflict(c, o));
                pick = alive.iter().copied().max_by(|&a, &b| {
                    m_of(a, &alive)
                        .cmp(&m_of(b, &alive))
                        .then(costs[b].total_cmp(&costs[a]))
                        .then(b.cmp(&a))
                });
            }
        }
        let mut confirmed: Vec<usize> = members
            .iter()
            .copied()
            .filter(|&c| votes[c] as f64 > tau * h.len() as f64)
            .collect();
        confirmed.sort_by(|&a, &b| {
            votes[b]
                .cmp(&votes[a])
                .then(costs[a].total_cmp(&costs[b]))
                .then(a.cmp(&b))
        });
        for c in confirmed {
            if ids(c).iter().all(|x| !used.contains(x)) {
                used.extend(ids(c));
                chosen.push(c);
            }
        }
    }
    chosen.sort_unstable();
    chosen
}

#[test]
fn intensity_search_equals_the_obvious_implementation() {
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    for case in 0..200 {
        let n_sensors = if case % 3 == 0 { 4 } else { 3 };
        let sizes: Vec<i64> = (0..n_sensors).map(|_| rng.random_range(1..5)).collect();
        let k = rng.random_range(1..25);
        let mut tuples = Vec::new();
        for _ in 0..k {
            loop {
                let t: Vec<i64> = sizes
                    .iter()
                    .map(|&n| {
                        if rng.random::<f64>() < 0.15 {
                            0
                        } else {
                            rng.random_range(1..=n)
                        }
                    })
                    .collect();
                if t.iter().filter(|&&i| i > 0).count() >= 2 {
                    tuples.extend(t);
                    break;
                }
            }
        }
        // Few distinct costs so that ties happen.
        let costs: Vec<f64> = (0..k).map(|_| -(rng.random_range(1..4) as f64)).collect();
        let positions = vec![0.0; 2 * k];
        let input =
            intensity_input(&tuples, n_sensors, &positions, 2, &costs, &sizes).expect("valid");
        for tau in [0.5, 0.3, 0.0] {
            let fast = intensity_search(
                &input,
                &IntensityOptions::paper()
                    .with_vote_fraction(tau)
                    .expect("valid")
                    .with_valid_airspace(false),
            )
            .expect("searches");
            assert_eq!(
                fast.chosen,
                naive_intensity(&tuples, n_sensors, &costs, tau),
                "case {case} tau {tau}"
            );
        }
    }
}

#[test]
fn points_of_more_than_three_coordinates_are_refused() {
    let err = intensity_input(&[1, 1, 1], 3, &[0.0; 4], 4, &[-1.0], &[1, 1, 1]);
    assert!(matches!(
        err,
        Err(CoreError::Shape {
            arg: "positions",
            ..
        })
    ));
}

#[test]
fn huge_report_counts_cost_no_memory() {
    // Memory follows the candidates, not `sizes`.
    let big = [i64::MAX, i64::MAX, i64::MAX];
    let input =
        intensity_input(&[1, 1, 1, 5, 0, 9], 3, &[0.0; 4], 2, &[-1.0, -1.0], &big).expect("valid");
    let out = intensity_search(&input, &IntensityOptions::paper()).expect("searches");
    assert_eq!(out.chosen, vec![0, 1]);
}

/// Report counts far above the candidates take the sorted path to measurement ids instead of
/// the lookup table: same answer as the obvious implementation either way.
#[test]
fn report_ids_by_sort_equal_those_by_table() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for case in 0..30 {
        let n_sensors = rng.random_range(3..5);
        let sizes: Vec<i64> = (0..n_sensors).map(|_| rng.random_range(2..7)).collect();
        let k = rng.random_range(5..60);
        let mut tuples = Vec::new();
        for _ in 0..k {
            tuples.extend(sizes.iter().map(|&n| rng.random_range(0..=n)));
        }
        let costs: Vec<f64> = (0..k).map(|_| -(rng.random_range(1..9) as f64)).collect();
        let positions = vec![0.0; 2 * k];
        let huge = vec![1i64 << 40; n_sensors];
        let options = IntensityOptions::paper().with_valid_airspace(false);
        let expected = naive_intensity(&tuples, n_sensors, &costs, 0.5);
        for sizes in [&sizes, &huge] {
            let input =
                intensity_input(&tuples, n_sensors, &positions, 2, &costs, sizes).expect("valid");
            let out = intensity_search(&input, &options).expect("searches");
            assert_eq!(out.chosen, expected, "case {case}, sizes {sizes:?}");
        }
    }
}

/// Levels with many start points, where the vote stops early (τ >= 0.5): still the obvious
/// implementation's answer, and the early stop does happen.
#[test]
fn early_decided_vote_equals_the_full_vote() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut stopped_early = 0;
    // Levels of more than one batch (VOTE_BATCH = 128 chains), or nothing can stop early.
    for case in 0..6 {
        let n_sensors = 3;
        let sizes: Vec<i64> = (0..n_sensors).map(|_| rng.random_range(6..12)).collect();
        let k = rng.random_range(260..330);
        let mut tuples = Vec::new();
        for _ in 0..k {
            let t: Vec<i64> = sizes.iter().map(|&n| rng.random_range(1..=n)).collect();
            tuples.extend(t);
        }
        let costs: Vec<f64> = (0..k).map(|_| -(rng.random_range(1..6) as f64)).collect();
        let positions = vec![0.0; 2 * k];
        let input =
            intensity_input(&tuples, n_sensors, &positions, 2, &costs, &sizes).expect("valid");
        for tau in [0.5, 0.8] {
            let options = IntensityOptions::paper()
                .with_vote_fraction(tau)
                .expect("valid")
                .with_valid_airspace(false);
            let fast = intensity_search(&input, &options).expect("searches");
            assert_eq!(
                fast.chosen,
                naive_intensity(&tuples, n_sensors, &costs, tau),
                "case {case} tau {tau}"
            );
            let level = &fast.levels[0];
            stopped_early += usize::from(level.chains < level.starts);
        }
    }
    eprintln!("stopped early in {stopped_early} of 12 levels");
    assert!(
        stopped_early >= 3,
        "the vote stopped early in only {stopped_early} levels"
    );
}
