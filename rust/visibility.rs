//! Who sees what: the coverage objective of the paper (its eq. 1, discretised on targets).
//!
//! A target `q` is seen from a UAV at `p` when `|p - q| <= d_max` and the segment from `p`
//! towards `q`, stopped 0.1 % of its length short of `q`, crosses no triangle. Coverage is the
//! weighted share of targets seen by at least one UAV.
//!
//! Work is split into fixed chunks of neighbouring targets, stolen by rayon's threads; each
//! chunk first drops the UAVs out of range of its bounding box, and a target stops at the first
//! UAV that sees it. Chunks are combined in order, so results are identical for any thread count.
//!
//! Each segment is tested on one of two paths ([`Path`]): the triangle mesh with parry's BVH, or,
//! for a surface built from an elevation grid, the [`HeightField`] walk, which gives the same
//! answer for every segment (see [`crate::heightfield`]) at a fraction of the cost and memory.
//! The grid path is chosen automatically; the mesh path of a grid stays available for comparison.
//! On the grid path, grid-node targets also get their skyline (how steeply the surface rises
//! around them, direction by direction) from their chunk's second evaluation on, which settles
//! most sight lines with two look-ups.
//!
//! ```
//! use uavcov::mesh::Surface;
//! use uavcov::visibility::{Targets, Visibility};
//! let s = Surface::from_grid(vec![0.0; 121], 11, 11, 1.0, 1.0, 0.0, 0.0).unwrap();
//! let targets = Targets::of_surface(&s, 1.0).unwrap();
//! let vis = Visibility::new(std::sync::Arc::new(s), targets, 100.0).unwrap();
//! // One UAV high above a flat square sees all of it.
//! assert_eq!(vis.coverage(&[[5.0, 5.0, 20.0]], 1).unwrap(), 1.0);
//! ```

use std::sync::{Arc, OnceLock};

use rayon::prelude::*;

use crate::error::{ensure, try_filled, try_with_capacity, Error, Result};
use crate::geometry::{in_bounds, Point, MAX_COORDINATE, UNLIMITED_RANGE};
use crate::heightfield::{HeightField, Horizon};
use crate::mesh::{Blockers, Surface, TriangleMesh};
use crate::sampling::default_targets;
use crate::sensor::Sensor;
use crate::skyline::{sector_edges, ChunkSkylines, SectorEdges, Skyline, Skylines, Stencil};
use crate::threads;

/// Targets per chunk: small enough to balance very unequal UAV footprints, large enough that
/// the per-chunk culling and rayon's ~1 us per task stay negligible.
pub(crate) const CHUNK: usize = 256;

/// Most horizon bounds kept at once for one evaluation (4 bytes each: 256 MiB), shared by its
/// UAVs; a horizon's size changes how much of a sight line it clears, never an answer.
pub(crate) const HORIZON_BUDGET: usize = 1 << 26;

/// Most per-UAV counters (`UavCounts`, 32 bytes per UAV) held at once by [`Visibility::per_uav`]
/// (128 MiB): its chunks are evaluated in batches of this many counters and summed in chunk
/// order, so the batch size never changes a result.
const COUNTS_BUDGET: usize = 1 << 22;

/// Points to see and the area (m^2) each stands for.
#[derive(Debug, Clone)]
pub struct Targets {
    points: Points,
    len: usize,
    weights: Vec<f64>,
    total_weight: f64,
    /// Bounding box `(mins, maxs)` of each chunk of `CHUNK` consecutive targets.
    chunk_bounds: Vec<(Point, Point)>,
    /// Unit surface normals of given points, when known (grid nodes compute theirs).
    normals: Option<Vec<Point>>,
    /// Grid-node targets' normals (NaN where no triangle around the node is whole), computed
    /// the first time a sensor needs them.
    node_normals: OnceLock<Vec<Point>>,
}

#[derive(Debug, Clone)]
enum Points {
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
    fn normals(&self) -> Result<Option<&[Point]>> {
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
    fn chunk_nodes(&self, c: usize, out: &mut Vec<usize>) {
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

    fn chunk_len(&self, c: usize) -> usize {
        CHUNK.min(self.len - c * CHUNK)
    }

    fn n_chunks(&self) -> usize {
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

fn squared_distance_to_box(q: Point, (lo, hi): (Point, Point)) -> f64 {
    (0..3).map(|k| (lo[k] - q[k]).max(0.0).max(q[k] - hi[k]).powi(2)).sum()
}

#[inline]
pub(crate) fn squared_distance(a: Point, b: Point) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
}

/// The per-chunk answers of one evaluation, in target order (`len` values in all).
fn concatenate<T>(chunks: Vec<Vec<T>>, len: usize, what: &str) -> Result<Vec<T>> {
    let mut out = try_with_capacity(len, what)?;
    for chunk in chunks {
        out.extend(chunk);
    }
    Ok(out)
}

/// Which targets each UAV can reach before occlusion: the one range of the [`Visibility`], or a
/// sensor per UAV.
#[derive(Clone, Copy)]
pub(crate) enum Reach<'a> {
    /// Squared range.
    Range(f64),
    Sensors(&'a [Sensor]),
}

impl Reach<'_> {
    /// Whether UAV `u` at `uav` reaches `target` (before occlusion); `normal` is the target's
    /// surface normal, which only a sensor with an incidence limit reads.
    #[inline]
    pub(crate) fn accepts(&self, u: usize, uav: Point, target: Point, normal: Option<Point>) -> bool {
        match self {
            Reach::Range(d2) => squared_distance(uav, target) <= *d2,
            Reach::Sensors(sensors) => sensors[u].accepts(uav, target) && sensors[u].incidence_ok(uav, target, normal),
        }
    }

    /// Whether UAV `u` at `uav` may reach a point of the box `b` (conservative).
    #[inline]
    fn may_reach_box(&self, u: usize, uav: Point, b: (Point, Point)) -> bool {
        match self {
            Reach::Range(d2) => squared_distance_to_box(uav, b) <= *d2,
            Reach::Sensors(sensors) => !sensors[u].misses_box(uav, b.0, b.1),
        }
    }
}

/// How many targets each UAV sees, and how many only it sees.
#[derive(Debug, Clone, PartialEq)]
pub struct UavCounts {
    /// Targets each UAV sees.
    pub seen: Vec<u64>,
    /// Targets each UAV is the only one to see (its marginal contribution).
    pub exclusive: Vec<u64>,
    /// Weight of the targets each UAV sees.
    pub seen_weight: Vec<f64>,
    /// Weight of the targets only each UAV sees.
    pub exclusive_weight: Vec<f64>,
    /// Total weight of all targets (the denominator of a share).
    pub total_weight: f64,
    /// The weighted share of targets seen by at least one UAV: what [`Visibility::coverage`]
    /// returns for the same UAVs, to the last bit.
    pub coverage: f64,
}

/// Which geometry answers the line-of-sight tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Path {
    /// The grid path for a surface built from a grid, the mesh path otherwise.
    Auto,
    /// The triangle mesh and parry's BVH (built on demand for a grid surface).
    Mesh,
    /// The height field of a grid surface.
    Grid,
}

impl std::str::FromStr for Path {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s {
            "auto" => Ok(Path::Auto),
            "mesh" => Ok(Path::Mesh),
            "grid" => Ok(Path::Grid),
            _ => Err(Error::InvalidInput(format!("method must be 'auto', 'mesh' or 'grid', got {s:?}"))),
        }
    }
}

/// The coverage objective for one surface, one target set and one sensing range.
#[derive(Debug)]
pub struct Visibility {
    surface: Arc<Surface>,
    targets: Targets,
    d_max: f64,
    /// `d_max`, at most [`UNLIMITED_RANGE`] (which every accepted pair of points is within, so
    /// the answers are `d_max`'s): the range the tests use.
    range: f64,
    grid_path: bool,
    /// For grid-node targets on the grid path.
    skylines: Option<(Arc<Skylines>, SkylineSource)>,
}

impl Visibility {
    /// The objective on the automatically chosen path ([`Path::Auto`]).
    ///
    /// # Errors
    /// When `d_max` is not finite and positive, or grid-node targets belong to another surface.
    /// Any finite `d_max` of [`UNLIMITED_RANGE`] or more is an unlimited range.
    pub fn new(surface: Arc<Surface>, targets: Targets, d_max: f64) -> Result<Self> {
        Self::with_path(surface, targets, d_max, Path::Auto)
    }

    /// The objective on a chosen path; every path gives the same answer.
    ///
    /// # Errors
    /// As [`Visibility::new`]; [`Error::InvalidInput`] for [`Path::Grid`] on a surface that is not
    /// a grid; [`Error::TooLarge`] for [`Path::Mesh`] on a grid too large for the mesh path.
    pub fn with_path(surface: Arc<Surface>, targets: Targets, d_max: f64, path: Path) -> Result<Self> {
        ensure!(d_max.is_finite() && d_max > 0.0, "d_max must be finite and > 0, got {d_max}");
        if let Points::GridNodes { surface: own, .. } = &targets.points {
            ensure!(Arc::ptr_eq(own, &surface), "grid-node targets belong to another surface");
        }
        let grid_path = match path {
            Path::Auto => surface.heightfield().is_some(),
            Path::Grid => {
                ensure!(surface.heightfield().is_some(), "the grid path needs a surface built from an elevation grid");
                true
            }
            Path::Mesh => {
                surface.triangle_mesh()?;
                false
            }
        };
        let source = if grid_path {
            surface.grid().filter(|_| targets.is_grid_nodes()).map(|g| SkylineSource::Grid(Stencil::of_grid(g)))
        } else {
            Some(SkylineSource::Mesh(Box::new(sector_edges())))
        };
        let skylines = source.map(|s| {
            // A grid node's skyline depends on the heights alone: the surface keeps them for
            // every objective over its nodes. Other targets' skylines are this objective's own.
            let store = match s {
                SkylineSource::Grid(_) => surface.node_skylines(targets.n_chunks()),
                SkylineSource::Mesh(_) => Arc::new(Skylines::new(targets.n_chunks())),
            };
            (store, s)
        });
        let range = d_max.min(UNLIMITED_RANGE);
        Ok(Self { surface, targets, d_max, range, grid_path, skylines })
    }

    /// The surface.
    #[must_use]
    pub fn surface(&self) -> &Arc<Surface> {
        &self.surface
    }

    /// The targets.
    #[must_use]
    pub fn targets(&self) -> &Targets {
        &self.targets
    }

    /// The sensing range, m.
    #[must_use]
    pub fn d_max(&self) -> f64 {
        self.d_max
    }

    /// The height field the tests walk, on the grid path.
    pub(crate) fn grid_field(&self) -> Option<&HeightField> {
        self.surface.heightfield().filter(|_| self.grid_path)
    }

    /// The range the tests use (`d_max`, at most [`UNLIMITED_RANGE`]), m.
    pub(crate) fn range(&self) -> f64 {
        self.range
    }

    /// The path the line-of-sight tests take ([`Path::Grid`] or [`Path::Mesh`]).
    #[must_use]
    pub fn path(&self) -> Path {
        if self.grid_path {
            Path::Grid
        } else {
            Path::Mesh
        }
    }

    pub(crate) fn check_uavs(uavs: &[Point]) -> Result<()> {
        ensure!(!uavs.is_empty(), "there must be at least one UAV");
        ensure!(uavs.iter().all(|q| q.iter().all(|c| c.is_finite())), "UAV coordinates must be finite");
        ensure!(uavs.iter().all(|&q| in_bounds(q)), "UAV coordinates must be at most {MAX_COORDINATE:e} m in magnitude");
        Ok(())
    }

    /// The UAVs (indices) within range of any point of a chunk's bounding box, nearest first:
    /// the nearest UAV is the likeliest to see a target, and a target stops at the first UAV that
    /// does.
    pub(crate) fn in_range_of(&self, chunk: usize, uavs: &[Point], reach: Reach<'_>, into: &mut Vec<usize>) {
        into.clear();
        let b = self.targets.chunk_bounds[chunk];
        into.extend((0..uavs.len()).filter(|&i| reach.may_reach_box(i, uavs[i], b)));
        let centre = [0, 1, 2].map(|k| 0.5 * (b.0[k] + b.1[k]));
        into.sort_by(|&u, &w| squared_distance(uavs[u], centre).total_cmp(&squared_distance(uavs[w], centre)));
    }

    /// The skylines of chunk `c`'s targets, from the chunk's second evaluation on, and the grid
    /// nodes of its targets (into `nodes`) on the grid path.
    pub(crate) fn skylines_of(&self, c: usize, nodes: &mut Vec<usize>) -> Option<ChunkSkylines<'_>> {
        let view = self.chunk_skylines(c)?;
        nodes.clear();
        if let Some((_, SkylineSource::Grid(_))) = &self.skylines {
            self.targets.chunk_nodes(c, nodes);
        }
        Some(view)
    }

    /// The skylines of chunk `c`'s targets, from the chunk's second evaluation on.
    pub(crate) fn chunk_skylines(&self, c: usize) -> Option<ChunkSkylines<'_>> {
        self.skylines.as_ref()?.0.chunk(c, self.targets.chunk_len(c))
    }

    /// The skyline of target `q` (grid node `node` on the grid path).
    pub(crate) fn skyline(&self, q: Point, node: Option<usize>) -> Skyline {
        match (&self.skylines, node, self.surface.grid()) {
            (Some((_, SkylineSource::Grid(stencil))), Some(k), Some(grid)) => stencil.skyline(grid, k / grid.nx, k % grid.nx),
            (Some((_, SkylineSource::Mesh(edges))), _, _) => match self.surface.triangle_mesh() {
                Ok(mesh) => mesh.skyline(q, edges),
                Err(_) => Skyline::UNBOUNDED,
            },
            _ => Skyline::UNBOUNDED,
        }
    }

    /// The engine the tests run on, resolved once per call (each UAV's horizon is built here,
    /// in parallel, within [`HORIZON_BUDGET`] bounds in all).
    fn engine(&self, uavs: &[Point], reach: Reach<'_>) -> Result<Engine<'_>> {
        self.engine_within(uavs, reach, HORIZON_BUDGET / uavs.len())
    }

    /// [`Visibility::engine`] with at most `per_uav` horizon bounds per UAV.
    fn engine_within(&self, uavs: &[Point], reach: Reach<'_>, per_uav: usize) -> Result<Engine<'_>> {
        let radius = |i: usize| match reach {
            Reach::Range(_) => self.range,
            Reach::Sensors(sensors) => sensors[i].range(),
        };
        if let (true, Some(field)) = (self.grid_path, self.surface.heightfield()) {
            // Grid-node targets are no higher than the surface: a UAV above every node within
            // its range reaches them only within a smaller horizontal radius, and its horizon
            // need go no farther (a shorter one would only leave more to the walk).
            let grid_nodes = self.targets.is_grid_nodes();
            let horizontal = |i: usize, u: Point| {
                let r = radius(i);
                if !grid_nodes || !r.is_finite() {
                    return r;
                }
                let below = u[2] - field.highest_within((u[0] - r, u[0] + r), (u[1] - r, u[1] + r));
                if below > 0.0 {
                    (r * r - below * below).max(0.0).sqrt()
                } else {
                    r
                }
            };
            let horizons: Result<Vec<Horizon>> =
                uavs.par_iter().enumerate().map(|(i, &u)| field.horizon(u, self.horizon_reach(field, horizontal(i, u)), per_uav)).collect();
            return Ok(Engine::Grid(field, horizons?));
        }
        let mesh = self.surface.triangle_mesh()?;
        let horizons: Result<Vec<Horizon>> = uavs.par_iter().enumerate().map(|(i, &u)| mesh.horizon(u, radius(i), per_uav)).collect();
        Ok(Engine::Mesh(mesh, horizons?))
    }

    /// How far, horizontally, a UAV's horizon on the grid path need reach for targets up to
    /// `radius` away: grid-node targets have skylines (from their second evaluation on), which
    /// clear a sight line's last [`REACH`](crate::skyline::REACH) cells, so the horizon stops
    /// that much short. A shorter horizon only leaves more of a line to the walk: the first
    /// evaluation, without skylines, walks those cells.
    pub(crate) fn horizon_reach(&self, field: &HeightField, radius: f64) -> f64 {
        if self.targets.is_grid_nodes() {
            (radius - field.skyline_reach()).max(0.0)
        } else {
            radius
        }
    }

    /// For each target, whether at least one UAV sees it.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when there is no UAV or a UAV coordinate is not finite.
    pub fn seen(&self, uavs: &[Point], n_threads: usize) -> Result<Vec<bool>> {
        self.seen_by(uavs, None, n_threads)
    }

    /// [`Visibility::seen`] with a sensor per UAV (`None`: every UAV omnidirectional up to the
    /// objective's `d_max`), each reaching what [`Sensor::accepts`] says before occlusion.
    ///
    /// # Errors
    /// As [`Visibility::seen`]; [`Error::InvalidInput`] when there are not as many sensors as UAVs.
    pub fn seen_by(&self, uavs: &[Point], sensors: Option<&[Sensor]>, n_threads: usize) -> Result<Vec<bool>> {
        Self::check_uavs(uavs)?;
        let reach = self.reach(uavs, sensors)?;
        let normals = if self.normals_for(reach, false)? { self.targets.normals()? } else { None };
        let chunks: Vec<Vec<bool>> = threads::run(n_threads, || {
            let engine = self.engine(uavs, reach)?;
            Ok::<_, Error>(
                (0..self.targets.n_chunks())
                    .into_par_iter()
                    .map_init(
                        || (Vec::new(), Vec::with_capacity(CHUNK), Vec::with_capacity(CHUNK), vec![Blockers::default(); uavs.len()]),
                        |(near, points, nodes, blockers), c| {
                            self.in_range_of(c, uavs, reach, near);
                            if near.is_empty() {
                                return vec![false; self.targets.chunk_len(c)];
                            }
                            points.clear();
                            self.targets.chunk_points(c, points);
                            let mut skylines = self.skylines_of(c, nodes);
                            let normal = |t: usize| normals.map(|n| n[c * CHUNK + t]);
                            // Neighbouring targets are mostly seen by the same UAV: the last one
                            // that saw a target moves to the front (the answer does not depend on
                            // the order).
                            points
                                .iter()
                                .enumerate()
                                .map(|(t, &q)| {
                                    let mut sky = None;
                                    for k in 0..near.len() {
                                        let u = near[k];
                                        if !reach.accepts(u, uavs[u], q, normal(t)) {
                                            continue;
                                        }
                                        if sky.is_none() {
                                            sky = skylines.as_mut().map(|s| s.get(t, || self.skyline(q, nodes.get(t).copied())));
                                        }
                                        if engine.line_of_sight(u, q, sky.as_ref(), blockers) {
                                            near.swap(0, k);
                                            return true;
                                        }
                                    }
                                    false
                                })
                                .collect()
                        },
                    )
                    .collect(),
            )
        })?;
        concatenate(chunks, self.targets.len(), "the seen mask")
    }

    /// Which targets one viewpoint sees, as bits (target `t` is bit `t % 64` of `words[t / 64]`,
    /// `words` zeroed by the caller): the answers of [`Visibility::seen_by`] for this viewpoint
    /// alone, on the calling thread (chunk after chunk), with at most `horizon_bounds` horizon
    /// bounds. A seen-matrix builds its columns with it, many viewpoints in parallel.
    ///
    /// # Errors
    /// As [`Visibility::seen_by`] for one UAV.
    pub(crate) fn seen_bits(&self, uav: Point, sensor: Option<&Sensor>, horizon_bounds: usize, words: &mut [u64]) -> Result<()> {
        let uavs = [uav];
        Self::check_uavs(&uavs)?;
        let sensors = sensor.map(std::slice::from_ref);
        let reach = self.reach(&uavs, sensors)?;
        let normals = if self.normals_for(reach, false)? { self.targets.normals()? } else { None };
        let engine = self.engine_within(&uavs, reach, horizon_bounds)?;
        let (mut near, mut points, mut nodes, mut blockers) = (Vec::new(), Vec::with_capacity(CHUNK), Vec::new(), [Blockers::default()]);
        for c in 0..self.targets.n_chunks() {
            self.in_range_of(c, &uavs, reach, &mut near);
            if near.is_empty() {
                continue;
            }
            points.clear();
            self.targets.chunk_points(c, &mut points);
            let mut skylines = self.skylines_of(c, &mut nodes);
            for (t, &q) in points.iter().enumerate() {
                if !reach.accepts(0, uav, q, normals.map(|n| n[c * CHUNK + t])) {
                    continue;
                }
                let sky = skylines.as_mut().map(|s| s.get(t, || self.skyline(q, nodes.get(t).copied())));
                if engine.line_of_sight(0, q, sky.as_ref(), &mut blockers) {
                    let k = c * CHUNK + t;
                    words[k / 64] |= 1 << (k % 64);
                }
            }
        }
        Ok(())
    }

    /// The weighted share of targets seen by at least one UAV, in `[0, 1]`.
    ///
    /// # Errors
    /// As [`Visibility::seen`].
    pub fn coverage(&self, uavs: &[Point], n_threads: usize) -> Result<f64> {
        let seen = self.seen(uavs, n_threads)?;
        Ok(self.share(&seen))
    }

    /// [`Visibility::coverage`] with a sensor per UAV (see [`Visibility::seen_by`]).
    ///
    /// # Errors
    /// As [`Visibility::seen_by`].
    pub fn coverage_by(&self, uavs: &[Point], sensors: Option<&[Sensor]>, n_threads: usize) -> Result<f64> {
        let seen = self.seen_by(uavs, sensors, n_threads)?;
        Ok(self.share(&seen))
    }

    /// Whether the targets' normals are to be read: for an incidence limit (an error when the
    /// targets have none) and, where known, for view quality.
    fn normals_for(&self, reach: Reach<'_>, quality: bool) -> Result<bool> {
        let Reach::Sensors(sensors) = reach else { return Ok(false) };
        if sensors.iter().any(|s| s.max_incidence_cos().is_some()) {
            ensure!(
                self.targets.has_normals(),
                "a sensor limits the incidence angle, but these targets carry no surface normals (give them with the targets)"
            );
            return Ok(true);
        }
        Ok(quality && self.targets.has_normals())
    }

    /// The best view quality of each target over the UAVs that see it ([`Sensor::quality`]), 0
    /// where none does; with the objective's one range (`sensors` `None`) every seen target has
    /// quality 1. UAVs are tried best quality first, and one whose quality cannot beat the best
    /// found is not tested for its line of sight.
    ///
    /// # Errors
    /// As [`Visibility::seen_by`].
    pub fn quality_by(&self, uavs: &[Point], sensors: Option<&[Sensor]>, n_threads: usize) -> Result<Vec<f64>> {
        Self::check_uavs(uavs)?;
        let reach = self.reach(uavs, sensors)?;
        let normals = if self.normals_for(reach, true)? { self.targets.normals()? } else { None };
        let chunks: Vec<Vec<f64>> = threads::run(n_threads, || {
            let engine = self.engine(uavs, reach)?;
            Ok::<_, Error>(
                (0..self.targets.n_chunks())
                    .into_par_iter()
                    .map_init(
                        || {
                            (
                                Vec::new(),
                                Vec::with_capacity(CHUNK),
                                Vec::with_capacity(CHUNK),
                                Vec::new(),
                                vec![Blockers::default(); uavs.len()],
                            )
                        },
                        |(near, points, nodes, rated, blockers), c| {
                            self.in_range_of(c, uavs, reach, near);
                            if near.is_empty() {
                                return vec![0.0; self.targets.chunk_len(c)];
                            }
                            points.clear();
                            self.targets.chunk_points(c, points);
                            let mut skylines = self.skylines_of(c, nodes);
                            points
                                .iter()
                                .enumerate()
                                .map(|(t, &q)| {
                                    let normal = normals.map(|n| n[c * CHUNK + t]);
                                    rated.clear();
                                    rated.extend(near.iter().filter(|&&u| reach.accepts(u, uavs[u], q, normal)).map(|&u| {
                                        let quality = match reach {
                                            Reach::Range(_) => 1.0,
                                            Reach::Sensors(s) => s[u].quality(uavs[u], q, normal),
                                        };
                                        (quality, u)
                                    }));
                                    rated.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
                                    let mut sky = None;
                                    for &(quality, u) in rated.iter() {
                                        if quality <= 0.0 {
                                            break;
                                        }
                                        if sky.is_none() {
                                            sky = skylines.as_mut().map(|s| s.get(t, || self.skyline(q, nodes.get(t).copied())));
                                        }
                                        if engine.line_of_sight(u, q, sky.as_ref(), blockers) {
                                            return quality; // the best of those that see it
                                        }
                                    }
                                    0.0
                                })
                                .collect()
                        },
                    )
                    .collect(),
            )
        })?;
        concatenate(chunks, self.targets.len(), "the targets' quality")
    }

    /// The quality-weighted coverage: the weighted mean over all targets of
    /// [`Visibility::quality_by`], in `[0, 1]` (the coverage when every view has quality 1).
    ///
    /// # Errors
    /// As [`Visibility::seen_by`].
    pub fn quality_coverage_by(&self, uavs: &[Point], sensors: Option<&[Sensor]>, n_threads: usize) -> Result<f64> {
        let quality = self.quality_by(uavs, sensors, n_threads)?;
        let total = quality.iter().zip(&self.targets.weights).fold(0.0, |acc, (q, w)| acc + q * w);
        Ok((total / self.targets.total_weight).min(1.0))
    }

    pub(crate) fn reach<'s>(&self, uavs: &[Point], sensors: Option<&'s [Sensor]>) -> Result<Reach<'s>> {
        match sensors {
            None => Ok(Reach::Range(self.range * self.range)),
            Some(list) => {
                ensure!(list.len() == uavs.len(), "{} sensors for {} UAVs: give one per UAV", list.len(), uavs.len());
                Ok(Reach::Sensors(list))
            }
        }
    }

    /// The weighted share of the targets flagged in `mask`.
    #[must_use]
    pub fn share(&self, mask: &[bool]) -> f64 {
        // A fold from +0.0, not `sum()`, whose empty sum is -0.0.
        let covered = mask.iter().zip(&self.targets.weights).filter(|(s, _)| **s).fold(0.0, |acc, (_, w)| acc + w);
        (covered / self.targets.total_weight).min(1.0)
    }

    /// Per-UAV counts, and the coverage: every UAV in range is tested for every target (no early
    /// stop), so one call answers what a per-robot optimiser needs.
    ///
    /// # Errors
    /// As [`Visibility::seen`].
    pub fn per_uav(&self, uavs: &[Point], n_threads: usize) -> Result<UavCounts> {
        self.per_uav_by(uavs, None, n_threads)
    }

    /// [`Visibility::per_uav`] with a sensor per UAV (see [`Visibility::seen_by`]).
    ///
    /// # Errors
    /// As [`Visibility::seen_by`].
    pub fn per_uav_by(&self, uavs: &[Point], sensors: Option<&[Sensor]>, n_threads: usize) -> Result<UavCounts> {
        Self::check_uavs(uavs)?;
        let n = uavs.len();
        let reach = self.reach(uavs, sensors)?;
        let normals = if self.normals_for(reach, false)? { self.targets.normals()? } else { None };
        let mut total = UavCounts::zeros(n, self.targets.total_weight)?;
        let mut mask = try_with_capacity(self.targets.len(), "the seen mask")?;
        // Chunks in batches whose counters fit in COUNTS_BUDGET, each batch summed in chunk order
        // into the total: the same sums, in the same order, as one batch of every chunk.
        let batch = (COUNTS_BUDGET / n).max(1);
        threads::run(n_threads, || {
            let engine = self.engine(uavs, reach)?;
            let mut first = 0;
            while first < self.targets.n_chunks() {
                let last = (first + batch).min(self.targets.n_chunks());
                let partials: Result<Vec<(UavCounts, Vec<bool>)>> = (first..last)
                    .into_par_iter()
                    .map_init(
                        || (Vec::with_capacity(n), Vec::with_capacity(CHUNK), Vec::with_capacity(CHUNK), vec![Blockers::default(); n]),
                        |(seers, points, nodes, blockers), c| {
                            let mut out = UavCounts::zeros(n, 0.0)?;
                            let mut seen = vec![false; self.targets.chunk_len(c)];
                            let b = self.targets.chunk_bounds[c];
                            let near: Vec<usize> = (0..n).filter(|&i| reach.may_reach_box(i, uavs[i], b)).collect();
                            if near.is_empty() {
                                return Ok((out, seen));
                            }
                            points.clear();
                            self.targets.chunk_points(c, points);
                            let mut skylines = self.skylines_of(c, nodes);
                            for (k, &q) in points.iter().enumerate() {
                                let w = self.targets.weights[c * CHUNK + k];
                                let normal = normals.map(|n| n[c * CHUNK + k]);
                                let in_range = |i: &usize| reach.accepts(*i, uavs[*i], q, normal);
                                let sky = match &mut skylines {
                                    Some(s) if near.iter().any(in_range) => Some(s.get(k, || self.skyline(q, nodes.get(k).copied()))),
                                    _ => None,
                                };
                                seers.clear();
                                seers.extend(
                                    near.iter().copied().filter(|i| in_range(i) && engine.line_of_sight(*i, q, sky.as_ref(), blockers)),
                                );
                                for &i in seers.iter() {
                                    out.seen[i] += 1;
                                    out.seen_weight[i] += w;
                                }
                                if let [only] = seers[..] {
                                    out.exclusive[only] += 1;
                                    out.exclusive_weight[only] += w;
                                }
                                seen[k] = !seers.is_empty();
                            }
                            Ok((out, seen))
                        },
                    )
                    .collect();
                for (part, seen) in partials? {
                    for i in 0..n {
                        total.seen[i] += part.seen[i];
                        total.exclusive[i] += part.exclusive[i];
                        total.seen_weight[i] += part.seen_weight[i];
                        total.exclusive_weight[i] += part.exclusive_weight[i];
                    }
                    mask.extend(seen);
                }
                first = last;
            }
            Ok::<_, Error>(())
        })?;
        // The same mask and the same sum as `coverage`, so the same value.
        total.coverage = self.share(&mask);
        Ok(total)
    }
}

/// How the targets' skylines are computed.
enum SkylineSource {
    /// From the grid's heights around each grid-node target.
    Grid(Stencil),
    /// From the triangles of the mesh around each target.
    Mesh(Box<SectorEdges>),
}

impl std::fmt::Debug for SkylineSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Grid(_) => "SkylineSource::Grid",
            Self::Mesh(_) => "SkylineSource::Mesh",
        })
    }
}

/// The geometry one evaluation runs on, with what it knows of each UAV.
enum Engine<'a> {
    Mesh(&'a TriangleMesh, Vec<Horizon>),
    Grid(&'a HeightField, Vec<Horizon>),
}

impl Engine<'_> {
    /// Whether UAV `uav` (an index) sees `target` (with its skyline when it is a grid node);
    /// `blockers[uav]` is the triangle that last blocked one of its lines on the mesh path (see
    /// [`TriangleMesh::ray_hits_between`]), `None` at first.
    #[inline]
    fn line_of_sight(&self, uav: usize, target: Point, skyline: Option<&Skyline>, blockers: &mut [Blockers]) -> bool {
        match (self, skyline) {
            (Engine::Mesh(mesh, horizons), Some(sky)) => mesh.line_of_sight_to_target(&horizons[uav], target, sky, &mut blockers[uav]),
            (Engine::Mesh(mesh, horizons), None) => mesh.line_of_sight_from(&horizons[uav], target, &mut blockers[uav]),
            (Engine::Grid(field, horizons), Some(sky)) => field.line_of_sight_to_node(&horizons[uav], target, sky),
            (Engine::Grid(field, horizons), None) => field.line_of_sight_from(&horizons[uav], target),
        }
    }
}

impl UavCounts {
    fn zeros(n: usize, total_weight: f64) -> Result<Self> {
        Ok(Self {
            seen: try_filled(0, n, "per-UAV counts")?,
            exclusive: try_filled(0, n, "per-UAV counts")?,
            seen_weight: try_filled(0.0, n, "per-UAV counts")?,
            exclusive_weight: try_filled(0.0, n, "per-UAV counts")?,
            total_weight,
            coverage: 0.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(n: usize) -> Arc<Surface> {
        Arc::new(Surface::from_grid(vec![0.0; n * n], n, n, 1.0, 1.0, 0.0, 0.0).unwrap())
    }

    #[test]
    fn a_target_computed_alone_is_the_one_its_chunk_lists() {
        // A grid with a nodata block, whose unused nodes the chunks skip, and one without.
        let z = |k: usize| if (300..340).contains(&k) || k % 97 == 5 { f64::NAN } else { (k % 13) as f64 };
        for holes in [false, true] {
            let heights: Vec<f64> = (0..41 * 41).map(|k| if holes { z(k) } else { (k % 13) as f64 }).collect();
            let targets = Targets::grid_nodes(Arc::new(Surface::from_grid(heights, 41, 41, 1.0, 1.0, 0.0, 0.0).unwrap())).unwrap();
            let mut all = Vec::new();
            for c in 0..targets.n_chunks() {
                let (mut points, mut nodes) = (Vec::new(), Vec::new());
                targets.chunk_points(c, &mut points);
                targets.chunk_nodes(c, &mut nodes);
                for (t, (q, k)) in points.iter().zip(&nodes).enumerate() {
                    assert_eq!(targets.chunk_target(c, t), (*q, Some(*k)));
                }
                all.extend(points);
            }
            assert_eq!(all.len() < 41 * 41, holes);
        }
    }

    #[test]
    fn range_limits_a_flat_plane_to_a_disk() {
        let s = flat(41);
        let vis = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 10.0).unwrap();
        let seen = vis.seen(&[[20.0, 20.0, 6.0]], 1).unwrap();
        for (q, &v) in vis.targets().points().iter().zip(&seen) {
            let r2 = (q[0] - 20.0).powi(2) + (q[1] - 20.0).powi(2);
            assert_eq!(v, r2 + 36.0 <= 100.0, "{q:?}");
        }
    }

    #[test]
    fn a_wall_hides_what_is_behind_it() {
        // Ground y in [0, 10] at z = 0 with a 5 m high wall along x = 5.
        let s = Arc::new(
            Surface::new(
                vec![
                    [0.0, 0.0, 0.0],
                    [10.0, 0.0, 0.0],
                    [10.0, 10.0, 0.0],
                    [0.0, 10.0, 0.0],
                    [5.0, 0.0, 0.0],
                    [5.0, 10.0, 0.0],
                    [5.0, 10.0, 5.0],
                    [5.0, 0.0, 5.0],
                ],
                vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]],
            )
            .unwrap(),
        );
        let targets = Targets::new(vec![[2.0, 5.0, 0.0], [8.0, 5.0, 0.0]], None).unwrap();
        let vis = Visibility::new(s, targets, 50.0).unwrap();
        assert_eq!(vis.seen(&[[1.0, 5.0, 1.0]], 1).unwrap(), vec![true, false]);
        let counts = vis.per_uav(&[[1.0, 5.0, 1.0], [9.0, 5.0, 1.0]], 2).unwrap();
        assert_eq!(counts.seen, vec![1, 1]);
        assert_eq!(counts.exclusive, vec![1, 1]);
    }

    #[test]
    fn thread_count_does_not_change_results() {
        let n = 60;
        let z: Vec<f64> = (0..n * n).map(|k| ((k % n) as f64 * 0.3).sin() * 4.0 + ((k / n) as f64 * 0.2).cos() * 3.0).collect();
        let s = Arc::new(Surface::from_grid(z, n, n, 1.0, 1.0, 0.0, 0.0).unwrap());
        let vis = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 20.0).unwrap();
        let uavs = [[10.0, 10.0, 9.0], [40.0, 30.0, 8.0], [50.0, 50.0, 12.0]];
        let one = vis.seen(&uavs, 1).unwrap();
        assert_eq!(one, vis.seen(&uavs, 2).unwrap());
        assert_eq!(vis.coverage(&uavs, 1).unwrap(), vis.coverage(&uavs, 3).unwrap());
        assert_eq!(vis.per_uav(&uavs, 1).unwrap(), vis.per_uav(&uavs, 2).unwrap());
        assert!(one.iter().any(|&v| v) && one.iter().any(|&v| !v));
    }

    /// Rugged hills with a few nodata holes and terraces, on a grid with an odd origin.
    fn rugged(n: usize) -> Arc<Surface> {
        let z: Vec<f64> = (0..n * n)
            .map(|k| {
                let (i, j) = ((k / n) as f64, (k % n) as f64);
                if (k * 7919) % 97 == 3 {
                    return f64::NAN;
                }
                let h = 6.0 * (0.7 * i).sin() * (0.5 * j).cos() + 3.0 * (1.3 * j + 0.2 * i).sin();
                if i > 30.0 {
                    (h / 2.0).round() * 2.0
                } else {
                    h
                }
            })
            .collect();
        Arc::new(Surface::from_grid(z, n, n, 0.5, 0.5, 101.25, -7.5).unwrap())
    }

    #[test]
    fn uavs_high_above_the_nodes_keep_the_mesh_paths_answers() {
        // Over rugged hills (heights within about 9 m), UAVs from level with the hilltops to
        // beyond the range: their horizons reach less far, the answers are the mesh path's.
        let s = rugged(50);
        let field = s.heightfield().unwrap();
        let g = field.grid();
        let (lo, hi) = ((102.0, 110.0), (-6.0, 3.0));
        let brute = (0..g.nx * g.ny)
            .map(|k| g.node_point(k))
            .filter(|q| q[2].is_finite() && (lo.0..=lo.1).contains(&q[0]) && (hi.0..=hi.1).contains(&q[1]))
            .fold(f64::NEG_INFINITY, |m, q| m.max(q[2]));
        let bound = field.highest_within(lo, hi);
        assert!(bound >= brute && bound <= g.z.iter().copied().fold(f64::NEG_INFINITY, f64::max), "{bound} {brute}");
        assert_eq!(field.highest_within((500.0, 600.0), hi), f64::NEG_INFINITY);
        let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 12.0).unwrap();
        let mesh = Visibility::with_path(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 12.0, Path::Mesh).unwrap();
        for z in [9.0, 12.0, 15.0, 18.0, 20.5, 21.5, 30.0] {
            let uavs: Vec<Point> =
                (0..4).map(|k| [104.0 + 5.0 * f64::from(k), -4.0 + 4.0 * f64::from(k), z + f64::from(k) * 0.25]).collect();
            let seen = mesh.seen(&uavs, 1).unwrap();
            for _ in 0..3 {
                assert_eq!(nodes.seen(&uavs, 2).unwrap(), seen, "UAVs at {z} m");
            }
            // Low enough, some nodes are seen; above range, none.
            assert!(z >= 15.0 || seen.iter().any(|&v| v), "UAVs at {z} m");
            assert!(z < 30.0 || !seen.iter().any(|&v| v), "UAVs at {z} m");
        }
    }

    #[test]
    fn horizons_stop_short_by_a_skylines_reach_with_the_mesh_paths_answers() {
        // Grid-node targets have skylines that clear a sight line's last REACH cells, so the
        // grid path's horizons stop that much short of the range. UAVs a few metres over rugged
        // hills (grazing lines, long ones across the whole range), from the first evaluation
        // (no skylines yet) on, give the mesh path's answers.
        let s = rugged(50);
        let field = s.heightfield().unwrap();
        let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 14.0).unwrap();
        let points = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 14.0).unwrap();
        let reach = crate::skyline::REACH as f64 * 0.5;
        assert_eq!(nodes.horizon_reach(field, 14.0), 14.0 - reach);
        assert_eq!(nodes.horizon_reach(field, 0.5 * reach), 0.0);
        assert_eq!(points.horizon_reach(field, 14.0), 14.0);
        let mesh = Visibility::with_path(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 14.0, Path::Mesh).unwrap();
        for z in [7.0, 9.0, 11.0] {
            let uavs: Vec<Point> = (0..5).map(|k| [102.0 + 5.5 * f64::from(k), 4.0 - 2.5 * f64::from(k), z - 0.3 * f64::from(k)]).collect();
            let seen = mesh.seen(&uavs, 1).unwrap();
            assert!(seen.iter().any(|&v| v) && !seen.iter().all(|&v| v), "UAVs at {z} m");
            for _ in 0..3 {
                assert_eq!(nodes.seen(&uavs, 2).unwrap(), seen, "UAVs at {z} m");
                assert_eq!(points.seen(&uavs, 1).unwrap(), seen, "UAVs at {z} m");
            }
        }
    }

    #[test]
    fn grid_and_mesh_paths_give_identical_answers() {
        let s = rugged(50);
        let targets = Targets::of_surface(&s, 1.0).unwrap();
        let grid = Visibility::with_path(s.clone(), targets.clone(), 9.0, Path::Auto).unwrap();
        let mesh = Visibility::with_path(s.clone(), targets, 9.0, Path::Mesh).unwrap();
        assert_eq!((grid.path(), mesh.path()), (Path::Grid, Path::Mesh));
        let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 9.0).unwrap();
        assert!(nodes.targets().is_grid_nodes());
        assert_eq!(nodes.targets().points().as_ref(), grid.targets().points().as_ref());
        assert_eq!(nodes.targets().weights(), grid.targets().weights());
        let uavs: Vec<Point> = (0..6).map(|k| [103.0 + 4.0 * f64::from(k), -5.0 + 3.5 * f64::from(k), 4.0 + f64::from(k)]).collect();
        for n in 1..=uavs.len() {
            let u = &uavs[..n];
            let seen = mesh.seen(u, 1).unwrap();
            assert_eq!(grid.seen(u, 2).unwrap(), seen);
            assert_eq!(nodes.seen(u, 2).unwrap(), seen);
            assert_eq!(grid.coverage(u, 1).unwrap(), mesh.coverage(u, 2).unwrap());
            assert_eq!(nodes.coverage(u, 1).unwrap(), mesh.coverage(u, 1).unwrap());
            assert_eq!(grid.per_uav(u, 2).unwrap(), mesh.per_uav(u, 1).unwrap());
            assert_eq!(nodes.per_uav(u, 1).unwrap(), mesh.per_uav(u, 2).unwrap());
            let count = seen.iter().filter(|&&v| v).count();
            assert!(count > 0 && count < seen.len());
        }
    }

    #[test]
    fn objectives_over_one_grids_nodes_share_its_skylines_with_the_same_answers() {
        let s = rugged(40);
        let nodes = || Targets::grid_nodes(s.clone()).unwrap();
        let first = Visibility::new(s.clone(), nodes(), 9.0).unwrap();
        let second = Visibility::new(s.clone(), nodes(), 6.0).unwrap();
        let store = |v: &Visibility| Arc::clone(&v.skylines.as_ref().expect("grid-node skylines").0);
        assert!(Arc::ptr_eq(&store(&first), &store(&second)));
        // Another surface with the same heights has its own store and, skylines or not, the
        // same answers: fill the shared store through `first`, then ask `second`.
        let alone = rugged(40);
        let fresh = Visibility::new(alone.clone(), Targets::grid_nodes(alone).unwrap(), 6.0).unwrap();
        assert!(!Arc::ptr_eq(&store(&first), &store(&fresh)));
        let configs: Vec<Vec<Point>> = (0..4)
            .map(|k| (0..3).map(|u| [103.0 + 5.0 * f64::from(u + k), -4.0 + 4.0 * f64::from(u), 5.0 + f64::from(k)]).collect())
            .collect();
        for uavs in &configs {
            first.seen(uavs, 2).unwrap();
            first.seen(uavs, 1).unwrap();
        }
        for uavs in &configs {
            for _ in 0..2 {
                assert_eq!(second.seen(uavs, 2).unwrap(), fresh.seen(uavs, 1).unwrap());
                assert_eq!(second.per_uav(uavs, 1).unwrap(), fresh.per_uav(uavs, 2).unwrap());
            }
        }
        // The mesh path's skylines of the same nodes come from the triangles: its own store.
        let mesh = Visibility::with_path(s.clone(), nodes(), 9.0, Path::Mesh).unwrap();
        assert!(!Arc::ptr_eq(&store(&first), &store(&mesh)));
    }

    /// A camera looking along heading `yaw` (degrees clockwise from +y) with gimbal pitch
    /// `pitch` (degrees, -90 straight down), `h` x `v` degrees wide.
    fn camera(yaw: f64, pitch: f64, h: f64, v: f64) -> crate::sensor::Frustum {
        let (sy, cy) = yaw.to_radians().sin_cos();
        let (sp, cp) = pitch.to_radians().sin_cos();
        let forward = [sy * cp, cy * cp, sp];
        let right = [cy, -sy, 0.0];
        let up = [
            right[1] * forward[2] - right[2] * forward[1],
            right[2] * forward[0] - right[0] * forward[2],
            right[0] * forward[1] - right[1] * forward[0],
        ];
        crate::sensor::Frustum::new(forward, right, up, (h / 2.0).to_radians().tan(), (v / 2.0).to_radians().tan()).unwrap()
    }

    #[test]
    fn sensors_give_each_uavs_sight_lines_within_its_reach_on_both_paths() {
        let s = rugged(50);
        let targets = Targets::of_surface(&s, 1.0).unwrap();
        let points = targets.points().into_owned();
        let grid = Visibility::with_path(s.clone(), targets.clone(), 9.0, Path::Auto).unwrap();
        let mesh = Visibility::with_path(s.clone(), targets, 9.0, Path::Mesh).unwrap();
        let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 9.0).unwrap();
        let uavs: Vec<Point> = (0..6).map(|k| [103.0 + 4.0 * f64::from(k), -5.0 + 3.5 * f64::from(k), 6.0 + f64::from(k)]).collect();
        let sensors = [
            Sensor::omnidirectional(9.0).unwrap(),
            Sensor::new(2.0, 12.0, Some(camera(0.0, -90.0, 84.0, 60.0))).unwrap(),
            Sensor::new(0.0, 15.0, Some(camera(359.0, -45.0, 60.0, 45.0))).unwrap(),
            Sensor::new(1.0, 7.0, Some(camera(90.0, 0.0, 120.0, 90.0))).unwrap(),
            Sensor::new(0.0, 20.0, Some(camera(200.0, -60.0, 30.0, 20.0))).unwrap(),
            Sensor::new(0.0, 10.0, None).unwrap(),
        ];
        // The reference: each UAV alone, omnidirectional with an ample range (its sight lines),
        // kept where its own sensor reaches.
        let wide = Visibility::with_path(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 25.0, Path::Mesh).unwrap();
        let alone: Vec<Vec<bool>> = uavs.iter().map(|&u| wide.seen(&[u], 1).unwrap()).collect();
        for n in 1..=uavs.len() {
            let (u, sens) = (&uavs[..n], &sensors[..n]);
            let expected: Vec<bool> = (0..points.len()).map(|t| (0..n).any(|i| alone[i][t] && sens[i].accepts(u[i], points[t]))).collect();
            assert_eq!(mesh.seen_by(u, Some(sens), 1).unwrap(), expected, "{n} UAVs");
            assert_eq!(grid.seen_by(u, Some(sens), 2).unwrap(), expected);
            assert_eq!(nodes.seen_by(u, Some(sens), 2).unwrap(), expected);
            assert_eq!(grid.per_uav_by(u, Some(sens), 1).unwrap(), mesh.per_uav_by(u, Some(sens), 2).unwrap());
            assert_eq!(nodes.coverage_by(u, Some(sens), 1).unwrap(), mesh.coverage_by(u, Some(sens), 1).unwrap());
            let count = expected.iter().filter(|&&v| v).count();
            assert!(count > 0 && count < expected.len());
        }
        // the paper's sensor given explicitly is the objective's own
        let omni = vec![Sensor::omnidirectional(9.0).unwrap(); 6];
        assert_eq!(grid.seen_by(&uavs, Some(&omni), 1).unwrap(), grid.seen(&uavs, 1).unwrap());
        assert!(grid.seen_by(&uavs, Some(&omni[..5]), 1).is_err());
    }

    #[test]
    fn incidence_and_quality_on_a_flat_plane_follow_their_formulas() {
        let s = flat(41); // 40 m x 40 m at 1 m, z = 0
        let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 100.0).unwrap();
        let given = Targets::of_surface(&s, 1.0).unwrap();
        let up = vec![[0.0, 0.0, 1.0]; given.len()];
        let given = Visibility::with_path(s.clone(), given.with_normals(up).unwrap(), 100.0, Path::Mesh).unwrap();
        let uav = [20.0, 20.0, 10.0];
        // at most 45 deg off the normal: the disk of radius 10 m under the UAV
        let steep = [Sensor::omnidirectional(100.0).unwrap().with_incidence_limit(std::f64::consts::FRAC_1_SQRT_2).unwrap()];
        let points = nodes.targets().points().into_owned();
        let seen = nodes.seen_by(&[uav], Some(&steep), 1).unwrap();
        for (q, &v) in points.iter().zip(&seen) {
            let r2 = (q[0] - 20.0).powi(2) + (q[1] - 20.0).powi(2);
            if (r2 - 100.0).abs() > 1e-6 {
                assert_eq!(v, r2 < 100.0, "{q:?}");
            }
        }
        assert_eq!(given.seen_by(&[uav], Some(&steep), 1).unwrap(), seen);
        // quality: resolution good up to 12 m (0.001 m/px per metre, 0.012 m/px), times cos
        let rated = [Sensor::omnidirectional(100.0).unwrap().with_resolution(0.001, 0.012).unwrap()];
        let quality = nodes.quality_by(&[uav], Some(&rated), 2).unwrap();
        for (q, &got) in points.iter().zip(&quality) {
            let d = ((q[0] - 20.0).powi(2) + (q[1] - 20.0).powi(2) + 100.0).sqrt();
            let expected = (0.012 / (0.001 * d)).min(1.0) * (10.0 / d);
            assert!((got - expected).abs() < 1e-12, "{q:?}: {got} vs {expected}");
        }
        assert_eq!(given.quality_by(&[uav], Some(&rated), 1).unwrap(), quality);
        let mean = nodes.quality_coverage_by(&[uav], Some(&rated), 1).unwrap();
        assert!(mean > 0.2 && mean < nodes.coverage(&[uav], 1).unwrap());
        // the objective's own range: every seen target has quality 1
        let plain = nodes.quality_by(&[uav], None, 1).unwrap();
        assert!(plain.iter().zip(nodes.seen(&[uav], 1).unwrap()).all(|(&q, v)| q == if v { 1.0 } else { 0.0 }));
        // targets without normals cannot take an incidence limit
        let bare = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 100.0).unwrap();
        assert!(bare.seen_by(&[uav], Some(&steep), 1).is_err());
        assert!(bare.quality_by(&[uav], Some(&rated), 1).is_ok()); // quality without incidence
    }

    #[test]
    fn incidence_and_quality_are_the_same_on_both_paths() {
        let s = rugged(50);
        let g = s.grid().unwrap();
        let normals: Vec<Point> =
            (0..g.nx * g.ny).filter(|&k| g.vertex_of_node[k] != u32::MAX).map(|k| g.node_normal(k).unwrap()).collect();
        let targets = Targets::of_surface(&s, 1.0).unwrap().with_normals(normals).unwrap();
        let grid = Visibility::with_path(s.clone(), targets.clone(), 9.0, Path::Auto).unwrap();
        let mesh = Visibility::with_path(s.clone(), targets, 9.0, Path::Mesh).unwrap();
        let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 9.0).unwrap();
        let uavs: Vec<Point> = (0..5).map(|k| [103.0 + 4.0 * f64::from(k), -5.0 + 3.5 * f64::from(k), 6.0 + f64::from(k)]).collect();
        let sensors: Vec<Sensor> = (0..5)
            .map(|k| {
                let s = Sensor::new(0.0, 8.0 + f64::from(k), (k % 2 == 1).then(|| camera(72.0 * f64::from(k), -60.0, 90.0, 70.0))).unwrap();
                s.with_incidence_limit(0.3 + 0.1 * f64::from(k)).unwrap().with_resolution(0.0005, 0.003).unwrap()
            })
            .collect();
        for n in 1..=5 {
            let (u, sens) = (&uavs[..n], &sensors[..n]);
            let seen = mesh.seen_by(u, Some(sens), 1).unwrap();
            assert_eq!(grid.seen_by(u, Some(sens), 2).unwrap(), seen);
            assert_eq!(nodes.seen_by(u, Some(sens), 2).unwrap(), seen);
            let quality = mesh.quality_by(u, Some(sens), 2).unwrap();
            assert_eq!(grid.quality_by(u, Some(sens), 1).unwrap(), quality);
            assert_eq!(nodes.quality_by(u, Some(sens), 1).unwrap(), quality);
            assert!(quality.iter().zip(&seen).all(|(&q, &v)| (q > 0.0) == v && q <= 1.0));
            assert_eq!(nodes.per_uav_by(u, Some(sens), 1).unwrap(), mesh.per_uav_by(u, Some(sens), 2).unwrap());
        }
    }

    #[test]
    fn paths_are_checked() {
        let s = flat(5);
        let t = || Targets::of_surface(&s, 1.0).unwrap();
        assert_eq!("grid".parse::<Path>().unwrap(), Path::Grid);
        assert!("bvh".parse::<Path>().is_err());
        let mesh = Arc::new(Surface::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]).unwrap());
        assert!(Visibility::with_path(mesh.clone(), t(), 5.0, Path::Grid).is_err());
        assert!(Targets::grid_nodes(mesh.clone()).is_err());
        assert_eq!(Visibility::new(mesh, t(), 5.0).unwrap().path(), Path::Mesh);
        // Grid-node targets of one surface cannot be used on another.
        assert!(Visibility::new(flat(5), Targets::grid_nodes(s.clone()).unwrap(), 5.0).is_err());
    }

    #[test]
    fn the_mesh_path_refuses_a_grid_too_large_for_it() {
        // 2300 x 2300 nodes: 10.6 million triangles, over MAX_TRIANGLES; the grid path is fine.
        let n = 2300;
        let s = Arc::new(Surface::from_grid(vec![0.0; n * n], n, n, 1.0, 1.0, 0.0, 0.0).unwrap());
        let targets = Targets::new(vec![[10.0, 10.0, 0.0]], None).unwrap();
        let err = Visibility::with_path(s.clone(), targets.clone(), 5.0, Path::Mesh).err().unwrap();
        assert!(matches!(err, crate::error::Error::TooLarge(_)), "{err:?}");
        let vis = Visibility::new(s, targets, 5.0).unwrap();
        assert_eq!(vis.seen(&[[10.0, 12.0, 3.0]], 1).unwrap(), vec![true]);
    }

    #[test]
    fn bad_input_is_an_error() {
        let s = flat(3);
        let t = || Targets::of_surface(&s, 1.0).unwrap();
        assert!(Visibility::new(s.clone(), t(), 0.0).is_err());
        assert!(Visibility::new(s.clone(), t(), f64::NAN).is_err());
        let vis = Visibility::new(s.clone(), t(), 5.0).unwrap();
        assert!(vis.seen(&[], 1).is_err());
        assert!(vis.seen(&[[f64::NAN, 0.0, 1.0]], 1).is_err());
        assert!(Targets::new(vec![], None).is_err());
        assert!(Targets::new(vec![[0.0; 3]], Some(vec![-1.0])).is_err());
        assert!(Targets::new(vec![[0.0; 3]], Some(vec![0.0])).is_err());
    }

    #[test]
    fn huge_ranges_are_unlimited_and_answer_like_the_mesh_path() {
        // The issue's panic: `Visibility(t, 1e19).coverage([[5, 5, 3]])` on an 11 x 11 grid.
        let s = flat(11);
        let nodes = || Targets::grid_nodes(s.clone()).unwrap();
        let all = Visibility::new(s.clone(), nodes(), 100.0).unwrap().seen(&[[5.0, 5.0, 3.0]], 1).unwrap();
        for d_max in [6e18, 1e19, 1e300, f64::MAX] {
            for path in [Path::Grid, Path::Mesh] {
                let vis = Visibility::with_path(s.clone(), nodes(), d_max, path).unwrap();
                assert_eq!(vis.d_max(), d_max);
                assert_eq!(vis.seen(&[[5.0, 5.0, 3.0]], 1).unwrap(), all, "{d_max} {path:?}");
                assert_eq!(vis.coverage(&[[5.0, 5.0, 3.0], [1e15, -1e15, 1e15]], 2).unwrap(), 1.0);
                assert_eq!(vis.per_uav(&[[5.0, 5.0, 3.0]], 1).unwrap().coverage, 1.0);
            }
        }
    }

    #[test]
    fn coordinates_beyond_the_bound_are_refused() {
        // The issue's silent 1.0: the mesh path, d_max = 1e300 and a UAV at z = 3e300.
        let s = flat(11);
        let vis = Visibility::with_path(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 1e300, Path::Mesh).unwrap();
        for uav in [[5.0, 5.0, 3e300], [5.0, 1.000_000_1e15, 3.0]] {
            assert!(matches!(vis.coverage(&[uav], 1), Err(Error::InvalidInput(_))), "{uav:?}");
            assert!(matches!(vis.per_uav(&[uav], 1), Err(Error::InvalidInput(_))));
        }
        assert!(matches!(Targets::new(vec![[1e300, 0.0, 0.0]], None), Err(Error::InvalidInput(_))));
    }

    #[test]
    fn grids_far_from_the_origin_give_the_mesh_paths_coverage() {
        // The issue's hang: a grid at 1e10 m, one UAV above it.
        let n = 30;
        let z: Vec<f64> = (0..n * n).map(|k| ((k * 7919) % 23) as f64 * 0.4).collect();
        let s = Arc::new(Surface::from_grid(z, n, n, 1.0, 1.0, 1e10, 1e10).unwrap());
        let grid = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 25.0).unwrap();
        let mesh = Visibility::with_path(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 25.0, Path::Mesh).unwrap();
        let uavs = [[1e10 + 15.0, 1e10 + 15.0, 12.0], [1e10 + 3.0, 1e10 + 25.0, 9.0]];
        assert_eq!(grid.seen(&uavs, 2).unwrap(), mesh.seen(&uavs, 1).unwrap());
        assert_eq!(grid.per_uav(&uavs, 1).unwrap(), mesh.per_uav(&uavs, 2).unwrap());
    }

    #[test]
    fn many_uavs_keep_to_the_horizon_and_counter_budgets() {
        // 5000 UAVs: horizons share HORIZON_BUDGET, counters are summed in batches; the answers
        // are those of the mesh path.
        let s = rugged(40);
        let targets = Targets::of_surface(&s, 1.0).unwrap();
        let grid = Visibility::new(s.clone(), targets.clone(), 1e9).unwrap();
        let mesh = Visibility::with_path(s.clone(), targets, 1e9, Path::Mesh).unwrap();
        let uavs: Vec<Point> = (0..5000).map(|k| [101.0 + f64::from(k % 50) * 0.4, -7.0 + f64::from(k / 50) * 0.2, 12.0]).collect();
        assert_eq!(grid.per_uav(&uavs, 2).unwrap(), mesh.per_uav(&uavs, 2).unwrap());
    }
}
