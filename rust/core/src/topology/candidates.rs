//! Which (local, system) pairs a scan scores: every pair, or with a position gate only the
//! pairs within it, found with an R*-tree over the system positions (a gate makes a large
//! picture's scan O(n log n + pairs) instead of O(n²)).

use rstar::primitives::GeomWithData;
use rstar::RTree;

use super::scan::ScanTracks;
use crate::error::{CoreError, CoreResult};

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

/// The candidate pairs: all of them, or those within `gate` metres (in 3-D where the scans
/// carry heights).
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
        if local.dim() == 3 {
            // The tree is planar: keep the pairs within the gate in 3-D too.
            let p = local.point(i as usize);
            near.retain(|&j| squared_distance(p, system.point(j as usize)) <= gate * gate);
        }
        pairs.extend(near.iter().map(|&j| (i, j)));
    }
    Candidates::Listed(pairs)
}

/// The candidates whose current positions pass the χ² gate `dᵀ(P_i + P_j)⁻¹d ≤ threshold`,
/// d the position difference and P the tracks' position covariances (a pair whose summed
/// covariance is not positive definite never passes). Both scans must carry covariances of
/// the same dimension.
pub fn chi2_gated(
    local: &ScanTracks<'_>,
    system: &ScanTracks<'_>,
    pairs: &Candidates,
    threshold: f64,
) -> CoreResult<Candidates> {
    if local.dim() != system.dim() {
        return Err(CoreError::ill_posed(
            "system",
            format!(
                "{}-D positions against the local side's {}-D",
                system.dim(),
                local.dim()
            ),
        ));
    }
    let mut kept = Vec::new();
    for k in 0..pairs.len() {
        let (i, j) = pairs.pair(k);
        let (Some(a), Some(b)) = (local.covariance(i), system.covariance(j)) else {
            return Err(CoreError::ill_posed(
                "covariance",
                "the χ² gate needs both sides' position covariances",
            ));
        };
        let (p, q) = (local.point(i), system.point(j));
        let d = local.dim();
        let diff = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let mut sum = [0.0; 9];
        for (s, (x, y)) in sum.iter_mut().zip(a.iter().zip(b)) {
            *s = x + y;
        }
        if mahalanobis(&sum[..d * d], &diff[..d]).is_some_and(|m| m <= threshold) {
            kept.push((i as u32, j as u32));
        }
    }
    Ok(Candidates::Listed(kept))
}

/// `dᵀ S⁻¹ d` for a 2×2 or 3×3 symmetric `S` by Cholesky; None when `S` is not positive
/// definite.
fn mahalanobis(s: &[f64], d: &[f64]) -> Option<f64> {
    let n = d.len();
    let mut l = [0.0; 9];
    for r in 0..n {
        for c in 0..=r {
            let mut v = s[r * n + c];
            for k in 0..c {
                v -= l[r * n + k] * l[c * n + k];
            }
            if r == c {
                if v.is_nan() || v <= 0.0 {
                    return None;
                }
                l[r * n + c] = v.sqrt();
            } else {
                l[r * n + c] = v / l[c * n + c];
            }
        }
    }
    // Forward substitution L z = d; the form is |z|².
    let mut z = [0.0; 3];
    let mut total = 0.0;
    for r in 0..n {
        let mut v = d[r];
        for k in 0..r {
            v -= l[r * n + k] * z[k];
        }
        z[r] = v / l[r * n + r];
        total += z[r] * z[r];
    }
    total.is_finite().then_some(total)
}

fn squared_distance(p: [f64; 3], q: [f64; 3]) -> f64 {
    let (dx, dy, dz) = (p[0] - q[0], p[1] - q[1], p[2] - q[2]);
    dx * dx + dy * dy + dz * dz
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
            if local.dim() == 2 {
                let (p, q) = (local.position(i), system.position(j));
                (p[0] - q[0]).hypot(p[1] - q[1])
            } else {
                squared_distance(local.point(i), system.point(j)).sqrt()
            }
        })
        .collect()
}

/// The candidates of the bias-bound gate (`Gate::Auto`): the pairs within
/// `offset + 3·sqrt(tr P_i + tr P_j)` metres in the plane, P the planar blocks of the tracks'
/// position covariances (`offset` alone where a scan has none).
pub fn auto_gated(local: &ScanTracks<'_>, system: &ScanTracks<'_>, offset: f64) -> Candidates {
    let spread = |tracks: &ScanTracks<'_>, k: usize| -> f64 {
        tracks.covariance(k).map_or(0.0, |c| {
            let d = tracks.dim();
            (c[0] + c[d + 1]).max(0.0)
        })
    };
    let widest = |tracks: &ScanTracks<'_>| {
        (0..tracks.len())
            .map(|k| spread(tracks, k))
            .fold(0.0_f64, f64::max)
    };
    let reach = offset + 3.0 * (widest(local) + widest(system)).sqrt();
    let tree = RTree::bulk_load(
        (0..system.len() as u32)
            .map(|j| Located::new(system.position(j as usize), j))
            .collect(),
    );
    let mut pairs = Vec::new();
    let mut near = Vec::new();
    for i in 0..local.len() {
        let p = local.position(i);
        near.clear();
        near.extend(
            tree.locate_within_distance(p, reach * reach)
                .map(|q| q.data)
                .filter(|&j| {
                    let q = system.position(j as usize);
                    let limit =
                        offset + 3.0 * (spread(local, i) + spread(system, j as usize)).sqrt();
                    (p[0] - q[0]).hypot(p[1] - q[1]) <= limit
                }),
        );
        near.sort_unstable();
        pairs.extend(near.iter().map(|&j| (i as u32, j)));
    }
    Candidates::Listed(pairs)
}
