//! One candidate target (METHODS §1 eq. 20–22) and its Gauss-Newton ML fit from the two ray
//! pairs it is made of (first-scan and last-scan rows of a sensor pair, module `ray_pairs`),
//! started from where each pair's rays meet. Module `candidates` forms and prunes them.

use super::problem::Problem;
use super::ray_pairs::{Meeting, RayPair};
use crate::estimation::fit::gauss_newton::{fit_into, FitSlots};
use crate::estimation::fit::{FitOptions, Termination};
use crate::geometry::los::pseudo_linear_state;
use crate::geometry::model::{Observation, MAX_DIM};

/// Candidate fits stop once the Gauss-Newton step is shorter than this many standard
/// deviations (Mahalanobis). The remaining χ² decrease is then of order its square (0.01),
/// nothing next to the χ² gate, and the descent refines the estimate anyway; stopping there
/// instead of at 1e-6 σ halves the fitting time (clutter 4-tuples have large residuals and
/// Gauss-Newton converges only linearly on them).
const CANDIDATE_STEP_SIGMAS: f64 = 0.1;

/// A fitted candidate: its rows (a-first, b-first, a-last, b-last), X0, the fit's standard
/// deviations and the lower Cholesky factor of its covariance (the descent's scalings).
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    pub rows: [usize; 4],
    pub estimate: [f64; MAX_DIM],
    pub scale: [f64; MAX_DIM],
    /// Row-major `L` with `L·Lᵀ` = covariance (zero past `dim`).
    pub factor: [[f64; MAX_DIM]; MAX_DIM],
    pub chi2: f64,
    /// The tracking gate's score (module `tracking_gate`); `None` when the support gate is
    /// off.
    pub support_score: Option<f64>,
}

/// Gauss-Newton fit of the 4 measurements from the triangulated start; `None` when the fit
/// is singular or non-finite.
pub(super) fn fit_candidate(
    problem: &Problem<'_>,
    first: &RayPair,
    last: &RayPair,
) -> Option<Candidate> {
    let rows = [first.rows[0], first.rows[1], last.rows[0], last.rows[1]];
    let [f, l] = [&first.observations, &last.observations];
    let obs: [Observation; 4] = [f[0], f[1], l[0], l[1]];
    let initial = match (first.meeting, last.meeting) {
        (Some(f), Some(l)) => start_from_meetings(problem, &f, &l),
        _ => pseudo_linear_state(&problem.layout, &obs)?,
    };
    let d = problem.layout.dim();
    let options = FitOptions::default()
        .with_step_sigmas(CANDIDATE_STEP_SIGMAS)
        .unwrap_or_default();
    // Stack slots: no allocation per fit.
    let (mut estimate, mut covariance) = ([0.0; MAX_DIM], [0.0; MAX_DIM * MAX_DIM]);
    let slots = FitSlots {
        estimate: &mut estimate[..d],
        covariance: &mut covariance[..d * d],
    };
    let summary = fit_into(&problem.layout, &obs, &initial[..d], &options, slots);
    if matches!(
        summary.termination,
        Termination::Singular | Termination::NonFinite
    ) || estimate[..d].iter().any(|v| !v.is_finite())
    {
        return None;
    }
    Some(Candidate {
        rows,
        estimate,
        scale: std::array::from_fn(|k| {
            if k < d {
                covariance[k * d + k].sqrt()
            } else {
                0.0
            }
        }),
        factor: cholesky(&covariance[..d * d], d)?,
        chi2: summary.chi2,
        support_score: None,
    })
}

/// Lower Cholesky factor of the row-major `d × d` matrix `a`, or `None` unless it is finite
/// and positive definite.
fn cholesky(a: &[f64], d: usize) -> Option<[[f64; MAX_DIM]; MAX_DIM]> {
    if a.len() < d * d {
        return None;
    }
    let mut l = [[0.0; MAX_DIM]; MAX_DIM];
    for i in 0..d {
        for j in 0..=i {
            let s = a[i * d + j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            if i == j {
                if !(s > 0.0 && s.is_finite()) {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    l.iter().flatten().all(|v| v.is_finite()).then_some(l)
}

/// X0 at t0 from the first and last meeting points: velocity = difference / time.
fn start_from_meetings(problem: &Problem<'_>, first: &Meeting, last: &Meeting) -> [f64; MAX_DIM] {
    let p = problem.layout.space.position_dim();
    let t0 = problem.t0;
    let mut x = [0.0; MAX_DIM];
    for k in 0..p {
        let v = (last.point[k] - first.point[k]) / (last.time - first.time);
        x[k] = first.point[k] + (t0 - first.time) * v;
        x[p + k] = v;
    }
    x
}
