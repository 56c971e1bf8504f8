//! The driver of METHODS §1: candidates → descents → merge → detection → classification →
//! final Gauss-Newton refit of each track.

use std::time::Instant;

use rayon::prelude::*;

use super::batch::Batch;
use super::candidates;
use super::closeness::{Precomputed, Spreads};
use super::detection::classify;
use super::formation_choice::Formation;
use super::formation_slots::{paper_slots, ranked_rounds, SlotWitnesses};
use super::options::InitiationOptions;
use super::output::{FormationLimit, Initiation, StageCounts, StageSeconds, Track};
use super::problem::Problem;
use super::refit::{padded, refit};
use super::scans::{resolve_pairs, Scans, Slot};
use super::stages::search_and_detect;
use super::support::{Gate, SupportTable};
use super::track_join;
use super::track_quality;
use super::track_swap;
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

    let with_scans = (scans.per_sensor.iter()).filter(|l| l.len() >= 2).count();
    let formation = match options.candidates().resolve(sensors.space(), with_scans) {
        // Without its test (read off the support gate's tables) it is the paper's.
        Formation::Witnessed if !(options.prefit_gates() && options.support_gate()) => {
            Formation::Paper
        }
        other => other,
    };
    let states = match formation {
        Formation::Paper | Formation::Auto | Formation::Witnessed => paper_passes(
            &mut run,
            &problem,
            &pre,
            &scans,
            &pairs,
            options,
            SlotWitnesses::choose(
                formation == Formation::Witnessed,
                with_scans,
                options,
                &scans,
            ),
            &mut available,
        )?,
        Formation::Rounds => {
            let mut states = round_passes(
                &mut run,
                &problem,
                &pre,
                &scans,
                &pairs,
                options,
                &mut available,
            )?;
            // A formation stopped at the user's limit ends there.
            if options.sweep() && run.limit.is_none() {
                states = sweep(
                    &mut run,
                    &problem,
                    &pre,
                    &scans,
                    &pairs,
                    options,
                    states,
                    &mut available,
                )?;
            }
            states
        }
    };
    let (counts, mut seconds) = (run.counts, run.seconds);

    // The sweep that found nothing has already run the end on these very states.
    let (tracks, labels) = match run.end.take() {
        Some(end) => end,
        None => {
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
            let end = finished(&problem, &pre, &scans, &states, labels, options)?;
            seconds.final_fit += clock.elapsed().as_secs_f64();
            end
        }
    };

    Ok(Initiation {
        dim,
        formation,
        limit: run.limit,
        tracks,
        labels,
        stage_counts: counts,
        descent_iterations: run.iterations,
        stage_seconds: seconds,
    })
}

/// The paper's formation: pass 1 on the first and last scans of every pair, over every row;
/// pass 2 (candidate_scans > 1) on the next-outermost scans, over the rows pass 1 left. Their
/// targets are missed in an outer scan; the rows already taken cannot be reused, so pass 1's
/// targets cannot be found twice. `witnesses`: the scans each slot's candidates are tested
/// against before their fit (module `formation_slots`).
#[allow(clippy::too_many_arguments)] // the pipeline's state, as round_passes takes it
fn paper_passes(
    run: &mut Run,
    problem: &Problem<'_>,
    pre: &Precomputed,
    scans: &Scans,
    pairs: &[[usize; 2]],
    options: &InitiationOptions,
    witnesses: SlotWitnesses,
    available: &mut [bool],
) -> CoreResult<Vec<[f64; MAX_DIM]>> {
    let outer = paper_slots(scans, pairs, 1, false, witnesses);
    let depth = options.candidate_scans();
    let inner = paper_slots(scans, pairs, depth, true, witnesses);
    run.slots = outer.len() + inner.len();
    let mut states = run.pass(problem, pre, scans, &outer, None, options, available, 1)?;
    if !inner.is_empty() && run.limit.is_none() {
        free_dissolved(problem, pre, scans, &states, options, true, available)?;
        let mask = available.to_vec();
        let inner_pass = run.pass(
            problem,
            pre,
            scans,
            &inner,
            Some(&mask),
            options,
            available,
            1,
        );
        states.extend(inner_pass?);
    }
    Ok(states)
}

/// The rounds formation: every (pair, round) slot, best first (the most nearly synchronous,
/// then the rounds nearest the middle), in passes of 1, 2, 4, … slots, each over the rows the
/// passes before it left.
fn round_passes(
    run: &mut Run,
    problem: &Problem<'_>,
    pre: &Precomputed,
    scans: &Scans,
    pairs: &[[usize; 2]],
    options: &InitiationOptions,
    available: &mut [bool],
) -> CoreResult<Vec<[f64; MAX_DIM]>> {
    let slots = ranked_rounds(problem, scans, pairs, options);
    run.slots = slots.len();
    // Several slots at once only while the tests before the fits keep their survivors few.
    let at_once = match options.prefit_gates() {
        true => candidates::SLOTS_AT_ONCE,
        false => 1,
    };
    // Once every pair has had two slots, a pass that finds nothing ends the formation.
    let patience = 2 * pairs.len();
    let mut states = Vec::new();
    let (mut start, mut size) = (0usize, 1usize);
    while start < slots.len() {
        let group = &slots[start..(start + size).min(slots.len())];
        if start > 0 {
            // Light (no joins, no refine passes): it runs before every pass.
            free_dissolved(problem, pre, scans, &states, options, false, available)?;
        }
        let mask = (start > 0).then(|| available.to_vec());
        let before = run.counts.detected;
        states.extend(run.pass(
            problem,
            pre,
            scans,
            group,
            mask.as_deref(),
            options,
            available,
            at_once,
        )?);
        start += size;
        size *= 2;
        if run.limit.is_some() || (run.counts.detected == before && start >= patience) {
            break;
        }
    }
    Ok(states)
}

/// The sweep's budget: this share of `max_candidates` (25 000 of the default 500 000).
const SWEEP_SHARE: usize = 20;

/// After the rounds, the sweep: the paper's formation (every pair's first × last scans, then
/// the inner slots down to `candidate_scans`) on the rows the rounds' tracks leave as
/// clutter. It finds the targets whose misses (Pd < 1) left no slot of rounds holding all four
/// of their rays; with the found targets' rows taken, the paper's n⁴ runs over the clutter and
/// those few targets only. Its budget is a twentieth of `max_candidates`; reaching it ends the
/// sweep with what it found, and is not the user's limit (the result does not report it).
///
/// The rows it may use are those the end of the pipeline ([`finished`]: final fit, joins,
/// refine passes, track test) leaves as clutter: detection takes rows a later classification
/// gives back, a missed target's among them, and rows trimmed from a track are clutter there
/// too. When the sweep finds a target, the tracks that end carries on go on (as their refitted
/// states) with the sweep's: a dissolved state kept would take the rows of the target the
/// sweep found in the final classification, and be dissolved again with them. When it finds
/// nothing, the rounds' states go on unchanged, so the answer is the rounds' own.
#[allow(clippy::too_many_arguments)] // the pipeline's state, as round_passes takes it
fn sweep(
    run: &mut Run,
    problem: &Problem<'_>,
    pre: &Precomputed,
    scans: &Scans,
    pairs: &[[usize; 2]],
    options: &InitiationOptions,
    states: Vec<[f64; MAX_DIM]>,
    available: &mut [bool],
) -> CoreResult<Vec<[f64; MAX_DIM]>> {
    let depth = options.candidate_scans();
    let mut slots = paper_slots(scans, pairs, 1, false, SlotWitnesses::Untested);
    slots.extend(paper_slots(
        scans,
        pairs,
        depth,
        true,
        SlotWitnesses::Untested,
    ));
    if slots.is_empty() {
        return Ok(states);
    }
    let (gate, one_per_scan) = (options.gate_sigmas(), options.one_per_scan());
    let clock = Instant::now();
    let classified = classify(problem, scans, &states, gate, one_per_scan)?;
    run.seconds.detection += clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let (tracks, labels) = finished(problem, pre, scans, &states, classified, options)?;
    run.seconds.final_fit += clock.elapsed().as_secs_f64();
    for (free, &label) in available.iter_mut().zip(&labels) {
        *free = label < 0;
    }
    let budget = (options.max_candidates() / SWEEP_SHARE).max(1);
    let swept = (options.clone())
        .with_max_candidates(budget)?
        .with_stop_at_limit(true);
    let mask = available.to_vec();
    let found = run.pass(
        problem,
        pre,
        scans,
        &slots,
        Some(&mask),
        &swept,
        available,
        1,
    )?;
    run.limit = None;
    if found.is_empty() {
        run.end = Some((tracks, labels)); // the pipeline's end of `states`, already run
        return Ok(states);
    }
    let mut carried: Vec<[f64; MAX_DIM]> = tracks.iter().map(|t| padded(&t.estimate)).collect();
    carried.extend(found);
    Ok(carried)
}

/// What the candidate passes have counted and timed so far.
#[derive(Default)]
struct Run {
    support: Option<SupportTable>,
    /// The limit that ended the formation (`stop_at_limit`).
    limit: Option<FormationLimit>,
    /// The formation's scan slots (those of every pass it may run), and those its passes
    /// have formed so far.
    slots: usize,
    slots_formed: usize,
    /// The end of the pipeline ([`finished`]) of the states the formation returns, when a
    /// pass has already run it on exactly those states (the sweep that found nothing).
    end: Option<(Vec<Track>, Vec<i64>)>,
    counts: StageCounts,
    seconds: StageSeconds,
    iterations: Vec<usize>,
}

impl Run {
    /// One pass: candidates from the scan quadruples `slots` (rows in `mask`, or all; formed
    /// `at_once` at a time, [`candidates::SLOTS_AT_ONCE`]), their descents and merge, and eq.
    /// 23 detection on the rows still `available`; returns the accepted optima's states in
    /// acceptance order.
    #[allow(clippy::too_many_arguments)] // one pass's inputs, each used once; a struct would only rename them
    fn pass(
        &mut self,
        problem: &Problem<'_>,
        pre: &Precomputed,
        scans: &Scans,
        slots: &[Slot],
        mask: Option<&[bool]>,
        options: &InitiationOptions,
        available: &mut [bool],
        at_once: usize,
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

        let batch = Batch::new(problem, options, gate.as_ref());
        let set =
            candidates::generate_at_once(problem, scans, slots, mask, options, batch, at_once)?;
        stop_if_stopped(problem)?;
        self.slots_formed += set.slots_formed;
        if let (None, Some(reached)) = (&self.limit, set.limit) {
            self.limit = Some(FormationLimit {
                reached,
                slots_formed: self.slots_formed,
                slots: self.slots,
            });
        }
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
/// dissolve (`thorough`; otherwise the track test alone, without the joins and refine passes,
/// judges them): such a target is usually a poor optimum that took a real target's rows in pass 1
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
    thorough: bool,
    available: &mut [bool],
) -> CoreResult<()> {
    if options.track_test().is_none() || states.is_empty() {
        return Ok(());
    }
    let (gate, one_per_scan) = (options.gate_sigmas(), options.one_per_scan());
    let classified = classify(problem, scans, states, gate, one_per_scan)?;
    let (_, kept) = match thorough {
        true => finished(problem, pre, scans, states, classified.clone(), options)?,
        false => {
            let (tracks, labels) = final_tracks(problem, states, classified.clone());
            let (n_rows, n_detect) = (labels.len(), options.n_detect_for(scans.len()));
            let level = options.track_test_level();
            track_quality::tested(problem, pre, scans, tracks, n_rows, n_detect, level)
        }
    };
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
/// the refine passes, the untangling (module `track_swap`) and the track test.
fn finished(
    problem: &Problem<'_>,
    pre: &Precomputed,
    scans: &Scans,
    states: &[[f64; MAX_DIM]],
    labels: Vec<i64>,
    options: &InitiationOptions,
) -> CoreResult<(Vec<Track>, Vec<i64>)> {
    let (gate, one_per_scan) = (options.gate_sigmas(), options.one_per_scan());
    let (mut tracks, mut labels) = final_tracks(problem, states, labels);
    let n_detect = options.n_detect_for(scans.len());
    let level = options.track_test_level();
    if let Some(z) = level {
        if let Some(states) = track_join::joined(problem, scans, &tracks, n_detect, gate, z) {
            let relabelled = classify(problem, scans, &states, gate, one_per_scan)?;
            (tracks, labels) = final_tracks(problem, &states, relabelled);
        }
    }
    for _ in 0..options.refine_passes() {
        let refined: Vec<[f64; MAX_DIM]> = tracks.iter().map(|t| padded(&t.estimate)).collect();
        let relabelled = classify(problem, scans, &refined, gate, one_per_scan)?;
        if relabelled == labels {
            break;
        }
        (tracks, labels) = final_tracks(problem, &refined, relabelled);
    }
    if options.untangle() {
        tracks = track_swap::untangled(problem, scans, tracks, gate);
    }
    // The track test runs once, on the refined tracks: an early classification can give a
    // target wrong rows that a refine pass then corrects. It labels the rows from the tracks
    // it keeps, so the labels above give only their count.
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
        .map(|(x, r)| refit(problem, x, r))
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
