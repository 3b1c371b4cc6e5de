//! A UAV's horizon: for each direction sector and distance bin around it, an upper bound on how
//! steeply the surface rises as seen from the UAV.
//!
//! A horizon is built once per UAV and evaluation from boxes that hold the surface near the UAV
//! (the elevation grid's 2 x 2-cell tiles on the grid path, the small nodes of parry's BVH on
//! the mesh path). A sight line whose slope stays above the bounds of its sector is clear of
//! every box nearer than the first bin that stops it, so only the rest of the line needs the
//! exact test: the walk of [`crate::surface::heightfield`] or the BVH of [`crate::surface::mesh`].
//!
//! Exactness: a triangle the exact test counts has a point within a few ulps of the ray (at
//! some parameter `t`). If that point is nearer the UAV than the cleared stretch, the box that
//! holds it was entered with a bound at most the horizon's value for the line's sector (the
//! box's angles hold the point's, to rounding, and one spare sector on each side), which is
//! below the line's slope: the ray passes above the point, a contradiction. The bound of a box:
//! its top raised by `delta_z`, over its nearest horizontal distance less `2 delta`, or over its
//! farthest plus `2 delta` when it is below the UAV; squared with its sign, with a relative
//! margin of `1.001e-9`, and rounded up to `f32`. The margins (`1e-9` of the coordinates) are
//! millions of ulps.

use crate::error::{try_filled, Result};
use crate::geometry::{Point, SIGHT_FRACTION};
use crate::surface::grid::{floor_index, pseudo_angle};
use crate::surface::skyline::{sector_of, Skyline};

/// At most this many distance bins and this many sectors in one horizon.
const MAX_SIDE: f64 = 4096.0;

/// What a UAV sees around it: for each angular sector and each distance, an upper bound on the
/// elevation slope (rise over horizontal run, from the UAV) of every box of that sector up to
/// that distance.
#[derive(Debug, Clone)]
pub(crate) struct Horizon {
    pub(crate) uav: Point,
    pub(crate) sectors: usize,
    pub(crate) bins: usize,
    /// Width of a distance bin, metres, and its inverse.
    pub(crate) bin: f64,
    pub(crate) inv_bin: f64,
    /// Sectors per unit of pseudo-angle.
    pub(crate) quarter: f64,
    /// Running maximum along distance of the slope bounds, `slope[bin * sectors + sector]`, each a
    /// signed square (`s |s|`, which orders like `s`) rounded up to `f32`.
    pub(crate) slope: Vec<f32>,
    /// How far every box was widened, metres.
    pub(crate) delta: f64,
}

/// One sector's bounds in a [`Horizon`], bin by bin.
#[derive(Clone, Copy)]
pub(crate) struct Column<'a> {
    slope: &'a [f32],
    stride: usize,
    pub(crate) len: usize,
}

impl Column<'_> {
    #[inline(always)]
    pub(crate) fn at(&self, bin: usize) -> f64 {
        f64::from(self.slope[bin * self.stride])
    }
}

/// `x` as an `f32` no smaller than it, without a branch: rounding to nearest goes down about
/// half the time, at random, and a mispredicted branch per box cost more than all the rest of
/// the rounding (`benches/README.md`, the grid method).
#[inline(always)]
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    let bits = f.to_bits();
    // Rounded down (never for NaN, where the comparison fails): the next value up, one more in
    // the bits of a value with the sign bit clear (zero included), one less in those of a
    // negative one (-inf gives -f32::MAX; never -0.0, which is not below any negative `x`).
    let down = u32::from(f64::from(f) < x);
    let step = 1u32.wrapping_sub((bits >> 31) << 1);
    f32::from_bits(bits.wrapping_add(down.wrapping_mul(step)))
}

/// Slots of the fixed window that [`HorizonBuilder::put_box`] fills for a box of a few sectors.
const WINDOW: usize = 8;

/// Raises `window[..=last]` to `sigma`, the other slots left as they are: every slot is visited,
/// so the loop has no exit that depends on the box (mispredicted once per box otherwise).
#[inline(always)]
fn put_window(window: &mut [f32; WINDOW], last: usize, sigma: f32) {
    for (i, slot) in window.iter_mut().enumerate() {
        let value = if i <= last { sigma } else { f32::NEG_INFINITY };
        *slot = if value > *slot { value } else { *slot };
    }
}

/// The bounds of a [`Horizon`] while its boxes are entered: by bin, then sector.
pub(crate) struct HorizonBuilder {
    uav: Point,
    pub(crate) sectors: usize,
    pub(crate) bins: usize,
    bin: f64,
    inv_bin: f64,
    quarter: f64,
    pub(crate) delta: f64,
    delta_z: f64,
    /// Every box nearer than this (metres) is entered.
    pub(crate) reach: f64,
    reach2: f64,
    by_bin: Vec<f32>,
}

impl HorizonBuilder {
    /// The empty horizon of a UAV at `uav` over a surface within `bounds`, for targets up to
    /// `radius` metres away horizontally, with bins `bin` metres wide, in at most `max_values`
    /// bounds (at least one bin of 64 sectors). `xy_scale` and `z_scale` are the magnitudes of
    /// the surface's coordinates (plus its extent) and of its heights (plus their range).
    ///
    /// Its size is bounded whatever the inputs: the radius stops at the surface's farthest corner
    /// (no box lies beyond; any radius gives the same answers, only the work differs), the bins
    /// and sectors are counted in floating point and clamped before they become integers (at
    /// most 4096 each), and the bounds are allocated with `try_reserve`.
    ///
    /// # Errors
    /// [`Error::TooLarge`](crate::Error::TooLarge) when the system refuses the memory.
    pub(crate) fn new(
        uav: Point,
        radius: f64,
        max_values: usize,
        bin: f64,
        bounds: (Point, Point),
        xy_scale: f64,
        z_scale: f64,
    ) -> Result<Self> {
        let radius = if radius.is_finite() { radius.max(0.0) } else { 0.0 };
        // No box is farther than the surface's farthest corner (plus two bins for rounding).
        let (lo, hi) = bounds;
        let far = |a: f64, l: f64, h: f64| (a - l).abs().max((h - a).abs());
        let corner = far(uav[0], lo[0], hi[0]).hypot(far(uav[1], lo[1], hi[1])) + 2.0 * bin;
        let radius = if radius > corner { corner } else { radius };
        let bins = ((radius / bin).ceil() + 2.0).min(MAX_SIDE) as usize;
        // Sectors about a bin wide at the far edge (at least 64, a multiple of 4).
        let sectors = ((std::f64::consts::PI * radius / bin).ceil().clamp(64.0, MAX_SIDE) as usize).next_multiple_of(4);
        let bins = bins.min((max_values / sectors).max(1));
        let delta = 1e-9 * (uav[0].abs().max(uav[1].abs()) + xy_scale + radius);
        let delta_z = 1e-9 * (uav[2].abs() + z_scale + 1e-300);
        let reach = bins as f64 * bin;
        let by_bin = try_filled(f32::NEG_INFINITY, sectors * bins, "a UAV's horizon")?;
        let quarter = sectors as f64 / 4.0;
        Ok(Self { uav, sectors, bins, bin, inv_bin: 1.0 / bin, quarter, delta, delta_z, reach, reach2: reach * reach, by_bin })
    }

    /// The sector of a box corner `(x, y)` relative to the UAV, for [`Self::put_box`] (the
    /// corners of neighbouring boxes are shared: their sectors are worked out once).
    #[inline(always)]
    pub(crate) fn corner_sector(&self, x: f64, y: f64) -> usize {
        let a = if x == 0.0 && y == 0.0 { 0.0 } else { pseudo_angle(x, y) };
        floor_index(a * self.quarter, (self.sectors - 1) as u32) // a in [0, 4]
    }

    /// Enters a box of the surface: horizontally `[xlo, xhi] x [ylo, yhi]` relative to the UAV,
    /// nothing in it higher than `top` (absolute), with the [`Self::corner_sector`]s of its
    /// corners `[(xlo, ylo), (xhi, ylo), (xlo, yhi), (xhi, yhi)]`. A box out of reach is skipped.
    #[inline(always)]
    pub(crate) fn put_box(&mut self, top: f64, (xlo, xhi): (f64, f64), (ylo, yhi): (f64, f64), corners: [usize; 4]) {
        let nx = xlo.max(-xhi).max(0.0);
        let ny = ylo.max(-yhi).max(0.0);
        let near2 = nx * nx + ny * ny;
        if near2 >= self.reach2 {
            return;
        }
        // The bound on rise over run, kept as a signed square: the box's top (raised by
        // delta_z) over its nearest distance (less 2 delta) when above the UAV, else over its
        // farthest (plus 2 delta); rounded up.
        let rise = top + self.delta_z - self.uav[2];
        let near = near2.sqrt();
        let sigma = if rise < 0.0 {
            let xfar = (-xlo).max(xhi) + 2.0 * self.delta;
            let yfar = (-ylo).max(yhi) + 2.0 * self.delta;
            -(rise * rise) / (xfar * xfar + yfar * yfar)
        } else {
            let run = near - 2.0 * self.delta;
            if run > 0.0 {
                rise * rise / (run * run)
            } else {
                f64::INFINITY
            }
        };
        // Rounded up with a margin for its own rounding (1e-12 of it) and the queries'
        // comparison margin (1e-9) already added, so that a query compares once per bin.
        let sigma = round_up(sigma + 1.001e-9 * sigma.abs() + 1e-300);
        let sectors = self.sectors;
        let b = floor_index(near * self.inv_bin, (self.bins - 1) as u32);
        let row = &mut self.by_bin[b * sectors..(b + 1) * sectors];
        let mut put = |k0: usize, k1: usize| {
            for slot in &mut row[k0..=k1] {
                *slot = if sigma > *slot { sigma } else { *slot };
            }
        };
        // Sectors of the box's angles from the corners that bound them (by where the box lies
        // from the UAV), one more on each side for rounding.
        let [lo_l, hi_l, lo_u, hi_u] = corners;
        let (right, left) = (xlo > 0.0, xhi < 0.0);
        let (above, below) = (ylo > 0.0, yhi < 0.0);
        let (k0, k1) = match (right, left, above, below) {
            (false, false, false, false) => {
                put(0, sectors - 1); // the UAV stands over this box
                return;
            }
            (true, _, false, false) => {
                // Across the +x axis, where the pseudo-angle wraps from 4 to 0.
                put(lo_l.saturating_sub(1), sectors - 1);
                put(0, (lo_u + 1).min(sectors - 1));
                return;
            }
            (true, _, true, _) => (hi_l, lo_u),
            (false, false, true, _) => (hi_l, lo_l),
            (_, true, true, _) => (hi_u, lo_l),
            (_, true, false, false) => (hi_u, hi_l),
            (_, true, _, true) => (lo_u, hi_l),
            (false, false, _, true) => (lo_u, hi_u),
            (true, _, _, true) => (lo_l, hi_u),
        };
        // Most boxes span a few sectors: with their spare ones, a fixed window away from the wrap.
        if k0 >= 1 && k0 - 1 + WINDOW <= sectors && (k0 - 1..k0 - 1 + WINDOW).contains(&(k1 + 1)) {
            let window = (&mut row[k0 - 1..k0 - 1 + WINDOW]).try_into().expect("a window of WINDOW slots");
            put_window(window, k1 + 2 - k0, sigma);
            return;
        }
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

    /// The horizon: a running maximum outwards, so that bin `b` of sector `k` bounds sector `k`
    /// up to bin `b`. Every row only ever grows, so this is a plain element-wise max of
    /// consecutive rows.
    pub(crate) fn finish(self) -> Horizon {
        let Self { uav, sectors, bins, bin, inv_bin, quarter, delta, mut by_bin, .. } = self;
        for b in 1..bins {
            let (done, rest) = by_bin.split_at_mut(b * sectors);
            for (slot, &before) in rest[..sectors].iter_mut().zip(&done[(b - 1) * sectors..]) {
                *slot = slot.max(before);
            }
        }
        Horizon { uav, sectors, bins, bin, inv_bin, quarter, slope: by_bin, delta }
    }
}

impl Horizon {
    /// What the skyline of `target` (reaching `reach` metres around it) and this horizon leave
    /// of the sight line to it; `z_scale` is the magnitude of the surface's heights. Both
    /// methods' sight lines to targets with skylines (`HeightField::line_of_sight_to_node`
    /// gives the argument).
    #[inline(always)]
    pub(crate) fn beside_skyline(&self, target: Point, skyline: &Skyline, reach: f64, z_scale: f64) -> Rest {
        let p = self.uav;
        let d = [target[0] - p[0], target[1] - p[1], target[2] - p[2]];
        let r2 = d[0] * d[0] + d[1] * d[1];
        if r2 == 0.0 {
            return Rest::Unsettled;
        }
        let r = r2.sqrt();
        let rho_end = (1.0 - SIGHT_FRACTION) * r;
        let eps = 4.0 * self.delta + 1e-9 * (p[2].abs() + target[2].abs() + z_scale);
        // Slope of the line from the target towards the UAV, and the skyline's bound that way
        // (the opposite pseudo-angle of the UAV-to-target direction).
        let line = -d[2] * (1.0 / r);
        let a = pseudo_angle(d[0], d[1]);
        let bound = skyline.slope(sector_of(if a < 2.0 { a + 2.0 } else { a - 2.0 }));
        if !(rho_end > 100.0 * eps && (line - bound) * rho_end > 2.0 * eps * (1.0 + bound.abs() + line.abs())) {
            return Rest::Unsettled;
        }
        // The ray is clear within `reach` of the target; the horizon must clear it up to `far`
        // from the UAV: every bin before `need` (the stretch cleared by `lo` bins ends `2 delta`
        // short of `lo` bins).
        let far = r - (reach - eps) + eps;
        if far <= 0.0 {
            return Rest::Clear;
        }
        let need = (far + 2.0 * self.delta) * self.inv_bin; // bins, not rounded
        let row = self.column(a);
        // The horizon's signed squared slope, from the UAV (the line's, negated), less the margin
        // of the comparison (the stored bounds hold theirs).
        let sigma = -line * line.abs();
        let s = sigma - 1e-9 * sigma.abs() - 1e-300;
        if need <= 0.0 {
            return Rest::Clear;
        }
        // `need` reaches into bin `ceil(need) - 1`, found without `ceil` (a library call on the
        // baseline x86-64 target) and without saturating casts.
        let len = row.len as u32;
        if need <= f64::from(len) {
            let whole = floor_index(need, len);
            let last = if (whole as f64) < need { whole } else { whole - 1 };
            if s > row.at(last) {
                return Rest::Clear;
            }
        }
        let cleared = first_unclear(row, s) as f64 * self.bin - 2.0 * self.delta;
        Rest::Stretch { cleared, far, r }
    }

    /// The bounds of the sector with pseudo-angle `a`, bin by bin.
    #[inline(always)]
    pub(crate) fn column(&self, a: f64) -> Column<'_> {
        let k = floor_index(a * self.quarter, (self.sectors - 1) as u32);
        Column { slope: &self.slope[k..], stride: self.sectors, len: self.bins }
    }

    /// Where the exact test of the sight line to `target` has to start: `None` when the horizon
    /// clears the line up to [`SIGHT_FRACTION`], else the parameter (of the segment from the UAV
    /// to `target`) up to which it clears it, `0` when it clears nothing.
    ///
    /// The horizon clears the line up to the first distance bin whose bound reaches the line's
    /// slope (a binary search, the bounds being a running maximum); the stretch stops `2 delta`
    /// short of that bin, as the ray there reaches boxes up to a few ulps farther.
    #[inline(always)]
    pub(crate) fn uncleared_from(&self, target: Point) -> Option<f64> {
        let p = self.uav;
        let d = [target[0] - p[0], target[1] - p[1], target[2] - p[2]];
        let r2 = d[0] * d[0] + d[1] * d[1];
        if r2 <= 0.0 {
            return Some(0.0);
        }
        let sigma = d[2] * d[2].abs() / r2;
        let row = self.column(pseudo_angle(d[0], d[1]));
        // The line's slope less its own margin against the stored bounds (which hold theirs;
        // an empty stretch has -inf, an unbounded one +inf, which never clears).
        let s = sigma - 1e-9 * sigma.abs() - 1e-300;
        let lo = first_unclear(row, s);
        let cleared = lo as f64 * self.bin - 2.0 * self.delta;
        let r = r2.sqrt();
        if cleared >= r * SIGHT_FRACTION {
            return None; // cleared all the way
        }
        Some(if cleared > 0.0 { cleared / r } else { 0.0 })
    }
}

/// What a target's [`Skyline`] and a [`Horizon`] leave of a sight line (see
/// [`Horizon::beside_skyline`]).
pub(crate) enum Rest {
    /// Nothing: the line is clear.
    Clear,
    /// The skyline does not settle the line's last stretch: test it without the skyline.
    Unsettled,
    /// The horizon clears the line up to `cleared` metres from the UAV (horizontally) and the
    /// skyline from `far` on; `r` is the line's horizontal length.
    Stretch { cleared: f64, far: f64, r: f64 },
}

/// The first distance bin of a horizon column whose bound reaches the signed squared slope `s`
/// (`row.len` when none does), by a halving without branches: the bounds are a running maximum,
/// so every bin before the answer clears.
#[inline(always)]
pub(crate) fn first_unclear(row: Column<'_>, s: f64) -> usize {
    let mut base = 0usize;
    let mut n = row.len;
    while n > 1 {
        let half = n / 2;
        base += half * usize::from(s > row.at(base + half));
        n -= half;
    }
    base + usize::from(s > row.at(base))
}

#[cfg(test)]
mod tests;
