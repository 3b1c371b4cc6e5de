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
//! answer for every segment (see [`crate::surface::heightfield`]) at a fraction of the cost and memory.
//! The grid path is chosen automatically; the mesh path of a grid stays available for comparison.
//! On the grid path, grid-node targets also get their skyline (how steeply the surface rises
//! around them, direction by direction) from their chunk's second evaluation on, which settles
//! most sight lines with two look-ups.
//!
//! ```
//! use uavcov::surface::mesh::Surface;
//! use uavcov::visibility::{Targets, Visibility};
//! let s = Surface::from_grid(vec![0.0; 121], 11, 11, 1.0, 1.0, 0.0, 0.0).unwrap();
//! let targets = Targets::of_surface(&s, 1.0).unwrap();
//! let vis = Visibility::new(std::sync::Arc::new(s), targets, 100.0).unwrap();
//! // One UAV high above a flat square sees all of it.
//! assert_eq!(vis.coverage(&[[5.0, 5.0, 20.0]], 1).unwrap(), 1.0);
//! ```

mod counts;
pub mod sampling;
pub mod sensor;
mod targets;
pub mod tracking;

pub use counts::UavCounts;
use targets::Points;
pub use targets::Targets;

use std::sync::Arc;

use rayon::prelude::*;

use crate::error::{ensure, try_with_capacity, Error, Result};
use crate::geometry::{in_bounds, Point, MAX_COORDINATE, UNLIMITED_RANGE};
use crate::surface::heightfield::{HeightField, Horizon};
use crate::surface::mesh::{Blockers, Surface, TriangleMesh};
use crate::surface::skyline::{sector_edges, ChunkSkylines, SectorEdges, Skyline, Skylines, Stencil};
use crate::threads;
use crate::visibility::sensor::Sensor;

/// Targets per chunk: small enough to balance very unequal UAV footprints, large enough that
/// the per-chunk culling and rayon's ~1 us per task stay negligible.
pub(crate) const CHUNK: usize = 256;

/// Most horizon bounds kept at once for one evaluation (4 bytes each: 256 MiB), shared by its
/// UAVs; a horizon's size changes how much of a sight line it clears, never an answer.
pub(crate) const HORIZON_BUDGET: usize = 1 << 26;

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
    /// clear a sight line's last [`REACH`](crate::surface::skyline::REACH) cells, so the horizon stops
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

#[cfg(test)]
mod tests;
