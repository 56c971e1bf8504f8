//! Joining a target split between two tracks (a project extension).
//!
//! Why: two nearby optima can both pass detection on one target's rows, each filling the scans
//! the other took with clutter, and the final classification then shares the target's rows
//! between two tracks (two targets of the 8-target 2-D scene of
//! `benches/bench_initiation_2d.py` without the join; docs/methods.md §1).
//! Each half fits its own rows well, so no test on the halves can see it.
//!
//! How: two tracks whose predicted angles come within the gate of each other in some scan
//! (they compete for rows there) are tried as one: the rows of both, one per scan (the nearer
//! to the larger track's state), refitted and put through the track test with its outlier
//! trimming. They are joined when the joined track passes, keeps more rows than the larger
//! of the two, and keeps at least half of each one's rows. Two distinct targets cannot pass:
//! one constant-velocity state does not fit both, and trimming one's rows away leaves less
//! than half of them. Two targets flying together that the sensors cannot tell apart may,
//! but then the joined track keeps at most one row per scan, no more than either had.
//! A track takes part in at most one join per call.

use rayon::prelude::*;

use super::detection::residual2;
use super::output::Track;
use super::problem::Problem;
use super::refit::{padded, refit};
use super::scans::Scans;
use super::track_quality::trimmed;
use crate::geometry::angles::wrap;
use crate::geometry::model::{predict, MAX_DIM};

/// The states after joining, in track order (a joined pair in the first one's place), or
/// `None` when no pair joins.
pub(super) fn joined(
    problem: &Problem<'_>,
    scans: &Scans,
    tracks: &[Track],
    n_detect: usize,
    gate: f64,
    z: f64,
) -> Option<Vec<[f64; MAX_DIM]>> {
    let mut states: Vec<Option<[f64; MAX_DIM]>> =
        tracks.iter().map(|t| Some(padded(&t.estimate))).collect();
    // A join of two tracks depends on those two alone, so every competing pair is tried at
    // once, in parallel; the pairs are then taken in order, each track in one join at most,
    // as a loop that tried them one by one would take them.
    let competing = competing(problem, scans, tracks, gate);
    let tried: Vec<Option<Track>> = competing
        .par_iter()
        .map(|&(a, b)| try_join(problem, scans, &tracks[a], &tracks[b], n_detect, z))
        .collect();
    let mut used = vec![false; tracks.len()];
    for (&(a, b), join) in competing.iter().zip(tried) {
        let Some(join) = join.filter(|_| !used[a] && !used[b]) else {
            continue;
        };
        (states[a], states[b]) = (Some(padded(&join.estimate)), None);
        (used[a], used[b]) = (true, true);
    }
    used.contains(&true)
        .then(|| states.into_iter().flatten().collect())
}

/// The pairs `(a, b)`, `a < b`, of `tracks` that compete for rows: their predicted angles
/// come within the `gate` (σ) of each other, in every angle, in some scan.
pub(super) fn competing(
    problem: &Problem<'_>,
    scans: &Scans,
    tracks: &[Track],
    gate: f64,
) -> Vec<(usize, usize)> {
    let predicted: Vec<Vec<[f64; 2]>> = tracks
        .iter()
        .map(|t| predictions(problem, scans, t))
        .collect();
    // Each scan's width once, not once per pair of tracks (the pairs are many at 100 targets).
    let widths: Vec<[f64; 2]> = (0..scans.len())
        .map(|k| problem.scan_sigma(scans.scan(k)).map(|s| gate * s))
        .collect();
    (0..tracks.len())
        .flat_map(|a| (a + 1..tracks.len()).map(move |b| (a, b)))
        .filter(|&(a, b)| compete(problem, &widths, &predicted[a], &predicted[b]))
        .collect()
}

/// A track's predicted angles in every scan (once per track, not once per pair).
fn predictions(problem: &Problem<'_>, scans: &Scans, t: &Track) -> Vec<[f64; 2]> {
    let layout = &problem.layout;
    (0..scans.len())
        .map(|k| {
            let probe = problem.observation(scans.scan(k)[0]);
            predict(
                layout.space,
                &probe.sensor,
                &layout.position(&t.estimate, probe.time),
            )
        })
        .collect()
}

/// Whether two tracks' predicted angles (`ha`, `hb`, per scan) come within each scan's
/// `widths` (the gate times its σ) of each other, in every angle, in some scan.
fn compete(problem: &Problem<'_>, widths: &[[f64; 2]], ha: &[[f64; 2]], hb: &[[f64; 2]]) -> bool {
    let angles = problem.layout.space.angles();
    (widths.iter().enumerate())
        .any(|(k, w)| (0..angles).all(|c| wrap(ha[k][c] - hb[k][c]).abs() <= w[c]))
}

/// The joined track of `a` and `b` if it passes the track test with more rows than either.
fn try_join(
    problem: &Problem<'_>,
    scans: &Scans,
    a: &Track,
    b: &Track,
    n_detect: usize,
    z: f64,
) -> Option<Track> {
    let larger = if b.measurements.len() > a.measurements.len() {
        b
    } else {
        a
    };
    let x = &larger.estimate;
    // One row per scan: the nearer to the larger track's state.
    let mut keyed: Vec<(usize, f64, usize)> = (a.measurements.iter().chain(&b.measurements))
        .map(|&m| (scans.scan_of[m], residual2(problem, x, m), m))
        .collect();
    keyed.sort_by(|p, q| p.0.cmp(&q.0).then(p.1.total_cmp(&q.1)).then(p.2.cmp(&q.2)));
    keyed.dedup_by_key(|k| k.0);
    let mut rows: Vec<usize> = keyed.into_iter().map(|k| k.2).collect();
    rows.sort_unstable();
    let most = a.measurements.len().max(b.measurements.len());
    if rows.len() <= most {
        return None;
    }
    let joined = refit(problem, &padded(x), &rows)?;
    let kept = trimmed(problem, joined, n_detect, z)?;
    // It must explain both halves: at least half of each track's rows survive the test.
    let share = |t: &Track| {
        let held = t.measurements.iter();
        held.filter(|m| kept.measurements.binary_search(m).is_ok())
            .count()
    };
    let explains = |t: &Track| 2 * share(t) >= t.measurements.len();
    (kept.measurements.len() > most && explains(a) && explains(b)).then_some(kept)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fti::options::TRACK_TEST;
    use crate::fti::quantiles::upper_normal_level;
    use crate::fti::refit::refit_rows;
    use crate::fti::tests::sim;

    /// One target's rows shared between two tracks (even and odd scans)
    /// are joined; two targets' own tracks are not.
    #[test]
    fn a_split_target_is_joined_and_two_targets_are_not() {
        let sc = sim::paper(5, true, 0, 8);
        let sensors = sc.sensors();
        let table = sc.measurements(&sensors);
        let problem = sim::problem(sensors, table);
        let scans = Scans::new(&table, sensors.len());
        let rows_of = |i: i64| sc.rows_of(i);
        let track = |target: usize, rows: &[usize]| {
            refit_rows(&problem, &sc.targets[target], rows.to_vec())
        };
        let own = rows_of(2);
        let (even, odd): (Vec<usize>, Vec<usize>) =
            own.iter().partition(|&&m| scans.scan_of[m] % 2 == 0);
        let halves = [track(2, &even), track(2, &odd)];
        let (n_detect, gate) = (4, 5.0);
        let states = joined(
            &problem,
            &scans,
            &halves,
            n_detect,
            gate,
            upper_normal_level(TRACK_TEST),
        )
        .expect("the halves join");
        assert_eq!(states.len(), 1);
        let err: f64 = (0..3)
            .map(|k| (states[0][k] - sc.targets[2][k]).powi(2))
            .sum();
        assert!(err.sqrt() < 500.0, "{:?}", &states[0][..6]);
        let targets = [track(0, &rows_of(0)), track(2, &own)];
        let apart = joined(
            &problem,
            &scans,
            &targets,
            n_detect,
            1e9,
            upper_normal_level(TRACK_TEST),
        );
        assert!(apart.is_none(), "two targets were joined");
    }
}
