//! The tile quadtree: a pyramid of tiles holding the lowest and highest node heights of their
//! cells, the grid path's stand-in for parry's BVH. It answers first hits (best-first, nearest
//! tile first) and closest points (best-first by box distance), and gives a second, independent
//! any-hit answer that the tests hold the walk to.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use parry3d_f64::math::Vector;
use parry3d_f64::query::{PointQuery, Ray};
use parry3d_f64::shape::Triangle;

use super::slab::{axis, Cast};
use super::HeightField;
use crate::geometry::{p, triangle_hit, v, Point};
use crate::surface::grid::Grid;

/// The smallest stored tiles are `2^FIRST_SHIFT` cells on a side; below them, cell boxes are
/// computed from the four corner heights, which the triangle test reads anyway.
const FIRST_SHIFT: u32 = 2;

/// Cells per side of a leaf tile.
const LEAF: usize = 1 << FIRST_SHIFT;

/// One level of the tile pyramid.
#[derive(Debug, Clone)]
pub(super) struct Level {
    /// Tiles are `2^shift` cells on a side.
    shift: u32,
    rows: usize,
    cols: usize,
    /// `[lowest, highest]` non-NaN node height per tile, row-major; `[inf, -inf]` when empty.
    pub(super) z: Vec<[f64; 2]>,
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
    /// The any-hit answer of the tile quadtree (the first-hit machinery); the same answer as
    /// [`HeightField::ray_hits`], kept as a second, independent way to it for the tests.
    #[cfg(test)]
    pub(super) fn ray_hits_quadtree(&self, origin: Point, dir: Point, t_max: f64) -> bool {
        self.cast::<true>(origin, dir, t_max).is_some()
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
    pub(super) fn cast<const ANY: bool>(&self, origin: Point, dir: Point, t_max: f64) -> Option<f64> {
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
                if self.leaf_tile::<ANY>(ti, tj, (ci0, ci1, cj0, cj1), &cast, &mut best, &mut found) && ANY {
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
    fn leaf_tile<const ANY: bool>(
        &self,
        ti: usize,
        tj: usize,
        cells: (usize, usize, usize, usize),
        cast: &Cast,
        best: &mut f64,
        found: &mut bool,
    ) -> bool {
        let g = &self.grid;
        let (i0, i1, j0, j1) = self.tile_nodes(&self.levels[0], ti, tj);
        // Only the cells the ray's footprint can touch (`cells`, rows then columns, from
        // `cell_span`, which is wider than any rounding: a cell beyond them fails the slab test
        // below anyway): a short or vertical ray's few of the tile's.
        let (ci0, ci1, cj0, cj1) = cells;
        let (i0, i1, j0, j1) = (i0.max(ci0), i1.min(ci1 + 1), j0.max(cj0), j1.min(cj1 + 1));
        if i0 >= i1 || j0 >= j1 {
            return false;
        }
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
                    if let Some(toi) = triangle_hit(p0, p1, p2, &cast.ray) {
                        if toi <= *best {
                            *best = toi;
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
}

/// The tile pyramid: leaf tiles of `2^FIRST_SHIFT` cells, then 2 x 2 merges up to one tile.
pub(super) fn build_levels(g: &Grid) -> Vec<Level> {
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
