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
    let Some(gate) = gate else {
        return Candidates::All {
            n_local: local.len(),
            n_system: system.len(),
        };
    };
    let mut pairs = Vec::new();
    // The visitor never fails, so neither does the walk.
    let _ = each_pair_within(local, system, gate, |i, j| {
        pairs.push((i, j));
        Ok(())
    });
    Candidates::Listed(pairs)
}

/// The pairs one scan scores, as [`candidate_pairs`] and then [`chi2_gated`] give them, but
/// with at most `cap` pairs kept and the stop request polled while they are found. Without a
/// position gate every pair is a candidate, so more than `cap` of them are refused before
/// any work; with one, the pairs within it (and passing the χ² gate, tested as they are found
/// instead of after listing them all) are refused once they outnumber the cap.
pub fn gated_pairs(
    local: &ScanTracks<'_>,
    system: &ScanTracks<'_>,
    (gate, chi2): (Option<f64>, Option<f64>),
    cap: usize,
) -> CoreResult<Candidates> {
    let over = |count: usize, hint: &'static str| CoreError::CapExceeded {
        what: "track pairs in one scan",
        count,
        cap,
        hint,
    };
    let Some(gate) = gate else {
        let all = local.len().saturating_mul(system.len());
        if all > cap {
            return Err(over(
                all,
                "give a position gate (only pairs within it are scored) for pictures this large",
            ));
        }
        let pairs = candidate_pairs(local, system, None);
        return match chi2 {
            Some(threshold) => chi2_gated(local, system, &pairs, threshold),
            None => Ok(pairs),
        };
    };
    if chi2.is_some() {
        check_dimensions(local, system)?;
    }
    let mut pairs = Vec::new();
    each_pair_within(local, system, gate, |i, j| {
        if crate::parallel::interrupted() {
            return Err(CoreError::Interrupted);
        }
        let kept = match chi2 {
            Some(threshold) => passes_chi2(local, system, (i as usize, j as usize), threshold)?,
            None => true,
        };
        if kept {
            if pairs.len() == cap {
                return Err(over(
                    cap + 1,
                    "narrow the position gate (or the χ² gate): too many pairs lie within it",
                ));
            }
            pairs.push((i, j));
        }
        Ok(())
    })?;
    Ok(Candidates::Listed(pairs))
}

/// Calls `visit(i, j)` for every pair within `gate` metres (in 3-D where the scans carry
/// heights), ascending by local row, then system row, with an R*-tree over the system
/// positions; stops at the first error.
fn each_pair_within(
    local: &ScanTracks<'_>,
    system: &ScanTracks<'_>,
    gate: f64,
    mut visit: impl FnMut(u32, u32) -> CoreResult<()>,
) -> CoreResult<()> {
    let (n_local, n_system) = (local.len() as u32, system.len() as u32);
    let tree = RTree::bulk_load(
        (0..n_system)
            .map(|j| Located::new(system.position(j as usize), j))
            .collect(),
    );
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
        for &j in &near {
            visit(i, j)?;
        }
    }
    Ok(())
}

/// The candidates whose current positions pass the χ² gate `dᵀ(P_i + P_j)⁻¹d ≤ threshold`,
/// d the position difference and P the tracks' position covariances (a pair whose summed
/// covariance is not positive definite never passes). Both scans must carry covariances of
/// the same dimension. Polls the stop request (`Interrupted`).
pub fn chi2_gated(
    local: &ScanTracks<'_>,
    system: &ScanTracks<'_>,
    pairs: &Candidates,
    threshold: f64,
) -> CoreResult<Candidates> {
    check_dimensions(local, system)?;
    let mut kept = Vec::new();
    for k in 0..pairs.len() {
        if k % 4096 == 0 && crate::parallel::interrupted() {
            return Err(CoreError::Interrupted);
        }
        let (i, j) = pairs.pair(k);
        if passes_chi2(local, system, (i, j), threshold)? {
            kept.push((i as u32, j as u32));
        }
    }
    Ok(Candidates::Listed(kept))
}

/// Both sides of a χ² gate have positions of the same dimension.
fn check_dimensions(local: &ScanTracks<'_>, system: &ScanTracks<'_>) -> CoreResult<()> {
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
    Ok(())
}

/// Whether pair `(i, j)` passes the χ² gate; an error when a side has no covariances.
fn passes_chi2(
    local: &ScanTracks<'_>,
    system: &ScanTracks<'_>,
    (i, j): (usize, usize),
    threshold: f64,
) -> CoreResult<bool> {
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
    Ok(mahalanobis(&sum[..d * d], &diff[..d]).is_some_and(|m| m <= threshold))
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
