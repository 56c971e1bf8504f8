//! The one error type of the core. Every fallible core function returns [`CoreResult`]; the
//! binding crate (`rust/src/errors.rs`) maps each variant to a Python exception in one place.

use thiserror::Error;

/// What went wrong, always naming the argument (`arg`) and, where it helps, the position.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CoreError {
    /// An array has the wrong length or shape.
    #[error("{arg}: {reason}")]
    Shape { arg: &'static str, reason: String },

    /// A value is NaN or infinite where a finite number is required.
    #[error("{arg}: non-finite value at index {index}")]
    NonFinite { arg: &'static str, index: usize },

    /// A value is outside its allowed range (negative std, unknown sensor, index out of range...).
    #[error("{arg}: {reason}")]
    OutOfRange { arg: &'static str, reason: String },

    /// The problem as posed cannot be solved (too few measurements, coincident sensors...).
    #[error("{arg}: {reason}")]
    IllPosed { arg: &'static str, reason: String },

    /// Memory for a result that grows with the input could not be had (a `try_reserve` failed):
    /// the bindings raise `MemoryError`, not an abort of the process.
    #[error("{what}: could not allocate memory for {count} entries; {hint}")]
    OutOfMemory {
        what: &'static str,
        count: usize,
        hint: &'static str,
    },

    /// The user asked to stop (`parallel::request_interrupt`, Ctrl-C): a long pipeline ends at
    /// its next stage instead of running later stages on partial results.
    #[error("interrupted")]
    Interrupted,

    /// A configurable resource cap was hit (e.g. too many candidates); raise the cap to go on.
    #[error("{what}: {count} exceeds the cap of {cap}; {hint}")]
    CapExceeded {
        what: &'static str,
        count: usize,
        cap: usize,
        hint: &'static str,
    },
}

impl CoreError {
    pub fn shape(arg: &'static str, reason: impl Into<String>) -> Self {
        Self::Shape {
            arg,
            reason: reason.into(),
        }
    }

    pub fn out_of_range(arg: &'static str, reason: impl Into<String>) -> Self {
        Self::OutOfRange {
            arg,
            reason: reason.into(),
        }
    }

    pub fn ill_posed(arg: &'static str, reason: impl Into<String>) -> Self {
        Self::IllPosed {
            arg,
            reason: reason.into(),
        }
    }
}

pub type CoreResult<T> = Result<T, CoreError>;

/// Makes room for one more entry in `vec`, growing it by doubling through `try_reserve`: a
/// failed allocation is [`CoreError::OutOfMemory`] instead of the process aborting.
pub fn reserve_one<T>(vec: &mut Vec<T>, what: &'static str, hint: &'static str) -> CoreResult<()> {
    if vec.len() < vec.capacity() {
        return Ok(());
    }
    reserve(vec, vec.len().max(64), what, hint)
}

/// Makes room for `additional` more entries in `vec` through `try_reserve`: a failed
/// allocation is [`CoreError::OutOfMemory`] instead of the process aborting.
pub fn reserve<T>(
    vec: &mut Vec<T>,
    additional: usize,
    what: &'static str,
    hint: &'static str,
) -> CoreResult<()> {
    vec.try_reserve(additional)
        .map_err(|_| CoreError::OutOfMemory {
            what,
            count: vec.len().saturating_add(additional),
            hint,
        })
}

/// `Ok` for `None` or a finite positive value; otherwise the error naming `arg`.
pub fn ensure_positive(arg: &'static str, value: Option<f64>) -> CoreResult<()> {
    match value {
        Some(v) if !(v.is_finite() && v > 0.0) => Err(CoreError::out_of_range(
            arg,
            format!("{v} must be finite and > 0"),
        )),
        _ => Ok(()),
    }
}

/// Fails with [`CoreError::NonFinite`] at the first NaN/inf of `values`.
pub fn ensure_finite(arg: &'static str, values: &[f64]) -> CoreResult<()> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(CoreError::NonFinite { arg, index }),
        None => Ok(()),
    }
}

/// A string option that names none of its choices; `FromStr` of every option enum returns it,
/// and the caller adds the argument's name.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("must be {expected}, got {got:?}")]
pub struct UnknownOption {
    /// The accepted spellings, e.g. `'auto' or 'given'`.
    pub expected: &'static str,
    pub got: String,
}

/// Parses `value` as one of `choices` (spelling, value), for the option enums' `FromStr`.
pub fn parse_option<T: Copy>(
    value: &str,
    choices: &[(&str, T)],
    expected: &'static str,
) -> Result<T, UnknownOption> {
    choices
        .iter()
        .find(|(name, _)| *name == value)
        .map(|&(_, v)| v)
        .ok_or_else(|| UnknownOption {
            expected,
            got: value.to_string(),
        })
}
