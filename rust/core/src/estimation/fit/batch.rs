//! Many independent fits in one call. Problems are given CSR-style: problem `p` uses the
//! measurement rows `indices[offsets[p]..offsets[p+1]]` of one shared table. Each problem is
//! solved by the same sequential code whatever thread runs it, and results are collected in
//! problem order, so the output is bit-identical for any thread count.

use rayon::prelude::*;

use super::gauss_newton::{fit_into, FitSlots, FitSummary};
use super::{FitOptions, Termination};
use crate::data::{check_offsets, Measurements, Sensors};
use crate::error::{ensure_finite, CoreError, CoreResult};
use crate::geometry::los::pseudo_linear_state;
use crate::geometry::model::{Observation, StateLayout};
use crate::parallel::interrupted;

/// Problems as CSR row groups plus optional initial states (row-major `P × dim`).
#[derive(Clone, Copy, Debug)]
pub struct Problems<'a> {
    pub indices: &'a [i64],
    pub offsets: &'a [i64],
    pub initial: Option<&'a [f64]>,
}

/// Columnar results: `estimates` is `P × dim`, `covariances` is `P × dim × dim`.
#[derive(Clone, Debug, PartialEq)]
pub struct BatchOutcome {
    pub dim: usize,
    pub estimates: Vec<f64>,
    pub covariances: Vec<f64>,
    pub chi2: Vec<f64>,
    pub iterations: Vec<u32>,
    pub termination: Vec<u8>,
}

impl Problems<'_> {
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Rows of problem `p` (valid after [`Problems::validate`]).
    fn rows(&self, p: usize) -> &[i64] {
        &self.indices[self.offsets[p] as usize..self.offsets[p + 1] as usize]
    }

    /// Checks the CSR structure, the row indices, that every problem has at least as many
    /// scalar measurements as unknowns, and the initial states' shape and finiteness.
    pub fn validate(&self, n_rows: usize, angles_per_row: usize, dim: usize) -> CoreResult<()> {
        let indices = self.indices;
        check_offsets(self.offsets, indices.len(), "problem")?;
        if let Some(k) = indices.iter().position(|&m| m < 0 || m as usize >= n_rows) {
            return Err(CoreError::out_of_range(
                "indices",
                format!(
                    "entry {k} is {} but the table has {n_rows} measurements",
                    indices[k]
                ),
            ));
        }
        for p in 0..self.len() {
            // More indices than rows means a repeated measurement; it would also size the
            // problem's buffers by the caller's count instead of by the table (10⁸ indices
            // of a small table once asked for gigabytes).
            if self.rows(p).len() > n_rows {
                return Err(CoreError::out_of_range(
                    "indices",
                    format!(
                        "problem {p} has {} indices but the table has {n_rows} measurements; each may enter a fit once",
                        self.rows(p).len()
                    ),
                ));
            }
            let scalars = self.rows(p).len() * angles_per_row;
            if scalars < dim {
                return Err(CoreError::ill_posed(
                    "indices",
                    format!("problem {p} has {scalars} scalar measurements for {dim} unknowns"),
                ));
            }
        }
        if let Some(initial) = self.initial {
            if initial.len() != self.len() * dim {
                return Err(CoreError::shape(
                    "initial",
                    format!(
                        "expected shape ({}, {dim}), got {} values",
                        self.len(),
                        initial.len()
                    ),
                ));
            }
            ensure_finite("initial", initial)?;
        }
        Ok(())
    }
}

/// Fewer problems than this are fitted on the calling thread: a fit takes microseconds, less
/// than handing the batch to a thread pool and waking it (`benches/bench_call_overhead.py`).
pub const PARALLEL_PROBLEMS: usize = 8;

/// Whether a batch of `problems` fits runs on the calling thread alone (so a caller can skip
/// the thread pool).
pub fn fits_sequentially(problems: usize) -> bool {
    problems < PARALLEL_PROBLEMS
}

/// Fits every problem; fails only on invalid input (a degenerate problem gets a
/// [`Termination`] code instead, so one bad problem does not sink a batch).
pub fn fit_batch(
    measurements: &Measurements<'_>,
    sensors: &Sensors<'_>,
    layout: &StateLayout,
    problems: &Problems<'_>,
    options: &FitOptions,
) -> CoreResult<BatchOutcome> {
    let dim = layout.dim();
    problems.validate(measurements.len(), layout.space.angles(), dim)?;
    let n = problems.len();
    let mut estimates = vec![0.0; n * dim];
    let mut covariances = vec![0.0; n * dim * dim];
    // Each problem writes only its own output chunks, so no result depends on scheduling.
    let fit_one =
        |obs: &mut Vec<Observation>,
         (p, (estimate, covariance)): (usize, (&mut [f64], &mut [f64]))| {
            if interrupted() {
                // Ctrl-C: skip the rest; the batch returns Interrupted below.
                return singular(FitSlots {
                    estimate,
                    covariance,
                });
            }
            obs.clear();
            obs.extend(
                problems
                    .rows(p)
                    .iter()
                    .map(|&m| measurements.observation(sensors, m as usize)),
            );
            let slots = FitSlots {
                estimate,
                covariance,
            };
            match problems.initial {
                Some(initial) => fit_into(
                    layout,
                    obs,
                    &initial[p * dim..(p + 1) * dim],
                    options,
                    slots,
                ),
                None => match pseudo_linear_state(layout, obs) {
                    Some(start) => fit_into(layout, obs, &start[..dim], options, slots),
                    None => singular(slots),
                },
            }
        };
    let summaries: Vec<FitSummary> = if fits_sequentially(n) {
        let mut obs = Vec::new();
        (estimates.chunks_mut(dim))
            .zip(covariances.chunks_mut(dim * dim))
            .enumerate()
            .map(|item| fit_one(&mut obs, item))
            .collect()
    } else {
        (estimates.par_chunks_mut(dim))
            .zip(covariances.par_chunks_mut(dim * dim))
            .enumerate()
            .map_init(Vec::new, fit_one)
            .collect()
    };
    if interrupted() {
        return Err(CoreError::Interrupted);
    }
    Ok(BatchOutcome {
        dim,
        estimates,
        covariances,
        chi2: summaries.iter().map(|s| s.chi2).collect(),
        iterations: summaries.iter().map(|s| s.iterations as u32).collect(),
        termination: summaries.iter().map(|s| s.termination as u8).collect(),
    })
}

fn singular(slots: FitSlots<'_>) -> FitSummary {
    slots.estimate.fill(f64::NAN);
    slots.covariance.fill(f64::NAN);
    FitSummary {
        chi2: f64::NAN,
        iterations: 0,
        termination: Termination::Singular,
    }
}
