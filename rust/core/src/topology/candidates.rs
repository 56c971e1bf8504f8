//! Which (local, system) pairs a scan scores: every pair, or with a position gate only the
//! pairs within it, found with an R*-tree over the system positions (a gate makes a large
//! picture's scan O(n log n + pairs) instead of O(n²)).

use rstar::primitives::GeomWithData;
use rstar::RTree;

use super::scan::ScanTracks;

type Located = GeomWithData<[f64; 2], u32>;

/// The pairs a scan scores, ascending by local row, then system row.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Candidates {
    /// Every `(i, j)` of `n_local × n_system`, pair `k` being `(k / n_system, k % n_system)`:
    /// no list is built.
    All { n_local: usize, n_system: usize },
    /// The listed pairs only.
    Listed(Vec<(u32, u32)>),
}

impl Candidates {
    pub fn len(&self) -> usize {
        match self {
            Self::All { n_local, n_system } => n_local * n_system,
            Self::Listed(pairs) => pairs.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Pair `k`.
    pub fn pair(&self, k: usize) -> (usize, usize) {
        match self {
            Self::All { n_system, .. } => (k / n_system, k % n_system),
            Self::Listed(pairs) => (pairs[k].0 as usize, pairs[k].1 as usize),
        }
    }

    /// The index of pair `(i, j)`, which must be a candidate.
    pub fn index_of(&self, i: usize, j: usize) -> usize {
        match self {
            Self::All { n_system, .. } => i * n_system + j,
            Self::Listed(pairs) => pairs.partition_point(|&p| p < (i as u32, j as u32)),
        }
    }
}

/// The candidate pairs: all of them, or those within `gate` metres.
pub fn candidate_pairs(
    local: &ScanTracks<'_>,
    system: &ScanTracks<'_>,
    gate: Option<f64>,
) -> Candidates {
    let (n_local, n_system) = (local.len() as u32, system.len() as u32);
    let Some(gate) = gate else {
        return Candidates::All {
            n_local: local.len(),
            n_system: system.len(),
        };
    };
    let tree = RTree::bulk_load(
        (0..n_system)
            .map(|j| Located::new(system.position(j as usize), j))
            .collect(),
    );
    let mut pairs = Vec::new();
    let mut near = Vec::new();
    for i in 0..n_local {
        near.clear();
        near.extend(
            tree.locate_within_distance(local.position(i as usize), gate * gate)
                .map(|p| p.data),
        );
        near.sort_unstable();
        pairs.extend(near.iter().map(|&j| (i, j)));
    }
    Candidates::Listed(pairs)
}

/// The distance of each candidate pair.
pub fn pair_distances(
    local: &ScanTracks<'_>,
    system: &ScanTracks<'_>,
    pairs: &Candidates,
) -> Vec<f64> {
    (0..pairs.len())
        .map(|k| {
            let (i, j) = pairs.pair(k);
            let (p, q) = (local.position(i), system.position(j));
            (p[0] - q[0]).hypot(p[1] - q[1])
        })
        .collect()
}
