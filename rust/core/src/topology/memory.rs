//! What a source's bias estimate is fitted to: each track's recent positions, and which
//! (local, system) track pairs are believed to be one target.
//!
//! A pair is *believed* from the scan it is decided on until a scan at which both of its
//! tracks are present and it is not decided: the latest word on it stands, so a wrong early
//! pair that the decisions have since undone no longer counts, and a pair whose tracks have
//! ended still does. The fit (`bias.rs`) takes every scan the two tracks of each believed pair
//! share, the pair being the cluster of its points: a pair decided late brings its whole common
//! history, and one undone takes its history away. Positions are kept for the last
//! [`HISTORY`] scans of each track.

use std::collections::VecDeque;

use rstar::primitives::GeomWithData;
use rstar::RTree;
use rustc_hash::{FxHashMap, FxHashSet};

use super::bias::{BiasAccumulator, BiasEstimate};
use super::scan::ScanTracks;

/// Scans of positions kept per track.
pub const HISTORY: usize = 128;

/// Scans whose pictures are kept whole (the current one included), for the registration's
/// consensus over time (`fusion.rs`).
pub const RECENT_SCANS: usize = 6;

/// One track of a kept picture: its planar position and, if the scan carried covariances, the
/// planar block `[xx, xy, yy]` of its position covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    pub position: [f64; 2],
    pub covariance: Option<[f64; 3]>,
}

impl Entry {
    fn of(tracks: &ScanTracks<'_>, k: usize) -> Self {
        let d = tracks.dim();
        Self {
            position: tracks.position(k),
            covariance: tracks
                .covariance(k)
                .map(|c| [c[0], (c[1] + c[d]) / 2.0, c[d + 1]]),
        }
    }

    /// The entries of a whole scan.
    pub fn all(tracks: &ScanTracks<'_>) -> Vec<Self> {
        (0..tracks.len()).map(|k| Self::of(tracks, k)).collect()
    }
}

/// A kept pair of pictures, the system's indexed by position.
#[derive(Debug, Clone)]
pub struct Picture {
    pub local: Vec<Entry>,
    pub system: Vec<Entry>,
    pub tree: RTree<GeomWithData<[f64; 2], u32>>,
}

/// Points a fit reads at most: beyond, each pair's common scans are thinned evenly.
pub const MAX_FIT_POINTS: usize = 20_000;

type Positions = VecDeque<(u64, [f64; 2])>;

/// Track positions and believed pairs of one local source against the system picture.
#[derive(Debug, Clone, Default)]
pub struct PairMemory {
    scan: u64,
    local: FxHashMap<i64, Positions>,
    system: FxHashMap<i64, Positions>,
    believed: FxHashSet<(i64, i64)>,
    recent: VecDeque<Picture>,
}

impl PairMemory {
    /// Records one scan's positions; call once per scan, before the decision.
    pub fn record(&mut self, local: &ScanTracks<'_>, system: &ScanTracks<'_>) {
        self.scan += 1;
        let scan = self.scan;
        for (map, tracks) in [(&mut self.local, local), (&mut self.system, system)] {
            for (k, &id) in tracks.ids().iter().enumerate() {
                let positions = map.entry(id).or_default();
                positions.push_back((scan, tracks.position(k)));
                if positions.len() > HISTORY {
                    positions.pop_front();
                }
            }
            // Tracks unseen for a whole history are forgotten.
            map.retain(|_, p| {
                p.back()
                    .is_some_and(|&(last, _)| last + HISTORY as u64 > scan)
            });
        }
        let (l, s) = (&self.local, &self.system);
        self.believed
            .retain(|(a, b)| l.contains_key(a) && s.contains_key(b));
        let system_entries = Entry::all(system);
        let tree = RTree::bulk_load(
            system_entries
                .iter()
                .enumerate()
                .map(|(j, e)| GeomWithData::new(e.position, j as u32))
                .collect(),
        );
        self.recent.push_back(Picture {
            local: Entry::all(local),
            system: system_entries,
            tree,
        });
        if self.recent.len() > RECENT_SCANS {
            self.recent.pop_front();
        }
    }

    /// The kept pictures before the current scan's, newest first.
    pub fn earlier(&self) -> impl Iterator<Item = &Picture> {
        self.recent.iter().rev().skip(1)
    }

    /// The believed pairs were `decided` (rows of this scan's `local`, `system`) this scan's
    /// decision, in an order that reads no id (by the tracks' latest positions).
    pub fn believed_with(
        &self,
        local: &ScanTracks<'_>,
        system: &ScanTracks<'_>,
        decided: &[(usize, usize)],
    ) -> Vec<(i64, i64)> {
        self.sorted(self.updated(local, system, decided))
    }

    /// The believed pairs, in an order that reads no id.
    pub fn believed(&self) -> Vec<(i64, i64)> {
        self.sorted(self.believed.iter().copied().collect())
    }

    fn sorted(&self, mut out: Vec<(i64, i64)>) -> Vec<(i64, i64)> {
        let latest = |map: &FxHashMap<i64, Positions>, id: i64| {
            map.get(&id)
                .and_then(|p| p.back())
                .map_or([f64::NAN; 2], |&(_, x)| x)
        };
        out.sort_by(|&(a, b), &(c, d)| {
            let (pa, pc) = (latest(&self.local, a), latest(&self.local, c));
            let (qb, qd) = (latest(&self.system, b), latest(&self.system, d));
            pa[0]
                .total_cmp(&pc[0])
                .then(pa[1].total_cmp(&pc[1]))
                .then(qb[0].total_cmp(&qd[0]))
                .then(qb[1].total_cmp(&qd[1]))
        });
        out
    }

    /// Makes this scan's decision the latest word on its pairs.
    pub fn commit(
        &mut self,
        local: &ScanTracks<'_>,
        system: &ScanTracks<'_>,
        decided: &[(usize, usize)],
    ) {
        self.believed = self.updated(local, system, decided).into_iter().collect();
    }

    fn updated(
        &self,
        local: &ScanTracks<'_>,
        system: &ScanTracks<'_>,
        decided: &[(usize, usize)],
    ) -> Vec<(i64, i64)> {
        let here_l: FxHashSet<i64> = local.ids().iter().copied().collect();
        let here_s: FxHashSet<i64> = system.ids().iter().copied().collect();
        let mut out: Vec<(i64, i64)> = self
            .believed
            .iter()
            .filter(|(a, b)| !(here_l.contains(a) && here_s.contains(b)))
            .copied()
            .collect();
        out.extend(
            decided
                .iter()
                .map(|&(i, j)| (local.ids()[i], system.ids()[j])),
        );
        out
    }

    /// The trimmed fit (rigid, or rotation-only about `centre`) over every scan the two
    /// tracks of each of `pairs` share; each pair is a cluster. None without points.
    pub fn fit(&self, pairs: &[(i64, i64)], centre: Option<[f64; 2]>) -> Option<BiasEstimate> {
        let shared: Vec<Vec<([f64; 2], [f64; 2])>> = pairs
            .iter()
            .map(|(a, b)| match (self.local.get(a), self.system.get(b)) {
                (Some(p), Some(q)) => common(p, q),
                _ => Vec::new(),
            })
            .collect();
        let total: usize = shared.iter().map(Vec::len).sum();
        let stride = total.div_ceil(MAX_FIT_POINTS).max(1);
        let mut sums = BiasAccumulator::default();
        for (label, points) in shared.iter().enumerate() {
            // Thinned from the latest scan back, so the newest point is always in.
            for &(p, q) in points.iter().rev().step_by(stride) {
                sums.add_in(label as u64, p, q);
            }
        }
        if sums.pairs() == 0 {
            return None;
        }
        match centre {
            Some(c) => sums.about(c),
            None => sums.rigid(),
        }
    }
}

/// The positions of two tracks at the scans both have, oldest first.
fn common(p: &Positions, q: &Positions) -> Vec<([f64; 2], [f64; 2])> {
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < p.len() && j < q.len() {
        match p[i].0.cmp(&q[j].0) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                out.push((p[i].1, q[j].1));
                i += 1;
                j += 1;
            }
        }
    }
    out
}
