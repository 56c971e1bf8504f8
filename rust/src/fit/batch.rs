//! Many independent fits in one call. Problems are given CSR-style: problem `p` uses the
//! measurement rows `indices[offsets[p]..offsets[p+1]]` of one shared table. Each problem is
//! solved by the same sequential code whatever thread runs it, and results are collected in
//! problem order, so the output is bit-identical for any thread count.

use rayon::prelude::*;

use super::gauss_newton::fit;
use super::{FitOptions, FitOutcome, Termination};
use crate::data::{Measurements, Sensors};
use crate::error::{ensure_finite, CoreError, CoreResult};
use crate::los::pseudo_linear_state;
use crate::model::{Observation, StateLayout};

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
        let (offsets, indices) = (self.offsets, self.indices);
        if offsets.first() != Some(&0) {
            return Err(CoreError::shape("offsets", "must start with 0 and have one entry per problem plus one"));
        }
        if let Some(p) = offsets.windows(2).position(|w| w[1] < w[0]) {
            return Err(CoreError::out_of_range("offsets", format!("decreases between entries {p} and {}", p + 1)));
        }
        if offsets.last().copied() != Some(indices.len() as i64) {
            return Err(CoreError::shape("offsets", format!("last entry must equal len(indices) = {}", indices.len())));
        }
        if let Some(k) = indices.iter().position(|&m| m < 0 || m as usize >= n_rows) {
            return Err(CoreError::out_of_range(
                "indices",
                format!("entry {k} is {} but the table has {n_rows} measurements", indices[k]),
            ));
        }
        for p in 0..self.len() {
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
                    format!("expected shape ({}, {dim}), got {} values", self.len(), initial.len()),
                ));
            }
            ensure_finite("initial", initial)?;
        }
        Ok(())
    }
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
    let outcomes: Vec<FitOutcome> = (0..problems.len())
        .into_par_iter()
        .map(|p| {
            let obs: Vec<Observation> = problems
                .rows(p)
                .iter()
                .map(|&m| measurements.observation(sensors, m as usize))
                .collect();
            let start = match problems.initial {
                Some(initial) => Some(initial[p * dim..(p + 1) * dim].to_vec()),
                None => pseudo_linear_state(layout, &obs).map(|s| s[..dim].to_vec()),
            };
            match start {
                Some(start) => fit(layout, &obs, &start, options),
                None => singular(dim),
            }
        })
        .collect();
    Ok(columnar(dim, outcomes))
}

fn singular(dim: usize) -> FitOutcome {
    FitOutcome {
        estimate: vec![f64::NAN; dim],
        covariance: vec![f64::NAN; dim * dim],
        chi2: f64::NAN,
        iterations: 0,
        termination: Termination::Singular,
    }
}

fn columnar(dim: usize, outcomes: Vec<FitOutcome>) -> BatchOutcome {
    let n = outcomes.len();
    let mut out = BatchOutcome {
        dim,
        estimates: Vec::with_capacity(n * dim),
        covariances: Vec::with_capacity(n * dim * dim),
        chi2: Vec::with_capacity(n),
        iterations: Vec::with_capacity(n),
        termination: Vec::with_capacity(n),
    };
    for o in outcomes {
        out.estimates.extend_from_slice(&o.estimate);
        out.covariances.extend_from_slice(&o.covariance);
        out.chi2.push(o.chi2);
        out.iterations.push(o.iterations as u32);
        out.termination.push(o.termination as u8);
    }
    out
}
