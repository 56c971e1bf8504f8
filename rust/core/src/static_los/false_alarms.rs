//! The default false-alarm density of a scan (a project extension, documented in
//! docs/methods.md §2): false alarms per radian (per rad² with elevations) for each sensor, when
//! the caller gives none.
//!
//! A sensor's expected false alarms are `p_false` of its reports (the paper's P_FA = 0.05), or
//! its excess over the median sensor's report count when that is larger: all sensors see the
//! same targets, so reports beyond the median sensor's are false alarms (or the others'
//! misses). They are spread over the azimuth (× elevation) span of the sensor's reports, each
//! span at least 10⁻³ rad; a sensor without reports gets π. The density is at least 10⁻¹².
//!
//! It is computed here, not in NumPy, because the per-call overhead of ten array operations
//! (about 20 µs) would be a quarter of a tiny scan's time. The arithmetic is the NumPy
//! expressions', operation for operation, so the densities are the same to the bit (a pytest
//! compares them with those expressions).

use crate::data::Measurements;
use crate::error::{CoreError, CoreResult};

/// The paper's probability that a report is a false alarm: the default `p_false`.
pub const DEFAULT_P_FALSE: f64 = 0.05;

/// Narrowest angular span a sensor's reports are taken to cover (rad).
const MIN_SPAN: f64 = 1e-3;

/// Least density returned, so eq. 2's logarithm exists.
const MIN_DENSITY: f64 = 1e-12;

/// Per sensor of one scan: reports, and the least and greatest azimuth and elevation.
#[derive(Clone, Copy)]
struct Extent {
    count: usize,
    azimuth: [f64; 2],
    elevation: [f64; 2],
}

impl Extent {
    const EMPTY: Self = Self {
        count: 0,
        azimuth: [f64::INFINITY, f64::NEG_INFINITY],
        elevation: [f64::INFINITY, f64::NEG_INFINITY],
    };

    fn add(&mut self, azimuth: f64, elevation: f64) {
        self.count += 1;
        self.azimuth = [self.azimuth[0].min(azimuth), self.azimuth[1].max(azimuth)];
        self.elevation = [
            self.elevation[0].min(elevation),
            self.elevation[1].max(elevation),
        ];
    }

    /// The sector the reports span: π for a sensor without reports.
    fn area(&self, with_elevation: bool) -> f64 {
        if self.count == 0 {
            return std::f64::consts::PI;
        }
        let width = (self.azimuth[1] - self.azimuth[0]).max(MIN_SPAN);
        if with_elevation {
            width * (self.elevation[1] - self.elevation[0]).max(MIN_SPAN)
        } else {
            width
        }
    }
}

/// Most sensors a density is asked for: the result holds one value per sensor, so a caller's
/// `n_sensors` bounds its memory (a network has far fewer).
pub const MAX_SENSORS: usize = 1 << 20;

/// Checks the scalars a caller gives: at most [`MAX_SENSORS`] sensors, `p_false` a
/// probability.
pub fn check(n_sensors: usize, p_false: f64) -> CoreResult<()> {
    if n_sensors > MAX_SENSORS {
        return Err(CoreError::out_of_range(
            "n_sensors",
            format!("{n_sensors} exceeds the maximum of {MAX_SENSORS}"),
        ));
    }
    if (0.0..=1.0).contains(&p_false) {
        return Ok(());
    }
    Err(CoreError::out_of_range(
        "p_false",
        format!("{p_false} is not a probability in [0, 1]"),
    ))
}

/// The default density of each of `n_sensors` sensors from one scan's `reports`, each
/// `(sensor, azimuth, elevation)`; the elevations are read only `with_elevation`. Reports of
/// sensors outside `0..n_sensors` are not counted.
pub fn scan_density(
    reports: impl IntoIterator<Item = (usize, f64, f64)>,
    n_sensors: usize,
    with_elevation: bool,
    p_false: f64,
) -> Vec<f64> {
    let mut extents = vec![Extent::EMPTY; n_sensors];
    for (j, azimuth, elevation) in reports {
        if let Some(extent) = extents.get_mut(j) {
            extent.add(azimuth, if with_elevation { elevation } else { 0.0 });
        }
    }
    let counts: Vec<usize> = extents.iter().map(|e| e.count).collect();
    let median = median(&counts);
    extents
        .iter()
        .map(|e| {
            let base = p_false * e.count.max(1) as f64;
            let excess = e.count as f64 - median;
            (base.max(excess) / e.area(with_elevation)).max(MIN_DENSITY)
        })
        .collect()
}

/// The default density of `table`'s `rows` (one scan), for every sensor of the table's network.
pub fn table_density(
    table: &Measurements<'_>,
    rows: impl IntoIterator<Item = usize>,
    n_sensors: usize,
    with_elevation: bool,
) -> Vec<f64> {
    let reports = rows.into_iter().map(|m| {
        let [azimuth, elevation] = table.angles(m);
        (table.sensor(m), azimuth, elevation)
    });
    scan_density(reports, n_sensors, with_elevation, DEFAULT_P_FALSE)
}

/// The median report count, as `np.median` computes it (the mean of the middle two when even).
fn median(counts: &[usize]) -> f64 {
    let mut sorted = counts.to_vec();
    sorted.sort_unstable();
    let n = sorted.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => sorted[n / 2] as f64,
        _ => 0.5 * (sorted[n / 2] as f64 + sorted[n / 2 - 1] as f64),
    }
}

#[cfg(test)]
mod tests {
    use super::{scan_density, MIN_DENSITY};

    /// Three sensors with 3, 3 and 5 reports and a fourth with none: the third holds two more
    /// than the median (3), so two expected false alarms (not 0.25) over its span; the first
    /// two get P_FA of their count (the second's span is 0, so 10⁻³); the fourth, P_FA of one
    /// report over π.
    #[test]
    fn the_excess_over_the_median_sensor_counts_as_false_alarms() {
        let sensor = [0, 0, 0, 1, 1, 1, 2, 2, 2, 2, 2];
        let azimuth = [0.1, 0.2, 0.5, 1.0, 1.0, 1.0, 0.0, 0.1, 0.2, 0.3, 0.4];
        let reports = |rows: &[usize]| -> Vec<(usize, f64, f64)> {
            rows.iter()
                .map(|&m| (sensor[m], azimuth[m], f64::NAN))
                .collect()
        };
        let all: Vec<usize> = (0..sensor.len()).collect();
        let density = scan_density(reports(&all), 4, false, 0.05);
        let expected = [
            0.15 / 0.4,
            0.15 / 1e-3,
            2.0 / 0.4,
            0.05 / std::f64::consts::PI,
        ];
        for (got, want) in density.iter().zip(expected) {
            assert!((got - want).abs() <= 1e-12 * want, "{density:?}");
        }
        // Only the rows asked for count; a sensor without any gets π and P_FA of one report.
        let first_two = scan_density(reports(&[0, 1]), 2, false, 0.0);
        assert!((first_two[0] - 1.0 / 0.1).abs() < 1e-12, "{first_two:?}");
        assert_eq!(first_two[1], MIN_DENSITY);
    }
}
