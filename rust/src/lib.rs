//! `passive_assoc` core: data association and track initiation for passive (angle-only)
//! sensor networks. Everything here is plain Rust; the Python bindings live in [`py`] alone.

pub mod angles;
pub mod assign;
pub mod data;
pub mod error;
pub mod fastmath;
pub mod fisher;
pub mod fit;
pub mod initiation;
pub mod los;
pub mod model;
pub mod parallel;
pub mod py;
pub mod static_assoc;
