//! Step 1 of the method: a baseline line of sight met by every line of every other sensor,
//! the meetings pruned by attribute support, range, region and (optionally) direction. What
//! survives for sensor k is the subset `A_k` of the paper.

use super::options::FormationOptions;
use crate::data::{Measurements, Sensors};
use crate::evidence::AttributeGate;
use crate::geometry::model::Observation;

/// One report's line of sight.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Line {
    pub row: usize,
    pub origin: [f64; 2],
    /// `[cos θ, sin θ]` of the bearing.
    pub direction: [f64; 2],
    pub observation: Observation,
}

/// Where the baseline line meets line `line` (index within its sensor): the point itself is
/// `along` the baseline from its sensor, which is all the later steps need.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Meeting {
    pub line: u32,
    /// Signed distance from the baseline sensor along the baseline bearing.
    pub along: f64,
    /// `m(assoc)` of the two reports (1 without attributes).
    pub support: f64,
}

/// Why meetings were dropped, summed over baseline reports (identical for any thread count).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PruneCounts {
    /// Baseline-line / other-line pairs examined.
    pub pairs: u64,
    /// Parallel lines: no meeting.
    pub parallel: u64,
    /// Attribute support below η.
    pub low_support: u64,
    /// Beyond `r_max` of either sensor.
    pub out_of_range: u64,
    /// Outside the surveillance region.
    pub outside_region: u64,
    /// Behind one of the two sensors (only with `in_front`).
    pub behind: u64,
    /// Reference points scored (candidate line sets whose radius was computed).
    pub candidates: u64,
}

impl PruneCounts {
    pub(crate) fn add(&mut self, other: &PruneCounts) {
        self.pairs += other.pairs;
        self.parallel += other.parallel;
        self.low_support += other.low_support;
        self.out_of_range += other.out_of_range;
        self.outside_region += other.outside_region;
        self.behind += other.behind;
        self.candidates += other.candidates;
    }
}

/// The scene: lines grouped per sensor in table order, and the gate.
pub(crate) struct Scene<'a> {
    pub lines: Vec<Vec<Line>>,
    pub gate: Option<AttributeGate<'a>>,
    pub options: FormationOptions,
}

impl<'a> Scene<'a> {
    pub fn new(
        sensors: &Sensors<'_>,
        measurements: &Measurements<'_>,
        gate: Option<AttributeGate<'a>>,
        options: FormationOptions,
    ) -> Self {
        let mut lines: Vec<Vec<Line>> = vec![Vec::new(); sensors.len()];
        for row in 0..measurements.len() {
            let s = measurements.sensor(row);
            let observation = measurements.observation(sensors, row);
            let origin = [observation.sensor[0], observation.sensor[1]];
            let (sin, cos) = observation.angles[0].sin_cos();
            lines[s].push(Line {
                row,
                origin,
                direction: [cos, sin],
                observation,
            });
        }
        Self {
            lines,
            gate,
            options,
        }
    }

    pub fn baseline_lines(&self) -> &[Line] {
        &self.lines[self.options.baseline_sensor()]
    }

    /// The subsets `A_k` of baseline line `base` for every sensor (the baseline's own is
    /// empty and never read), with the pruning counts.
    pub fn subsets(&self, base: &Line, counts: &mut PruneCounts) -> Vec<Vec<Meeting>> {
        let baseline = self.options.baseline_sensor();
        (0..self.lines.len())
            .map(|k| match k == baseline {
                true => Vec::new(),
                false => self.lines[k]
                    .iter()
                    .enumerate()
                    .filter_map(|(l, other)| self.meet(base, l, other, counts))
                    .collect(),
            })
            .collect()
    }

    fn meet(
        &self,
        base: &Line,
        l: usize,
        other: &Line,
        counts: &mut PruneCounts,
    ) -> Option<Meeting> {
        counts.pairs += 1;
        let support = match self.gate.map(|g| g.admitted_mass(base.row, other.row)) {
            None => 1.0,
            Some(Some(mass)) => mass,
            Some(None) => {
                counts.low_support += 1;
                return None;
            }
        };
        let Some((point, along, range_other)) = intersect(base, other) else {
            counts.parallel += 1;
            return None;
        };
        let r_max = self.options.r_max();
        if along.abs() > r_max || range_other.abs() > r_max {
            counts.out_of_range += 1;
            return None;
        }
        if self.options.region().is_some_and(|r| !r.contains(&point)) {
            counts.outside_region += 1;
            return None;
        }
        if self.options.in_front() && (along <= 0.0 || range_other <= 0.0) {
            counts.behind += 1;
            return None;
        }
        Some(Meeting {
            line: l as u32,
            along,
            support,
        })
    }
}

/// Where full lines `a` and `b` meet, with the signed ranges along each; `None` if parallel.
/// The ranges are the distances to the two sensors, so `r_max` is tested on them directly.
#[inline]
pub(crate) fn intersect(a: &Line, b: &Line) -> Option<([f64; 2], f64, f64)> {
    let (ua, ub) = (a.direction, b.direction);
    let cross = ua[0] * ub[1] - ua[1] * ub[0];
    if cross.abs() <= 1e-12 {
        return None;
    }
    let w = [b.origin[0] - a.origin[0], b.origin[1] - a.origin[1]];
    let range_a = (w[0] * ub[1] - w[1] * ub[0]) / cross;
    let range_b = (w[0] * ua[1] - w[1] * ua[0]) / cross;
    let point = [a.origin[0] + range_a * ua[0], a.origin[1] + range_a * ua[1]];
    Some((point, range_a, range_b))
}
