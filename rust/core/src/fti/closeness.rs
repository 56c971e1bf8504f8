//! The fuzzy synthetic closeness (METHODS §1 eq. 17–18) and its analytic gradient — the hot
//! kernel of the search.
//!
//! 3-D: `μ_m = ½exp(−(Δβ/sβ_j)²) + ½exp(−(Δε/sε_j)²)`; 2-D: `μ_m = exp(−(Δθ/s_j)²)`;
//! `R = (1/N) Σ_m μ_m` over all N rows of all sensors. Residuals are wrapped to (−π, π].
//!
//! How it is made fast without changing the function beyond rounding:
//! * **Per scan, not per row.** All rows of one scan share the sensor and the time, hence the
//!   predicted target position, the predicted angles β̂, ε̂ and their gradients. Those (two
//!   `atan2`, a `sqrt`) are computed once per scan; a row costs a subtraction, a wrap and an
//!   `exp`. The gradient is accumulated per scan as `Σ e·Δ/s²` times the scan's `∂β̂/∂X`.
//! * **Tail skip.** A row with `(Δ/s)² > 60` would add `exp(−(Δ/s)²) < e⁻⁶⁰ ≈ 9·10⁻²⁷` to
//!   `N·R`: wherever some row lies within √23·s ≈ 4.8 s of its prediction (a term ≥ e⁻²³), all
//!   N rows' skipped terms together are below `N·e⁻³⁷ ≈ N·10⁻¹⁶` of R — rounding for the
//!   scenes this library runs (states of the paper and ring scenes move by ≤ 3·10⁻¹³
//!   relative, `benches/initiation_identity.py`). Each scan keeps its measured angles sorted,
//!   and the rows with `|Δ| ≤ √60·s` (a window around β̂, or ε̂, modulo 2π) are found by binary
//!   search; the rest are never touched. A state farther than √60·s from every row has R = 0
//!   and no gradient. The window is narrow on purpose: elevations span a fraction of a radian,
//!   so a window of `exp`'s full range (√746·s, where it is exactly 0.0 in f64) holds almost
//!   every row of a scan and an evaluation costs twice as much on the 4 × 50 ring scene's rows
//!   (`benches/bench_closeness.py`).
//! * Precomputed once per call into a struct of arrays ([`Precomputed`]); no allocation.
//!
//! Wherever some row lies within 4.8 s of its prediction the result equals the naive
//! row-by-row sum up to rounding (the terms are added per scan, azimuth window then elevation
//! window, instead of in row order, and the tail is skipped).
//!
//! A scan whose sensor sees the hypothesised target exactly on its vertical axis (zero
//! horizontal range: a measure-zero set where the azimuth is undefined) contributes 0.

use std::f64::consts::PI;

use rayon::prelude::*;

use super::scans::Scans;
use crate::data::{Measurements, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::geometry::angles::wrap;
use crate::geometry::model::{Space, MAX_DIM};

/// `(Δ/s)²` above which a row's term (< e⁻⁶⁰) is skipped: see the module doc.
const TAIL: f64 = 60.0;

/// Per-sensor membership spreads `s` (paper `s = 2σ`), validated.
#[derive(Clone, Copy, Debug)]
pub struct Spreads<'a> {
    pub azimuth: &'a [f64],
    pub elevation: &'a [f64],
}

impl<'a> Spreads<'a> {
    /// Checks one finite positive spread per sensor (`elevation` is ignored in 2-D).
    pub fn new(
        space: Space,
        n_sensors: usize,
        azimuth: &'a [f64],
        elevation: &'a [f64],
    ) -> CoreResult<Self> {
        check_spreads("spread_azimuth", azimuth, n_sensors)?;
        if space == Space::Spatial {
            check_spreads("spread_elevation", elevation, n_sensors)?;
        }
        Ok(Self { azimuth, elevation })
    }
}

fn check_spreads(arg: &'static str, values: &[f64], n: usize) -> CoreResult<()> {
    if values.len() != n {
        return Err(CoreError::shape(
            arg,
            format!("expected {n} values (one per sensor), got {}", values.len()),
        ));
    }
    match values.iter().position(|s| !(s.is_finite() && *s > 0.0)) {
        Some(j) => Err(CoreError::out_of_range(
            arg,
            format!(
                "sensor {j} has spread {}, must be finite and > 0",
                values[j]
            ),
        )),
        None => Ok(()),
    }
}

/// Everything R needs, per scan (struct of arrays) plus each scan's sorted angles.
#[derive(Clone, Debug)]
pub struct Precomputed {
    space: Space,
    n_rows: usize,
    inv_n: f64,
    sx: Vec<f64>,
    sy: Vec<f64>,
    sz: Vec<f64>,
    dt: Vec<f64>,
    inv_s2_az: Vec<f64>,
    inv_s2_el: Vec<f64>,
    /// Half-widths `√TAIL·s` of the windows outside which a term is skipped.
    window_az: Vec<f64>,
    window_el: Vec<f64>,
    /// The angles of scan k are `[offsets[k]..offsets[k + 1]]` of the sorted arrays.
    offsets: Vec<usize>,
    /// Measured angles wrapped to (−π, π], ascending within each scan.
    azimuth: Vec<f64>,
    elevation: Vec<f64>,
}

impl Precomputed {
    /// Precomputes R for the constant-velocity state with epoch `t0` (finite).
    pub fn new(
        sensors: &Sensors<'_>,
        measurements: &Measurements<'_>,
        spreads: &Spreads<'_>,
        t0: f64,
    ) -> CoreResult<Self> {
        if !t0.is_finite() {
            return Err(CoreError::out_of_range(
                "t0",
                format!("{t0} must be finite"),
            ));
        }
        let space = sensors.space();
        let scans = Scans::new(measurements, sensors.len());
        let n = measurements.len();
        let mut pre = Precomputed {
            space,
            n_rows: n,
            inv_n: if n == 0 { 0.0 } else { 1.0 / n as f64 },
            sx: Vec::with_capacity(scans.len()),
            sy: Vec::with_capacity(scans.len()),
            sz: Vec::with_capacity(scans.len()),
            dt: Vec::with_capacity(scans.len()),
            inv_s2_az: Vec::with_capacity(scans.len()),
            inv_s2_el: Vec::with_capacity(scans.len()),
            window_az: Vec::with_capacity(scans.len()),
            window_el: Vec::with_capacity(scans.len()),
            offsets: vec![0],
            azimuth: Vec::with_capacity(n),
            elevation: Vec::with_capacity(n),
        };
        for k in 0..scans.len() {
            let rows = scans.scan(k);
            let obs = measurements.observation(sensors, rows[0]);
            let j = measurements.sensor(rows[0]);
            // Reports with their own noise widen the sensor's spread in proportion.
            let own = sensors.sigma(j);
            let widest = (rows.iter().map(|&m| measurements.sigma(sensors, m)))
                .fold([0.0_f64; 2], |a, s| [a[0].max(s[0]), a[1].max(s[1])]);
            let (s_az, s_el) = match space {
                Space::Planar => (spreads.azimuth[j] * widest[0] / own[0], 1.0),
                Space::Spatial => (
                    spreads.azimuth[j] * widest[0] / own[0],
                    spreads.elevation[j] * widest[1] / own[1],
                ),
            };
            let [x, y, z] = obs.sensor;
            pre.sx.push(x);
            pre.sy.push(y);
            pre.sz.push(z);
            pre.dt.push(obs.time - t0);
            pre.inv_s2_az.push(1.0 / (s_az * s_az));
            pre.inv_s2_el.push(1.0 / (s_el * s_el));
            pre.window_az.push(TAIL.sqrt() * s_az);
            pre.window_el.push(TAIL.sqrt() * s_el);
            let mut angles: Vec<[f64; 2]> = rows
                .iter()
                .map(|&m| measurements.observation(sensors, m).angles.map(wrap))
                .collect();
            let start = pre.azimuth.len();
            angles.sort_by(|a, b| a[0].total_cmp(&b[0]));
            pre.azimuth.extend(angles.iter().map(|a| a[0]));
            angles.sort_by(|a, b| a[1].total_cmp(&b[1]));
            pre.elevation.extend(angles.iter().map(|a| a[1]));
            pre.offsets.push(start + rows.len());
        }
        Ok(pre)
    }

    pub fn space(&self) -> Space {
        self.space
    }

    /// State dimension (4 or 6).
    pub fn dim(&self) -> usize {
        2 * self.space.position_dim()
    }

    /// Number of measurement rows N.
    pub fn len(&self) -> usize {
        self.n_rows
    }

    pub fn is_empty(&self) -> bool {
        self.n_rows == 0
    }
}

/// R(X0) and ∂R/∂X0 (entries past `dim()` are 0). `x` holds at least `dim()` values.
pub fn closeness_and_gradient(pre: &Precomputed, x: &[f64]) -> (f64, [f64; MAX_DIM]) {
    kernel::<true>(pre, x)
}

/// R(X0) alone.
pub fn closeness(pre: &Precomputed, x: &[f64]) -> f64 {
    kernel::<false>(pre, x).0
}

/// R and gradient of many states (row-major `P × dim`), in parallel, in input order.
pub fn closeness_batch(pre: &Precomputed, states: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let d = pre.dim();
    let results: Vec<(f64, [f64; MAX_DIM])> = states
        .par_chunks_exact(d)
        .map(|x| closeness_and_gradient(pre, x))
        .collect();
    let values = results.iter().map(|r| r.0).collect();
    let gradients = results.iter().flat_map(|r| r.1[..d].to_vec()).collect();
    (values, gradients)
}

/// Both spaces; `GRAD = false` skips the gradient arithmetic.
#[inline(always)]
fn kernel<const GRAD: bool>(pre: &Precomputed, x: &[f64]) -> (f64, [f64; MAX_DIM]) {
    let spatial = pre.space == Space::Spatial;
    let p = pre.space.position_dim();
    let position = [x[0], x[1], if spatial { x[2] } else { 0.0 }];
    let velocity = [x[p], x[p + 1], if spatial { x[5] } else { 0.0 }];
    let mut sum = 0.0;
    let (mut gp, mut gv) = ([0.0f64; 3], [0.0f64; 3]);
    for k in 0..pre.dt.len() {
        let dt = pre.dt[k];
        let dx = position[0] + dt * velocity[0] - pre.sx[k];
        let dy = position[1] + dt * velocity[1] - pre.sy[k];
        let rho2 = dx * dx + dy * dy;
        if rho2.is_nan() || rho2 <= 0.0 {
            continue; // on the vertical axis (or a non-finite state): see the module doc
        }
        let rows = pre.offsets[k]..pre.offsets[k + 1];
        let beta = dy.atan2(dx);
        let (a_sum, a_grad) = window_terms::<GRAD>(
            &pre.azimuth[rows.clone()],
            beta,
            pre.window_az[k],
            pre.inv_s2_az[k],
        );
        // ∂β̂/∂p = (−dy, dx, 0)/ρ².
        let mut g = [-dy * a_grad / rho2, dx * a_grad / rho2, 0.0];
        if spatial {
            let dz = position[2] + dt * velocity[2] - pre.sz[k];
            let rho = rho2.sqrt();
            let r2 = rho2 + dz * dz;
            let eps = dz.atan2(rho);
            let (e_sum, e_grad) = window_terms::<GRAD>(
                &pre.elevation[rows],
                eps,
                pre.window_el[k],
                pre.inv_s2_el[k],
            );
            sum += 0.5 * (a_sum + e_sum);
            if GRAD {
                // ½ of μ cancels the 2 of d(Δ²); ∂ε̂/∂p = (−dx·dz/ρ, −dy·dz/ρ, ρ)/r².
                let c = e_grad / r2;
                let h = c * dz / rho;
                g = [g[0] - h * dx, g[1] - h * dy, c * rho];
            }
        } else {
            sum += a_sum;
            g = [2.0 * g[0], 2.0 * g[1], 0.0]; // μ = exp(−(Δ/s)²) has no ½ in 2-D
        }
        if GRAD {
            for c in 0..3 {
                gp[c] += g[c];
                gv[c] += dt * g[c];
            }
        }
    }
    let s = pre.inv_n;
    let mut grad = [0.0; MAX_DIM];
    for c in 0..p {
        grad[c] = gp[c] * s;
        grad[p + c] = gv[c] * s;
    }
    (sum * s, grad)
}

/// `(Σ e, Σ e·Δ/s²)` with `e = exp(−(Δ/s)²)`, `Δ = wrap(v − center)`, over the sorted
/// `angles` within `window` of `center` modulo 2π — the rows outside are skipped.
#[inline(always)]
fn window_terms<const GRAD: bool>(
    angles: &[f64],
    center: f64,
    window: f64,
    inv_s2: f64,
) -> (f64, f64) {
    let mut acc = (0.0, 0.0);
    let mut add = |range: &[f64]| {
        for &v in range {
            let d = wrap(v - center);
            let e = (-(d * d) * inv_s2).exp();
            acc.0 += e;
            if GRAD {
                acc.1 += e * d * inv_s2;
            }
        }
    };
    if window >= PI {
        add(angles);
        return acc;
    }
    let (lo, hi) = (center - window, center + window);
    let between = |a: f64, b: f64| {
        let i0 = angles.partition_point(|&v| v < a);
        let i1 = angles.partition_point(|&v| v <= b);
        &angles[i0..i1.max(i0)]
    };
    if lo < -PI {
        add(between(-PI, hi));
        add(between(lo + 2.0 * PI, PI));
    } else if hi > PI {
        add(between(-PI, hi - 2.0 * PI));
        add(between(lo, PI));
    } else {
        add(between(lo, hi));
    }
    acc
}
