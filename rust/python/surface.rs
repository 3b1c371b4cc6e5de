//! `uavcov._core.Surface`: the triangle mesh and its geometric queries.

use std::sync::Arc;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use super::{detached, held, invalid, parallel_map, points, points_to_py, to_py_err};
use crate::error::{try_copy, try_with_capacity, Error};
use crate::flight;
use crate::geometry::{in_bounds, Point, MAX_COORDINATE};
use crate::surface::mesh;
use crate::visibility::sampling;

/// `(points (n, 3), weights (n,))`.
type WeightedPoints<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);

/// `(closest points (n, 3), face indices (n,))`.
type PointsOnFaces<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<i64>>);
type FaceSets<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<i64>>, Bound<'py, PyArray1<i64>>);

/// A triangle mesh with its BVH (see `uavcov.Terrain`).
#[derive(Debug)]
#[pyclass(module = "uavcov._core", frozen, name = "Surface")]
pub struct PySurface {
    pub(crate) inner: Arc<mesh::Surface>,
}

#[pymethods]
impl PySurface {
    #[new]
    fn new(py: Python<'_>, vertices: PyReadonlyArray2<'_, f64>, faces: PyReadonlyArray2<'_, i64>) -> PyResult<Self> {
        let vertices = vertices.as_array();
        if vertices.ncols() != 3 {
            return Err(to_py_err(py, Error::Mesh(format!("vertices must have shape (n, 3), got {:?}", vertices.shape()))));
        }
        let mut verts: Vec<Point> = try_with_capacity(vertices.nrows(), "a copy of the vertices").map_err(|e| to_py_err(py, e))?;
        verts.extend(vertices.rows().into_iter().map(|r| [r[0], r[1], r[2]]));
        let f = faces.as_array();
        if f.ncols() != 3 {
            return Err(to_py_err(py, Error::Mesh(format!("faces must have shape (f, 3), got {:?}", f.shape()))));
        }
        let mut tris = try_with_capacity(f.nrows(), "a copy of the faces").map_err(|e| to_py_err(py, e))?;
        for (k, r) in f.rows().into_iter().enumerate() {
            let mut t = [0u32; 3];
            for c in 0..3 {
                t[c] = u32::try_from(r[c])
                    .map_err(|_| to_py_err(py, Error::Mesh(format!("face {k} has index {} outside [0, {})", r[c], verts.len()))))?;
            }
            tris.push(t);
        }
        let inner = detached(py, || mesh::Surface::new(verts, tris))?;
        Ok(Self { inner: Arc::new(inner) })
    }

    /// Triangulates an elevation grid `z` of shape `(ny, nx)`; NaN is nodata.
    #[staticmethod]
    fn from_grid(py: Python<'_>, z: PyReadonlyArray2<'_, f64>, dx: f64, dy: f64, x0: f64, y0: f64) -> PyResult<Self> {
        let a = z.as_array();
        let (ny, nx) = a.dim();
        let mut heights = try_with_capacity(a.len(), "a copy of the heights").map_err(|e| to_py_err(py, e))?;
        heights.extend(a.iter().copied());
        let inner = detached(py, || mesh::Surface::from_grid(heights, ny, nx, dx, dy, x0, y0))?;
        Ok(Self { inner: Arc::new(inner) })
    }

    #[getter]
    fn n_vertices(&self) -> usize {
        self.inner.n_vertices()
    }

    #[getter]
    fn n_faces(&self) -> usize {
        self.inner.n_triangles()
    }

    #[getter]
    fn area(&self) -> f64 {
        self.inner.area()
    }

    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = &self.inner;
        let flat = detached(py, || s.try_flat_vertices())?;
        let array = Array2::from_shape_vec((flat.len() / 3, 3), flat).map_err(|e| to_py_err(py, Error::Internal(e.to_string())))?;
        Ok(array.into_pyarray(py))
    }

    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let s = &self.inner;
        let (n, flat) = detached(py, || {
            let f = s.try_faces()?;
            let mut flat = try_with_capacity(3 * f.len(), "the face array")?;
            flat.extend(f.iter().flat_map(|t| t.map(i64::from)));
            Ok((f.len(), flat))
        })?;
        let array = Array2::from_shape_vec((n, 3), flat).map_err(|e| to_py_err(py, Error::Internal(e.to_string())))?;
        Ok(array.into_pyarray(py))
    }

    fn face_areas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let s = &self.inner;
        Ok(detached(py, || try_copy(s.try_areas()?, "the face areas"))?.into_pyarray(py))
    }

    fn bounds<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (lo, hi) = held(py, || Ok(self.inner.bounds()))?;
        Ok(points_to_py(py, vec![lo, hi]))
    }

    /// The vertices with a third of the area around each: `(points (V, 3), weights (V,))`.
    fn vertex_targets<'py>(&self, py: Python<'py>) -> PyResult<WeightedPoints<'py>> {
        let s = &self.inner;
        let (pts, w) = detached(py, || Ok(sampling::vertex_targets(s)))?;
        Ok((points_to_py(py, pts), w.into_pyarray(py)))
    }

    /// `density` evenly spread points per m^2: `(points (T, 3), weights (T,))`.
    fn area_targets<'py>(&self, py: Python<'py>, density: f64) -> PyResult<WeightedPoints<'py>> {
        let s = &self.inner;
        let (pts, w) = detached(py, || sampling::area_targets(s, density))?;
        Ok((points_to_py(py, pts), w.into_pyarray(py)))
    }

    /// The unit normal at each vertex of a grid surface (its default targets, in their order):
    /// `Grid::node_normal`, the one the engine rates incidence with; NaN where no whole triangle
    /// surrounds the vertex.
    fn vertex_normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let surface = &self.inner;
        let Some(grid) = surface.grid() else {
            return Err(invalid(py, "vertex normals are computed for elevation grids (Terrain.from_grid)".to_owned()));
        };
        let normals = detached(py, || {
            let n = surface.n_vertices();
            let mut out: Vec<Point> = try_with_capacity(n, "the vertex normals")?;
            out.resize(n, [f64::NAN; 3]);
            for k in 0..grid.ny * grid.nx {
                let v = if grid.vertex_of_node.is_empty() { k } else { grid.vertex_of_node[k] as usize };
                if let Some(slot) = out.get_mut(v) {
                    *slot = grid.node_normal(k).unwrap_or([f64::NAN; 3]);
                }
            }
            Ok(out)
        })?;
        Ok(points_to_py(py, normals))
    }

    /// Highest surface height under each `(x, y)`; NaN where there is none.
    #[pyo3(signature = (xy, n_threads=0))]
    fn ground_height<'py>(&self, py: Python<'py>, xy: PyReadonlyArray2<'_, f64>, n_threads: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let a = xy.as_array();
        if a.ncols() != 2 {
            return Err(invalid(py, format!("xy must have shape (n, 2), got {:?}", xy.shape())));
        }
        let pts: Vec<[f64; 2]> = a.rows().into_iter().map(|r| [r[0], r[1]]).collect();
        if pts.iter().any(|q| !q[0].is_finite() || !q[1].is_finite()) {
            return Err(invalid(py, "xy contains NaN or infinite values".into()));
        }
        if let Some(q) = pts.iter().find(|q| !in_bounds([q[0], q[1], 0.0])) {
            return Err(invalid(py, format!("xy has a coordinate beyond {MAX_COORDINATE:e} m in magnitude: {q:?}")));
        }
        let s = &self.inner;
        let out = parallel_map(py, n_threads, &pts, |q| s.ground_height(q[0], q[1]).unwrap_or(f64::NAN))?;
        Ok(out.into_pyarray(py))
    }

    /// Distance straight down from each point to the surface; inf where nothing is below.
    #[pyo3(signature = (points, n_threads=0))]
    fn clearance<'py>(&self, py: Python<'py>, points: PyReadonlyArray2<'_, f64>, n_threads: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let pts = super::points(py, &points, "points")?;
        let s = &self.inner;
        Ok(parallel_map(py, n_threads, &pts, |&q| s.clearance(q))?.into_pyarray(py))
    }

    /// The closest surface point to each point.
    #[pyo3(signature = (points, n_threads=0))]
    fn closest_point<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'_, f64>,
        n_threads: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let pts = super::points(py, &points, "points")?;
        let s = &self.inner;
        Ok(points_to_py(py, parallel_map(py, n_threads, &pts, |&q| s.closest_point(q))?))
    }

    /// The closest surface point to each point and the index of a triangle holding it:
    /// `(points (n, 3), faces (n,))`.
    #[pyo3(signature = (points, n_threads=0))]
    fn closest_face<'py>(&self, py: Python<'py>, points: PyReadonlyArray2<'_, f64>, n_threads: usize) -> PyResult<PointsOnFaces<'py>> {
        let pts = super::points(py, &points, "points")?;
        let s = &self.inner;
        detached(py, || s.triangle_mesh().map(|_| ()))?; // a grid's mesh, built once outside the pool
        let found = parallel_map(py, n_threads, &pts, |&q| s.closest_face(q).unwrap_or(([f64::NAN; 3], 0)))?;
        let faces: Vec<i64> = found.iter().map(|&(_, f)| f as i64).collect();
        Ok((points_to_py(py, found.into_iter().map(|(q, _)| q).collect()), faces.into_pyarray(py)))
    }

    /// The closest surface point to each point and every triangle holding it, as a CSR list:
    /// `(points (n, 3), start (n + 1,), faces (m,))`, point `i`'s faces `faces[start[i]:start[i + 1]]`.
    #[pyo3(signature = (points, n_threads=0))]
    fn faces_at_closest<'py>(&self, py: Python<'py>, points: PyReadonlyArray2<'_, f64>, n_threads: usize) -> PyResult<FaceSets<'py>> {
        let pts = super::points(py, &points, "points")?;
        let s = &self.inner;
        detached(py, || s.triangle_mesh().map(|_| ()))?; // a grid's mesh, built once outside the pool
        let found = parallel_map(py, n_threads, &pts, |&q| s.faces_at_closest(q).unwrap_or(([f64::NAN; 3], Vec::new())))?;
        let mut start: Vec<i64> = Vec::with_capacity(found.len() + 1);
        start.push(0);
        let mut faces: Vec<i64> = Vec::new();
        let mut closest = Vec::with_capacity(found.len());
        for (q, held) in found {
            faces.extend(held.into_iter().map(|f| f as i64));
            start.push(faces.len() as i64);
            closest.push(q);
        }
        Ok((points_to_py(py, closest), start.into_pyarray(py), faces.into_pyarray(py)))
    }

    /// The right-hand unit normal of each triangle, `(F, 3)`.
    fn face_normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = &self.inner;
        Ok(points_to_py(py, detached(py, || s.face_normals())?))
    }

    /// The least 3D distance from each point to the surface.
    #[pyo3(signature = (points, n_threads=0))]
    fn distance<'py>(&self, py: Python<'py>, points: PyReadonlyArray2<'_, f64>, n_threads: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let pts = super::points(py, &points, "points")?;
        let s = &self.inner;
        detached(py, || s.triangle_mesh().map(|_| ()))?; // a grid's mesh, built once outside the pool
        Ok(parallel_map(py, n_threads, &pts, |&q| s.distance(q).unwrap_or(f64::NAN))?.into_pyarray(py))
    }

    /// Whether each point is inside a closed solid of the surface.
    #[pyo3(signature = (points, n_threads=0))]
    fn inside<'py>(&self, py: Python<'py>, points: PyReadonlyArray2<'_, f64>, n_threads: usize) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let pts = super::points(py, &points, "points")?;
        let s = &self.inner;
        detached(py, || s.triangle_mesh().map(|_| ()))?;
        Ok(parallel_map(py, n_threads, &pts, |&q| s.inside(q).unwrap_or(false))?.into_pyarray(py))
    }

    /// Which of the `len(candidates) / len(current)` configurations in `candidates` (one after
    /// the other) are admissible under the flight limits of eq. 2 (see `uavcov.flight`).
    #[pyo3(signature = (current, candidates, bounds, h_min, h_max, z_max, d_safe, check_moves, n_threads=0, clearance="vertical"))]
    #[allow(clippy::too_many_arguments)] // the limits as Python gives them, one value each
    fn admissible_mask<'py>(
        &self,
        py: Python<'py>,
        current: PyReadonlyArray2<'_, f64>,
        candidates: PyReadonlyArray2<'_, f64>,
        bounds: [f64; 4],
        h_min: f64,
        h_max: Option<f64>,
        z_max: f64,
        d_safe: f64,
        check_moves: bool,
        n_threads: usize,
        clearance: &str,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let clearance: flight::Clearance = clearance.parse().map_err(|e| to_py_err(py, e))?;
        let current = points(py, &current, "current")?;
        // Candidates far outside the bounds are refused, not errors: copied as they are (the
        // kernel queries the surface only for those inside the bounds, and checks them there).
        let c = candidates.as_array();
        if c.ncols() != 3 {
            return Err(invalid(py, format!("candidates must have shape (n, 3), got {:?}", candidates.shape())));
        }
        let mut cand: Vec<Point> = try_with_capacity(c.nrows(), "a copy of the candidates").map_err(|e| to_py_err(py, e))?;
        cand.extend(c.rows().into_iter().map(|r| [r[0], r[1], r[2]]));
        let limits = flight::FlightLimits { bounds, h_min, h_max, z_max, d_safe, check_moves, clearance };
        let s = &self.inner;
        Ok(detached(py, || flight::admissible_mask(s, &limits, &current, &cand, n_threads))?.into_pyarray(py))
    }

    /// Distance along each ray `origins[k] + t directions[k]` (unit directions) to its first
    /// triangle, metres, `0 <= t <= t_max` (directions are normalised); inf where the ray meets
    /// none (a depth camera's pixels).
    #[pyo3(signature = (origins, directions, t_max, n_threads=0))]
    fn first_hits<'py>(
        &self,
        py: Python<'py>,
        origins: PyReadonlyArray2<'_, f64>,
        directions: PyReadonlyArray2<'_, f64>,
        t_max: f64,
        n_threads: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let origins = points(py, &origins, "origins")?;
        let directions = points(py, &directions, "directions")?;
        if origins.len() != directions.len() {
            return Err(invalid(py, format!("origins has {} rays but directions has {}", origins.len(), directions.len())));
        }
        if !(t_max.is_finite() && t_max > 0.0 && t_max <= MAX_COORDINATE) {
            return Err(invalid(py, format!("t_max must be positive and finite, at most {MAX_COORDINATE:e}, got {t_max}")));
        }
        let mut rays: Vec<(Point, Point)> = try_with_capacity(origins.len(), "a copy of the rays").map_err(|e| to_py_err(py, e))?;
        for (k, (o, d)) in origins.into_iter().zip(directions).enumerate() {
            let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if !(norm > 1e-12 && norm.is_finite()) {
                return Err(invalid(py, format!("direction {k} has length {norm}: every ray needs a direction")));
            }
            rays.push((o, [d[0] / norm, d[1] / norm, d[2] / norm])); // unit, so t is metres
        }
        let s = &self.inner; // a grid answers from its height field: no triangle mesh is built
        Ok(parallel_map(py, n_threads, &rays, |&(o, d)| s.first_hit(o, d, t_max).unwrap_or(f64::INFINITY))?.into_pyarray(py))
    }

    /// Whether each closed segment `a[k] -> b[k]` crosses no triangle.
    #[pyo3(signature = (a, b, n_threads=0))]
    fn segments_clear<'py>(
        &self,
        py: Python<'py>,
        a: PyReadonlyArray2<'_, f64>,
        b: PyReadonlyArray2<'_, f64>,
        n_threads: usize,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let a = points(py, &a, "a")?;
        let b = points(py, &b, "b")?;
        if a.len() != b.len() {
            return Err(invalid(py, format!("a has {} points but b has {}", a.len(), b.len())));
        }
        let pairs: Vec<(Point, Point)> = a.into_iter().zip(b).collect();
        let s = &self.inner;
        Ok(parallel_map(py, n_threads, &pairs, |&(p, q)| s.segment_clear(p, q))?.into_pyarray(py))
    }
}
