//! The driver: every baseline report decided in parallel (step 5), the one-to-one variant's
//! greedy resolution, and the ML triangulation of each chosen line set.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::choice::Choice;
use super::labels::partition;
use super::options::{FormationOptions, Reference};
use super::subsets::{Meeting, PruneCounts, Scene};
use crate::data::{Measurements, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::estimation::fit::gauss_newton::fit;
use crate::evidence::AttributeGate;
use crate::geometry::model::{Motion, Observation, Space, StateLayout};
use crate::progress::{Progress, Silent, Tally};

/// The result, one entry per report of the baseline sensor in table order (`B` of them).
#[derive(Clone, Debug, PartialEq)]
pub struct FormationOutput {
    pub n_sensors: usize,
    /// `B`: the table row of each baseline report.
    pub baseline_rows: Vec<i64>,
    /// `B × S`: the chosen table row per sensor (the baseline's own row in its column), all
    /// −1 but the baseline column where the report has no association.
    pub rows: Vec<i64>,
    /// `B × S`: `m(assoc)` of the baseline report with each chosen report (NaN at the
    /// baseline and where nothing was chosen; 1 without attributes).
    pub support: Vec<f64>,
    /// `B`: eq. 6 cluster radius of the chosen set (NaN when none).
    pub radius: Vec<f64>,
    /// `B × 2`: ML position of the chosen set (NaN when none; a set whose fit failed is
    /// not reported, as if none had been chosen).
    pub positions: Vec<f64>,
    /// `B × 4`: its covariance, row-major 2 × 2.
    pub covariances: Vec<f64>,
    /// `B`: χ² of the bearings at the ML position.
    pub chi2: Vec<f64>,
    /// `N`: the group (baseline index) each input row ends in, −1 for none (see `labels.rs`).
    pub labels: Vec<i64>,
    /// `N`: how many chosen sets hold each row (≤ 1 with one-to-one).
    pub times_chosen: Vec<i64>,
    pub counts: PruneCounts,
}

/// One baseline report's subsets, best set and counts.
type Decided = (Vec<Vec<Meeting>>, Option<Choice>, PruneCounts);

/// Below this many (report × baseline report) pairs a scene is decided on the calling thread.
const SEQUENTIAL_WORK: usize = 2048;

/// Below this many chosen sets the ML fits run on the calling thread (a fit is a few
/// Gauss-Newton steps on M lines: cheaper than the handoff).
const SEQUENTIAL_FITS: usize = 32;

/// Locates the formation from one snapshot of 2-D bearings (METHODS §3). `gate` carries the
/// attributes (`None`: azimuth only). Runs on the current rayon pool; the result does not
/// depend on its size.
///
/// Errors: a 3-D network, fewer than 3 sensors, a baseline or reference sensor that does not
/// exist (or a reference equal to the baseline), an attribute table of the wrong length, more
/// (baseline, other) report pairs than [`FormationOptions::max_pairs`], and `Interrupted` on a
/// stop request.
pub fn locate(
    sensors: &Sensors<'_>,
    measurements: &Measurements<'_>,
    gate: Option<AttributeGate<'_>>,
    options: &FormationOptions,
) -> CoreResult<FormationOutput> {
    locate_reporting(sensors, measurements, gate, options, &Silent)
}

/// [`locate`], reporting the baseline reports decided to `progress` (stage `"baseline
/// reports"`, then `"one-to-one"` for the greedy pass) and stopping, as for Ctrl-C, when it
/// is cancelled. The stop request is polled once per baseline report (a pass over the other
/// sensors' reports) and per greedy step.
pub fn locate_reporting(
    sensors: &Sensors<'_>,
    measurements: &Measurements<'_>,
    gate: Option<AttributeGate<'_>>,
    options: &FormationOptions,
    progress: &dyn Progress,
) -> CoreResult<FormationOutput> {
    check(sensors, measurements, gate.as_ref(), options)?;
    let scene = Scene::new(sensors, measurements, gate, *options);
    let bases = scene.baseline_lines();
    let pairs = bases.len().saturating_mul(measurements.len() - bases.len());
    if pairs > options.max_pairs() {
        return Err(CoreError::CapExceeded {
            what: "(baseline report, other report) pairs",
            count: pairs,
            cap: options.max_pairs(),
            hint: "raise max_pairs, or locate a smaller snapshot (the work grows with the pairs)",
        });
    }
    let stop = || crate::parallel::interrupted() || progress.cancelled();
    let tally = Tally::new(progress, "baseline reports", bases.len() as u64);
    let decide = |b: usize| -> Option<Decided> {
        if stop() {
            return None;
        }
        let mut counts = PruneCounts::default();
        let subsets = scene.subsets(&bases[b], &mut counts);
        let choice = scene.choose(b, &subsets, None, &mut counts);
        // Only the one-to-one pass re-decides, so only it keeps the subsets (B × Σ|A_k|
        // meetings: gigabytes for tens of thousands of reports per sensor).
        let kept = if options.one_to_one() {
            subsets
        } else {
            Vec::new()
        };
        tally.advance(1);
        Some((kept, choice, counts))
    };
    // Handing a small scene to the thread pool costs more than deciding it (criterion
    // `formation/paper_scene`, docs/performance.md); both paths give the same output.
    let decided: Vec<Option<Decided>> = match measurements.len() * bases.len() < SEQUENTIAL_WORK {
        true => (0..bases.len()).map(decide).collect(),
        false => (0..bases.len()).into_par_iter().map(decide).collect(),
    };
    tally.finish();
    let decided: Vec<Decided> = decided
        .into_iter()
        .collect::<Option<_>>()
        .ok_or(CoreError::Interrupted)?;
    let mut counts = PruneCounts::default();
    decided.iter().for_each(|d| counts.add(&d.2));
    let choices = match options.one_to_one() {
        false => decided.into_iter().map(|d| d.1).collect(),
        true => one_to_one(&scene, decided, measurements.len(), &mut counts, progress)?,
    };
    let mut out = assemble(&scene, &choices, counts);
    (out.labels, out.times_chosen) = partition(&out.rows, &out.radius, measurements.len());
    Ok(out)
}

fn check(
    sensors: &Sensors<'_>,
    measurements: &Measurements<'_>,
    gate: Option<&AttributeGate<'_>>,
    options: &FormationOptions,
) -> CoreResult<()> {
    let s = sensors.len();
    if sensors.space() != Space::Planar {
        return Err(CoreError::ill_posed(
            "sensors",
            "the formation method takes 2-D bearing sensors",
        ));
    }
    if s < 3 {
        return Err(CoreError::ill_posed(
            "sensors",
            format!("the baseline least-distance method needs at least 3 sensors, got {s}"),
        ));
    }
    if options.baseline_sensor() >= s {
        return Err(CoreError::out_of_range(
            "baseline_sensor",
            format!(
                "{} is not a sensor of the {s}-sensor network",
                options.baseline_sensor()
            ),
        ));
    }
    if let Reference::Sensor(r) = options.reference() {
        if r >= s || r == options.baseline_sensor() {
            return Err(CoreError::out_of_range(
                "reference",
                format!("sensor {r} must exist (< {s}) and differ from the baseline sensor"),
            ));
        }
    }
    match gate {
        Some(g) if g.table.n_rows() != measurements.len() => Err(CoreError::shape(
            "attributes",
            format!(
                "has {} rows, the measurements {}",
                g.table.n_rows(),
                measurements.len()
            ),
        )),
        _ => Ok(()),
    }
}

/// Greedy one-to-one: accept the baseline report whose best set clusters tightest, mark its
/// lines used, and re-decide the others without them. A report's best radius can only grow
/// as lines are used, so a report popped with an up-to-date radius is the global minimum
/// (lazy evaluation: only reports whose set lost a line are re-decided). Ties go to the
/// lower baseline index.
fn one_to_one(
    scene: &Scene<'_>,
    decided: Vec<Decided>,
    n_rows: usize,
    counts: &mut PruneCounts,
    progress: &dyn Progress,
) -> CoreResult<Vec<Option<Choice>>> {
    let mut used = vec![false; n_rows];
    let mut subsets = Vec::with_capacity(decided.len());
    let mut pending = Vec::with_capacity(decided.len());
    let mut heap = BinaryHeap::new();
    for (b, (subset, choice, _)) in decided.into_iter().enumerate() {
        if let Some(c) = &choice {
            heap.push(Reverse((OrderedRadius(c.radius), b)));
        }
        subsets.push(subset);
        pending.push(choice);
    }
    let mut accepted: Vec<Option<Choice>> = vec![None; pending.len()];
    // Settled reports: accepted, or left without a set (those without one from the start).
    let settled = pending.iter().filter(|c| c.is_none()).count() as u64;
    let tally = Tally::resumed(progress, "one-to-one", settled, pending.len() as u64);
    while let Some(Reverse((_, b))) = heap.pop() {
        if crate::parallel::interrupted() || progress.cancelled() {
            return Err(CoreError::Interrupted);
        }
        let Some(choice) = pending[b].take() else {
            continue;
        };
        let rows = scene.rows_of(&choice);
        if rows.iter().all(|&row| !used[row]) {
            rows.iter().for_each(|&row| used[row] = true);
            accepted[b] = Some(choice);
            tally.advance(1);
            continue;
        }
        match scene.choose(b, &subsets[b], Some(&used), counts) {
            Some(again) => {
                heap.push(Reverse((OrderedRadius(again.radius), b)));
                pending[b] = Some(again);
            }
            None => tally.advance(1),
        }
    }
    tally.finish();
    Ok(accepted)
}

/// A radius ordered totally (NaN last), for the heap.
#[derive(Clone, Copy, Debug, PartialEq)]
struct OrderedRadius(f64);

impl Eq for OrderedRadius {}

impl PartialOrd for OrderedRadius {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for OrderedRadius {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

impl Scene<'_> {
    /// Table rows of a choice's lines, one per sensor.
    fn rows_of(&self, choice: &Choice) -> Vec<usize> {
        choice
            .lines
            .iter()
            .enumerate()
            .map(|(k, &l)| self.lines[k][l as usize].row)
            .collect()
    }
}

fn assemble(scene: &Scene<'_>, choices: &[Option<Choice>], counts: PruneCounts) -> FormationOutput {
    let s = scene.lines.len();
    let bases = scene.baseline_lines();
    let fit = |c: &Option<Choice>| c.as_ref().map(|c| triangulate(scene, c));
    let fitted: Vec<Option<Fitted>> = match choices.len() < SEQUENTIAL_FITS {
        true => choices.iter().map(fit).collect(),
        false => choices.par_iter().map(fit).collect(),
    };
    let mut out = FormationOutput {
        n_sensors: s,
        baseline_rows: bases.iter().map(|l| l.row as i64).collect(),
        rows: Vec::with_capacity(bases.len() * s),
        support: Vec::with_capacity(bases.len() * s),
        radius: Vec::with_capacity(bases.len()),
        positions: Vec::with_capacity(bases.len() * 2),
        covariances: Vec::with_capacity(bases.len() * 4),
        chi2: Vec::with_capacity(bases.len()),
        labels: Vec::new(),
        times_chosen: Vec::new(),
        counts,
    };
    let baseline = scene.options.baseline_sensor();
    for (b, (choice, fit)) in choices.iter().zip(&fitted).enumerate() {
        match (choice, fit) {
            // A set whose ML fit fails (an azimuth of 1e300 rad keeps no digits of its
            // angle) is no association: its report stays unassociated, its lines clutter.
            (Some(c), Some(f)) if f.is_finite() => {
                out.rows.extend(scene.rows_of(c).iter().map(|&r| r as i64));
                out.support.extend_from_slice(&c.support);
                out.radius.push(c.radius);
                out.positions.extend_from_slice(&f.position);
                out.covariances.extend_from_slice(&f.covariance);
                out.chi2.push(f.chi2);
            }
            _ => {
                out.rows.extend((0..s).map(|k| {
                    if k == baseline {
                        bases[b].row as i64
                    } else {
                        -1
                    }
                }));
                out.support.extend(std::iter::repeat_n(f64::NAN, s));
                out.radius.push(f64::NAN);
                out.positions.extend([f64::NAN; 2]);
                out.covariances.extend([f64::NAN; 4]);
                out.chi2.push(f64::NAN);
            }
        }
    }
    out
}

struct Fitted {
    position: [f64; 2],
    covariance: [f64; 4],
    chi2: f64,
}

impl Fitted {
    fn is_finite(&self) -> bool {
        (self.position.iter().chain(&self.covariance))
            .chain([&self.chi2])
            .all(|v| v.is_finite())
    }
}

/// ML position of the chosen lines (the project's addition to the paper), started from the
/// mean of their pairwise intersections; NaN where the fit fails (parallel lines, absurd
/// angles), and the set is then left unassociated.
fn triangulate(scene: &Scene<'_>, choice: &Choice) -> Fitted {
    let observations: Vec<Observation> = choice
        .lines
        .iter()
        .enumerate()
        .map(|(k, &l)| scene.lines[k][l as usize].observation)
        .collect();
    let start = scene.start_point(choice);
    let layout = StateLayout::new(Space::Planar, Motion::Static);
    let outcome = fit(&layout, &observations, &start, scene.options.fit());
    Fitted {
        position: [outcome.estimate[0], outcome.estimate[1]],
        covariance: [
            outcome.covariance[0],
            outcome.covariance[1],
            outcome.covariance[2],
            outcome.covariance[3],
        ],
        chi2: outcome.chi2,
    }
}

impl Scene<'_> {
    fn start_point(&self, choice: &Choice) -> [f64; 2] {
        let lines: Vec<_> = choice
            .lines
            .iter()
            .enumerate()
            .map(|(k, &l)| &self.lines[k][l as usize])
            .collect();
        let mut sum = [0.0; 2];
        let mut n = 0.0;
        for (a, la) in lines.iter().enumerate() {
            for lb in &lines[a + 1..] {
                if let Some((p, _, _)) = super::subsets::intersect(la, lb) {
                    sum = [sum[0] + p[0], sum[1] + p[1]];
                    n += 1.0;
                }
            }
        }
        [sum[0] / n, sum[1] / n]
    }
}
