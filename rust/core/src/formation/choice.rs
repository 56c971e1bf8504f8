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
        let baseline = self.options.baseline();
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
        let mut best: Option<(f64, Vec<usize>)> = None;
        let mut picks = vec![0usize; self.lines.len()];
        for (r, point) in subsets[reference].iter().enumerate() {
            for k in others() {
                picks[k] = if k == reference {
                    r
                } else {
                    nearest(&subsets[k], &point.point)
                };
            }
            counts.candidates += 1;
            let radius = self.radius(base_index, subsets, &picks);
            if best.as_ref().is_none_or(|(b, _)| radius < *b) {
                best = Some((radius, picks.clone()));
            }
        }
        let (radius, picks) = best?;
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
        let baseline = self.options.baseline();
        match self.options.radius() {
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

/// Index of the meeting nearest to `point` (first of equals). `subset` is non-empty.
fn nearest(subset: &[Meeting], point: &[f64; 2]) -> usize {
    let mut best = (f64::INFINITY, 0);
    for (i, m) in subset.iter().enumerate() {
        let d2 = (m.point[0] - point[0]).powi(2) + (m.point[1] - point[1]).powi(2);
        if d2 < best.0 {
            best = (d2, i);
        }
    }
    best.1
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
