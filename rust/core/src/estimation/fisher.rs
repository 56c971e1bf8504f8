//! Fisher information and the Cramér-Rao lower bound (METHODS §6) of a true state observed by
//! given sensors at given times. For Gaussian angle noise the information is `Σ gᵀg` over the
//! normalised measurement gradients at the truth; the CRLB is its inverse.

use nalgebra::DMatrix;

use crate::data::{ReportOverrides, Sensors};
use crate::error::{ensure_finite, CoreError, CoreResult};
use crate::geometry::model::{predict, residual_rows, Observation, StateLayout};

/// Row-major `dim × dim` Fisher information and its inverse (the CRLB).
#[derive(Clone, Debug, PartialEq)]
pub struct Bound {
    pub fisher: Vec<f64>,
    pub crlb: Vec<f64>,
}

/// Information of the state `truth` from one measurement per `(sensor_index[k], times[k])`,
/// taken where `overrides` says the sensor was then and with the noise it says (the sensor's
/// own where it says nothing: [`ReportOverrides::default`] for fixed sensors).
pub fn crlb(
    layout: &StateLayout,
    sensors: &Sensors<'_>,
    sensor_index: &[i64],
    times: &[f64],
    overrides: &ReportOverrides<'_>,
    truth: &[f64],
) -> CoreResult<Bound> {
    let dim = layout.dim();
    validate(sensors, sensor_index, times, truth, dim)?;
    overrides.validate(sensors.space(), times.len())?;
    let mut fisher = DMatrix::<f64>::zeros(dim, dim);
    for (k, (&j, &time)) in sensor_index.iter().zip(times).enumerate() {
        let sensor = overrides.position(sensors, j as usize, k);
        let target = layout.position(truth, time);
        let obs = Observation::new(
            sensor,
            time,
            predict(layout.space, &sensor, &target),
            overrides.sigma(sensors, j as usize, k),
        );
        let rows = residual_rows(layout, truth, &obs).ok_or_else(|| {
            CoreError::ill_posed(
                "truth",
                format!("the target is on sensor {j}'s vertical axis at time {time}"),
            )
        })?;
        for c in 0..rows.count {
            let g = &rows.gradient[c][..dim];
            for a in 0..dim {
                for b in 0..dim {
                    fisher[(a, b)] += g[a] * g[b];
                }
            }
        }
    }
    let inverse = fisher
        .clone()
        .cholesky()
        .map(|c| c.inverse())
        .ok_or_else(|| {
            CoreError::ill_posed(
                "times",
                "the measurements do not determine the state (singular Fisher information)",
            )
        })?;
    // The Cholesky inverse is symmetric only to rounding, which an ill-conditioned Fisher
    // matrix (a state moving at 1e8 m/s) amplified to 4e7 absolute; the CRLB is symmetric.
    let inverse = (&inverse + inverse.transpose()) * 0.5;
    Ok(Bound {
        fisher: fisher.transpose().as_slice().to_vec(),
        crlb: inverse.transpose().as_slice().to_vec(),
    })
}

fn validate(
    sensors: &Sensors<'_>,
    sensor_index: &[i64],
    times: &[f64],
    truth: &[f64],
    dim: usize,
) -> CoreResult<()> {
    if truth.len() != dim {
        return Err(CoreError::shape(
            "truth",
            format!("expected {dim} values, got {}", truth.len()),
        ));
    }
    ensure_finite("truth", truth)?;
    if times.len() != sensor_index.len() {
        return Err(CoreError::shape(
            "times",
            format!(
                "has {} entries, sensor_index has {}",
                times.len(),
                sensor_index.len()
            ),
        ));
    }
    ensure_finite("times", times)?;
    let s = sensors.len() as i64;
    if let Some(k) = sensor_index.iter().position(|&j| j < 0 || j >= s) {
        return Err(CoreError::out_of_range(
            "sensor_index",
            format!(
                "entry {k} is {} but the network has {s} sensors",
                sensor_index[k]
            ),
        ));
    }
    let scalars = sensor_index.len() * sensors.space().angles();
    if scalars < dim {
        return Err(CoreError::ill_posed(
            "times",
            format!("{scalars} scalar measurements for {dim} unknowns"),
        ));
    }
    Ok(())
}
