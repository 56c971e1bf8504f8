//! The validated input: a shared table of measurement rows ([`KalmanInput`]) and the tracks
//! as CSR groups of its rows ([`Tracks`]). Everything a track's filter reads is checked here,
//! before any work starts, so a bad value is an error naming the argument and row, never a
//! panic or a silent NaN.

use nalgebra::{SMatrix, SVector};

use super::measurement::{polar_to_point, MeasurementModel, Point};
use crate::data::check_offsets;
use crate::error::{ensure_finite, CoreError, CoreResult};

/// Measurement noise of every row.
#[derive(Clone, Copy, Debug)]
pub enum Noise<'a> {
    /// Standard deviations, `n × m` (one per row and column; for polar rows (σr, σθ)).
    Std(&'a [f64]),
    /// Full covariances, `n × m × m` row-major (symmetric positive definite).
    Covariance(&'a [f64]),
}

/// The measurement table the tracks index into. Row `i` is taken at `times[i]` and holds
/// `measurements[i·m..(i+1)·m]`: a position (1–3 columns) or (range, azimuth) from
/// `sensor_positions[2i..2i+2]` (polar models only).
#[derive(Clone, Copy, Debug)]
pub struct KalmanInput<'a> {
    pub times: &'a [f64],
    pub measurements: &'a [f64],
    /// Columns per row, `m`.
    pub columns: usize,
    pub noise: Noise<'a>,
    pub sensor_positions: Option<&'a [f64]>,
}

/// Tracks as CSR groups: track `p` is the rows `indices[offsets[p]..offsets[p+1]]`, sorted by
/// time. A row belongs to at most one track.
#[derive(Clone, Copy, Debug)]
pub struct Tracks<'a> {
    pub indices: &'a [i64],
    pub offsets: &'a [i64],
}

/// Marks a row no track uses in the row → CSR position map.
pub(crate) const UNUSED: usize = usize::MAX;

impl KalmanInput<'_> {
    /// Rows in the table.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// Checks shapes, finiteness and the noise of every row against `model`; returns the
    /// position dimension of the state (2 for polar models).
    pub fn validate(&self, model: MeasurementModel) -> CoreResult<usize> {
        let (n, m) = (self.len(), self.columns);
        match model {
            MeasurementModel::Position if !(1..=3).contains(&m) => {
                return Err(CoreError::shape(
                    "measurements",
                    format!("position measurements have 1 to 3 columns, got {m}"),
                ));
            }
            MeasurementModel::Polar | MeasurementModel::PolarConverted if m != 2 => {
                return Err(CoreError::shape(
                    "measurements",
                    format!("polar measurements have 2 columns (range, azimuth), got {m}"),
                ));
            }
            _ => {}
        }
        expect_len("measurements", self.measurements.len(), n, m)?;
        ensure_finite("times", self.times)?;
        ensure_finite("measurements", self.measurements)?;
        match self.noise {
            Noise::Std(std) => {
                expect_len("noise", std.len(), n, m)?;
                ensure_finite("noise", std)?;
                if let Some(k) = std.iter().position(|&s| s <= 0.0) {
                    return Err(CoreError::out_of_range(
                        "noise",
                        format!("row {} has std {}, must be > 0", k / m, std[k]),
                    ));
                }
            }
            Noise::Covariance(cov) => {
                expect_len("noise", cov.len(), n, m * m)?;
                ensure_finite("noise", cov)?;
                (0..n).try_for_each(|row| {
                    check_covariance(&cov[row * m * m..(row + 1) * m * m], m, row)
                })?;
            }
        }
        match (model.is_polar(), self.sensor_positions) {
            (true, None) => {
                return Err(CoreError::ill_posed(
                    "sensor_positions",
                    "polar measurements need the sensor position of every row",
                ))
            }
            (false, Some(_)) => {
                return Err(CoreError::out_of_range(
                    "sensor_positions",
                    "only polar measurements use sensor positions",
                ))
            }
            (true, Some(sensors)) => {
                expect_len("sensor_positions", sensors.len(), n, 2)?;
                ensure_finite("sensor_positions", sensors)?;
                if let Some(row) = (0..n).find(|&row| self.measurements[2 * row] < 0.0) {
                    return Err(CoreError::out_of_range(
                        "measurements",
                        format!(
                            "row {row} has a negative range {}",
                            self.measurements[2 * row]
                        ),
                    ));
                }
            }
            (false, None) => {}
        }
        Ok(if model.is_polar() { 2 } else { m })
    }

    /// Row `row`'s measurement noise covariance (`D = m`).
    pub(crate) fn noise_matrix<const D: usize>(&self, row: usize) -> SMatrix<f64, D, D> {
        match self.noise {
            Noise::Std(std) => SMatrix::from_fn(|i, j| {
                if i == j {
                    std[row * D + i].powi(2)
                } else {
                    0.0
                }
            }),
            Noise::Covariance(cov) => SMatrix::from_fn(|i, j| cov[row * D * D + i * D + j]),
        }
    }

    /// Row `row`'s values (`m` of them).
    pub(crate) fn values(&self, row: usize) -> &[f64] {
        &self.measurements[row * self.columns..(row + 1) * self.columns]
    }

    /// Row `row`'s sensor position (polar models; the origin otherwise).
    pub(crate) fn sensor(&self, row: usize) -> [f64; 2] {
        self.sensor_positions
            .map_or([0.0; 2], |s| [s[2 * row], s[2 * row + 1]])
    }

    /// Row `row` as a Cartesian position with covariance; polar rows are converted.
    pub(crate) fn point<const D: usize>(&self, model: MeasurementModel, row: usize) -> Point<D> {
        let values = self.values(row);
        if model.is_polar() && D == 2 {
            let converted = polar_to_point(
                self.sensor(row),
                values[0],
                values[1],
                &self.noise_matrix::<2>(row),
            );
            return Point {
                z: SVector::from_fn(|i, _| converted.z[i]),
                r: SMatrix::from_fn(|i, j| converted.r[(i, j)]),
            };
        }
        Point {
            z: SVector::from_fn(|i, _| values[i]),
            r: self.noise_matrix::<D>(row),
        }
    }
}

fn expect_len(arg: &'static str, len: usize, rows: usize, per_row: usize) -> CoreResult<()> {
    if len == rows * per_row {
        Ok(())
    } else {
        Err(CoreError::shape(
            arg,
            format!("expected {rows} rows of {per_row} values (one per time), got {len} values"),
        ))
    }
}

/// A row's covariance must be symmetric (to rounding) and positive definite.
fn check_covariance(cov: &[f64], m: usize, row: usize) -> CoreResult<()> {
    for i in 0..m {
        for j in 0..i {
            let scale = (cov[i * m + i].abs() * cov[j * m + j].abs()).sqrt();
            if (cov[i * m + j] - cov[j * m + i]).abs() > 1e-9 * scale {
                return Err(CoreError::out_of_range(
                    "noise",
                    format!("row {row}'s covariance is not symmetric"),
                ));
            }
        }
    }
    let matrix = nalgebra::DMatrix::from_row_slice(m, m, cov);
    if matrix.cholesky().is_none() {
        return Err(CoreError::out_of_range(
            "noise",
            format!("row {row}'s covariance is not positive definite"),
        ));
    }
    Ok(())
}

impl Tracks<'_> {
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Rows of track `p` (valid after [`Tracks::validate`]).
    pub(crate) fn rows(&self, p: usize) -> &[i64] {
        &self.indices[self.offsets[p] as usize..self.offsets[p + 1] as usize]
    }

    /// Checks the CSR structure against `times` (one per row): rows in range and in at most
    /// one track, no empty track, times non-decreasing along a track, and the first
    /// `distinct` times of a track that has that many different (what differencing divides
    /// by; a shorter track gets no state and is not checked). Returns each
    /// row's position in `indices` (`UNUSED` for rows of no track).
    pub fn validate(&self, times: &[f64], distinct: usize) -> CoreResult<Vec<usize>> {
        let (offsets, indices, n) = (self.offsets, self.indices, times.len());
        check_offsets(offsets, indices.len(), "track")?;
        if let Some(p) = offsets.windows(2).position(|w| w[1] == w[0]) {
            return Err(CoreError::ill_posed(
                "offsets",
                format!("track {p} has no rows"),
            ));
        }
        let mut position = vec![UNUSED; n];
        for (k, &row) in indices.iter().enumerate() {
            let Some(slot) = usize::try_from(row).ok().and_then(|r| position.get_mut(r)) else {
                return Err(CoreError::out_of_range(
                    "indices",
                    format!("entry {k} is {row} but the table has {n} rows"),
                ));
            };
            if *slot != UNUSED {
                return Err(CoreError::out_of_range(
                    "indices",
                    format!(
                        "row {row} is in entries {} and {k}; a row belongs to one track",
                        *slot
                    ),
                ));
            }
            *slot = k;
        }
        for p in 0..self.len() {
            let rows = self.rows(p);
            for (k, pair) in rows.windows(2).enumerate() {
                let (before, after) = (times[pair[0] as usize], times[pair[1] as usize]);
                if after < before {
                    return Err(CoreError::out_of_range(
                        "times",
                        format!(
                            "track {p} goes back in time at row {} ({after} after {before}); sort each track's rows by time",
                            pair[1]
                        ),
                    ));
                }
                if after == before && k + 1 < distinct && rows.len() >= distinct {
                    return Err(CoreError::ill_posed(
                        "times",
                        format!(
                            "track {p}'s first {distinct} measurements need distinct times for differencing, rows {} and {} are both at {after} (or use init 'single_point')",
                            pair[0], pair[1]
                        ),
                    ));
                }
            }
        }
        Ok(position)
    }
}
