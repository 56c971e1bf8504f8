//! Thread-count control. Work runs on rayon's global pool unless the caller asks for a
//! specific count, in which case a pool of that size runs it; results never depend on the
//! count because every parallel stage collects in input order or sums integers.

use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::error::{CoreError, CoreResult};

/// Pool sizes kept at once per calling thread. A caller uses one or two sizes over and over;
/// one sweeping `n_threads` over many values would otherwise leave every pool's threads parked
/// for good. A calling thread's pools end with it.
const MAX_CACHED_POOLS: usize = 4;

/// Pools by size, built once per calling thread: starting threads costs more than a small
/// call's work (a per-scan association or a single fit asked for on one thread). Per calling
/// thread, not per process: with one shared pool of each size, two Python threads that each
/// asked for one thread queued on the same worker and ran one after the other.
fn pool(threads: usize) -> CoreResult<Arc<ThreadPool>> {
    thread_local! {
        static POOLS: RefCell<HashMap<usize, Arc<ThreadPool>>> = RefCell::new(HashMap::new());
    }
    if let Some(pool) = POOLS.with(|pools| pools.borrow().get(&threads).cloned()) {
        return Ok(pool);
    }
    let pool = ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map(Arc::new)
        .map_err(|e| {
            CoreError::out_of_range("n_threads", format!("cannot start {threads} threads: {e}"))
        })?;
    POOLS.with(|pools| remember(&mut pools.borrow_mut(), threads, Arc::clone(&pool)));
    Ok(pool)
}

/// Caches `pool` under `threads`, first forgetting every pool if the cache is full (a pool
/// still running work lives on in its callers' handles).
fn remember<P>(pools: &mut HashMap<usize, P>, threads: usize, pool: P) {
    if pools.len() >= MAX_CACHED_POOLS {
        pools.clear();
    }
    pools.insert(threads, pool);
}

/// Stop requests so far (the binding's SIGINT handler adds one; nothing here knows about
/// signals). The long loops — the static enumeration, branch-and-bound, the Lagrangian, the
/// intensity chains, the fuzzy initiation's candidates and descents, the formation locator,
/// the track-to-track scans — poll [`interrupted`] and stop early; the binding then raises
/// `KeyboardInterrupt` instead of returning the partial result.
///
/// A request counts for the calls running when it came: Ctrl-C stops every running call, as
/// it stops the program, and a call that starts later does not see it. Calls that overlap
/// share an epoch, [`ACKNOWLEDGED`]: the requests made before the first of them began. It
/// moves on only when no call is running, so a call started from a second thread can no
/// longer clear a request meant for the first (each call used to clear one shared flag on
/// entry, swallowing a Ctrl-C that had arrived while another call ran).
static REQUESTS: AtomicUsize = AtomicUsize::new(0);

/// The requests the running calls do not answer to (those made before the first began).
static ACKNOWLEDGED: AtomicUsize = AtomicUsize::new(0);

/// Calls running between [`begin_call`] and the end of its guard.
static RUNNING: Mutex<usize> = Mutex::new(0);

/// Asks every running call to stop (async-signal-safe: one lock-free atomic add).
pub fn request_interrupt() {
    REQUESTS.fetch_add(1, Ordering::Relaxed);
}

/// Forgets every request made so far (a test's, or a program's between its calls).
pub fn clear_interrupt() {
    ACKNOWLEDGED.store(REQUESTS.load(Ordering::Relaxed), Ordering::Relaxed);
}

/// Whether a stop was requested since the running calls began.
#[inline]
pub fn interrupted() -> bool {
    REQUESTS.load(Ordering::Relaxed) != ACKNOWLEDGED.load(Ordering::Relaxed)
}

/// Marks a call as running until the guard is dropped. The first of a set of overlapping
/// calls forgets older requests (a Ctrl-C that came while no call ran is the program's to
/// handle, not the next call's); a call that starts while others run joins their epoch, so a
/// request that came while they ran stops it too and is never cleared under them.
pub fn begin_call() -> CallGuard {
    let mut running = RUNNING
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if *running == 0 {
        clear_interrupt();
    }
    *running += 1;
    CallGuard(())
}

/// A running call (see [`begin_call`]).
#[derive(Debug)]
pub struct CallGuard(());

impl Drop for CallGuard {
    fn drop(&mut self) {
        let mut running = RUNNING
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        *running = running.saturating_sub(1);
    }
}

/// Largest thread count accepted: far above any machine, low enough that a typo cannot ask
/// the OS for millions of threads.
pub const MAX_THREADS: usize = 1024;

/// Runs `work` on `threads` threads (`None` = rayon's global pool, sized to the machine).
pub fn with_threads<R: Send>(
    threads: Option<usize>,
    work: impl FnOnce() -> R + Send,
) -> CoreResult<R> {
    check_threads(threads)?;
    match threads {
        None => Ok(work()),
        Some(n) => Ok(pool(n)?.install(work)),
    }
}

/// As [`with_threads`], but `work` runs on the calling thread when it is `sequential` (it
/// starts no parallel iterator, so a pool would add only its handoff, tens of microseconds,
/// to a call whose work may take less). The thread count is validated either way.
pub fn with_threads_unless_sequential<R: Send>(
    sequential: bool,
    threads: Option<usize>,
    work: impl FnOnce() -> R + Send,
) -> CoreResult<R> {
    if sequential {
        check_threads(threads).map(|()| work())
    } else {
        with_threads(threads, work)
    }
}

fn check_threads(threads: Option<usize>) -> CoreResult<()> {
    match threads {
        Some(0) => Err(CoreError::out_of_range(
            "n_threads",
            "must be at least 1 (or None for all cores)",
        )),
        Some(n) if n > MAX_THREADS => Err(CoreError::out_of_range(
            "n_threads",
            format!("{n} exceeds the maximum of {MAX_THREADS}"),
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sequential_work_stays_on_the_calling_thread_and_counts_are_still_checked() {
        let caller = std::thread::current().id();
        let ran_on = with_threads_unless_sequential(true, Some(1), || std::thread::current().id());
        assert_eq!(ran_on.unwrap(), caller);
        let pooled = with_threads_unless_sequential(false, Some(1), || std::thread::current().id());
        assert_ne!(pooled.unwrap(), caller);
        assert!(with_threads_unless_sequential(true, Some(0), || ()).is_err());
        assert!(with_threads_unless_sequential(true, Some(MAX_THREADS + 1), || ()).is_err());
    }

    #[test]
    fn pools_are_reused_and_sized_as_asked() {
        let first = with_threads(Some(3), rayon::current_num_threads).expect("pool");
        assert_eq!(first, 3);
        let a = pool(3).expect("pool");
        let b = pool(3).expect("pool");
        assert!(Arc::ptr_eq(&a, &b));
        assert!(with_threads(Some(0), || ()).is_err());
        assert!(with_threads(Some(MAX_THREADS + 1), || ()).is_err());
    }

    #[test]
    fn calling_threads_get_their_own_pools() {
        let here = pool(1).expect("pool");
        let there = std::thread::spawn(|| pool(1).expect("pool"))
            .join()
            .expect("thread");
        assert!(!Arc::ptr_eq(&here, &there));
        assert!(Arc::ptr_eq(&here, &pool(1).expect("pool")));
    }

    #[test]
    fn a_sweep_over_thread_counts_keeps_few_pools() {
        let mut pools = HashMap::new();
        for threads in 1..=3 * MAX_CACHED_POOLS {
            remember(&mut pools, threads, ());
            assert!(
                pools.len() <= MAX_CACHED_POOLS,
                "{threads}: {} pools",
                pools.len()
            );
            assert!(pools.contains_key(&threads));
        }
    }
}

#[cfg(test)]
mod isolation {
    /// A one-thread call must not leave the calling thread inside a one-thread pool: a pool
    /// built with rayon's `use_current_thread` (tried, to save the pool handoff) does, and
    /// every later all-cores call on that thread then ran on one thread.
    #[test]
    fn a_one_thread_call_leaves_later_calls_on_all_cores() {
        let before = rayon::current_num_threads();
        super::with_threads(Some(1), || ()).expect("pool");
        let after = super::with_threads(None, rayon::current_num_threads).expect("pool");
        assert_eq!(before, after);
    }
}
