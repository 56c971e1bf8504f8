//! The binding layer: the only code that knows about Python. Each function extracts typed
//! input under the GIL (the `SensorNetwork`, `MeasurementTable` and settings objects are read
//! by attribute), releases the GIL (`py.detach`) while the core works, and hands the core's
//! vectors to NumPy without copying, as arrays or frozen result objects.

mod assign;
mod batch;
mod convert;
mod defaults;
mod errors;
mod fit;
mod formation;
mod fti;
mod interrupt;
mod kalman;
mod progress;
mod radar_esm;
mod static_los;
mod topology;

use pyo3::prelude::*;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    interrupt::install(m.py())?;
    m.add_function(wrap_pyfunction!(fit::fit_batch, m)?)?;
    m.add_function(wrap_pyfunction!(fit::crlb, m)?)?;
    m.add_function(wrap_pyfunction!(assign::assign_sd, m)?)?;
    m.add_function(wrap_pyfunction!(assign::assign_2d, m)?)?;
    m.add_function(wrap_pyfunction!(assign::assign_2d_sparse, m)?)?;
    m.add_function(wrap_pyfunction!(batch::associate_scans, m)?)?;
    m.add_function(wrap_pyfunction!(
        static_los::default_false_alarm_density,
        m
    )?)?;
    m.add_function(wrap_pyfunction!(fti::initiate, m)?)?;
    m.add_function(wrap_pyfunction!(fti::closeness, m)?)?;
    m.add_function(wrap_pyfunction!(fti::maximize_closeness, m)?)?;
    m.add_function(wrap_pyfunction!(static_los::enumerate_static, m)?)?;
    m.add_function(wrap_pyfunction!(static_los::intensity_search, m)?)?;
    m.add_function(wrap_pyfunction!(formation::locate_formation, m)?)?;
    m.add_function(wrap_pyfunction!(kalman::kalman_filter, m)?)?;
    m.add_function(wrap_pyfunction!(topology::topology_vectors, m)?)?;
    m.add_function(wrap_pyfunction!(radar_esm::wavelet_coarse_gate, m)?)?;
    m.add_function(wrap_pyfunction!(radar_esm::wavelet_coarse_gate_coupled, m)?)?;
    m.add_function(wrap_pyfunction!(radar_esm::repeated_maximum, m)?)?;
    m.add_function(wrap_pyfunction!(defaults::option_defaults, m)?)?;
    m.add_class::<topology::AssociatorState>()?;
    m.add_class::<topology::ScanPairs>()?;
    m.add_class::<topology::Bias>()?;
    m.add_class::<assign::SdResult>()?;
    m.add_class::<fti::InitiationOutput>()?;
    m.add_class::<fti::StageCounts>()?;
    m.add_class::<fti::StageSeconds>()?;
    m.add_class::<fti::RayNeighbourhood>()?;
    m.add_class::<static_los::Candidates>()?;
    m.add_class::<static_los::EnumerationStages>()?;
    m.add_class::<static_los::IntensityResult>()?;
    m.add_class::<static_los::IntensityLevel>()?;
    m.add_class::<formation::FormationOutputPy>()?;
    m.add_class::<formation::FormationCounts>()?;
    Ok(())
}
