//! The PyO3 binding, `uavcov._core`: converts numpy arrays, releases the GIL around heavy work
//! and maps [`Error`] onto `uavcov.errors`. It holds no algorithm; users call the Python
//! wrappers (`uavcov.Terrain`, `uavcov.Visibility`), which validate before calling here.
//!
//! One file per Python class (and `draws` for the free functions with an algorithm
//! behind them, numpy's draws); this one holds the module and the conversions they share.
//!
//! No panic crosses into Python (where it would be a `pyo3_runtime.PanicException`, a
//! `BaseException` that `except Exception` misses): every method runs its Rust work through
//! [`guarded`] (with the GIL released, [`detached`]), which turns a residual panic, a bug, into
//! [`Error::Internal`], raised as the base class `uavcov.errors.UavcovError`.

// PyO3 extracts every argument by value (arrays, strings, errors for `map_err`), whether or not
// the body consumes it.
#![allow(clippy::needless_pass_by_value, reason = "PyO3's calling convention")]

mod cover;
mod cvt;
mod draws;
mod surface;
mod surrogate;
mod tracking;
mod visibility;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rayon::prelude::*;

use crate::error::{guarded, try_with_capacity, Error, Result};
use crate::geometry::{in_bounds, Point, MAX_COORDINATE};
use crate::threads;

pub(crate) fn to_py_err(py: Python<'_>, err: Error) -> PyErr {
    let class = match err {
        Error::InvalidInput(_) => "InvalidInputError",
        Error::Mesh(_) => "MeshError",
        Error::TooLarge(_) => "SurfaceTooLargeError",
        Error::Internal(_) => "UavcovError",
    };
    let message = err.to_string();
    match py.import("uavcov.errors").and_then(|m| m.getattr(class)) {
        Ok(cls) => match cls.call1((message,)) {
            Ok(instance) => PyErr::from_value(instance),
            Err(e) => e,
        },
        Err(_) => PyValueError::new_err(message),
    }
}

/// [`guarded`] `work` with the GIL released, its error mapped onto `uavcov.errors`.
pub(crate) fn detached<T: Send>(py: Python<'_>, work: impl FnOnce() -> Result<T> + Send) -> PyResult<T> {
    py.detach(|| guarded(work)).map_err(|e| to_py_err(py, e))
}

/// [`guarded`] `work` holding the GIL (for cheap calls), its error mapped onto `uavcov.errors`.
pub(crate) fn held<T>(py: Python<'_>, work: impl FnOnce() -> Result<T>) -> PyResult<T> {
    guarded(work).map_err(|e| to_py_err(py, e))
}

pub(crate) fn invalid(py: Python<'_>, message: String) -> PyErr {
    to_py_err(py, Error::InvalidInput(message))
}

/// Copies an `(n, 3)` array into owned points, so the GIL can be released while Rust reads them.
pub(crate) fn points(py: Python<'_>, array: &PyReadonlyArray2<'_, f64>, name: &str) -> PyResult<Vec<Point>> {
    let a = array.as_array();
    if a.ncols() != 3 {
        return Err(invalid(py, format!("{name} must have shape (n, 3), got {:?}", array.shape())));
    }
    let mut out: Vec<Point> = try_with_capacity(a.nrows(), &format!("a copy of {name}")).map_err(|e| to_py_err(py, e))?;
    out.extend(a.rows().into_iter().map(|r| [r[0], r[1], r[2]]));
    if out.iter().any(|q| q.iter().any(|c| !c.is_finite())) {
        return Err(invalid(py, format!("{name} contains NaN or infinite values")));
    }
    if let Some(q) = out.iter().find(|q| !in_bounds(**q)) {
        return Err(invalid(py, format!("{name} has a coordinate beyond {MAX_COORDINATE:e} m in magnitude: {q:?}")));
    }
    Ok(out)
}

pub(crate) fn points_to_py(py: Python<'_>, pts: Vec<Point>) -> Bound<'_, PyArray2<f64>> {
    let n = pts.len();
    let flat: Vec<f64> = pts.into_iter().flatten().collect();
    Array2::from_shape_vec((n, 3), flat).expect("n x 3 values").into_pyarray(py)
}

/// Runs `f` over `items` in parallel without the GIL; output order follows `items`.
pub(crate) fn parallel_map<T: Sync, R: Send>(
    py: Python<'_>,
    n_threads: usize,
    items: &[T],
    f: impl Fn(&T) -> R + Sync,
) -> PyResult<Vec<R>> {
    detached(py, || Ok(threads::run(n_threads, || items.par_iter().with_min_len(64).map(&f).collect())))
}

/// Number of cores the Rust side uses when `n_threads` is 0.
#[pyfunction]
fn available_threads() -> usize {
    threads::available()
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<surface::PySurface>()?;
    m.add_class::<visibility::PyVisibility>()?;
    m.add_class::<tracking::PyCoverageTracker>()?;
    m.add_class::<cvt::PyCvt>()?;
    m.add_class::<cover::PySeenMatrix>()?;
    m.add_class::<surrogate::PySurrogate>()?;
    m.add_function(wrap_pyfunction!(available_threads, m)?)?;
    m.add_function(wrap_pyfunction!(draws::pcg64_standard_normal, m)?)?;
    m.add_function(wrap_pyfunction!(draws::pcg64_random, m)?)?;
    m.add_function(wrap_pyfunction!(draws::pcg64_integers, m)?)?;
    m.add_function(wrap_pyfunction!(draws::pcg64_monomials, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
