//! One error type for everything a caller can get wrong.

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
    /// A surface would need more memory than this path allows.
    #[error("{0}")]
    TooLarge(String),
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
