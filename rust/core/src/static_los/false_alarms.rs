//! The default false-alarm density of a scan (a project extension, documented in
//! docs/methods.md §2): false alarms per radian (per rad² with elevations) for each sensor, when
//! the caller gives none.
//!
//! A sensor's expected false alarms are `p_false` of its reports (the paper's P_FA = 0.05), or
//! its excess over the median sensor's report count when that is larger: all sensors see the
//! same targets, so reports beyond the median sensor's are false alarms (or the others'
//! misses). They are spread over the azimuth (× elevation) span of the sensor's reports; a
//! sensor without reports gets π. The density is at least 10⁻¹².
//!
//! Tiny scans: a span is at least 10⁻³ rad and at least the width of the default gate on the
//! sensor's angle, 2 × 2.576 σ ([`DEFAULT_GATE_SIGMAS`]), capped at 2π. One report per sensor
//! spans nothing: with the 10⁻³ rad floor alone its density was 50 per radian, above the
//! likelihood of a perfect report at σ = 10 mrad (40 per radian), and eq. 2 called a lone
//! noiseless target clutter. Reports closer together than a gate's width cannot tell how far
//! false alarms spread; with the gate's width, a report at its target's bearing always beats
//! a false alarm (by `Pd · 2 · 2.576 / (P_FA · √(2π))` ≈ 39 Pd per sensor). Wider scans are
//! unchanged.
//!
//! It is computed here, not in NumPy, because the per-call overhead of ten array operations
//! (about 20 µs) would be a quarter of a tiny scan's time. The arithmetic is the NumPy
//! expressions', operation for operation, so the densities are the same to the bit (a pytest
//! compares them with those expressions).

use super::options::DEFAULT_GATE_SIGMAS;
use crate::data::{Measurements, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::geometry::model::Space;

/// The paper's probability that a report is a false alarm: the default `p_false`.
pub const DEFAULT_P_FALSE: f64 = 0.05;

/// Narrowest angular span a sensor's reports are taken to cover (rad), whatever its σ.
pub const MIN_SPAN: f64 = 1e-3;

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

    /// The sector the reports span, each side at least its `floor`: π for a sensor without
    /// reports.
    fn area(&self, with_elevation: bool, floor: [f64; 2]) -> f64 {
        if self.count == 0 {
            return std::f64::consts::PI;
        }
        let width = (self.azimuth[1] - self.azimuth[0]).max(floor[0]);
        if with_elevation {
            width * (self.elevation[1] - self.elevation[0]).max(floor[1])
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

/// The narrowest span of each sensor's reports, `[azimuth, elevation]`: [`MIN_SPAN`], and the
/// width of the default gate on its angles, `2 · DEFAULT_GATE_SIGMAS · σ` (at most 2π).
pub fn min_spans(sensors: &Sensors<'_>) -> Vec<[f64; 2]> {
    (0..sensors.len())
        .map(|j| sensors.sigma(j).map(gate_width))
        .collect()
}

/// The width of the default gate on an angle of std `sigma`, at least [`MIN_SPAN`].
pub fn gate_width(sigma: f64) -> f64 {
    (2.0 * DEFAULT_GATE_SIGMAS * sigma).clamp(MIN_SPAN, std::f64::consts::TAU)
}

/// The default density of each sensor from one scan's `reports`, each `(sensor, azimuth,
/// elevation)`; the elevations are read only `with_elevation`. `floors` holds each sensor's
/// narrowest span ([`min_spans`]), one per sensor `0..floors.len()`; reports of other sensors
/// are not counted.
pub fn scan_density(
    reports: impl IntoIterator<Item = (usize, f64, f64)>,
    floors: &[[f64; 2]],
    with_elevation: bool,
    p_false: f64,
) -> Vec<f64> {
    let n_sensors = floors.len();
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
        .zip(floors)
        .map(|(e, &floor)| {
            let base = p_false * e.count.max(1) as f64;
            let excess = e.count as f64 - median;
            (base.max(excess) / e.area(with_elevation, floor)).max(MIN_DENSITY)
        })
        .collect()
}

/// The default density of `table`'s `rows` (one scan), for every sensor of `sensors`.
pub fn table_density(
    table: &Measurements<'_>,
    rows: impl IntoIterator<Item = usize>,
    sensors: &Sensors<'_>,
) -> Vec<f64> {
    let reports = rows.into_iter().map(|m| {
        let [azimuth, elevation] = table.angles(m);
        (table.sensor(m), azimuth, elevation)
    });
    let spatial = sensors.space() == Space::Spatial;
    scan_density(reports, &min_spans(sensors), spatial, DEFAULT_P_FALSE)
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
    use super::{gate_width, scan_density, MIN_DENSITY, MIN_SPAN};

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
        let density = scan_density(reports(&all), &[[MIN_SPAN; 2]; 4], false, 0.05);
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
        let first_two = scan_density(reports(&[0, 1]), &[[MIN_SPAN; 2]; 2], false, 0.0);
        assert!((first_two[0] - 1.0 / 0.1).abs() < 1e-12, "{first_two:?}");
        assert_eq!(first_two[1], MIN_DENSITY);
    }

    /// One report per sensor spans nothing: the span is the default gate's width on the
    /// sensor's angle (at least 10⁻³ rad), so a lone report's density is P_FA over that width.
    #[test]
    fn a_lone_report_spreads_its_false_alarms_over_a_gate_width() {
        let floors = [[gate_width(1e-2), 1.0], [gate_width(1e-5), 1.0]];
        let density = scan_density([(0, 0.3, 0.0), (1, 1.2, 0.0)], &floors, false, 0.05);
        let width = 2.0 * 2.5758293035489004 * 1e-2;
        assert!((density[0] - 0.05 / width).abs() <= 1e-12 * density[0]);
        assert_eq!(density[1], 0.05 / MIN_SPAN);
        assert_eq!(gate_width(3.0), std::f64::consts::TAU);
    }
}
