//! The motion-corrected ray gate (3-D, a project extension of the ray gate; on whenever
//! `ray_gate_sigmas` is): a candidate's own velocity replaces the `v_max` slack of the pair rule.
//!
//! The ray gate judges one ray pair alone, so for asynchronous sensors it must allow the
//! target to move `v_max·|t_a − t_b|` between the two samples (2.5 km at the paper's 5 s and
//! 500 m/s) and lets most clutter pairs through; the χ² gate then rejects them only after a
//! Gauss-Newton fit each (the paper scene: 1 200 fits for 50 survivors). Once a first-scan
//! pair is combined with a last-scan pair, the candidate has a velocity estimate
//! `v = (P_last − P_first)/(t_last − t_first)` from the two meeting points; moving ray b by
//! `v·(t_a − t_b)` puts the target on both lines at the same instant, so for a true candidate
//! the two lines meet up to noise. The rule: in both pairs, the corrected closest approach is
//! at most `ray_gate_sigmas · (√((σ_a·r_a)² + (σ_b·r_b)²) + |t_a − t_b|·δv)`, where δv bounds the
//! velocity estimate's own error, `(noise_first + noise_last)/(t_last − t_first)` — the
//! meeting points are each good to their noise. Rejected candidates are never fitted.

use super::options::InitiationOptions;
use super::ray_pairs::RayPair;
use crate::geometry::model::Space;

/// What the speed rule and this gate read of a ray pair with a meeting, in one small record:
/// the tests visit millions of pairs, and a [`RayPair`] spans several cache lines.
#[derive(Clone, Copy, Debug)]
pub(super) struct Motion {
    /// The meeting's point and time.
    pub(super) point: [f64; 3],
    pub(super) time: f64,
    /// Lateral spread of the meeting from angle noise, as the ray gate computes it.
    noise: f64,
    /// `t_a − t_b`, the time between the pair's two rays.
    dt: f64,
    /// [`RayPair::normal`].
    normal: Option<([f64; 3], f64)>,
}

impl Motion {
    /// The record of `pair`, or `None` without a meeting.
    pub(super) fn of(pair: &RayPair) -> Option<Self> {
        let m = pair.meeting?;
        let [oa, ob] = &pair.observations;
        let (sa, sb) = (oa.sigma[0].max(oa.sigma[1]), ob.sigma[0].max(ob.sigma[1]));
        Some(Self {
            point: m.point,
            time: m.time,
            noise: ((sa * m.range_a).powi(2) + (sb * m.range_b).powi(2)).sqrt(),
            dt: oa.time - ob.time,
            normal: pair.normal,
        })
    }
}

/// Whether the candidate of two pairs, their records `first` and `last`, passes (always
/// when the rule is off, in 2-D, or when a meeting is missing: the rules before it decide
/// those).
pub(super) fn passes(
    space: Space,
    first: Option<&Motion>,
    last: Option<&Motion>,
    options: &InitiationOptions,
) -> bool {
    match (first, last) {
        (Some(f), Some(l)) => passes_motion(space, f, l, options),
        _ => true,
    }
}

/// [`passes`] of two pairs with meetings.
fn passes_motion(space: Space, f: &Motion, l: &Motion, options: &InitiationOptions) -> bool {
    let Some(gate) = options.ray_gate_sigmas() else {
        return true;
    };
    if space == Space::Planar {
        return true;
    }
    let span = l.time - f.time;
    if span.is_nan() || span <= 0.0 {
        return true;
    }
    let v: [f64; 3] = std::array::from_fn(|k| (l.point[k] - f.point[k]) / span);
    let dv = (f.noise + l.noise) / span;
    [f, l]
        .iter()
        .all(|pair| corrected_distance_passes(pair, &v, gate, dv))
}

fn corrected_distance_passes(pair: &Motion, v: &[f64; 3], gate: f64, dv: f64) -> bool {
    let dt = pair.dt;
    // The lines' distance once sensor b moves by v·dt: along their common normal (module
    // `ray_pairs`), the distance of the closest points `closest_points` would find.
    match pair.normal {
        Some((n, offset)) => {
            let along = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
            (offset - dt * along).abs() <= gate * (pair.noise + dt.abs() * dv)
        }
        None => true, // parallel lines: nothing to judge
    }
}

#[cfg(test)]
mod tests {
    use super::Motion;
    use crate::fti::candidate::fit_candidate;
    use crate::fti::options::{InitiationOptions, CHI2_2DOF_999};
    use crate::fti::problem::Problem;
    use crate::fti::ray_pairs::{ray_pairs, RayPair};
    use crate::fti::scans::Scans;
    use crate::fti::tests::sim;

    /// The gate on two ray pairs.
    fn passes(
        problem: &Problem<'_>,
        f: &RayPair,
        l: &RayPair,
        options: &InitiationOptions,
    ) -> bool {
        let (f, l) = (Motion::of(f), Motion::of(l));
        super::passes(problem.layout.space, f.as_ref(), l.as_ref(), options)
    }

    /// Every 4-tuple of the outer scans of two cluttered paper runs, brute force: the gate
    /// keeps every candidate whose fit passes the χ² gate and rejects most of the others.
    #[test]
    fn the_gate_keeps_every_candidate_the_chi2_gate_keeps() {
        for seed in [2024, 5] {
            let sc = sim::paper(seed, true, 8, 8);
            let sensors = sc.sensors();
            let table = sc.measurements(&sensors);
            let problem = sim::problem(sensors, table);
            let scans = Scans::new(&table, 2);
            let [a1, b1, a2, b2] = scans.scan_slots([0, 1], 1, false)[0].map(|k| scans.scan(k));
            // The pairs the pipeline combines: past the ray gate and the behind-sensor rule.
            let options = InitiationOptions::default();
            let pairs = |ra: &[usize], rb: &[usize]| -> Vec<RayPair> {
                ray_pairs(&problem, ra, rb, &options)
                    .expect("under the cap")
                    .0
            };
            let (firsts, lasts) = (pairs(a1, b1), pairs(a2, b2));
            let (mut kept_by_chi2, mut rejected) = (0, 0);
            for f in &firsts {
                for l in &lasts {
                    let good =
                        fit_candidate(&problem, f, l).is_some_and(|c| c.chi2 <= CHI2_2DOF_999);
                    let pass = passes(&problem, f, l, &options);
                    assert!(pass || !good, "seed {seed}: rows {:?} {:?}", f.rows, l.rows);
                    kept_by_chi2 += usize::from(good);
                    rejected += usize::from(!pass);
                }
            }
            assert!(kept_by_chi2 >= 4 && rejected > 8 * firsts.len() * lasts.len() / 10);
        }
    }
}
