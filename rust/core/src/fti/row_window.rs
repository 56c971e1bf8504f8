//! Each scan's rows by azimuth, so that detection and classification (module `detection`)
//! compute a state's residual only for the rows that can relate to it.
//!
//! A row relates to a state when its `d² = (Δβ/σβ)² + (Δε/σε)²` is below `g²`, so only rows whose
//! azimuth lies within `g·σβ` of the predicted one can. Detection and classification ask this for
//! every optimum or target against every scan; a residual costs an angle read, its noise, a wrap
//! and a division, and at 5 sensors × 100 targets a scan holds about 290 rows of which a window
//! holds a few (`benches/bench_initiation_stages.py` times the detection stage). The index
//! holds each scan's row positions sorted by azimuth, with a bucket index ([`BucketIndex`],
//! whose window it shares with the gates' [`super::angle_index::Azimuths`]) and the scan's
//! widest azimuth noise; a query visits the rows
//! within `g·σβ,max`, widened by a part in 10⁹ and 10⁻¹² rad so that rounding cannot leave out a
//! row the full scan would relate, in the scan's own row order. Rows outside have `d² ≥ g²`, which
//! every caller treats as unrelated: the answers are those of the full scan, bit for bit.

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

/// Every scan of `scans` with its rows by azimuth (module doc).
pub(super) struct RowWindows<'s> {
    pub(super) scans: &'s Scans,
    by_scan: Vec<ScanRows>,
}

impl<'s> RowWindows<'s> {
    pub(super) fn new(problem: &Problem<'_>, scans: &'s Scans) -> Self {
        let by_scan = (0..scans.len())
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
        Self { scans, by_scan }
    }

    /// The positions in scan `k` of the rows whose azimuth lies within the window of `gate`
    /// (the `g` of `d² < g²`) around `azimuth`, ascending, into `out` (cleared first): every
    /// row when the window reaches π, none when `azimuth` is NaN (every residual would be NaN,
    /// which no caller relates).
    pub(super) fn near(&self, k: usize, azimuth: f64, gate: f64, out: &mut Vec<usize>) {
        let scan = &self.by_scan[k];
        let width = gate * scan.widest * (1.0 + 1e-9) + 1e-12;
        let [main, wrapped] = scan.index.window(&scan.azimuths, azimuth, width);
        out.clear();
        out.extend_from_slice(&scan.positions[main]);
        out.extend_from_slice(&scan.positions[wrapped]);
        out.sort_unstable();
    }
}
