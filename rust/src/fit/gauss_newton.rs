//! Gauss-Newton with a step-halving safeguard for one problem. Hand-rolled with fixed-size
//! nalgebra matrices: the problems are tiny (≤ 6 unknowns, a handful of rows), so a general
//! least-squares crate's per-call allocation and setup would cost more than the arithmetic.

use nalgebra::{SMatrix, SVector};

use super::{FitOptions, FitOutcome, Termination};
use crate::model::{residual_rows, Observation, StateLayout, MAX_DIM};

/// Normal equations `H = Σ gᵀg`, `b = Σ gᵀr` and `χ² = Σ r²` over the residual rows at `x`.
struct Normal<const D: usize> {
    information: SMatrix<f64, D, D>,
    gradient: SVector<f64, D>,
    chi2: f64,
}

fn accumulate<const D: usize>(layout: &StateLayout, x: &SVector<f64, D>, obs: &[Observation]) -> Option<Normal<D>> {
    let mut normal = Normal {
        information: SMatrix::zeros(),
        gradient: SVector::zeros(),
        chi2: 0.0,
    };
    for o in obs {
        let rows = residual_rows(layout, x.as_slice(), o)?;
        for c in 0..rows.count {
            let g = SVector::<f64, D>::from_fn(|k, _| rows.gradient[c][k]);
            normal.information += g * g.transpose();
            normal.gradient += g * rows.residual[c];
            normal.chi2 += rows.residual[c] * rows.residual[c];
        }
    }
    normal.chi2.is_finite().then_some(normal)
}

/// χ² alone (for the line search), or `None` where the model is undefined.
pub fn chi2(layout: &StateLayout, x: &[f64], obs: &[Observation]) -> Option<f64> {
    let mut total = 0.0;
    for o in obs {
        let rows = residual_rows(layout, x, o)?;
        total += rows.residual[..rows.count].iter().map(|r| r * r).sum::<f64>();
    }
    total.is_finite().then_some(total)
}

/// Fits `layout`'s state to `obs` from `initial` (length ≥ `layout.dim()`).
pub fn fit(layout: &StateLayout, obs: &[Observation], initial: &[f64], options: &FitOptions) -> FitOutcome {
    match layout.dim() {
        2 => fit_fixed::<2>(layout, obs, initial, options),
        3 => fit_fixed::<3>(layout, obs, initial, options),
        4 => fit_fixed::<4>(layout, obs, initial, options),
        _ => fit_fixed::<MAX_DIM>(layout, obs, initial, options),
    }
}

fn fit_fixed<const D: usize>(layout: &StateLayout, obs: &[Observation], initial: &[f64], options: &FitOptions) -> FitOutcome {
    let mut x = SVector::<f64, D>::from_fn(|k, _| initial[k]);
    let mut iterations = 0;
    let termination = loop {
        let Some(normal) = accumulate(layout, &x, obs) else {
            break Termination::NonFinite;
        };
        if iterations == options.max_iter() {
            break Termination::MaxIterations;
        }
        let Some(cholesky) = normal.information.cholesky() else {
            break Termination::Singular;
        };
        iterations += 1;
        let step = cholesky.solve(&normal.gradient);
        match line_search(layout, obs, &x, &step, normal.chi2, options) {
            Some(next) => {
                let small = (next - x).norm() <= options.xtol() * (x.norm() + options.xtol());
                x = next;
                if small {
                    break Termination::Converged;
                }
            }
            None if step.norm() <= options.xtol() * (x.norm() + options.xtol()) => break Termination::Converged,
            None => break Termination::Stalled,
        }
    };
    finish(layout, obs, x, iterations, termination)
}

/// The full step, halved until χ² does not rise; `None` if no tried length lowers it.
fn line_search<const D: usize>(
    layout: &StateLayout,
    obs: &[Observation],
    x: &SVector<f64, D>,
    step: &SVector<f64, D>,
    chi2_now: f64,
    options: &FitOptions,
) -> Option<SVector<f64, D>> {
    let mut length = 1.0;
    for _ in 0..=options.max_halvings() {
        let candidate = x + step * length;
        if let Some(c) = chi2(layout, candidate.as_slice(), obs) {
            if c <= chi2_now {
                return Some(candidate);
            }
        }
        length *= 0.5;
    }
    None
}

/// Covariance and χ² at the final estimate.
fn finish<const D: usize>(
    layout: &StateLayout,
    obs: &[Observation],
    x: SVector<f64, D>,
    iterations: usize,
    termination: Termination,
) -> FitOutcome {
    let nan = |n| vec![f64::NAN; n];
    let inverse = accumulate(layout, &x, obs).and_then(|n| Some((n.information.cholesky()?.inverse(), n.chi2)));
    match (termination, inverse) {
        (Termination::Singular | Termination::NonFinite, _) | (_, None) => FitOutcome {
            estimate: nan(D),
            covariance: nan(D * D),
            chi2: f64::NAN,
            iterations,
            termination: if termination == Termination::NonFinite { termination } else { Termination::Singular },
        },
        (_, Some((covariance, chi2))) => FitOutcome {
            estimate: x.as_slice().to_vec(),
            // Symmetric, so column-major storage reads as row-major too.
            covariance: covariance.as_slice().to_vec(),
            chi2,
            iterations,
            termination,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{predict, Motion, Space};

    fn paper_observations(layout: &StateLayout, truth: &[f64], noise: f64) -> Vec<Observation> {
        let sensors = [[0.0, 0.0, 0.0], [20_000.0, 0.0, 0.0]];
        let mut k = 0u64;
        let mut jitter = || {
            // Deterministic pseudo-noise, enough to make the fit non-trivial.
            k = k.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            noise * (((k >> 11) as f64 / (1u64 << 53) as f64) - 0.5)
        };
        let mut out = Vec::new();
        for scan in 0..8 {
            for (j, s) in sensors.iter().enumerate() {
                let time = 15.0 * scan as f64 + 5.0 * j as f64;
                let p = layout.position(truth, time);
                let [a, e] = predict(layout.space, s, &p);
                out.push(Observation { sensor: *s, time, angles: [a + jitter(), e + jitter()], sigma: [5e-3, 5e-3] });
            }
        }
        out
    }

    #[test]
    fn noiseless_cv_fit_recovers_truth_from_a_poor_start() {
        let layout = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
        let truth = [1340.0, 15000.0, 1000.0, 173.2, -100.0, 0.0];
        let obs = paper_observations(&layout, &truth, 0.0);
        let start = [1800.0, 13000.0, 1500.0, 150.0, -70.0, 10.0];
        let out = fit(&layout, &obs, &start, &FitOptions::default());
        assert_eq!(out.termination, Termination::Converged);
        for k in 0..6 {
            assert!((out.estimate[k] - truth[k]).abs() <= 1e-8 * truth[k].abs().max(1.0), "{k}");
        }
        assert!(out.chi2 < 1e-12);
    }

    #[test]
    fn single_sensor_static_fit_is_singular_not_a_panic() {
        let layout = StateLayout::new(Space::Spatial, Motion::Static);
        let obs = vec![Observation { sensor: [0.0; 3], time: 0.0, angles: [0.3, 0.1], sigma: [1e-3, 1e-3] }; 3];
        let out = fit(&layout, &obs, &[1000.0, 300.0, 100.0], &FitOptions::default());
        assert_eq!(out.termination, Termination::Singular);
        assert!(out.estimate.iter().all(|v| v.is_nan()));
    }

    #[test]
    fn noisy_fit_lowers_chi2_below_the_truth() {
        let layout = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
        let truth = [6000.0, 1000.0, 1000.0, 0.0, 200.0, 0.0];
        let obs = paper_observations(&layout, &truth, 0.01);
        let out = fit(&layout, &obs, &truth, &FitOptions::default());
        assert_eq!(out.termination, Termination::Converged);
        assert!(out.chi2 <= chi2(&layout, &truth, &obs).expect("defined"));
    }
}
