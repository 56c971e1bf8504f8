//! Steps 2–4 of the method for one baseline report: pick the reference subset, complete each
//! reference point with the nearest point of every other subset, and keep the line set whose
//! intersections cluster tightest.

use super::options::{ClusterRadius, Reference};
use super::subsets::{intersect, Line, Meeting, PruneCounts, Scene};

/// The line set chosen for one baseline report.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Choice {
    /// Per sensor, the index (within that sensor's lines) of the chosen line; the baseline
    /// sensor holds the baseline line's own index.
    pub lines: Vec<u32>,
    /// Per sensor, `m(assoc)` with the baseline report (NaN at the baseline).
    pub support: Vec<f64>,
    pub radius: f64,
}

impl Scene<'_> {
    /// The smallest-radius line set for baseline line `base_index`, with the lines `used`
    /// (indexed by table row; `None` = nothing excluded) left out, or `None` when a sensor's
    /// subset is empty. Ties keep the first reference point in its subset's order.
    pub fn choose(
        &self,
        base_index: usize,
        subsets: &[Vec<Meeting>],
        used: Option<&[bool]>,
        counts: &mut PruneCounts,
    ) -> Option<Choice> {
        let baseline = self.options.baseline_sensor();
        let free: Vec<Vec<Meeting>>;
        let subsets = match used {
            None => subsets,
            Some(used) => {
                free = self.without_used(subsets, used);
                &free
            }
        };
        let others = || (0..self.lines.len()).filter(move |&k| k != baseline);
        if others().any(|k| subsets[k].is_empty()) {
            return None;
        }
        let reference = match self.options.reference() {
            Reference::Sensor(r) => r,
            Reference::Smallest => others().min_by_key(|&k| (subsets[k].len(), k))?,
        };
        // The reference subset is scanned, never searched: only the others are sorted.
        let by_along: Vec<ByAlong> = (0..subsets.len())
            .map(|k| match k == reference || k == baseline {
                true => ByAlong(Vec::new()),
                false => ByAlong::new(&subsets[k]),
            })
            .collect();
        let mut picks = vec![0usize; self.lines.len()];
        let complete = |r: usize, picks: &mut [usize]| {
            let along = subsets[reference][r].along;
            for k in others() {
                picks[k] = if k == reference {
                    r
                } else {
                    by_along[k].nearest(along)
                };
            }
        };
        let mut best: Option<(f64, usize)> = None;
        for r in 0..subsets[reference].len() {
            complete(r, &mut picks);
            counts.candidates += 1;
            let radius = self.radius(base_index, subsets, &picks);
            if best.is_none_or(|(b, _)| radius < b) {
                best = Some((radius, r));
            }
        }
        let (radius, r) = best?;
        complete(r, &mut picks);
        let mut lines = vec![base_index as u32; self.lines.len()];
        let mut support = vec![f64::NAN; self.lines.len()];
        for k in others() {
            let meeting = &subsets[k][picks[k]];
            lines[k] = meeting.line;
            support[k] = meeting.support;
        }
        Some(Choice {
            lines,
            support,
            radius,
        })
    }

    fn without_used(&self, subsets: &[Vec<Meeting>], used: &[bool]) -> Vec<Vec<Meeting>> {
        subsets
            .iter()
            .enumerate()
            .map(|(k, subset)| {
                let lines = &self.lines[k];
                subset
                    .iter()
                    .filter(|m| !used[lines[m.line as usize].row])
                    .copied()
                    .collect()
            })
            .collect()
    }

    /// Eq. 6 for the lines `picks` (meeting index per non-baseline sensor).
    fn radius(&self, base_index: usize, subsets: &[Vec<Meeting>], picks: &[usize]) -> f64 {
        let baseline = self.options.baseline_sensor();
        match self.options.cluster_radius() {
            ClusterRadius::AlongBaseline => {
                let along = (0..self.lines.len())
                    .filter(|&k| k != baseline)
                    .map(|k| subsets[k][picks[k]].along);
                spread_1d(along)
            }
            ClusterRadius::Planar => {
                let line_of = |k: usize| -> &Line {
                    match k == baseline {
                        true => &self.lines[k][base_index],
                        false => &self.lines[k][subsets[k][picks[k]].line as usize],
                    }
                };
                let n = self.lines.len();
                let points = (0..n).flat_map(|a| {
                    (a + 1..n).filter_map(move |b| intersect(line_of(a), line_of(b)).map(|m| m.0))
                });
                spread_2d(points)
            }
        }
    }
}

/// One subset's meetings sorted by their position along the baseline line. Every meeting
/// lies on that line, so the nearest point (step 3, Euclidean) is the nearest along it: a
/// binary search instead of a scan of the subset for every reference point.
struct ByAlong(Vec<(f64, u32)>);

impl ByAlong {
    fn new(subset: &[Meeting]) -> Self {
        let mut sorted: Vec<(f64, u32)> = subset
            .iter()
            .enumerate()
            .map(|(i, m)| (m.along, i as u32))
            .collect();
        sorted.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        Self(sorted)
    }

    /// Index (in subset order) of the meeting nearest to `along`; of equals, the first in
    /// subset order. The subset is non-empty.
    fn nearest(&self, along: f64) -> usize {
        let sorted = &self.0;
        let first_of_run = |value: f64| sorted.partition_point(|e| e.0 < value);
        let pos = first_of_run(along);
        let right = sorted.get(pos).map(|e| (e.0 - along, e.1));
        let left = pos
            .checked_sub(1)
            .map(|p| sorted[first_of_run(sorted[p].0)])
            .map(|e| (along - e.0, e.1));
        let best = match (left, right) {
            (Some(l), Some(r)) if l.0 < r.0 || (l.0 == r.0 && l.1 < r.1) => l,
            (_, Some(r)) => r,
            (Some(l), None) => l,
            (None, None) => (0.0, 0),
        };
        best.1 as usize
    }
}

/// `sqrt(Σ|P − P̄|² / n)` over the points (infinite when there are none: never the best).
fn spread_2d(points: impl Iterator<Item = [f64; 2]>) -> f64 {
    let mut buffer = [[0.0; 2]; 64];
    let mut spill = Vec::new();
    let mut n = 0;
    for p in points {
        match buffer.get_mut(n) {
            Some(slot) => *slot = p,
            None => spill.push(p),
        }
        n += 1;
    }
    if n == 0 {
        return f64::INFINITY;
    }
    let all = || buffer.iter().take(n).chain(spill.iter());
    let mean = all().fold([0.0; 2], |m, p| [m[0] + p[0], m[1] + p[1]]);
    let mean = [mean[0] / n as f64, mean[1] / n as f64];
    let sum: f64 = all()
        .map(|p| (p[0] - mean[0]).powi(2) + (p[1] - mean[1]).powi(2))
        .sum();
    (sum / n as f64).sqrt()
}

fn spread_1d(values: impl Iterator<Item = f64> + Clone) -> f64 {
    let n = values.clone().count();
    if n == 0 {
        return f64::INFINITY;
    }
    let mean = values.clone().sum::<f64>() / n as f64;
    (values.map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64).sqrt()
}
