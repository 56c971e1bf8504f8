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

/// What a report may say in place of its sensor's values: where the sensor was when it took
/// the report (a moving platform), and the report's own noise stds. Each column is optional,
/// and a NaN on a row (in a position row: its x) means the sensor's value there.
#[derive(Clone, Copy, Debug, Default)]
pub struct ReportOverrides<'a> {
    /// Row-major `(N, 3)` sensor positions.
    pub positions: Option<&'a [f64]>,
    pub sigma_azimuth: Option<&'a [f64]>,
    pub sigma_elevation: Option<&'a [f64]>,
}

impl ReportOverrides<'_> {
    /// Whether any column is given (the fixed-sensor case has none).
    pub fn any(&self) -> bool {
        self.positions.is_some() || self.sigma_azimuth.is_some() || self.sigma_elevation.is_some()
    }

    /// Checks lengths against `n` rows: each position row all NaN or all finite (z = 0 in the
    /// plane), each std NaN or in [`ANGLE_STD_RANGE`].
    pub fn validate(&self, space: Space, n: usize) -> CoreResult<()> {
        if let Some(p) = self.positions {
            if p.len() != 3 * n {
                return Err(CoreError::shape(
                    "sensor_position",
                    format!("expected shape ({n}, 3), got {} values", p.len()),
                ));
            }
            for (m, row) in p.chunks_exact(3).enumerate() {
                let given = row.iter().all(|v| v.is_finite());
                if !given && !row.iter().all(|v| v.is_nan()) {
                    return Err(CoreError::out_of_range(
                        "sensor_position",
                        format!("row {m} is {row:?}: all finite, or all NaN (the sensor's)"),
                    ));
                }
                if given && space == Space::Planar && row[2] != 0.0 {
                    return Err(CoreError::out_of_range(
                        "sensor_position",
                        format!(
                            "row {m} has z = {}; a 2-D network's sensors have z = 0",
                            row[2]
                        ),
                    ));
                }
            }
        }
        for (arg, column) in [
            ("sigma_azimuth", self.sigma_azimuth),
            ("sigma_elevation", self.sigma_elevation),
        ] {
            let Some(column) = column else { continue };
            if column.len() != n {
                return Err(CoreError::shape(
                    arg,
                    format!("has {} rows, sensor has {n}", column.len()),
                ));
            }
            let (low, high) = ANGLE_STD_RANGE;
            if let Some(m) = column
                .iter()
                .position(|s| !(s.is_nan() || (*s >= low && *s <= high)))
            {
                return Err(CoreError::out_of_range(
                    arg,
                    format!(
                        "row {m} has std {} rad, must be NaN or lie in [{low:e}, π]",
                        column[m]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Where sensor `j` was for report `m`.
    #[inline]
    pub fn position(&self, sensors: &Sensors<'_>, j: usize, m: usize) -> [f64; 3] {
        match self.positions {
            Some(p) if !p[3 * m].is_nan() => [p[3 * m], p[3 * m + 1], p[3 * m + 2]],
            _ => sensors.position(j),
        }
    }

    /// Report `m`'s noise stds `[σβ, σε]`, sensor `j`'s where the report gives none.
    #[inline]
    pub fn sigma(&self, sensors: &Sensors<'_>, j: usize, m: usize) -> [f64; 2] {
        let mut sigma = sensors.sigma(j);
        if let Some(s) = self.sigma_azimuth.map(|c| c[m]).filter(|s| !s.is_nan()) {
            sigma[0] = s;
        }
        if sensors.space() == Space::Spatial {
            if let Some(s) = self.sigma_elevation.map(|c| c[m]).filter(|s| !s.is_nan()) {
                sigma[1] = s;
            }
        }
        sigma
    }
}

/// A columnar measurement table: sensor index, time, azimuth, elevation (ignored in the
/// plane), and what the reports say in place of their sensors' values ([`ReportOverrides`]).
#[derive(Clone, Copy, Debug)]
pub struct Measurements<'a> {
    sensor: &'a [i64],
    time: &'a [f64],
    azimuth: &'a [f64],
    elevation: &'a [f64],
    overrides: ReportOverrides<'a>,
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
            overrides: ReportOverrides::default(),
        })
    }

    /// The table with per-report sensor positions and noise stds, checked against its rows.
    pub fn with_overrides(
        mut self,
        sensors: &Sensors<'_>,
        overrides: ReportOverrides<'a>,
    ) -> CoreResult<Self> {
        overrides.validate(sensors.space(), self.len())?;
        self.overrides = overrides;
        Ok(self)
    }

    /// The per-report values this table carries.
    pub fn overrides(&self) -> &ReportOverrides<'a> {
        &self.overrides
    }

    /// Where report `m`'s sensor was when it took the report.
    #[inline]
    pub fn sensor_position(&self, sensors: &Sensors<'_>, m: usize) -> [f64; 3] {
        self.overrides.position(sensors, self.sensor(m), m)
    }

    /// Report `m`'s noise stds `[σβ, σε]` (σε = 1 in the plane, where it is never used).
    #[inline]
    pub fn sigma(&self, sensors: &Sensors<'_>, m: usize) -> [f64; 2] {
        self.overrides.sigma(sensors, self.sensor(m), m)
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

    /// Measurement `m` with its sensor's position and noise at that report, ready for the
    /// model.
    #[inline]
    pub fn observation(&self, sensors: &Sensors<'_>, m: usize) -> Observation {
        let j = self.sensor(m);
        let elevation = match sensors.space() {
            Space::Planar => 0.0,
            Space::Spatial => self.elevation[m],
        };
        Observation::new(
            self.overrides.position(sensors, j, m),
            self.time[m],
            [self.azimuth[m], elevation],
            self.overrides.sigma(sensors, j, m),
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
