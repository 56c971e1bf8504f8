//! The 2-D solvers against brute force, and their input checks.

use super::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Min over all maps assigning `min(nr, nc)` pairs; `None` if every such map is forbidden.
fn brute_dense(nr: usize, nc: usize, c: &[f64]) -> Option<f64> {
    fn go(i: usize, nr: usize, nc: usize, c: &[f64], used: &mut Vec<bool>, left: usize) -> f64 {
        if i == nr {
            return if left == 0 { 0.0 } else { f64::INFINITY };
        }
        let mut best = if nr - i > left {
            go(i + 1, nr, nc, c, used, left)
        } else {
            f64::INFINITY
        };
        for j in 0..nc {
            if used[j] || left == 0 {
                continue;
            }
            used[j] = true;
            best = best.min(c[i * nc + j] + go(i + 1, nr, nc, c, used, left - 1));
            used[j] = false;
        }
        best
    }
    let v = go(0, nr, nc, c, &mut vec![false; nc], nr.min(nc));
    v.is_finite().then_some(v)
}

#[test]
fn dense_matches_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for case in 0..300 {
        let (nr, nc) = (rng.random_range(0..6usize), rng.random_range(0..6usize));
        let c: Vec<f64> = (0..nr * nc)
            .map(|_| {
                if rng.random_bool(0.15) {
                    f64::INFINITY
                } else {
                    rng.random_range(-5..10i32) as f64
                }
            })
            .collect();
        match (solve_dense(nr, nc, &c), brute_dense(nr, nc, &c)) {
            (Ok(a), Some(best)) => {
                assert_eq!(a.cost, best, "case {case}: {nr}x{nc} {c:?}");
                let cols: Vec<usize> = a.row_to_col.iter().flatten().copied().collect();
                assert_eq!(cols.len(), nr.min(nc));
                let mut sorted = cols.clone();
                sorted.sort_unstable();
                sorted.dedup();
                assert_eq!(sorted.len(), cols.len(), "case {case}: column reused");
            }
            (Err(CoreError::IllPosed { .. }), None) => {}
            (got, want) => panic!("case {case}: got {got:?}, brute force {want:?}"),
        }
    }
}

#[test]
fn dense_rejects_bad_input() {
    assert!(matches!(
        solve_dense(2, 2, &[0.0; 3]),
        Err(CoreError::Shape { arg: "costs", .. })
    ));
    let e = solve_dense(1, 2, &[0.0, f64::NAN]).unwrap_err();
    assert_eq!(
        e,
        CoreError::NonFinite {
            arg: "costs",
            index: 1
        }
    );
    let e = solve_dense(2, 2, &[1.0, f64::INFINITY, 2.0, f64::INFINITY]).unwrap_err();
    assert!(matches!(e, CoreError::IllPosed { .. }), "{e}");
}

fn brute_sparse(m: &SparseCosts, a: &[f64], b: &[f64]) -> f64 {
    fn go(i: usize, m: &SparseCosts, a: &[f64], b: &[f64], used: &mut Vec<bool>) -> f64 {
        if i == m.n_rows() {
            return (0..m.n_cols()).filter(|&j| !used[j]).map(|j| b[j]).sum();
        }
        let mut best = a[i] + go(i + 1, m, a, b, used);
        for (j, c) in m.row(i).collect::<Vec<_>>() {
            if !used[j] {
                used[j] = true;
                best = best.min(c + go(i + 1, m, a, b, used));
                used[j] = false;
            }
        }
        best
    }
    go(0, m, a, b, &mut vec![false; m.n_cols()])
}

#[test]
fn sparse_matches_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for case in 0..400 {
        let (nr, nc) = (rng.random_range(0..6usize), rng.random_range(0..6usize));
        let mut trip = Vec::new();
        for i in 0..nr {
            for j in 0..nc {
                // Some duplicates on purpose: the cheaper one must count.
                for _ in 0..rng.random_range(0..3) {
                    if rng.random_bool(0.4) {
                        trip.push((i, j, rng.random_range(-20..5i32) as f64));
                    }
                }
            }
        }
        let m = SparseCosts::from_triplets(nr, nc, &trip).unwrap();
        let a: Vec<f64> = (0..nr).map(|_| rng.random_range(-6..3i32) as f64).collect();
        let b: Vec<f64> = (0..nc).map(|_| rng.random_range(-6..3i32) as f64).collect();
        let s = solve_sparse(&m, &a, &b).unwrap();
        assert_eq!(
            s.cost,
            brute_sparse(&m, &a, &b),
            "case {case}: {trip:?} a={a:?} b={b:?}"
        );
        for (i, j) in s.row_to_col.iter().enumerate() {
            if let Some(j) = j {
                assert_eq!(s.col_to_row[*j], Some(i));
                assert!(
                    m.row(i).any(|e| e.0 == *j),
                    "case {case}: forbidden pair used"
                );
            }
        }
    }
}

#[test]
fn reused_solver_matches_fresh_solves() {
    // One solver through problems that grow and shrink: leftovers of an earlier solve
    // must not leak into a later one.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut solver = SparseSolver::default();
    for case in 0..200 {
        let (nr, nc) = (rng.random_range(0..30usize), rng.random_range(0..30usize));
        let mut trip = Vec::new();
        for k in 0..nr * nc {
            if rng.random_bool(0.3) {
                trip.push((k / nc, k % nc, rng.random_range(-9..3i32) as f64));
            }
        }
        let m = SparseCosts::from_triplets(nr, nc, &trip).unwrap();
        let a: Vec<f64> = (0..nr).map(|_| rng.random_range(-4..2i32) as f64).collect();
        let b: Vec<f64> = (0..nc).map(|_| rng.random_range(-4..2i32) as f64).collect();
        let fresh = sparse_core(&m, &a, &b);
        assert_eq!(solver.solve(&m, &a, &b), &fresh, "case {case}");
    }
}

#[test]
fn sparse_with_prohibitive_unassigned_costs_equals_dense() {
    // Beyond brute-force sizes: forcing every row and column to be assigned makes the
    // sparse problem a dense square one, plus the constant it subtracts out.
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for n in [1usize, 7, 30, 60] {
        let c: Vec<f64> = (0..n * n)
            .map(|_| rng.random_range(0..50i32) as f64)
            .collect();
        let trip: Vec<_> = (0..n * n).map(|k| (k / n, k % n, c[k])).collect();
        let m = SparseCosts::from_triplets(n, n, &trip).unwrap();
        let s = solve_sparse(&m, &vec![1e4; n], &vec![1e4; n]).unwrap();
        assert_eq!(s.cost, solve_dense(n, n, &c).unwrap().cost, "n = {n}");
        assert!(s.row_to_col.iter().all(Option::is_some));
    }
}

#[test]
fn sparse_rejects_bad_input() {
    let e = SparseCosts::new(2, 2, vec![0, 1], vec![0], vec![1.0]).unwrap_err();
    assert!(
        matches!(
            e,
            CoreError::Shape {
                arg: "row_offsets",
                ..
            }
        ),
        "{e}"
    );
    let e = SparseCosts::new(1, 2, vec![0, 1], vec![2], vec![1.0]).unwrap_err();
    assert_eq!(e.to_string(), "col_indices: entry 0 is 2 but n_cols is 2");
    let e = SparseCosts::new(2, 2, vec![0, 2, 1], vec![0, 1], vec![1.0, 1.0]).unwrap_err();
    assert!(
        matches!(
            e,
            CoreError::OutOfRange {
                arg: "row_offsets",
                ..
            }
        ),
        "{e}"
    );
    let m = SparseCosts::from_triplets(1, 1, &[(0, 0, 1.0)]).unwrap();
    assert!(matches!(
        solve_sparse(&m, &[], &[0.0]),
        Err(CoreError::Shape {
            arg: "row_unassigned",
            ..
        })
    ));
    let e = solve_sparse(&m, &[0.0], &[f64::INFINITY]).unwrap_err();
    assert_eq!(
        e,
        CoreError::NonFinite {
            arg: "col_unassigned",
            index: 0
        }
    );
    assert!(SparseCosts::from_triplets(1, 1, &[(3, 0, 1.0)]).is_err());
}

/// Square finite matrices take Jonker & Volgenant's initialisation: against brute force on
/// small ones full of ties, and on larger ones against the same matrix with an extra
/// all-forbidden column (rectangular, so solved without the initialisation).
#[test]
fn the_initialised_square_solve_is_optimal() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    for case in 0..400 {
        let n = rng.random_range(2..7usize);
        let c: Vec<f64> = (0..n * n)
            .map(|_| rng.random_range(-3..4i32) as f64)
            .collect();
        let a = solve_dense(n, n, &c).unwrap();
        assert_eq!(Some(a.cost), brute_dense(n, n, &c), "case {case}: {c:?}");
    }
    for (case, n) in [40usize, 97, 150].into_iter().enumerate() {
        for spread in [3.0, 1e6] {
            let c: Vec<f64> = (0..n * n)
                .map(|_| rng.random_range(0.0f64..spread).floor())
                .collect();
            let mut wide = Vec::with_capacity(n * (n + 1));
            for row in c.chunks_exact(n) {
                wide.extend_from_slice(row);
                wide.push(f64::INFINITY);
            }
            let square = solve_dense(n, n, &c).unwrap();
            let plain = solve_dense(n, n + 1, &wide).unwrap();
            assert_eq!(
                square.cost, plain.cost,
                "case {case}, n {n}, spread {spread}"
            );
            let mut cols: Vec<usize> = square.row_to_col.iter().flatten().copied().collect();
            cols.sort_unstable();
            cols.dedup();
            assert_eq!(cols.len(), n);
        }
    }
}

/// The complete sparse solve equals the dense solve with `+inf` at the absent entries: random
/// rectangular problems both ways, feasible and not, with ties and duplicate entries.
#[test]
fn the_complete_sparse_solve_equals_the_dense_one() {
    let mut rng = ChaCha8Rng::seed_from_u64(33);
    let mut infeasible = 0;
    for case in 0..600 {
        let (nr, nc) = (rng.random_range(0..9usize), rng.random_range(0..9usize));
        let density = rng.random_range(0.15..1.0);
        let mut dense = vec![f64::INFINITY; nr * nc];
        let mut triplets = Vec::new();
        for i in 0..nr {
            for j in 0..nc {
                if rng.random_bool(density) {
                    let c = rng.random_range(-4..5i32) as f64;
                    dense[i * nc + j] = c;
                    triplets.push((i, j, c));
                    if rng.random_bool(0.1) {
                        triplets.push((i, j, c + 2.0)); // a dearer duplicate never counts
                    }
                }
            }
        }
        let sparse = SparseCosts::from_triplets(nr, nc, &triplets).unwrap();
        match (solve_sparse_complete(&sparse), solve_dense(nr, nc, &dense)) {
            (Ok(s), Ok(d)) => {
                assert_eq!(s.cost, d.cost, "case {case}: {nr}x{nc}");
                let mut cols: Vec<usize> = s.row_to_col.iter().flatten().copied().collect();
                assert_eq!(cols.len(), nr.min(nc), "case {case}");
                assert!(s
                    .row_to_col
                    .iter()
                    .enumerate()
                    .all(|(i, j)| j.is_none_or(|j| dense[i * nc + j].is_finite())));
                cols.sort_unstable();
                cols.dedup();
                assert_eq!(cols.len(), nr.min(nc), "case {case}: column reused");
            }
            (Err(CoreError::IllPosed { .. }), Err(CoreError::IllPosed { .. })) => infeasible += 1,
            (s, d) => panic!("case {case}: sparse {s:?}, dense {d:?}"),
        }
    }
    assert!(
        infeasible > 20,
        "the infeasible branch was exercised ({infeasible})"
    );
}

/// A sparse problem whose few distinct costs, signed zeros among them, tie in almost every
/// search, with unassigned costs as often tied.
fn tie_heavy(rng: &mut ChaCha8Rng, nr: usize, nc: usize) -> (SparseCosts, Vec<f64>, Vec<f64>) {
    const VALUES: [f64; 5] = [-0.0, 0.0, -1.0, -2.0, -3.0];
    let pick = |rng: &mut ChaCha8Rng| VALUES[rng.random_range(0..VALUES.len())];
    let mut triplets = Vec::new();
    for i in 0..nr {
        for j in 0..nc {
            if rng.random_bool(0.6) {
                triplets.push((i, j, pick(rng)));
            }
        }
    }
    let a = (0..nr).map(|_| pick(rng)).collect();
    let b = (0..nc).map(|_| pick(rng)).collect();
    (SparseCosts::from_triplets(nr, nc, &triplets).unwrap(), a, b)
}

/// The flat list and the heap pick the same column at every step, ties and signed zeros
/// included: the same matchings from the cold, complete and warm-started sparse solves.
/// (Flipping the list's index tie rule, or its free-first rule, makes this fail.)
#[test]
fn the_flat_list_and_the_heap_give_the_same_matchings() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut list, mut heap) = (sap::SparseWork::default(), sap::SparseWork::heap_only());
    for _ in 0..300 {
        let (nr, nc) = (rng.random_range(1..12usize), rng.random_range(1..12usize));
        let (costs, a, b) = tie_heavy(&mut rng, nr, nc);
        let by_list = sap::sparse(&mut list, &costs, &a, &b).to_vec();
        assert!(list.took_list() && !heap.took_list());
        assert_eq!(by_list, sap::sparse(&mut heap, &costs, &a, &b));
        // The complete solve takes no more rows than columns (feasible or not).
        let wide = if nr <= nc { costs } else { costs.transposed() };
        assert_eq!(
            sap::sparse_full(&mut list, &wide),
            sap::sparse_full(&mut heap, &wide)
        );
        let (mut warm_list, mut warm_heap) = (sap::WarmState::default(), sap::WarmState::default());
        for _ in 0..4 {
            let (costs, a, b) = tie_heavy(&mut rng, nr, nc);
            let by_list = sap::sparse_warm(&mut list, &mut warm_list, &costs, &a, &b).to_vec();
            assert_eq!(
                by_list,
                sap::sparse_warm(&mut heap, &mut warm_heap, &costs, &a, &b)
            );
        }
    }
}

/// An `nr × nc` matrix of `value`s with each entry `forbidden` with probability `forbid`, and
/// its diagonal at `diagonal`, so that a complete assignment exists.
fn gated<T: Copy>(
    rng: &mut ChaCha8Rng,
    (nr, nc): (usize, usize),
    forbid: f64,
    forbidden: T,
    diagonal: T,
    mut value: impl FnMut(&mut ChaCha8Rng) -> T,
) -> Vec<T> {
    let mut c: Vec<T> = (0..nr * nc)
        .map(|_| match rng.random_bool(forbid) {
            true => forbidden,
            false => value(rng),
        })
        .collect();
    (0..nr.min(nc)).for_each(|i| c[i * nc + i] = diagonal);
    c
}

/// An `f32` matrix is solved as the `f64` matrix of its values: the same columns and cost,
/// on every path (square with the start, rectangular, transposed, `+inf`, the sparse path of
/// a mostly forbidden matrix). Entries near 1000 spaced by f32's step there: sums of them are
/// exact in f64 but not in f32, so arithmetic in single precision would show.
#[test]
fn f32_matrices_are_solved_exactly_as_their_f64_values() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let step = 2f32.powi(-14); // f32's spacing in [512, 1024)
    let shapes = [
        (1, 1),
        (5, 5),
        (4, 7),
        (7, 4),
        (30, 30),
        (80, 80),
        (70, 90),
        (90, 70),
    ];
    let mut sparse_cases = 0;
    for (case, &(nr, nc)) in shapes.iter().cycle().take(64).enumerate() {
        let forbid = [0.97, 0.0, 0.6][case % 3];
        let c32 = gated(&mut rng, (nr, nc), forbid, f32::INFINITY, 1000.0, |rng| {
            1000.0 + step * rng.random_range(0..64u16) as f32
        });
        let c64: Vec<f64> = c32.iter().map(|&x| f64::from(x)).collect();
        let allowed = c64.iter().filter(|c| c.is_finite()).count();
        sparse_cases += usize::from(as_sparse(nr, nc, &c32, allowed).is_some());
        match (solve_dense(nr, nc, &c32), solve_dense(nr, nc, &c64)) {
            (Ok(a), Ok(b)) => {
                assert_eq!(a.row_to_col, b.row_to_col, "case {case}: {nr}x{nc}");
                assert_eq!(a.cost, b.cost, "case {case}");
                if nr * nc <= 36 {
                    assert_eq!(Some(a.cost), brute_dense(nr, nc, &c64), "case {case}");
                }
            }
            (Err(CoreError::IllPosed { .. }), Err(CoreError::IllPosed { .. })) => {}
            (a, b) => panic!("case {case}: f32 {a:?}, f64 {b:?}"),
        }
    }
    assert!(
        sparse_cases >= 6,
        "the sparse path ran {sparse_cases} times"
    );
    let e = solve_dense(1, 2, &[0.0f32, f32::NAN]).unwrap_err();
    assert!(
        matches!(
            e,
            CoreError::NonFinite {
                arg: "costs",
                index: 1
            }
        ),
        "{e:?}"
    );
}

/// A square matrix with forbidden pairs but a finite entry in every row and column gets
/// Jonker & Volgenant's start; its optimum equals the sparse solver's on the allowed entries
/// (an independent path); one with a forbidden column, or with two rows that may take only
/// the same column, is refused as before.
#[test]
fn forbidden_pairs_with_the_start_match_the_sparse_solver() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    for case in 0..60 {
        let n = rng.random_range(2..70usize);
        let share = [0.1, 0.3, 0.45][case % 3];
        let mut c: Vec<f64> = (0..n * n)
            .map(|_| {
                if rng.random_bool(share) {
                    f64::INFINITY
                } else {
                    f64::from(rng.random_range(0..20u8)) // ties
                }
            })
            .collect();
        for i in 0..n {
            c[i * n + (i * 7 + case) % n] = f64::from(rng.random_range(0..20u8));
            // feasible
        }
        let triplets: Vec<(usize, usize, f64)> = (0..n * n)
            .filter(|&k| c[k].is_finite())
            .map(|k| (k / n, k % n, c[k]))
            .collect();
        let sparse = SparseCosts::from_triplets(n, n, &triplets).unwrap();
        let (dense, reference) = (
            solve_dense(n, n, &c).unwrap(),
            solve_sparse_complete(&sparse),
        );
        assert_eq!(dense.cost, reference.unwrap().cost, "case {case}: n = {n}");
        let cols: Vec<usize> = dense.row_to_col.iter().flatten().copied().collect();
        assert!(cols
            .iter()
            .enumerate()
            .all(|(i, &j)| c[i * n + j].is_finite()));
        let mut sorted = cols.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), n, "case {case}: a column reused");
        // A forbidden column: no complete assignment, refused as ill-posed.
        let j = case % n;
        (0..n).for_each(|i| c[i * n + j] = f64::INFINITY);
        assert!(matches!(
            solve_dense(n, n, &c),
            Err(CoreError::IllPosed { .. })
        ));
    }
    // Every row and column has a finite entry (so the start runs), but rows 0 and 1 may take
    // only column 0: no complete assignment, refused as ill-posed.
    let n = 6;
    let mut c = vec![f64::INFINITY; n * n];
    c[0] = 1.0;
    c[n] = 2.0;
    for i in 2..n {
        (1..n).for_each(|j| c[i * n + j] = (i * j % 5) as f64);
    }
    assert!(matches!(
        solve_dense(n, n, &c),
        Err(CoreError::IllPosed { .. })
    ));
}

/// `prepare_dense(..)?.solve()` answers as `solve_dense` does, on every path (empty, the
/// sparse path of a mostly forbidden matrix, dense, transposed) and with the same errors.
#[test]
fn a_prepared_matrix_solves_as_solve_dense() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let shapes = [(0, 4), (3, 3), (5, 9), (9, 5), (70, 70), (80, 66)];
    let mut sparse_cases = 0;
    for (case, &(nr, nc)) in shapes.iter().cycle().take(48).enumerate() {
        let forbid = [0.0, 0.3, 0.97][case % 3];
        let mut c = gated(&mut rng, (nr, nc), forbid, f64::INFINITY, 1.0, |rng| {
            rng.random_range(0.0..10.0)
        });
        if case % 7 == 6 && !c.is_empty() {
            c[nr * nc / 2] = f64::NAN;
        }
        let allowed = c.iter().filter(|c| c.is_finite()).count();
        sparse_cases += usize::from(as_sparse(nr, nc, &c, allowed).is_some());
        let prepared = prepare_dense(nr, nc, &c).and_then(|p| p.solve());
        match (prepared, solve_dense(nr, nc, &c)) {
            (Ok(a), Ok(b)) => assert_eq!(a, b, "case {case}"),
            (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "case {case}"),
            (a, b) => panic!("case {case}: prepared {a:?}, direct {b:?}"),
        }
    }
    assert!(
        sparse_cases >= 4,
        "the sparse path ran {sparse_cases} times"
    );
    assert!(prepare_dense(2, 2, &[0.0; 3]).is_err());
}

/// The sparse share follows the measured crossovers (about 7 % at 300², 20 % at 1000², 30 % at
/// 3000²), grows with the size, and stays within [0.05, 0.3] beyond them.
#[test]
fn the_sparse_share_grows_with_the_size() {
    for (side, expected) in [(300usize, 0.07), (1000, 0.19), (3000, 0.30)] {
        let share = sparse_max_share(side * side);
        assert!((share - expected).abs() < 0.01, "{side}²: {share}");
    }
    let shares: Vec<f64> = (64..6000)
        .step_by(97)
        .map(|s| sparse_max_share(s * s))
        .collect();
    assert!(shares.windows(2).all(|w| w[0] <= w[1]));
    assert_eq!(sparse_max_share(64 * 64), 0.05);
    assert_eq!(sparse_max_share(10_000 * 10_000), 0.3);
}
