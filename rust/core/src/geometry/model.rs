//! The passive measurement model of METHODS §0: what a sensor at `p_j` measures of a point,
//! and how that changes with the point and with a constant-velocity initial state.

use crate::error::{parse_option, CoreError, CoreResult, UnknownOption};
use crate::geometry::fastmath;

/// What each sensor measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Space {
    /// 2-D: bearing `θ = atan2(y − y_j, x − x_j)` only; targets live in the plane z = 0.
    Planar,
    /// 3-D: azimuth `β` and elevation `ε = atan2(z − z_j, hypot(x − x_j, y − y_j))`.
    Spatial,
}

impl Space {
    /// Angles per measurement (1 or 2).
    pub fn angles(self) -> usize {
        match self {
            Space::Planar => 1,
            Space::Spatial => 2,
        }
    }

    /// Position coordinates (2 or 3).
    pub fn position_dim(self) -> usize {
        match self {
            Space::Planar => 2,
            Space::Spatial => 3,
        }
    }
}

/// How the unknown state maps to a position at time t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// The state is the position itself.
    Static,
    /// The state is `X0 = (position at t0, velocity)`.
    ConstantVelocity { t0: f64 },
}

/// The motion model by name, before its epoch is known: `"static"` or `"cv"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionKind {
    Static,
    ConstantVelocity,
}

impl std::str::FromStr for MotionKind {
    type Err = UnknownOption;

    /// `"static"` or `"cv"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [("static", Self::Static), ("cv", Self::ConstantVelocity)];
        parse_option(value, &choices, "'static' or 'cv'")
    }
}

impl MotionKind {
    /// The motion with its epoch; `t0` must be finite for constant velocity (unused for a
    /// static state).
    ///
    /// ```
    /// use passive_assoc_core::geometry::model::{Motion, MotionKind};
    /// let cv: MotionKind = "cv".parse().unwrap();
    /// assert_eq!(cv.at(5.0).unwrap(), Motion::ConstantVelocity { t0: 5.0 });
    /// assert!(cv.at(f64::NAN).is_err());
    /// assert!("spline".parse::<MotionKind>().is_err());
    /// ```
    pub fn at(self, t0: f64) -> CoreResult<Motion> {
        match self {
            Self::Static => Ok(Motion::Static),
            Self::ConstantVelocity if t0.is_finite() => Ok(Motion::ConstantVelocity { t0 }),
            Self::ConstantVelocity => Err(CoreError::out_of_range(
                "t0",
                format!("must be finite, got {t0}"),
            )),
        }
    }
}

/// A state parameterisation: the space and the motion. Its dimension is 2, 3, 4 or 6.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateLayout {
    pub space: Space,
    pub motion: Motion,
}

/// The largest state dimension (3-D constant velocity); buffers are sized by it.
pub const MAX_DIM: usize = 6;

impl StateLayout {
    pub fn new(space: Space, motion: Motion) -> Self {
        Self { space, motion }
    }

    pub fn dim(&self) -> usize {
        let p = self.space.position_dim();
        match self.motion {
            Motion::Static => p,
            Motion::ConstantVelocity { .. } => 2 * p,
        }
    }

    /// Elapsed time since the state's epoch (0 for a static state).
    #[inline]
    fn elapsed(&self, time: f64) -> f64 {
        match self.motion {
            Motion::Static => 0.0,
            Motion::ConstantVelocity { t0 } => time - t0,
        }
    }

    /// Target position at `time` (z = 0 in the plane).
    #[inline]
    pub fn position(&self, state: &[f64], time: f64) -> [f64; 3] {
        let p = self.space.position_dim();
        let dt = self.elapsed(time);
        let mut out = [0.0; 3];
        for (k, o) in out.iter_mut().enumerate().take(p) {
            *o = match self.motion {
                Motion::Static => state[k],
                Motion::ConstantVelocity { .. } => state[k] + dt * state[p + k],
            };
        }
        out
    }

    /// Chain rule: the gradient of a scalar with respect to the state, given its gradient with
    /// respect to the position at `time`. Entries past `dim()` are zero.
    #[inline(always)]
    pub fn state_gradient(&self, position_gradient: &[f64; 3], time: f64) -> [f64; MAX_DIM] {
        let p = self.space.position_dim();
        let mut out = [0.0; MAX_DIM];
        out[..p].copy_from_slice(&position_gradient[..p]);
        if let Motion::ConstantVelocity { .. } = self.motion {
            let dt = self.elapsed(time);
            for k in 0..p {
                out[p + k] = dt * position_gradient[k];
            }
        }
        out
    }
}

/// Predicted angles of `target` seen from `sensor`: `[azimuth, elevation]` (elevation 0 in the
/// plane).
#[inline]
pub fn predict(space: Space, sensor: &[f64; 3], target: &[f64; 3]) -> [f64; 2] {
    let dx = target[0] - sensor[0];
    let dy = target[1] - sensor[1];
    let azimuth = dy.atan2(dx);
    match space {
        Space::Planar => [azimuth, 0.0],
        Space::Spatial => [azimuth, (target[2] - sensor[2]).atan2(dx.hypot(dy))],
    }
}

/// The sensor-to-target vector, its horizontal range (spatial only) and the angle gradients, computed once
/// and with one division per angle: divisions, not multiplications, bound the residual
/// kernel's latency.
#[derive(Clone, Copy)]
struct LineOfSight {
    delta: [f64; 3],
    rho: f64,
    gradient: [[f64; 3]; 2],
}

#[inline(always)]
fn line_of_sight(space: Space, sensor: &[f64; 3], target: &[f64; 3]) -> Option<LineOfSight> {
    let delta: [f64; 3] = std::array::from_fn(|k| target[k] - sensor[k]);
    let [dx, dy, dz] = delta;
    let rho2 = dx * dx + dy * dy;
    if rho2 <= 0.0 || !rho2.is_finite() {
        return None;
    }
    let inv_rho2 = 1.0 / rho2;
    let d_azimuth = [-dy * inv_rho2, dx * inv_rho2, 0.0];
    if space == Space::Planar {
        return Some(LineOfSight {
            delta,
            rho: 0.0, // only elevation needs it
            gradient: [d_azimuth, [0.0; 3]],
        });
    }
    let rho = rho2.sqrt();
    let r2 = rho2 + dz * dz;
    let k = 1.0 / (r2 * rho);
    let d_elevation = [-dx * dz * k, -dy * dz * k, rho2 * k];
    Some(LineOfSight {
        delta,
        rho,
        gradient: [d_azimuth, d_elevation],
    })
}

/// Normalised residuals `wrap(z − h)/σ` of one measurement and their state gradients
/// `(∂h/∂X)/σ` — one row per measured angle. The rows are what Gauss-Newton, the Fisher
/// information and the χ² gates all consume.
#[derive(Clone, Copy, Debug)]
pub struct ResidualRows {
    pub count: usize,
    pub residual: [f64; 2],
    pub gradient: [[f64; MAX_DIM]; 2],
}

/// One measurement as the model sees it, with the cosine and sine of each measured angle
/// cached: they turn every residual into the arctangent of a small angle (see
/// [`residual_rows`]), computed once per measurement instead of once per evaluation.
#[derive(Clone, Copy, Debug)]
pub struct Observation {
    pub sensor: [f64; 3],
    pub time: f64,
    pub angles: [f64; 2],
    pub sigma: [f64; 2],
    /// `[cos, sin]` of each of `angles`.
    unit: [[f64; 2]; 2],
    /// `1/σ`, so the kernel multiplies instead of dividing.
    inv_sigma: [f64; 2],
}

impl Observation {
    pub fn new(sensor: [f64; 3], time: f64, angles: [f64; 2], sigma: [f64; 2]) -> Self {
        let unit = angles.map(|a| {
            let (s, c) = a.sin_cos();
            [c, s]
        });
        Self {
            sensor,
            time,
            angles,
            sigma,
            unit,
            inv_sigma: sigma.map(|v| 1.0 / v),
        }
    }

    /// `[cos, sin]` of each measured angle (azimuth, then elevation), computed once.
    pub fn cos_sin(&self) -> [[f64; 2]; 2] {
        self.unit
    }

    /// The unit line of sight `[cos ε·cos β, cos ε·sin β, sin ε]` (the bearing's unit vector
    /// in the plane, z = 0, in 2-D where ε = 0), from the cached cosines and sines.
    pub fn line_of_sight(&self) -> [f64; 3] {
        let ([ca, sa], [ce, se]) = (self.unit[0], self.unit[1]);
        [ce * ca, ce * sa, se]
    }
}

/// `wrap(z − atan2(v, u))` as `atan2(sin z·u − cos z·v, cos z·u + sin z·v)`: the same angle
/// (the rotation of (u, v) by −z), already in (−π, π], and near a solution the arctangent of
/// a small angle with a positive cosine — the fast path of [`fastmath::atan2`].
#[inline(always)]
fn angle_residual(unit: &[f64; 2], u: f64, v: f64) -> f64 {
    let [c, s] = *unit;
    fastmath::atan2(s * u - c * v, c * u + s * v)
}

/// Normalised residuals and their gradients with respect to the *position* at the
/// observation time, before the chain rule to the state: what the constant-velocity
/// normal equations accumulate per measurement (see `fit::gauss_newton`).
#[derive(Clone, Copy, Debug)]
pub struct PositionRows {
    pub count: usize,
    pub residual: [f64; 2],
    pub gradient: [[f64; 3]; 2],
}

/// [`PositionRows`] of `obs` at `state`, or `None` at a non-differentiable geometry.
#[inline(always)]
pub fn position_rows(
    layout: &StateLayout,
    state: &[f64],
    obs: &Observation,
) -> Option<PositionRows> {
    let target = layout.position(state, obs.time);
    match layout.space {
        Space::Spatial => position_rows_at::<true>(&target, obs),
        Space::Planar => position_rows_at::<false>(&target, obs),
    }
}

/// [`position_rows`] of a target at `target`, in 3-D (`SPATIAL`) or in the plane: the space
/// fixed at compile time, for loops that call it once per measurement (the constant-velocity
/// fit), where the runtime layout's branches cost more than the arithmetic.
#[inline(always)]
pub fn position_rows_at<const SPATIAL: bool>(
    target: &[f64; 3],
    obs: &Observation,
) -> Option<PositionRows> {
    let space = if SPATIAL {
        Space::Spatial
    } else {
        Space::Planar
    };
    let los = line_of_sight(space, &obs.sensor, target)?;
    let [dx, dy, dz] = los.delta;
    let mut rows = PositionRows {
        count: space.angles(),
        residual: [0.0; 2],
        gradient: [[0.0; 3]; 2],
    };
    let w = obs.inv_sigma;
    rows.residual[0] = angle_residual(&obs.unit[0], dx, dy) * w[0];
    rows.gradient[0] = los.gradient[0].map(|g| g * w[0]);
    if SPATIAL {
        rows.residual[1] = angle_residual(&obs.unit[1], los.rho, dz) * w[1];
        rows.gradient[1] = los.gradient[1].map(|g| g * w[1]);
    }
    Some(rows)
}

/// Residual rows of `obs` at `state`, or `None` at a non-differentiable geometry.
// Always inlined: returned by value it is a 120-byte copy per measurement in the fit loop.
#[inline(always)]
pub fn residual_rows(
    layout: &StateLayout,
    state: &[f64],
    obs: &Observation,
) -> Option<ResidualRows> {
    let position = position_rows(layout, state, obs)?;
    let mut rows = ResidualRows {
        count: position.count,
        residual: position.residual,
        gradient: [[0.0; MAX_DIM]; 2],
    };
    for c in 0..position.count {
        rows.gradient[c] = layout.state_gradient(&position.gradient[c], obs.time);
    }
    Some(rows)
}

/// The state gradients of [`residual_rows`] without the residuals (so without an
/// arctangent), for callers that need only how sure a prediction is: `(count, gradient)`.
// Always inlined: the support gates call it millions of times a run, and out of line its
// 100-byte result and the layout's branches cost more than its arithmetic.
#[inline(always)]
pub fn gradient_rows(
    layout: &StateLayout,
    state: &[f64],
    obs: &Observation,
) -> Option<(usize, [[f64; MAX_DIM]; 2])> {
    let target = layout.position(state, obs.time);
    let los = line_of_sight(layout.space, &obs.sensor, &target)?;
    let count = layout.space.angles();
    let mut gradient = [[0.0; MAX_DIM]; 2];
    for (c, row) in gradient.iter_mut().enumerate().take(count) {
        let w = obs.inv_sigma[c];
        *row = layout.state_gradient(&los.gradient[c].map(|g| g * w), obs.time);
    }
    Some((count, gradient))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layouts() -> Vec<StateLayout> {
        let cv = Motion::ConstantVelocity { t0: 2.0 };
        vec![
            StateLayout::new(Space::Planar, Motion::Static),
            StateLayout::new(Space::Spatial, Motion::Static),
            StateLayout::new(Space::Planar, cv),
            StateLayout::new(Space::Spatial, cv),
        ]
    }

    #[test]
    fn gradient_rows_are_the_residual_rows_gradients() {
        let state = [1200.0, 8000.0, 900.0, 150.0, -80.0, 5.0];
        let obs = Observation::new([300.0, -200.0, 10.0], 37.0, [1.2, 0.1], [0.005, 0.007]);
        for layout in layouts() {
            let d = layout.dim();
            let rows = residual_rows(&layout, &state[..d], &obs).expect("regular geometry");
            let (count, gradient) = gradient_rows(&layout, &state[..d], &obs).expect("regular");
            assert_eq!((count, gradient), (rows.count, rows.gradient));
        }
        let on_axis = Observation::new([1200.0, 8000.0, 0.0], 0.0, [0.0; 2], [1.0; 2]);
        let planar = StateLayout::new(Space::Planar, Motion::Static);
        assert!(gradient_rows(&planar, &state[..2], &on_axis).is_none());
    }

    #[test]
    fn gradients_match_central_differences() {
        let state = [1200.0, 8000.0, 900.0, 150.0, -80.0, 5.0];
        let obs = Observation::new([300.0, -200.0, 10.0], 37.0, [1.2, 0.1], [0.005, 0.007]);
        for layout in layouts() {
            let d = layout.dim();
            let rows = residual_rows(&layout, &state[..d], &obs).expect("regular geometry");
            for k in 0..d {
                let h = 1e-4 * state[k].abs().max(1.0);
                let (mut up, mut down) = (state, state);
                up[k] += h;
                down[k] -= h;
                let r_up = residual_rows(&layout, &up[..d], &obs).expect("regular");
                let r_down = residual_rows(&layout, &down[..d], &obs).expect("regular");
                for c in 0..rows.count {
                    // residual = (z − h)/σ, so ∂residual/∂x = −gradient.
                    let numeric = -(r_up.residual[c] - r_down.residual[c]) / (2.0 * h);
                    let analytic = rows.gradient[c][k];
                    assert!(
                        (numeric - analytic).abs() <= 1e-6 * analytic.abs().max(1e-3),
                        "{layout:?} angle {c} component {k}: {numeric} vs {analytic}"
                    );
                }
            }
        }
    }

    #[test]
    fn vertical_axis_is_reported_not_divided_by_zero() {
        let layout = StateLayout::new(Space::Spatial, Motion::Static);
        let obs = Observation::new([1.0, 2.0, 0.0], 0.0, [0.0, 0.0], [1.0, 1.0]);
        assert!(residual_rows(&layout, &[1.0, 2.0, 5.0], &obs).is_none());
    }
}
