//! Estimation: batched Gauss-Newton ML fitting ([`fit`]) and the Fisher information and CRLB
//! ([`fisher`]) of METHODS §1 and §6.

pub mod fisher;
pub mod fit;
