//! A UAV's horizon: for each direction sector and distance bin around it, an upper bound on how
//! steeply the grid rises as seen from the UAV. Built once per UAV and evaluation, it clears
//! most of every sight line with a binary search, and with the target node's
//! [`Skyline`] usually all of it; what neither clears goes to the walk.

use super::slab::max;
use super::HeightField;
use crate::error::{try_filled, Result};
use crate::geometry::{Point, SIGHT_FRACTION};
use crate::grid::pseudo_angle;
use crate::skyline::{sector_of, Skyline, REACH};

/// The horizon is built from tiles of `2^HORIZON_SHIFT` cells a side.
const HORIZON_SHIFT: u32 = 1;

/// What a UAV sees around it: for each angular sector and each distance, an upper bound on the
/// elevation slope (rise over horizontal run, from the UAV) of every grid cell of that sector up
/// to that distance. Built once per UAV and evaluation; it lets most sight lines skip the walk
/// but for their last few cells (see [`HeightField::line_of_sight_from`]), and, with the
/// target's [`Skyline`], skip it altogether (see [`HeightField::line_of_sight_to_node`]).
#[derive(Debug, Clone)]
pub(crate) struct Horizon {
    uav: Point,
    pub(super) sectors: usize,
    pub(super) bins: usize,
    /// Width of a distance bin, metres, and its inverse.
    bin: f64,
    inv_bin: f64,
    /// Sectors per unit of pseudo-angle.
    quarter: f64,
    /// Running maximum along distance of the slope bounds, `slope[bin * sectors + sector]`, each a
    /// signed square (`s |s|`, which orders like `s`) rounded up to `f32`.
    pub(super) slope: Vec<f32>,
    /// How far every cell box was widened, metres.
    delta: f64,
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
        f64::from(self.slope[bin * self.stride])
    }
}

/// `x` as an `f32` no smaller than it.
#[inline(always)]
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    // Rounded down (never for NaN, where the comparison fails): the next value up.
    if f64::from(f) < x {
        f.next_up()
    } else {
        f
    }
}

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
    #[expect(clippy::too_many_lines, reason = "one pass over the cells near the UAV; its steps share a dozen locals")]
    pub(crate) fn horizon(&self, uav: Point, radius: f64, max_values: usize) -> Result<Horizon> {
        let g = &self.grid;
        let w = g.dx.min(g.dy);
        let radius = if radius.is_finite() { radius.max(0.0) } else { 0.0 };
        // No cell is farther than the grid's farthest corner (plus a cell for rounding).
        let (lo, hi) = (self.bounds.0, self.bounds.1);
        let far = |a: f64, l: f64, h: f64| (a - l).abs().max((h - a).abs());
        let corner = far(uav[0], lo[0], hi[0]).hypot(far(uav[1], lo[1], hi[1])) + 2.0 * w;
        let radius = if radius > corner { corner } else { radius };
        let bins = ((radius / w).ceil() + 2.0).min(4096.0) as usize;
        // Sectors about a bin wide at the far edge (at least 64, a multiple of 4).
        let sectors = ((std::f64::consts::PI * radius / w).ceil().clamp(64.0, 4096.0) as usize).next_multiple_of(4);
        let bins = bins.min((max_values / sectors).max(1));
        let (px, py, pz) = (uav[0], uav[1], uav[2]);
        let delta = 1e-9 * (px.abs().max(py.abs()) + self.scales.xy + radius);
        let delta_z = 1e-9 * (pz.abs() + self.scales.z + 1e-300);
        let reach = bins as f64 * w; // every cell nearer than this is entered
        let reach2 = reach * reach;
        let inv_w = 1.0 / w;
        // Bounds by bin then sector while cells are entered; a running maximum along distance,
        // stored sector by sector for the queries, at the end.
        let mut by_bin = try_filled(f32::NEG_INFINITY, sectors * bins, "a UAV's horizon")?;
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
        Ok(Horizon { uav, sectors, bins, bin: w, inv_bin: 1.0 / w, quarter, slope, delta })
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
    pub(crate) fn line_of_sight_to_node(&self, horizon: &Horizon, target: Point, skyline: &Skyline) -> bool {
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
}
