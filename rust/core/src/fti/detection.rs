//! Target detection (eq. 23) and measurement classification with ambiguity resolution
//! (eq. 24).
//!
//! A row m of sensor j is *related* to a state X̂ when its normalised squared residual
//! `d²_m = (Δβ/σβ_j)² + (Δε/σε_j)²` (2-D: `(Δθ/σ_j)²`) is below `g²`.
//!
//! **Detection.** Optima are visited in the options' order (module `detection_order`: the
//! paper's decreasing R, ties by lower candidate index, or by the membership of the rows
//! each would take, the default); each counts its related rows among those not yet removed;
//! with more than `Nd` it is accepted and those rows are removed.
//!
//! **One per scan** (`one_per_scan`, default on — a project choice the paper leaves
//! implicit): a target is a single point, so it produces at most one measurement per
//! (sensor, scan). Detection then counts, in each scan, only the related row with the
//! smallest residual, and removes only those. Without it, two targets that one sensor sees
//! within a few σ of each other (paper targets 1 and 4 from sensor 1: ~1.4σ apart) are
//! both related to each of that sensor's two rows per scan: the first target accepted takes
//! all of them and the second falls below Nd.
//!
//! **Classification (paper §5, eq. 24).** After detection every row is related to every
//! accepted target by eq. 23 over the full table; a row related to several goes to the one
//! with the smallest `d²` (ties: lower track index) — order-independent. With one-per-scan,
//! each (sensor, scan) is instead resolved as a gated minimum-cost assignment: rows ↔
//! targets, each at most once, minimising `Σ (d² − g²)` over the chosen related pairs (every
//! pair has negative cost, so as many pairs as possible are made, preferring small
//! residuals). When no target is the smallest-residual choice of two rows of one scan this is
//! exactly eq. 24; otherwise it is eq. 24's maximum-likelihood reading under the
//! one-measurement-per-scan constraint. Rows related to no target are clutter.

use rayon::prelude::*;

use super::descent::Optimum;
use super::options::InitiationOptions;
use super::problem::Problem;
use super::row_window::RowWindows;
use super::scans::Scans;
use crate::assign::lap::solve_dense;
use crate::error::CoreResult;
use crate::geometry::angles::wrap;
use crate::geometry::model::{predict, Space, MAX_DIM};

/// `d²` of row `m` against state `x` (NaN only for a non-finite state).
pub fn residual2(problem: &Problem<'_>, x: &[f64], m: usize) -> f64 {
    let obs = problem.observation(m);
    let target = problem.layout.position(x, obs.time);
    let predicted = predict(problem.layout.space, &obs.sensor, &target);
    residual2_from(problem.layout.space, obs.angles, obs.sigma, predicted)
}

/// `d²` of measured `angles` with stds `sigma` against the angles `predicted` for their
/// sensor and time: what [`residual2`] computes once the prediction is made.
#[inline]
fn residual2_from(
    space: Space,
    angles: [f64; 2],
    sigma: [f64; 2],
    [azimuth, elevation]: [f64; 2],
) -> f64 {
    let da = wrap(angles[0] - azimuth) / sigma[0];
    match space {
        Space::Planar => da * da,
        Space::Spatial => {
            let de = wrap(angles[1] - elevation) / sigma[1];
            da * da + de * de
        }
    }
}

/// Calls `each(m, d²)`, with the number [`residual2`] gives, for the rows `m` of scan `k` that
/// can relate to `x` under `gate2` (module `row_window`), in the scan's order; the others have
/// `d² ≥ gate2`. The rows share the sensor and the time, hence the prediction: it is made once
/// (two arctangents) instead of once per row. `near` is scratch.
fn for_each_near_residual2(
    problem: &Problem<'_>,
    windows: &RowWindows<'_>,
    k: usize,
    x: &[f64],
    gate2: f64,
    near: &mut Vec<usize>,
    mut each: impl FnMut(usize, f64),
) {
    let rows = windows.scans.scan(k);
    let Some(&first) = rows.first() else {
        return;
    };
    let probe = problem.observation(first);
    let target = problem.layout.position(x, probe.time);
    let predicted = predict(problem.layout.space, &probe.sensor, &target);
    windows.near(k, predicted[0], gate2.sqrt(), near);
    let space = problem.layout.space;
    for &p in near.iter() {
        let m = rows[p];
        // In the plane the stored elevation (NaN) is not read.
        let angles = problem.measurements.angles(m);
        let sigma = problem.measurements.sigma(&problem.sensors, m);
        each(m, residual2_from(space, angles, sigma, predicted));
    }
}

/// Related rows of `x` among the `available` ones (all related, or the smallest-residual
/// related row of each scan), ascending; `each_d2` sees the `d²` of each, in scan order.
/// `windows` indexes the scans (module `row_window`).
pub(super) fn related_rows_with(
    problem: &Problem<'_>,
    windows: &RowWindows<'_>,
    x: &[f64],
    gate2: f64,
    one_per_scan: bool,
    available: &[bool],
    mut each_d2: impl FnMut(f64),
) -> Vec<usize> {
    let mut out = Vec::new();
    let mut near = Vec::new();
    for k in 0..windows.scans.len() {
        let rows = windows.scans.scan(k);
        if !rows.iter().any(|&m| available[m]) {
            continue; // nothing to relate: no prediction
        }
        let mut best: Option<(f64, usize)> = None;
        for_each_near_residual2(problem, windows, k, x, gate2, &mut near, |m, d2| {
            if !available[m] || d2.is_nan() || d2 >= gate2 {
                return;
            }
            if !one_per_scan {
                out.push(m);
                each_d2(d2);
            } else if best.is_none_or(|(b, _)| d2 < b) {
                best = Some((d2, m));
            }
        });
        if let Some((d2, m)) = best {
            out.push(m);
            each_d2(d2);
        }
    }
    out.sort_unstable();
    out
}

/// Eq. 23 detection in the paper's order: the merged optima `order` as given (by decreasing
/// R). See [`detection_order::detect`](super::detection_order::detect).
pub(super) fn detect_by_closeness(
    problem: &Problem<'_>,
    scans: &Scans,
    optima: &[Optimum],
    order: &[usize],
    options: &InitiationOptions,
    available: &mut [bool],
) -> Vec<usize> {
    let gate2 = options.gate_sigmas() * options.gate_sigmas();
    let n_detect = options.n_detect_for(scans.len());
    let one = options.one_per_scan();
    let windows = RowWindows::new(problem, scans);
    let mut accepted = Vec::new();
    for &i in order {
        let x = &optima[i].x;
        let related = related_rows_with(problem, &windows, x, gate2, one, available, |_| {});
        if related.len() > n_detect {
            for &m in &related {
                available[m] = false;
            }
            accepted.push(i);
        }
    }
    accepted
}

/// Classifies every row: the index of its target in `targets`, or −1 (see the module doc).
pub fn classify(
    problem: &Problem<'_>,
    scans: &Scans,
    targets: &[[f64; MAX_DIM]],
    gate: f64,
    one_per_scan: bool,
) -> CoreResult<Vec<i64>> {
    let n = problem.measurements.len();
    let gate2 = gate * gate;
    // Each target's related rows, scan by scan; targets in parallel, then scans in parallel
    // (each scan's rows are its own): the same numbers and labels as in order, whatever the
    // thread count. Only rows that can relate are computed (module `row_window`), and only
    // those with a finite `d² < g²` are kept: every use below asks that, so the rest read as
    // unrelated.
    let windows = RowWindows::new(problem, scans);
    let related: Vec<Related> = targets
        .par_iter()
        .map(|x| {
            let (mut near, mut rows) = (Vec::new(), Vec::new());
            let mut starts = Vec::with_capacity(scans.len() + 1);
            starts.push(0);
            for k in 0..scans.len() {
                for_each_near_residual2(problem, &windows, k, x, gate2, &mut near, |m, v| {
                    if v.is_finite() && v < gate2 {
                        rows.push((m, v));
                    }
                });
                starts.push(rows.len());
            }
            Related { rows, starts }
        })
        .collect();
    let mut labels = vec![-1i64; n];
    if !one_per_scan {
        // Each row to its nearest target, the first of equals (targets in order, a later
        // one taking the row only when strictly nearer).
        let mut best = vec![f64::INFINITY; n];
        for (t, target) in related.iter().enumerate() {
            for &(m, v) in &target.rows {
                if v < best[m] {
                    (best[m], labels[m]) = (v, t as i64);
                }
            }
        }
        return Ok(labels);
    }
    // Each row's column in its scan's problem: its position among the scan's rows.
    let mut column = vec![0usize; n];
    for k in 0..scans.len() {
        for (j, &m) in scans.scan(k).iter().enumerate() {
            column[m] = j;
        }
    }
    let assigned: Vec<Vec<(usize, i64)>> = (0..scans.len())
        .into_par_iter()
        .map(|k| assign_scan(scans.scan(k), k, &related, &column, gate2))
        .collect::<CoreResult<_>>()?;
    for (m, label) in assigned.into_iter().flatten() {
        labels[m] = label;
    }
    Ok(labels)
}

/// One target's rows with a finite `d² < g²`, as `(row, d²)`: those of scan `k` are
/// `rows[starts[k]..starts[k + 1]]`, in the scan's order.
struct Related {
    rows: Vec<(usize, f64)>,
    starts: Vec<usize>,
}

impl Related {
    fn in_scan(&self, k: usize) -> &[(usize, f64)] {
        &self.rows[self.starts[k]..self.starts[k + 1]]
    }
}

/// Gated minimum-cost assignment of scan `k`'s rows to targets (each at most once): the rows
/// assigned and their targets.
fn assign_scan(
    rows: &[usize],
    k: usize,
    related: &[Related],
    column: &[usize],
    gate2: f64,
) -> CoreResult<Vec<(usize, i64)>> {
    let involved: Vec<usize> = (0..related.len())
        .filter(|&t| !related[t].in_scan(k).is_empty())
        .collect();
    let mut labels = Vec::new();
    if involved.is_empty() {
        return Ok(labels);
    }
    // Rows of the problem = involved targets; columns = the scan's rows, then one "no
    // measurement" column per target at cost 0. Unrelated pairs cost 1 > 0, so the optimum
    // never uses them (a free no-measurement column is always cheaper).
    let (r, c) = (involved.len(), rows.len() + involved.len());
    let mut cost = vec![0.0; r * c];
    for (i, &t) in involved.iter().enumerate() {
        cost[i * c..i * c + rows.len()].fill(1.0);
        for &(m, v) in related[t].in_scan(k) {
            cost[i * c + column[m]] = v - gate2;
        }
    }
    // r <= c and every entry finite: the project's dense solver assigns every row.
    let solved = solve_dense(r, c, &cost)?;
    for (i, col) in solved.row_to_col.into_iter().enumerate() {
        match col {
            Some(col) if col < rows.len() && cost[i * c + col] < 0.0 => {
                labels.push((rows[col], involved[i] as i64));
            }
            _ => {}
        }
    }
    Ok(labels)
}

#[cfg(test)]
mod tests {
    use super::{for_each_near_residual2, predict, residual2, residual2_from};
    use crate::fti::problem::Problem;
    use crate::fti::row_window::RowWindows;
    use crate::fti::scans::Scans;
    use crate::fti::tests::sim;

    /// Calls `each(m, d²)` for every row `m` of one scan's `rows`, in order, with one prediction
    /// for the scan: the full scan that [`for_each_near_residual2`] stands in for.
    fn for_each_residual2(
        problem: &Problem<'_>,
        rows: &[usize],
        x: &[f64],
        mut each: impl FnMut(usize, f64),
    ) {
        let Some(&first) = rows.first() else {
            return;
        };
        let probe = problem.observation(first);
        let target = problem.layout.position(x, probe.time);
        let predicted = predict(problem.layout.space, &probe.sensor, &target);
        let space = problem.layout.space;
        for &m in rows {
            // In the plane the stored elevation (NaN) is not read.
            let angles = problem.measurements.angles(m);
            let sigma = problem.measurements.sigma(&problem.sensors, m);
            each(m, residual2_from(space, angles, sigma, predicted));
        }
    }

    /// The windowed query visits, in the same order and with the same numbers, every row the
    /// full scan relates at gates of 1, 3, 5 and 30 σ (30 σ: windows past π, every row): in
    /// 3-D and in the plane, with per-report azimuth noise from half to three times the
    /// sensor's (the window takes the scan's widest), at the true states, near them, far from
    /// any row and at a non-finite state (no row relates); and it leaves out rows.
    #[test]
    fn the_windowed_residuals_are_those_of_the_full_scan() {
        let (mut related, mut skipped) = (0, 0);
        for sc in [sim::paper(7, true, 30, 8), sim::planar(7, true, 30, 8)] {
            let sensors = sc.sensors();
            let n = sc.sensor.len();
            let noise: Vec<f64> = (0..n)
                .map(|m| {
                    sensors.sigma(sc.sensor[m] as usize)[0]
                        * (0.5 + 2.5 * ((m * 7919) % 101) as f64 / 100.0)
                })
                .collect();
            let overrides = crate::data::ReportOverrides {
                positions: None,
                sigma_azimuth: Some(&noise),
                sigma_elevation: None,
            };
            let table = sc
                .measurements(&sensors)
                .with_overrides(&sensors, overrides)
                .expect("valid");
            let problem: Problem<'_> = sim::problem(sensors, table);
            let scans = Scans::new(&table, sensors.len());
            let windows = RowWindows::new(&problem, &scans);
            let d = problem.layout.dim();
            let far: Vec<f64> = (0..d).map(|k| 1e5 * (k as f64 + 1.0)).collect();
            let near: Vec<Vec<f64>> = (sc.targets.iter())
                .map(|t| {
                    t[..d]
                        .iter()
                        .enumerate()
                        .map(|(k, v)| v + 150.0 * (k as f64 - 1.5))
                        .collect()
                })
                .collect();
            let states = sc
                .targets
                .iter()
                .map(|t| t[..d].to_vec())
                .chain(near)
                .chain([far, vec![f64::NAN; d]]);
            let mut scratch = Vec::new();
            for x in states {
                for gate in [1.0f64, 3.0, 5.0, 30.0] {
                    let gate2 = gate * gate;
                    for k in 0..scans.len() {
                        let mut full = Vec::new();
                        for_each_residual2(&problem, scans.scan(k), &x, |m, v| {
                            if v < gate2 {
                                full.push((m, v.to_bits()));
                            }
                        });
                        let (mut windowed, mut visited) = (Vec::new(), 0);
                        for_each_near_residual2(
                            &problem,
                            &windows,
                            k,
                            &x,
                            gate2,
                            &mut scratch,
                            |m, v| {
                                visited += 1;
                                if v < gate2 {
                                    windowed.push((m, v.to_bits()));
                                }
                            },
                        );
                        assert_eq!(windowed, full, "scan {k}, gate {gate}");
                        related += full.len();
                        skipped += scans.scan(k).len() - visited;
                    }
                }
            }
        }
        assert!(
            related > 100 && skipped > 10 * related,
            "{related} related, {skipped} skipped"
        );
    }

    /// The per-scan prediction gives every row the number `residual2` gives, bit for bit, in
    /// 3-D and in the plane (where the stored elevation is NaN and must not be read), for the
    /// true states and for states far from any row.
    #[test]
    fn per_scan_residuals_equal_residual2() {
        for sc in [sim::paper(5, true, 8, 8), sim::planar(5, true, 8, 8)] {
            let sensors = sc.sensors();
            let table = sc.measurements(&sensors);
            let problem = sim::problem(sensors, table);
            let scans = Scans::new(&table, sensors.len());
            let d = problem.layout.dim();
            let far: Vec<f64> = (0..d).map(|k| 1e5 * (k as f64 + 1.0)).collect();
            let mut visited = 0;
            for x in sc.targets.iter().map(|t| &t[..d]).chain([&far[..]]) {
                for k in 0..scans.len() {
                    for_each_residual2(&problem, scans.scan(k), x, |m, v| {
                        assert_eq!(v.to_bits(), residual2(&problem, x, m).to_bits(), "row {m}");
                        visited += 1;
                    });
                }
            }
            assert_eq!(visited, (sc.targets.len() + 1) * table.len());
        }
    }
}
