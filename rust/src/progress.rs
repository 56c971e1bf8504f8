//! The core's progress reports, forwarded to a Python callable `progress(stage, fraction)` (the
//! package's `_progress.StageBar`, or a user's own). The callable runs under the GIL, taken for
//! each report a core thread forwards: at most one every [`INTERVAL`] within a stage, and every
//! change of stage and every stage's end, so a bar costs the call nothing measurable.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use pyo3::prelude::*;

use passive_assoc_core::error::{CoreError, CoreResult};
use passive_assoc_core::progress::{Progress, Silent};

use super::errors::BindResult;

/// Least time between two reports of one stage that reach Python.
const INTERVAL: Duration = Duration::from_millis(200);

/// A binding's optional `progress` argument as the core sees it: the callable's sink, or
/// [`Silent`] without one.
pub struct Sink(Option<PyProgress>);

impl Sink {
    pub fn new(callback: Option<Py<PyAny>>) -> Self {
        Self(callback.map(PyProgress::new))
    }

    pub fn progress(&self) -> &dyn Progress {
        match &self.0 {
            Some(sink) => sink,
            None => &Silent,
        }
    }

    /// The call's answer, once it is over. When the callable raised, the call stopped early
    /// (it ends as interrupted) and the callable's error is raised; otherwise the call's own
    /// error, which names the input, comes first.
    pub fn settle<R>(self, result: CoreResult<R>) -> BindResult<R> {
        let raised = self.0.and_then(PyProgress::into_error);
        match (result, raised) {
            (Err(CoreError::Interrupted) | Ok(_), Some(error)) => Err(error.into()),
            (result, _) => Ok(result?),
        }
    }
}

/// A Python callable as a core progress sink. The first error the callable raises is kept
/// (later reports are dropped), the call is asked to stop, and the binding raises the error.
#[derive(Debug)]
struct PyProgress {
    callback: Py<PyAny>,
    state: Mutex<Forwarded>,
    /// Set once the callable raised: polled by the core's loops, so without the lock.
    failed: AtomicBool,
}

#[derive(Debug, Default)]
struct Forwarded {
    last: Option<(Instant, &'static str)>,
    error: Option<PyErr>,
}

impl PyProgress {
    fn new(callback: Py<PyAny>) -> Self {
        Self {
            callback,
            state: Mutex::new(Forwarded::default()),
            failed: AtomicBool::new(false),
        }
    }

    /// What the callable raised, if it did.
    fn into_error(self) -> Option<PyErr> {
        self.state.into_inner().ok().and_then(|state| state.error)
    }
}

impl Progress for PyProgress {
    fn report(&self, stage: &'static str, fraction: f64) {
        // A poisoned lock (a panic while reporting) only ends the reports.
        let Ok(mut state) = self.state.lock() else {
            return;
        };
        let now = Instant::now();
        let recent = state.last.is_some_and(|(at, last)| {
            last == stage && now.duration_since(at) < INTERVAL && fraction < 1.0
        });
        if state.error.is_some() || recent {
            return;
        }
        state.last = Some((now, stage));
        let called = Python::attach(|py| self.callback.call1(py, (stage, fraction)).map(drop));
        if let Err(error) = called {
            state.error = Some(error);
            self.failed.store(true, Ordering::Relaxed);
        }
    }

    fn cancelled(&self) -> bool {
        self.failed.load(Ordering::Relaxed)
    }
}
