//! Initiation with missed detections: in the middle scans (harmless) and in the outer scans
//! (the second candidate pass, `candidate_scans`).

use super::{assert_exact_tracks, assert_partition, run, sim};
use crate::fti::InitiationOptions;

#[test]
fn three_sensors_with_missed_detections_still_give_the_tracks() {
    // Pd < 1 in the middle scans: drop one target report in three there. (A target missed in
    // a first or last scan of every pair cannot be initiated: candidates come from those.)
    let mut sc = sim::planar(21, true, 2, 8);
    let (first, last) = (0.0, 70.0);
    let keep: Vec<bool> = (0..sc.sensor.len())
        .map(|m| sc.truth[m] < 0 || sc.time[m] == first || sc.time[m] == last || m % 3 != 1)
        .collect();
    sc.keep_rows(&keep);
    let result = run(&sc, &InitiationOptions::default()).expect("runs");
    assert_partition(&result, sc.sensor.len());
    assert_eq!(result.tracks.len(), 2, "{:?}", result.stage_counts);
    for (i, target) in sc.targets.iter().enumerate() {
        let own = (0..sc.truth.len())
            .filter(|&m| sc.truth[m] == i as i64)
            .count();
        let track = result
            .tracks
            .iter()
            .max_by_key(|t| {
                t.measurements
                    .iter()
                    .filter(|&&m| sc.truth[m] == i as i64)
                    .count()
            })
            .expect("a track");
        let hits = track
            .measurements
            .iter()
            .filter(|&&m| sc.truth[m] == i as i64)
            .count();
        assert!(hits + 1 >= own, "target {i}: {hits} of {own}");
        assert!(
            (track.estimate[0] - target[0]).abs() < 200.0
                && (track.estimate[2] - target[2]).abs() < 5.0
        );
    }
}

#[test]
fn targets_missed_in_an_outer_scan_are_initiated_by_the_second_pass() {
    // Noiseless paper scene; target i is missed in one of the four outer scans (sensor i % 2,
    // first scan for i < 2, last scan otherwise), so no (first, last) candidate holds it.
    let mut sc = sim::paper(11, false, 0, 8);
    let times: Vec<f64> = sc.time.clone();
    let (t_first, t_last) = (
        |s: i64| if s == 0 { 0.0 } else { 5.0 },
        |s: i64| {
            if s == 0 {
                105.0
            } else {
                110.0
            }
        },
    );
    let keep: Vec<bool> = (0..sc.sensor.len())
        .map(|m| {
            let (i, s) = (sc.truth[m], sc.sensor[m]);
            let outer = if i < 2 { t_first(s) } else { t_last(s) };
            !(i >= 0 && s == i % 2 && times[m] == outer)
        })
        .collect();
    assert_eq!(
        keep.iter().filter(|k| !**k).count(),
        4,
        "one row dropped per target"
    );
    sc.keep_rows(&keep);
    let paper = InitiationOptions::default()
        .with_candidate_scans(1)
        .expect("valid");
    let lost = run(&sc, &paper).expect("runs");
    // Only mixed candidates (rows of two targets) remain; some still climb to a target.
    assert!(lost.tracks.len() < 4, "{:?}", lost.stage_counts);
    let result = run(&sc, &InitiationOptions::default()).expect("runs");
    assert_partition(&result, sc.sensor.len());
    assert_exact_tracks(&sc, &result, 1e-6);
    assert!(result.tracks.iter().all(|t| t.measurements.len() == 15));
}
