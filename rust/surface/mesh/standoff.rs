//! Standoff queries: how far a point is from the nearest triangle in 3D, whether a triangle lies
//! within a radius, and whether a point is inside a closed solid of the mesh.
//!
//! These are the questions the flight limits ask when the clearance is a standoff (a UAV under
//! a bridge deck, beside a tower) rather than a height straight down (see [`crate::flight`]).
//!
//! ```
//! use uavcov::surface::mesh::Surface;
//! // A closed unit cube (outward-wound) standing on nothing.
//! let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
//!              [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0]];
//! let f = vec![[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
//!              [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]];
//! let cube = Surface::new(v, f)?;
//! assert!((cube.distance([0.5, 0.5, 3.0])? - 2.0).abs() < 1e-12);
//! assert!(cube.inside([0.5, 0.4, 0.3])?);
//! assert!(!cube.inside([0.5, 0.4, 1.3])?);
//! assert!(cube.within([0.5, 0.5, 3.0], 2.5, false)? && !cube.within([0.5, 0.5, 3.0], 1.5, false)?);
//! # Ok::<(), uavcov::Error>(())
//! ```
//!
//! # The inside test
//!
//! A point is inside when the faces a ray from it crosses do not cancel by their winding
//! (leaving an outward-wound face counts +1, entering one -1: the winding number along the
//! ray; an odd number of crossings never cancels), voted over three fixed, skewed, upward
//! directions (two of three decide). Beside parity alone, the winding also sees what users'
//! exports hold: two solids that overlap (a point in both crosses an even number of faces,
//! winding 2) and a face given twice; either way the point is refused rather than accepted
//! (`tests/test_unseen_shapes.py`); a solid wound inward counts -1, still not zero. Parity is exact for closed
//! components whatever their shape, unlike the sign of the nearest face (ambiguous where two
//! components touch, as a pier on the ground plane does, and at edges without pseudo-normals),
//! and unlike a generalised winding number over the whole mesh (an open ground plane adds about
//! -1/2 to every point above it). A ray that grazes an edge can count it twice or never; three
//! directions with no simple ratio between their components make two such rays for one point
//! unlikely. Upward rays keep the ground plane (open, below the UAVs) out of the count; an open
//! surface above a point (a hillside, a lone wall) can flip one direction's parity, which
//! refuses a point rather than accepting one. The test costs three full ray traversals, so the
//! flight limits ask it only of UAVs that did not reach their position by a checked clear move
//! from outside (see [`crate::flight`]).

use parry3d_f64::math::Vector;
use parry3d_f64::partitioning::TraversalAction;
use parry3d_f64::query::{PointQuery, Ray};
use parry3d_f64::shape::Triangle;

use super::{slab_test, Surface, TriangleMesh};
use crate::error::Result;
use crate::geometry::{triangle_hit, v, Point};

/// The inside test's ray directions: upward, skewed, no two components in a simple ratio.
const INSIDE_RAYS: [[f64; 3]; 3] = [[0.2724, 0.1513, 0.9502], [-0.3071, 0.2246, 0.9248], [0.0893, -0.3417, 0.9355]];

/// Squared distance from `q` to the box `[lo, hi]`.
#[inline]
fn box_distance2(lo: Vector, hi: Vector, q: Vector) -> f64 {
    let d = (lo - q).max(q - hi).max(Vector::ZERO);
    d.dot(d)
}

impl TriangleMesh {
    /// Whether a triangle lies closer to `q` than `r` (`inclusive`: at most `r` away).
    ///
    /// The BVH is pruned by each box's distance, and the search stops at the first triangle
    /// found: a sphere test, much cheaper than the nearest distance when the answer is no.
    #[must_use]
    pub fn within(&self, q: Point, r: f64, inclusive: bool) -> bool {
        let q = v(q);
        let r2 = r * r;
        let near = |d2: f64| if inclusive { d2 <= r2 } else { d2 < r2 };
        let mut found = false;
        self.mesh.bvh().traverse(|node| {
            if !near(box_distance2(node.mins(), node.maxs(), q)) {
                return TraversalAction::Prune;
            }
            if let Some(f) = node.leaf_data() {
                let [a, b, c] = self.corners[f as usize];
                let p = Triangle::new(a, b, c).project_local_point(q, true).point;
                if near((p - q).length_squared()) {
                    found = true;
                    return TraversalAction::EarlyExit;
                }
            }
            TraversalAction::Continue
        });
        found
    }

    /// How many triangles the ray `origin + t dir`, `t >= 0`, crosses, and their signed sum:
    /// +1 for a triangle whose right-hand normal points along the ray (the ray leaves an
    /// outward-wound solid there), -1 for one facing it (the ray enters one).
    #[must_use]
    pub fn crossings(&self, origin: Point, dir: Point) -> (usize, i64) {
        let ray = Ray::new(v(origin), v(dir));
        let inv = Vector::new(1.0 / dir[0], 1.0 / dir[1], 1.0 / dir[2]);
        let (mut count, mut signed) = (0, 0);
        self.mesh.bvh().traverse(|node| {
            if !slab_test(node.mins(), node.maxs(), ray.origin, inv, 0.0, f64::INFINITY) {
                return TraversalAction::Prune;
            }
            if let Some(f) = node.leaf_data() {
                let [a, b, c] = self.corners[f as usize];
                if triangle_hit(a, b, c, &ray).is_some() {
                    count += 1;
                    let along = (b - a).cross(c - a).dot(ray.dir);
                    signed += i64::from(along > 0.0) - i64::from(along < 0.0);
                }
            }
            TraversalAction::Continue
        });
        (count, signed)
    }

    /// Whether `q` is inside a closed solid of the mesh (see the module's notes).
    #[must_use]
    pub fn inside(&self, q: Point) -> bool {
        let says_inside = |d: &&[f64; 3]| {
            let (count, signed) = self.crossings(q, **d);
            count % 2 == 1 || signed != 0
        };
        INSIDE_RAYS.iter().filter(says_inside).count() >= 2
    }
}

impl Surface {
    /// The least 3D distance from `point` to the surface, metres.
    ///
    /// # Errors
    /// As [`Surface::triangle_mesh`] (the mesh of a grid is built on first use).
    pub fn distance(&self, point: Point) -> Result<f64> {
        let c = self.triangle_mesh()?.closest_point(point);
        Ok(((c[0] - point[0]).powi(2) + (c[1] - point[1]).powi(2) + (c[2] - point[2]).powi(2)).sqrt())
    }

    /// Whether a triangle lies closer to `point` than `r` (`inclusive`: at most `r` away).
    ///
    /// # Errors
    /// As [`Surface::triangle_mesh`].
    pub fn within(&self, point: Point, r: f64, inclusive: bool) -> Result<bool> {
        Ok(self.triangle_mesh()?.within(point, r, inclusive))
    }

    /// Whether `point` is inside a closed solid of the surface (see the module's notes).
    ///
    /// # Errors
    /// As [`Surface::triangle_mesh`].
    pub fn inside(&self, point: Point) -> Result<bool> {
        Ok(self.triangle_mesh()?.inside(point))
    }

    /// Whether some surface lies straight below `point` (the standoff limits' "above the
    /// ground": a UAV under the ground plane, or off its edge, has none).
    #[must_use]
    pub fn surface_below(&self, point: Point) -> bool {
        let (mins, _) = self.bounds();
        let depth = point[2] - mins[2] + 1.0;
        depth >= 0.0 && self.ray_hits(point, [0.0, 0.0, -1.0], depth)
    }
}

#[cfg(test)]
pub(crate) mod tests;
