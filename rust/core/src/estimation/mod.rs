//! Estimation: batched Gauss-Newton ML fitting ([`fit`]) and the Fisher information and CRLB
//! ([`fisher`]) of METHODS §1 and §6; batched Kalman filtering of measurements into local
//! tracks ([`kalman`]), shared by §4 and §5.

pub mod fisher;
pub mod fit;
pub mod kalman;
