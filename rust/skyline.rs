//! The skyline of a grid node: how steeply the surface rises around it, direction by direction.
//!
//! A sight line that ends at a grid node spends its last metres over the cells around that node,
//! and on a height field those are the cells whose exact test costs the most: the target's own
//! triangles always pass the bounding-box tests. A [`Skyline`] settles them once for all UAVs:
//! for each of [`SECTORS`] directions around the node, an upper bound on the slope (rise over
//! horizontal run) from the node to every point of the surface within [`REACH`] cells. A sight
//! line that arrives from direction `k` more steeply than the bound passes above all of that
//! surface, so only the stretch farther than `REACH` cells from the target is left to the UAV's
//! horizon and the walk (see [`HeightField::line_of_sight_to_node`]).
//!
//! The bounds are exact where it matters: the triangles that touch the node are planes through
//! it, bounded by their gradient over each sector; every other cell by its highest corner over
//! its nearest distance. Each is rounded up to one of 256 levels, so a skyline is 32 bytes.
//!
//! ```
//! use uavcov::heightfield::HeightField;
//! use uavcov::skyline::{Skyline, SECTORS};
//! // A plane rising 0.5 m per metre along +x.
//! let z: Vec<f64> = (0..49).map(|k| 0.5 * (k % 7) as f64).collect();
//! let hf = HeightField::new(z, 7, 7, 1.0, 1.0, 0.0, 0.0).unwrap();
//! let sky = Skyline::of_node(hf.grid(), 3, 3);
//! assert!(sky.slope(0) >= 0.5 && sky.slope(0) < 0.6); // towards +x: the plane's own slope
//! assert!(sky.slope(SECTORS / 2) < 0.0); // towards -x the surface falls away
//! ```
//!
//! [`HeightField::line_of_sight_to_node`]: crate::heightfield::HeightField::line_of_sight_to_node

use std::sync::LazyLock;

use crate::heightfield::pseudo_angle;
use crate::mesh::Grid;

/// Directions around a node; sector `k` holds the pseudo-angles `[4k, 4(k+1)) / SECTORS` (see
/// [`sector_of`]).
pub const SECTORS: usize = 32;

/// How far a skyline reaches, in cells: every point within `REACH * min(dx, dy)` of the node
/// horizontally is accounted for.
pub const REACH: usize = 3;

/// Slope levels: `LEVELS[q]` is the slope that code `q` stands for, strictly increasing, evenly
/// spaced in angle from straight down to straight up; the last is `+inf`.
static LEVELS: LazyLock<[f64; 256]> = LazyLock::new(|| {
    let step = std::f64::consts::PI / 256.0;
    let mut levels = [f64::INFINITY; 256];
    for (q, level) in levels.iter_mut().enumerate().take(255) {
        *level = (-std::f64::consts::FRAC_PI_2 + (q + 1) as f64 * step).tan();
    }
    levels
});

/// Upper bounds on the slope from a grid node to the surface around it, per direction sector.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Skyline([u8; SECTORS]);

/// The sector of a direction given by its pseudo-angle `a` in `[0, 4]`.
#[inline(always)]
pub fn sector_of(a: f64) -> usize {
    ((a * (SECTORS as f64 / 4.0)) as usize).min(SECTORS - 1)
}

impl Skyline {
    /// The upper bound on the slope from the node towards sector `k`, for every point of the
    /// surface within [`REACH`] cells whose direction lies within one sector of `k`; `+inf` when
    /// nothing is known, `LEVELS[0]` (about -81) where there is no surface.
    #[inline(always)]
    pub fn slope(&self, k: usize) -> f64 {
        LEVELS[self.0[k] as usize]
    }

    /// The skyline of node `(i, j)` (row, column) of `grid`, whose height must not be nodata.
    pub fn of_node(grid: &Grid, i: usize, j: usize) -> Self {
        let nx = grid.nx;
        let z = &grid.z;
        let zt = z[i * nx + j];
        debug_assert!(zt.is_finite());
        let (dx, dy) = (grid.dx, grid.dy);
        let mut bound = [f64::NEG_INFINITY; SECTORS];
        let rows = i.saturating_sub(REACH)..(i + REACH).min(grid.ny - 1);
        let cols = j.saturating_sub(REACH)..(j + REACH).min(nx - 1);
        for ci in rows {
            for cj in cols.clone() {
                let row = ci * nx + cj;
                let (za, zb, zc, zd) = (z[row], z[row + 1], z[row + nx + 1], z[row + nx]);
                if za.is_nan() || zc.is_nan() {
                    continue; // both triangles use the diagonal a-c
                }
                // Corners relative to the node, metres: a, b, c, d as in the mesh.
                let (x0, x1) = ((cj as f64 - j as f64) * dx, (cj as f64 + 1.0 - j as f64) * dx);
                let (y0, y1) = ((ci as f64 - i as f64) * dy, (ci as f64 + 1.0 - i as f64) * dy);
                let (a, b, c, d) = ([x0, y0, za - zt], [x1, y0, zb - zt], [x1, y1, zc - zt], [x0, y1, zd - zt]);
                let away = x0 > 0.0 || x1 < 0.0 || y0 > 0.0 || y1 < 0.0;
                // The nearest distance of the cell, for a cell away from the node.
                let (gap_x, gap_y) = (x0.max(-x1).max(0.0), y0.max(-y1).max(0.0));
                let cell_near = (gap_x * gap_x + gap_y * gap_y).sqrt();
                for tri in [[a, b, c], [a, c, d]] {
                    if tri[1][2].is_nan() {
                        continue; // left out of the mesh
                    }
                    let near = if away {
                        cell_near
                    } else if let Some(at) = tri.iter().position(|p| p[0] == 0.0 && p[1] == 0.0) {
                        wedge(&mut bound, tri[(at + 1) % 3], tri[(at + 2) % 3]);
                        continue;
                    } else {
                        // The triangle across the diagonal a-c from the node: no nearer than
                        // the line through a and c.
                        let (ex, ey) = (c[0] - a[0], c[1] - a[1]);
                        (a[0] * ey - a[1] * ex).abs() / (ex * ex + ey * ey).sqrt()
                    };
                    away_from(&mut bound, tri, near);
                }
            }
        }
        // Each sector also answers for its neighbours' directions, which absorbs the rounding of
        // every pseudo-angle, then every bound is rounded up to a level (with a margin of 1e-9).
        let mut codes = [0u8; SECTORS];
        for (k, code) in codes.iter_mut().enumerate() {
            let wide = bound[(k + SECTORS - 1) % SECTORS].max(bound[k]).max(bound[(k + 1) % SECTORS]);
            *code = if wide == f64::NEG_INFINITY { 0 } else { level_above(wide + 1e-9 * (1.0 + wide.abs())) };
        }
        Skyline(codes)
    }
}

/// The code of the smallest level at or above `slope` (NaN: the top level, `+inf`).
fn level_above(slope: f64) -> u8 {
    if slope.is_nan() {
        return 255;
    }
    let step = std::f64::consts::PI / 256.0;
    let guess = ((slope.atan() + std::f64::consts::FRAC_PI_2) / step).ceil() as isize - 1;
    let mut q = guess.clamp(0, 255) as usize;
    while q > 0 && LEVELS[q - 1] >= slope {
        q -= 1;
    }
    while LEVELS[q] < slope {
        q += 1; // LEVELS[255] is +inf: stops there
    }
    q as u8
}

/// Unit vectors along the sector boundaries: `EDGES[k]` at pseudo-angle `4k / SECTORS`.
static EDGES: LazyLock<[(f64, f64); SECTORS + 1]> = LazyLock::new(|| {
    let mut edges = [(0.0, 0.0); SECTORS + 1];
    for (k, e) in edges.iter_mut().enumerate() {
        *e = direction(4.0 * k as f64 / SECTORS as f64);
    }
    edges
});

/// The largest value of `gx ux + gy uy` over the unit vectors `u` of sector `k`: a sinusoid in
/// the angle, so at an end of the sector, or `|g|` when `g` points into it.
#[inline(always)]
fn steepest_in(k: usize, gx: f64, gy: f64, g_sector: Option<usize>) -> f64 {
    if g_sector == Some(k) {
        return (gx * gx + gy * gy).sqrt();
    }
    let ((ax, ay), (bx, by)) = (EDGES[k], EDGES[k + 1]);
    (gx * ax + gy * ay).max(gx * bx + gy * by)
}

/// The sector `g` points into, if any (a zero gradient points nowhere).
fn gradient_sector(gx: f64, gy: f64) -> Option<usize> {
    (gx != 0.0 || gy != 0.0).then(|| sector_of(pseudo_angle(gx, gy)))
}

/// Bounds for a triangle through the node; `p` and `q` are its other corners relative to the
/// node (with heights). Its slope from the node in direction `u` is exactly `g . u`, `g` the
/// gradient of its plane, over the sectors between its two edges.
fn wedge(bound: &mut [f64; SECTORS], p: [f64; 3], q: [f64; 3]) {
    let det = p[0] * q[1] - q[0] * p[1];
    let gx = (p[2] * q[1] - q[2] * p[1]) / det;
    let gy = (p[0] * q[2] - q[0] * p[2]) / det;
    let g_sector = gradient_sector(gx, gy);
    let (a, b) = (pseudo_angle(p[0], p[1]), pseudo_angle(q[0], q[1]));
    let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
    let mut cover = |k: usize| bound[k] = bound[k].max(steepest_in(k, gx, gy, g_sector));
    // The wedge is at most a right angle: a pseudo-angle range wider than 2 wraps across +x.
    if hi - lo <= 2.0 {
        (sector_of(lo)..=sector_of(hi)).for_each(&mut cover);
    } else {
        (sector_of(hi)..SECTORS).for_each(&mut cover);
        (0..=sector_of(lo)).for_each(&mut cover);
    }
}

/// Bounds for a triangle clear of the node, no nearer than `near` (> 0) horizontally. On its
/// plane `h(P) = h0 + g . (P - node)`, so its slope from the node is `h0 / rho + g . u`: the
/// first term is bounded by the nearest (h0 > 0) or farthest (h0 <= 0) distance, the second as
/// in [`wedge`], over the sectors of the corners' directions.
fn away_from(bound: &mut [f64; SECTORS], tri: [[f64; 3]; 3], near: f64) {
    let [p, q, r] = tri;
    let (e1, e2) = ([q[0] - p[0], q[1] - p[1], q[2] - p[2]], [r[0] - p[0], r[1] - p[1], r[2] - p[2]]);
    let det = e1[0] * e2[1] - e2[0] * e1[1];
    let gx = (e1[2] * e2[1] - e2[2] * e1[1]) / det;
    let gy = (e1[0] * e2[2] - e2[0] * e1[2]) / det;
    let h0 = p[2] - gx * p[0] - gy * p[1];
    let far = tri.iter().map(|c| (c[0] * c[0] + c[1] * c[1]).sqrt()).fold(0.0, f64::max);
    let lift = if h0 > 0.0 { h0 / near } else { h0 / far };
    let g_sector = gradient_sector(gx, gy);
    // The triangle lies in a half-plane through the node; one below the x axis has its
    // directions along +x at pseudo-angle 4, not 0, so that its range does not wrap.
    let below = tri.iter().all(|c| c[1] <= 0.0);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for c in &tri {
        let a = pseudo_angle(c[0], c[1]);
        let a = if below && a == 0.0 { 4.0 } else { a };
        lo = lo.min(a);
        hi = hi.max(a);
    }
    let first = sector_of(lo);
    for (k, b) in bound.iter_mut().enumerate().take(sector_of(hi) + 1).skip(first) {
        *b = b.max(lift + steepest_in(k, gx, gy, g_sector));
    }
}

/// The unit vector at pseudo-angle `s` in `[0, 4]` (the inverse of [`pseudo_angle`]).
fn direction(s: f64) -> (f64, f64) {
    let (x, y) = if s < 1.0 {
        (1.0 - s, s)
    } else if s < 2.0 {
        (1.0 - s, 2.0 - s)
    } else if s < 3.0 {
        (s - 3.0, 2.0 - s)
    } else {
        (s - 3.0, s - 4.0)
    };
    let n = (x * x + y * y).sqrt();
    (x / n, y / n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::HeightField;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn levels_round_up_and_are_tight() {
        for &s in &[-1e9, -81.0, -3.0, -0.5, -1e-12, 0.0, 1e-12, 0.3, 1.0, 7.5, 80.0, 1e9] {
            let q = level_above(s) as usize;
            assert!(LEVELS[q] >= s, "{s}");
            assert!(q == 0 || LEVELS[q - 1] < s, "{s}");
        }
        assert_eq!(level_above(f64::NAN), 255);
        assert_eq!(level_above(f64::INFINITY), 255);
    }

    #[test]
    fn direction_inverts_the_pseudo_angle() {
        for k in 0..400 {
            let s = 4.0 * k as f64 / 400.0;
            let (x, y) = direction(s);
            assert!((pseudo_angle(x, y) - s).abs() < 1e-12 || (s == 4.0), "{s}");
            assert!(((x * x + y * y) - 1.0).abs() < 1e-12);
        }
    }

    /// Brute force: dense samples of every triangle within reach must lie under the bound of
    /// their direction's sector.
    #[test]
    fn bounds_hold_for_points_sampled_on_the_surface() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for case in 0..40 {
            let (ny, nx) = (9, 10);
            let (dx, dy) = if case % 3 == 0 { (0.5, 0.8) } else { (1.0, 1.0) };
            let z: Vec<f64> = (0..ny * nx)
                .map(|_| if case % 5 == 4 && rng.random::<f64>() < 0.1 { f64::NAN } else { rng.random_range(-2.0..2.0) })
                .collect();
            let hf = HeightField::new(z.clone(), ny, nx, dx, dy, 0.0, 0.0);
            let Ok(hf) = hf else { continue };
            let g = hf.grid();
            let reach = REACH as f64 * dx.min(dy);
            for i in 0..ny {
                for j in 0..nx {
                    let zt = z[i * nx + j];
                    if zt.is_nan() {
                        continue;
                    }
                    let sky = Skyline::of_node(g, i, j);
                    for ci in 0..ny - 1 {
                        for cj in 0..nx - 1 {
                            for tri in g.cell_triangles(ci, cj).into_iter().flatten() {
                                for _ in 0..30 {
                                    let (mut u, mut w) = (rng.random::<f64>(), rng.random::<f64>());
                                    if u + w > 1.0 {
                                        (u, w) = (1.0 - u, 1.0 - w);
                                    }
                                    let p = tri[0] + (tri[1] - tri[0]) * u + (tri[2] - tri[0]) * w;
                                    let (px, py) = (p.x - j as f64 * dx, p.y - i as f64 * dy);
                                    let rho = (px * px + py * py).sqrt();
                                    if rho > reach || rho < 1e-9 {
                                        continue;
                                    }
                                    let k = sector_of(pseudo_angle(px, py));
                                    let slope = (p.z - zt) / rho;
                                    assert!(slope <= sky.slope(k) + 1e-9, "case {case} node ({i}, {j}) slope {slope} > {}", sky.slope(k));
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}
