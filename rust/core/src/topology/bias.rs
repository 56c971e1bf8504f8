//! Each radar's bias relative to the system picture, from the associated pairs (beyond the
//! paper; METHODS §4, paper line 150: association "gives prior information for
//! registration").
//!
//! A local picture is the system picture turned by the two radars' relative azimuth bias Δ
//! and shifted: with biases b (local radar at r) and b₁ (system radar at r₁), a target seen at
//! `q` by the system is seen at `p = R(Δ) q + t`, `Δ = b − b₁`, `t = r − R(Δ) r₁ + R(b)(r₁ − r)`.
//! So the least-squares rigid fit of local onto system positions (2-D Procrustes) estimates
//! Δ; a rotation-only fit about a known centre is the option for a system picture without
//! bias. Wrong pairs (a target the system radar does not see, paired with a neighbour
//! kilometres away) would drag a plain least-squares fit, so the fit is trimmed: pairs whose
//! residual exceeds `TRIM_SIGMAS` robust standard deviations (1.4826 × the median residual)
//! are dropped and the fit repeated, until the kept set stops changing.
//!
//! **The standard deviation is honest about correlated errors.** The pairs of one track pair
//! over many scans share most of their error (a filtered track's error drifts slowly), so
//! they are not independent samples: each point belongs to a *cluster* (its track pair), and
//! the rotation's variance is the cluster-robust sandwich `G/(G−1) Σ_c (Σ_{k∈c} g_k)²`, `g_k`
//! point k's influence on the rotation, over the G clusters kept. With few clusters that
//! variance is itself uncertain, so the standard deviation is scaled by `t_{G−1}/3`, the
//! Student quantile at the 3σ level over 3: ±3 standard deviations then hold the truth as
//! often as ±3σ of a normal law (99.73 %). Points added without a cluster are their own.

use rustc_hash::FxHashMap;

/// The fitted transform `p ≈ R(rotation)·q + translation`, with its uncertainty.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiasEstimate {
    /// Δ, radians, counter-clockwise (the azimuth convention of METHODS §0).
    pub rotation: f64,
    /// Standard deviation of `rotation`, honest at 3σ (module docs); ∞ with one cluster.
    pub rotation_std: f64,
    /// Metres; for a rotation-only fit about c, `c − R c` (the turn about c as a rigid move).
    pub translation: [f64; 2],
    /// Pairs (points) the final fit kept after trimming.
    pub pairs: usize,
    /// Clusters (track pairs) among them: the independent evidence.
    pub clusters: usize,
    /// The centroid of the kept system positions `q̄` (the centre for a rotation-only fit).
    pub centre: [f64; 2],
    /// Standard deviation of the fitted image of `centre`, per axis, metres, honest at 3σ
    /// as `rotation_std` (0 for a rotation-only fit, which fixes it).
    pub centre_std: f64,
    /// The residuals' standard deviation per coordinate, metres: the two pictures' relative
    /// noise once registered.
    pub residual_std: f64,
    /// Whether the estimate can be used: set by the associator from its bounds
    /// (`Associator::bias`); the accumulator's own fits say only that they have at least
    /// [`MIN_CLUSTERS`] clusters.
    pub reliable: bool,
}

impl BiasEstimate {
    /// `R(rotation)·q + translation`.
    pub fn apply(&self, q: [f64; 2]) -> [f64; 2] {
        let (c, s) = (self.rotation.cos(), self.rotation.sin());
        [
            c * q[0] - s * q[1] + self.translation[0],
            s * q[0] + c * q[1] + self.translation[1],
        ]
    }
}

/// Fewest clusters for an estimate to count as one.
pub const MIN_CLUSTERS: usize = 3;

/// Residuals beyond this many robust standard deviations are trimmed.
pub const TRIM_SIGMAS: f64 = 3.0;

/// Trimming rounds at most (each drops pairs or ends the loop).
const MAX_ROUNDS: usize = 10;

/// Matched positions (local `p`, system `q`), pooled over the scans, each in a cluster of
/// correlated points.
#[derive(Debug, Clone, Default)]
pub struct BiasAccumulator {
    pairs: Vec<([f64; 2], [f64; 2])>,
    clusters: Vec<usize>,
    /// Cluster label → dense index.
    labels: FxHashMap<u64, usize>,
}

impl BiasAccumulator {
    /// Adds one matched pair, a cluster of its own.
    pub fn add(&mut self, p: [f64; 2], q: [f64; 2]) {
        let next = self.labels.len() + self.pairs.len();
        self.pairs.push((p, q));
        // Unlabelled points take indices no label can reach (labels are dense from 0 up).
        self.clusters.push(usize::MAX - next);
    }

    /// Adds one matched pair to cluster `label` (its track pair, say).
    pub fn add_in(&mut self, label: u64, p: [f64; 2], q: [f64; 2]) {
        let next = self.labels.len();
        let index = *self.labels.entry(label).or_insert(next);
        self.pairs.push((p, q));
        self.clusters.push(index);
    }

    pub fn pairs(&self) -> usize {
        self.pairs.len()
    }

    /// The trimmed rigid (rotation + translation) least-squares fit; `None` without pairs.
    pub fn rigid(&self) -> Option<BiasEstimate> {
        self.trimmed(None)
    }

    /// The trimmed rotation-only fit about `centre` (`p − c ≈ R (q − c)`); `None` without
    /// pairs.
    pub fn about(&self, centre: [f64; 2]) -> Option<BiasEstimate> {
        self.trimmed(Some(centre))
    }

    fn trimmed(&self, centre: Option<[f64; 2]>) -> Option<BiasEstimate> {
        let mut keep = vec![true; self.pairs.len()];
        let mut fit = fit(&self.pairs, &keep, centre)?;
        for _ in 0..MAX_ROUNDS {
            let residuals: Vec<f64> = self
                .pairs
                .iter()
                .map(|&(p, q)| fit.residual(p, q))
                .collect();
            let mut sorted: Vec<f64> = residuals
                .iter()
                .copied()
                .zip(&keep)
                .filter(|(_, &k)| k)
                .map(|(r, _)| r)
                .collect();
            sorted.sort_by(f64::total_cmp);
            let median = sorted[sorted.len() / 2];
            let limit = TRIM_SIGMAS * 1.4826 * median;
            let next: Vec<bool> = residuals.iter().map(|&r| r <= limit).collect();
            if next == keep || next.iter().filter(|&&k| k).count() < 3 {
                break;
            }
            keep = next;
            fit = self::fit(&self.pairs, &keep, centre)?;
        }
        let mut estimate = fit.estimate;
        self.robust_std(&mut estimate, &keep, centre);
        Some(estimate)
    }

    /// Replaces the estimate's standard deviations by the cluster-robust ones (module docs)
    /// and counts its clusters.
    fn robust_std(&self, estimate: &mut BiasEstimate, keep: &[bool], centre: Option<[f64; 2]>) {
        let (c, s) = (estimate.rotation.cos(), estimate.rotation.sin());
        let q0 = centre.unwrap_or(estimate.centre);
        let n = estimate.pairs as f64;
        // Σ|q − q̄|² over the kept points, and each point's influence on the rotation and on
        // the centroid's image.
        let kept = || {
            self.pairs
                .iter()
                .zip(&self.clusters)
                .zip(keep)
                .filter(|(_, &k)| k)
                .map(|(pc, _)| pc)
        };
        // Offsets divided by a power of two where their squares could overflow (exact).
        let scale = {
            let largest = kept().fold(0.0_f64, |m, ((p, q), _)| {
                m.max((q[0] - q0[0]).abs())
                    .max((q[1] - q0[1]).abs())
                    .max(p[0].abs())
                    .max(p[1].abs())
            });
            if largest.is_finite() && largest > LARGE_OFFSET {
                2.0_f64.powi((largest.log2().ceil() as i32).min(1023))
            } else {
                1.0
            }
        };
        let sqq: f64 = kept()
            .map(|((_, q), _)| ((q[0] - q0[0]) / scale).powi(2) + ((q[1] - q0[1]) / scale).powi(2))
            .sum();
        let image_of_centre = estimate.apply(q0);
        let mut sums: FxHashMap<usize, [f64; 3]> = FxHashMap::default();
        for (&(p, q), &cluster) in kept() {
            let (x, y) = ((q[0] - q0[0]) / scale, (q[1] - q0[1]) / scale);
            let turned = [c * x - s * y, s * x + c * y];
            // p − T(q) = (p − T(q̄)) − R(q − q̄), in the scaled units.
            let r = [
                (p[0] - image_of_centre[0]) / scale - turned[0],
                (p[1] - image_of_centre[1]) / scale - turned[1],
            ];
            let entry = sums.entry(cluster).or_insert([0.0; 3]);
            entry[0] += (turned[0] * r[1] - turned[1] * r[0]) / sqq;
            entry[1] += r[0] / n;
            entry[2] += r[1] / n;
        }
        let g = sums.len();
        estimate.clusters = g;
        estimate.reliable = g >= MIN_CLUSTERS;
        if g < 2 || sqq.is_nan() || sqq <= 0.0 {
            estimate.rotation_std = f64::INFINITY;
            estimate.centre_std = if centre.is_some() { 0.0 } else { f64::INFINITY };
            return;
        }
        let honest = student_3sigma(g - 1) / 3.0;
        let rotation_var: f64 =
            sums.values().map(|v| v[0] * v[0]).sum::<f64>() * g as f64 / (g as f64 - 1.0);
        estimate.rotation_std = rotation_var.sqrt() * honest;
        estimate.centre_std = if centre.is_some() {
            0.0
        } else {
            let var: f64 = sums
                .values()
                .map(|v| v[1] * v[1] + v[2] * v[2])
                .sum::<f64>()
                / 2.0;
            (var * g as f64 / (g as f64 - 1.0)).sqrt() * honest * scale
        };
    }
}

/// Student's t quantile at the probability of a normal 3σ, Φ(3) = 0.998650, for `dof`
/// degrees of freedom (≥ 1): tabulated to 30 (SciPy's `t.ppf`), the Cornish-Fisher
/// expansion beyond (within 2e-6 of it at 30).
pub fn student_3sigma(dof: usize) -> f64 {
    const TABLE: [f64; 30] = [
        235.801498, 19.206744, 9.218940, 6.620206, 5.507080, 4.904065, 4.529974, 4.276633,
        4.094255, 3.956937, 3.849936, 3.764277, 3.694188, 3.635801, 3.586423, 3.544128, 3.507498,
        3.475471, 3.447233, 3.422151, 3.399726, 3.379557, 3.361320, 3.344753, 3.329635, 3.315784,
        3.303049, 3.291300, 3.280426, 3.270334,
    ];
    if dof == 0 {
        return f64::INFINITY;
    }
    if dof <= TABLE.len() {
        return TABLE[dof - 1];
    }
    let (z, n) = (3.0_f64, dof as f64);
    z + (z.powi(3) + z) / (4.0 * n)
        + (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / (96.0 * n * n)
        + (3.0 * z.powi(7) + 19.0 * z.powi(5) + 17.0 * z.powi(3) - 15.0 * z) / (384.0 * n.powi(3))
        + (79.0 * z.powi(9) + 776.0 * z.powi(7) + 1482.0 * z.powi(5)
            - 1920.0 * z.powi(3)
            - 945.0 * z)
            / (92160.0 * n.powi(4))
}

/// One least-squares fit and how to evaluate it.
struct Fit {
    estimate: BiasEstimate,
}

impl Fit {
    /// Distance between `p` and the transformed `q`.
    fn residual(&self, p: [f64; 2], q: [f64; 2]) -> f64 {
        let (c, s) = (self.estimate.rotation.cos(), self.estimate.rotation.sin());
        let t = self.estimate.translation;
        let (x, y) = (c * q[0] - s * q[1] + t[0], s * q[0] + c * q[1] + t[1]);
        (p[0] - x).hypot(p[1] - y)
    }
}

/// Offsets beyond this have squares that can overflow, so the fit divides them by a power of
/// two first (exact: the rotation, and the rotation's standard deviation, are unchanged).
const LARGE_OFFSET: f64 = 1e150;

/// 1, or for offsets from the centres beyond [`LARGE_OFFSET`] (absurd positions) the power of
/// two that brings the largest to about 1, so that no sum of squares overflows to NaN.
fn product_scale(kept: &[&([f64; 2], [f64; 2])], pc: [f64; 2], qc: [f64; 2]) -> f64 {
    let largest = kept.iter().fold(0.0_f64, |m, &&(p, q)| {
        m.max((p[0] - pc[0]).abs())
            .max((p[1] - pc[1]).abs())
            .max((q[0] - qc[0]).abs())
            .max((q[1] - qc[1]).abs())
    });
    if largest.is_finite() && largest > LARGE_OFFSET {
        2.0_f64.powi((largest.log2().ceil() as i32).min(1023))
    } else {
        1.0
    }
}

/// The least-squares fit over the kept pairs: rigid, or rotation-only about `centre`.
fn fit(pairs: &[([f64; 2], [f64; 2])], keep: &[bool], centre: Option<[f64; 2]>) -> Option<Fit> {
    let kept: Vec<&([f64; 2], [f64; 2])> = pairs
        .iter()
        .zip(keep)
        .filter(|(_, &k)| k)
        .map(|(p, _)| p)
        .collect();
    if kept.is_empty() {
        return None;
    }
    let n = kept.len() as f64;
    // Rigid: centre each side on its own mean; rotation-only: on the given centre.
    let (pc, qc) = match centre {
        Some(c) => (c, c),
        None => {
            let mean = |side: usize| {
                let sum = kept.iter().fold([0.0, 0.0], |acc, pq| {
                    let v = if side == 0 { pq.0 } else { pq.1 };
                    [acc[0] + v[0], acc[1] + v[1]]
                });
                if sum.iter().all(|v| v.is_finite()) {
                    [sum[0] / n, sum[1] / n]
                } else {
                    // Positions near the float64 limit: average the fractions instead.
                    kept.iter().fold([0.0, 0.0], |acc, pq| {
                        let v = if side == 0 { pq.0 } else { pq.1 };
                        [acc[0] + v[0] / n, acc[1] + v[1] / n]
                    })
                }
            };
            (mean(0), mean(1))
        }
    };
    let scale = product_scale(&kept, pc, qc);
    let (mut a, mut b, mut spp, mut sqq) = (0.0, 0.0, 0.0, 0.0);
    for &&(p, q) in &kept {
        let (px, py) = ((p[0] - pc[0]) / scale, (p[1] - pc[1]) / scale);
        let (qx, qy) = ((q[0] - qc[0]) / scale, (q[1] - qc[1]) / scale);
        a += px * qx + py * qy;
        b += py * qx - px * qy;
        spp += px * px + py * py;
        sqq += qx * qx + qy * qy;
    }
    let rotation = b.atan2(a);
    let (c, s) = (rotation.cos(), rotation.sin());
    // Rigid: the fitted centroids; rotation-only about c: `c − R c`, a turn about c.
    let translation = [
        pc[0] - (c * qc[0] - s * qc[1]),
        pc[1] - (s * qc[0] + c * qc[1]),
    ];
    let residual = (spp + sqq - 2.0 * a.hypot(b)).max(0.0);
    let dof = if centre.is_some() {
        2.0 * n - 1.0
    } else {
        2.0 * n - 3.0
    };
    let residual_std = if dof > 0.0 {
        (residual / dof).sqrt() * scale
    } else {
        f64::NAN
    };
    Some(Fit {
        estimate: BiasEstimate {
            rotation,
            // The cluster-robust values replace these (`robust_std`).
            rotation_std: f64::NAN,
            translation,
            pairs: kept.len(),
            clusters: 0,
            centre: qc,
            centre_std: f64::NAN,
            residual_std,
            reliable: false,
        },
    })
}
