//! The search of eq. 19: maximise R from each candidate by steepest descent on −R.
//!
//! **Scaling.** The state mixes metres and m/s, and the geometry makes some directions (range
//! from a sensor, position against velocity) far less determined than others: in raw units
//! R's Hessian has a condition number of ~10⁶ and plain steepest descent zig-zags for
//! thousands of steps. Near a target, −R is a sum of Gaussian bumps of the angle residuals,
//! so its Hessian is shaped like the Fisher information of the related measurements, and the
//! candidate fit's covariance C (the inverse of the information of 4 of them) is a cheap,
//! already computed approximation of its inverse. Each descent therefore works in variables
//! `y` of `x = x_c + L·y`:
//!
//! * [`Scaling::Whitened`] (default): `L·Lᵀ = C` (Cholesky). In `y` the candidate's
//!   uncertainty is the unit ball, the Hessian's eigenvalues are all of order one, and a unit
//!   step is one standard deviation in every direction. Steepest descent in `y` is steepest
//!   descent in the metric of the candidate's information (`Δx ∝ C·∇R`).
//! * [`Scaling::Diagonal`]: `L = diag(√C_kk)`, the per-component standard deviations
//!   (METHODS §1 wording). It fixes the units but not the correlations (position–velocity,
//!   along-range x–y), which remain strong with 4 measurements.
//!
//! `python benches/bench_search.py` prints the evaluations per search of both scalings on
//! one paper run's candidates (whitened needs fewer; docs/performance.md has the figures).
//!
//! **Step length.** The first trial step is one scaled unit (one standard deviation); later
//! trials use the Barzilai-Borwein length `sᵀs / −sᵀΔg` (the secant estimate of the inverse
//! curvature along the last step), capped at `MAX_STEP` (10) scaled units. A trial is accepted
//! only under the Armijo condition `R(x + t·L·Lᵀ∇R) ≥ R(x) + c·t·|Lᵀ∇R|²`, halving `t` until
//! it holds, so R rises monotonically. Stop on a scaled step below `step_tol`, a rise of R
//! below `r_tol·R`, no acceptable step (a maximum to rounding), or `max_iter`. The step
//! tolerance must stay small (default 0.01): descents from mixed candidates cross plateaus
//! and ridges where the steps shrink to ~0.05 before R climbs again.
//!
//! **Merging** of the optima that are the same optimum: module `merge`.

use nalgebra::DMatrix;
use rayon::prelude::*;

use super::candidate::Candidate;
use super::closeness::{closeness_and_gradient, Precomputed};
use super::descent_options::{DescentOptions, Scaling};
use crate::error::{ensure_finite, CoreError, CoreResult};
use crate::geometry::model::MAX_DIM;
use crate::progress::Tally;

/// Armijo sufficient-increase constant.
const ARMIJO: f64 = 1e-4;
/// Step halvings before a descent is declared converged to rounding (2⁻⁶⁰ of a unit step).
const MAX_HALVINGS: usize = 60;
/// Largest trial step, in scaled units (standard deviations of the candidate fit).
const MAX_STEP: f64 = 10.0;

/// A local maximum of R reached from one candidate.
#[derive(Clone, Debug, PartialEq)]
pub struct Optimum {
    pub x: [f64; MAX_DIM],
    pub closeness: f64,
    pub iterations: usize,
    /// Evaluations of R and its gradient (iterations plus rejected trials).
    pub evaluations: usize,
    /// The scaling of its descent (the candidate's standard deviations).
    pub scale: [f64; MAX_DIM],
}

type Factor = [[f64; MAX_DIM]; MAX_DIM];

/// One descent per candidate, in parallel, in candidate order.
pub fn descend_all(
    pre: &Precomputed,
    candidates: &[&Candidate],
    options: &DescentOptions,
    tally: &Tally<'_>,
) -> Vec<Optimum> {
    candidates
        .par_iter()
        .map(|&c| {
            let factor = match options.scaling() {
                Scaling::Whitened => c.factor,
                Scaling::Diagonal => diagonal(&c.scale),
            };
            let mut opt = descend(pre, &c.estimate, &factor, options);
            opt.scale = c.scale;
            tally.advance(1);
            opt
        })
        .collect()
}

/// Descents from caller-given starts, each scaled by its own covariance (`P × D × D`,
/// row-major): the entry point for searching R directly; the pipeline uses `descend_all`.
pub fn descend_from(
    pre: &Precomputed,
    starts: &[f64],
    covariances: &[f64],
    options: &DescentOptions,
) -> CoreResult<Vec<Optimum>> {
    let d = pre.dim();
    if starts.len() % d != 0 {
        return Err(CoreError::shape(
            "starts",
            format!("expected shape (P, {d}), got {} values", starts.len()),
        ));
    }
    let p = starts.len() / d;
    if covariances.len() != p * d * d {
        return Err(CoreError::shape(
            "covariances",
            format!(
                "expected shape ({p}, {d}, {d}), got {} values",
                covariances.len()
            ),
        ));
    }
    ensure_finite("starts", starts)?;
    ensure_finite("covariances", covariances)?;
    let factors = (0..p)
        .map(|k| factor_of(&covariances[k * d * d..(k + 1) * d * d], d, k))
        .collect::<CoreResult<Vec<_>>>()?;
    Ok(factors
        .par_iter()
        .enumerate()
        .map(|(k, lower)| {
            let factor = match options.scaling() {
                Scaling::Whitened => *lower,
                Scaling::Diagonal => diagonal(&std::array::from_fn(|i| {
                    if i < d {
                        lower_row_norm(lower, i)
                    } else {
                        0.0
                    }
                })),
            };
            let mut start = [0.0; MAX_DIM];
            start[..d].copy_from_slice(&starts[k * d..(k + 1) * d]);
            descend(pre, &start, &factor, options)
        })
        .collect())
}

/// Cholesky factor L (lower, `L·Lᵀ = C`) of one covariance, or an error naming it.
fn factor_of(cov: &[f64], d: usize, k: usize) -> CoreResult<Factor> {
    let c = DMatrix::from_row_slice(d, d, cov);
    let l = c
        .cholesky()
        .ok_or_else(|| {
            CoreError::ill_posed(
                "covariances",
                format!("matrix {k} is not positive definite"),
            )
        })?
        .l();
    Ok(std::array::from_fn(|i| {
        std::array::from_fn(|j| if i < d && j < d { l[(i, j)] } else { 0.0 })
    }))
}

/// sqrt(C_ii) from the factor: the per-component standard deviation.
fn lower_row_norm(lower: &Factor, i: usize) -> f64 {
    lower[i].iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// The factor of a per-component scaling.
pub fn diagonal(scale: &[f64; MAX_DIM]) -> Factor {
    std::array::from_fn(|i| std::array::from_fn(|j| if i == j { scale[i] } else { 0.0 }))
}

/// Maximises R from `start` in the variables `y` of `x = start + L·y` (`factor` = L, lower
/// triangular; see the module doc). The returned `scale` is L's diagonal; `descend_all`
/// replaces it by the candidate's standard deviations.
pub fn descend(
    pre: &Precomputed,
    start: &[f64; MAX_DIM],
    factor: &Factor,
    options: &DescentOptions,
) -> Optimum {
    let d = pre.dim();
    let mut x = *start;
    if crate::parallel::interrupted() {
        // Not even the first evaluation: an interrupted pipeline discards every optimum.
        return Optimum {
            x,
            closeness: f64::NAN,
            iterations: 0,
            evaluations: 0,
            scale: std::array::from_fn(|k| factor[k][k]),
        };
    }
    let (mut r, g) = closeness_and_gradient(pre, &x);
    let mut gy = scaled(&g, factor, d);
    let mut next_step: Option<f64> = None;
    let (mut iterations, mut evaluations) = (0, 1);
    while iterations < options.max_iter() && r.is_finite() && !crate::parallel::interrupted() {
        let g2: f64 = gy.iter().map(|v| v * v).sum();
        if !(g2 > 0.0 && g2.is_finite()) {
            break; // stationary (or every row in the skipped tail)
        }
        let norm = g2.sqrt();
        // t multiplies the scaled gradient: the scaled step length is t·norm.
        let mut t = next_step.unwrap_or(1.0).min(MAX_STEP) / norm;
        let mut accepted = None;
        for _ in 0..MAX_HALVINGS {
            let trial: [f64; MAX_DIM] = std::array::from_fn(|k| {
                x[k] + t * (0..=k).map(|c| factor[k][c] * gy[c]).sum::<f64>()
            });
            let (rt, gt) = closeness_and_gradient(pre, &trial);
            evaluations += 1;
            if rt >= r + ARMIJO * t * g2 {
                accepted = Some((trial, rt, scaled(&gt, factor, d)));
                break;
            }
            t *= 0.5;
        }
        let Some((trial, rt, gy_new)) = accepted else {
            break;
        };
        iterations += 1;
        let step = t * norm;
        let gain = rt - r;
        next_step = barzilai_borwein(t, &gy, &gy_new).or(Some(2.0 * step));
        x = trial;
        r = rt;
        gy = gy_new;
        if step < options.step_tol() || gain <= options.r_tol() * r.abs() {
            break;
        }
    }
    let scale = std::array::from_fn(|k| factor[k][k]);
    Optimum {
        x,
        closeness: r,
        iterations,
        evaluations,
        scale,
    }
}

/// Gradient in `y`: `Lᵀ∇R` (zero past `d`).
fn scaled(g: &[f64; MAX_DIM], factor: &Factor, d: usize) -> [f64; MAX_DIM] {
    std::array::from_fn(|k| {
        if k < d {
            (k..d).map(|r| factor[r][k] * g[r]).sum()
        } else {
            0.0
        }
    })
}

/// BB1 step length in scaled units for the next iteration, from the step `s = t·gy` just
/// taken and the change of the scaled gradient; `None` where R is not concave along `s`.
fn barzilai_borwein(t: f64, gy: &[f64; MAX_DIM], gy_new: &[f64; MAX_DIM]) -> Option<f64> {
    let ss: f64 = gy.iter().map(|v| (t * v) * (t * v)).sum();
    // For f = −R the gradient change is −(gy_new − gy).
    let sq: f64 = gy.iter().zip(gy_new).map(|(a, b)| t * a * (a - b)).sum();
    let new_norm = gy_new.iter().map(|v| v * v).sum::<f64>().sqrt();
    (sq > 0.0 && ss.is_finite())
        .then(|| ss / sq * new_norm)
        .filter(|s| s.is_finite() && *s > 0.0)
}
