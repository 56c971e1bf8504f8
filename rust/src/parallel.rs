//! Thread-count control. Work runs on rayon's global pool unless the caller asks for a
//! specific count, in which case a dedicated pool of that size runs it; results never depend
//! on the count because every parallel stage collects in input order.

use crate::error::{CoreError, CoreResult};

/// Runs `work` on `threads` threads (`None` = rayon's global pool, sized to the machine).
pub fn with_threads<R: Send>(
    threads: Option<usize>,
    work: impl FnOnce() -> R + Send,
) -> CoreResult<R> {
    match threads {
        None => Ok(work()),
        Some(0) => Err(CoreError::out_of_range(
            "n_threads",
            "must be at least 1 (or None for all cores)",
        )),
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| {
                    CoreError::out_of_range("n_threads", format!("cannot start {n} threads: {e}"))
                })?;
            Ok(pool.install(work))
        }
    }
}
