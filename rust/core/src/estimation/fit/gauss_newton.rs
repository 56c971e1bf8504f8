//! Gauss-Newton with a step-halving safeguard for one problem. Hand-rolled with fixed-size
//! nalgebra matrices: the problems are tiny (≤ 6 unknowns, a handful of rows), so a general
//! least-squares crate's per-call allocation and setup would cost more than the arithmetic.

use nalgebra::{SMatrix, SVector};

use super::{FitOptions, FitOutcome, Termination};
use crate::geometry::model::{
    position_rows_at, residual_rows, Motion, Observation, Space, StateLayout, MAX_DIM,
};

/// Normal equations `H = Σ gᵀg`, `b = Σ gᵀr` and `χ² = Σ r²` over the residual rows at one
/// state. Plain arrays with compile-time bounds: the per-row update compiles to straight-line
/// multiply-adds with no index checks.
#[derive(Clone, Copy)]
struct Normal<const D: usize> {
    information: [[f64; D]; D],
    gradient: [f64; D],
    chi2: f64,
}

impl<const D: usize> Normal<D> {
    const ZERO: Self = Self {
        information: [[0.0; D]; D],
        gradient: [0.0; D],
        chi2: 0.0,
    };

    fn information_matrix(&self) -> SMatrix<f64, D, D> {
        SMatrix::from_fn(|i, j| self.information[i][j])
    }
}

/// Fills `out` with the normal equations at `x`; false where the model is undefined.
fn accumulate<const D: usize>(
    layout: &StateLayout,
    x: &SVector<f64, D>,
    obs: &[Observation],
    out: &mut Normal<D>,
) -> bool {
    #[cfg(test)]
    tests::EVALUATIONS.with(|n| n.set(n.get() + 1));
    if let Motion::ConstantVelocity { t0 } = layout.motion {
        return accumulate_cv(layout, t0, x, obs, out);
    }
    accumulate_rows(layout, x, obs, out)
}

/// [`accumulate`] row by row through the state gradients, for any motion.
fn accumulate_rows<const D: usize>(
    layout: &StateLayout,
    x: &SVector<f64, D>,
    obs: &[Observation],
    out: &mut Normal<D>,
) -> bool {
    // Local accumulators and a full (fixed-length, so vectorisable) outer product: cheaper
    // than a triangular update through memory, and H stays symmetric.
    let mut information = [[0.0; D]; D];
    let mut gradient = [0.0; D];
    let mut chi2 = 0.0;
    for o in obs {
        let Some(rows) = residual_rows(layout, x.as_slice(), o) else {
            return false;
        };
        for c in 0..rows.count {
            let (g, r) = (&rows.gradient[c], rows.residual[c]);
            for (a, row) in information.iter_mut().enumerate() {
                for (b, h) in row.iter_mut().enumerate() {
                    *h += g[a] * g[b];
                }
                gradient[a] += g[a] * r;
            }
            chi2 += r * r;
        }
    }
    *out = Normal {
        information,
        gradient,
        chi2,
    };
    chi2.is_finite()
}

/// The constant-velocity normal equations by blocks. A row's state gradient is
/// `g = [gₚ, Δt·gₚ]` (gₚ w.r.t. the position at the measurement time), so
/// `H = Σ [[P, Δt P], [Δt P, Δt² P]]` with `P = Σ_rows gₚ gₚᵀ` per measurement: three p×p
/// sums instead of a (2p)×(2p) outer product per row, and no chain rule per row. The space is
/// fixed at compile time (`SPATIAL`), and the symmetric blocks are summed on and above the
/// diagonal only, then mirrored (`a·b = b·a` exactly, so the sums are those of the full loop).
fn accumulate_cv<const D: usize>(
    layout: &StateLayout,
    t0: f64,
    x: &SVector<f64, D>,
    obs: &[Observation],
    out: &mut Normal<D>,
) -> bool {
    match layout.space {
        Space::Spatial => accumulate_cv_in::<D, true>(t0, x, obs, out),
        Space::Planar => accumulate_cv_in::<D, false>(t0, x, obs, out),
    }
}

#[inline(always)]
fn accumulate_cv_in<const D: usize, const SPATIAL: bool>(
    t0: f64,
    x: &SVector<f64, D>,
    obs: &[Observation],
    out: &mut Normal<D>,
) -> bool {
    let p = D / 2;
    let mut blocks = [[[0.0; 3]; 3]; 3]; // Σ P, Σ Δt P, Σ Δt² P
    let mut sums = [[0.0; 3]; 2]; // Σ q, Σ Δt q with q = Σ_rows gₚ r
    let mut chi2 = 0.0;
    for o in obs {
        let dt = o.time - t0;
        let mut target = [0.0; 3];
        for (k, value) in target.iter_mut().enumerate().take(p) {
            *value = x[k] + dt * x[p + k];
        }
        let Some(rows) = position_rows_at::<SPATIAL>(&target, o) else {
            return false;
        };
        let (mut pm, mut qm) = ([[0.0; 3]; 3], [0.0; 3]);
        for c in 0..rows.count {
            let (g, r) = (&rows.gradient[c], rows.residual[c]);
            for a in 0..3 {
                for b in a..3 {
                    pm[a][b] += g[a] * g[b];
                }
                qm[a] += g[a] * r;
            }
            chi2 += r * r;
        }
        for a in 0..3 {
            for b in a..3 {
                blocks[0][a][b] += pm[a][b];
                blocks[1][a][b] += dt * pm[a][b];
                blocks[2][a][b] += dt * dt * pm[a][b];
            }
            sums[0][a] += qm[a];
            sums[1][a] += dt * qm[a];
        }
    }
    let mut information = [[0.0; D]; D];
    let mut gradient = [0.0; D];
    for a in 0..p {
        for b in 0..p {
            let (i, j) = (a.min(b), a.max(b));
            information[a][b] = blocks[0][i][j];
            information[a][p + b] = blocks[1][i][j];
            information[p + a][b] = blocks[1][i][j];
            information[p + a][p + b] = blocks[2][i][j];
        }
        gradient[a] = sums[0][a];
        gradient[p + a] = sums[1][a];
    }
    *out = Normal {
        information,
        gradient,
        chi2,
    };
    chi2.is_finite()
}

/// χ² alone, or `None` where the model is undefined.
pub fn chi2(layout: &StateLayout, x: &[f64], obs: &[Observation]) -> Option<f64> {
    let mut total = 0.0;
    for o in obs {
        let rows = residual_rows(layout, x, o)?;
        total += rows.residual[..rows.count]
            .iter()
            .map(|r| r * r)
            .sum::<f64>();
    }
    total.is_finite().then_some(total)
}

/// Where one fit writes its result: `estimate` (dim) and row-major `covariance` (dim²).
pub struct FitSlots<'a> {
    pub estimate: &'a mut [f64],
    pub covariance: &'a mut [f64],
}

/// What a fit reports besides the slots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitSummary {
    pub chi2: f64,
    pub iterations: usize,
    pub termination: Termination,
}

/// Fits `layout`'s state to `obs` from `initial` (length ≥ `layout.dim()`).
pub fn fit(
    layout: &StateLayout,
    obs: &[Observation],
    initial: &[f64],
    options: &FitOptions,
) -> FitOutcome {
    let dim = layout.dim();
    let (mut estimate, mut covariance) = (vec![0.0; dim], vec![0.0; dim * dim]);
    let summary = fit_into(
        layout,
        obs,
        initial,
        options,
        FitSlots {
            estimate: &mut estimate,
            covariance: &mut covariance,
        },
    );
    FitOutcome {
        estimate,
        covariance,
        chi2: summary.chi2,
        iterations: summary.iterations,
        termination: summary.termination,
    }
}

/// [`fit`] writing into caller-provided slots (no allocation: the batch driver's hot path).
pub fn fit_into(
    layout: &StateLayout,
    obs: &[Observation],
    initial: &[f64],
    options: &FitOptions,
    slots: FitSlots<'_>,
) -> FitSummary {
    match layout.dim() {
        2 => fit_fixed::<2>(layout, obs, initial, options, slots),
        3 => fit_fixed::<3>(layout, obs, initial, options, slots),
        4 => fit_fixed::<4>(layout, obs, initial, options, slots),
        _ => fit_fixed::<MAX_DIM>(layout, obs, initial, options, slots),
    }
}

fn fit_fixed<const D: usize>(
    layout: &StateLayout,
    obs: &[Observation],
    initial: &[f64],
    options: &FitOptions,
    slots: FitSlots<'_>,
) -> FitSummary {
    let mut x = SVector::<f64, D>::from_fn(|k, _| initial[k]);
    // Two buffers whose roles (current, trial) swap by index: an accepted trial's normal
    // equations are the next iteration's, computed once and never copied.
    let mut normals = [Normal::<D>::ZERO; 2];
    let mut current = 0;
    if !accumulate(layout, &x, obs, &mut normals[current]) {
        return write_failure(slots, 0, Termination::NonFinite);
    }
    let mut iterations = 0;
    let termination = loop {
        if iterations == options.max_iter() {
            break Termination::MaxIterations;
        }
        let normal = normals[current];
        let Some(cholesky) = normal.information_matrix().cholesky() else {
            return write_failure(slots, iterations, Termination::Singular);
        };
        iterations += 1;
        let gradient = SVector::<f64, D>::from_column_slice(&normal.gradient);
        let step = cholesky.solve(&gradient);
        // Converged when the step is negligible relative to the state, or statistically: its
        // Mahalanobis length sqrt(δᵀHδ) = sqrt(δᵀb) is below `step_sigmas` standard deviations.
        // The second test ends the zig-zag along the flat valleys of barely-determined
        // problems (4 measurements, 6 unknowns), where χ² has stopped changing.
        let tiny = step.norm() <= options.xtol() * (x.norm() + options.xtol())
            || step.dot(&gradient) <= options.step_sigmas().powi(2);
        if tiny {
            // Take the negligible last step without re-evaluating: χ² and the covariance
            // stay those of the previous iterate, which differ from the new one's by less
            // than the step itself (< step_sigmas σ). Saves one of ~6 evaluations per fit.
            x += step;
            break Termination::Converged;
        }
        let trial = 1 - current;
        let accepted = line_search(
            layout,
            obs,
            &x,
            &step,
            normal.chi2,
            options,
            &mut normals[trial],
        );
        match accepted {
            // The accepted state is the current one to the bit (a step below χ²'s rounding,
            // halved until it vanishes): every later iteration would repeat this one, so
            // the loop would end at `max_iter` with this state and these normal equations.
            // End it there now (a large-residual fit can spend most of its evaluations so).
            Some(next) if same_bits(&next, &x) => {
                iterations = options.max_iter();
                break Termination::MaxIterations;
            }
            Some(next) => {
                x = next;
                current = trial;
            }
            None => break Termination::Stalled,
        }
    };
    let normal = &normals[current];
    match normal.information_matrix().cholesky() {
        Some(cholesky) => {
            slots.estimate.copy_from_slice(x.as_slice());
            // Symmetric, so column-major storage reads as row-major too.
            slots
                .covariance
                .copy_from_slice(cholesky.inverse().as_slice());
            FitSummary {
                chi2: normal.chi2,
                iterations,
                termination,
            }
        }
        None => write_failure(slots, iterations, Termination::Singular),
    }
}

/// Whether two states are equal to the bit (`==` would equate −0 with +0).
fn same_bits<const D: usize>(a: &SVector<f64, D>, b: &SVector<f64, D>) -> bool {
    a.iter()
        .zip(b.iter())
        .all(|(u, v)| u.to_bits() == v.to_bits())
}

fn write_failure(slots: FitSlots<'_>, iterations: usize, termination: Termination) -> FitSummary {
    slots.estimate.fill(f64::NAN);
    slots.covariance.fill(f64::NAN);
    FitSummary {
        chi2: f64::NAN,
        iterations,
        termination,
    }
}

/// The full step, halved until χ² does not rise; returns the accepted state, its normal
/// equations left in `trial`, or `None` if no tried length lowers χ².
fn line_search<const D: usize>(
    layout: &StateLayout,
    obs: &[Observation],
    x: &SVector<f64, D>,
    step: &SVector<f64, D>,
    chi2_now: f64,
    options: &FitOptions,
    trial: &mut Normal<D>,
) -> Option<SVector<f64, D>> {
    let mut length = 1.0;
    for _ in 0..=options.max_halvings() {
        let candidate = x + step * length;
        if accumulate(layout, &candidate, obs, trial) && trial.chi2 <= chi2_now {
            return Some(candidate);
        }
        length *= 0.5;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::model::{predict, Motion, Space};

    fn paper_observations(layout: &StateLayout, truth: &[f64], noise: f64) -> Vec<Observation> {
        let sensors = [[0.0, 0.0, 0.0], [20_000.0, 0.0, 0.0]];
        let mut k = 0u64;
        let mut jitter = || {
            // Deterministic pseudo-noise, enough to make the fit non-trivial.
            k = k
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            noise * (((k >> 11) as f64 / (1u64 << 53) as f64) - 0.5)
        };
        let mut out = Vec::new();
        for scan in 0..8 {
            for (j, s) in sensors.iter().enumerate() {
                let time = 15.0 * scan as f64 + 5.0 * j as f64;
                let p = layout.position(truth, time);
                let [a, e] = predict(layout.space, s, &p);
                out.push(Observation::new(
                    *s,
                    time,
                    [a + jitter(), e + jitter()],
                    [5e-3, 5e-3],
                ));
            }
        }
        out
    }

    /// The constant-velocity blocks (summed on and above the diagonal, then mirrored) are the
    /// row-by-row normal equations, in 3-D and in the plane.
    #[test]
    fn the_cv_blocks_are_the_row_by_row_normal_equations() {
        fn compare<const D: usize>(layout: &StateLayout, x: [f64; D], obs: &[Observation]) {
            let x = SVector::<f64, D>::from_column_slice(&x);
            let (mut blocks, mut rows) = (Normal::<D>::ZERO, Normal::<D>::ZERO);
            assert!(accumulate(layout, &x, obs, &mut blocks));
            assert!(accumulate_rows(layout, &x, obs, &mut rows));
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1e-300);
            assert!(close(blocks.chi2, rows.chi2) && blocks.chi2 > 0.0);
            for a in 0..D {
                assert!(close(blocks.gradient[a], rows.gradient[a]), "b[{a}]");
                for b in 0..D {
                    let (h, r) = (blocks.information[a][b], rows.information[a][b]);
                    assert!(close(h, r), "H[{a}][{b}]: {h} vs {r}");
                    assert_eq!(h, blocks.information[b][a], "H symmetric");
                }
            }
        }
        let truth = [1_000.0, 20_000.0, 3_000.0, 120.0, -80.0, 15.0];
        let spatial = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 1.0 });
        let obs = paper_observations(&spatial, &truth, 4e-3);
        let off = truth.map(|v| v * 1.02 + 35.0);
        compare(&spatial, off, &obs);
        let planar = StateLayout::new(Space::Planar, Motion::ConstantVelocity { t0: 1.0 });
        let flat = [truth[0], truth[1], truth[3], truth[4]];
        let obs = paper_observations(&planar, &flat, 4e-3);
        compare(&planar, flat.map(|v| v * 0.97 - 20.0), &obs);
    }

    #[test]
    fn noiseless_cv_fit_recovers_truth_from_a_poor_start() {
        let layout = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
        let truth = [1340.0, 15000.0, 1000.0, 173.2, -100.0, 0.0];
        let obs = paper_observations(&layout, &truth, 0.0);
        let start = [1800.0, 13000.0, 1500.0, 150.0, -70.0, 10.0];
        let out = fit(&layout, &obs, &start, &FitOptions::default());
        assert_eq!(out.termination, Termination::Converged);
        for (k, (got, want)) in out.estimate.iter().zip(truth).enumerate() {
            assert!((got - want).abs() <= 1e-8 * want.abs().max(1.0), "{k}");
        }
        assert!(out.chi2 < 1e-12);
    }

    #[test]
    fn single_sensor_static_fit_is_singular_not_a_panic() {
        let layout = StateLayout::new(Space::Spatial, Motion::Static);
        let obs = vec![Observation::new([0.0; 3], 0.0, [0.3, 0.1], [1e-3, 1e-3]); 3];
        let out = fit(
            &layout,
            &obs,
            &[1000.0, 300.0, 100.0],
            &FitOptions::default(),
        );
        assert_eq!(out.termination, Termination::Singular);
        assert!(out.estimate.iter().all(|v| v.is_nan()));
    }

    thread_local! {
        /// Evaluations of the normal equations on this thread (`accumulate` calls).
        pub(super) static EVALUATIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    }

    /// A fit of one target's rows for half the scans and another's, 14 km away, for the rest
    /// (χ² ≈ 7·10⁴, as a mixed track's) creeps towards its minimum until a step lies below
    /// χ²'s rounding and is halved to nothing; the state then stands still. The fit ends there
    /// as the iterations would: at `max_iter`, with the same state, χ² and covariance to the
    /// bit whatever `max_iter`, and without evaluating again. (The case was found by trying
    /// such mixtures; most converge.)
    #[test]
    fn a_fit_that_stands_still_ends_as_max_iter_would() {
        let layout = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
        let truth = [6000.0, 1000.0, 1000.0, 0.0, 200.0, 0.0];
        let other = [20_000.0, 1000.0, 500.0, 0.0, 0.0, 0.0];
        let a = paper_observations(&layout, &truth, 4e-3);
        let b = paper_observations(&layout, &other, 4e-3);
        let obs: Vec<Observation> = a[..8].iter().chain(&b[8..]).copied().collect();
        let start = truth.map(|v| v * 1.01 + 50.0);
        let run = |max_iter: usize| {
            let options = FitOptions::default()
                .with_max_iter(max_iter)
                .expect("valid");
            EVALUATIONS.with(|n| n.set(0));
            let out = fit(&layout, &obs, &start, &options);
            (out, EVALUATIONS.with(|n| n.get()))
        };
        let (short, _) = run(50);
        let (long, evaluations) = run(100_000);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(short.termination, Termination::MaxIterations);
        assert_eq!((short.iterations, long.iterations), (50, 100_000));
        assert_eq!(long.termination, Termination::MaxIterations);
        assert_eq!(bits(&short.estimate), bits(&long.estimate));
        assert_eq!(bits(&short.covariance), bits(&long.covariance));
        assert_eq!(short.chi2.to_bits(), long.chi2.to_bits());
        assert!(short.chi2 > 5e4 && short.chi2.is_finite(), "{}", short.chi2);
        // Every iteration evaluates at least once: 100 000 iterations were not run.
        assert!(evaluations < 1_000, "{evaluations}");
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
