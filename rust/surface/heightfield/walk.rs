//! The segment walk, the any-hit test behind every line of sight on the grid path: bisect the
//! segment while a piece of it passes above the highest node under its footprint (a pyramid of
//! highest heights, [`TopLevel`]), then give the cells of what is left the mesh path's own leaf
//! test.

use parry3d_f64::math::Vector;
use parry3d_f64::query::Ray;

use super::slab::{axis, max, min, Cast};
use super::HeightField;
use crate::geometry::{triangle_hit, v, Point};
use crate::surface::grid::Grid;

/// Pieces of segment whose footprint box spans at most this many cells a side are tested cell
/// by cell.
const BOX: usize = 8;

/// The widest margin (cells) the bisection works with. The margins are `1e-9` of the
/// coordinates, so they pass a cell only for coordinates over `5e8` cells from the origin (or
/// a UAV that far from the grid); there a piece's box never shrinks below [`BOX`] cells, and
/// bisecting would only multiply the work (it did: a grid at `1e10` m with 1 m cells spun for
/// minutes per sight line). Such a segment takes the tile quadtree's any-hit test instead,
/// which needs no margin and gives the same answer.
const MAX_MARGIN: f64 = 1.0;

/// `x as usize` for `x` already known to lie in `[0, usize::MAX)`, without the saturation checks.
#[inline(always)]
#[allow(unsafe_code, reason = "the one unchecked cast of the walk's hot loop; its callers rule out NaN and clamp")]
fn cell_index(x: f64) -> usize {
    debug_assert!((0.0..(usize::MAX as f64)).contains(&x));
    // SAFETY: callers clamp `x` into `[0, cells)` after ruling out NaN, so it is finite and in range.
    unsafe { x.to_int_unchecked::<usize>() }
}

impl HeightField {
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
            if max(enter_xy, nz) <= min(exit_xy, fz)
                && triangle_hit(a, Vector::new(xb, ya, zb), c, &cast.ray).is_some_and(|toi| toi <= t_max)
            {
                return true;
            }
        }
        if !zd.is_nan() {
            let (nz, fz) = axis(min(lo_ac, zd), max(hi_ac, zd), oz, cast.inv[2]);
            if max(enter_xy, nz) <= min(exit_xy, fz)
                && triangle_hit(a, c, Vector::new(xa, yc, zd), &cast.ray).is_some_and(|toi| toi <= t_max)
            {
                return true;
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
        Self::spans(&mut cols[..=j1 - j0], |c| self.x(j0 + c), o.x, cast.inv[0]);
        Self::spans(&mut rows[..=i1 - i0], |r| self.y(i0 + r), o.y, cast.inv[1]);
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
                // The cell box: NaN corners ignored (their triangle is left out below). `min` and
                // `max` give their second value when the comparison fails, so a NaN first one
                // leaves the box as it is: one comparison each, where `f64::min` takes two.
                let (lo, hi) = (min(zd, min(zb, lo_ac)), max(zd, max(zb, hi_ac)));
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
    fn spans(out: &mut [(f64, f64)], at: impl Fn(usize) -> f64, origin: f64, inv: f64) {
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
    pub(super) fn walk_hits(&self, origin: Point, dir: Point, t_max: f64) -> bool {
        self.walk_hits_from(origin, dir, 0.0, t_max, t_max)
    }

    /// [`HeightField::walk_hits`] for the triangles the ray can reach at parameters in
    /// `[t_from, t_to]` (the leaf test is the mesh path's, with the limit `t_max >= t_to`).
    pub(super) fn walk_hits_from(&self, origin: Point, dir: Point, t_from: f64, t_to: f64, t_max: f64) -> bool {
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
        if delta > MAX_MARGIN || delta.is_nan() {
            return self.cast::<true>(origin, dir, t_max).is_some(); // also for NaN
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
                // Too deep to split further (a segment of some 2^16 boxes, from a UAV very far
                // from the grid): the quadtree's any-hit test of the whole segment, the same
                // answer in work bounded by the tiles it crosses, where testing the cells of
                // this box could take the whole grid for each of 2^16 pieces.
                return self.cast::<true>(origin, dir, t_max).is_some();
            }
            // Go on with the half nearer the end (the target, on the ground): it decides most
            // often.
            stack[top] = (ta, tm);
            top += 1;
            piece = Some((tm, tb));
        }
        false
    }
}

/// Highest node heights of the segment walk's tiles.
#[derive(Debug, Clone)]
pub(super) struct TopLevel {
    pub(super) shift: u32,
    pub(super) cols: usize,
    /// Highest non-NaN node height per tile, row-major; `-inf` when there is none.
    pub(super) zmax: Vec<f64>,
}

/// Tiles of 2 x 2 cells from the heights, then 2 x 2 merges until one tile is left.
pub(super) fn build_tops(g: &Grid) -> Vec<TopLevel> {
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
