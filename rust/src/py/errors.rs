//! The one place where core errors become Python exceptions. Every core variant describes a
//! bad argument value, so all map to `ValueError`; wrong types are rejected by PyO3's own
//! extraction as `TypeError` before the core is reached.

use pyo3::exceptions::PyValueError;
use pyo3::PyErr;

use crate::error::CoreError;

impl From<CoreError> for PyErr {
    fn from(err: CoreError) -> PyErr {
        PyValueError::new_err(err.to_string())
    }
}
