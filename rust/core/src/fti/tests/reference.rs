//! The unpruned paper algorithm, written as four nested loops, and the test that the
//! pipeline with every pruning rule off is exactly it.

use super::{candidates_of, run, sim};
use crate::fti::candidate::{fit_candidate, Candidate};
use crate::fti::ray_pairs::RayPair;
use crate::fti::scans::Scans;
use crate::fti::{InitiationOptions, Problem};
use crate::geometry::model::{Motion, StateLayout};

/// Every 4-tuple of every pair, fitted from the same start as the pipeline uses.
pub fn all_fitted(problem: &Problem<'_>, scans: &Scans, pairs: &[[usize; 2]]) -> Vec<Candidate> {
    let mut out = Vec::new();
    for &[a, b] in pairs {
        let (a1, a2) = scans.first_last(a).expect("validated");
        let (b1, b2) = scans.first_last(b).expect("validated");
        for &ra1 in scans.scan(a1) {
            for &rb1 in scans.scan(b1) {
                for &ra2 in scans.scan(a2) {
                    for &rb2 in scans.scan(b2) {
                        let f = RayPair::of(problem, ra1, rb1);
                        let l = RayPair::of(problem, ra2, rb2);
                        out.extend(fit_candidate(problem, &f, &l));
                    }
                }
            }
        }
    }
    out
}

/// Every pruning rule switched off.
pub fn rules_off() -> InitiationOptions {
    InitiationOptions::default()
        .with_ray_gate_sigmas(None)
        .and_then(|o| o.with_v_max(None))
        .and_then(|o| o.with_chi2_gate(None))
        .expect("None is always valid")
        .with_reject_behind(false)
}

#[test]
fn all_rules_off_is_the_unpruned_paper_algorithm() {
    for sc in [sim::paper(9, true, 1, 3), sim::planar(9, true, 1, 3)] {
        let sensors = sc.sensors();
        let table = sc.measurements(&sensors);
        let (got, counts, scans, pairs) =
            candidates_of(&sensors, &table, 0.0, &rules_off()).expect("runs");
        let problem = Problem {
            sensors,
            measurements: table,
            layout: StateLayout::new(sc.space, Motion::ConstantVelocity { t0: 0.0 }),
            t0: 0.0,
            progress: &crate::progress::Silent,
        };
        let expected = all_fitted(&problem, &scans, &pairs);
        assert_eq!(counts.raw, counts.v_max);
        assert_eq!(got, expected);
        // Rules so loose they prune nothing change nothing downstream either.
        let loose = InitiationOptions::default()
            .with_ray_gate_sigmas(Some(1e12))
            .and_then(|o| o.with_v_max(Some(1e12)))
            .and_then(|o| o.with_chi2_gate(Some(1e300)))
            .expect("valid")
            .with_reject_behind(false);
        let (a, b) = (
            run(&sc, &rules_off()).expect("runs"),
            run(&sc, &loose).expect("runs"),
        );
        assert_eq!(
            (a.tracks, a.labels, a.descent_iterations),
            (b.tracks, b.labels, b.descent_iterations)
        );
    }
}
