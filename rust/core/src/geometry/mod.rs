//! Angles, the measurement model (METHODS §0) and line-of-sight geometry.

pub mod angles;
pub mod fastmath;
pub mod los;
pub mod model;
