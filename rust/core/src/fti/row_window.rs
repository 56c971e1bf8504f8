//! Each scan's rows by azimuth, so that detection and classification (module `detection`)
//! compute a state's residual only for the rows that can relate to it.
//!
//! A row relates to a state when its `d² = (Δβ/σβ)² + (Δε/σε)²` is below `g²`, so only rows
//! whose azimuth lies within `g·σβ` of the predicted one can. Detection and classification ask
//! this for every optimum or target against every scan, and computing every row's residual
//! (an angle read, its noise, a wrap and a division per row) was most of their time. The
//! index holds each scan's row positions sorted by azimuth, with a bucket index
//! ([`BucketIndex`]) and the scan's widest azimuth noise; a query visits the rows within
//! `g·σβ,max`, widened by a part in 10⁹ and 10⁻¹² rad so that rounding cannot leave out a row
//! the full scan would relate, in the scan's own row order. Rows outside have `d² ≥ g²`, which
//! every caller treats as unrelated: the answers are those of the full scan, bit for bit.

use std::f64::consts::PI;

use super::angle_index::BucketIndex;
use super::problem::Problem;
use super::scans::Scans;
use crate::geometry::angles::wrap;

/// One scan's row positions (into [`Scans::scan`]) by azimuth, and the widest azimuth noise.
struct ScanRows {
    positions: Vec<usize>,
    azimuths: Vec<f64>,
    index: BucketIndex,
    widest: f64,
}

/// Every scan's rows by azimuth (module doc).
pub(super) struct RowWindows {
    scans: Vec<ScanRows>,
}

impl RowWindows {
    pub(super) fn new(problem: &Problem<'_>, scans: &Scans) -> Self {
        let scans = (0..scans.len())
            .map(|k| {
                let rows = scans.scan(k);
                let mut by_azimuth: Vec<(f64, usize)> = (rows.iter().enumerate())
                    .map(|(p, &m)| (wrap(problem.measurements.angles(m)[0]), p))
                    .collect();
                by_azimuth.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                let azimuths: Vec<f64> = by_azimuth.iter().map(|e| e.0).collect();
                let widest = (rows.iter())
                    .map(|&m| problem.measurements.sigma(&problem.sensors, m)[0])
                    .fold(0.0, f64::max);
                ScanRows {
                    index: BucketIndex::new(&azimuths),
                    positions: by_azimuth.into_iter().map(|e| e.1).collect(),
                    azimuths,
                    widest,
                }
            })
            .collect();
        Self { scans }
    }

    /// The positions in scan `k` of the rows whose azimuth lies within the window of `gate`
    /// (the `g` of `d² < g²`) around `azimuth`, ascending, into `out` (cleared first); every
    /// row when the window reaches π or `azimuth` is not finite.
    pub(super) fn near(&self, k: usize, azimuth: f64, gate: f64, out: &mut Vec<usize>) {
        out.clear();
        let scan = &self.scans[k];
        let width = gate * scan.widest * (1.0 + 1e-9) + 1e-12;
        if !(azimuth.is_finite() && width < PI) {
            out.extend(0..scan.positions.len());
            return;
        }
        let mut take = |lo: f64, hi: f64| {
            let range = scan.index.between(&scan.azimuths, lo, hi);
            out.extend_from_slice(&scan.positions[range]);
        };
        let (lo, hi) = (azimuth - width, azimuth + width);
        if lo < -PI {
            take(-PI, hi);
            take(lo + 2.0 * PI, PI);
        } else if hi > PI {
            take(lo, PI);
            take(-PI, hi - 2.0 * PI);
        } else {
            take(lo, hi);
        }
        out.sort_unstable();
        out.dedup();
    }
}
