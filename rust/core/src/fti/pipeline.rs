//! The driver of METHODS §1: candidates → descents → merge → detection → classification →
//! final Gauss-Newton refit of each track.

use std::time::Instant;

use rayon::prelude::*;

use super::candidates;
use super::closeness::{Precomputed, Spreads};
use super::detection::classify;
use super::options::InitiationOptions;
use super::output::{Initiation, StageCounts, StageSeconds, Track};
use super::problem::Problem;
use super::refit::{padded, refit};
use super::scans::{resolve_pairs, Scans};
use super::stages::search_and_detect;
use super::support::{Gate, SupportTable};
use super::track_join;
use super::track_quality;
use crate::data::{Measurements, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::geometry::model::{Motion, StateLayout, MAX_DIM};
use crate::progress::{Progress, Silent};

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
    initiate_reporting(sensors, measurements, spreads, t0, options, &Silent)
}

/// [`initiate`], reporting each pass's candidate formation and search to `progress` (stages
/// `"candidates"` and `"search"`, once per pass).
pub fn initiate_reporting(
    sensors: &Sensors<'_>,
    measurements: &Measurements<'_>,
    spreads: &Spreads<'_>,
    t0: f64,
    options: &InitiationOptions,
    progress: &dyn Progress,
) -> CoreResult<Initiation> {
    let pre = Precomputed::new(sensors, measurements, spreads, t0)?;
    let problem = Problem {
        sensors: *sensors,
        measurements: *measurements,
        layout: StateLayout::new(sensors.space(), Motion::ConstantVelocity { t0 }),
        t0,
        progress,
    };
    let dim = problem.layout.dim();
    let scans = Scans::new(measurements, sensors.len());
    let pairs = resolve_pairs(options.pairs(), &scans)?;
    let mut available = vec![true; measurements.len()];
    let mut run = Run {
        support: options
            .support_gate()
            .then(|| SupportTable::new(&problem, &scans)),
        ..Run::default()
    };

    // Pass 1: the paper's first and last scans, over every row.
    let outer: Vec<[usize; 4]> = pairs
        .iter()
        .flat_map(|&p| scans.scan_slots(p, 1, false))
        .collect();
    let mut states = run.pass(
        &problem,
        &pre,
        &scans,
        &outer,
        None,
        options,
        &mut available,
    )?;
    // Pass 2 (candidate_scans > 1): the next-outermost scans, over the rows pass 1 left. Their
    // targets are missed in an outer scan; the rows already taken cannot be reused, so pass 1's
    // targets cannot be found twice.
    let depth = options.candidate_scans();
    let inner: Vec<[usize; 4]> = pairs
        .iter()
        .flat_map(|&p| scans.scan_slots(p, depth, true))
        .collect();
    if !inner.is_empty() {
        free_dissolved(&problem, &pre, &scans, &states, options, &mut available)?;
        let mask = available.clone();
        states.extend(run.pass(
            &problem,
            &pre,
            &scans,
            &inner,
            Some(&mask),
            options,
            &mut available,
        )?);
    }
    let (counts, mut seconds) = (run.counts, run.seconds);

    let clock = Instant::now();
    let labels = classify(
        &problem,
        &scans,
        &states,
        options.gate_sigmas(),
        options.one_per_scan(),
    )?;
    seconds.detection += clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let (tracks, labels) = finished(&problem, &pre, &scans, &states, labels, options)?;
    seconds.final_fit = clock.elapsed().as_secs_f64();

    Ok(Initiation {
        dim,
        tracks,
        labels,
        stage_counts: counts,
        descent_iterations: run.iterations,
        stage_seconds: seconds,
    })
}

/// What the candidate passes have counted and timed so far.
#[derive(Default)]
struct Run {
    support: Option<SupportTable>,
    counts: StageCounts,
    seconds: StageSeconds,
    iterations: Vec<usize>,
}

impl Run {
    /// One pass: candidates from the scan quadruples `slots` (rows in `mask`, or all), their
    /// descents and merge, and eq. 23 detection on the rows still `available`; returns the
    /// accepted optima's states in acceptance order.
    #[allow(clippy::too_many_arguments)] // one pass's inputs, each used once; a struct would only rename them
    fn pass(
        &mut self,
        problem: &Problem<'_>,
        pre: &Precomputed,
        scans: &Scans,
        slots: &[[usize; 4]],
        mask: Option<&[bool]>,
        options: &InitiationOptions,
        available: &mut [bool],
    ) -> CoreResult<Vec<[f64; MAX_DIM]>> {
        let clock = Instant::now();
        // Pass 2's detection counts only the rows still free, so its gates do too.
        let masked = (self.support.is_some() && mask.is_some())
            .then(|| SupportTable::of_rows(problem, scans, mask));
        let gate = masked.as_ref().or(self.support.as_ref()).map(|table| Gate {
            table,
            scans,
            gate: options.gate_sigmas(),
            n_detect: options.n_detect_for(scans.len()),
            miss_score: options.gate_pd().map_or(0.0, |pd| (1.0 - pd).ln()),
        });
        self.seconds.support += clock.elapsed().as_secs_f64();

        let set = candidates::generate(problem, scans, slots, mask, options, gate.as_ref())?;
        stop_if_stopped(problem)?;
        let mut counts = set.counts;
        self.seconds.candidates += set.seconds_enumerate;
        self.seconds.fit += set.seconds_fit;
        self.seconds.support += set.seconds_support;

        let clock = Instant::now();
        let searched = search_and_detect(
            problem,
            pre,
            scans,
            &set.candidates,
            options,
            gate.as_ref(),
            available,
        );
        stop_if_stopped(problem)?;
        let seconds = clock.elapsed().as_secs_f64();
        let (detection, regate) = (searched.seconds_detection, searched.seconds_regate);
        self.seconds.descent += seconds - detection - regate;
        self.seconds.detection += detection;
        self.seconds.support += regate;
        counts.optima = searched.optima.len();
        counts.merged = searched.merged;
        counts.detected = searched.accepted.len();
        self.iterations
            .extend(searched.optima.iter().map(|o| o.iterations));
        self.counts.accumulate(&counts);
        Ok(searched
            .accepted
            .iter()
            .map(|&i| searched.optima[i].x)
            .collect())
    }
}

/// Gives pass 2 the rows of pass-1 targets that the end of the pipeline ([`finished`]) would
/// dissolve: such a target is usually a poor optimum that took a real target's rows in pass 1
/// (that target missed in an outer scan, so its own candidate exists only in pass 2), and
/// without its rows pass 2 cannot find it. Rows trimmed from a surviving track stay taken:
/// they lie in a target's gate, and freed they would only seed candidates that climb back to
/// it. The pass-1 states stay; the final classification and test decide.
fn free_dissolved(
    problem: &Problem<'_>,
    pre: &Precomputed,
    scans: &Scans,
    states: &[[f64; MAX_DIM]],
    options: &InitiationOptions,
    available: &mut [bool],
) -> CoreResult<()> {
    if options.track_test().is_none() || states.is_empty() {
        return Ok(());
    }
    let (gate, one_per_scan) = (options.gate_sigmas(), options.one_per_scan());
    let classified = classify(problem, scans, states, gate, one_per_scan)?;
    let (_, kept) = finished(problem, pre, scans, states, classified.clone(), options)?;
    let mut survived = vec![false; states.len()];
    for (&was, &is) in classified.iter().zip(&kept) {
        if let (Ok(s), true) = (usize::try_from(was), is >= 0) {
            survived[s] = true;
        }
    }
    for (m, &was) in classified.iter().enumerate() {
        if usize::try_from(was).is_ok_and(|s| !survived[s]) {
            available[m] = true;
        }
    }
    Ok(())
}

/// From classified states to the result's tracks: the final fit, the joining of split tracks,
/// the refine passes and the track test.
fn finished(
    problem: &Problem<'_>,
    pre: &Precomputed,
    scans: &Scans,
    states: &[[f64; MAX_DIM]],
    labels: Vec<i64>,
    options: &InitiationOptions,
) -> CoreResult<(Vec<Track>, Vec<i64>)> {
    let (gate, one_per_scan) = (options.gate_sigmas(), options.one_per_scan());
    let (mut tracks, mut labels) = final_tracks(problem, pre, states, labels);
    let n_detect = options.n_detect_for(scans.len());
    let level = options.track_test_level();
    if let Some(z) = level {
        if let Some(states) = track_join::joined(problem, pre, scans, &tracks, n_detect, gate, z) {
            let relabelled = classify(problem, scans, &states, gate, one_per_scan)?;
            (tracks, labels) = final_tracks(problem, pre, &states, relabelled);
        }
    }
    for _ in 0..options.refine_passes() {
        let refined: Vec<[f64; MAX_DIM]> = tracks.iter().map(|t| padded(&t.estimate)).collect();
        let relabelled = classify(problem, scans, &refined, gate, one_per_scan)?;
        if relabelled == labels {
            break;
        }
        (tracks, labels) = final_tracks(problem, pre, &refined, relabelled);
    }
    // The track test runs once, on the refined tracks: an early classification can give a
    // target wrong rows that a refine pass then corrects.
    let n_rows = labels.len();
    Ok(track_quality::tested(
        problem, pre, scans, tracks, n_rows, n_detect, level,
    ))
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

/// Ends the pipeline between stages when the user asked to stop (Ctrl-C, or the progress
/// watcher): the stages after an interrupted one would otherwise run on its partial output
/// (millions of descents).
fn stop_if_stopped(problem: &Problem<'_>) -> CoreResult<()> {
    match problem.stopped() {
        true => Err(CoreError::Interrupted),
        false => Ok(()),
    }
}
