//! The coverage test (a project extension, part of the track test): a track must be seen in
//! about as large a share of its sensors' scans as the typical track of the scene.
//!
//! Why: detection's threshold Nd is a count, and where clutter is dense a count is weak
//! evidence. In the 2-D scenes of `benches/bench_initiation_2d.py` (8 targets and 16 clutter
//! bearings a scan and sensor, over half a turn) about every other relation gate holds a row
//! by chance, and the search threads constant-velocity lines through the clutter that
//! collect 15 or 16 of the 24 scans (above Nd = 14, with residuals that pass the χ² test),
//! where a target is seen in nearly every scan. Comparing a track's count with the chance of
//! clutter in its gate does not separate the two: the threaded lines are the best of millions
//! of tries, and targets crowd the same sector (docs/methods.md §1, *Coverage test*).
//!
//! How: a track's coverage is its scans over the scans of the sensors that contribute any of
//! its rows (a target outside one sensor's view is not penalised for it). The detection
//! probability is estimated as the tracks' median coverage (the upper median for an even
//! count), capped at 1 − 1/N for the table's N scans so that a scene of complete tracks
//! does not claim certainty. A track is dissolved when its count is improbable under that
//! probability: `P(Binomial(n, Pd) ≤ seen) < LEVEL`. With fewer than [`MIN_TRACKS`]
//! tracks a median says little, and the test does not run. It assumes the targets share one
//! detection probability and are present over the whole window, as the candidates do (they
//! come from each sensor's outermost scans).

use super::output::Track;
use super::problem::Problem;
use super::scans::Scans;

/// Lower-tail probability below which a track's count is too low to be a target's.
const LEVEL: f64 = 1e-4;

/// Tracks needed before their median coverage is taken as the detection probability.
const MIN_TRACKS: usize = 3;

/// The tracks whose coverage passes (module doc), in order.
pub(super) fn covered(problem: &Problem<'_>, scans: &Scans, tracks: Vec<Track>) -> Vec<Track> {
    if tracks.len() < MIN_TRACKS {
        return tracks;
    }
    let coverage: Vec<(usize, usize)> = tracks.iter().map(|t| seen_of(problem, scans, t)).collect();
    let mut shares: Vec<f64> = coverage
        .iter()
        .map(|&(seen, of)| seen as f64 / of as f64)
        .collect();
    shares.sort_by(f64::total_cmp);
    let pd = shares[shares.len() / 2].min(1.0 - 1.0 / scans.len() as f64);
    tracks
        .into_iter()
        .zip(coverage)
        .filter(|&(_, (seen, of))| at_most(of, pd, seen) >= LEVEL)
        .map(|(t, _)| t)
        .collect()
}

/// The scans holding a row of `track`, and the scans of the sensors it has rows from.
fn seen_of(problem: &Problem<'_>, scans: &Scans, track: &Track) -> (usize, usize) {
    let mut own: Vec<usize> = track
        .measurements
        .iter()
        .map(|&m| scans.scan_of[m])
        .collect();
    own.sort_unstable();
    own.dedup();
    let mut sensors = vec![false; problem.sensors.len()];
    for &m in &track.measurements {
        sensors[problem.measurements.sensor(m)] = true;
    }
    let possible = (0..scans.len())
        .filter(|&k| sensors[problem.measurements.sensor(scans.scan(k)[0])])
        .count();
    (own.len(), possible)
}

/// `P(X ≤ k)` for `X ~ Binomial(n, p)` with `0 ≤ p < 1`, by the ratio of successive terms.
fn at_most(n: usize, p: f64, k: usize) -> f64 {
    let ratio = p / (1.0 - p);
    let mut term = (1.0 - p).powf(n as f64); // P(X = 0)
    let mut total = 0.0;
    for i in 0..=k.min(n) {
        total += term;
        term *= (n - i) as f64 / (i + 1) as f64 * ratio;
    }
    total.min(1.0)
}

#[cfg(test)]
mod tests {
    use super::{at_most, covered};
    use crate::fti::refit::refit;
    use crate::fti::scans::Scans;
    use crate::fti::tests::sim;
    use crate::geometry::model::MAX_DIM;

    /// Two 2-D targets, three sensors, 8 scans: each target's rows, one target's rows from two
    /// sensors only (out of the third's view), and every other scan of one target (a track
    /// seen in half its scans, as a thread of clutter is).
    #[test]
    fn a_half_seen_track_is_dissolved_and_one_out_of_a_sensors_view_kept() {
        let sc = sim::planar(3, true, 0, 8);
        let sensors = sc.sensors();
        let table = sc.measurements(&sensors);
        let problem = sim::problem(sensors, table);
        let scans = Scans::new(&table, sensors.len());
        let rows_of = |i: i64, keep: &dyn Fn(usize) -> bool| -> Vec<usize> {
            (0..sc.truth.len())
                .filter(|&m| sc.truth[m] == i && keep(m))
                .collect()
        };
        let fit = |i: usize, rows: Vec<usize>| {
            let mut start = [0.0; MAX_DIM];
            start[..4].copy_from_slice(&sc.targets[i]);
            refit(&problem, &start, &rows).expect("fits")
        };
        let two_sensors = |m: usize| table.sensor(m) < 2;
        let alternate = |m: usize| scans.scan_of[m] % 2 == 0;
        let tracks = vec![
            fit(0, rows_of(0, &|_| true)),
            fit(1, rows_of(1, &|_| true)),
            fit(1, rows_of(1, &two_sensors)),
            fit(0, rows_of(0, &alternate)),
        ];
        assert_eq!(tracks[3].measurements.len(), 12);
        let kept = covered(&problem, &scans, tracks.clone());
        // The same tracks, by their rows (a refit leaves R unset: NaN, never equal to itself).
        let rows = |t: &[crate::fti::output::Track]| {
            t.iter().map(|t| t.measurements.clone()).collect::<Vec<_>>()
        };
        assert_eq!(rows(&kept), rows(&tracks[..3]));
        // Fewer than three tracks: no median to trust, nothing dissolved.
        assert_eq!(covered(&problem, &scans, tracks[2..].to_vec()).len(), 2);
    }

    #[test]
    fn the_binomial_tail_matches_closed_forms() {
        // Binomial(4, 1/2): P(X ≤ 1) = 5/16; every count: 1.
        assert!((at_most(4, 0.5, 1) - 5.0 / 16.0).abs() < 1e-15);
        assert!((at_most(4, 0.5, 4) - 1.0).abs() < 1e-15);
        // Binomial(24, 0.9): P(X ≤ 15) = 3.2127e-4 (scipy.stats.binom.cdf(15, 24, 0.9)).
        assert!((at_most(24, 0.9, 15) - 3.2127e-4).abs() < 1e-8);
        assert_eq!(at_most(5, 0.0, 0), 1.0);
    }
}
