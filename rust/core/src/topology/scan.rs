//! One source's tracks at one scan: the associator's input, validated once.

use crate::error::{ensure_finite, CoreError, CoreResult};

/// Borrowed columns of one scan: track ids, planar positions `(n, 2)` row-major and, for
/// the heading-referenced grid, planar velocities `(n, 2)`.
#[derive(Debug, Clone, Copy)]
pub struct ScanTracks<'a> {
    ids: &'a [i64],
    positions: &'a [f64],
    velocities: Option<&'a [f64]>,
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
        })
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
