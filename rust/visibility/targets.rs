//! The points to see: given ones, with weights and optionally normals, or the nodes of a grid
//! surface, generated chunk by chunk.

use std::sync::{Arc, OnceLock};

use super::CHUNK;
use crate::error::{ensure, try_with_capacity, Error, Result};
use crate::geometry::{in_bounds, Point, MAX_COORDINATE};
use crate::surface::mesh::Surface;
use crate::visibility::sampling::default_targets;

/// Points to see and the area (m^2) each stands for.
#[derive(Debug, Clone)]
pub struct Targets {
    pub(super) points: Points,
    pub(super) len: usize,
    pub(super) weights: Vec<f64>,
    pub(super) total_weight: f64,
    /// Bounding box `(mins, maxs)` of each chunk of `CHUNK` consecutive targets.
    pub(super) chunk_bounds: Vec<(Point, Point)>,
    /// Unit surface normals of given points, when known (grid nodes compute theirs).
    pub(super) normals: Option<Vec<Point>>,
    /// Grid-node targets' normals (NaN where no triangle around the node is whole), computed
    /// the first time a sensor needs them.
    pub(super) node_normals: OnceLock<Vec<Point>>,
}

#[derive(Debug, Clone)]
pub(super) enum Points {
    /// Stored points.
    Given(Vec<Point>),
    /// The vertices of a grid surface, generated when needed: for chunk `c`, the first node of
    /// the chunk (the rest follow in row-major order, skipping unused nodes).
    GridNodes { surface: Arc<Surface>, chunk_start: Vec<usize> },
}

impl Targets {
    /// User-given targets; weights default to 1 each.
    ///
    /// # Errors
    /// When a coordinate is not finite or beyond [`MAX_COORDINATE`], weights have the wrong
    /// length or a negative or non-finite value, or all weights are zero.
    pub fn new(points: Vec<Point>, weights: Option<Vec<f64>>) -> Result<Self> {
        ensure!(!points.is_empty(), "there must be at least one target");
        ensure!(points.iter().all(|q| q.iter().all(|c| c.is_finite())), "target coordinates must be finite");
        ensure!(points.iter().all(|&q| in_bounds(q)), "target coordinates must be at most {MAX_COORDINATE:e} m in magnitude");
        let weights = weights.unwrap_or_else(|| vec![1.0; points.len()]);
        ensure!(weights.len() == points.len(), "{} weights for {} targets", weights.len(), points.len());
        let chunk_bounds = points.chunks(CHUNK).map(bounds).collect();
        Self::finish(Points::Given(points), weights, chunk_bounds)
    }

    fn finish(points: Points, weights: Vec<f64>, chunk_bounds: Vec<(Point, Point)>) -> Result<Self> {
        ensure!(weights.iter().all(|w| w.is_finite() && *w >= 0.0), "target weights must be finite and >= 0");
        let total_weight: f64 = weights.iter().sum();
        ensure!(total_weight.is_finite() && total_weight > 0.0, "target weights are all zero or sum to infinity");
        Ok(Self { points, len: weights.len(), weights, total_weight, chunk_bounds, normals: None, node_normals: OnceLock::new() })
    }

    /// These targets with their unit surface normals (one per point, for incidence limits and
    /// view quality); grid-node targets compute theirs from the grid.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for grid-node targets, a count other than one per target, or a
    /// normal that is not a finite unit vector (to 1e-6).
    pub fn with_normals(mut self, normals: Vec<Point>) -> Result<Self> {
        ensure!(matches!(self.points, Points::Given(_)), "grid-node targets compute their own normals");
        ensure!(normals.len() == self.len, "{} normals for {} targets", normals.len(), self.len);
        ensure!(
            normals.iter().all(|n| n.iter().all(|c| c.is_finite()) && ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1.0).abs() <= 1e-6),
            "target normals must be finite unit vectors"
        );
        self.normals = Some(normals);
        Ok(self)
    }

    /// Whether every target has a normal (given, or a grid node's).
    #[must_use]
    pub fn has_normals(&self) -> bool {
        self.normals.is_some() || self.is_grid_nodes()
    }

    /// Every target's unit normal (NaN where unknown), when the targets have normals; a grid's
    /// are computed on the first call (24 bytes a target).
    ///
    /// # Errors
    /// [`Error::TooLarge`] when the system refuses the memory for a grid's normals.
    pub(super) fn normals(&self) -> Result<Option<&[Point]>> {
        match &self.points {
            Points::GridNodes { surface, .. } => {
                if let Some(done) = self.node_normals.get() {
                    return Ok(Some(done));
                }
                let g = surface.grid().expect("grid-node targets hold a grid surface");
                let mut all = try_with_capacity(self.len, "the grid targets' normals")?;
                all.extend(
                    (0..g.nx * g.ny).filter(|&k| g.vertex_of_node[k] != u32::MAX).map(|k| g.node_normal(k).unwrap_or([f64::NAN; 3])),
                );
                Ok(Some(self.node_normals.get_or_init(|| all)))
            }
            Points::Given(_) => Ok(self.normals.as_deref()),
        }
    }

    /// The surface's default targets (see [`default_targets`]).
    ///
    /// # Errors
    /// As [`default_targets`].
    pub fn of_surface(surface: &Surface, density: f64) -> Result<Self> {
        let (points, weights) = default_targets(surface, density)?;
        Self::new(points, Some(weights))
    }

    /// The vertices of a grid surface, each weighted by a third of the triangles around it: the
    /// same targets, order and weights as [`Targets::of_surface`], without storing the points
    /// (8 bytes a target instead of 32), which is what lets a map of many millions of nodes fit.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when the surface was not built from a grid.
    pub fn grid_nodes(surface: Arc<Surface>) -> Result<Self> {
        let field = surface
            .heightfield()
            .ok_or_else(|| Error::InvalidInput("grid-node targets need a surface built from an elevation grid".into()))?;
        let g = field.grid();
        let weights = field.vertex_weights();
        let mut chunk_start = Vec::with_capacity(weights.len().div_ceil(CHUNK));
        let mut chunk_bounds = Vec::with_capacity(chunk_start.capacity());
        let mut chunk = Vec::with_capacity(CHUNK);
        for (k, &vertex) in g.vertex_of_node.iter().enumerate() {
            if vertex == u32::MAX {
                continue;
            }
            if chunk.is_empty() {
                chunk_start.push(k);
            }
            chunk.push(g.node_point(k));
            if chunk.len() == CHUNK {
                chunk_bounds.push(bounds(&chunk));
                chunk.clear();
            }
        }
        if !chunk.is_empty() {
            chunk_bounds.push(bounds(&chunk));
        }
        drop(chunk);
        Self::finish(Points::GridNodes { surface, chunk_start }, weights, chunk_bounds)
    }

    /// Whether the points are generated from a grid surface rather than stored.
    #[must_use]
    pub fn is_grid_nodes(&self) -> bool {
        matches!(self.points, Points::GridNodes { .. })
    }

    /// The target points (generated for grid-node targets).
    #[must_use]
    pub fn points(&self) -> std::borrow::Cow<'_, [Point]> {
        match &self.points {
            Points::Given(p) => std::borrow::Cow::Borrowed(p),
            Points::GridNodes { .. } => {
                let mut out = Vec::with_capacity(self.len);
                for c in 0..self.chunk_bounds.len() {
                    self.chunk_points(c, &mut out);
                }
                std::borrow::Cow::Owned(out)
            }
        }
    }

    /// Target `t` of chunk `c` and its grid node (grid-node targets), computed alone: at once
    /// when every node is a target, by counting the chunk's nodes up to it otherwise.
    #[inline]
    pub(crate) fn chunk_target(&self, c: usize, t: usize) -> (Point, Option<usize>) {
        match &self.points {
            Points::Given(p) => (p[c * CHUNK + t], None),
            Points::GridNodes { surface, chunk_start } => {
                let g = surface.grid().expect("grid-node targets hold a grid surface");
                let k = if self.len == g.vertex_of_node.len() {
                    c * CHUNK + t
                } else {
                    (chunk_start[c]..).filter(|&k| g.vertex_of_node[k] != u32::MAX).nth(t).expect("a chunk holds its targets")
                };
                (g.node_point(k), Some(k))
            }
        }
    }

    /// Appends the points of chunk `c` to `out`.
    pub(crate) fn chunk_points(&self, c: usize, out: &mut Vec<Point>) {
        match &self.points {
            Points::Given(p) => out.extend_from_slice(&p[c * CHUNK..((c + 1) * CHUNK).min(p.len())]),
            Points::GridNodes { surface, chunk_start } => {
                let g = surface.grid().expect("grid-node targets hold a grid surface");
                let n = self.chunk_len(c);
                let k0 = chunk_start[c];
                if self.len == g.vertex_of_node.len() {
                    // Every node is a target: the chunk is a run of whole row pieces.
                    let (mut k, stop) = (k0, k0 + n);
                    while k < stop {
                        let (i, j0) = (k / g.nx, k % g.nx);
                        let j1 = g.nx.min(j0 + stop - k);
                        let (y, row) = (g.y0 + i as f64 * g.dy, &g.z[i * g.nx..(i + 1) * g.nx]);
                        out.extend((j0..j1).map(|j| [g.x0 + j as f64 * g.dx, y, row[j]]));
                        k += j1 - j0;
                    }
                    return;
                }
                // Walk row by row instead of dividing each node index by the row length.
                let (mut i, mut j) = (k0 / g.nx, k0 % g.nx);
                let mut y = g.y0 + i as f64 * g.dy;
                let stop = out.len() + n;
                while out.len() < stop {
                    let k = i * g.nx + j;
                    if g.vertex_of_node[k] != u32::MAX {
                        out.push([g.x0 + j as f64 * g.dx, y, g.z[k]]);
                    }
                    j += 1;
                    if j == g.nx {
                        j = 0;
                        i += 1;
                        y = g.y0 + i as f64 * g.dy;
                    }
                }
            }
        }
    }

    /// Appends the grid nodes (row-major indices) of chunk `c`'s targets to `out`, for grid-node
    /// targets (nothing otherwise).
    pub(super) fn chunk_nodes(&self, c: usize, out: &mut Vec<usize>) {
        let Points::GridNodes { surface, chunk_start } = &self.points else {
            return;
        };
        let g = surface.grid().expect("grid-node targets hold a grid surface");
        if self.len == g.vertex_of_node.len() {
            out.extend(chunk_start[c]..chunk_start[c] + self.chunk_len(c));
            return;
        }
        let stop = out.len() + self.chunk_len(c);
        out.extend((chunk_start[c]..).filter(|&k| g.vertex_of_node[k] != u32::MAX).take(stop - out.len()));
    }

    /// The weight of each target.
    #[must_use]
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Number of targets.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Always false: a target set is never empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub(super) fn chunk_len(&self, c: usize) -> usize {
        CHUNK.min(self.len - c * CHUNK)
    }

    pub(super) fn n_chunks(&self) -> usize {
        self.chunk_bounds.len()
    }
}

fn bounds(points: &[Point]) -> (Point, Point) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for q in points {
        for k in 0..3 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    (lo, hi)
}
