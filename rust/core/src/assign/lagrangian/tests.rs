//! Tests of the Lagrangian solver against brute force and of its options.

use super::*;
use crate::assign::test_support::{brute_force, random_problem};
use crate::error::CoreError;

/// The subgradient loop alone: no end-of-solve polish and no time limit, so a slow machine
/// stops no solve early.
fn unpolished() -> LagrangianOptions {
    let options = LagrangianOptions::recommended().with_polish(false);
    options.with_time_limit(None).expect("no limit is valid")
}

#[test]
fn bounds_bracket_the_optimum_and_usually_hit_it() {
    for order in [SensorOrder::Auto, SensorOrder::Given] {
        bracket_and_hit(&unpolished().with_sensor_order(order));
    }
    bracket_and_hit(&unpolished().with_polish(true));
}

fn bracket_and_hit(opts: &LagrangianOptions) {
    let (mut hits, n) = (0, 150);
    for seed in 0..n {
        let s = 2 + seed as usize % 3;
        let p = random_problem(seed, s, 4, 3, 8);
        let opt = brute_force(&p);
        let sol = solve(&p, opts);
        let scale = opt.abs().max(1.0);
        assert_eq!(p.evaluate(&sol.chosen), Ok(sol.primal_cost), "seed {seed}");
        assert!(
            sol.primal_cost >= opt - 1e-9 * scale,
            "seed {seed}: primal below optimum"
        );
        assert!(
            sol.dual_bound <= opt + 1e-9 * scale,
            "seed {seed}: bound above optimum"
        );
        assert_eq!(sol.gap, relative_gap(sol.primal_cost, sol.dual_bound));
        assert!(sol.primal_cost - opt <= sol.gap * sol.primal_cost.abs().max(1.0) + 1e-9);
        match sol.termination {
            Termination::Optimal => {
                assert!((sol.primal_cost - opt).abs() <= 1e-9 * scale, "seed {seed}")
            }
            Termination::GapReached => assert!(sol.gap <= opts.gap_tol()),
            _ => {}
        }
        if s == 2 {
            assert_eq!(
                sol.termination,
                Termination::Optimal,
                "seed {seed}: S = 2 is exact"
            );
        }
        hits += usize::from((sol.primal_cost - opt).abs() <= 1e-9 * scale);
    }
    assert!(
        hits * 10 >= n as usize * 9,
        "optimum found in only {hits} of {n}"
    );
}

thread_local! {
    /// Solves of this thread that left tuples proven out (module `lagrangian`'s `prove_out`).
    pub(super) static REDUCTIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// With tuples proven out during the solve, the answers stay bracketed by the optimum: on
/// random problems of 3 and 4 sensors with up to 7 reports each, where most solves run long
/// enough to leave some out, the primal is feasible and never below the optimum, the bound
/// never above it, and the optimum is found in most.
#[test]
fn answers_stay_bracketed_when_tuples_are_proven_out() {
    REDUCTIONS.with(|n| n.set(0));
    let (mut hits, n) = (0, 100);
    for seed in 0..n {
        let p = random_problem(1_000 + seed, 3 + seed as usize % 2, 7, 5, 14);
        let opt = brute_force(&p);
        let scale = opt.abs().max(1.0);
        let sol = solve(
            &p,
            &LagrangianOptions::default().with_time_limit(None).unwrap(),
        );
        assert_eq!(p.evaluate(&sol.chosen), Ok(sol.primal_cost), "seed {seed}");
        assert!(sol.primal_cost >= opt - 1e-9 * scale, "seed {seed}");
        assert!(sol.dual_bound <= opt + 1e-9 * scale, "seed {seed}");
        hits += usize::from((sol.primal_cost - opt).abs() <= 1e-9 * scale);
    }
    let reductions = REDUCTIONS.with(|n| n.get());
    assert!(reductions >= 15, "only {reductions} reductions");
    assert!(
        hits * 10 >= n as usize * 9,
        "optimum found in only {hits} of {n}"
    );
}

#[test]
fn is_deterministic_and_respects_max_iter() {
    let base = unpolished()
        .with_max_iter(3)
        .unwrap()
        .with_gap_tol(0.0)
        .unwrap();
    for p in [
        random_problem(3, 4, 6, 4, 30),
        random_problem(5, 3, 8, 5, 40),
    ] {
        for opts in [
            base.clone(),
            base.clone().with_polish(true),
            base.clone().with_sensor_order(SensorOrder::Given),
        ] {
            let a = solve(&p, &opts);
            assert_eq!(a, solve(&p, &opts));
            assert!(a.iterations <= 3);
        }
    }
}

#[test]
fn empty_problem_is_optimal_at_zero() {
    let p = SdProblem::new(vec![0, 0, 0, 1, 1, 1], 3, vec![-1.0, 4.0], vec![1, 1, 1]).unwrap();
    let s = solve(&p, &LagrangianOptions::default());
    assert_eq!((s.chosen.len(), s.primal_cost, s.dual_bound), (0, 0.0, 0.0));
    assert_eq!(s.termination, Termination::Optimal);
}

#[test]
fn options_reject_out_of_range_values() {
    let d = LagrangianOptions::default();
    assert!(matches!(
        d.clone().with_max_iter(0),
        Err(CoreError::OutOfRange {
            arg: "max_iter",
            ..
        })
    ));
    assert!(matches!(
        d.clone().with_gap_tol(f64::NAN),
        Err(CoreError::OutOfRange { arg: "gap_tol", .. })
    ));
    assert!(matches!(
        d.clone().with_step_scale(2.5),
        Err(CoreError::OutOfRange {
            arg: "step_scale",
            ..
        })
    ));
    assert!(matches!(
        d.with_stall_iters(0),
        Err(CoreError::OutOfRange {
            arg: "stall_iters",
            ..
        })
    ));
}

/// A time limit past what the clock can represent (up to `Duration::MAX`, 1.8e19 s) panicked
/// adding itself to `Instant::now()`; it now never binds.
#[test]
fn a_time_limit_past_the_clock_never_binds() {
    let p = random_problem(3, 4, 6, 4, 30);
    let unlimited = solve(&p, &unpolished().with_time_limit(None).unwrap());
    for seconds in [2f64.powi(63), 1e19, 1.8e19] {
        let limit = Some(std::time::Duration::from_secs_f64(seconds));
        let s = solve(&p, &unpolished().with_time_limit(limit).unwrap());
        assert_eq!(s, unlimited, "{seconds}");
    }
}
