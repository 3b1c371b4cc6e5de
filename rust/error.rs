//! One error type for everything a caller can get wrong, and the checked allocations that turn
//! an allocation the system refuses into an error instead of an abort.

use thiserror::Error;

/// What went wrong, in terms of the caller's input.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Error {
    /// A value is out of its documented range, not finite, or of the wrong shape.
    #[error("{0}")]
    InvalidInput(String),
    /// A surface mesh is empty, degenerate, or refers to vertices that do not exist.
    #[error("{0}")]
    Mesh(String),
    /// A surface, target set or run would need more memory than this path allows, or than the
    /// system gives.
    #[error("{0}")]
    TooLarge(String),
    /// A bug: the binding caught a panic and reports it as this (the message says where).
    #[error("{0}")]
    Internal(String),
}

/// `Result` with [`Error`](enum@Error).
pub type Result<T> = std::result::Result<T, Error>;

/// Returns `Err(Error::InvalidInput)` with the formatted message unless `cond` holds.
macro_rules! ensure {
    ($cond:expr, $($msg:tt)+) => {
        if !$cond {
            return Err($crate::error::Error::InvalidInput(format!($($msg)+)));
        }
    };
}
pub(crate) use ensure;

/// The error of an allocation of `n` values of `T` for `what` that failed or could not be sized.
fn refused<T>(n: usize, what: &str) -> Error {
    let bytes = (n as f64) * std::mem::size_of::<T>() as f64;
    Error::TooLarge(format!("{what} needs {n} values ({:.3} GB), more memory than the system gives", bytes / 1e9))
}

/// An empty vector with room for `n` values, or [`Error::TooLarge`] when the system refuses the
/// memory (instead of aborting the process).
pub(crate) fn try_with_capacity<T>(n: usize, what: &str) -> Result<Vec<T>> {
    let mut out = Vec::new();
    out.try_reserve_exact(n).map_err(|_| refused::<T>(n, what))?;
    Ok(out)
}

/// `vec![value; n]`, or [`Error::TooLarge`] when the system refuses the memory.
pub(crate) fn try_filled<T: Clone>(value: T, n: usize, what: &str) -> Result<Vec<T>> {
    let mut out = try_with_capacity(n, what)?;
    out.resize(n, value);
    Ok(out)
}

/// A copy of `values`, or [`Error::TooLarge`] when the system refuses the memory.
pub(crate) fn try_copy<T: Clone>(values: &[T], what: &str) -> Result<Vec<T>> {
    let mut out = try_with_capacity(values.len(), what)?;
    out.extend_from_slice(values);
    Ok(out)
}

/// `work()`, with a panic caught and returned as [`Error::Internal`]: the binding's last line
/// of defence (no input is known to reach a panic, and the tests hold it so). The work is
/// treated as unwind-safe: what a panic could leave half-updated is the work's own state
/// (dropped with it) or a cache behind a `OnceLock`, which stays unset.
#[cfg_attr(not(feature = "python"), allow(dead_code, reason = "used by the binding"))]
pub(crate) fn guarded<T>(work: impl FnOnce() -> Result<T>) -> Result<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)).unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".to_owned());
        Err(Error::Internal(format!("internal error in uavcov's Rust core (a bug, please report it): {what}")))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refused_allocations_are_errors() {
        // More bytes than any address space: `try_reserve` refuses before asking the system.
        assert!(matches!(try_with_capacity::<[f64; 3]>(usize::MAX / 8, "a test"), Err(Error::TooLarge(_))));
        assert!(matches!(try_filled(0u64, usize::MAX / 4, "a test"), Err(Error::TooLarge(_))));
        assert_eq!(try_filled(7u8, 3, "a test").unwrap(), vec![7, 7, 7]);
        assert_eq!(try_copy(&[1, 2], "a test").unwrap(), vec![1, 2]);
    }

    #[test]
    fn a_panic_becomes_an_internal_error() {
        assert_eq!(guarded(|| Ok(3)), Ok(3));
        assert_eq!(guarded::<()>(|| Err(Error::Mesh("m".into()))), Err(Error::Mesh("m".into())));
        let hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {})); // keep the test's output clean
        let caught = guarded::<()>(|| panic!("range start index {} out of range", usize::MAX));
        // A panic on a rayon worker comes back to the caller, and is caught the same way.
        let parallel = guarded::<u64>(|| {
            use rayon::prelude::*;
            Ok((0..1000u64).into_par_iter().map(|k| if k == 777 { panic!("worker") } else { k }).sum())
        });
        std::panic::set_hook(hook);
        assert!(matches!(&caught, Err(Error::Internal(m)) if m.contains("18446744073709551615")), "{caught:?}");
        assert!(matches!(&parallel, Err(Error::Internal(m)) if m.contains("worker")), "{parallel:?}");
    }
}
