//! The binding layer: the only code that knows about Python. Each function extracts NumPy
//! input under the GIL, releases the GIL (`py.detach`) while the core works, and hands the
//! core's vectors to NumPy without copying. Core errors become exceptions in `errors`.

mod assign;
mod convert;
mod errors;
mod fit;
mod initiation;
mod static_assoc;

use pyo3::prelude::*;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(fit::fit_batch, m)?)?;
    m.add_function(wrap_pyfunction!(fit::crlb, m)?)?;
    m.add_function(wrap_pyfunction!(assign::assign_sd, m)?)?;
    m.add_function(wrap_pyfunction!(assign::assign_2d, m)?)?;
    m.add_function(wrap_pyfunction!(initiation::initiate, m)?)?;
    m.add_function(wrap_pyfunction!(initiation::closeness, m)?)?;
    m.add_function(wrap_pyfunction!(initiation::maximize_closeness, m)?)?;
    m.add_function(wrap_pyfunction!(static_assoc::enumerate_static, m)?)?;
    m.add_function(wrap_pyfunction!(static_assoc::intensity_search, m)?)?;
    Ok(())
}
