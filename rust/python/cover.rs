//! `uavcov._core.SeenMatrix`: candidate viewpoints' seen-matrix, lazy greedy and the online
//! bound (see `uavcov.placement.greedy_placement`).

use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use super::visibility::{sensors, PyVisibility};
use super::{detached, held, points};
use crate::cover::{self, SeenMatrix};
use crate::geometry::Point;

/// `(picks (k,) int64, gains (k,) float64, coverage, bound)`.
type GreedyOutput<'py> = (Bound<'py, PyArray1<i64>>, Bound<'py, PyArray1<f64>>, f64, f64);

/// For each candidate viewpoint, the targets it sees (bitsets), with the candidates' positions.
#[derive(Debug)]
#[pyclass(module = "uavcov._core", frozen, name = "SeenMatrix")]
pub struct PySeenMatrix {
    inner: SeenMatrix,
    positions: Vec<Point>,
}

#[pymethods]
impl PySeenMatrix {
    /// Builds the columns of `candidates` `(C, 3)` on `visibility`'s surface and targets, each with
    /// its packed sensor row (`sensors` `(C, 16)`, or `None`: the objective's range).
    #[new]
    #[pyo3(signature = (visibility, candidates, sensors=None, n_threads=0))]
    fn new(
        py: Python<'_>,
        visibility: &PyVisibility,
        candidates: PyReadonlyArray2<'_, f64>,
        sensors: Option<PyReadonlyArray2<'_, f64>>,
        n_threads: usize,
    ) -> PyResult<Self> {
        let positions = points(py, &candidates, "candidates")?;
        let sensors = self::sensors(py, sensors)?;
        let vis = visibility.inner.clone();
        let inner = detached(py, || SeenMatrix::build(&vis, &positions, sensors.as_deref(), n_threads))?;
        Ok(Self { inner, positions })
    }

    #[getter]
    fn n_candidates(&self) -> usize {
        self.inner.n_candidates()
    }

    #[getter]
    fn n_targets(&self) -> usize {
        self.inner.n_targets()
    }

    /// Bytes the bits take.
    #[getter]
    fn nbytes(&self) -> usize {
        self.inner.bytes()
    }

    /// The weighted share of the targets at least one candidate sees.
    fn ceiling(&self, py: Python<'_>) -> f64 {
        py.detach(|| self.inner.ceiling())
    }

    /// `(T,)` bool: the targets candidate `c` sees.
    fn column<'py>(&self, py: Python<'py>, c: usize) -> PyResult<Bound<'py, PyArray1<bool>>> {
        Ok(held(py, || self.inner.column(c))?.into_pyarray(py))
    }

    /// Lazy greedy of `k` candidates kept `d_safe` apart: picks, gains (shares), coverage, bound.
    #[pyo3(signature = (k, d_safe, n_threads=0))]
    fn greedy<'py>(&self, py: Python<'py>, k: usize, d_safe: f64, n_threads: usize) -> PyResult<GreedyOutput<'py>> {
        let g = detached(py, || cover::greedy(&self.inner, &self.positions, k, d_safe, n_threads))?;
        let picks: Vec<i64> = g.picks.iter().map(|&c| c as i64).collect();
        Ok((picks.into_pyarray(py), g.gains.into_pyarray(py), g.coverage, g.bound))
    }

    /// The online bound for a placement of `k` whose true seen mask is `seen` `(T,)`:
    /// `(coverage, bound)`.
    #[pyo3(signature = (seen, k, n_threads=0))]
    fn bound(&self, py: Python<'_>, seen: PyReadonlyArray1<'_, bool>, k: usize, n_threads: usize) -> PyResult<(f64, f64)> {
        let seen = seen.as_array().to_vec();
        let b = detached(py, || cover::bound(&self.inner, &seen, k, n_threads))?;
        Ok((b.coverage, b.bound))
    }
}
