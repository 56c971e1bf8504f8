//! Many scans in one call: each scan enumerated and solved on its own (METHODS §2), the
//! scans in parallel. A stream of scans pays one crossing from Python instead of one per
//! scan, and the scans share the cores. Each scan's result is what the one-scan calls give;
//! the results do not depend on the thread count.

use std::borrow::Cow;

use rayon::prelude::*;

use super::false_alarms::table_density;
use super::{
    enumerate_with_attributes, intensity_search, Candidates, DetectionModel, EnumerateOptions,
    IntensityInput, IntensityOptions,
};
use crate::assign::branch_bound::{self, BranchBoundOptions};
use crate::assign::lagrangian::{self, LagrangianOptions};
use crate::assign::{CandidateSet, Limit, SdProblem, Termination};
use crate::data::{Measurements, ReportOverrides, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::progress::{Progress, Tally};

/// The solver each scan's candidates go to.
#[derive(Debug, Clone)]
pub enum ScanSolver {
    Intensity(IntensityOptions),
    Lagrangian(LagrangianOptions),
    /// The core's branch-and-bound (not HiGHS, which lives in Python).
    Exact(BranchBoundOptions),
}

/// The rows of the whole table that make up each scan: `rows[offsets[k]..offsets[k + 1]]`,
/// in table order within a scan (the one-scan calls see them in that order).
#[derive(Debug, Clone, Copy)]
pub struct Scans<'a> {
    pub rows: &'a [usize],
    pub offsets: &'a [usize],
}

/// One scan's answer: per row of the scan (in [`Scans`] order) its target index within the
/// scan, or −1 for a false alarm; and the targets' ML positions (`targets × dim`).
#[derive(Debug, Clone, PartialEq)]
pub struct ScanResult {
    pub labels: Vec<i64>,
    pub positions: Vec<f64>,
    pub targets: usize,
    /// The branch-and-bound stopped at its node cap without proving its answer optimal (only
    /// with [`ScanSolver::Exact`]): a caller whose one-scan path hands such a problem to
    /// another solver (the Python layer's HiGHS) re-solves this scan that way.
    pub node_limited: bool,
}

/// Associates every scan. `false_alarm_density` holds one value per scan and sensor
/// (row-major `scans × S`), or is `None` for each scan's default from its own reports
/// ([`false_alarms`](super::false_alarms)).
///
/// Fails on invalid input (naming the scan), or with `Interrupted` on a stop request. Reports
/// the scans done to `progress` (stage `"scans"`).
pub fn associate_scans(
    sensors: &Sensors<'_>,
    table: &Measurements<'_>,
    scans: Scans<'_>,
    (pd, false_alarm_density): (&[f64], Option<&[f64]>),
    (enumerate, solver): (&EnumerateOptions, &ScanSolver),
    progress: &dyn Progress,
) -> CoreResult<Vec<ScanResult>> {
    let n_scans = scans.offsets.len().saturating_sub(1);
    let s = sensors.len();
    if let Some(given) = false_alarm_density.filter(|d| d.len() != n_scans * s) {
        return Err(CoreError::shape(
            "false_alarm_density",
            format!(
                "expected scans × sensors = {n_scans} × {s} values, got {}",
                given.len()
            ),
        ));
    }
    crate::data::check_offsets(
        &scans.offsets.iter().map(|&o| o as i64).collect::<Vec<_>>(),
        scans.rows.len(),
        "rows",
    )?;
    if let Some(&bad) = scans.rows.iter().find(|&&r| r >= table.len()) {
        return Err(CoreError::out_of_range(
            "rows",
            format!("row {bad} is beyond the table's {} rows", table.len()),
        ));
    }
    let tally = Tally::new(progress, "scans", n_scans as u64);
    let results = (0..n_scans)
        .into_par_iter()
        .map(|k| {
            if crate::parallel::interrupted() || progress.cancelled() {
                return Err(CoreError::Interrupted);
            }
            let rows = &scans.rows[scans.offsets[k]..scans.offsets[k + 1]];
            let density = match false_alarm_density {
                Some(given) => Cow::Borrowed(&given[k * s..(k + 1) * s]),
                None => Cow::Owned(table_density(table, rows.iter().copied(), sensors)),
            };
            let result = one_scan(sensors, table, rows, (pd, &density), enumerate, solver);
            tally.advance(1);
            result
        })
        .collect();
    tally.finish();
    results
}

fn one_scan(
    sensors: &Sensors<'_>,
    table: &Measurements<'_>,
    rows: &[usize],
    (pd, density): (&[f64], &[f64]),
    enumerate: &EnumerateOptions,
    solver: &ScanSolver,
) -> CoreResult<ScanResult> {
    let sensor: Vec<i64> = rows.iter().map(|&r| table.sensor(r) as i64).collect();
    let time = vec![0.0; rows.len()];
    let (azimuth, elevation): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .map(|&r| {
            let [a, e] = table.angles(r);
            (a, e)
        })
        .unzip();
    let given = table.overrides();
    let positions: Option<Vec<f64>> = given.positions.map(|_| {
        rows.iter()
            .flat_map(|&r| table.sensor_position(sensors, r))
            .collect()
    });
    let sigmas: Option<[Vec<f64>; 2]> = (given.sigma_azimuth.is_some()
        || given.sigma_elevation.is_some())
    .then(|| [0, 1].map(|k| rows.iter().map(|&r| table.sigma(sensors, r)[k]).collect()));
    let overrides = ReportOverrides {
        positions: positions.as_deref(),
        sigma_azimuth: sigmas.as_ref().map(|[a, _]| a.as_slice()),
        sigma_elevation: sigmas.as_ref().map(|[_, e]| e.as_slice()),
    };
    let scan = Measurements::new(sensors, &sensor, &time, &azimuth, &elevation)?
        .with_overrides(sensors, overrides)?;
    let detection = DetectionModel::new(sensors, pd, density)?;
    let candidates = enumerate_with_attributes(sensors, &scan, &detection, enumerate, None)?;
    let (chosen, node_limited) = solve(&candidates, solver)?;
    let mut labels = vec![-1; rows.len()];
    let (s, dim) = (candidates.n_sensors, candidates.dim);
    let mut positions = Vec::with_capacity(chosen.len() * dim);
    for (t, &k) in chosen.iter().enumerate() {
        for &r in &candidates.rows[k * s..(k + 1) * s] {
            if let Ok(r) = usize::try_from(r) {
                labels[r] = t as i64;
            }
        }
        positions.extend_from_slice(&candidates.positions[k * dim..(k + 1) * dim]);
    }
    Ok(ScanResult {
        labels,
        positions,
        targets: chosen.len(),
        node_limited,
    })
}

/// The chosen candidate indices, ascending, as the one-scan solvers return them, and whether
/// the branch-and-bound stopped at its node cap.
fn solve(c: &Candidates, solver: &ScanSolver) -> CoreResult<(Vec<usize>, bool)> {
    let tuples: Vec<usize> = c.tuples.iter().map(|&v| v as usize).collect();
    let chosen = match solver {
        ScanSolver::Intensity(options) => {
            let set = CandidateSet::new(tuples, c.n_sensors, c.costs.clone(), c.sizes.clone())?;
            let input = IntensityInput::new(set, c.positions.clone(), c.dim)?;
            (intensity_search(&input, options)?.chosen, false)
        }
        ScanSolver::Lagrangian(options) => {
            let problem = SdProblem::new(tuples, c.n_sensors, c.costs.clone(), c.sizes.clone())?;
            (lagrangian::solve(&problem, options).chosen, false)
        }
        ScanSolver::Exact(options) => {
            let problem = SdProblem::new(tuples, c.n_sensors, c.costs.clone(), c.sizes.clone())?;
            let solved = branch_bound::solve(&problem, options);
            let capped = solved.termination == Termination::NotProven(Limit::Nodes);
            (solved.chosen, capped)
        }
    };
    Ok(chosen)
}
