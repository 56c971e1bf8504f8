//! The tuple cost of eq. 2: the negative log-likelihood ratio of "a target at x̂ produced the
//! tuple's reports" against "all of them are false alarms",
//!
//! `c = −Σ_s [u_s ln(Pd_s f(z_s | x̂) / λ_s) + (1 − u_s) ln(1 − Pd_s)]`,
//!
//! with `u_s = 1` when sensor s contributes a report. `f` is the Gaussian density of the
//! report's angle(s) at the ML point x̂: for a 2-D bearing `N(θ; θ̂, σ²)` in 1/rad; for az/el the
//! product of the azimuth and elevation densities, in 1/rad². `λ_s` is sensor s's false-alarm
//! density in the same units — false reports per radian of bearing (2-D) or per rad² of
//! azimuth × elevation (3-D) — so `Pd f / λ` is dimensionless. Negative costs are tuples
//! more likely to be a target than clutter. The dummy (all-missed) tuple costs 0 by definition
//! (it is the reference hypothesis), not the `−Σ ln(1 − Pd_s)` the formula would give.
//!
//! Written out, `c = ½ χ² − Σ_{s: u_s=1} a_s − Σ_{s: u_s=0} ln(1 − Pd_s)` with
//! `a_s = ln Pd_s − ln λ_s − Σ_angles ln(σ √(2π))` and χ² the sum of the tuple's normalised
//! squared residuals at x̂; [`DetectionModel`] holds `a_s` and `ln(1 − Pd_s)`.

use crate::data::Sensors;
use crate::error::{CoreError, CoreResult};

/// Per-sensor detection probability and false-alarm density, reduced to the two constants
/// of eq. 2 each sensor contributes.
#[derive(Clone, Debug, PartialEq)]
pub struct DetectionModel {
    detected: Vec<f64>,
    missed: Vec<f64>,
}

impl DetectionModel {
    /// Validates `pd ∈ (0, 1)` (the log of `1 − Pd` must exist) and `false_alarm_density > 0`,
    /// finite, one per sensor of `sensors`.
    pub fn new(sensors: &Sensors<'_>, pd: &[f64], false_alarm_density: &[f64]) -> CoreResult<Self> {
        let n = sensors.len();
        for (arg, values) in [("pd", pd), ("false_alarm_density", false_alarm_density)] {
            if values.len() != n {
                return Err(CoreError::shape(
                    arg,
                    format!("expected {n} values (one per sensor), got {}", values.len()),
                ));
            }
        }
        if let Some(j) = pd
            .iter()
            .position(|p| !(p.is_finite() && *p > 0.0 && *p < 1.0))
        {
            return Err(CoreError::out_of_range(
                "pd",
                format!(
                    "sensor {j} has pd {}, must be in (0, 1) (eq. 2 takes ln(1 − pd))",
                    pd[j]
                ),
            ));
        }
        if let Some(j) = false_alarm_density
            .iter()
            .position(|l| !(l.is_finite() && *l > 0.0))
        {
            return Err(CoreError::out_of_range(
                "false_alarm_density",
                format!(
                    "sensor {j} has {}, must be finite and > 0 (false alarms per rad, per rad² for az/el)",
                    false_alarm_density[j]
                ),
            ));
        }
        let angles = sensors.space().angles();
        let half_ln_tau = 0.5 * std::f64::consts::TAU.ln();
        let detected = (0..n)
            .map(|j| {
                let sigma = sensors.sigma(j);
                let normalisation: f64 = sigma[..angles].iter().map(|s| s.ln() + half_ln_tau).sum();
                pd[j].ln() - false_alarm_density[j].ln() - normalisation
            })
            .collect();
        let missed = pd.iter().map(|p| (-p).ln_1p()).collect();
        Ok(Self { detected, missed })
    }

    pub fn len(&self) -> usize {
        self.detected.len()
    }

    pub fn is_empty(&self) -> bool {
        self.detected.is_empty()
    }

    /// Eq. 2 for a tuple given which sensors contribute (`contributes[s]`) and the tuple's χ²
    /// at its ML point; 0 for the dummy tuple.
    pub fn cost(&self, contributes: impl Iterator<Item = bool>, chi2: f64) -> f64 {
        let mut cost = 0.0;
        let mut any = false;
        for (s, used) in contributes.enumerate().take(self.detected.len()) {
            if used {
                any = true;
                cost -= self.detected[s];
            } else {
                cost -= self.missed[s];
            }
        }
        if any {
            cost + 0.5 * chi2
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::model::Space;

    #[test]
    fn cost_matches_the_formula_term_by_term() {
        let positions = [0.0, 0.0, 0.0, 1000.0, 0.0, 0.0, 2000.0, 0.0, 0.0];
        let (sa, se) = ([1e-3, 2e-3, 3e-3], [4e-3, 5e-3, 6e-3]);
        let (pd, lambda) = ([0.9, 0.8, 0.95], [0.5, 2.0, 10.0]);
        for space in [Space::Planar, Space::Spatial] {
            let sensors = Sensors::new(space, &positions, &sa, &se).expect("valid");
            let model = DetectionModel::new(&sensors, &pd, &lambda).expect("valid");
            // Sensor 0 and 2 contribute with normalised residuals r0 (1 or 2 angles), sensor 1 misses.
            let r: [[f64; 2]; 3] = [[0.7, -1.1], [0.0, 0.0], [-0.3, 0.4]];
            let angles = space.angles();
            let gauss = |x: f64, s: f64| (-0.5 * x * x).exp() / (s * std::f64::consts::TAU.sqrt());
            let mut expected = -(1.0f64 - pd[1]).ln();
            let mut chi2 = 0.0;
            for s in [0, 2] {
                let sig = [sa[s], se[s]];
                let f: f64 = (0..angles).map(|c| gauss(r[s][c], sig[c])).product();
                chi2 += (0..angles).map(|c| r[s][c] * r[s][c]).sum::<f64>();
                expected -= (pd[s] * f / lambda[s]).ln();
            }
            let got = model.cost([true, false, true].into_iter(), chi2);
            assert!(
                (got - expected).abs() < 1e-10 * expected.abs().max(1.0),
                "{space:?}: {got} vs {expected}"
            );
            assert_eq!(model.cost([false, false, false].into_iter(), 0.0), 0.0);
        }
    }

    #[test]
    fn bad_detection_parameters_are_rejected() {
        let positions = [0.0, 0.0, 0.0, 1000.0, 0.0, 0.0];
        let s = [1e-3, 1e-3];
        let sensors = Sensors::new(Space::Planar, &positions, &s, &s).expect("valid");
        let err = DetectionModel::new(&sensors, &[0.9, 1.0], &[1.0, 1.0]).unwrap_err();
        assert!(err.to_string().starts_with("pd: sensor 1"), "{err}");
        let err = DetectionModel::new(&sensors, &[0.9, 0.9], &[1.0, -1.0]).unwrap_err();
        assert!(
            err.to_string().starts_with("false_alarm_density: sensor 1"),
            "{err}"
        );
        assert!(DetectionModel::new(&sensors, &[0.9], &[1.0, 1.0]).is_err());
    }
}
