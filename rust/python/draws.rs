//! numpy's `Generator` draws for a PCG64 state, bit for bit (see [`crate::cao::pcg64`]):
//! `pcg64_standard_normal`, `pcg64_random`, `pcg64_integers`, and CAO's monomial refresh,
//! `pcg64_monomials` (see [`crate::cao::monomials`]). `uavcov.draws` reads and writes the numpy
//! generator's state around them.
//!
//! A state is passed as the integers of numpy's `bit_generator.state`: `state` and `inc`, and,
//! for the functions that draw 32-bit words, `has_uint32` and `uinteger`; each function returns
//! the entries its draws change.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyInt;

use super::{detached, held, invalid, to_py_err};
use crate::cao::monomials::redraw;
use crate::cao::pcg64::Pcg64;
use crate::error::{try_filled, try_with_capacity, Error, Result};

/// At most 2^34 values (128 GiB) per call: a bound checked before allocating, so a mistaken
/// size is an error at once rather than a long wait for the allocator's refusal.
const MAX_VALUES: u64 = 1 << 34;

/// Below this many values the call keeps the GIL: releasing it would cost more than the draws.
const DETACH_FROM: usize = 1 << 16;

/// `(values, state, has_uint32, uinteger)`: what a draw of 32-bit words returns.
type Drawn32<T> = (T, u128, u8, u32);

fn draw<T: Clone + Send>(n: usize, what: &str, rng: &mut Pcg64, fill: impl FnOnce(&mut Pcg64, &mut [T]) + Send, zero: T) -> Result<Vec<T>> {
    let mut out = try_filled(zero, n, what)?;
    fill(rng, &mut out);
    Ok(out)
}

/// Runs `work`, with the GIL released from [`DETACH_FROM`] values on.
fn run<T: Send>(py: Python<'_>, n: usize, work: impl FnOnce() -> Result<T> + Send) -> PyResult<T> {
    if n < DETACH_FROM {
        held(py, work)
    } else {
        detached(py, work)
    }
}

fn word(py: Python<'_>, value: &Bound<'_, PyAny>, name: &str) -> PyResult<u128> {
    value.extract::<u128>().map_err(|_| invalid(py, format!("{name} must be an integer in [0, 2**128), got {value}")))
}

/// numpy's whole PCG64 state from the four integers of its state dict.
fn generator(
    py: Python<'_>,
    state: &Bound<'_, PyAny>,
    inc: &Bound<'_, PyAny>,
    has_uint32: &Bound<'_, PyAny>,
    uinteger: &Bound<'_, PyAny>,
) -> PyResult<Pcg64> {
    let has = has_uint32
        .extract::<u8>()
        .ok()
        .filter(|&h| h <= 1)
        .ok_or_else(|| invalid(py, format!("has_uint32 must be 0 or 1, got {has_uint32}")))?;
    let uinteger =
        uinteger.extract::<u32>().map_err(|_| invalid(py, format!("uinteger must be an integer in [0, 2**32), got {uinteger}")))?;
    Ok(Pcg64::with_buffer(word(py, state, "state")?, word(py, inc, "inc")?, has == 1, uinteger))
}

/// A non-negative Python integer as `u64`; any value past `u64::MAX` (even beyond 64 bits) is
/// `u64::MAX`, for the caller's bound to refuse.
fn size(py: Python<'_>, value: &Bound<'_, PyAny>, name: &str) -> PyResult<u64> {
    if !value.is_instance_of::<PyInt>() {
        return Err(invalid(py, format!("{name} must be an integer, got {value}")));
    }
    if value.lt(0)? {
        return Err(invalid(py, format!("{name} must be >= 0, got {value}")));
    }
    Ok(value.extract::<u64>().unwrap_or(u64::MAX))
}

/// A count of values to draw, at most [`MAX_VALUES`].
fn n_values(py: Python<'_>, n: &Bound<'_, PyAny>, what: &str) -> PyResult<usize> {
    let count = size(py, n, "n")?;
    if count > MAX_VALUES {
        return Err(to_py_err(py, Error::TooLarge(format!("{n} {what} in one call, more than {MAX_VALUES}"))));
    }
    Ok(count as usize) // <= 2^34: fits on the 64-bit targets the crate builds for
}

/// `n` standard normal values drawn as numpy's `Generator.standard_normal(n)` draws them from
/// a PCG64 generator at `(state, inc)`, and the generator's state afterwards.
#[pyfunction]
pub(super) fn pcg64_standard_normal<'py>(
    py: Python<'py>,
    state: &Bound<'py, PyAny>,
    inc: &Bound<'py, PyAny>,
    n: &Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyArray1<f64>>, u128)> {
    doubles(py, state, inc, n, "standard normal values", Pcg64::fill_standard_normal)
}

/// `n` doubles drawn as numpy's `Generator.random(n)` draws them from a PCG64 generator at
/// `(state, inc)`, and the generator's state afterwards (64-bit draws leave the 32-bit buffer).
#[pyfunction]
pub(super) fn pcg64_random<'py>(
    py: Python<'py>,
    state: &Bound<'py, PyAny>,
    inc: &Bound<'py, PyAny>,
    n: &Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyArray1<f64>>, u128)> {
    doubles(py, state, inc, n, "doubles", Pcg64::fill_f64)
}

/// `n` doubles that `fill` draws from a PCG64 generator at `(state, inc)` (64-bit draws only),
/// and the generator's state afterwards.
fn doubles<'py>(
    py: Python<'py>,
    state: &Bound<'py, PyAny>,
    inc: &Bound<'py, PyAny>,
    n: &Bound<'py, PyAny>,
    what: &str,
    fill: impl FnOnce(&mut Pcg64, &mut [f64]) + Send,
) -> PyResult<(Bound<'py, PyArray1<f64>>, u128)> {
    let mut rng = Pcg64::new(word(py, state, "state")?, word(py, inc, "inc")?);
    let n = n_values(py, n, what)?;
    let values = run(py, n, || draw(n, what, &mut rng, fill, 0.0))?;
    Ok((values.into_pyarray(py), rng.state))
}

/// `n` integers drawn as numpy's `Generator.integers(low, high, n)` draws them (int64) from a
/// PCG64 generator at numpy's whole state, for `0 < high - low <= 2^32` (numpy's 32-bit path),
/// and the state's entries afterwards.
#[pyfunction]
#[allow(clippy::too_many_arguments, reason = "numpy's four state integers, then the draw's three")]
pub(super) fn pcg64_integers<'py>(
    py: Python<'py>,
    state: &Bound<'py, PyAny>,
    inc: &Bound<'py, PyAny>,
    has_uint32: &Bound<'py, PyAny>,
    uinteger: &Bound<'py, PyAny>,
    low: i64,
    high: i64,
    n: &Bound<'py, PyAny>,
) -> PyResult<Drawn32<Bound<'py, PyArray1<i64>>>> {
    let mut rng = generator(py, state, inc, has_uint32, uinteger)?;
    let range = i128::from(high) - i128::from(low);
    if !(1..=1 << 32).contains(&range) {
        return Err(invalid(py, format!("high - low must be in [1, 2**32], got {high} - {low} = {range}")));
    }
    let span = (range - 1) as u32;
    let n = n_values(py, n, "integers")?;
    let values = run(py, n, || draw(n, "integers", &mut rng, |r, out| r.fill_integers(low, span, out), 0))?;
    Ok((values.into_pyarray(py), rng.state, u8::from(rng.has_uint32), rng.uinteger))
}

/// CAO's monomial refresh (see [`crate::cao::monomials::redraw`]): the `keep` strongest rows of
/// `terms (T, 3)` by `strength (T,)`, in index order, then `count` fresh monomials of `dim`
/// variables drawn as numpy's `_draw_monomials` draws them from a PCG64 generator at numpy's
/// whole state; and the state's entries afterwards. `None` instead of the rows (the state
/// unchanged) when numpy samples without replacement instead.
#[pyfunction]
#[allow(clippy::too_many_arguments, reason = "numpy's four state integers, then the refresh's five")]
pub(super) fn pcg64_monomials<'py>(
    py: Python<'py>,
    terms: PyReadonlyArray2<'py, i64>,
    strength: PyReadonlyArray1<'py, f64>,
    keep: &Bound<'py, PyAny>,
    count: &Bound<'py, PyAny>,
    dim: &Bound<'py, PyAny>,
    state: &Bound<'py, PyAny>,
    inc: &Bound<'py, PyAny>,
    has_uint32: &Bound<'py, PyAny>,
    uinteger: &Bound<'py, PyAny>,
) -> PyResult<Drawn32<Option<Bound<'py, PyArray2<i64>>>>> {
    let mut rng = generator(py, state, inc, has_uint32, uinteger)?;
    let (keep, count, dim) = (size(py, keep, "keep")?, size(py, count, "count")?, size(py, dim, "dim")?);
    if terms.shape()[1] != 3 {
        return Err(invalid(py, format!("terms must have shape (T, 3), got {:?}", terms.shape())));
    }
    let rows = held(py, || {
        let t = terms.as_array();
        let mut rows = try_with_capacity(t.nrows(), "a copy of the terms")?;
        rows.extend(t.rows().into_iter().map(|r| [r[0], r[1], r[2]]));
        let s = strength.as_array();
        let mut values = try_with_capacity(s.len(), "a copy of the strengths")?;
        values.extend(s.iter().copied());
        // Sizes past usize are past the kernel's bounds too.
        let (keep, count) = (usize::try_from(keep).unwrap_or(usize::MAX), usize::try_from(count).unwrap_or(usize::MAX));
        redraw(&rows, &values, keep, count, dim, &mut rng)
    })?;
    let rows = match rows {
        Some(rows) => {
            let n = rows.len();
            let flat = Array2::from_shape_vec((n, 3), rows.into_iter().flatten().collect())
                .map_err(|e| to_py_err(py, Error::Internal(format!("monomials of unexpected shape: {e}"))))?;
            Some(flat.into_pyarray(py))
        }
        None => None,
    };
    Ok((rows, rng.state, u8::from(rng.has_uint32), rng.uinteger))
}
