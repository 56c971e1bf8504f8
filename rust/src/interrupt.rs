//! Ctrl-C during a compiled call. Python's SIGINT handler only marks the signal; the
//! interpreter raises `KeyboardInterrupt` when it next runs bytecode, which a long call into
//! the core would delay until the call returned. A second handler, chained in front of
//! Python's, sets the core's stop flag (`parallel::request_interrupt`, one atomic store): the
//! long loops poll it and end early, and [`detach`] then raises `KeyboardInterrupt` instead of
//! returning a partial result. If a program replaces the SIGINT handler with
//! `signal.signal`, the chain is gone and calls run to their end.

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::marker::Ungil;
use pyo3::prelude::*;

use super::errors::BindResult;
use passive_assoc_core::parallel::{clear_interrupt, interrupted, request_interrupt};

/// Chains the stop-flag handler in front of the current SIGINT handler (once, at import).
pub fn install() {
    #[cfg(unix)]
    {
        const SIGINT: i32 = 2; // POSIX
                               // SAFETY: the action is async-signal-safe (one relaxed atomic store, no allocation,
                               // no lock), as `register` requires; the registry calls Python's handler after it.
        let _ = unsafe { signal_hook_registry::register(SIGINT, request_interrupt) };
    }
}

/// `py.detach(work)`, raising `KeyboardInterrupt` if Ctrl-C arrived while it ran.
pub fn detach<R: Ungil>(py: Python<'_>, work: impl Ungil + FnOnce() -> R) -> BindResult<R> {
    clear_interrupt(); // a request left from before this call is Python's to raise, not ours
    let out = py.detach(work);
    if interrupted() {
        clear_interrupt();
        py.check_signals()?; // raises the KeyboardInterrupt Python's own handler prepared
        return Err(PyKeyboardInterrupt::new_err("interrupted").into());
    }
    Ok(out)
}
