//! The grid path's horizons: a UAV's [`Horizon`] built from the 2 x 2-cell tiles of the grid,
//! and the sight lines it clears, with the target node's [`Skyline`] usually all of them; what
//! neither clears goes to the walk.

use super::HeightField;
use crate::error::Result;
use crate::geometry::{Point, SIGHT_FRACTION};
use crate::surface::horizon::{Horizon, HorizonBuilder, Rest};
use crate::surface::skyline::{Skyline, REACH};

/// The horizon is built from tiles of `2^HORIZON_SHIFT` cells a side.
const HORIZON_SHIFT: u32 = 1;

/// Length, in cells, of the stretch where a sight line goes under the surface that
/// [`HeightField::hits_where_it_goes_under`] tests.
const CROSSING_CELLS: f64 = 1.0;

impl HeightField {
    /// The [`Horizon`] of a UAV at `uav`, for targets up to `radius` metres away horizontally,
    /// in at most `max_values` bounds (at least one bin of 64 sectors).
    ///
    /// Its size is bounded whatever the inputs: the radius stops at the grid's farthest corner
    /// (no cell lies beyond; any radius gives the same answers, only the work differs), the
    /// bins and sectors are counted in floating point and clamped before they become integers
    /// (at most 4096 each), and the bounds are allocated with `try_reserve`.
    ///
    /// # Errors
    /// [`Error::TooLarge`](crate::Error::TooLarge) when the system refuses the memory.
    pub(crate) fn horizon(&self, uav: Point, radius: f64, max_values: usize) -> Result<Horizon> {
        let g = &self.grid;
        let w = g.dx.min(g.dy);
        let (px, py) = (uav[0], uav[1]);
        let mut h = HorizonBuilder::new(uav, radius, max_values, w, self.bounds, self.scales.xy, self.scales.z)?;
        let reach = h.reach;
        if let Some((i0, i1, j0, j1)) = self.cells_of_box((px - reach, px + reach), (py - reach, py + reach)) {
            // Units of 2^s x 2^s cells (the pyramid's tiles), or single cells for s = 0.
            let s = HORIZON_SHIFT.min(self.tops.len() as u32);
            let (ui0, ui1, uj0, uj1) = (i0 >> s, i1 >> s, j0 >> s, j1 >> s);
            // Unit edges relative to the UAV, and the sectors of the unit corners of the current
            // pair of corner rows (shared by neighbouring units).
            let xs: Vec<f64> = (uj0..=uj1 + 1).map(|u| self.x((u << s).min(g.nx - 1)) - px).collect();
            let y_of = |u: usize| self.y((u << s).min(g.ny - 1)) - py;
            let corners = |h: &HorizonBuilder, y: f64, out: &mut Vec<usize>| {
                out.clear();
                out.extend(xs.iter().map(|&x| h.corner_sector(x, y)));
            };
            let (mut lower, mut upper) = (Vec::with_capacity(xs.len()), Vec::with_capacity(xs.len()));
            corners(&h, y_of(ui0), &mut lower);
            let mut unit_top = vec![0.0f64; xs.len()];
            for i in ui0..=ui1 {
                let (ylo, yhi) = (y_of(i), y_of(i + 1));
                corners(&h, yhi, &mut upper);
                let ny = ylo.max(-yhi).max(0.0);
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
                        h.put_box(top, (xs[c], xs[c + 1]), (ylo, yhi), [lower[c], lower[c + 1], upper[c], upper[c + 1]]);
                    }
                }
                std::mem::swap(&mut lower, &mut upper);
            }
        }
        Ok(h.finish())
    }

    /// How far a grid node's [`Skyline`] reaches around it, metres: [`REACH`] cells of the smaller
    /// grid spacing (a horizon's bin).
    pub(crate) fn skyline_reach(&self) -> f64 {
        REACH as f64 * self.grid.dx.min(self.grid.dy)
    }

    /// The cells `(i0, i1, j0, j1)` (rows and columns, inclusive) of the box `[x0, x1] x [y0,
    /// y1]` (metres), widened by a cell each way and clamped to the grid; `None` when it misses
    /// the grid (or a bound is NaN).
    fn cells_of_box(&self, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> Option<(usize, usize, usize, usize)> {
        let g = &self.grid;
        let (last_row, last_col) = ((g.ny - 2) as f64, (g.nx - 2) as f64);
        let i_lo = ((y0 - g.y0) / g.dy).floor() - 1.0;
        let i_hi = ((y1 - g.y0) / g.dy).floor() + 1.0;
        let j_lo = ((x0 - g.x0) / g.dx).floor() - 1.0;
        let j_hi = ((x1 - g.x0) / g.dx).floor() + 1.0;
        (i_hi >= 0.0 && i_lo <= last_row && j_hi >= 0.0 && j_lo <= last_col)
            .then(|| (i_lo.max(0.0) as usize, i_hi.min(last_row) as usize, j_lo.max(0.0) as usize, j_hi.min(last_col) as usize))
    }

    /// An upper bound on the heights of the grid's nodes within `[x0, x1] x [y0, y1]` (metres):
    /// the highest of the pyramid tiles that cover the box (widened by a cell), at the finest
    /// level where they are at most 64; `-inf` when no node lies there.
    pub(crate) fn highest_within(&self, x: (f64, f64), y: (f64, f64)) -> f64 {
        let Some((i0, i1, j0, j1)) = self.cells_of_box(x, y) else {
            // Off the grid, no node; with a NaN bound, nothing is known.
            return if [x.0, x.1, y.0, y.1].iter().any(|v| v.is_nan()) { f64::INFINITY } else { f64::NEG_INFINITY };
        };
        let Some(level) =
            self.tops.iter().find(|l| ((i1 >> l.shift) - (i0 >> l.shift) + 1) * ((j1 >> l.shift) - (j0 >> l.shift) + 1) <= 64)
        else {
            return f64::INFINITY; // a pyramid always ends in one tile; no bound otherwise
        };
        let s = level.shift;
        let mut top = f64::NEG_INFINITY;
        for ti in i0 >> s..=i1 >> s {
            for &z in &level.zmax[ti * level.cols + (j0 >> s)..=ti * level.cols + (j1 >> s)] {
                top = top.max(z);
            }
        }
        top
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
    pub(crate) fn line_of_sight_from(&self, horizon: &Horizon, target: Point) -> bool {
        let Some(t_from) = horizon.uncleared_from(target) else { return true };
        let p = horizon.uav;
        let d = [target[0] - p[0], target[1] - p[1], target[2] - p[2]];
        !self.walk_hits_from(p, d, t_from, SIGHT_FRACTION, SIGHT_FRACTION)
    }

    /// Whether the sight line from `uav` to `target` hits a triangle where it goes under the
    /// surface: when it starts above the surface and ends below it (at `SIGHT_FRACTION`), a
    /// bisection on the heights along it finds a stretch of [`CROSSING_CELLS`] cells where it
    /// crosses, and that stretch alone gets the exact test. The heights only choose where to
    /// look: `true` is a hit of the same leaf test within the same limit, so the whole line's
    /// answer; `false` says nothing.
    pub(super) fn hits_where_it_goes_under(&self, uav: Point, target: Point) -> bool {
        let d = [target[0] - uav[0], target[1] - uav[1], target[2] - uav[2]];
        let r = d[0].hypot(d[1]);
        if r == 0.0 {
            return false;
        }
        // Height of the line over the surface at parameter t (None off the grid or over nodata).
        let over = |t: f64| self.height_at(uav[0] + d[0] * t, uav[1] + d[1] * t).map(|h| uav[2] + d[2] * t - h);
        let (Some(start), Some(end)) = (over(0.0), over(SIGHT_FRACTION)) else { return false };
        if !(start > 0.0 && end < 0.0) {
            return false;
        }
        let step = CROSSING_CELLS / (r * self.scales.inv_cell);
        let (mut above, mut below) = (0.0, SIGHT_FRACTION);
        while below - above > step {
            let mid = 0.5 * (above + below);
            match over(mid) {
                Some(h) if h > 0.0 => above = mid,
                Some(_) => below = mid,
                None => return false,
            }
        }
        let pad = 0.5 * step;
        self.walk_hits_from(uav, d, (above - pad).max(0.0), (below + pad).min(SIGHT_FRACTION), SIGHT_FRACTION)
    }

    /// The surface's height at `(x, y)` from the two triangles of its cell (`None` off the
    /// grid or where a corner it needs is nodata).
    fn height_at(&self, x: f64, y: f64) -> Option<f64> {
        let g = &self.grid;
        let (u, w) = ((x - g.x0) * self.scales.inv_dx, (y - g.y0) * self.scales.inv_dy);
        if !(u >= 0.0 && w >= 0.0 && u <= (g.nx - 1) as f64 && w <= (g.ny - 1) as f64) {
            return None;
        }
        // Truncation is the floor here (both are at least 0); the last cell takes its far edge.
        let (j, i) = ((u as usize).min(g.nx - 2), (w as usize).min(g.ny - 2));
        let (fx, fy) = (u - j as f64, w - i as f64);
        let row = i * g.nx + j;
        let (za, zb, zc, zd) = (g.z[row], g.z[row + 1], g.z[row + g.nx + 1], g.z[row + g.nx]);
        let h = if fx >= fy { za + (zb - za) * fx + (zc - zb) * fy } else { za + (zc - zd) * fx + (zd - za) * fy };
        h.is_finite().then_some(h)
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
    /// (the line's and its neighbours, 0.06 radians or more each), and `z_P - z_T <= slope rho_P`,
    /// while the ray there is `line rho` above `z_T` (to `eps`): then
    /// `(line - slope) rho <= eps (2 + |slope|)`, which the test below rules out. Otherwise the
    /// ray point is farther than the cleared reach from the target, i.e. nearer the UAV than
    /// `r - reach + 2 eps`, where the horizon (as in [`HeightField::line_of_sight_from`]) or the
    /// walk of that stretch decides.
    ///
    /// [`REACH`]: crate::surface::skyline::REACH
    pub(crate) fn line_of_sight_to_node(&self, horizon: &Horizon, target: Point, skyline: &Skyline) -> bool {
        let (cleared, far, r) = match horizon.beside_skyline(target, skyline, self.skyline_reach(), self.scales.z) {
            Rest::Clear => return true,
            Rest::Unsettled => {
                // Most of these are blocked, and end below the surface around the target (98 % of
                // the blocked ones in the paper's missions): the stretch where such a line goes
                // under is tested first.
                if self.hits_where_it_goes_under(horizon.uav, target) {
                    return false;
                }
                return self.line_of_sight_from(horizon, target);
            }
            Rest::Stretch { cleared, far, r } => (cleared, far, r),
        };
        let t_from = if cleared > 0.0 { cleared / r } else { 0.0 };
        let t_to = (far / r).min(SIGHT_FRACTION);
        if t_from >= t_to {
            return true;
        }
        let p = horizon.uav;
        let d = [target[0] - p[0], target[1] - p[1], target[2] - p[2]];
        !self.walk_hits_from(p, d, t_from, t_to, SIGHT_FRACTION)
    }
}
