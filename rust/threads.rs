//! Rayon thread pools, one per requested size, built once and reused: building a pool costs far
//! more than the ~20 us a parallel call does, and an optimiser makes thousands of calls.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use rayon::{ThreadPool, ThreadPoolBuilder};

/// Runs `work` inside a pool of `n_threads` threads (`0` means one per core).
///
/// One thread means the calling thread itself (a one-thread pool made of it, kept per thread).
/// Results never depend on the pool size: callers split work into fixed chunks and combine them
/// in order. That is also why a refusal is harmless: when the OS will not start `n_threads`
/// threads, the work runs on a single-thread pool or, failing that, on the calling thread alone,
/// and gives the same answer.
pub(crate) fn run<R: Send>(n_threads: usize, work: impl FnOnce() -> R + Send) -> R {
    let n = if n_threads == 0 { available() } else { n_threads };
    if n == 1 {
        // One thread: the calling thread itself, as a pool of its own, so that a call does not
        // hand its work to another thread and wait for it to wake up (tens of microseconds after
        // a pause, on every call of an optimiser's loop).
        let mut work = Some(work);
        let take = |w: &mut Option<_>| w.take().expect("the work runs once");
        if let Some(result) = CALLER.with(|own| own.as_ref().map(|p| p.install(|| take(&mut work)()))) {
            return result;
        }
        return run_elsewhere(1, take(&mut work));
    }
    run_elsewhere(n, work)
}

thread_local! {
    /// A one-thread pool made of the calling thread (`None` if rayon refused it). Rayon never
    /// frees such a pool's registry (a few kilobytes): one per thread that ever asks for a single
    /// thread, which an optimiser's loop or a sweep worker does from one thread for its lifetime.
    static CALLER: Option<ThreadPool> = ThreadPoolBuilder::new().num_threads(1).use_current_thread().build().ok();
}

/// [`run`] on a pool of `n` threads of their own.
fn run_elsewhere<R: Send>(n: usize, work: impl FnOnce() -> R + Send) -> R {
    if let Some(p) = pool(n).or_else(|| pool(1)) {
        return p.install(work);
    }
    // A pool made of the calling thread starts no thread, so the OS cannot refuse it; rayon does
    // when the thread already belongs to one (its own, from `CALLER`), and then `work` runs on
    // this thread in that one-thread pool.
    match ThreadPoolBuilder::new().num_threads(1).use_current_thread().build() {
        Ok(p) => p.install(work),
        Err(_) => work(),
    }
}

/// The number of threads rayon would use by default: `RAYON_NUM_THREADS` when it is set to a
/// positive integer, else one per core.
pub(crate) fn available() -> usize {
    default_threads(std::env::var("RAYON_NUM_THREADS").ok().as_deref())
}

/// [`available`] for a given value of `RAYON_NUM_THREADS` (rayon ignores one that is not a
/// positive integer, and so does this).
fn default_threads(rayon_num_threads: Option<&str>) -> usize {
    match rayon_num_threads.and_then(|text| text.trim().parse::<usize>().ok()) {
        Some(n) if n > 0 => n,
        _ => std::thread::available_parallelism().map_or(1, std::num::NonZero::get),
    }
}

fn pool(n: usize) -> Option<Arc<ThreadPool>> {
    static POOLS: OnceLock<Mutex<HashMap<usize, Arc<ThreadPool>>>> = OnceLock::new();
    let mut pools = POOLS.get_or_init(Default::default).lock().unwrap_or_else(std::sync::PoisonError::into_inner);
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
    fn the_default_follows_rayon_num_threads_like_rayon() {
        let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
        assert_eq!(super::default_threads(Some("3")), 3);
        assert_eq!(super::default_threads(Some(" 2 ")), 2);
        for ignored in [None, Some(""), Some("0"), Some("-1"), Some("many")] {
            assert_eq!(super::default_threads(ignored), cores);
        }
    }

    #[test]
    fn results_come_back_from_any_pool_size() {
        use rayon::prelude::*;
        let sum = |n| super::run(n, || (0..1000u64).into_par_iter().sum::<u64>());
        assert_eq!(sum(0), 499_500);
        assert_eq!(sum(1), sum(3));
    }

    #[test]
    fn one_thread_runs_on_the_caller_and_leaves_other_sizes_alone() {
        let caller = std::thread::current().id();
        assert_eq!(super::run(1, || (rayon::current_num_threads(), std::thread::current().id())), (1, caller));
        // The calling thread now belongs to its own one-thread pool; larger pools still get
        // their own threads, and the one-thread pool comes back on the next call.
        assert_eq!(super::run(2, rayon::current_num_threads), 2);
        assert_eq!(super::run(1, rayon::current_num_threads), 1);
        // Each thread has its own.
        let others: Vec<_> = (0..4)
            .map(|_| std::thread::spawn(|| super::run(1, || (rayon::current_num_threads(), std::thread::current().id()))))
            .map(|h| h.join().unwrap())
            .collect();
        assert!(others.iter().all(|&(n, id)| n == 1 && id != caller));
    }
}
