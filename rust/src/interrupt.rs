//! Ctrl-C during a compiled call. Python's SIGINT handler only marks the signal; the
//! interpreter raises `KeyboardInterrupt` when it next runs bytecode, which a long call into
//! the core would delay until the call returned. A second handler, chained in front of
//! Python's, records a stop request in the core (`parallel::request_interrupt`, one atomic
//! add): the long loops poll it and end early, and [`detach`] then raises `KeyboardInterrupt`
//! instead of returning a partial result. A request reaches every call running when it came
//! (`parallel::begin_call`), whichever thread started them. If a program replaces the SIGINT
//! handler with `signal.signal`, the chain is gone and calls run to their end.
//!
//! Where SIGINT is ignored when the module is imported (a job started in the background by a
//! non-interactive shell, or `signal.signal(SIGINT, SIG_IGN)` first), nothing is installed:
//! the handler would replace the ignored disposition, and an ignored signal would stop calls.

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::marker::Ungil;
use pyo3::prelude::*;

use super::errors::BindResult;
use passive_assoc_core::parallel::{begin_call, interrupted, request_interrupt};

/// Chains the stop-request handler in front of the current SIGINT handler (once, at import),
/// unless SIGINT is ignored.
pub fn install(py: Python<'_>) -> PyResult<()> {
    #[cfg(unix)]
    {
        if sigint_ignored(py)? {
            return Ok(());
        }
        const SIGINT: i32 = 2; // POSIX
                               // SAFETY: the action is async-signal-safe (one lock-free atomic add, no allocation,
                               // no lock), as `register` requires; the registry calls Python's handler after it.
        let _ = unsafe { signal_hook_registry::register(SIGINT, request_interrupt) };
    }
    #[cfg(not(unix))]
    let _ = py;
    Ok(())
}

/// Whether SIGINT is ignored: Python records the disposition it found at start-up (or the one
/// a program set) in `signal.getsignal`.
#[cfg(unix)]
fn sigint_ignored(py: Python<'_>) -> PyResult<bool> {
    let signal = py.import("signal")?;
    let current = signal.call_method1("getsignal", (signal.getattr("SIGINT")?,))?;
    current.eq(signal.getattr("SIG_IGN")?)
}

/// `py.detach(work)`, raising `KeyboardInterrupt` if Ctrl-C arrived while it ran.
pub fn detach<R: Ungil>(py: Python<'_>, work: impl Ungil + FnOnce() -> R) -> BindResult<R> {
    let call = begin_call(); // a request from before any running call is Python's to raise
    let out = py.detach(work);
    let stopped = interrupted();
    drop(call);
    if stopped {
        py.check_signals()?; // raises the KeyboardInterrupt Python's own handler prepared
        return Err(PyKeyboardInterrupt::new_err("interrupted").into());
    }
    Ok(out)
}
