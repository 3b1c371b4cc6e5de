//! The mesh path's sight lines, as the grid path's: a UAV's [`Horizon`] from the small boxes of
//! the BVH, a target's [`Skyline`] from the triangles around it, and the BVH's own exact test
//! for the stretch of a line that neither clears.
//!
//! Both bounds only ever skip triangles that the plain test ([`TriangleMesh::ray_hits`]) would
//! not count, and every triangle not skipped gets that test: the answers are the same, to the
//! last bit (`tests` below compare them on terrains, boxes and overhangs).

use parry3d_f64::partitioning::TraversalAction;

use super::Blockers;
use super::TriangleMesh;
use crate::error::Result;
use crate::geometry::{Point, SIGHT_FRACTION};
use crate::surface::grid::pseudo_angle;
use crate::surface::horizon::{Horizon, HorizonBuilder, Rest};
use crate::surface::skyline::{sector_of, SectorEdges, Skyline, SkylineBounds, Span, ALL_SECTORS, REACH};

impl TriangleMesh {
    /// The [`Horizon`] of a UAV at `uav`, for targets up to `radius` metres away horizontally,
    /// in at most `max_values` bounds: from the boxes of the BVH's nodes within reach, each
    /// entered whole once it is a leaf or at most two bins wide.
    ///
    /// # Errors
    /// [`Error::TooLarge`](crate::Error::TooLarge) when the system refuses the memory.
    pub(crate) fn horizon(&self, uav: Point, radius: f64, max_values: usize) -> Result<Horizon> {
        let bin = self.horizon_bin;
        let mut h = HorizonBuilder::new(uav, radius, max_values, bin, self.bounds(), self.scales.0, self.scales.1)?;
        let reach2 = h.reach * h.reach;
        let (px, py) = (uav[0], uav[1]);
        self.mesh.bvh().traverse(|node| {
            let (lo, hi) = (node.mins(), node.maxs());
            let (x, y) = ((lo.x - px, hi.x - px), (lo.y - py, hi.y - py));
            let (nx, ny) = (x.0.max(-x.1).max(0.0), y.0.max(-y.1).max(0.0));
            if nx * nx + ny * ny >= reach2 {
                return TraversalAction::Prune; // nothing in it is within reach
            }
            if node.leaf_data().is_none() && (hi.x - lo.x).max(hi.y - lo.y) > 2.0 * bin {
                return TraversalAction::Continue;
            }
            let corners = [h.corner_sector(x.0, y.0), h.corner_sector(x.1, y.0), h.corner_sector(x.0, y.1), h.corner_sector(x.1, y.1)];
            h.put_box(hi.z, x, y, corners);
            TraversalAction::Prune
        });
        Ok(h.finish())
    }

    /// How far (metres, horizontally) a target's [`Skyline`] reaches on this mesh.
    fn skyline_reach(&self) -> f64 {
        REACH as f64 * self.horizon_bin
    }

    /// The [`Skyline`] of the point `q`: for each sector, an upper bound on the slope from `q`
    /// to every point of the surface within [`TriangleMesh::skyline_reach`] of it horizontally.
    ///
    /// Each triangle within reach is bounded by its plane (`h0 / rho + g . u`, `h0` the plane's
    /// height over `q`, as on the grid) or, when that is looser (steep and vertical triangles),
    /// by its highest corner over its nearest distance; a triangle whose footprint holds `q`
    /// counts in every direction, and one that rises above `q` there clears nothing.
    pub(crate) fn skyline(&self, q: Point, edges: &SectorEdges) -> Skyline {
        let reach = self.skyline_reach();
        let reach2 = reach * reach;
        let (qx, qy, qz) = (q[0], q[1], q[2]);
        // A point this close to a footprint is in it, and a plane this close to `q` is through
        // it: far below the sight lines' margins (1e-9 of the coordinates).
        let tol_xy = 1e-12 * self.scales.0;
        let tol_z = 1e-12 * (self.scales.1 + qz.abs());
        let mut bounds = SkylineBounds::new(edges);
        self.mesh.bvh().traverse(|node| {
            let (lo, hi) = (node.mins(), node.maxs());
            let (nx, ny) = ((lo.x - qx).max(qx - hi.x).max(0.0), (lo.y - qy).max(qy - hi.y).max(0.0));
            if nx * nx + ny * ny > reach2 {
                return TraversalAction::Prune; // the box is out of reach (its nearest point is)
            }
            let Some(f) = node.leaf_data() else { return TraversalAction::Continue };
            let [a, b, c] = self.corners[f as usize];
            let xy = [(a.x - qx, a.y - qy), (b.x - qx, b.y - qy), (c.x - qx, c.y - qy)];
            let near = footprint_distance(xy);
            if near > reach {
                return TraversalAction::Prune;
            }
            let z = [a.z - qz, b.z - qz, c.z - qz];
            // Squares, then one root: coordinates are at most 1e15 m, so nothing overflows, and
            // the rounding (an ulp or two, as `hypot`'s) is far inside the margins.
            let far = xy.iter().map(|p| p.0 * p.0 + p.1 * p.1).fold(0.0, f64::max).sqrt();
            if far <= 0.0 || far.is_nan() {
                return TraversalAction::Prune; // all of it straight above or below q
            }
            let inside = near <= tol_xy;
            let span = if inside { ALL_SECTORS } else { arc_of(xy) };
            let top = z[0].max(z[1]).max(z[2]);
            let by_box = if top <= 0.0 {
                top / far
            } else if inside {
                f64::INFINITY
            } else {
                top / near
            };
            let plane = plane(xy, z);
            if inside && plane.is_none() && top > 0.0 {
                // A wall through q: its points rise from q only along the wall's line, so only
                // those two directions are unbounded. (A sight line looks no nearer q than
                // 100 margins, 1e-7 of the coordinates, where a wall within 1e-9 of vertical
                // departs from that line by under 0.01 rad, which the neighbouring sectors
                // every bound also answers for absorb.)
                let (ex, ey) = longest_side(xy);
                for (x, y) in [(ex, ey), (-ex, -ey)] {
                    let k = sector_of(pseudo_angle(x, y));
                    bounds.add_slope(f64::INFINITY, Span::new(k, k));
                }
                return TraversalAction::Prune;
            }
            match plane {
                Some((h0, g)) => {
                    let lift = if inside {
                        if h0.abs() <= tol_z {
                            0.0 // through q
                        } else if h0 > 0.0 {
                            f64::INFINITY // over q
                        } else {
                            h0 / far
                        }
                    } else if h0 > 0.0 {
                        h0 / near
                    } else {
                        h0 / far
                    };
                    if lift + (g.0 * g.0 + g.1 * g.1).sqrt() <= by_box {
                        bounds.add_plane(lift, g, span);
                    } else {
                        bounds.add_slope(by_box, span);
                    }
                }
                None => bounds.add_slope(by_box, span),
            }
            TraversalAction::Prune
        });
        bounds.finish()
    }

    /// [`TriangleMesh::line_of_sight`] from the UAV of `horizon`, the same answer to the last
    /// bit: the horizon clears the sight line up to some distance (see [`crate::surface::horizon`]), and
    /// the BVH tests the rest.
    ///
    /// Exactness: a triangle the plain test counts has a point within a few ulps of the ray at
    /// its time of impact, which the horizon puts beyond the cleared stretch; every box that
    /// holds that point is then passed by the ray at parameters from the stretch's end on (to
    /// rounding, and the search starts `2 delta` earlier still), so the traversal reaches the
    /// triangle and gives it the same leaf test.
    pub(crate) fn line_of_sight_from(&self, horizon: &Horizon, target: Point, blocker: &mut Blockers) -> bool {
        let Some(t_from) = horizon.uncleared_from(target) else { return true };
        let p = horizon.uav;
        let d = [target[0] - p[0], target[1] - p[1], target[2] - p[2]];
        let t_min = if t_from > 0.0 { (t_from - 2.0 * horizon.delta / d[0].hypot(d[1])).max(0.0) } else { 0.0 };
        !self.ray_hits_between(p, d, t_min, SIGHT_FRACTION, SIGHT_FRACTION, blocker)
    }

    /// [`TriangleMesh::line_of_sight_from`] with the target's [`Skyline`] (see
    /// [`TriangleMesh::skyline`]): the same answer to the last bit, usually without the BVH.
    ///
    /// As on the grid (`HeightField::line_of_sight_to_node`, whose argument this follows step
    /// by step): a sight line that arrives more steeply than the skyline's bound for its
    /// direction passes above every triangle within the skyline's reach of the target, so the
    /// horizon only has to clear it up to that distance from the target, and what neither
    /// clears goes to the BVH.
    pub(crate) fn line_of_sight_to_target(&self, horizon: &Horizon, target: Point, skyline: &Skyline, blocker: &mut Blockers) -> bool {
        let (cleared, far, r) = match horizon.beside_skyline(target, skyline, self.skyline_reach(), self.scales.1) {
            Rest::Clear => return true,
            Rest::Unsettled => return self.line_of_sight_from(horizon, target, blocker),
            Rest::Stretch { cleared, far, r } => (cleared, far, r),
        };
        // The BVH's search runs `2 delta` wider on both sides than the stretch to clear.
        let t_from = if cleared > 0.0 { ((cleared - 2.0 * horizon.delta) / r).max(0.0) } else { 0.0 };
        let t_to = ((far + 2.0 * horizon.delta) / r).min(SIGHT_FRACTION);
        if t_from >= t_to {
            return true;
        }
        let p = horizon.uav;
        let d = [target[0] - p[0], target[1] - p[1], target[2] - p[2]];
        !self.ray_hits_between(p, d, t_from, t_to, SIGHT_FRACTION, blocker)
    }
}

/// The horizontal distance from the origin to the triangle with corners `xy`, `0` inside it.
fn footprint_distance(xy: [(f64, f64); 3]) -> f64 {
    let cross = |p: (f64, f64), q: (f64, f64)| p.0 * q.1 - p.1 * q.0;
    let sides = [cross(xy[0], xy[1]), cross(xy[1], xy[2]), cross(xy[2], xy[0])];
    if sides.iter().all(|&s| s >= 0.0) || sides.iter().all(|&s| s <= 0.0) {
        return 0.0;
    }
    let to_edge = |p: (f64, f64), q: (f64, f64)| {
        let (ex, ey) = (q.0 - p.0, q.1 - p.1);
        let len2 = ex * ex + ey * ey;
        let t = if len2 > 0.0 { (-(p.0 * ex + p.1 * ey) / len2).clamp(0.0, 1.0) } else { 0.0 };
        let (x, y) = (p.0 + t * ex, p.1 + t * ey);
        x * x + y * y
    };
    to_edge(xy[0], xy[1]).min(to_edge(xy[1], xy[2])).min(to_edge(xy[2], xy[0])).sqrt()
}

/// The longest side of a triangle's footprint, as a vector.
fn longest_side(xy: [(f64, f64); 3]) -> (f64, f64) {
    let sides = [(xy[1].0 - xy[0].0, xy[1].1 - xy[0].1), (xy[2].0 - xy[1].0, xy[2].1 - xy[1].1), (xy[0].0 - xy[2].0, xy[0].1 - xy[2].1)];
    sides.into_iter().max_by(|p, q| p.0.hypot(p.1).total_cmp(&q.0.hypot(q.1))).unwrap_or((1.0, 0.0))
}

/// The sectors of the directions of a triangle clear of the origin: the arc its corners span,
/// which is less than a half-turn and lies opposite the widest gap between their directions.
fn arc_of(xy: [(f64, f64); 3]) -> Span {
    let mut a = xy.map(|p| pseudo_angle(p.0, p.1));
    a.sort_by(f64::total_cmp);
    let gaps = [a[1] - a[0], a[2] - a[1], 4.0 - a[2] + a[0]];
    let (first, last) = if gaps[2] >= gaps[0] && gaps[2] >= gaps[1] {
        (a[0], a[2])
    } else if gaps[0] >= gaps[1] {
        (a[1], a[0]) // across +x: from a[1] up through a[2] and 4 = 0 to a[0]
    } else {
        (a[2], a[1])
    };
    Span::new(sector_of(first), sector_of(last))
}

/// The plane through corners `xy` (relative to the point) at heights `z` (relative to it): its
/// height over the point and its gradient, or `None` for a triangle too steep to bound that way
/// (vertical, or within rounding of it).
fn plane(xy: [(f64, f64); 3], z: [f64; 3]) -> Option<(f64, (f64, f64))> {
    let (e1, e2) = ((xy[1].0 - xy[0].0, xy[1].1 - xy[0].1), (xy[2].0 - xy[0].0, xy[2].1 - xy[0].1));
    let (dz1, dz2) = (z[1] - z[0], z[2] - z[0]);
    let cross = e1.0 * e2.1 - e1.1 * e2.0;
    let size = (e1.0.abs() + e1.1.abs()) * (e2.0.abs() + e2.1.abs());
    if cross.abs() <= 1e-9 * size || cross.is_nan() {
        return None;
    }
    let gx = (dz1 * e2.1 - dz2 * e1.1) / cross;
    let gy = (dz2 * e1.0 - dz1 * e2.0) / cross;
    let h0 = z[0] - gx * xy[0].0 - gy * xy[0].1;
    (gx.is_finite() && gy.is_finite() && h0.is_finite()).then_some((h0, (gx, gy)))
}

#[cfg(test)]
mod tests;
