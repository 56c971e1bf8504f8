//! Kalman filtering of measurements into local tracks (shared by METHODS §4 and §5): many
//! independent tracks in one call, in parallel.
//!
//! Pipeline per track: validate the whole input once ([`input`]), start the track from its
//! first measurements ([`init`]), then for every further row predict over the time step
//! ([`motion`]) and update with the measurement ([`measurement`]) — [`track`] is that loop,
//! [`batch`] runs it over all tracks and puts the results back in row order. Settings are
//! [`KalmanOptions`] ([`options`]); `linalg` has the unrolled fixed-size products.
//!
//! * Motion: constant velocity (`cv`) or constant acceleration (`ca`) in 1, 2 or 3 axes; the
//!   state is in block order `[x, y, z, vx, vy, vz, ax, …]`. Process noise is continuous white
//!   acceleration (CV) or jerk (CA) of spectral density `q`, discretised exactly for each
//!   (possibly different) time step.
//! * Measurements: Cartesian `position` (linear), or 2-D range/azimuth from a per-row sensor
//!   position as an extended Kalman filter (`polar`, azimuth residual wrapped) or converted to
//!   Cartesian first (`polar_converted`). Noise per row: standard deviations or a full
//!   covariance.
//! * Start: `differencing` (default: exact, no prior) or `single_point`.
//! * Output aligned to the input rows: state, covariance and normalised innovation squared;
//!   NaN before a track is initialised (see [`KalmanOutcome`]).
//!
//! Why our own filter and not a library: a Python filter library (FilterPy and the like)
//! costs microseconds of interpreter overhead per predict/update, which dominates when
//! thousands of tracks are filtered per scan, and a general Rust one brings allocation per
//! call or a dynamic-size API; the filter itself is a few dozen lines of fixed-size nalgebra
//! (already a dependency), monomorphised per state dimension, with exactly the
//! discretisation, initialisation and angle wrapping this library needs.

pub mod batch;
pub mod init;
pub mod input;
mod linalg;
pub mod measurement;
pub mod motion;
pub mod options;
pub mod track;

#[cfg(test)]
mod tests;

pub use batch::{filters_sequentially, kalman_filter, KalmanOutcome, PARALLEL_TRACKS};
pub use init::Init;
pub use input::{KalmanInput, Noise, Tracks};
pub use measurement::MeasurementModel;
pub use motion::MotionModel;
pub use options::KalmanOptions;
