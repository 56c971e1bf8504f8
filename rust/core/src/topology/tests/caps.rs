//! The pair cap of a scan holds with and without a position gate and with the χ² gate, and
//! the gated listing keeps what listing then filtering kept.

use super::*;
use crate::error::CoreError;

/// `n` tracks on a line 100 m apart, each with a 100 m position std, and their ids.
fn line(n: usize) -> (Vec<i64>, Vec<f64>, Vec<f64>) {
    let ids = (0..n as i64).collect();
    let pos = (0..n).flat_map(|k| [100.0 * k as f64, 0.0]).collect();
    let cov = (0..n).flat_map(|_| [1e4, 0.0, 0.0, 1e4]).collect();
    (ids, pos, cov)
}

#[test]
fn the_cap_binds_with_and_without_gates() {
    let (ids, pos, cov) = line(30);
    let tracks = ScanTracks::new("local", &ids, &pos, None)
        .unwrap()
        .with_covariances("local", &cov)
        .unwrap();
    let over = |gates: (Option<f64>, Option<f64>), cap: usize| match gated_pairs(
        &tracks, &tracks, gates, cap,
    ) {
        Err(CoreError::CapExceeded { count, cap: c, .. }) => Some((count, c)),
        Ok(_) => None,
        Err(other) => panic!("{other}"),
    };
    // No gate: every pair, refused before any work.
    assert_eq!(over((None, None), 899), Some((900, 899)));
    assert_eq!(over((None, None), 900), None);
    // With the χ² gate alone the candidates are still every pair.
    assert_eq!(over((None, Some(9.21)), 899), Some((900, 899)));
    // A gate wider than the picture keeps every pair: refused once the list outgrows the cap.
    assert_eq!(over((Some(1e9), None), 500), Some((501, 500)));
    // With both gates only the pairs passing the χ² test count: 3σ of the summed 141 m std,
    // about 430 m, keeps each track's 9 nearest at most.
    let both = gated_pairs(&tracks, &tracks, (Some(1e9), Some(9.21)), 900).unwrap();
    assert!(both.len() < 900);
    assert_eq!(over((Some(1e9), Some(9.21)), both.len()), None);
    assert_eq!(
        over((Some(1e9), Some(9.21)), both.len() - 1),
        Some((both.len(), both.len() - 1))
    );
}

#[test]
fn gated_pairs_are_the_listed_pairs_filtered() {
    let (ids, pos, cov) = line(40);
    let local = ScanTracks::new("local", &ids, &pos, None)
        .unwrap()
        .with_covariances("local", &cov)
        .unwrap();
    let shifted: Vec<f64> = pos.iter().map(|v| v + 55.0).collect();
    let system = ScanTracks::new("system", &ids, &shifted, None)
        .unwrap()
        .with_covariances("system", &cov)
        .unwrap();
    for gate in [None, Some(80.0), Some(1e9)] {
        for chi2 in [None, Some(2.0), Some(9.21)] {
            let listed = candidate_pairs(&local, &system, gate);
            let expected = match chi2 {
                Some(t) => chi2_gated(&local, &system, &listed, t).unwrap(),
                None => listed,
            };
            let got = gated_pairs(&local, &system, (gate, chi2), usize::MAX).unwrap();
            assert_eq!(
                (0..got.len()).map(|k| got.pair(k)).collect::<Vec<_>>(),
                (0..expected.len())
                    .map(|k| expected.pair(k))
                    .collect::<Vec<_>>(),
                "gate {gate:?}, χ² {chi2:?}"
            );
        }
    }
}
