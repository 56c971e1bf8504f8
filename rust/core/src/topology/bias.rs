//! Each radar's bias relative to the system picture, from the associated pairs (beyond the
//! paper; METHODS §4, paper line 150: association "gives prior information for
//! registration").
//!
//! A local picture is the system picture turned by the two radars' relative azimuth bias Δ
//! and shifted: with biases b (local radar at r) and b₁ (system radar at r₁), a target seen at
//! `q` by the system is seen at `p = R(Δ) q + t`, `Δ = b − b₁`, `t = r − R(Δ) r₁ + R(b)(r₁ − r)`.
//! So the least-squares rigid fit of local onto system positions (2-D Procrustes) estimates
//! Δ; a rotation-only fit about a known centre is the option for a system picture without
//! bias. Pairs from every scan are pooled. Wrong pairs (a target the system radar does not
//! see, paired with a neighbour kilometres away) would drag a plain least-squares fit, so the
//! fit is trimmed: pairs whose residual exceeds `TRIM_SIGMAS` robust standard deviations
//! (1.4826 × the median residual) are dropped and the fit repeated, until the kept set stops
//! changing. The rotation's standard deviation is `sqrt(s² / Σ|q − q̄|²)` over the kept pairs,
//! `s²` their residual variance per coordinate.

/// The fitted transform `p ≈ R(rotation)·q + translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiasEstimate {
    /// Δ, radians, counter-clockwise (the azimuth convention of METHODS §0).
    pub rotation: f64,
    /// Standard deviation of `rotation` (NaN with fewer than 3 pairs).
    pub rotation_std: f64,
    /// Metres; zero for a rotation-only fit.
    pub translation: [f64; 2],
    /// Pairs the final fit kept (after trimming).
    pub pairs: usize,
}

/// Residuals beyond this many robust standard deviations are trimmed.
pub const TRIM_SIGMAS: f64 = 3.0;

/// Trimming rounds at most (each drops pairs or ends the loop).
const MAX_ROUNDS: usize = 10;

/// Matched positions (local `p`, system `q`), pooled over the scans.
#[derive(Debug, Clone, Default)]
pub struct BiasAccumulator {
    pairs: Vec<([f64; 2], [f64; 2])>,
}

impl BiasAccumulator {
    /// Adds one matched pair.
    pub fn add(&mut self, p: [f64; 2], q: [f64; 2]) {
        self.pairs.push((p, q));
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
        Some(fit.estimate)
    }
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
    let translation = match centre {
        Some(_) => [0.0, 0.0],
        None => [
            pc[0] - (c * qc[0] - s * qc[1]),
            pc[1] - (s * qc[0] + c * qc[1]),
        ],
    };
    let residual = (spp + sqq - 2.0 * a.hypot(b)).max(0.0);
    let dof = if centre.is_some() {
        2.0 * n - 1.0
    } else {
        2.0 * n - 3.0
    };
    let rotation_std = if dof > 0.0 && sqq > 0.0 {
        (residual / dof / sqq).sqrt()
    } else {
        f64::NAN
    };
    Some(Fit {
        estimate: BiasEstimate {
            rotation,
            rotation_std,
            translation,
            pairs: kept.len(),
        },
    })
}
