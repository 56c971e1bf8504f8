//! The window's flat history gives, bit for bit, the averages of a per-pair ring of scores
//! (the plain reading of "the mean over the last `window` scans"), on scans whose tracks come
//! and go, with and without a listed set of pairs.

use std::collections::{HashMap, VecDeque};

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::super::candidates::Candidates;
use super::super::history::ScoreHistory;

/// Per-pair rings of (scan, score), trimmed to the window: the reference.
struct Rings {
    window: u64,
    scan: u64,
    pairs: HashMap<(i64, i64), VecDeque<(u64, f64)>>,
}

impl Rings {
    fn average(&mut self, local: &[i64], system: &[i64], pairs: &Candidates, scores: &mut [f64]) {
        self.scan += 1;
        let oldest = self.scan.saturating_sub(self.window - 1);
        for (k, score) in scores.iter_mut().enumerate() {
            let (i, j) = pairs.pair(k);
            let ring = self.pairs.entry((local[i], system[j])).or_default();
            while ring.front().is_some_and(|&(scan, _)| scan < oldest) {
                ring.pop_front();
            }
            ring.push_back((self.scan, *score));
            *score = ring.iter().map(|&(_, s)| s).sum::<f64>() / ring.len() as f64;
        }
    }
}

/// A scan's ids: each of `pool` ids present with probability 0.7, in a shuffled order.
fn present(rng: &mut ChaCha8Rng, pool: i64) -> Vec<i64> {
    let mut ids: Vec<i64> = (0..pool).filter(|_| rng.random_bool(0.7)).collect();
    for k in (1..ids.len()).rev() {
        ids.swap(k, rng.random_range(0..=k));
    }
    ids
}

#[test]
fn the_window_average_matches_per_pair_rings() {
    for window in [1, 2, 3, 6] {
        for listed in [false, true] {
            let mut rng = ChaCha8Rng::seed_from_u64(window as u64 * 2 + listed as u64);
            let mut history = ScoreHistory::new(window);
            let mut rings = Rings {
                window: window as u64,
                scan: 0,
                pairs: HashMap::new(),
            };
            for _ in 0..12 {
                let (local, system) = (present(&mut rng, 9), present(&mut rng, 8));
                let pairs = if listed {
                    let all = (0..local.len() as u32)
                        .flat_map(|i| (0..system.len() as u32).map(move |j| (i, j)));
                    Candidates::Listed(all.filter(|_| rng.random_bool(0.5)).collect())
                } else {
                    Candidates::All {
                        n_local: local.len(),
                        n_system: system.len(),
                    }
                };
                let raw: Vec<f64> = (0..pairs.len())
                    .map(|_| rng.random_range(-3.0..10.0))
                    .collect();
                let (mut got, mut expected) = (raw.clone(), raw.clone());
                assert!(history.average_in_place(&local, &system, &pairs, &mut got));
                if window > 1 {
                    rings.average(&local, &system, &pairs, &mut expected);
                }
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&got),
                    bits(&expected),
                    "window {window}, listed {listed}"
                );
            }
            assert!(history.len() < window);
        }
    }
}
