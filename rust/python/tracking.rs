//! `uavcov._core.CoverageTracker`: coverage of a moving team (see [`crate::visibility::tracking`]).

use numpy::{IntoPyArray, PyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use super::visibility::PyVisibility;
use super::{detached, points};
use crate::visibility::tracking::{CoverageTracker, Margin};

/// The coverage of one team evaluated again and again as it moves (see `uavcov.CoverageTracker`).
#[derive(Debug)]
#[pyclass(module = "uavcov._core", name = "CoverageTracker")]
pub struct PyCoverageTracker {
    inner: CoverageTracker,
}

#[pymethods]
impl PyCoverageTracker {
    /// `margin` in metres, or `None` for each anchor its own (`Margin::Adaptive`).
    #[new]
    #[pyo3(signature = (visibility, margin=None))]
    fn new(py: Python<'_>, visibility: &PyVisibility, margin: Option<f64>) -> PyResult<Self> {
        let vis = visibility.inner.clone();
        let margin = margin.map_or(Margin::Adaptive, Margin::Fixed);
        Ok(Self { inner: detached(py, || CoverageTracker::new(vis, margin))? })
    }

    #[getter]
    fn margin(&self) -> Option<f64> {
        match self.inner.margin() {
            Margin::Fixed(m) => Some(m),
            Margin::Adaptive => None,
        }
    }

    #[getter]
    fn certifies(&self) -> bool {
        self.inner.certifies()
    }

    #[getter]
    fn settled(&self) -> usize {
        self.inner.settled()
    }

    /// `(T,)` bool: whether at least one UAV sees each target.
    #[pyo3(signature = (uavs, n_threads=0))]
    fn seen<'py>(&mut self, py: Python<'py>, uavs: PyReadonlyArray2<'_, f64>, n_threads: usize) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let u = points(py, &uavs, "uavs")?;
        let tracker = &mut self.inner;
        Ok(detached(py, || tracker.seen(&u, n_threads))?.into_pyarray(py))
    }

    /// Weighted share of targets seen, in [0, 1].
    #[pyo3(signature = (uavs, n_threads=0))]
    fn coverage(&mut self, py: Python<'_>, uavs: PyReadonlyArray2<'_, f64>, n_threads: usize) -> PyResult<f64> {
        let u = points(py, &uavs, "uavs")?;
        let tracker = &mut self.inner;
        detached(py, || tracker.coverage(&u, n_threads))
    }
}
