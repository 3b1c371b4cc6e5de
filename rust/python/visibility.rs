//! `uavcov._core.Visibility`: the coverage objective.

use std::sync::Arc;

use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use super::surface::PySurface;
use super::{detached, held, invalid, points, to_py_err};
use crate::error::Result;
use crate::geometry::Point;
use crate::visibility;
use crate::visibility::sensor::{Frustum, Sensor};

/// Columns of a packed sensor row: `d_min, d_max`, a camera's `forward (3), right (3), up (3),
/// tan_h, tan_v` (all NaN for an omnidirectional sensor), the cosine of the largest incidence
/// angle (NaN: no limit), and `gsd per metre, GSD of full quality` (NaN: no resolution rating).
const SENSOR_COLUMNS: usize = 16;

/// The sensors packed by `uavcov.sensors` (one row per UAV), copied and checked.
pub(super) fn sensors(py: Python<'_>, packed: Option<PyReadonlyArray2<'_, f64>>) -> PyResult<Option<Vec<Sensor>>> {
    let Some(packed) = packed else { return Ok(None) };
    let a = packed.as_array();
    if a.ncols() != SENSOR_COLUMNS {
        return Err(invalid(py, format!("sensors must have shape (N, {SENSOR_COLUMNS}), got {:?}", a.shape())));
    }
    let parse = |r: numpy::ndarray::ArrayView1<'_, f64>| -> Result<Sensor> {
        let camera = if r.iter().skip(2).take(11).all(|v| v.is_nan()) {
            None
        } else {
            let axis = |k: usize| [r[k], r[k + 1], r[k + 2]];
            Some(Frustum::new(axis(2), axis(5), axis(8), r[11], r[12])?)
        };
        let mut sensor = Sensor::new(r[0], r[1], camera)?;
        if !r[13].is_nan() {
            sensor = sensor.with_incidence_limit(r[13])?;
        }
        if !(r[14].is_nan() && r[15].is_nan()) {
            sensor = sensor.with_resolution(r[14], r[15])?;
        }
        Ok(sensor)
    };
    a.rows().into_iter().map(parse).collect::<Result<Vec<_>>>().map(Some).map_err(|e| to_py_err(py, e))
}

/// `(seen (U,), exclusive (U,), seen_weight (U,), exclusive_weight (U,), total_weight, coverage)`.
type PerUavOutput<'py> =
    (Bound<'py, PyArray1<u64>>, Bound<'py, PyArray1<u64>>, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, f64, f64);

/// The coverage objective for one surface, target set and sensing range (see
/// `uavcov.Visibility`).
#[derive(Debug)]
#[pyclass(module = "uavcov._core", frozen, name = "Visibility")]
pub struct PyVisibility {
    pub(super) inner: Arc<visibility::Visibility>,
}

/// The UAVs' positions and their sensors (`None`: the objective's one range), copied and checked.
fn team(
    py: Python<'_>,
    uavs: &PyReadonlyArray2<'_, f64>,
    packed: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<(Vec<Point>, Option<Vec<Sensor>>)> {
    Ok((points(py, uavs, "uavs")?, sensors(py, packed)?))
}

#[pymethods]
impl PyVisibility {
    /// `targets` and `weights` both `None`: the grid surface's vertices, generated in Rust.
    /// `method`: "auto" (the grid path for a grid surface), "mesh" or "grid".
    #[new]
    #[pyo3(signature = (surface, targets, weights, d_max, method="auto", normals=None))]
    fn new(
        py: Python<'_>,
        surface: &PySurface,
        targets: Option<PyReadonlyArray2<'_, f64>>,
        weights: Option<PyReadonlyArray1<'_, f64>>,
        d_max: f64,
        method: &str,
        normals: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<Self> {
        let path: visibility::Path = method.parse().map_err(|e| to_py_err(py, e))?;
        let normals = match normals {
            Some(n) => Some(points(py, &n, "normals")?),
            None => None,
        };
        let t = match (targets, weights) {
            (Some(targets), Some(weights)) => {
                let pts = points(py, &targets, "targets")?;
                let w = weights.as_array().to_vec();
                detached(py, || {
                    let t = visibility::Targets::new(pts, Some(w))?;
                    match normals {
                        Some(n) => t.with_normals(n),
                        None => Ok(t),
                    }
                })?
            }
            (None, None) => {
                let s = surface.inner.clone();
                detached(py, || visibility::Targets::grid_nodes(s))?
            }
            _ => return Err(to_py_err(py, crate::error::Error::InvalidInput("give both targets and weights, or neither".into()))),
        };
        let s = surface.inner.clone();
        let inner = detached(py, || visibility::Visibility::with_path(s, t, d_max, path))?;
        Ok(Self { inner: Arc::new(inner) })
    }

    /// The path the line-of-sight tests take: "grid" or "mesh".
    #[getter]
    fn path(&self) -> &'static str {
        match self.inner.path() {
            visibility::Path::Grid => "grid",
            _ => "mesh",
        }
    }

    #[getter]
    fn n_targets(&self, py: Python<'_>) -> PyResult<usize> {
        held(py, || Ok(self.inner.targets().len()))
    }

    #[getter]
    fn d_max(&self) -> f64 {
        self.inner.d_max()
    }

    /// `(T,)` bool: whether at least one UAV sees each target.
    #[pyo3(signature = (uavs, n_threads=0, sensors=None))]
    fn seen<'py>(
        &self,
        py: Python<'py>,
        uavs: PyReadonlyArray2<'_, f64>,
        n_threads: usize,
        sensors: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let (u, sensors) = team(py, &uavs, sensors)?;
        let mask = detached(py, || self.inner.seen_by(&u, sensors.as_deref(), n_threads))?;
        Ok(mask.into_pyarray(py))
    }

    /// Weighted share of targets seen, in [0, 1].
    #[pyo3(signature = (uavs, n_threads=0, sensors=None))]
    fn coverage(
        &self,
        py: Python<'_>,
        uavs: PyReadonlyArray2<'_, f64>,
        n_threads: usize,
        sensors: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<f64> {
        let (u, sensors) = team(py, &uavs, sensors)?;
        detached(py, || self.inner.coverage_by(&u, sensors.as_deref(), n_threads))
    }

    /// `(T,)` float: each target's best view quality over the UAVs that see it (0: unseen).
    #[pyo3(signature = (uavs, n_threads=0, sensors=None))]
    fn quality<'py>(
        &self,
        py: Python<'py>,
        uavs: PyReadonlyArray2<'_, f64>,
        n_threads: usize,
        sensors: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (u, sensors) = team(py, &uavs, sensors)?;
        Ok(detached(py, || self.inner.quality_by(&u, sensors.as_deref(), n_threads))?.into_pyarray(py))
    }

    /// Quality-weighted coverage, in [0, 1].
    #[pyo3(signature = (uavs, n_threads=0, sensors=None))]
    fn quality_coverage(
        &self,
        py: Python<'_>,
        uavs: PyReadonlyArray2<'_, f64>,
        n_threads: usize,
        sensors: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<f64> {
        let (u, sensors) = team(py, &uavs, sensors)?;
        detached(py, || self.inner.quality_coverage_by(&u, sensors.as_deref(), n_threads))
    }

    /// Per UAV, `(seen (U,) uint64, exclusive (U,) uint64, seen_weight (U,), exclusive_weight (U,))`,
    /// then `total_weight` and the team's `coverage` (equal to `coverage()` to the last bit).
    #[pyo3(signature = (uavs, n_threads=0, sensors=None))]
    fn per_uav<'py>(
        &self,
        py: Python<'py>,
        uavs: PyReadonlyArray2<'_, f64>,
        n_threads: usize,
        sensors: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<PerUavOutput<'py>> {
        let (u, sensors) = team(py, &uavs, sensors)?;
        let c = detached(py, || self.inner.per_uav_by(&u, sensors.as_deref(), n_threads))?;
        Ok((
            c.seen.into_pyarray(py),
            c.exclusive.into_pyarray(py),
            c.seen_weight.into_pyarray(py),
            c.exclusive_weight.into_pyarray(py),
            c.total_weight,
            c.coverage,
        ))
    }
}
