//! Line-of-sight geometry: where rays meet. These give the closed-form starting points of the
//! iterative fits (METHODS §1 initial guess, §2 eq. 4).

use nalgebra::{SMatrix, SVector};

use crate::geometry::model::{Observation, StateLayout, MAX_DIM};

/// Unit direction of the line of sight with azimuth `az` and elevation `el`.
#[inline]
pub fn direction(azimuth: f64, elevation: f64) -> [f64; 3] {
    let (sa, ca) = azimuth.sin_cos();
    let (se, ce) = elevation.sin_cos();
    [ce * ca, ce * sa, se]
}

/// Where two 3-D rays `o + t·u` come closest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayMeeting {
    /// Closest point on ray a and on ray b.
    pub point_a: [f64; 3],
    pub point_b: [f64; 3],
    /// Ray parameters (ranges along the unit directions) of the two points.
    pub range_a: f64,
    pub range_b: f64,
    /// Distance between the two closest points.
    pub distance: f64,
}

impl RayMeeting {
    pub fn midpoint(&self) -> [f64; 3] {
        std::array::from_fn(|k| 0.5 * (self.point_a[k] + self.point_b[k]))
    }

    /// True when the meeting point lies in front of both sensors.
    pub fn in_front(&self) -> bool {
        self.range_a > 0.0 && self.range_b > 0.0
    }
}

/// Closest points of two lines of sight with unit directions `ua`, `ub`; `None` when they are
/// parallel (no unique closest pair).
pub fn closest_points(
    oa: &[f64; 3],
    ua: &[f64; 3],
    ob: &[f64; 3],
    ub: &[f64; 3],
) -> Option<RayMeeting> {
    let dot = |p: &[f64; 3], q: &[f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    let w: [f64; 3] = std::array::from_fn(|k| oa[k] - ob[k]);
    let b = dot(ua, ub);
    let (d, e) = (dot(ua, &w), dot(ub, &w));
    let denom = 1.0 - b * b;
    if denom <= 1e-14 {
        return None;
    }
    let range_a = (b * e - d) / denom;
    let range_b = (e - b * d) / denom;
    let point_a: [f64; 3] = std::array::from_fn(|k| oa[k] + range_a * ua[k]);
    let point_b: [f64; 3] = std::array::from_fn(|k| ob[k] + range_b * ub[k]);
    let distance = (0..3)
        .map(|k| (point_a[k] - point_b[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    Some(RayMeeting {
        point_a,
        point_b,
        range_a,
        range_b,
        distance,
    })
}

/// Intersection of two 2-D bearing lines from `sa` (bearing `ta`) and `sb` (bearing `tb`), with
/// the ranges along each line; `None` for parallel lines.
pub fn intersect_bearings(
    sa: &[f64; 2],
    ta: f64,
    sb: &[f64; 2],
    tb: f64,
) -> Option<([f64; 2], f64, f64)> {
    let (ua, ub) = ([ta.cos(), ta.sin()], [tb.cos(), tb.sin()]);
    let cross = ua[0] * ub[1] - ua[1] * ub[0];
    if cross.abs() <= 1e-12 {
        return None;
    }
    let w = [sb[0] - sa[0], sb[1] - sa[1]];
    let range_a = (w[0] * ub[1] - w[1] * ub[0]) / cross;
    let range_b = (w[0] * ua[1] - w[1] * ua[0]) / cross;
    Some((
        [sa[0] + range_a * ua[0], sa[1] + range_a * ua[1]],
        range_a,
        range_b,
    ))
}

/// Linear least-squares ("pseudo-linear") estimate of a state from lines of sight: each
/// measured angle says the target lies on a plane (3-D) or line (2-D) through the sensor,
/// `n·(position(t) − sensor) = 0`, which is linear in the state for both motions. Rows are
/// scaled by 1/σ. Biased with noise, exact without; used only as a starting point.
/// Returns `None` when the rays do not determine the state (too few, or degenerate geometry).
pub fn pseudo_linear_state(
    layout: &StateLayout,
    observations: &[Observation],
) -> Option<[f64; MAX_DIM]> {
    match layout.dim() {
        2 => solve_pseudo_linear::<2>(layout, observations),
        3 => solve_pseudo_linear::<3>(layout, observations),
        4 => solve_pseudo_linear::<4>(layout, observations),
        _ => solve_pseudo_linear::<6>(layout, observations),
    }
}

fn solve_pseudo_linear<const D: usize>(
    layout: &StateLayout,
    observations: &[Observation],
) -> Option<[f64; MAX_DIM]> {
    let mut normal = SMatrix::<f64, D, D>::zeros();
    let mut rhs = SVector::<f64, D>::zeros();
    for obs in observations {
        for &(plane_normal, sigma) in &constraint_normals(obs)[..layout.space.angles()] {
            // n·(p(t) − s) = 0 with p(t) linear in the state: gradient row a, target n·s.
            let a = layout.state_gradient(&plane_normal, obs.time);
            let row = SVector::<f64, D>::from_fn(|k, _| a[k] / sigma);
            let target: f64 = (0..3).map(|k| plane_normal[k] * obs.sensor[k]).sum::<f64>() / sigma;
            normal += row * row.transpose();
            rhs += row * target;
        }
    }
    let solution = normal.cholesky()?.solve(&rhs);
    if solution.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut out = [0.0; MAX_DIM];
    out[..D].copy_from_slice(solution.as_slice());
    Some(out)
}

/// Unit normals of the planes (lines in 2-D) that contain the line of sight, with the σ of the
/// angle each one encodes; a planar layout uses only the first.
fn constraint_normals(obs: &Observation) -> [([f64; 3], f64); 2] {
    // Fixed-size: this runs per measurement for every default starting point.
    let (sa, ca) = obs.angles[0].sin_cos();
    let (se, ce) = obs.angles[1].sin_cos();
    let horizontal = ([-sa, ca, 0.0], obs.sigma[0]);
    let vertical = ([-se * ca, -se * sa, ce], obs.sigma[1]);
    [horizontal, vertical]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::model::{predict, Motion, Space};

    #[test]
    fn crossing_rays_meet_at_the_target() {
        let target = [3000.0, 7000.0, 800.0];
        let (oa, ob) = ([0.0, 0.0, 0.0], [20_000.0, 0.0, 10.0]);
        let [a1, e1] = predict(Space::Spatial, &oa, &target);
        let [a2, e2] = predict(Space::Spatial, &ob, &target);
        let m =
            closest_points(&oa, &direction(a1, e1), &ob, &direction(a2, e2)).expect("not parallel");
        assert!(m.distance < 1e-6 && m.in_front());
        for (got, want) in m.midpoint().iter().zip(target) {
            assert!((got - want).abs() < 1e-6);
        }
    }

    #[test]
    fn target_behind_one_sensor_is_flagged() {
        let (oa, ob) = ([0.0, 0.0, 0.0], [10.0, 0.0, 0.0]);
        // Ray a points away from where ray b crosses it.
        let m = closest_points(&oa, &[0.0, -1.0, 0.0], &ob, &direction(2.0, 0.0))
            .expect("not parallel");
        assert!(!m.in_front());
    }

    #[test]
    fn bearing_lines_intersect() {
        let target: [f64; 2] = [4000.0, 9000.0];
        let (sa, sb) = ([0.0, 0.0], [10_000.0, 0.0]);
        let ta = (target[1] - sa[1]).atan2(target[0] - sa[0]);
        let tb = (target[1] - sb[1]).atan2(target[0] - sb[0]);
        let (p, ra, rb) = intersect_bearings(&sa, ta, &sb, tb).expect("not parallel");
        assert!((p[0] - target[0]).abs() < 1e-6 && (p[1] - target[1]).abs() < 1e-6);
        assert!(ra > 0.0 && rb > 0.0);
        assert!(intersect_bearings(&sa, 0.3, &sb, 0.3).is_none());
    }

    #[test]
    fn pseudo_linear_recovers_noiseless_cv_state() {
        let layout = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
        let truth = [1340.0, 15000.0, 1000.0, 173.2, -100.0, 0.0];
        let sensors = [[0.0, 0.0, 0.0], [20_000.0, 0.0, 0.0]];
        let obs: Vec<Observation> = (0..8)
            .flat_map(|k| {
                sensors.iter().enumerate().map(move |(j, s)| {
                    let time = 15.0 * k as f64 + 5.0 * j as f64;
                    let p = layout.position(&truth, time);
                    Observation::new(*s, time, predict(Space::Spatial, s, &p), [5e-3, 5e-3])
                })
            })
            .collect();
        let est = pseudo_linear_state(&layout, &obs).expect("well posed");
        for k in 0..6 {
            assert!(
                (est[k] - truth[k]).abs() < 1e-5 * truth[k].abs().max(1.0),
                "{k}: {}",
                est[k]
            );
        }
    }
}
