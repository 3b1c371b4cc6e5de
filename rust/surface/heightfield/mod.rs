//! The exact fast path for surfaces built from an elevation grid.
//!
//! A [`HeightField`] answers the same questions as the triangle mesh of the grid (see
//! [`Surface::from_grid`](crate::surface::mesh::Surface::from_grid)) without ever storing that mesh: the
//! triangles are rebuilt from the heights when a query reaches them, with the very same corner
//! coordinates, so memory is the heights, one `u32` per node and a small pyramid of tiles.
//!
//! # Why the answers are identical to the mesh path
//!
//! The mesh path walks parry's BVH: a triangle counts for a ray when the ray passes the slab test
//! of the triangle's bounding box and then the leaf test (parry's, `geometry::triangle_hit`). Here the
//! bounding volume hierarchy is a quadtree of grid tiles instead: each tile's box spans exactly
//! the node coordinates it covers and the lowest and highest node heights in it, so it contains
//! the bounding box of every triangle of its cells, bit for bit. The slab test is monotone under
//! box inclusion, also in floating point (every step is a rounded subtraction or product with a
//! fixed sign), so a tile that fails it holds no triangle that could pass it. The leaves run the
//! same slab test on the same triangle boxes and the same triangle test on the same corners, in
//! the same order `[a, b, c]`, with the same ray and limit. Hence the same any-hit answer for
//! every segment; first hits (ground height, clearance) agree to the last bit except in exact
//! ties between triangles, where traversal order may pick the other of two equal distances.
//!
//! The max-height skipping comes for free: a segment that passes above a tile fails the z part of
//! the tile's slab test.
//!
//! ```
//! use uavcov::surface::heightfield::HeightField;
//! // A 3 x 3 grid, flat at z = 0 except a 5 m spike at the centre node.
//! let mut z = vec![0.0; 9];
//! z[4] = 5.0;
//! let hf = HeightField::new(z, 3, 3, 1.0, 1.0, 0.0, 0.0).unwrap();
//! assert!(!hf.line_of_sight([0.0, 1.0, 1.0], [2.0, 1.0, 0.0])); // the spike is in the way
//! assert!(hf.line_of_sight([0.0, 1.0, 11.0], [2.0, 1.0, 0.0])); // high enough to look over it
//! ```
//!
//! # Where things are
//!
//! This file holds the storage (heights, node numbering, the mesh tables built on demand) and
//! the public queries; each way of answering them has a file of its own:
//!
//! - `slab`: the mesh path's slab test taken apart, the primitive every other file uses.
//! - `walk`: any-hit by bisecting the segment over a pyramid of highest heights
//!   ([`HeightField::ray_hits`], [`HeightField::line_of_sight`]).
//! - `quadtree`: the tile quadtree of lowest and highest heights, for first hits and closest
//!   points ([`HeightField::first_hit`], [`HeightField::closest_point`]).
//! - `horizon`: a UAV's horizon, which clears most of a sight line before the walk, and with a
//!   target's skyline (see `crate::surface::skyline`) often all of it.

mod grid_horizon;
mod quadtree;
mod slab;
#[cfg(test)]
mod tests;
mod walk;

use std::sync::OnceLock;

use parry3d_f64::math::Vector;

use crate::error::{ensure, try_filled, try_with_capacity, Error, Result};
use crate::geometry::{triangle_area, Point, MAX_COORDINATE, SIGHT_FRACTION};
use crate::surface::grid::Grid;

pub(crate) use crate::surface::horizon::Horizon;
use quadtree::{build_levels, Level};
use walk::{build_tops, TopLevel};

/// An elevation grid with the structure for exact segment, vertical and closest-point queries.
#[derive(Debug, Clone)]
pub struct HeightField {
    grid: Grid,
    /// Finest first; the last level has a single tile.
    levels: Vec<Level>,
    /// Highest node height of tiles of 2, 4, 8, ... cells a side, up to one tile, for the walk.
    tops: Vec<TopLevel>,
    scales: Scales,
    n_vertices: usize,
    n_triangles: usize,
    area: f64,
    bounds: (Point, Point),
    /// No nodata at all: vertex `k` is node `k` and triangle `f` is half `f % 2` of cell `f / 2`.
    complete: bool,
    faces: OnceLock<Vec<[u32; 3]>>,
    areas: OnceLock<Vec<f64>>,
    /// `2 * cell + half` of each triangle, built on first use when there is nodata.
    cell_of_face: OnceLock<Vec<u64>>,
    /// Node of each vertex, built on first use when there is nodata.
    node_of_vertex: OnceLock<Vec<u32>>,
}

/// Constants of the walk, from the grid's size and position.
#[derive(Debug, Clone)]
struct Scales {
    inv_dx: f64,
    inv_dy: f64,
    /// One over the smaller spacing.
    inv_cell: f64,
    /// Magnitude of the grid's x and y coordinates plus its extent, metres.
    xy: f64,
    /// Magnitude of its heights plus their range, metres.
    z: f64,
}

impl HeightField {
    /// Builds the height field of a grid: node `(i, j)` at `x = x0 + j dx`, `y = y0 + i dy`,
    /// height `z[i * nx + j]`, each cell split along its diagonal `(i, j)-(i+1, j+1)` into the
    /// triangles `[(i,j), (i,j+1), (i+1,j+1)]` and `[(i,j), (i+1,j+1), (i+1,j)]`. NaN is nodata:
    /// a triangle with a NaN corner is left out, and so is every node no triangle uses.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for fewer than 2 rows or columns, a wrong-sized `z`, spacing or
    /// origin that is not finite (spacing also > 0), infinite heights, a node coordinate or
    /// height beyond [`MAX_COORDINATE`], or a spacing below the resolution of the coordinates
    /// (two neighbouring columns or rows at the same `x` or `y`); [`Error::Mesh`] when nodata
    /// leaves no triangle or the area is not a positive finite number (it underflows);
    /// [`Error::TooLarge`] for 2^32 nodes or more, or when the system refuses the memory.
    pub fn new(z: Vec<f64>, ny: usize, nx: usize, dx: f64, dy: f64, x0: f64, y0: f64) -> Result<Self> {
        /// Marks a node some triangle uses, before the vertices are numbered.
        const USED: u32 = 0;
        ensure!(ny >= 2 && nx >= 2, "an elevation grid needs at least 2 rows and 2 columns, got {ny} x {nx}");
        let n_nodes = ny.checked_mul(nx).ok_or_else(|| Error::TooLarge(format!("a {ny} x {nx} grid is too large")))?;
        ensure!(z.len() == n_nodes, "z has {} values, expected {ny} x {nx}", z.len());
        if n_nodes >= u32::MAX as usize {
            return Err(Error::TooLarge(format!("a {ny} x {nx} grid has 2^32 nodes or more; split it into tiles")));
        }
        ensure!(dx.is_finite() && dx > 0.0 && dy.is_finite() && dy > 0.0, "grid spacing must be finite and > 0, got ({dx}, {dy})");
        ensure!(x0.is_finite() && y0.is_finite(), "grid origin must be finite, got ({x0}, {y0})");
        ensure!(z.iter().all(|h| !h.is_infinite()), "heights must be finite or NaN (nodata), found an infinite value");
        ensure!(
            z.iter().all(|h| h.is_nan() || h.abs() <= MAX_COORDINATE),
            "heights must be at most {MAX_COORDINATE:e} m in magnitude (or NaN, nodata)"
        );
        let mut grid = Grid { ny, nx, dx, dy, x0, y0, z, vertex_of_node: Vec::new() };
        Self::check_coordinates(&grid)?;

        // Triangles, area and used nodes, in the mesh path's face order so the area sums alike.
        let mut vertex_of_node = try_filled(u32::MAX, n_nodes, "the grid's node numbering")?;
        let mut n_triangles = 0usize;
        let mut area = -0.0; // `Iterator::sum` of f64 starts here too
        for i in 0..ny - 1 {
            for j in 0..nx - 1 {
                let [t0, t1] = grid.cell_triangles(i, j);
                let [a, b, c, d] = grid.cell_nodes(i, j);
                if let Some([pa, pb, pc]) = t0 {
                    n_triangles += 1;
                    area += triangle_area(pa, pb, pc);
                    for k in [a, b, c] {
                        vertex_of_node[k] = USED;
                    }
                }
                if let Some([pa, pc, pd]) = t1 {
                    n_triangles += 1;
                    area += triangle_area(pa, pc, pd);
                    for k in [a, c, d] {
                        vertex_of_node[k] = USED;
                    }
                }
            }
        }
        if n_triangles == 0 {
            return Err(Error::Mesh("the elevation grid has no triangle without nodata".into()));
        }
        if !(area.is_finite() && area > 0.0) {
            return Err(Error::Mesh(format!("the elevation grid's area is {area} m^2, not a positive number (spacing too fine)")));
        }
        let mut n_vertices = 0u32;
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for (k, slot) in vertex_of_node.iter_mut().enumerate() {
            if *slot == USED {
                *slot = n_vertices;
                n_vertices += 1;
                let q = grid.node_point(k);
                for a in 0..3 {
                    lo[a] = lo[a].min(q[a]);
                    hi[a] = hi[a].max(q[a]);
                }
            }
        }
        let complete = grid.z.iter().all(|h| !h.is_nan());
        grid.vertex_of_node = vertex_of_node;
        let levels = build_levels(&grid);
        let tops = build_tops(&grid);
        let extent = ((nx - 1) as f64 * dx).max((ny - 1) as f64 * dy);
        let scales = Scales {
            inv_dx: 1.0 / dx,
            inv_dy: 1.0 / dy,
            inv_cell: 1.0 / dx.min(dy),
            xy: x0.abs().max(y0.abs()).max((x0 + (nx - 1) as f64 * dx).abs()).max((y0 + (ny - 1) as f64 * dy).abs()) + extent,
            z: lo[2].abs() + hi[2].abs() + (hi[2] - lo[2]),
        };
        Ok(Self {
            grid,
            tops,
            scales,
            levels,
            n_vertices: n_vertices as usize,
            n_triangles,
            area,
            bounds: (lo, hi),
            complete,
            faces: OnceLock::new(),
            areas: OnceLock::new(),
            cell_of_face: OnceLock::new(),
            node_of_vertex: OnceLock::new(),
        })
    }

    /// Refuses a grid whose nodes are not all within [`MAX_COORDINATE`], or whose spacing is
    /// below the resolution of its coordinates: node coordinates `x0 + j dx` (and `y0 + i dy`)
    /// must strictly increase, or cells have no width and the geometry no meaning (a grid at
    /// `1e300` m with 1 m cells is a single point).
    fn check_coordinates(g: &Grid) -> Result<()> {
        for (name, start, step, n) in [("x", g.x0, g.dx, g.nx), ("y", g.y0, g.dy, g.ny)] {
            let last = start + (n - 1) as f64 * step;
            ensure!(
                start.abs() <= MAX_COORDINATE && last.abs() <= MAX_COORDINATE,
                "grid nodes must be at most {MAX_COORDINATE:e} m from 0, got {name} from {start} to {last}"
            );
            let mut before = start;
            for k in 1..n {
                let at = start + k as f64 * step;
                if at <= before {
                    return Err(Error::InvalidInput(format!(
                        "grid spacing {step} m is below the resolution of its {name} coordinates near {start} m: nodes {} and {k} coincide",
                        k - 1
                    )));
                }
                before = at;
            }
        }
        Ok(())
    }

    /// The grid: shape, spacing, origin, heights and node-to-vertex numbering.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// Number of vertices (nodes used by at least one triangle).
    pub fn n_vertices(&self) -> usize {
        self.n_vertices
    }

    /// Number of triangles.
    pub fn n_triangles(&self) -> usize {
        self.n_triangles
    }

    /// Total area, m^2 (summed in face order, as the mesh path does).
    pub fn area(&self) -> f64 {
        self.area
    }

    /// `(mins, maxs)` of the vertices.
    pub fn bounds(&self) -> (Point, Point) {
        self.bounds
    }

    /// Vertex `i` (vertices are the used nodes in row-major order).
    pub fn vertex(&self, i: usize) -> Point {
        if self.complete {
            return self.grid.node_point(i);
        }
        let table = self.node_of_vertex.get_or_init(|| {
            (0..self.grid.vertex_of_node.len() as u32).filter(|&k| self.grid.vertex_of_node[k as usize] != u32::MAX).collect()
        });
        self.grid.node_point(table[i] as usize)
    }

    /// The triangles as vertex indices, in the mesh path's order (built on first call).
    ///
    /// # Panics
    /// When the system refuses the memory of the table (12 bytes a triangle); see
    /// [`HeightField::try_faces`].
    pub fn faces(&self) -> &[[u32; 3]] {
        self.try_faces().expect("memory for the face table")
    }

    /// [`HeightField::faces`], or [`Error::TooLarge`] when the system refuses the memory.
    ///
    /// # Errors
    /// [`Error::TooLarge`] when the table cannot be allocated (it is then not kept).
    pub fn try_faces(&self) -> Result<&[[u32; 3]]> {
        if let Some(f) = self.faces.get() {
            return Ok(f);
        }
        let vof = &self.grid.vertex_of_node;
        let mut out = try_with_capacity(self.n_triangles, "the grid's face table")?;
        self.for_each_face(|nodes, _| out.push(nodes.map(|k| vof[k])));
        Ok(self.faces.get_or_init(|| out))
    }

    /// The area of each triangle, m^2 (built on first call).
    ///
    /// # Panics
    /// When the system refuses the memory of the table (8 bytes a triangle); see
    /// [`HeightField::try_areas`].
    pub fn areas(&self) -> &[f64] {
        self.try_areas().expect("memory for the area table")
    }

    /// [`HeightField::areas`], or [`Error::TooLarge`] when the system refuses the memory.
    ///
    /// # Errors
    /// [`Error::TooLarge`] when the table cannot be allocated (it is then not kept).
    pub fn try_areas(&self) -> Result<&[f64]> {
        if let Some(a) = self.areas.get() {
            return Ok(a);
        }
        let mut out = try_with_capacity(self.n_triangles, "the grid's area table")?;
        self.for_each_face(|_, [a, b, c]| out.push(triangle_area(a, b, c)));
        Ok(self.areas.get_or_init(|| out))
    }

    /// The corners of triangle `f`.
    ///
    /// # Panics
    /// When `f` is not below [`HeightField::n_triangles`].
    pub fn triangle(&self, f: usize) -> [Vector; 3] {
        let code = if self.complete {
            f as u64
        } else {
            self.cell_of_face.get_or_init(|| {
                let mut out = Vec::with_capacity(self.n_triangles);
                for cell in 0..(self.grid.ny - 1) * (self.grid.nx - 1) {
                    let [t0, t1] = self.grid.cell_triangles(cell / (self.grid.nx - 1), cell % (self.grid.nx - 1));
                    if t0.is_some() {
                        out.push(2 * cell as u64);
                    }
                    if t1.is_some() {
                        out.push(2 * cell as u64 + 1);
                    }
                }
                out
            })[f]
        };
        let cell = (code / 2) as usize;
        let halves = self.grid.cell_triangles(cell / (self.grid.nx - 1), cell % (self.grid.nx - 1));
        halves[(code % 2) as usize].expect("a face index names a valid triangle")
    }

    /// Each vertex weighted by a third of the area of the triangles around it; the sums run in
    /// face order, so the weights equal the mesh path's to the last bit.
    pub fn vertex_weights(&self) -> Vec<f64> {
        let vof = &self.grid.vertex_of_node;
        let mut w = vec![0.0; self.n_vertices];
        self.for_each_face(|nodes, [a, b, c]| {
            let third = triangle_area(a, b, c) / 3.0;
            for k in nodes {
                w[vof[k] as usize] += third;
            }
        });
        w
    }

    fn for_each_face(&self, mut f: impl FnMut([usize; 3], [Vector; 3])) {
        let g = &self.grid;
        for i in 0..g.ny - 1 {
            for j in 0..g.nx - 1 {
                let [a, b, c, d] = g.cell_nodes(i, j);
                let [t0, t1] = g.cell_triangles(i, j);
                if let Some(t) = t0 {
                    f([a, b, c], t);
                }
                if let Some(t) = t1 {
                    f([a, c, d], t);
                }
            }
        }
    }

    /// Whether the ray `origin + t dir`, `0 <= t <= t_max`, crosses a triangle.
    ///
    /// A walk along the segment: over the tiles its footprint crosses, skipping those it passes
    /// above, then over the cells of the others, skipping the cells it passes above, then the
    /// mesh path's own leaf test on each remaining triangle (see [the module docs](self) for why
    /// the answer is the mesh path's, for every segment).
    pub fn ray_hits(&self, origin: Point, dir: Point, t_max: f64) -> bool {
        self.walk_hits(origin, dir, t_max)
    }

    /// The surface's height under `(x, y)` when that point lies well inside one triangle of a
    /// cell without nodata (clear of the cell's edges and its diagonal by `1e-6` of a cell), with
    /// a bound on how far it may differ from the exact vertical query's (parry's triangle test
    /// of [`HeightField::first_hit`]); `None` elsewhere. Inside a triangle, that query hits it,
    /// and both are that plane's height to a few ulps of the coordinates: the bound is `1e-9` of
    /// them, millions of ulps.
    pub(crate) fn interior_height(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        const CLEAR: f64 = 1e-6;
        let g = &self.grid;
        let (u, w) = ((x - g.x0) * self.scales.inv_dx, (y - g.y0) * self.scales.inv_dy);
        if !(u > 0.0 && w > 0.0 && u < (g.nx - 1) as f64 && w < (g.ny - 1) as f64) {
            return None; // off the grid, on its border, or NaN
        }
        // Truncation is the floor here (both are positive).
        let (j, i) = (u as usize, w as usize);
        let (fx, fy) = (u - j as f64, w - i as f64);
        if !(fx > CLEAR && fx < 1.0 - CLEAR && fy > CLEAR && fy < 1.0 - CLEAR && (fx - fy).abs() > CLEAR) {
            return None;
        }
        let row = i * g.nx + j;
        let (za, zb, zc, zd) = (g.z[row], g.z[row + 1], g.z[row + g.nx + 1], g.z[row + g.nx]);
        // The cell's triangles [a, b, c] (below its diagonal a-c, fx > fy) and [a, c, d].
        let h = if fx > fy { za + (zb - za) * fx + (zc - zb) * fy } else { za + (zc - zd) * fx + (zd - za) * fy };
        let spread = za.abs() + zb.abs() + zc.abs() + zd.abs();
        h.is_finite().then_some((h, 1e-9 * (spread + self.scales.xy + self.scales.z)))
    }

    /// Time of impact of the first crossing of `origin + t dir`, `0 <= t <= t_max`, if any.
    pub fn first_hit(&self, origin: Point, dir: Point, t_max: f64) -> Option<f64> {
        self.cast::<false>(origin, dir, t_max)
    }

    /// Whether a UAV at `uav` sees the point `target`: the segment from `uav` towards `target`,
    /// stopped 0.1 % of its length short of it, crosses no triangle (as the mesh path).
    #[inline]
    pub fn line_of_sight(&self, uav: Point, target: Point) -> bool {
        let d = [target[0] - uav[0], target[1] - uav[1], target[2] - uav[2]];
        !self.ray_hits(uav, d, SIGHT_FRACTION)
    }

    #[inline(always)]
    fn x(&self, j: usize) -> f64 {
        self.grid.x0 + j as f64 * self.grid.dx
    }

    #[inline(always)]
    fn y(&self, i: usize) -> f64 {
        self.grid.y0 + i as f64 * self.grid.dy
    }

    /// Bytes held, roughly: heights, node numbering, tile pyramid and any lazily built tables.
    pub fn memory_bytes(&self) -> usize {
        let levels: usize =
            self.levels.iter().map(|l| l.z.len() * 16).sum::<usize>() + self.tops.iter().map(|l| l.zmax.len() * 8).sum::<usize>();
        self.grid.z.len() * 8
            + self.grid.vertex_of_node.len() * 4
            + levels
            + self.faces.get().map_or(0, |f| f.len() * 12)
            + self.areas.get().map_or(0, |a| a.len() * 8)
            + self.cell_of_face.get().map_or(0, |c| c.len() * 8)
            + self.node_of_vertex.get().map_or(0, |n| n.len() * 4)
    }
}
