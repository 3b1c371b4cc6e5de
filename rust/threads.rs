//! Rayon thread pools, one per requested size, built once and reused: building a pool costs far
//! more than the ~20 us a parallel call does, and an optimiser makes thousands of calls.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use rayon::{ThreadPool, ThreadPoolBuilder};

/// Runs `work` inside a pool of `n_threads` threads (`0` means one per core).
///
/// Results never depend on the pool size: callers split work into fixed chunks and combine them
/// in order. That is also why a refusal is harmless: when the OS will not start `n_threads`
/// threads, the work runs on a single-thread pool or, failing that, on the calling thread alone,
/// and gives the same answer.
pub fn run<R: Send>(n_threads: usize, work: impl FnOnce() -> R + Send) -> R {
    let n = if n_threads == 0 { available() } else { n_threads };
    if let Some(p) = pool(n).or_else(|| pool(1)) {
        return p.install(work);
    }
    // A pool made of the calling thread starts no thread at all, so it cannot be refused.
    match ThreadPoolBuilder::new().num_threads(1).use_current_thread().build() {
        Ok(p) => p.install(work),
        Err(_) => work(),
    }
}

/// The number of cores rayon would use by default.
pub fn available() -> usize {
    std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
}

fn pool(n: usize) -> Option<Arc<ThreadPool>> {
    static POOLS: OnceLock<Mutex<HashMap<usize, Arc<ThreadPool>>>> = OnceLock::new();
    let mut pools = POOLS.get_or_init(Default::default).lock().unwrap_or_else(|e| e.into_inner());
    if let Some(p) = pools.get(&n) {
        return Some(p.clone());
    }
    let built = ThreadPoolBuilder::new().num_threads(n).thread_name(|i| format!("uavcov-{i}")).build().ok()?;
    let built = Arc::new(built);
    pools.insert(n, built.clone());
    Some(built)
}

#[cfg(test)]
mod tests {
    #[test]
    fn results_come_back_from_any_pool_size() {
        use rayon::prelude::*;
        let sum = |n| super::run(n, || (0..1000u64).into_par_iter().sum::<u64>());
        assert_eq!(sum(0), 499_500);
        assert_eq!(sum(1), sum(3));
    }
}
