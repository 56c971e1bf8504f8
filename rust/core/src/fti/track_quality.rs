//! The final track test (a project extension; `track_test`): a target's reports fit its track
//! to noise, so a refit χ² far above the χ²(dof) quantile means rows that are not its own.
//!
//! A search with four or six free parameters can thread a dense clutter field (2-D, 10
//! clutter bearings a scan: states related to 15 of 24 scans, above Nd = 14), but the rows
//! it collects are spread over the whole relation gate (χ²/dof 5–7 instead of ≈ 1). A real
//! target's track can also hold a few clutter rows that fell inside its gate. So the test
//! *trims outliers*: while the refit χ² exceeds the quantile, the row with the largest
//! normalised residual becomes clutter and the track is refitted — if that row is an outlier
//! (its own d² beyond the χ²(angles) 99.9 % point). When the worst row is not an outlier the
//! misfit is spread over the rows, as in threaded clutter, and the track is dissolved; so is
//! a track trimmed to Nd rows or fewer (detection's own threshold), and a trimmed track must
//! then pass at a 10⁻⁴ tail (its remaining rows are claimed to be clean). A
//! target with a stray row loses the row; a clutter track cannot shed rows until it fits.

use rayon::prelude::*;

use super::closeness::{closeness, Precomputed};
use super::coverage;
use super::detection::residual2;
use super::output::Track;
use super::problem::Problem;
use super::quantiles::chi2_quantile;
use super::refit::refit;
use super::scans::Scans;
use crate::geometry::model::MAX_DIM;

/// Standard-normal level of an outlier row: χ²(angles) at 1 − 10⁻³ (`−Φ⁻¹(10⁻³)`).
const OUTLIER_Z: f64 = 3.090_232_306_167_813;

/// Standard-normal level a trimmed track must pass: a 10⁻⁴ tail (`−Φ⁻¹(10⁻⁴)`). Its
/// comparison with 10⁻³, 10⁻⁵ and 10⁻⁶ is in CHANGELOG.md (*Missed detections and clutter*).
const TRIMMED_Z: f64 = 3.719_016_485_455_709;

/// The tracks that pass at standard-normal level `z` (all when `None`; trimmed, then the coverage test of module `coverage`),
/// relabelled, each with its closeness R (module `refit` leaves it to here); every other row
/// is clutter.
pub(super) fn tested(
    problem: &Problem<'_>,
    pre: &Precomputed,
    scans: &Scans,
    tracks: Vec<Track>,
    n_rows: usize,
    n_detect: usize,
    z: Option<f64>,
) -> (Vec<Track>, Vec<i64>) {
    let mut kept: Vec<Track> = match z {
        None => tracks,
        Some(z) => {
            // In parallel, in order: each track is trimmed and refitted on its own.
            let trimmed = (tracks.into_par_iter())
                .filter_map(|t| trimmed(problem, t, n_detect, z))
                .collect();
            coverage::covered(problem, scans, trimmed)
        }
    };
    kept.par_iter_mut()
        .for_each(|t| t.closeness = closeness(pre, &t.estimate));
    let mut labels = vec![-1i64; n_rows];
    for (k, track) in kept.iter().enumerate() {
        for &m in &track.measurements {
            labels[m] = k as i64;
        }
    }
    (kept, labels)
}

/// `track` with its worst rows removed until its χ² passes, or `None` when that leaves it
/// Nd rows or fewer (or its refit fails).
pub(super) fn trimmed(
    problem: &Problem<'_>,
    mut track: Track,
    n_detect: usize,
    z: f64,
) -> Option<Track> {
    // Once a row is trimmed, the rest is claimed to be the target's alone: it must then fit
    // at an ordinary level (TRIMMED_Z), not merely below the outlying 1e-6 tail.
    let mut level = z;
    while !passes(problem, &track, level) {
        if track.measurements.len() <= n_detect + 1 {
            return None;
        }
        let x = &track.estimate;
        let d2: Vec<f64> = (track.measurements.iter())
            .map(|&m| residual2(problem, x, m))
            .collect();
        let worst = (0..d2.len()).max_by(|&i, &j| d2[i].total_cmp(&d2[j]))?;
        let angles = problem.layout.space.angles() as f64;
        if d2[worst].is_nan() || d2[worst] <= chi2_quantile(angles, OUTLIER_Z) {
            return None; // no outlier to blame: the whole track misfits
        }
        let mut rows = track.measurements.clone();
        rows.remove(worst);
        let mut start = [0.0; MAX_DIM];
        start[..x.len()].copy_from_slice(x);
        track = refit(problem, &start, &rows)?;
        level = level.min(TRIMMED_Z);
    }
    Some(track)
}

/// Whether a track's χ² is plausible for its degrees of freedom (angles − state dimension).
fn passes(problem: &Problem<'_>, track: &Track, z: f64) -> bool {
    let angles = track.measurements.len() * problem.layout.space.angles();
    let dof = angles.saturating_sub(problem.layout.dim());
    dof == 0 || track.chi2 <= chi2_quantile(dof as f64, z)
}

#[cfg(test)]
mod tests {
    use super::trimmed;
    use crate::fti::options::TRACK_TEST;
    use crate::fti::quantiles::upper_normal_level;
    use crate::fti::refit::refit;
    use crate::fti::tests::sim;
    use crate::geometry::model::MAX_DIM;

    #[test]
    fn a_stray_row_is_trimmed_and_a_mixed_track_dissolved() {
        let sc = sim::paper(11, true, 0, 8);
        let sensors = sc.sensors();
        let table = sc.measurements(&sensors);
        let problem = sim::problem(sensors, table);
        let truth = &sc.truth;
        let rows_of =
            |i: i64| -> Vec<usize> { (0..truth.len()).filter(|&m| truth[m] == i).collect() };
        let mut start = [0.0; MAX_DIM];
        start[..6].copy_from_slice(&sc.targets[2]);
        // Target 2's 16 rows and one of target 0's.
        let stray = rows_of(0)[0];
        let mut rows: Vec<usize> = rows_of(2).into_iter().chain([stray]).collect();
        rows.sort_unstable();
        let track = refit(&problem, &start, &rows).expect("fits");
        let kept = trimmed(&problem, track, 9, upper_normal_level(TRACK_TEST)).expect("kept");
        assert_eq!(kept.measurements, rows_of(2));
        // Half of target 2's rows and half of target 3's: no single outlier to blame.
        let (two, three) = (rows_of(2), rows_of(3));
        let halves = two.iter().step_by(2).chain(three.iter().skip(1).step_by(2));
        let mut mixed: Vec<usize> = halves.copied().collect();
        mixed.sort_unstable();
        let track = refit(&problem, &start, &mixed).expect("fits");
        assert!(trimmed(&problem, track, 9, upper_normal_level(TRACK_TEST)).is_none());
    }
}
