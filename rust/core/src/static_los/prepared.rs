//! The enumeration's prepared problem and its per-prefix primitives: the point estimate of a
//! two-ray prefix, of a longer prefix, the gate, and the covariance of a survivor. The brute-force
//! check in the tests calls the same primitives, so both apply the identical gate.

use nalgebra::{Matrix2, Matrix3};

use super::cost::DetectionModel;
use super::window::Wedge;
use super::EnumerateOptions;
use crate::data::{Measurements, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::estimation::fit::gauss_newton::{fit_into, FitSlots};
use crate::estimation::fit::Termination;
use crate::evidence::AttributeGate;
use crate::geometry::angles::wrap;
use crate::geometry::los::{closest_points, direction, intersect_bearings};
use crate::geometry::model::{residual_rows, Motion, Observation, Space, StateLayout};

/// One report, ready for the model.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ray {
    pub row: usize,
    pub obs: Observation,
    /// Unit line-of-sight direction (z = 0 in the plane).
    pub direction: [f64; 3],
    pub wedge: Wedge,
    /// `Σ ln(σ_report / σ_sensor)` over the angles: what the report's own noise adds to the
    /// cost of a tuple holding it (eq. 2's normalisation is the sensor's); 0 without one.
    pub cost_excess: f64,
}

/// A point estimate of a prefix that passed the gate.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Estimate {
    pub point: [f64; 3],
    /// Row-major `dim × dim` in the first `dim²` entries; `None` until needed (2-D pairs).
    pub covariance: Option<[f64; 9]>,
    pub chi2: f64,
}

/// The prepared problem: reports grouped per sensor in table order.
pub(crate) struct Prepared<'a> {
    pub layout: StateLayout,
    pub n_sensors: usize,
    pub rays: Vec<Vec<Ray>>,
    /// Per sensor, `(wrapped azimuth, index into rays[s])` in ascending azimuth.
    pub by_azimuth: Vec<Vec<(f64, u32)>>,
    /// Per sensor, the widest gate half-width of its reports' azimuths, `√γ·σ_az` (with a
    /// tiny margin).
    pub half_width: Vec<f64>,
    /// Per sensor, the horizontal position all its reports were taken from; `None` when they
    /// were taken from several (a moving sensor), which turns the window off at that sensor.
    pub apex: Vec<Option<[f64; 2]>>,
    pub detection: &'a DetectionModel,
    pub options: EnumerateOptions,
    /// The attribute gate (METHODS §3 used by §2): pairs of reports below η never share a
    /// tuple. `None`: bearings only.
    pub attributes: Option<AttributeGate<'a>>,
}

impl<'a> Prepared<'a> {
    pub fn new(
        sensors: &Sensors<'_>,
        measurements: &Measurements<'_>,
        detection: &'a DetectionModel,
        options: &EnumerateOptions,
    ) -> CoreResult<Self> {
        let n_sensors = sensors.len();
        options.check_sensor_count(n_sensors)?;
        if detection.len() != n_sensors {
            return Err(CoreError::shape(
                "pd",
                format!("expected {n_sensors} values, got {}", detection.len()),
            ));
        }
        let space = sensors.space();
        let layout = StateLayout::new(space, Motion::Static);
        let root_gate = options.gate_sigmas();
        let gate = |sigma: f64| root_gate * sigma * (1.0 + 1e-9) + 1e-12;
        let mut half_width: Vec<f64> = (0..n_sensors).map(|s| gate(sensors.sigma(s)[0])).collect();
        let mut apex: Vec<Option<[f64; 2]>> = (0..n_sensors)
            .map(|s| {
                let p = sensors.position(s);
                Some([p[0], p[1]])
            })
            .collect();
        let angles = space.angles();
        let mut rays: Vec<Vec<Ray>> = vec![Vec::new(); n_sensors];
        for m in 0..measurements.len() {
            let s = measurements.sensor(m);
            let mut obs = measurements.observation(sensors, m);
            obs.time = 0.0;
            let direction = match space {
                Space::Planar => direction(obs.angles[0], 0.0),
                Space::Spatial => direction(obs.angles[0], obs.angles[1]),
            };
            let at = [obs.sensor[0], obs.sensor[1]];
            if rays[s].is_empty() {
                apex[s] = Some(at);
                half_width[s] = gate(obs.sigma[0]);
            } else if apex[s] != Some(at) {
                apex[s] = None;
            }
            half_width[s] = half_width[s].max(gate(obs.sigma[0]));
            let wedge = Wedge {
                apex: at,
                bearing: wrap(obs.angles[0]),
                half_width: gate(obs.sigma[0]),
            };
            let own = sensors.sigma(s);
            let cost_excess = (0..angles).map(|k| (obs.sigma[k] / own[k]).ln()).sum();
            rays[s].push(Ray {
                row: m,
                obs,
                direction,
                wedge,
                cost_excess,
            });
        }
        if let Some(s) = rays.iter().position(|r| r.len() > u32::MAX as usize) {
            return Err(CoreError::out_of_range(
                "sensor",
                format!("sensor {s} has more than 2^32 reports"),
            ));
        }
        let by_azimuth = rays
            .iter()
            .map(|list| {
                let mut sorted: Vec<(f64, u32)> = list
                    .iter()
                    .enumerate()
                    .map(|(i, r)| (r.wedge.bearing, i as u32))
                    .collect();
                sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                sorted
            })
            .collect();
        Ok(Self {
            layout,
            n_sensors,
            rays,
            by_azimuth,
            half_width,
            apex,
            detection,
            options: *options,
            attributes: None,
        })
    }

    /// Adds the attribute gate; its table must have one row per measurement.
    pub fn with_attributes(
        mut self,
        gate: Option<AttributeGate<'a>>,
        rows: usize,
    ) -> CoreResult<Self> {
        if let Some(g) = &gate {
            if g.table.n_rows() != rows {
                return Err(CoreError::shape(
                    "attributes",
                    format!("has {} rows, the measurements {rows}", g.table.n_rows()),
                ));
            }
        }
        self.attributes = gate;
        Ok(self)
    }

    pub fn dim(&self) -> usize {
        self.layout.dim()
    }

    /// The gate on a point: every normalised squared residual ≤ γ and in front of every
    /// sensor. Returns χ² when it passes.
    fn gate(&self, point: &[f64; 3], obs: &[Observation]) -> Option<f64> {
        let dim = self.dim();
        let mut chi2 = 0.0;
        for o in obs {
            let rows = residual_rows(&self.layout, &point[..dim], o)?;
            for r in &rows.residual[..rows.count] {
                let r2 = r * r;
                if r2.is_nan() || r2 > self.options.chi2_per_angle() {
                    return None;
                }
                chi2 += r2;
            }
            // The measured line of sight from the cosines and sines the observation caches
            // (what `direction` of its angles gives, bit for bit: this runs per prefix fit).
            let d = o.line_of_sight();
            let ahead: f64 = (0..dim).map(|k| (point[k] - o.sensor[k]) * d[k]).sum();
            if ahead.is_nan() || ahead <= 0.0 {
                return None;
            }
        }
        Some(chi2)
    }

    /// Gauss-Newton ML of `obs` from `start`, then the gate.
    fn fit_and_gate(&self, obs: &[Observation], start: &[f64; 3]) -> Option<Estimate> {
        let dim = self.dim();
        let mut estimate = [0.0; 3];
        let mut covariance = [0.0; 9];
        let summary = fit_into(
            &self.layout,
            obs,
            &start[..dim],
            self.options.fit(),
            FitSlots {
                estimate: &mut estimate[..dim],
                covariance: &mut covariance[..dim * dim],
            },
        );
        if matches!(
            summary.termination,
            Termination::Singular | Termination::NonFinite
        ) {
            return None;
        }
        if !estimate[..dim].iter().all(|v| v.is_finite()) {
            return None;
        }
        let chi2 = self.gate(&estimate, obs)?;
        Some(Estimate {
            point: estimate,
            covariance: Some(covariance),
            chi2,
        })
    }

    /// Prefix of two rays: closed form (and, for az/el, Gauss-Newton from it), then the gate.
    pub fn estimate_pair(&self, a: &Ray, b: &Ray) -> Option<Estimate> {
        match self.layout.space {
            Space::Planar => {
                let (sa, sb) = (
                    [a.obs.sensor[0], a.obs.sensor[1]],
                    [b.obs.sensor[0], b.obs.sensor[1]],
                );
                let (p, ra, rb) = intersect_bearings(&sa, a.obs.angles[0], &sb, b.obs.angles[0])?;
                if !(ra > 0.0 && rb > 0.0) {
                    return None;
                }
                // On both lines and in front of both sensors: both residuals are 0 (to
                // rounding), so the gate passes without evaluating it.
                if !(p[0].is_finite() && p[1].is_finite()) {
                    return None;
                }
                Some(Estimate {
                    point: [p[0], p[1], 0.0],
                    covariance: None,
                    chi2: 0.0,
                })
            }
            Space::Spatial => {
                let meeting =
                    closest_points(&a.obs.sensor, &a.direction, &b.obs.sensor, &b.direction)?;
                if !meeting.in_front() {
                    return None;
                }
                self.fit_and_gate(&[a.obs, b.obs], &meeting.midpoint())
            }
        }
    }

    /// Prefix of three or more rays: Gauss-Newton from the previous prefix's point.
    pub fn estimate_extension(&self, parent: &Estimate, obs: &[Observation]) -> Option<Estimate> {
        self.fit_and_gate(obs, &parent.point)
    }

    /// The inverse Fisher information at `point` (row-major in the first dim² entries).
    pub fn covariance_at(&self, point: &[f64; 3], obs: &[Observation]) -> [f64; 9] {
        let dim = self.dim();
        if self.layout.space == Space::Planar {
            // ∂θ/∂(x, y) = (−dy, dx)/ρ²: no angle needed.
            let mut info = Matrix2::zeros();
            for o in obs {
                let (dx, dy) = (point[0] - o.sensor[0], point[1] - o.sensor[1]);
                let scale = 1.0 / ((dx * dx + dy * dy) * o.sigma[0]);
                let g = nalgebra::Vector2::new(-dy * scale, dx * scale);
                info += g * g.transpose();
            }
            let mut out = [f64::NAN; 9];
            if let Some(inv) = info.try_inverse() {
                out[..4].copy_from_slice(&[inv[(0, 0)], inv[(0, 1)], inv[(1, 0)], inv[(1, 1)]]);
            }
            return out;
        }
        let mut info = [[0.0; 3]; 3];
        for o in obs {
            let Some(rows) = residual_rows(&self.layout, &point[..dim], o) else {
                return [f64::NAN; 9];
            };
            for g in &rows.gradient[..rows.count] {
                for a in 0..dim {
                    for b in 0..dim {
                        info[a][b] += g[a] * g[b];
                    }
                }
            }
        }
        let mut out = [f64::NAN; 9];
        if dim == 2 {
            if let Some(inv) =
                Matrix2::new(info[0][0], info[0][1], info[1][0], info[1][1]).try_inverse()
            {
                out[..4].copy_from_slice(&[inv[(0, 0)], inv[(0, 1)], inv[(1, 0)], inv[(1, 1)]]);
            }
        } else if let Some(inv) = Matrix3::from_fn(|a, b| info[a][b]).try_inverse() {
            for a in 0..3 {
                for b in 0..3 {
                    out[3 * a + b] = inv[(a, b)];
                }
            }
        }
        out
    }
}
