//! Untangling two tracks that took each other's rows at one sensor (a project extension;
//! `untangle`).
//!
//! Why: where two targets fly close, one sensor can see them along nearly the same line, and
//! the classification can give each track the other target's rows at that sensor, in every
//! scan or from a crossing on. Each track is then a compromise of two targets that fits its
//! rows to within the gates, the refine passes keep the assignment (each classification agrees
//! with the states it came from), and neither track holds a target (the 8-target 2-D scene of
//! `bearing_only_2d_scenario` at Pd 0.9: two targets of seed 1 swapped at the third sensor;
//! the 4-scan paper scene: two sensors, where a swap pairs one target's rays with another's).
//!
//! How: for each pair of tracks that compete for rows (module `track_join`), every exchange of
//! one sensor's rows from one of its scans on is tried, both tracks refitted from their
//! states; an exchange may start only at a scan where a row of one track lies within the
//! other's gate (the rows are exchangeable there). The exchange that lowers the two tracks'
//! summed χ² most is kept when it lowers it by more than [`MARGIN`]. The row counts do not
//! change, so this is the likelihood-ratio choice between the two assignments. Pairs are tried
//! in parallel and taken best first, each track in one exchange a round; rounds repeat on the
//! pairs whose tracks changed, at most [`MAX_ROUNDS`]. No row is lost or gained: rows only
//! move between the two tracks.

use rayon::prelude::*;

use super::detection::residual2;
use super::output::Track;
use super::problem::Problem;
use super::refit::{padded, refit};
use super::scans::Scans;
use super::track_join::competing;

/// The drop in summed χ² an exchange must exceed: a likelihood ratio of e (the assignments
/// have as many rows and parameters). Lower margins made more exchanges and found about as
/// many targets, with more found targets lost to a wrong one (CHANGELOG.md).
pub(super) const MARGIN: f64 = 2.0;

/// Rounds of exchanges at most: a round changes each track once at most, and later rounds
/// try only the pairs a round changed.
const MAX_ROUNDS: usize = 8;

/// `tracks` with their rows exchanged where that fits both better (module doc); rows keep
/// their tracks' indices.
pub(super) fn untangled(
    problem: &Problem<'_>,
    scans: &Scans,
    mut tracks: Vec<Track>,
    gate: f64,
) -> Vec<Track> {
    let pairs = competing(problem, scans, &tracks, gate);
    if pairs.is_empty() {
        return tracks;
    }
    // Each scan's sensor and its place among that sensor's scans.
    let mut place = vec![(0usize, 0usize); scans.len()];
    for (sensor, list) in scans.per_sensor.iter().enumerate() {
        for (order, &k) in list.iter().enumerate() {
            place[k] = (sensor, order);
        }
    }
    let gate2 = gate * gate;
    let mut changed = vec![true; tracks.len()];
    for _ in 0..MAX_ROUNDS {
        // A pair's best exchange depends on its two tracks alone: one whose tracks did not
        // change keeps the answer it had (below the margin, or beaten on one of its tracks,
        // which then changed).
        let mut found: Vec<(f64, usize, usize, Track, Track)> = pairs
            .par_iter()
            .filter(|&&(a, b)| changed[a] || changed[b])
            .filter_map(|&(a, b)| {
                let (gain, ta, tb) =
                    best_exchange(problem, scans, &place, &tracks[a], &tracks[b], gate2)?;
                Some((gain, a, b, ta, tb))
            })
            .collect();
        found.sort_by(|p, q| q.0.total_cmp(&p.0).then((p.1, p.2).cmp(&(q.1, q.2))));
        changed.fill(false);
        for (_, a, b, ta, tb) in found {
            if changed[a] || changed[b] {
                continue;
            }
            (tracks[a], tracks[b]) = (ta, tb);
            (changed[a], changed[b]) = (true, true);
        }
        if !changed.contains(&true) {
            break;
        }
    }
    tracks
}

/// The exchange of `a`'s and `b`'s rows that lowers their summed χ² most, if by more than
/// [`MARGIN`]: `(drop, new a, new b)`.
fn best_exchange(
    problem: &Problem<'_>,
    scans: &Scans,
    place: &[(usize, usize)],
    a: &Track,
    b: &Track,
    gate2: f64,
) -> Option<(f64, Track, Track)> {
    // Where an exchange may start: a scan where a row of one lies within the other's gate.
    let mut starts: Vec<(usize, usize)> = (a.measurements.iter().map(|&m| (m, &b.estimate)))
        .chain(b.measurements.iter().map(|&m| (m, &a.estimate)))
        .filter(|&(m, other)| residual2(problem, other, m) <= gate2)
        .map(|(m, _)| place[scans.scan_of[m]])
        .collect();
    starts.sort_unstable();
    starts.dedup();
    let (sa, sb) = (padded(&a.estimate), padded(&b.estimate));
    let before = a.chi2 + b.chi2;
    let mut best: Option<(f64, Track, Track)> = None;
    for (sensor, from) in starts {
        // Whether row m is one of the exchanged: that sensor's, from that scan on.
        let moves = |m: &usize| {
            let (s, order) = place[scans.scan_of[*m]];
            s == sensor && order >= from
        };
        let exchanged = |keep: &Track, take: &Track| -> Vec<usize> {
            let mut rows: Vec<usize> = (keep.measurements.iter().filter(|m| !moves(m)))
                .chain(take.measurements.iter().filter(|m| moves(m)))
                .copied()
                .collect();
            rows.sort_unstable();
            rows
        };
        let (Some(na), Some(nb)) = (
            refit(problem, &sa, &exchanged(a, b)),
            refit(problem, &sb, &exchanged(b, a)),
        ) else {
            continue;
        };
        let gain = before - (na.chi2 + nb.chi2);
        if gain > MARGIN && best.as_ref().is_none_or(|(g, _, _)| gain > *g) {
            best = Some((gain, na, nb));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fti::refit::refit_rows;
    use crate::fti::tests::sim;

    /// Two targets' tracks that hold each other's rows at one sensor are untangled, every row
    /// kept; the tracks of the same targets with their own rows are left as they are.
    #[test]
    fn tracks_swapped_at_one_sensor_are_untangled() {
        let sc = sim::paper(5, true, 0, 8);
        let sensors = sc.sensors();
        let table = sc.measurements(&sensors);
        let problem = sim::problem(sensors, table);
        let scans = Scans::new(&table, sensors.len());
        let fitted =
            |target: usize, rows: Vec<usize>| refit_rows(&problem, &sc.targets[target], rows);
        // Two targets, and their rows of sensor 1 exchanged between their tracks.
        let (t0, t1) = (0usize, 1usize);
        let (r0, r1) = (sc.rows_of(t0 as i64), sc.rows_of(t1 as i64));
        let at_1 = |m: &usize| table.sensor(*m) == 1;
        let tangled = |own: &[usize], other: &[usize]| -> Vec<usize> {
            (own.iter().filter(|m| !at_1(m)))
                .chain(other.iter().filter(|m| at_1(m)))
                .copied()
                .collect()
        };
        let gate = 1e9; // they compete everywhere: the exchange itself must decide
        let tracks = vec![fitted(t0, tangled(&r0, &r1)), fitted(t1, tangled(&r1, &r0))];
        let held: usize = tracks.iter().map(|t| t.measurements.len()).sum();
        let sets = |ts: &[Track]| -> Vec<Vec<usize>> {
            let mut v: Vec<Vec<usize>> = ts.iter().map(|t| t.measurements.clone()).collect();
            v.sort();
            v
        };
        let mut own_sets = vec![r0.clone(), r1.clone()];
        own_sets.sort();
        assert_ne!(
            sets(&tracks),
            own_sets,
            "the tracks are tangled to begin with"
        );
        let out = untangled(&problem, &scans, tracks, gate);
        // Each track holds one target's rows (exchanging the other sensor's rows does it too,
        // with the tracks' roles swapped).
        assert_eq!(sets(&out), own_sets);
        assert_eq!(
            out.iter().map(|t| t.measurements.len()).sum::<usize>(),
            held
        );
        // Untangled tracks stay so.
        let own = vec![fitted(t0, r0), fitted(t1, r1)];
        let again = untangled(&problem, &scans, own.clone(), gate);
        let rows = |ts: &[Track]| -> Vec<Vec<usize>> {
            ts.iter().map(|t| t.measurements.clone()).collect()
        };
        assert_eq!(rows(&again), rows(&own));
    }
}
