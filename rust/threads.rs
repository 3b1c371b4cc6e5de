//! Rayon thread pools, one per requested size, built once and reused: building a pool costs far
//! more than the ~20 us a parallel call does, and an optimiser makes thousands of calls.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use rayon::{ThreadPool, ThreadPoolBuilder};

/// Runs `work` inside a pool of `n_threads` threads (`0` means one per core).
///
/// Results never depend on the pool size: callers split work into fixed chunks and combine them
/// in order.
pub fn run<R: Send>(n_threads: usize, work: impl FnOnce() -> R + Send) -> R {
    let n = if n_threads == 0 { available() } else { n_threads };
    pool(n).install(work)
}

/// The number of cores rayon would use by default.
pub fn available() -> usize {
    std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
}

fn pool(n: usize) -> Arc<ThreadPool> {
    static POOLS: OnceLock<Mutex<HashMap<usize, Arc<ThreadPool>>>> = OnceLock::new();
    let mut pools = POOLS.get_or_init(Default::default).lock().unwrap_or_else(|e| e.into_inner());
    pools
        .entry(n)
        .or_insert_with(|| {
            Arc::new(
                ThreadPoolBuilder::new()
                    .num_threads(n)
                    .thread_name(|i| format!("uavcov-{i}"))
                    .build()
                    .expect("the OS refused to start rayon threads"),
            )
        })
        .clone()
}
