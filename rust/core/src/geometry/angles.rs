//! Angle conventions of METHODS §0.

use std::f64::consts::{PI, TAU};

/// Wraps an angle to (−π, π]. Every angular residual goes through this before it is squared or
/// exponentiated, so that a bearing of 179° against a prediction of −179° is a 2° error.
///
/// ```
/// use passive_assoc_core::geometry::angles::wrap;
/// assert!((wrap(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
/// assert_eq!(wrap(-std::f64::consts::PI), std::f64::consts::PI);
/// ```
#[inline]
pub fn wrap(angle: f64) -> f64 {
    // Residuals are nearly always already in range: skip the division on that path.
    if angle > -PI && angle <= PI {
        angle
    } else {
        angle - TAU * ((angle - PI) / TAU).ceil()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_stays_in_half_open_interval() {
        for k in -2000..2000 {
            let a = k as f64 * 0.0137;
            let w = wrap(a);
            assert!(w > -PI && w <= PI, "{a} -> {w}");
            let turns = (a - w) / TAU;
            assert!((turns - turns.round()).abs() < 1e-9);
        }
    }
}
