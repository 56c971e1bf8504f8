//! Each radar's bias relative to the system picture, from the associated pairs (beyond the
//! paper; METHODS §4, paper line 150: association "gives prior information for
//! registration").
//!
//! A local picture is the system picture turned by the two radars' relative azimuth bias Δ
//! and shifted: with biases b (local radar at r) and b₁ (system radar at r₁), a target seen at
//! `q` by the system is seen at `p = R(Δ) q + t`, `Δ = b − b₁`, `t = r − R(Δ) r₁ + R(b)(r₁ − r)`.
//! So the least-squares rigid fit of local onto system positions (2-D Procrustes) estimates
//! Δ; a rotation-only fit about a known centre is the option for a system picture without
//! bias. Pairs from every scan are pooled through running sums (positions relative to the
//! first pair's, so the sums stay well conditioned); the rotation's standard deviation is
//! `sqrt(s² / Σ|q − q̄|²)` with `s²` the residual variance per coordinate.

/// The fitted transform `p ≈ R(rotation)·q + translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiasEstimate {
    /// Δ, radians, counter-clockwise (the azimuth convention of METHODS §0).
    pub rotation: f64,
    /// Standard deviation of `rotation` (NaN with fewer than 3 pairs).
    pub rotation_std: f64,
    /// Metres; zero for a rotation-only fit.
    pub translation: [f64; 2],
    pub pairs: usize,
}

/// Running sums of matched positions (local `p`, system `q`).
#[derive(Debug, Clone, Default)]
pub struct BiasAccumulator {
    origin: Option<([f64; 2], [f64; 2])>,
    n: f64,
    sp: [f64; 2],
    sq: [f64; 2],
    /// Σ p_x q_x, Σ p_y q_y, Σ p_y q_x, Σ p_x q_y.
    cross: [f64; 4],
    pp: f64,
    qq: f64,
}

impl BiasAccumulator {
    /// Adds one matched pair.
    pub fn add(&mut self, p: [f64; 2], q: [f64; 2]) {
        let (po, qo) = *self.origin.get_or_insert((p, q));
        let (p, q) = ([p[0] - po[0], p[1] - po[1]], [q[0] - qo[0], q[1] - qo[1]]);
        self.n += 1.0;
        for k in 0..2 {
            self.sp[k] += p[k];
            self.sq[k] += q[k];
        }
        self.cross[0] += p[0] * q[0];
        self.cross[1] += p[1] * q[1];
        self.cross[2] += p[1] * q[0];
        self.cross[3] += p[0] * q[1];
        self.pp += p[0] * p[0] + p[1] * p[1];
        self.qq += q[0] * q[0] + q[1] * q[1];
    }

    pub fn pairs(&self) -> usize {
        self.n as usize
    }

    /// The rigid (rotation + translation) least-squares fit; `None` without pairs.
    pub fn rigid(&self) -> Option<BiasEstimate> {
        let (po, qo) = self.origin?;
        let n = self.n;
        let (mp, mq) = (
            [self.sp[0] / n, self.sp[1] / n],
            [self.sq[0] / n, self.sq[1] / n],
        );
        // Centred sums: Σ (p − p̄)(q − q̄) etc.
        let a = self.cross[0] + self.cross[1] - n * (mp[0] * mq[0] + mp[1] * mq[1]);
        let b = self.cross[2] - self.cross[3] - n * (mp[1] * mq[0] - mp[0] * mq[1]);
        let spp = self.pp - n * (mp[0] * mp[0] + mp[1] * mp[1]);
        let sqq = self.qq - n * (mq[0] * mq[0] + mq[1] * mq[1]);
        let rotation = b.atan2(a);
        let (c, s) = (rotation.cos(), rotation.sin());
        // p̄ and q̄ in the caller's frame, then t = p̄ − R q̄.
        let (pbar, qbar) = (
            [mp[0] + po[0], mp[1] + po[1]],
            [mq[0] + qo[0], mq[1] + qo[1]],
        );
        let translation = [
            pbar[0] - (c * qbar[0] - s * qbar[1]),
            pbar[1] - (s * qbar[0] + c * qbar[1]),
        ];
        let residual = (spp + sqq - 2.0 * a.hypot(b)).max(0.0);
        let dof = 2.0 * n - 3.0;
        Some(BiasEstimate {
            rotation,
            rotation_std: rotation_std(residual, dof, sqq),
            translation,
            pairs: self.pairs(),
        })
    }

    /// The rotation-only fit about `centre` (`p − c ≈ R (q − c)`); `None` without pairs.
    pub fn about(&self, centre: [f64; 2]) -> Option<BiasEstimate> {
        let (po, qo) = self.origin?;
        let n = self.n;
        // Re-centre the sums on `centre`: p' = p + (po − c), likewise q'.
        let (dp, dq) = (
            [po[0] - centre[0], po[1] - centre[1]],
            [qo[0] - centre[0], qo[1] - centre[1]],
        );
        let xx = self.cross[0] + dp[0] * self.sq[0] + dq[0] * self.sp[0] + n * dp[0] * dq[0];
        let yy = self.cross[1] + dp[1] * self.sq[1] + dq[1] * self.sp[1] + n * dp[1] * dq[1];
        let yx = self.cross[2] + dp[1] * self.sq[0] + dq[0] * self.sp[1] + n * dp[1] * dq[0];
        let xy = self.cross[3] + dp[0] * self.sq[1] + dq[1] * self.sp[0] + n * dp[0] * dq[1];
        let pp = self.pp
            + 2.0 * (dp[0] * self.sp[0] + dp[1] * self.sp[1])
            + n * (dp[0] * dp[0] + dp[1] * dp[1]);
        let qq = self.qq
            + 2.0 * (dq[0] * self.sq[0] + dq[1] * self.sq[1])
            + n * (dq[0] * dq[0] + dq[1] * dq[1]);
        let (a, b) = (xx + yy, yx - xy);
        let residual = (pp + qq - 2.0 * a.hypot(b)).max(0.0);
        Some(BiasEstimate {
            rotation: b.atan2(a),
            rotation_std: rotation_std(residual, 2.0 * n - 1.0, qq),
            translation: [0.0, 0.0],
            pairs: self.pairs(),
        })
    }
}

fn rotation_std(residual: f64, dof: f64, spread: f64) -> f64 {
    if dof <= 0.0 || spread <= 0.0 {
        return f64::NAN;
    }
    (residual / dof / spread).sqrt()
}
