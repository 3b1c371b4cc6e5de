//! `uavcov._core.CVT`: the constrained CVT of a surface (see `uavcov.cvt`).

use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use super::surface::PySurface;
use super::{detached, invalid, points, points_to_py, to_py_err};
use crate::cvt::{self, CvtOptions, Weights};

/// `(generators (N, 3), normals (N, 3), moves (K,), drift (K,), energy (K,), iterations, converged)`.
type RunOutput<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    usize,
    bool,
);

/// The probabilistic MacQueen CVT; static methods only (one class keeps the module's names few).
#[derive(Debug)]
#[pyclass(module = "uavcov._core", frozen, name = "CVT")]
pub struct PyCvt;

#[pymethods]
impl PyCvt {
    /// Runs the CVT; the Python wrapper `uavcov.cvt.cvt` validates and documents the arguments.
    #[staticmethod]
    #[pyo3(signature = (surface, n, samples_per_iteration, alpha, beta, tolerance, window, max_iterations, seed, density=None, initial=None, n_threads=0, normal_weight=0.0))]
    #[expect(clippy::too_many_arguments, reason = "the Python-visible signature of `_core.CVT.run`; Rust gathers them in `CvtOptions`")]
    fn run<'py>(
        py: Python<'py>,
        surface: &Bound<'py, PySurface>,
        n: usize,
        samples_per_iteration: usize,
        alpha: (f64, f64),
        beta: (f64, f64),
        tolerance: f64,
        window: usize,
        max_iterations: usize,
        seed: u64,
        density: Option<PyReadonlyArray1<'py, f64>>,
        initial: Option<PyReadonlyArray2<'py, f64>>,
        n_threads: usize,
        normal_weight: f64,
    ) -> PyResult<RunOutput<'py>> {
        let weights = Weights::new([alpha.0, alpha.1], [beta.0, beta.1]).map_err(|e| to_py_err(py, e))?;
        let options = CvtOptions { samples_per_iteration, weights, tolerance, window, max_iterations, seed, n_threads, normal_weight };
        // Copies, so Rust reads nothing Python could change once the GIL is released.
        let density: Option<Vec<f64>> = density.map(|d| d.as_array().to_vec());
        let initial = match initial {
            Some(a) => Some(points(py, &a, "initial")?),
            None => None,
        };
        let surface = surface.get().inner.clone();
        let result = detached(py, || cvt::constrained_cvt(&surface, n, &options, density.as_deref(), initial.as_deref()))?;
        Ok((
            points_to_py(py, result.generators),
            points_to_py(py, result.normals),
            result.moves.into_pyarray(py),
            result.drift.into_pyarray(py),
            result.energy.into_pyarray(py),
            result.iterations,
            result.converged,
        ))
    }

    /// For each point `(n, 3)`, the index of its nearest generator `(N, 3)`: `(n,)` int64.
    #[staticmethod]
    #[pyo3(signature = (generators, points, n_threads=0))]
    fn regions<'py>(
        py: Python<'py>,
        generators: PyReadonlyArray2<'py, f64>,
        points: PyReadonlyArray2<'py, f64>,
        n_threads: usize,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let gens = super::points(py, &generators, "generators")?;
        let pts = super::points(py, &points, "points")?;
        if gens.is_empty() {
            return Err(invalid(py, "there must be at least one generator".into()));
        }
        let labels = detached(py, || cvt::nearest_generator(&gens, &pts, n_threads))?;
        Ok(labels.into_iter().map(|i| i as i64).collect::<Vec<i64>>().into_pyarray(py))
    }
}
