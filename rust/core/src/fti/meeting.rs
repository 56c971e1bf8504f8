//! A meeting of a sensor pair's two rays, located: the point, its covariance and its time.
//! The round gate makes them (`round_gate.rs`) and the witness gate reads them
//! (`witness_gate.rs`).

/// A 3 × 3 covariance (the third row and column unused in 2-D).
pub(super) type Matrix = [[f64; 3]; 3];

/// A meeting with its covariance and time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Located3 {
    pub(super) point: [f64; 3],
    pub(super) covariance: Matrix,
    pub(super) time: f64,
}
