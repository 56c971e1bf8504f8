//! `passive_assoc_core`: data association and track initiation for passive (angle-only)
//! sensor networks, in plain Rust. The Python bindings are a separate crate (`rust`, sources in `rust/src`) that
//! depends on this one; nothing here knows about Python.
//!
//! Layers, dependencies pointing down only:
//! * [`fti`], [`static_los`], [`formation`], [`topology`], [`radar_esm`] — one folder per
//!   published method (METHODS §1–§5);
//! * [`assign`] — 2-D and S-D assignment solvers every method ends in;
//! * [`estimation`] — Gauss-Newton ML fitting and the Fisher information / CRLB;
//! * [`geometry`] — angles, the measurement model, line-of-sight geometry;
//! * [`data`], [`evidence`] — validated borrowed views of the measurements, emitter-attribute
//!   evidence;
//! * [`error`], [`parallel`], [`progress`] — the error type, thread pools, progress reports.

pub mod assign;
pub mod data;
pub mod error;
pub mod estimation;
pub mod evidence;
pub mod formation;
pub mod fti;
pub mod geometry;
pub mod parallel;
pub mod progress;
pub mod radar_esm;
pub mod static_los;
pub mod topology;
