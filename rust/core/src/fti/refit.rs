//! The Gauss-Newton ML refit of a track on its rows, which the end of the pipeline, the
//! track join and the track test all run.

use super::output::Track;
use super::problem::Problem;
use crate::estimation::fit::gauss_newton::fit;
use crate::estimation::fit::{FitOptions, Termination};
use crate::geometry::model::MAX_DIM;

/// The track of `rows` (in any order) refitted from `start`; the tests' tracks.
#[cfg(test)]
pub(super) fn refit_rows(problem: &Problem<'_>, start: &[f64], mut rows: Vec<usize>) -> Track {
    rows.sort_unstable();
    refit(problem, &padded(start), &rows).expect("fits")
}

/// `estimate` (X0 of the layout's dimension) in a state of the stages' fixed size.
pub(super) fn padded(estimate: &[f64]) -> [f64; MAX_DIM] {
    let mut x = [0.0; MAX_DIM];
    x[..estimate.len()].copy_from_slice(estimate);
    x
}

/// The track of `rows` fitted from `start`, or `None` when they cannot determine a state
/// (too few angles) or the fit is singular or not finite. Its closeness is left NaN: the
/// joins and the track test refit many tracks that never reach the result, so R is computed
/// once, for the tracks the track test keeps (module `track_quality`).
pub(super) fn refit(
    problem: &Problem<'_>,
    start: &[f64; MAX_DIM],
    rows: &[usize],
) -> Option<Track> {
    let d = problem.layout.dim();
    if rows.len() * problem.layout.space.angles() < d {
        return None;
    }
    let obs: Vec<_> = rows.iter().map(|&m| problem.observation(m)).collect();
    let outcome = fit(&problem.layout, &obs, &start[..d], &FitOptions::default());
    let usable = !matches!(
        outcome.termination,
        Termination::Singular | Termination::NonFinite
    ) && outcome
        .estimate
        .iter()
        .chain(&outcome.covariance)
        .all(|v| v.is_finite());
    usable.then(|| Track {
        closeness: f64::NAN,
        estimate: outcome.estimate,
        covariance: outcome.covariance,
        chi2: outcome.chi2,
        measurements: rows.to_vec(),
    })
}
