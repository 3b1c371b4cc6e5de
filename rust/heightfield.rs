//! The exact fast path for surfaces built from an elevation grid.
//!
//! A [`HeightField`] answers the same questions as the triangle mesh of the grid (see
//! [`Surface::from_grid`](crate::mesh::Surface::from_grid)) without ever storing that mesh: the
//! triangles are rebuilt from the heights when a query reaches them, with the very same corner
//! coordinates, so memory is the heights, one `u32` per node and a small pyramid of tiles.
//!
//! # Why the answers are identical to the mesh path
//!
//! The mesh path walks parry's BVH: a triangle counts for a ray when the ray passes the slab test
//! of the triangle's bounding box and then `local_ray_intersection_with_triangle`. Here the
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
//! use uavcov::heightfield::HeightField;
//! // A 3 x 3 grid, flat at z = 0 except a 5 m spike at the centre node.
//! let mut z = vec![0.0; 9];
//! z[4] = 5.0;
//! let hf = HeightField::new(z, 3, 3, 1.0, 1.0, 0.0, 0.0).unwrap();
//! assert!(!hf.line_of_sight([0.0, 1.0, 1.0], [2.0, 1.0, 0.0])); // the spike is in the way
//! assert!(hf.line_of_sight([0.0, 1.0, 11.0], [2.0, 1.0, 0.0])); // high enough to look over it
//! ```

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::sync::OnceLock;

use parry3d_f64::math::Vector;
use parry3d_f64::query::details::local_ray_intersection_with_triangle;
use parry3d_f64::query::{PointQuery, Ray};
use parry3d_f64::shape::Triangle;

use crate::error::{ensure, Error, Result};
use crate::mesh::{p, triangle_area, v, Grid, Point, SIGHT_FRACTION};
#[cfg(test)]
use crate::skyline::Stencil;
use crate::skyline::{sector_of, Skyline, REACH};

/// The smallest stored tiles are `2^FIRST_SHIFT` cells on a side; below them, cell boxes are
/// computed from the four corner heights, which the triangle test reads anyway.
const FIRST_SHIFT: u32 = 2;

/// The horizon is built from tiles of `2^HORIZON_SHIFT` cells a side.
const HORIZON_SHIFT: u32 = 1;

/// Pieces of segment whose footprint box spans at most this many cells a side are tested cell
/// by cell.
const BOX: usize = 8;

/// Cells per side of a leaf tile.
const LEAF: usize = 1 << FIRST_SHIFT;

/// One level of the tile pyramid.
#[derive(Debug, Clone)]
struct Level {
    /// Tiles are `2^shift` cells on a side.
    shift: u32,
    rows: usize,
    cols: usize,
    /// `[lowest, highest]` non-NaN node height per tile, row-major; `[inf, -inf]` when empty.
    z: Vec<[f64; 2]>,
}

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

/// A ray prepared the way the mesh path prepares it.
struct Cast {
    ray: Ray,
    inv: [f64; 3],
}

/// The `[near, far]` parameter interval of one axis of the slab test, exactly as
/// `mesh::slab_test` computes it (an axis the ray does not move along is a position test).
#[inline(always)]
fn axis(lo: f64, hi: f64, origin: f64, inv: f64) -> (f64, f64) {
    if inv.is_infinite() {
        if origin < lo || origin > hi {
            (f64::INFINITY, f64::NEG_INFINITY)
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        }
    } else {
        let (a, b) = ((lo - origin) * inv, (hi - origin) * inv);
        if a < b {
            (a, b)
        } else {
            (b, a)
        }
    }
}

/// `a.min(b)` for values that are never NaN: one instruction instead of a NaN-aware sequence.
#[inline(always)]
fn min(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// `a.max(b)` for values that are never NaN.
#[inline(always)]
fn max(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// `x as usize` for `x` already known to lie in `[0, usize::MAX)`, without the saturation checks.
#[inline(always)]
fn cell_index(x: f64) -> usize {
    debug_assert!((0.0..(usize::MAX as f64)).contains(&x));
    // SAFETY: callers clamp `x` into `[0, cells)` after ruling out NaN, so it is finite and in range.
    unsafe { x.to_int_unchecked::<usize>() }
}

/// What a UAV sees around it: for each angular sector and each distance, an upper bound on the
/// elevation slope (rise over horizontal run, from the UAV) of every grid cell of that sector up
/// to that distance. Built once per UAV and evaluation; it lets most sight lines skip the walk
/// but for their last few cells (see [`HeightField::line_of_sight_from`]), and, with the
/// target's [`Skyline`], skip it altogether (see [`HeightField::line_of_sight_to_node`]).
#[derive(Debug, Clone)]
pub struct Horizon {
    uav: Point,
    sectors: usize,
    bins: usize,
    /// Width of a distance bin, metres, and its inverse.
    bin: f64,
    inv_bin: f64,
    /// Sectors per unit of pseudo-angle.
    quarter: f64,
    /// Running maximum along distance of the slope bounds, `slope[bin * sectors + sector]`, each a
    /// signed square (`s |s|`, which orders like `s`) rounded up to `f32`.
    slope: Vec<f32>,
    /// How far every cell box was widened, metres.
    delta: f64,
}

impl Horizon {
    /// The UAV position.
    pub fn uav(&self) -> Point {
        self.uav
    }
}

/// One sector's bounds in a [`Horizon`], bin by bin.
#[derive(Clone, Copy)]
struct Column<'a> {
    slope: &'a [f32],
    stride: usize,
    len: usize,
}

impl Column<'_> {
    #[inline(always)]
    fn at(&self, bin: usize) -> f64 {
        self.slope[bin * self.stride] as f64
    }
}

/// A monotone stand-in for the angle of `(x, y)`, in `[0, 4)`: the diamond angle, which needs a
/// division instead of an arctangent.
#[inline(always)]
pub(crate) fn pseudo_angle(x: f64, y: f64) -> f64 {
    if y >= 0.0 {
        if x >= 0.0 {
            y / (x + y)
        } else {
            1.0 - x / (y - x)
        }
    } else if x < 0.0 {
        2.0 - y / (-x - y)
    } else {
        3.0 + x / (x - y)
    }
}

/// `x` as an `f32` no smaller than it.
#[inline(always)]
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    // Rounded down (never for NaN, where the comparison fails): the next value up.
    if (f as f64) < x {
        f.next_up()
    } else {
        f
    }
}

/// `f64` ordered for the closest-point heap (distances are never NaN).
#[derive(PartialEq)]
struct Near(f64, u8, u32, u32);

impl Eq for Near {}

impl PartialOrd for Near {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Near {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: BinaryHeap pops the largest, we want the nearest.
        other.0.total_cmp(&self.0)
    }
}

impl HeightField {
    /// Builds the height field of a grid: node `(i, j)` at `x = x0 + j dx`, `y = y0 + i dy`,
    /// height `z[i * nx + j]`, each cell split along its diagonal `(i, j)-(i+1, j+1)` into the
    /// triangles `[(i,j), (i,j+1), (i+1,j+1)]` and `[(i,j), (i+1,j+1), (i+1,j)]`. NaN is nodata:
    /// a triangle with a NaN corner is left out, and so is every node no triangle uses.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for fewer than 2 rows or columns, a wrong-sized `z`, spacing or
    /// origin that is not finite (spacing also > 0), infinite heights; [`Error::Mesh`] when nodata
    /// leaves no triangle; [`Error::TooLarge`] for 2^32 nodes or more.
    pub fn new(z: Vec<f64>, ny: usize, nx: usize, dx: f64, dy: f64, x0: f64, y0: f64) -> Result<Self> {
        ensure!(ny >= 2 && nx >= 2, "an elevation grid needs at least 2 rows and 2 columns, got {ny} x {nx}");
        let n_nodes = ny.checked_mul(nx).ok_or_else(|| Error::TooLarge(format!("a {ny} x {nx} grid is too large")))?;
        ensure!(z.len() == n_nodes, "z has {} values, expected {ny} x {nx}", z.len());
        if n_nodes >= u32::MAX as usize {
            return Err(Error::TooLarge(format!("a {ny} x {nx} grid has 2^32 nodes or more; split it into tiles")));
        }
        ensure!(dx.is_finite() && dx > 0.0 && dy.is_finite() && dy > 0.0, "grid spacing must be finite and > 0, got ({dx}, {dy})");
        ensure!(x0.is_finite() && y0.is_finite(), "grid origin must be finite, got ({x0}, {y0})");
        ensure!(z.iter().all(|h| !h.is_infinite()), "heights must be finite or NaN (nodata), found an infinite value");
        let mut grid = Grid { ny, nx, dx, dy, x0, y0, z, vertex_of_node: Vec::new() };

        // Triangles, area and used nodes, in the mesh path's face order so the area sums alike.
        const USED: u32 = 0;
        let mut vertex_of_node = vec![u32::MAX; n_nodes];
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
    pub fn faces(&self) -> &[[u32; 3]] {
        self.faces.get_or_init(|| {
            let vof = &self.grid.vertex_of_node;
            let mut out = Vec::with_capacity(self.n_triangles);
            self.for_each_face(|nodes, _| out.push(nodes.map(|k| vof[k])));
            out
        })
    }

    /// The area of each triangle, m^2 (built on first call).
    pub fn areas(&self) -> &[f64] {
        self.areas.get_or_init(|| {
            let mut out = Vec::with_capacity(self.n_triangles);
            self.for_each_face(|_, [a, b, c]| out.push(triangle_area(a, b, c)));
            out
        })
    }

    /// The corners of triangle `f`.
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
    /// mesh path's own leaf test on each remaining triangle (see [`HeightField::walk_hits`]).
    pub fn ray_hits(&self, origin: Point, dir: Point, t_max: f64) -> bool {
        self.walk_hits(origin, dir, t_max)
    }

    /// The any-hit answer of the tile quadtree (the first-hit machinery); the same answer as
    /// [`HeightField::ray_hits`], kept as a second, independent way to it for the tests.
    pub fn ray_hits_quadtree(&self, origin: Point, dir: Point, t_max: f64) -> bool {
        self.cast::<true>(origin, dir, t_max).is_some()
    }

    /// The mesh path's leaf test on the triangles of cell `(i, j)`: the slab test of each
    /// triangle's box, then parry's triangle test, corners in the mesh's order.
    #[inline(always)]
    fn cell_hit(&self, i: usize, j: usize, cast: &Cast, t_max: f64) -> bool {
        let g = &self.grid;
        let row = i * g.nx + j;
        let (za, zb, zc, zd) = (g.z[row], g.z[row + 1], g.z[row + g.nx + 1], g.z[row + g.nx]);
        if za.is_nan() || zc.is_nan() {
            return false; // both triangles use the diagonal a-c
        }
        let (xa, xb) = (self.x(j), self.x(j + 1));
        let (ya, yc) = (self.y(i), self.y(i + 1));
        let o = cast.ray.origin;
        // The slab test of each triangle's box, as `mesh::slab_test` (no value here is NaN, so
        // the plain comparisons below give what its `f64::max`/`min` give).
        let (nx, fx) = axis(xa, xb, o.x, cast.inv[0]);
        let (ny, fy) = axis(ya, yc, o.y, cast.inv[1]);
        let enter_xy = max(max(0.0, nx), ny);
        let exit_xy = min(min(t_max, fx), fy);
        if enter_xy > exit_xy {
            return false; // both triangles span the cell's whole footprint
        }
        self.triangles_hit(i, j, [za, zb, zc, zd], (enter_xy, exit_xy), cast, t_max)
    }

    /// The second half of the mesh path's leaf test, for the triangles `[a, b, c]` and
    /// `[a, c, d]` of cell `(i, j)` (corner heights `z`, `a` and `c` not NaN) on a ray that
    /// passes the cell's footprint between `xy.0` and `xy.1`: the z part of each triangle's slab
    /// test, then parry's triangle test, corners in the mesh's order.
    #[inline(always)]
    fn triangles_hit(&self, i: usize, j: usize, z: [f64; 4], xy: (f64, f64), cast: &Cast, t_max: f64) -> bool {
        let [za, zb, zc, zd] = z;
        let (enter_xy, exit_xy) = xy;
        let oz = cast.ray.origin.z;
        let (xa, xb) = (self.x(j), self.x(j + 1));
        let (ya, yc) = (self.y(i), self.y(i + 1));
        let a = Vector::new(xa, ya, za);
        let c = Vector::new(xb, yc, zc);
        let (lo_ac, hi_ac) = (min(za, zc), max(za, zc));
        // [a, b, c] and [a, c, d], as the mesh stores them.
        if !zb.is_nan() {
            let (nz, fz) = axis(min(lo_ac, zb), max(hi_ac, zb), oz, cast.inv[2]);
            if max(enter_xy, nz) <= min(exit_xy, fz) {
                if let Some((inter, _)) = local_ray_intersection_with_triangle(a, Vector::new(xb, ya, zb), c, &cast.ray) {
                    if inter.time_of_impact <= t_max {
                        return true;
                    }
                }
            }
        }
        if !zd.is_nan() {
            let (nz, fz) = axis(min(lo_ac, zd), max(hi_ac, zd), oz, cast.inv[2]);
            if max(enter_xy, nz) <= min(exit_xy, fz) {
                if let Some((inter, _)) = local_ray_intersection_with_triangle(a, c, Vector::new(xa, yc, zd), &cast.ray) {
                    if inter.time_of_impact <= t_max {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// The mesh path's leaf test on every triangle of the cells `[i0, i1] x [j0, j1]` (at most
    /// `BOX` a side): the slab test of each cell's box first (it holds both triangle boxes, so
    /// failing it fails theirs), with the x and y intervals of each column and row computed once.
    #[inline(always)]
    fn box_hits(&self, i0: usize, i1: usize, j0: usize, j1: usize, cast: &Cast, t_max: f64) -> bool {
        let g = &self.grid;
        let o = cast.ray.origin;
        let mut cols = [(0.0, 0.0); BOX];
        let mut rows = [(0.0, 0.0); BOX];
        self.spans(&mut cols[..=j1 - j0], |c| self.x(j0 + c), o.x, cast.inv[0]);
        self.spans(&mut rows[..=i1 - i0], |r| self.y(i0 + r), o.y, cast.inv[1]);
        for (r, &(ny, fy)) in rows.iter().enumerate().take(i1 - i0 + 1) {
            let (ny, fy) = (max(0.0, ny), min(t_max, fy));
            if ny > fy {
                continue;
            }
            let i = i0 + r;
            for (c, &(nx, fx)) in cols.iter().enumerate().take(j1 - j0 + 1) {
                let enter_xy = max(ny, nx);
                let exit_xy = min(fy, fx);
                if enter_xy > exit_xy {
                    continue;
                }
                let j = j0 + c;
                let row = i * g.nx + j;
                let (za, zb, zc, zd) = (g.z[row], g.z[row + 1], g.z[row + g.nx + 1], g.z[row + g.nx]);
                if za.is_nan() || zc.is_nan() {
                    continue; // both triangles use the diagonal a-c
                }
                let (lo_ac, hi_ac) = (min(za, zc), max(za, zc));
                // The cell box: NaN corners ignored (their triangle is left out below).
                let (lo, hi) = (lo_ac.min(zb).min(zd), hi_ac.max(zb).max(zd));
                let (nz, fz) = axis(lo, hi, o.z, cast.inv[2]);
                if max(enter_xy, nz) > min(exit_xy, fz) {
                    continue;
                }
                if self.triangles_hit(i, j, [za, zb, zc, zd], (enter_xy, exit_xy), cast, t_max) {
                    return true;
                }
            }
        }
        false
    }

    /// The slab intervals of consecutive cells along one axis, `out[c]` for the cell between the
    /// boundaries `at(c)` and `at(c + 1)`: [`axis`] for each, the boundaries computed once each
    /// and the interval's ends ordered by the sign of `inv` (which is what `axis`'s comparison
    /// finds, since the products are monotone in the boundary).
    #[inline(always)]
    fn spans(&self, out: &mut [(f64, f64)], at: impl Fn(usize) -> f64, origin: f64, inv: f64) {
        if inv.is_infinite() {
            for (c, span) in out.iter_mut().enumerate() {
                *span = axis(at(c), at(c + 1), origin, inv);
            }
            return;
        }
        let mut a = (at(0) - origin) * inv;
        for (c, span) in out.iter_mut().enumerate() {
            let b = (at(c + 1) - origin) * inv;
            *span = if inv > 0.0 { (a, b) } else { (b, a) };
            a = b;
        }
    }

    /// [`HeightField::cell_hit`] unless the piece of segment, lowest at `zmin`, passes above
    /// every corner of the cell.
    #[inline(always)]
    fn cell_hit_below(&self, i: usize, j: usize, zmin: f64, cast: &Cast, t_max: f64) -> bool {
        // A cell of nodata only has NaN corners: not skipped here, its triangles are left out.
        if zmin > self.cell_top(i, j) {
            return false;
        }
        self.cell_hit(i, j, cast, t_max)
    }

    /// The highest corner of cell `(i, j)` (NaN corners ignored; NaN when all are).
    #[inline(always)]
    fn cell_top(&self, i: usize, j: usize) -> f64 {
        let g = &self.grid;
        let row = i * g.nx + j;
        g.z[row].max(g.z[row + 1]).max(g.z[row + g.nx]).max(g.z[row + g.nx + 1])
    }

    /// Any-hit by bisecting the segment.
    ///
    /// A piece of the segment is clear when its lowest point is above the highest node of the
    /// (at most 2 x 2) pyramid tiles that cover its footprint box; otherwise it is cut in two,
    /// down to pieces whose footprint box spans at most 2 x 2 cells, whose triangles get the mesh
    /// path's own leaf test (skipping a cell the piece passes above).
    ///
    /// Exactness: the mesh path counts a triangle only when the ray passes the slab test of the
    /// triangle's box, which with rounding means some `t` in `[0, t_max]` puts the ray within a
    /// few ulps of the box (about `1e-16` of the coordinates). Here every footprint box is widened
    /// by `delta` (`1e-9` of the coordinates, millions of ulps) and every lowest point lowered by
    /// `delta_z`, so no triangle the mesh path would count is ever skipped, and every triangle not
    /// skipped gets the same leaf test: the answers are the same.
    pub fn walk_hits(&self, origin: Point, dir: Point, t_max: f64) -> bool {
        self.walk_hits_from(origin, dir, 0.0, t_max, t_max)
    }

    /// [`HeightField::walk_hits`] for the triangles the ray can reach at parameters in
    /// `[t_from, t_to]` (the leaf test is the mesh path's, with the limit `t_max >= t_to`).
    fn walk_hits_from(&self, origin: Point, dir: Point, t_from: f64, t_to: f64, t_max: f64) -> bool {
        let g = &self.grid;
        let s = &self.scales;
        let (cells_x, cells_y) = (g.nx - 1, g.ny - 1);
        // The segment in cell units: u along columns (x), w along rows (y).
        let (u0, du) = ((origin[0] - g.x0) * s.inv_dx, dir[0] * s.inv_dx);
        let (w0, dw) = ((origin[1] - g.y0) * s.inv_dy, dir[1] * s.inv_dy);
        let (z0, dz) = (origin[2], dir[2]);
        let end = [origin[0] + dir[0] * t_max, origin[1] + dir[1] * t_max, z0 + dz * t_max];
        let reach = max(max(origin[0].abs(), origin[1].abs()), max(end[0].abs(), end[1].abs()));
        let delta = 1e-9 * (1.0 + (reach + s.xy) * s.inv_cell);
        let delta_z = 1e-9 * (z0.abs() + end[2].abs() + s.z + 1e-300);
        if min(z0, end[2]) - delta_z > self.bounds.1[2] {
            return false; // above everything
        }
        let cast = Cast { ray: Ray::new(v(origin), v(dir)), inv: [1.0 / dir[0], 1.0 / dir[1], 1.0 / dir[2]] };
        let (nx_f, ny_f) = (cells_x as f64, cells_y as f64);
        // Pieces `[ta, tb]` of the parameter range still to clear, depth first: the piece in
        // hand, and the pieces put aside (the far halves, nearer the UAV).
        let mut stack = [(0.0f64, 0.0f64); 16];
        let mut top = 0;
        let mut piece = Some((t_from, t_to));
        loop {
            let (ta, tb) = match piece.take() {
                Some(p) => p,
                None if top > 0 => {
                    top -= 1;
                    stack[top]
                }
                None => break,
            };
            let (ua, ub) = (u0 + du * ta, u0 + du * tb);
            let (wa, wb) = (w0 + dw * ta, w0 + dw * tb);
            let (ulo, uhi) = (min(ua, ub) - delta, max(ua, ub) + delta);
            let (wlo, whi) = (min(wa, wb) - delta, max(wa, wb) + delta);
            if !(uhi >= 0.0 && ulo <= nx_f && whi >= 0.0 && wlo <= ny_f) {
                continue; // off the grid (also for NaN from absurd inputs)
            }
            // Cells of the widened footprint box, clamped to the grid; the clamps keep every
            // value in `[0, cells)` and the test above rules out NaN, so truncation is floor.
            let j0 = cell_index(max(ulo, 0.0));
            let j1 = cell_index(min(uhi, nx_f - 0.5));
            let i0 = cell_index(max(wlo, 0.0));
            let i1 = cell_index(min(whi, ny_f - 0.5));
            let zmin = min(z0 + dz * ta, z0 + dz * tb) - delta_z;
            if j1 - j0 < BOX && i1 - i0 < BOX {
                if self.box_hits(i0, i1, j0, j1, &cast, t_max) {
                    return true;
                }
                continue;
            }
            // The finest pyramid level whose tiles cover the box with at most 2 x 2 of them:
            // tiles of 2^(k+1) cells, where 2^(k+1) is at least the larger extent minus one.
            // The extent is at least 2. Tiles of 2^s >= extent cells meet the extent + 1 cells in
            // at most two; the top level is a single tile, which always does.
            let extent = (j1 - j0).max(i1 - i0);
            let k = ((usize::BITS - (extent - 1).leading_zeros()) as usize - 1).min(self.tops.len() - 1);
            let level = &self.tops[k];
            let s = level.shift;
            let (ti0, ti1, tj0, tj1) = (i0 >> s, i1 >> s, j0 >> s, j1 >> s);
            let row0 = &level.zmax[ti0 * level.cols..];
            let row1 = &level.zmax[ti1 * level.cols..];
            let high = max(max(row0[tj0], row0[tj1]), max(row1[tj0], row1[tj1]));
            if zmin > high {
                continue;
            }
            let tm = 0.5 * (ta + tb);
            if top + 1 > stack.len() || !(ta < tm && tm < tb) {
                // Too deep to split further (not reached with sane inputs): test every cell.
                for i in i0..=i1 {
                    for j in j0..=j1 {
                        if self.cell_hit_below(i, j, zmin, &cast, t_max) {
                            return true;
                        }
                    }
                }
                continue;
            }
            // Go on with the half nearer the end (the target, on the ground): it decides most
            // often.
            stack[top] = (ta, tm);
            top += 1;
            piece = Some((tm, tb));
        }
        false
    }

    /// Time of impact of the first crossing of `origin + t dir`, `0 <= t <= t_max`, if any.
    pub fn first_hit(&self, origin: Point, dir: Point, t_max: f64) -> Option<f64> {
        self.cast::<false>(origin, dir, t_max)
    }

    /// The [`Horizon`] of a UAV at `uav`, for targets up to `radius` metres away horizontally.
    pub fn horizon(&self, uav: Point, radius: f64) -> Horizon {
        let g = &self.grid;
        let w = g.dx.min(g.dy);
        let radius = if radius.is_finite() { radius.max(0.0) } else { 0.0 };
        let bins = ((radius / w).ceil() as usize).saturating_add(2).min(1 << 12);
        // Sectors about a bin wide at the far edge (at least 64, a multiple of 4).
        let sectors = ((std::f64::consts::PI * radius / w).ceil().max(64.0) as usize).next_multiple_of(4).min(4096);
        let (px, py, pz) = (uav[0], uav[1], uav[2]);
        let delta = 1e-9 * (px.abs().max(py.abs()) + self.scales.xy + radius);
        let delta_z = 1e-9 * (pz.abs() + self.scales.z + 1e-300);
        let reach = bins as f64 * w; // every cell nearer than this is entered
        let reach2 = reach * reach;
        let inv_w = 1.0 / w;
        // Bounds by bin then sector while cells are entered; a running maximum along distance,
        // stored sector by sector for the queries, at the end.
        let mut by_bin = vec![f32::NEG_INFINITY; sectors * bins];
        let quarter = sectors as f64 / 4.0;
        let last_row = (g.ny - 2) as f64;
        let last_col = (g.nx - 2) as f64;
        let i_lo = ((py - reach - g.y0) / g.dy).floor() - 1.0;
        let i_hi = ((py + reach - g.y0) / g.dy).floor() + 1.0;
        let j_lo = ((px - reach - g.x0) / g.dx).floor() - 1.0;
        let j_hi = ((px + reach - g.x0) / g.dx).floor() + 1.0;
        if i_hi >= 0.0 && i_lo <= last_row && j_hi >= 0.0 && j_lo <= last_col {
            let (i0, i1) = (i_lo.max(0.0) as usize, i_hi.min(last_row) as usize);
            let (j0, j1) = (j_lo.max(0.0) as usize, j_hi.min(last_col) as usize);
            // Units of 2^s x 2^s cells (the pyramid's tiles), or single cells for s = 0.
            let s = HORIZON_SHIFT.min(self.tops.len() as u32);
            let (ui0, ui1, uj0, uj1) = (i0 >> s, i1 >> s, j0 >> s, j1 >> s);
            // Unit edges relative to the UAV, and the pseudo-angles of the unit corners of the
            // current pair of corner rows (shared by neighbouring units).
            let xs: Vec<f64> = (uj0..=uj1 + 1).map(|u| self.x((u << s).min(g.nx - 1)) - px).collect();
            let y_of = |u: usize| self.y((u << s).min(g.ny - 1)) - py;
            let angles = |y: f64| -> Vec<f64> { xs.iter().map(|&x| if x == 0.0 && y == 0.0 { 0.0 } else { pseudo_angle(x, y) }).collect() };
            let mut lower = angles(y_of(ui0));
            let mut unit_top = vec![0.0f64; xs.len()];
            for i in ui0..=ui1 {
                let (ylo, yhi) = (y_of(i), y_of(i + 1));
                let upper = angles(yhi);
                let ny = max(max(ylo, -yhi), 0.0);
                let yfar = max(-ylo, yhi) + 2.0 * delta;
                if s == 0 {
                    let (row0, row1) = (&g.z[i * g.nx..(i + 1) * g.nx], &g.z[(i + 1) * g.nx..(i + 2) * g.nx]);
                    for (k, top) in unit_top.iter_mut().enumerate() {
                        *top = row0[j0 + k].max(row1[j0 + k]); // NaN ignored unless both are
                    }
                    for k in 0..unit_top.len() - 1 {
                        unit_top[k] = unit_top[k].max(unit_top[k + 1]);
                    }
                } else {
                    let level = &self.tops[s as usize - 1];
                    unit_top[..=uj1 - uj0].copy_from_slice(&level.zmax[i * level.cols + uj0..=i * level.cols + uj1]);
                }
                if ny < reach {
                    for c in 0..=uj1 - uj0 {
                        let top = unit_top[c];
                        if top.is_nan() || top == f64::NEG_INFINITY {
                            continue; // nodata (NaN, or an empty tile's -inf): no triangle
                        }
                        let (xlo, xhi) = (xs[c], xs[c + 1]);
                        let nx = max(max(xlo, -xhi), 0.0);
                        let near2 = nx * nx + ny * ny;
                        if near2 >= reach2 {
                            continue;
                        }
                        // The bound on rise over run, kept as a signed square: the cell's top
                        // (raised by delta_z) over its nearest distance (less 2 delta) when above
                        // the UAV, else over its farthest (plus 2 delta); rounded up.
                        let rise = top + delta_z - pz;
                        let near = near2.sqrt();
                        let sigma = if rise < 0.0 {
                            let xfar = max(-xlo, xhi) + 2.0 * delta;
                            -(rise * rise) / (xfar * xfar + yfar * yfar)
                        } else {
                            let run = near - 2.0 * delta;
                            if run > 0.0 {
                                rise * rise / (run * run)
                            } else {
                                f64::INFINITY
                            }
                        };
                        // Rounded up with a margin for its own rounding (1e-12 of it) and the
                        // queries' comparison margin (1e-9) already added, so that a query
                        // compares once per bin.
                        let sigma = round_up(sigma + 1.001e-9 * sigma.abs() + 1e-300);
                        let b = ((near * inv_w) as usize).min(bins - 1);
                        let row = &mut by_bin[b * sectors..(b + 1) * sectors];
                        let mut put = |k0: usize, k1: usize| {
                            for slot in &mut row[k0..=k1] {
                                *slot = if sigma > *slot { sigma } else { *slot };
                            }
                        };
                        // Sectors of the cell's angles from the corners that bound them (by where
                        // the cell lies from the UAV), one more on each side for rounding.
                        let sector = |a: f64| ((a * quarter) as usize).min(sectors - 1); // a in [0, 4]
                        let (lo_l, hi_l, lo_u, hi_u) = (lower[c], lower[c + 1], upper[c], upper[c + 1]);
                        let (right, left) = (xlo > 0.0, xhi < 0.0);
                        let (above, below) = (ylo > 0.0, yhi < 0.0);
                        let (first, last) = match (right, left, above, below) {
                            (false, false, false, false) => {
                                put(0, sectors - 1); // the UAV stands over this cell
                                continue;
                            }
                            (true, _, false, false) => {
                                // Across the +x axis, where the pseudo-angle wraps from 4 to 0.
                                put(sector(lo_l).saturating_sub(1), sectors - 1);
                                put(0, (sector(lo_u) + 1).min(sectors - 1));
                                continue;
                            }
                            (true, _, true, _) => (hi_l, lo_u),
                            (false, false, true, _) => (hi_l, lo_l),
                            (_, true, true, _) => (hi_u, lo_l),
                            (_, true, false, false) => (hi_u, hi_l),
                            (_, true, _, true) => (lo_u, hi_l),
                            (false, false, _, true) => (lo_u, hi_u),
                            (true, _, _, true) => (lo_l, hi_u),
                        };
                        let (k0, k1) = (sector(first), sector(last));
                        // Next to the wrap, the spare sector is across it.
                        let k0 = if k0 == 0 {
                            put(sectors - 1, sectors - 1);
                            0
                        } else {
                            k0 - 1
                        };
                        let k1 = if k1 + 1 >= sectors {
                            put(0, 0);
                            sectors - 1
                        } else {
                            k1 + 1
                        };
                        put(k0, k1);
                    }
                }
                lower = upper;
            }
        }
        // Running maximum outwards: bin b of sector k then bounds sector k up to bin b. Every
        // row only ever grows, so this is a plain element-wise max of consecutive rows.
        for b in 1..bins {
            let (done, rest) = by_bin.split_at_mut(b * sectors);
            for (slot, &before) in rest[..sectors].iter_mut().zip(&done[(b - 1) * sectors..]) {
                *slot = slot.max(before);
            }
        }
        let slope = by_bin;
        Horizon { uav, sectors, bins, bin: w, inv_bin: 1.0 / w, quarter, slope, delta }
    }

    /// [`HeightField::line_of_sight`] from the UAV of `horizon`, the same answer to the last bit.
    ///
    /// The horizon clears the sight line up to the first distance bin whose bound reaches the
    /// line's slope (a binary search, the bounds being a running maximum); only the rest of the
    /// line, usually its last cell or two, goes through [`HeightField::walk_hits`].
    ///
    /// Exactness: a triangle the mesh path counts is within a few ulps of the ray at some `t`.
    /// If that `t` is past the cleared stretch, the walk of the rest finds the triangle.
    /// Otherwise the ray there is at most the cleared distance from the UAV, so the triangle's
    /// cell is nearer than the first uncleared bin (the stretch stops `2 delta` short of it); the
    /// cell's angles hold the sight line's (to rounding, and one spare sector each side), so its
    /// bound is at most the horizon value of the target's sector, which is below the sight line's
    /// slope: the ray passes above the cell at that `t`, a contradiction. (The bound of a cell:
    /// its highest corner raised by `delta_z`, over its nearest distance less `2 delta`, or over
    /// its farthest plus `2 delta` when below the UAV; squared with its sign and rounded up.)
    pub fn line_of_sight_from(&self, horizon: &Horizon, target: Point) -> bool {
        let p = horizon.uav;
        let d = [target[0] - p[0], target[1] - p[1], target[2] - p[2]];
        let r2 = d[0] * d[0] + d[1] * d[1];
        let mut t_from = 0.0;
        if r2 > 0.0 {
            let k = ((pseudo_angle(d[0], d[1]) * horizon.quarter) as usize).min(horizon.sectors - 1);
            let sigma = d[2] * d[2].abs() / r2;
            let row = Column { slope: &horizon.slope[k..], stride: horizon.sectors, len: horizon.bins };
            // The line's slope less its own margin against the stored bounds (which hold theirs;
            // an empty stretch has -inf, an unbounded one +inf, which never clears).
            let s = sigma - 1e-9 * sigma.abs() - 1e-300;
            let lo = Self::first_unclear(row, s);
            // Every cell nearer than `lo` bins is cleared; the ray at distance `cleared` from
            // the UAV only reaches cells nearer than that plus a few ulps.
            let cleared = lo as f64 * horizon.bin - 2.0 * horizon.delta;
            let r = r2.sqrt();
            if cleared >= r * SIGHT_FRACTION {
                return true; // cleared all the way
            }
            if cleared > 0.0 {
                t_from = cleared / r;
            }
        }
        !self.walk_hits_from(p, d, t_from, SIGHT_FRACTION, SIGHT_FRACTION)
    }

    /// [`HeightField::line_of_sight_from`] for a target at a grid node, with the node's
    /// [`Skyline`]: the same answer to the last bit, usually without walking at all.
    ///
    /// When the sight line arrives at the node more steeply than the skyline's bound for its
    /// direction, it passes above every triangle within [`REACH`] cells of the node; the UAV's
    /// horizon then only has to clear it up to that distance from the target, which a single
    /// look-up answers (its bounds are a running maximum), and what neither clears is walked.
    ///
    /// Exactness: a triangle the mesh path counts has a point `P` within `eps` (a few ulps, here
    /// `1e-9` of the coordinates) of the ray at some `t <= SIGHT_FRACTION`, where the ray is at
    /// least `rho_end = (1 - SIGHT_FRACTION) r` from the target horizontally. If `P` is within
    /// [`REACH`] cells of the node, its direction is within `eps / rho_end < 0.01` radians of
    /// the line's (the test asks `rho_end > 100 eps`), so inside the sectors the bound covers
    /// (the line's and its neighbours, 0.1 radians or more each), and `z_P - z_T <= slope rho_P`,
    /// while the ray there is `line rho` above `z_T` (to `eps`): then
    /// `(line - slope) rho <= eps (2 + |slope|)`, which the test below rules out. Otherwise the
    /// ray point is farther than the cleared reach from the target, i.e. nearer the UAV than
    /// `r - reach + 2 eps`, where the horizon (as in [`HeightField::line_of_sight_from`]) or the
    /// walk of that stretch decides.
    ///
    /// [`REACH`]: crate::skyline::REACH
    pub fn line_of_sight_to_node(&self, horizon: &Horizon, target: Point, skyline: &Skyline) -> bool {
        let p = horizon.uav;
        let d = [target[0] - p[0], target[1] - p[1], target[2] - p[2]];
        let r2 = d[0] * d[0] + d[1] * d[1];
        if r2 == 0.0 {
            return self.line_of_sight_from(horizon, target);
        }
        let r = r2.sqrt();
        let inv_r = 1.0 / r;
        let rho_end = (1.0 - SIGHT_FRACTION) * r;
        let eps = 4.0 * horizon.delta + 1e-9 * (p[2].abs() + target[2].abs() + self.scales.z);
        // Slope of the line from the target towards the UAV, and the skyline's bound that way
        // (the opposite pseudo-angle of the UAV-to-target direction).
        let line = -d[2] * inv_r;
        let a = pseudo_angle(d[0], d[1]);
        let bound = skyline.slope(sector_of(if a < 2.0 { a + 2.0 } else { a - 2.0 }));
        if !(rho_end > 100.0 * eps && (line - bound) * rho_end > 2.0 * eps * (1.0 + bound.abs() + line.abs())) {
            return self.line_of_sight_from(horizon, target);
        }
        // The ray is clear within `reach` of the target; the horizon must clear it up to `far`
        // from the UAV: every bin before `need` (the stretch cleared by `lo` bins ends `2 delta`
        // short of `lo` bins).
        let reach = REACH as f64 * horizon.bin - eps;
        let far = r - reach + eps;
        if far <= 0.0 {
            return true;
        }
        let need = ((far + 2.0 * horizon.delta) * horizon.inv_bin).ceil();
        let k = ((a * horizon.quarter) as usize).min(horizon.sectors - 1);
        let row = Column { slope: &horizon.slope[k..], stride: horizon.sectors, len: horizon.bins };
        // The horizon's signed squared slope, from the UAV (the line's, negated), less the margin
        // of the comparison (the stored bounds hold theirs).
        let sigma = -line * line.abs();
        let s = sigma - 1e-9 * sigma.abs() - 1e-300;
        if need < 1.0 || (need <= row.len as f64 && s > row.at(need as usize - 1)) {
            return true;
        }
        let lo = Self::first_unclear(row, s);
        let cleared = lo as f64 * horizon.bin - 2.0 * horizon.delta;
        let t_from = if cleared > 0.0 { cleared * inv_r } else { 0.0 };
        let t_to = (far * inv_r).min(SIGHT_FRACTION);
        if t_from >= t_to {
            return true;
        }
        !self.walk_hits_from(p, d, t_from, t_to, SIGHT_FRACTION)
    }

    /// The first distance bin of a horizon row whose bound reaches the signed squared slope
    /// `s` (`row.len()` when none does), by a halving without branches: the bounds are a
    /// running maximum, so every bin before the answer clears.
    #[inline(always)]
    fn first_unclear(row: Column<'_>, s: f64) -> usize {
        let mut base = 0usize;
        let mut n = row.len;
        while n > 1 {
            let half = n / 2;
            base += half * usize::from(s > row.at(base + half));
            n -= half;
        }
        base + usize::from(s > row.at(base))
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

    /// Node rows `[i0, i1]` and columns `[j0, j1]` of tile `(ti, tj)` at `level`.
    #[inline(always)]
    fn tile_nodes(&self, level: &Level, ti: usize, tj: usize) -> (usize, usize, usize, usize) {
        let s = level.shift;
        let i0 = ti << s;
        let j0 = tj << s;
        (i0, ((ti + 1) << s).min(self.grid.ny - 1), j0, ((tj + 1) << s).min(self.grid.nx - 1))
    }

    /// The cell range `[lo, hi]` along one axis that a coordinate range can touch, widened by one
    /// cell plus far more than any rounding of the slab test; `None` when it misses the grid.
    fn cell_span(lo: f64, hi: f64, start: f64, step: f64, n_cells: usize) -> Option<(usize, usize)> {
        let scale = lo.abs().max(hi.abs()).max(start.abs()) + n_cells as f64 * step;
        let slack = 1.0 + 1e-9 * scale / step;
        let a = ((lo - start) / step - slack).floor();
        let b = ((hi - start) / step + slack).floor();
        let last = (n_cells - 1) as f64;
        if !(a <= last && b >= 0.0) {
            return None; // also catches NaN from absurd inputs
        }
        Some((a.max(0.0) as usize, b.min(last) as usize))
    }

    /// The ray cast shared by the any-hit (`ANY`) and first-hit queries.
    fn cast<const ANY: bool>(&self, origin: Point, dir: Point, t_max: f64) -> Option<f64> {
        let g = &self.grid;
        let end = [origin[0] + dir[0] * t_max, origin[1] + dir[1] * t_max];
        let (cj0, cj1) = Self::cell_span(origin[0].min(end[0]), origin[0].max(end[0]), g.x0, g.dx, g.nx - 1)?;
        let (ci0, ci1) = Self::cell_span(origin[1].min(end[1]), origin[1].max(end[1]), g.y0, g.dy, g.ny - 1)?;
        let cast = Cast { ray: Ray::new(v(origin), v(dir)), inv: [1.0 / dir[0], 1.0 / dir[1], 1.0 / dir[2]] };
        // Start at the finest level whose tiles hold the span in at most 2 x 2 of them.
        let start = self
            .levels
            .iter()
            .position(|l| (cj1 >> l.shift) - (cj0 >> l.shift) <= 1 && (ci1 >> l.shift) - (ci0 >> l.shift) <= 1)
            .unwrap_or(self.levels.len() - 1);
        let mut best = t_max;
        let mut found = false;
        // Depth-first over (level, tile row, tile column); each pop pushes at most 4.
        let mut stack: [(u32, u32, u32); 160] = [(0, 0, 0); 160];
        let mut top = 0usize;
        let l = &self.levels[start];
        for ti in ci0 >> l.shift..=ci1 >> l.shift {
            for tj in cj0 >> l.shift..=cj1 >> l.shift {
                if self.tile_passes(start, ti, tj, &cast, best).is_some() {
                    stack[top] = (start as u32, ti as u32, tj as u32);
                    top += 1;
                }
            }
        }
        while top > 0 {
            top -= 1;
            let (lv, ti, tj) = stack[top];
            let (lv, ti, tj) = (lv as usize, ti as usize, tj as usize);
            if !ANY && lv < start && self.tile_passes(lv, ti, tj, &cast, best).is_none() {
                continue; // the first hit so far has moved closer than this tile
            }
            if lv == 0 {
                if self.leaf_tile::<ANY>(ti, tj, &cast, &mut best, &mut found) && ANY {
                    return Some(best);
                }
                continue;
            }
            let child = &self.levels[lv - 1];
            let mut kids: [(f64, u32, u32); 4] = [(0.0, 0, 0); 4];
            let mut n = 0;
            for ci in 2 * ti..(2 * ti + 2).min(child.rows) {
                for cj in 2 * tj..(2 * tj + 2).min(child.cols) {
                    if let Some(enter) = self.tile_passes(lv - 1, ci, cj, &cast, best) {
                        kids[n] = (enter, ci as u32, cj as u32);
                        n += 1;
                    }
                }
            }
            if !ANY {
                // Nearest child on top of the stack, so the first hit shrinks the limit early.
                kids[..n].sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
            }
            for &(_, ci, cj) in &kids[..n] {
                stack[top] = ((lv - 1) as u32, ci, cj);
                top += 1;
            }
        }
        found.then_some(best)
    }

    /// The slab test of a stored tile's box; `Some(entry parameter)` when the ray passes it.
    #[inline(always)]
    fn tile_passes(&self, lv: usize, ti: usize, tj: usize, cast: &Cast, t_lim: f64) -> Option<f64> {
        let level = &self.levels[lv];
        let [zlo, zhi] = level.z[ti * level.cols + tj];
        if zlo > zhi {
            return None; // all nodata
        }
        let (i0, i1, j0, j1) = self.tile_nodes(level, ti, tj);
        let o = cast.ray.origin;
        let (nx, fx) = axis(self.x(j0), self.x(j1), o.x, cast.inv[0]);
        let (ny, fy) = axis(self.y(i0), self.y(i1), o.y, cast.inv[1]);
        let (nz, fz) = axis(zlo, zhi, o.z, cast.inv[2]);
        let enter = 0.0f64.max(nx).max(ny).max(nz);
        let exit = t_lim.min(fx).min(fy).min(fz);
        (enter <= exit).then_some(enter)
    }

    /// Tests the triangles of one leaf tile; true when an any-hit search can stop.
    #[inline(always)]
    fn leaf_tile<const ANY: bool>(&self, ti: usize, tj: usize, cast: &Cast, best: &mut f64, found: &mut bool) -> bool {
        let g = &self.grid;
        let (i0, i1, j0, j1) = self.tile_nodes(&self.levels[0], ti, tj);
        let o = cast.ray.origin;
        // Parameter intervals of each cell column and row, shared by the cells of the tile.
        let mut cols = [(0.0, 0.0); LEAF];
        let mut rows = [(0.0, 0.0); LEAF];
        for (c, span) in cols.iter_mut().enumerate().take(j1 - j0) {
            *span = axis(self.x(j0 + c), self.x(j0 + c + 1), o.x, cast.inv[0]);
        }
        for (r, span) in rows.iter_mut().enumerate().take(i1 - i0) {
            *span = axis(self.y(i0 + r), self.y(i0 + r + 1), o.y, cast.inv[1]);
        }
        for (r, &(ny, fy)) in rows.iter().enumerate().take(i1 - i0) {
            let i = i0 + r;
            for (c, &(nx, fx)) in cols.iter().enumerate().take(j1 - j0) {
                let enter_xy = 0.0f64.max(nx).max(ny);
                if enter_xy > best.min(fx).min(fy) {
                    continue; // both triangles span the cell's whole footprint
                }
                let j = j0 + c;
                let row = i * g.nx + j;
                let (za, zb, zc, zd) = (g.z[row], g.z[row + 1], g.z[row + g.nx + 1], g.z[row + g.nx]);
                // The cell's box first: it holds both triangle boxes.
                let (cell_lo, cell_hi) = (za.min(zb).min(zc).min(zd), za.max(zb).max(zc).max(zd));
                let (nz, fz) = axis(cell_lo, cell_hi, o.z, cast.inv[2]);
                if enter_xy.max(nz) > best.min(fx).min(fy).min(fz) {
                    continue;
                }
                let (xa, xb) = (self.x(j), self.x(j + 1));
                let (ya, yc) = (self.y(i), self.y(i + 1));
                let a = Vector::new(xa, ya, za);
                let c3 = Vector::new(xb, yc, zc);
                // Corners in the mesh's order: [a, b, c], then [a, c, d].
                let halves = [(za, zb, zc, a, Vector::new(xb, ya, zb), c3), (za, zc, zd, a, c3, Vector::new(xa, yc, zd))];
                for (h0, h1, h2, p0, p1, p2) in halves {
                    if h0.is_nan() || h1.is_nan() || h2.is_nan() {
                        continue;
                    }
                    let (nz, fz) = axis(h0.min(h1).min(h2), h0.max(h1).max(h2), o.z, cast.inv[2]);
                    if enter_xy.max(nz) > best.min(fx).min(fy).min(fz) {
                        continue;
                    }
                    if let Some((inter, _)) = local_ray_intersection_with_triangle(p0, p1, p2, &cast.ray) {
                        if inter.time_of_impact <= *best {
                            *best = inter.time_of_impact;
                            *found = true;
                            if ANY {
                                return true;
                            }
                        }
                    }
                }
            }
        }
        false
    }

    /// The surface point closest to `point`: best-first over the tiles by box distance, then
    /// parry's projection onto each triangle of the nearest cells.
    pub fn closest_point(&self, point: Point) -> Point {
        let q = v(point);
        let top = self.levels.len() - 1;
        let mut heap = BinaryHeap::new();
        let l = &self.levels[top];
        for ti in 0..l.rows {
            for tj in 0..l.cols {
                if let Some(d2) = self.tile_distance(top, ti, tj, q) {
                    heap.push(Near(d2, top as u8, ti as u32, tj as u32));
                }
            }
        }
        let mut best = f64::INFINITY;
        let mut best_point = q;
        while let Some(Near(d2, lv, ti, tj)) = heap.pop() {
            if d2 >= best {
                break;
            }
            let (lv, ti, tj) = (lv as usize, ti as usize, tj as usize);
            if lv == 0 {
                let (i0, i1, j0, j1) = self.tile_nodes(&self.levels[0], ti, tj);
                for i in i0..i1 {
                    for j in j0..j1 {
                        let [t0, t1] = self.grid.cell_triangles(i, j);
                        for [a, b, c] in [t0, t1].into_iter().flatten() {
                            let lo = a.min(b).min(c);
                            let hi = a.max(b).max(c);
                            if (q.max(lo).min(hi) - q).length_squared() >= best {
                                continue;
                            }
                            let proj = Triangle::new(a, b, c).project_local_point(q, false).point;
                            let d = (proj - q).length_squared();
                            if d < best {
                                best = d;
                                best_point = proj;
                            }
                        }
                    }
                }
                continue;
            }
            let child = &self.levels[lv - 1];
            for ci in 2 * ti..(2 * ti + 2).min(child.rows) {
                for cj in 2 * tj..(2 * tj + 2).min(child.cols) {
                    if let Some(d2) = self.tile_distance(lv - 1, ci, cj, q) {
                        if d2 < best {
                            heap.push(Near(d2, (lv - 1) as u8, ci as u32, cj as u32));
                        }
                    }
                }
            }
        }
        p(best_point)
    }

    fn tile_distance(&self, lv: usize, ti: usize, tj: usize, q: Vector) -> Option<f64> {
        let level = &self.levels[lv];
        let [zlo, zhi] = level.z[ti * level.cols + tj];
        if zlo > zhi {
            return None;
        }
        let (i0, i1, j0, j1) = self.tile_nodes(level, ti, tj);
        let lo = Vector::new(self.x(j0), self.y(i0), zlo);
        let hi = Vector::new(self.x(j1), self.y(i1), zhi);
        Some((q.max(lo).min(hi) - q).length_squared())
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

impl Grid {
    /// The position of node `k` (row-major), as the mesh path computes it.
    #[inline(always)]
    pub fn node_point(&self, k: usize) -> Point {
        let (i, j) = (k / self.nx, k % self.nx);
        [self.x0 + j as f64 * self.dx, self.y0 + i as f64 * self.dy, self.z[k]]
    }

    /// Nodes `[a, b, c, d] = [(i, j), (i, j+1), (i+1, j+1), (i+1, j)]` of cell `(i, j)`.
    #[inline(always)]
    pub fn cell_nodes(&self, i: usize, j: usize) -> [usize; 4] {
        let a = i * self.nx + j;
        [a, a + 1, a + self.nx + 1, a + self.nx]
    }

    /// The corners of the two triangles of cell `(i, j)`, `[a, b, c]` and `[a, c, d]`, or `None`
    /// for a triangle with a nodata corner.
    #[inline(always)]
    pub fn cell_triangles(&self, i: usize, j: usize) -> [Option<[Vector; 3]>; 2] {
        let [a, b, c, d] = self.cell_nodes(i, j).map(|k| v(self.node_point(k)));
        let ok = |q: Vector| !q.z.is_nan();
        [(ok(a) && ok(b) && ok(c)).then_some([a, b, c]), (ok(a) && ok(c) && ok(d)).then_some([a, c, d])]
    }
}

/// Highest node heights of the segment walk's tiles.
#[derive(Debug, Clone)]
struct TopLevel {
    shift: u32,
    cols: usize,
    /// Highest non-NaN node height per tile, row-major; `-inf` when there is none.
    zmax: Vec<f64>,
}

/// Tiles of 2 x 2 cells from the heights, then 2 x 2 merges until one tile is left.
fn build_tops(g: &Grid) -> Vec<TopLevel> {
    let (cells_y, cells_x) = (g.ny - 1, g.nx - 1);
    let (rows, cols) = (cells_y.div_ceil(2), cells_x.div_ceil(2));
    let mut zmax = vec![f64::NEG_INFINITY; rows * cols];
    for ti in 0..rows {
        for i in 2 * ti..=(2 * ti + 2).min(cells_y) {
            let heights = &g.z[i * g.nx..(i + 1) * g.nx];
            for tj in 0..cols {
                let slot = &mut zmax[ti * cols + tj];
                for &h in &heights[2 * tj..=(2 * tj + 2).min(cells_x)] {
                    *slot = slot.max(h); // max ignores NaN
                }
            }
        }
    }
    let mut levels = vec![TopLevel { shift: 1, cols, zmax }];
    let mut rows = rows;
    while let Some(last) = levels.last().filter(|l| rows > 1 || l.cols > 1) {
        let (r2, c2) = (rows.div_ceil(2), last.cols.div_ceil(2));
        let mut zmax = vec![f64::NEG_INFINITY; r2 * c2];
        for ti in 0..r2 {
            for tj in 0..c2 {
                let slot = &mut zmax[ti * c2 + tj];
                for ci in 2 * ti..(2 * ti + 2).min(rows) {
                    for cj in 2 * tj..(2 * tj + 2).min(last.cols) {
                        *slot = slot.max(last.zmax[ci * last.cols + cj]);
                    }
                }
            }
        }
        levels.push(TopLevel { shift: last.shift + 1, cols: c2, zmax });
        rows = r2;
    }
    levels
}

/// The tile pyramid: leaf tiles of `2^FIRST_SHIFT` cells, then 2 x 2 merges up to one tile.
fn build_levels(g: &Grid) -> Vec<Level> {
    let (cells_y, cells_x) = (g.ny - 1, g.nx - 1);
    let rows = cells_y.div_ceil(LEAF);
    let cols = cells_x.div_ceil(LEAF);
    let mut z = vec![[f64::INFINITY, f64::NEG_INFINITY]; rows * cols];
    for ti in 0..rows {
        let (i0, i1) = (ti * LEAF, ((ti + 1) * LEAF).min(cells_y));
        for tj in 0..cols {
            let (j0, j1) = (tj * LEAF, ((tj + 1) * LEAF).min(cells_x));
            let slot = &mut z[ti * cols + tj];
            for i in i0..=i1 {
                for &h in &g.z[i * g.nx + j0..=i * g.nx + j1] {
                    if !h.is_nan() {
                        slot[0] = slot[0].min(h);
                        slot[1] = slot[1].max(h);
                    }
                }
            }
        }
    }
    let mut levels = vec![Level { shift: FIRST_SHIFT, rows, cols, z }];
    while let Some(last) = levels.last().filter(|l| l.rows > 1 || l.cols > 1) {
        let (rows, cols) = (last.rows.div_ceil(2), last.cols.div_ceil(2));
        let mut z = vec![[f64::INFINITY, f64::NEG_INFINITY]; rows * cols];
        for ti in 0..rows {
            for tj in 0..cols {
                let slot = &mut z[ti * cols + tj];
                for ci in 2 * ti..(2 * ti + 2).min(last.rows) {
                    for cj in 2 * tj..(2 * tj + 2).min(last.cols) {
                        let [lo, hi] = last.z[ci * last.cols + cj];
                        slot[0] = slot[0].min(lo);
                        slot[1] = slot[1].max(hi);
                    }
                }
            }
        }
        levels.push(Level { shift: last.shift + 1, rows, cols, z });
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Surface;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A grid surface and the mesh path of the same grid.
    fn both(z: Vec<f64>, ny: usize, nx: usize, dx: f64, dy: f64, x0: f64, y0: f64) -> (Surface, Surface) {
        let grid = Surface::from_grid(z, ny, nx, dx, dy, x0, y0).unwrap();
        let mesh_of_grid = grid.triangle_mesh().unwrap();
        let faces = mesh_of_grid.trimesh().indices().to_vec();
        let mesh = Surface::new(grid.vertices().collect(), faces).unwrap();
        (grid, mesh)
    }

    /// Heights of four kinds: smooth hills, rough noise, terraces (flat plateaus, cliffs), spikes.
    fn heights(rng: &mut ChaCha8Rng, ny: usize, nx: usize, kind: usize, holes: bool) -> Vec<f64> {
        let phase: [f64; 4] = [0, 1, 2, 3].map(|_| rng.random::<f64>() * 6.0);
        (0..ny * nx)
            .map(|k| {
                let (i, j) = ((k / nx) as f64, (k % nx) as f64);
                let smooth = 3.0 * (0.4 * i + phase[0]).sin() + 2.0 * (0.3 * j + phase[1]).cos();
                let h = match kind {
                    0 => smooth,
                    1 => smooth + 4.0 * rng.random::<f64>(),
                    2 => (smooth * 0.8).round() * 2.0,
                    _ => {
                        if rng.random::<f64>() < 0.1 {
                            8.0
                        } else {
                            0.0
                        }
                    }
                };
                if holes && rng.random::<f64>() < 0.08 {
                    f64::NAN
                } else {
                    h
                }
            })
            .collect()
    }

    /// End points that stress the boundaries: grid nodes (exactly), points on grid lines and
    /// diagonals, points above nodes, random points, some outside the grid.
    fn point(rng: &mut ChaCha8Rng, g: &Grid, zmin: f64, zmax: f64) -> Point {
        let i = rng.random_range(0..g.ny);
        let j = rng.random_range(0..g.nx);
        let node = g.node_point(i * g.nx + j);
        let lift = zmin + (zmax - zmin + 6.0) * rng.random::<f64>() - 1.0;
        let u = rng.random::<f64>();
        match rng.random_range(0..7) {
            0 if !node[2].is_nan() => node,
            1 => [node[0], node[1], lift],
            2 => [node[0], node[1] + u * g.dy, lift],
            3 => [node[0] + u * g.dx, node[1], lift],
            4 => [node[0] + u * g.dx, node[1] + u * g.dy, lift],
            5 => [node[0] + (u - 0.5) * 6.0 * g.dx, node[1] - 3.0 * g.dy, lift],
            _ => [
                g.x0 + (rng.random::<f64>() * 1.2 - 0.1) * (g.nx - 1) as f64 * g.dx,
                g.y0 + (rng.random::<f64>() * 1.2 - 0.1) * (g.ny - 1) as f64 * g.dy,
                lift,
            ],
        }
    }

    #[test]
    fn segments_agree_with_the_mesh_path_exactly() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut blocked = 0;
        let mut total = 0;
        for case in 0..48 {
            let (ny, nx) = if case % 8 == 7 {
                (rng.random_range(30..90), rng.random_range(30..90))
            } else {
                (rng.random_range(2..24), rng.random_range(2..24))
            };
            let (dx, dy) = if case % 3 == 0 { (1.0, 1.0) } else { (0.1 + rng.random::<f64>(), 0.1 + rng.random::<f64>()) };
            let (x0, y0) = if case % 4 == 0 { (0.0, 0.0) } else { (rng.random::<f64>() * 1e3 - 500.0, 12.25) };
            let z = heights(&mut rng, ny, nx, case % 4, case % 5 == 1);
            if z.chunks(nx).zip(z.chunks(nx).skip(1)).all(|(a, b)| a.iter().chain(b).any(|h| h.is_nan())) {
                continue; // every cell touches nodata: no triangle at all
            }
            let Ok(grid) = Surface::from_grid(z.clone(), ny, nx, dx, dy, x0, y0) else {
                continue;
            };
            let (grid, mesh) = (grid, both(z, ny, nx, dx, dy, x0, y0).1);
            let g = grid.grid().unwrap().clone();
            let (lo, hi) = grid.bounds();
            for _ in 0..400 {
                let a = point(&mut rng, &g, lo[2], hi[2]);
                let b = point(&mut rng, &g, lo[2], hi[2]);
                let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                for t_max in [SIGHT_FRACTION, 1.0] {
                    let expect = mesh.ray_hits(a, d, t_max);
                    assert_eq!(grid.ray_hits(a, d, t_max), expect, "case {case}: {a:?} -> {b:?} up to {t_max}");
                    let field = grid.heightfield().unwrap();
                    assert_eq!(field.ray_hits_quadtree(a, d, t_max), expect, "quadtree, case {case}");
                    blocked += expect as usize;
                    total += 1;
                }
                assert_eq!(grid.line_of_sight(a, b), mesh.line_of_sight(a, b));
                // A ray starting on a triangle's plane outside the triangle gets a spurious hit at
                // t = 0 from parry, which the mesh path keeps or prunes depending on its
                // traversal order; first hits are compared only from points off the grid nodes.
                if (0..g.ny * g.nx).any(|k| g.node_point(k) == a) {
                    continue;
                }
                let (fg, fm) = (grid.first_hit(a, d, 1.0), mesh.first_hit(a, d, 1.0));
                match (fg, fm) {
                    (Some(x), Some(y)) => assert!((x - y).abs() <= 1e-12, "case {case} {a:?} {b:?}: {x} vs {y}"),
                    _ => assert_eq!(fg, fm, "case {case} {a:?} {b:?}"),
                }
            }
        }
        // Both outcomes are well represented, so agreement means something.
        assert!(blocked > total / 5 && blocked < 4 * total / 5, "{blocked} of {total}");
    }

    #[test]
    fn horizons_give_the_mesh_paths_sight_lines() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let (mut seen, mut total) = (0, 0);
        for case in 0..40 {
            let (ny, nx) = if case % 4 == 3 {
                (rng.random_range(30..80), rng.random_range(30..80))
            } else {
                (rng.random_range(2..24), rng.random_range(2..24))
            };
            let (dx, dy) = if case % 3 == 0 { (0.5, 0.5) } else { (0.2 + rng.random::<f64>(), 0.2 + rng.random::<f64>()) };
            let (x0, y0) = if case % 5 == 0 { (0.0, 0.0) } else { (rng.random::<f64>() * 1e3 - 500.0, -3.75) };
            let z = heights(&mut rng, ny, nx, case % 4, case % 6 == 1);
            let Ok(grid) = Surface::from_grid(z.clone(), ny, nx, dx, dy, x0, y0) else {
                continue;
            };
            let mesh = both(z, ny, nx, dx, dy, x0, y0).1;
            let field = grid.heightfield().unwrap();
            let g = field.grid().clone();
            let (lo, hi) = grid.bounds();
            for _ in 0..12 {
                let uav = point(&mut rng, &g, lo[2], hi[2]);
                // Sometimes shorter than the farthest targets: those must fall back to the walk.
                let radius = rng.random::<f64>() * 1.5 * ((nx as f64 * dx).powi(2) + (ny as f64 * dy).powi(2)).sqrt();
                let horizon = field.horizon(uav, radius);
                for _ in 0..150 {
                    let q = point(&mut rng, &g, lo[2], hi[2]);
                    let expect = mesh.line_of_sight(uav, q);
                    assert_eq!(field.line_of_sight_from(&horizon, q), expect, "case {case}: {uav:?} -> {q:?}, radius {radius}");
                    seen += expect as usize;
                    total += 1;
                }
            }
        }
        assert!(seen > total / 5 && seen < 4 * total / 5, "{seen} of {total}");
    }

    #[test]
    fn skylines_give_the_mesh_paths_sight_lines_to_nodes() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let (mut seen, mut total, mut steep) = (0, 0, 0);
        for case in 0..40 {
            let (ny, nx) = if case % 4 == 3 {
                (rng.random_range(30..80), rng.random_range(30..80))
            } else {
                (rng.random_range(2..24), rng.random_range(2..24))
            };
            let (dx, dy) = if case % 3 == 0 { (0.5, 0.5) } else { (0.2 + rng.random::<f64>(), 0.2 + rng.random::<f64>()) };
            let (x0, y0) = if case % 5 == 0 { (0.0, 0.0) } else { (rng.random::<f64>() * 1e3 - 500.0, -3.75) };
            let z = heights(&mut rng, ny, nx, case % 4, case % 6 == 1);
            let Ok(grid) = Surface::from_grid(z.clone(), ny, nx, dx, dy, x0, y0) else {
                continue;
            };
            let mesh = both(z, ny, nx, dx, dy, x0, y0).1;
            let field = grid.heightfield().unwrap();
            let g = field.grid().clone();
            let (lo, hi) = grid.bounds();
            let nodes: Vec<usize> = (0..ny * nx).filter(|&k| g.vertex_of_node[k] != u32::MAX).collect();
            let stencil = Stencil::of_grid(&g);
            for _ in 0..12 {
                let uav = point(&mut rng, &g, lo[2], hi[2]);
                let radius = rng.random::<f64>() * 1.5 * ((nx as f64 * dx).powi(2) + (ny as f64 * dy).powi(2)).sqrt();
                let horizon = field.horizon(uav, radius);
                for _ in 0..150 {
                    let k = nodes[rng.random_range(0..nodes.len())];
                    let q = g.node_point(k);
                    let sky = stencil.skyline(&g, k / nx, k % nx);
                    let expect = mesh.line_of_sight(uav, q);
                    assert_eq!(field.line_of_sight_to_node(&horizon, q, &sky), expect, "case {case}: {uav:?} -> {q:?}, radius {radius}");
                    // How often the skyline settles the last cells (the line arrives more steeply).
                    let (ex, ey) = (uav[0] - q[0], uav[1] - q[1]);
                    let r = (ex * ex + ey * ey).sqrt();
                    if r > 0.0 && (uav[2] - q[2]) / r > sky.slope(crate::skyline::sector_of(pseudo_angle(ex, ey))) {
                        steep += 1;
                    }
                    seen += expect as usize;
                    total += 1;
                }
            }
        }
        assert!(seen > total / 5 && seen < 4 * total / 5, "{seen} of {total}");
        assert!(steep > total / 8, "the skylines decided too rarely to be tested: {steep} of {total}");
    }

    #[test]
    fn vertical_and_closest_point_queries_agree_with_the_mesh_path() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for case in 0..12 {
            let (ny, nx) = (rng.random_range(2..30), rng.random_range(2..30));
            let z = heights(&mut rng, ny, nx, case % 4, case % 3 == 2);
            let Ok(grid) = Surface::from_grid(z.clone(), ny, nx, 0.5, 0.7, 3.0, -2.0) else {
                continue;
            };
            let mesh = both(z, ny, nx, 0.5, 0.7, 3.0, -2.0).1;
            assert_eq!(grid.bounds(), mesh.bounds());
            assert_eq!(grid.area(), mesh.area());
            let g = grid.grid().unwrap().clone();
            let (lo, hi) = grid.bounds();
            for _ in 0..300 {
                let q = point(&mut rng, &g, lo[2], hi[2]);
                let (hg, hm) = (grid.ground_height(q[0], q[1]), mesh.ground_height(q[0], q[1]));
                match (hg, hm) {
                    (Some(x), Some(y)) => assert!((x - y).abs() <= 1e-12, "{q:?}: {x} vs {y}"),
                    _ => assert_eq!(hg, hm, "{q:?}"),
                }
                let (cg, cm) = (grid.clearance(q), mesh.clearance(q));
                assert!(cg == cm || (cg - cm).abs() <= 1e-12, "{q:?}: {cg} vs {cm}");
                let (pg, pm) = (grid.closest_point(q), mesh.closest_point(q));
                let dist = |r: Point| ((r[0] - q[0]).powi(2) + (r[1] - q[1]).powi(2) + (r[2] - q[2]).powi(2)).sqrt();
                assert!((dist(pg) - dist(pm)).abs() <= 1e-9, "{q:?}: {pg:?} vs {pm:?}");
            }
        }
    }

    #[test]
    fn mesh_tables_match_the_mesh_path() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let z = heights(&mut rng, 9, 11, 1, true);
        let (grid, mesh) = both(z, 9, 11, 0.5, 0.25, 1.0, 2.0);
        assert_eq!(grid.n_vertices(), mesh.n_vertices());
        assert_eq!(grid.n_triangles(), mesh.n_triangles());
        assert_eq!(grid.faces(), mesh.faces());
        assert_eq!(grid.areas(), mesh.areas());
        assert!(grid.vertices().eq(mesh.vertices()));
        for f in 0..grid.n_triangles() {
            assert_eq!(grid.triangle(f), mesh.triangle(f));
        }
        let field = grid.heightfield().unwrap();
        let mut w = vec![0.0; mesh.n_vertices()];
        for (t, &a) in mesh.faces().iter().zip(mesh.areas()) {
            for &k in t {
                w[k as usize] += a / 3.0;
            }
        }
        assert_eq!(field.vertex_weights(), w);
    }

    #[test]
    fn a_ridge_hides_what_is_behind_it_and_grazing_it_from_above_does_not() {
        // A 1 m ridge along column 5 of a flat 11 x 11 grid.
        let z: Vec<f64> = (0..121).map(|k| if k % 11 == 5 { 1.0 } else { 0.0 }).collect();
        let hf = HeightField::new(z, 11, 11, 1.0, 1.0, 0.0, 0.0).unwrap();
        assert!(!hf.line_of_sight([2.0, 5.0, 0.5], [8.0, 5.0, 0.0]));
        assert!(hf.line_of_sight([2.0, 5.0, 3.0], [8.0, 5.0, 0.0]));
        // Along the ridge line, exactly over its nodes and above them: nothing is crossed.
        assert!(hf.line_of_sight([5.0, 0.0, 1.5], [5.0, 10.0, 1.0]));
        // Touching the ridge's top edge counts as crossing it (as on the mesh path); a hair
        // above it does not.
        assert!(hf.ray_hits([4.0, 5.0, 1.0], [2.0, 0.0, 0.0], 1.0));
        assert!(!hf.ray_hits([4.0, 5.0, 1.0 + 1e-9], [2.0, 0.0, 0.0], 1.0));
        assert!(!hf.line_of_sight([4.0, 5.0, 0.9], [6.0, 5.0, 0.9]));
    }

    #[test]
    fn memory_scales_with_nodes() {
        let hf = HeightField::new(vec![0.0; 201 * 201], 201, 201, 0.5, 0.5, 0.0, 0.0).unwrap();
        let per_node = hf.memory_bytes() as f64 / (201.0 * 201.0);
        assert!(per_node < 18.0, "{per_node} bytes per node");
        assert!(HeightField::new(vec![0.0; 4], 2, 2, 1.0, f64::NAN, 0.0, 0.0).is_err());
        assert!(matches!(HeightField::new(vec![f64::NAN; 4], 2, 2, 1.0, 1.0, 0.0, 0.0), Err(Error::Mesh(_))));
        assert!(matches!(HeightField::new(vec![f64::INFINITY; 4], 2, 2, 1.0, 1.0, 0.0, 0.0), Err(Error::InvalidInput(_))));
    }
}
