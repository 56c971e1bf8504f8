//! One source's tracks at one scan: the associator's input, validated once.

use crate::error::{ensure_finite, CoreError, CoreResult};

/// Borrowed columns of one scan: track ids, planar positions `(n, 2)` row-major and, for
/// the heading-referenced grid, planar velocities `(n, 2)`. Optionally the heights `(n,)`
/// (the distance of the nearest-neighbour scoring is then taken in 3-D) and each track's
/// position covariance `(n, d, d)`, d = 2, or 3 with heights (for the χ² gate).
#[derive(Debug, Clone, Copy)]
pub struct ScanTracks<'a> {
    ids: &'a [i64],
    positions: &'a [f64],
    velocities: Option<&'a [f64]>,
    heights: Option<&'a [f64]>,
    covariances: Option<&'a [f64]>,
}

impl<'a> ScanTracks<'a> {
    /// Checks lengths, finiteness and that no id repeats (a source reports a track once a
    /// scan). `side` names the argument in errors (`"local"`, `"system"`).
    pub fn new(
        side: &'static str,
        ids: &'a [i64],
        positions: &'a [f64],
        velocities: Option<&'a [f64]>,
    ) -> CoreResult<Self> {
        let n = ids.len();
        if positions.len() != 2 * n {
            return Err(CoreError::shape(
                side,
                format!(
                    "{} position values for {n} tracks; expected (n, 2)",
                    positions.len()
                ),
            ));
        }
        ensure_finite(side, positions)?;
        if let Some(v) = velocities {
            if v.len() != 2 * n {
                return Err(CoreError::shape(
                    side,
                    format!(
                        "{} velocity values for {n} tracks; expected (n, 2)",
                        v.len()
                    ),
                ));
            }
            ensure_finite(side, v)?;
        }
        let mut sorted = ids.to_vec();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(CoreError::ill_posed(
                side,
                format!("track id {} appears twice in one scan", w[0]),
            ));
        }
        Ok(Self {
            ids,
            positions,
            velocities,
            heights: None,
            covariances: None,
        })
    }

    /// The tracks' heights `(n,)`, finite: positions become 3-D for distances and the χ²
    /// gate (the topology grid and the bias stay planar). Give them before covariances.
    pub fn with_heights(mut self, side: &'static str, heights: &'a [f64]) -> CoreResult<Self> {
        if heights.len() != self.len() {
            return Err(CoreError::shape(
                side,
                format!("{} heights for {} tracks", heights.len(), self.len()),
            ));
        }
        ensure_finite(side, heights)?;
        self.heights = Some(heights);
        Ok(self)
    }

    /// Each track's position covariance `(n, d, d)` row-major, finite, d = [`Self::dim`].
    pub fn with_covariances(
        mut self,
        side: &'static str,
        covariances: &'a [f64],
    ) -> CoreResult<Self> {
        let d = self.dim();
        if covariances.len() != self.len() * d * d {
            return Err(CoreError::shape(
                side,
                format!(
                    "{} covariance values for {} tracks; expected (n, {d}, {d})",
                    covariances.len(),
                    self.len()
                ),
            ));
        }
        ensure_finite(side, covariances)?;
        self.covariances = Some(covariances);
        Ok(self)
    }

    /// 3 with heights, else 2.
    pub fn dim(&self) -> usize {
        if self.heights.is_some() {
            3
        } else {
            2
        }
    }

    /// Track `k`'s position in [`Self::dim`] coordinates (the height 0 in 2-D).
    pub fn point(&self, k: usize) -> [f64; 3] {
        let [x, y] = self.position(k);
        [x, y, self.heights.map_or(0.0, |h| h[k])]
    }

    /// Track `k`'s position covariance, `dim × dim` row-major, if the scan carries them.
    pub fn covariance(&self, k: usize) -> Option<&'a [f64]> {
        let d = self.dim();
        self.covariances.map(|c| &c[k * d * d..(k + 1) * d * d])
    }

    pub fn len(&self) -> usize {
        self.ids.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    pub fn ids(&self) -> &'a [i64] {
        self.ids
    }

    pub fn position(&self, k: usize) -> [f64; 2] {
        [self.positions[2 * k], self.positions[2 * k + 1]]
    }

    /// Track `k`'s velocity, if the scan carries velocities.
    pub fn velocity(&self, k: usize) -> Option<[f64; 2]> {
        self.velocities.map(|v| [v[2 * k], v[2 * k + 1]])
    }

    pub fn has_velocities(&self) -> bool {
        self.velocities.is_some()
    }
}
