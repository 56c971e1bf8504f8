//! Validated views of the caller's sensor and measurement arrays. The core borrows the arrays
//! (no copy); validation happens once, here, so the algorithms can index without checks.

use crate::error::{ensure_finite, CoreError, CoreResult};
use crate::geometry::model::{Observation, Space};

/// Sensors that coincide closer than this cannot triangulate anything.
const COINCIDENT_SENSORS_M: f64 = 1e-9;

/// A fixed sensor network. `positions` is row-major (S, 3); planar networks use z = 0.
#[derive(Clone, Copy, Debug)]
pub struct Sensors<'a> {
    space: Space,
    positions: &'a [f64],
    sigma_azimuth: &'a [f64],
    sigma_elevation: &'a [f64],
}

impl<'a> Sensors<'a> {
    /// Checks shapes, finiteness, positive noise stds and that no two sensors coincide.
    /// `sigma_elevation` is ignored (may be empty) for a planar network.
    pub fn new(
        space: Space,
        positions: &'a [f64],
        sigma_azimuth: &'a [f64],
        sigma_elevation: &'a [f64],
    ) -> CoreResult<Self> {
        let n = sigma_azimuth.len();
        if n == 0 {
            return Err(CoreError::shape("sensors", "the network has no sensors"));
        }
        if positions.len() != 3 * n {
            return Err(CoreError::shape(
                "sensor_positions",
                format!("expected shape ({n}, 3), got {} values", positions.len()),
            ));
        }
        ensure_finite("sensor_positions", positions)?;
        check_stds("sigma_azimuth", sigma_azimuth)?;
        if space == Space::Spatial {
            if sigma_elevation.len() != n {
                return Err(CoreError::shape(
                    "sigma_elevation",
                    format!(
                        "expected {n} values (one per sensor), got {}",
                        sigma_elevation.len()
                    ),
                ));
            }
            check_stds("sigma_elevation", sigma_elevation)?;
        }
        check_not_coincident(positions)?;
        Ok(Self {
            space,
            positions,
            sigma_azimuth,
            sigma_elevation,
        })
    }

    pub fn space(&self) -> Space {
        self.space
    }

    pub fn len(&self) -> usize {
        self.sigma_azimuth.len()
    }

    pub fn is_empty(&self) -> bool {
        self.sigma_azimuth.is_empty()
    }

    /// Position of sensor `j` (caller guarantees `j < len()`).
    #[inline]
    pub fn position(&self, j: usize) -> [f64; 3] {
        [
            self.positions[3 * j],
            self.positions[3 * j + 1],
            self.positions[3 * j + 2],
        ]
    }

    /// Noise stds `[σβ, σε]` of sensor `j` (σε = 1 in the plane, where it is never used).
    #[inline]
    pub fn sigma(&self, j: usize) -> [f64; 2] {
        match self.space {
            Space::Planar => [self.sigma_azimuth[j], 1.0],
            Space::Spatial => [self.sigma_azimuth[j], self.sigma_elevation[j]],
        }
    }
}

/// Accepted angle noise stds, radians (as the Python `SensorNetwork`'s `ANGLE_STD_RANGE`):
/// below 1e-12 the information 1/σ² overflows the fitter's sums at long ranges, above π an
/// angle carries no information.
pub const ANGLE_STD_RANGE: (f64, f64) = (1e-12, std::f64::consts::PI);

fn check_stds(arg: &'static str, stds: &[f64]) -> CoreResult<()> {
    let (low, high) = ANGLE_STD_RANGE;
    match stds.iter().position(|s| !(*s >= low && *s <= high)) {
        Some(j) => Err(CoreError::out_of_range(
            arg,
            format!(
                "sensor {j} has std {} rad, must lie in [{low:e}, π]",
                stds[j]
            ),
        )),
        None => Ok(()),
    }
}

fn check_not_coincident(positions: &[f64]) -> CoreResult<()> {
    let rows: Vec<&[f64]> = positions.chunks_exact(3).collect();
    for (a, pa) in rows.iter().enumerate() {
        for (b, pb) in rows.iter().enumerate().skip(a + 1) {
            let d2: f64 = pa
                .iter()
                .zip(pb.iter())
                .map(|(u, v)| (u - v) * (u - v))
                .sum();
            if d2.sqrt() < COINCIDENT_SENSORS_M {
                return Err(CoreError::ill_posed(
                    "sensor_positions",
                    format!("sensors {a} and {b} coincide"),
                ));
            }
        }
    }
    Ok(())
}

/// A columnar measurement table: sensor index, time, azimuth, elevation (ignored in the plane).
#[derive(Clone, Copy, Debug)]
pub struct Measurements<'a> {
    sensor: &'a [i64],
    time: &'a [f64],
    azimuth: &'a [f64],
    elevation: &'a [f64],
}

impl<'a> Measurements<'a> {
    /// Checks equal lengths, finite values and that every sensor index exists in `sensors`.
    pub fn new(
        sensors: &Sensors<'_>,
        sensor: &'a [i64],
        time: &'a [f64],
        azimuth: &'a [f64],
        elevation: &'a [f64],
    ) -> CoreResult<Self> {
        let n = sensor.len();
        for (arg, len) in [("time", time.len()), ("azimuth", azimuth.len())] {
            if len != n {
                return Err(CoreError::shape(
                    arg,
                    format!("has {len} rows, sensor has {n}"),
                ));
            }
        }
        ensure_finite("time", time)?;
        ensure_finite("azimuth", azimuth)?;
        if sensors.space() == Space::Spatial {
            if elevation.len() != n {
                return Err(CoreError::shape(
                    "elevation",
                    format!("has {} rows, sensor has {n}", elevation.len()),
                ));
            }
            ensure_finite("elevation", elevation)?;
        }
        let s = sensors.len() as i64;
        if let Some(row) = sensor.iter().position(|&j| j < 0 || j >= s) {
            return Err(CoreError::out_of_range(
                "sensor",
                format!(
                    "row {row} names sensor {} but the network has {s} sensors",
                    sensor[row]
                ),
            ));
        }
        Ok(Self {
            sensor,
            time,
            azimuth,
            elevation,
        })
    }

    pub fn len(&self) -> usize {
        self.sensor.len()
    }

    pub fn is_empty(&self) -> bool {
        self.sensor.is_empty()
    }

    #[inline]
    pub fn sensor(&self, m: usize) -> usize {
        self.sensor[m] as usize
    }

    #[inline]
    pub fn time(&self, m: usize) -> f64 {
        self.time[m]
    }

    /// Measurement `m`'s azimuth and elevation as stored (the elevation is NaN in the plane).
    #[inline]
    pub fn angles(&self, m: usize) -> [f64; 2] {
        [self.azimuth[m], self.elevation[m]]
    }

    /// Measurement `m` with its sensor's position and noise, ready for the model.
    #[inline]
    pub fn observation(&self, sensors: &Sensors<'_>, m: usize) -> Observation {
        let j = self.sensor(m);
        let elevation = match sensors.space() {
            Space::Planar => 0.0,
            Space::Spatial => self.elevation[m],
        };
        Observation::new(
            sensors.position(j),
            self.time[m],
            [self.azimuth[m], elevation],
            sensors.sigma(j),
        )
    }
}

/// Checks CSR group offsets over `n_indices` indices: they start at 0, never decrease, and
/// end at `n_indices`. `unit` names a group in the messages ("problem", "track").
pub fn check_offsets(offsets: &[i64], n_indices: usize, unit: &str) -> CoreResult<()> {
    if offsets.first() != Some(&0) {
        return Err(CoreError::shape(
            "offsets",
            format!("must start with 0 and have one entry per {unit} plus one"),
        ));
    }
    if let Some(p) = offsets.windows(2).position(|w| w[1] < w[0]) {
        return Err(CoreError::out_of_range(
            "offsets",
            format!("decreases between entries {p} and {}", p + 1),
        ));
    }
    if offsets.last().copied() != Some(n_indices as i64) {
        return Err(CoreError::shape(
            "offsets",
            format!("last entry must equal len(indices) = {n_indices}"),
        ));
    }
    Ok(())
}
