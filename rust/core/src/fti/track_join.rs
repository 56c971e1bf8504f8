//! Joining a target split between two tracks (a project extension).
//!
//! Why: two nearby optima can both pass detection on one target's rows, each filling the scans
//! the other took with clutter, and the final classification then shares the target's rows
//! between two tracks (two targets of issue 16's 8-target 2-D scene, docs/methods.md §1).
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

use super::closeness::Precomputed;
use super::detection::residual2;
use super::pipeline::{padded, refit};
use super::scans::Scans;
use super::track_test::trimmed;
use super::{Problem, Track};
use crate::geometry::angles::wrap;
use crate::geometry::model::{predict, MAX_DIM};

/// The states after joining, in track order (a joined pair in the first one's place), or
/// `None` when no pair joins.
pub(super) fn joined(
    problem: &Problem<'_>,
    pre: &Precomputed,
    scans: &Scans,
    tracks: &[Track],
    n_detect: usize,
    gate: f64,
    z: f64,
) -> Option<Vec<[f64; MAX_DIM]>> {
    let mut states: Vec<Option<[f64; MAX_DIM]>> =
        tracks.iter().map(|t| Some(padded(&t.estimate))).collect();
    let mut used = vec![false; tracks.len()];
    for a in 0..tracks.len() {
        for b in a + 1..tracks.len() {
            if used[a] || used[b] || !compete(problem, scans, &tracks[a], &tracks[b], gate) {
                continue;
            }
            let Some(join) = try_join(problem, pre, scans, &tracks[a], &tracks[b], n_detect, z)
            else {
                continue;
            };
            (states[a], states[b]) = (Some(padded(&join.estimate)), None);
            (used[a], used[b]) = (true, true);
        }
    }
    used.contains(&true)
        .then(|| states.into_iter().flatten().collect())
}

/// Whether the two tracks' predicted angles come within `gate` σ of each other, in every
/// angle, in some scan.
fn compete(problem: &Problem<'_>, scans: &Scans, a: &Track, b: &Track, gate: f64) -> bool {
    let layout = &problem.layout;
    (0..scans.len()).any(|k| {
        let probe = problem.observation(scans.scan(k)[0]);
        let [ha, hb] = [a, b].map(|t| {
            let target = layout.position(&t.estimate, probe.time);
            predict(layout.space, &probe.sensor, &target)
        });
        (0..layout.space.angles()).all(|c| wrap(ha[c] - hb[c]).abs() <= gate * probe.sigma[c])
    })
}

/// The joined track of `a` and `b` if it passes the track test with more rows than either.
fn try_join(
    problem: &Problem<'_>,
    pre: &Precomputed,
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
    let mut rows: Vec<usize> = a
        .measurements
        .iter()
        .chain(&b.measurements)
        .copied()
        .collect();
    rows.sort_by(|&p, &q| {
        let key = |m: usize| (scans.scan_of[m], residual2(problem, x, m));
        let ((sp, dp), (sq, dq)) = (key(p), key(q));
        sp.cmp(&sq).then(dp.total_cmp(&dq)).then(p.cmp(&q))
    });
    rows.dedup_by_key(|m| scans.scan_of[*m]);
    rows.sort_unstable();
    let most = a.measurements.len().max(b.measurements.len());
    if rows.len() <= most {
        return None;
    }
    let joined = refit(problem, pre, &padded(x), &rows)?;
    let kept = trimmed(problem, pre, joined, n_detect, z)?;
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
    use crate::fti::sim;
    use crate::fti::TRACK_TEST_Z;

    /// One target's rows shared between two tracks (alternate scans, one stray row each)
    /// are joined; two targets' own tracks are not.
    #[test]
    fn a_split_target_is_joined_and_two_targets_are_not() {
        let sc = sim::paper(5, true, 0, 8);
        let sensors = sc.sensors();
        let table = sc.measurements(&sensors);
        let problem = sim::spatial_problem(sensors, table);
        let pre = Precomputed::new(&sensors, &table, &sc.spreads(), 0.0).expect("valid");
        let scans = Scans::new(&table, sensors.len());
        let rows_of =
            |i: i64| -> Vec<usize> { (0..sc.truth.len()).filter(|&m| sc.truth[m] == i).collect() };
        let track = |target: usize, rows: &[usize]| {
            let mut rows = rows.to_vec();
            rows.sort_unstable();
            refit(&problem, &pre, &padded(&sc.targets[target]), &rows).expect("fits")
        };
        let own = rows_of(2);
        let (even, odd): (Vec<usize>, Vec<usize>) =
            own.iter().partition(|&&m| scans.scan_of[m] % 2 == 0);
        let halves = [track(2, &even), track(2, &odd)];
        let (n_detect, gate) = (4, 5.0);
        let states = joined(
            &problem,
            &pre,
            &scans,
            &halves,
            n_detect,
            gate,
            TRACK_TEST_Z,
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
            &pre,
            &scans,
            &targets,
            n_detect,
            1e9,
            TRACK_TEST_Z,
        );
        assert!(apart.is_none(), "two targets were joined");
    }
}
