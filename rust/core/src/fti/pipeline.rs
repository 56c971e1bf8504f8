//! The driver of METHODS §1: candidates → descents → merge → detection → classification →
//! final Gauss-Newton refit of each track.

use std::time::Instant;

use rayon::prelude::*;

use super::candidates;
use super::closeness::{closeness, Precomputed, Spreads};
use super::descent::{descend_all, merge};
use super::detection::{classify, detect};
use super::scans::{resolve_pairs, Scans};
use super::{Initiation, InitiationOptions, Problem, StageSeconds, Track};
use crate::data::{Measurements, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::estimation::fit::gauss_newton::fit;
use crate::estimation::fit::{FitOptions, Termination};
use crate::geometry::model::{Motion, StateLayout, MAX_DIM};

/// Fuzzy track initiation of constant-velocity targets with epoch `t0` (METHODS §1).
///
/// Fails only on invalid input or a hit resource cap; every row ends in exactly one track or
/// in clutter (`labels`).
pub fn initiate(
    sensors: &Sensors<'_>,
    measurements: &Measurements<'_>,
    spreads: &Spreads<'_>,
    t0: f64,
    options: &InitiationOptions,
) -> CoreResult<Initiation> {
    let pre = Precomputed::new(sensors, measurements, spreads, t0)?;
    let problem = Problem {
        sensors: *sensors,
        measurements: *measurements,
        layout: StateLayout::new(sensors.space(), Motion::ConstantVelocity { t0 }),
        t0,
    };
    let dim = problem.layout.dim();
    let scans = Scans::new(measurements, sensors.len());
    let pairs = resolve_pairs(options.pairs(), &scans)?;

    let set = candidates::generate(&problem, &scans, &pairs, options)?;
    stop_if_interrupted()?;
    let mut counts = set.counts;
    let mut seconds = StageSeconds {
        candidates: set.seconds_enumerate,
        fit: set.seconds_fit,
        ..StageSeconds::default()
    };

    let clock = Instant::now();
    let optima = descend_all(&pre, &set.candidates, options.descent());
    stop_if_interrupted()?;
    let order = merge(&optima, dim, options.merge_tol());
    seconds.descent = clock.elapsed().as_secs_f64();
    counts.optima = optima.len();
    counts.merged = order.len();

    let clock = Instant::now();
    let accepted = detect(
        &problem,
        &scans,
        &optima,
        &order,
        options.gate(),
        options.n_detect(),
        options.one_per_scan(),
    );
    counts.detected = accepted.len();
    let states: Vec<[f64; MAX_DIM]> = accepted.iter().map(|&i| optima[i].x).collect();
    let labels = classify(
        &problem,
        &scans,
        &states,
        options.gate(),
        options.one_per_scan(),
    )?;
    seconds.detection = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let (mut tracks, mut labels) = final_tracks(&problem, &pre, &states, labels);
    for _ in 0..options.refine_passes() {
        let refined: Vec<[f64; MAX_DIM]> = tracks.iter().map(|t| padded(&t.estimate)).collect();
        let relabelled = classify(
            &problem,
            &scans,
            &refined,
            options.gate(),
            options.one_per_scan(),
        )?;
        if relabelled == labels {
            break;
        }
        (tracks, labels) = final_tracks(&problem, &pre, &refined, relabelled);
    }
    seconds.final_fit = clock.elapsed().as_secs_f64();

    Ok(Initiation {
        dim,
        tracks,
        labels,
        stage_counts: counts,
        descent_iterations: optima.iter().map(|o| o.iterations).collect(),
        stage_seconds: seconds,
    })
}

fn padded(estimate: &[f64]) -> [f64; MAX_DIM] {
    let mut x = [0.0; MAX_DIM];
    x[..estimate.len()].copy_from_slice(estimate);
    x
}

/// Refits each classified target on its rows (in parallel, in order). A target whose refit
/// fails (its rows no longer determine a state after classification) is dissolved: its rows
/// become clutter and later tracks move up one index.
fn final_tracks(
    problem: &Problem<'_>,
    pre: &Precomputed,
    states: &[[f64; MAX_DIM]],
    labels: Vec<i64>,
) -> (Vec<Track>, Vec<i64>) {
    let mut rows: Vec<Vec<usize>> = vec![Vec::new(); states.len()];
    for (m, &label) in labels.iter().enumerate() {
        if let Ok(t) = usize::try_from(label) {
            rows[t].push(m);
        }
    }
    let fitted: Vec<Option<Track>> = states
        .par_iter()
        .zip(rows.par_iter())
        .map(|(x, r)| refit(problem, pre, x, r))
        .collect();
    let mut tracks = Vec::new();
    let mut out = vec![-1i64; labels.len()];
    for track in fitted.into_iter().flatten() {
        for &m in &track.measurements {
            out[m] = tracks.len() as i64;
        }
        tracks.push(track);
    }
    (tracks, out)
}

fn refit(
    problem: &Problem<'_>,
    pre: &Precomputed,
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
        closeness: closeness(pre, &outcome.estimate),
        estimate: outcome.estimate,
        covariance: outcome.covariance,
        chi2: outcome.chi2,
        measurements: rows.to_vec(),
    })
}

/// What [`candidates_of`] returns: the fitted candidates, the stage counts, the scans and
/// the resolved pairs.
#[cfg(test)]
pub(crate) type CandidateRun = (
    Vec<candidates::Candidate>,
    super::StageCounts,
    Scans,
    Vec<[usize; 2]>,
);

/// Candidates only (no search), for tests and diagnostics.
#[cfg(test)]
pub(crate) fn candidates_of(
    sensors: &Sensors<'_>,
    measurements: &Measurements<'_>,
    t0: f64,
    options: &InitiationOptions,
) -> CoreResult<CandidateRun> {
    let problem = Problem {
        sensors: *sensors,
        measurements: *measurements,
        layout: StateLayout::new(sensors.space(), Motion::ConstantVelocity { t0 }),
        t0,
    };
    let scans = Scans::new(measurements, sensors.len());
    let pairs = resolve_pairs(options.pairs(), &scans)?;
    let set = candidates::generate(&problem, &scans, &pairs, options)?;
    stop_if_interrupted()?;
    Ok((set.candidates, set.counts, scans, pairs))
}

/// Ends the pipeline between stages when the user asked to stop: the stages after an
/// interrupted one would otherwise run on its partial output (millions of descents).
fn stop_if_interrupted() -> CoreResult<()> {
    match crate::parallel::interrupted() {
        true => Err(CoreError::Interrupted),
        false => Ok(()),
    }
}
