//! `uavcov._core.Surrogate`: CAO's estimator, one call per iteration (see `uavcov.cao`).
//!
//! The calls are small (a window of about a hundred points, a few hundred candidates): they keep
//! the GIL, whose release would cost more than the work.

use numpy::ndarray::{Array2, Axis};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;

use super::{held, invalid};
use crate::cao::surrogate::{fit, Regressors};
use crate::error::{try_with_capacity, Error, Result};

/// `(theta (L,), scores (M,), strength (T,))`.
type FitOutput<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);
/// `(theta (N, L), scores (N, M), strength (N, T))`.
type RobotsOutput<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// The estimator's kernels; static methods only.
#[derive(Debug)]
#[pyclass(module = "uavcov._core", frozen, name = "Surrogate")]
pub struct PySurrogate;

fn terms_of(py: Python<'_>, terms: &PyReadonlyArray2<'_, i64>) -> PyResult<Vec<[usize; 3]>> {
    let t = terms.as_array();
    if t.ncols() != 3 {
        return Err(invalid(py, format!("terms must have shape (T, 3), got {:?}", terms.shape())));
    }
    t.rows()
        .into_iter()
        .map(|r| {
            let mut out = [0usize; 3];
            for c in 0..3 {
                out[c] = usize::try_from(r[c]).map_err(|_| invalid(py, format!("terms hold a negative index {}", r[c])))?;
            }
            Ok(out)
        })
        .collect()
}

/// An owned copy of an array's values in logical (row-major) order.
fn copy_of<T>(values: impl Iterator<Item = T>, n: usize, what: &str) -> Result<Vec<T>> {
    let mut out = try_with_capacity(n, what)?;
    out.extend(values);
    Ok(out)
}

/// [`copy_of`] a whole array: one memcpy when it is C-contiguous.
fn copy_array<T: numpy::Element + Copy, D: numpy::ndarray::Dimension>(
    array: &numpy::PyReadonlyArray<'_, T, D>,
    what: &str,
) -> Result<Vec<T>> {
    let view = array.as_array();
    match view.as_slice() {
        Some(values) => copy_of(values.iter().copied(), values.len(), what),
        None => copy_of(view.iter().copied(), view.len(), what),
    }
}

fn to_2d(rows: usize, cols: usize, values: Vec<f64>) -> Result<Array2<f64>> {
    Array2::from_shape_vec((rows, cols), values).map_err(|e| Error::Internal(format!("a result of unexpected shape: {e}")))
}

#[pymethods]
impl PySurrogate {
    /// Fits the centralised estimator on `window (W, d)` and `values (W,)` and scores
    /// `candidates (M, d)`; `terms (T, 3)` are the monomials (index `d` is the one).
    #[staticmethod]
    fn fit<'py>(
        py: Python<'py>,
        window: PyReadonlyArray2<'py, f64>,
        values: PyReadonlyArray1<'py, f64>,
        terms: PyReadonlyArray2<'py, i64>,
        candidates: PyReadonlyArray2<'py, f64>,
        ridge: f64,
    ) -> PyResult<FitOutput<'py>> {
        let dim = window.shape()[1];
        if candidates.shape()[1] != dim {
            return Err(invalid(py, format!("candidates have {} coordinates, the window {dim}", candidates.shape()[1])));
        }
        let terms = terms_of(py, &terms)?;
        let (theta, scores, strength) = held(py, || {
            let reg = Regressors::new(dim, terms)?;
            let points = copy_array(&window, "a copy of the window")?;
            let y = copy_array(&values, "a copy of the values")?;
            let model = fit(&reg, &points, &y, ridge, None)?;
            let cand = copy_array(&candidates, "a copy of the candidates")?;
            let scores = reg.scores(&model.theta, &cand)?;
            Ok((model.theta, scores, model.strength))
        })?;
        Ok((theta.into_pyarray(py), scores.into_pyarray(py), strength.into_pyarray(py)))
    }

    /// Fits one estimator per robot: `window (N, W, 3)`, `values (N, W)`, the monomials
    /// `terms (T, 3)` of 3 coordinates with `active (N, T)` marking each robot's, and scores
    /// each robot's `candidates (N, M, 3)`.
    #[staticmethod]
    fn fit_robots<'py>(
        py: Python<'py>,
        window: PyReadonlyArray3<'py, f64>,
        values: PyReadonlyArray2<'py, f64>,
        terms: PyReadonlyArray2<'py, i64>,
        active: PyReadonlyArray2<'py, bool>,
        candidates: PyReadonlyArray3<'py, f64>,
        ridge: f64,
    ) -> PyResult<RobotsOutput<'py>> {
        let &[n_robots, n_window, dim] = window.shape() else { unreachable!("a 3-d array") };
        let &[n_cand_robots, n_cand, cand_dim] = candidates.shape() else { unreachable!("a 3-d array") };
        let terms = terms_of(py, &terms)?;
        if values.shape() != [n_robots, n_window] {
            return Err(invalid(py, format!("values must have shape ({n_robots}, {n_window}), got {:?}", values.shape())));
        }
        if active.shape() != [n_robots, terms.len()] {
            return Err(invalid(py, format!("active must have shape ({n_robots}, {}), got {:?}", terms.len(), active.shape())));
        }
        if n_cand_robots != n_robots || cand_dim != dim {
            return Err(invalid(py, format!("candidates must have shape ({n_robots}, M, {dim}), got {:?}", candidates.shape())));
        }
        let (window, values, active, candidates) = (window.as_array(), values.as_array(), active.as_array(), candidates.as_array());
        let width = 1 + dim + terms.len();
        let (theta, scores, strength) = held(py, || {
            let reg = Regressors::new(dim, terms)?;
            let mut theta = try_with_capacity(n_robots * width, "the robots' coefficients")?;
            let mut scores = try_with_capacity(n_robots * n_cand, "the robots' scores")?;
            let mut strength = try_with_capacity(n_robots * (width - 1 - dim), "the robots' monomial strengths")?;
            for r in 0..n_robots {
                let points = copy_of(window.index_axis(Axis(0), r).iter().copied(), n_window * dim, "a robot's window")?;
                let y = copy_of(values.row(r).iter().copied(), n_window, "a robot's values")?;
                let on = copy_of(active.row(r).iter().copied(), active.ncols(), "a robot's monomials")?;
                let model = fit(&reg, &points, &y, ridge, Some(&on))?;
                let cand = copy_of(candidates.index_axis(Axis(0), r).iter().copied(), n_cand * dim, "a robot's candidates")?;
                scores.extend(reg.scores(&model.theta, &cand)?);
                theta.extend(model.theta);
                strength.extend(model.strength);
            }
            Ok((to_2d(n_robots, width, theta)?, to_2d(n_robots, n_cand, scores)?, to_2d(n_robots, width - 1 - dim, strength)?))
        })?;
        Ok((theta.into_pyarray(py), scores.into_pyarray(py), strength.into_pyarray(py)))
    }
}
