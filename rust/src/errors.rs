//! The one place where core errors become Python exceptions. Every core variant but two
//! describes a bad argument value and maps to `ValueError`; `OutOfMemory` maps to
//! `MemoryError` and `Interrupted` to `KeyboardInterrupt`. Wrong types are rejected by PyO3's
//! own extraction as `TypeError` before the core is reached, or by [`type_error`] where a
//! binding tests the type itself.
//!
//! The orphan rule forbids `impl From<CoreError> for PyErr` outside the core, so the bindings
//! return [`BindResult`], whose error holds either side and converts to `PyErr` at the edge.

use pyo3::exceptions::{PyKeyboardInterrupt, PyMemoryError, PyTypeError, PyValueError};
use pyo3::PyErr;

use passive_assoc_core::error::CoreError;

/// A core error (a bad value, raised as `ValueError`) or an error PyO3 already raised.
pub enum BindError {
    Core(CoreError),
    Python(PyErr),
}

pub type BindResult<T> = Result<T, BindError>;

impl From<CoreError> for BindError {
    fn from(err: CoreError) -> Self {
        BindError::Core(err)
    }
}

impl From<PyErr> for BindError {
    fn from(err: PyErr) -> Self {
        BindError::Python(err)
    }
}

impl From<BindError> for PyErr {
    fn from(err: BindError) -> PyErr {
        match err {
            BindError::Core(core @ CoreError::OutOfMemory { .. }) => {
                PyMemoryError::new_err(core.to_string())
            }
            BindError::Core(CoreError::Interrupted) => PyKeyboardInterrupt::new_err("interrupted"),
            BindError::Core(core) => PyValueError::new_err(core.to_string()),
            BindError::Python(py) => py,
        }
    }
}

/// A `ValueError` naming the argument.
pub fn value_error(arg: &str, problem: impl std::fmt::Display) -> BindError {
    BindError::Python(PyValueError::new_err(format!("{arg}: {problem}")))
}

/// A `TypeError` naming the argument.
pub fn type_error(arg: &str, problem: impl std::fmt::Display) -> BindError {
    BindError::Python(PyTypeError::new_err(format!("{arg}: {problem}")))
}
