//! `uavcov._core.pcg64_standard_normal`: numpy's `Generator.standard_normal` for a PCG64
//! state, bit for bit (see [`crate::pcg64`]); `uavcov.draws` reads and writes the numpy
//! generator's state around it.

use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyInt;

use super::{detached, held, invalid, to_py_err};
use crate::error::{try_filled, Error, Result};
use crate::pcg64::Pcg64;

/// At most 2^34 values (128 GiB) per call: a bound checked before allocating, so a mistaken
/// size is an error at once rather than a long wait for the allocator's refusal.
const MAX_VALUES: u64 = 1 << 34;

/// Below this many values the call keeps the GIL: releasing it would cost more than the draws.
const DETACH_FROM: usize = 1 << 16;

fn draw(state: u128, inc: u128, n: usize) -> Result<(Vec<f64>, u128)> {
    let mut out = try_filled(0.0, n, "standard normal values")?;
    let mut rng = Pcg64::new(state, inc);
    rng.fill_standard_normal(&mut out);
    Ok((out, rng.state))
}

fn word(py: Python<'_>, value: &Bound<'_, PyAny>, name: &str) -> PyResult<u128> {
    value.extract::<u128>().map_err(|_| invalid(py, format!("{name} must be an integer in [0, 2**128), got {value}")))
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
    let (state, inc) = (word(py, state, "state")?, word(py, inc, "inc")?);
    if !n.is_instance_of::<PyInt>() {
        return Err(to_py_err(py, Error::InvalidInput(format!("n must be an integer, got {n}"))));
    }
    if n.lt(0)? {
        return Err(invalid(py, format!("n must be >= 0, got {n}")));
    }
    // Any size past the bound, however large (even beyond 64 bits), is the same refusal.
    let count = n.extract::<u64>().unwrap_or(u64::MAX);
    if count > MAX_VALUES {
        return Err(to_py_err(py, Error::TooLarge(format!("{n} standard normal values in one call, more than {MAX_VALUES}"))));
    }
    let n = count as usize; // <= 2^34: fits on the 64-bit targets the crate builds for
    let (values, state) = if n < DETACH_FROM { held(py, || draw(state, inc, n))? } else { detached(py, || draw(state, inc, n))? };
    Ok((values.into_pyarray(py), state))
}
