//! The vocabulary every surface shares: [`Point`], the conversions to and from parry's vectors,
//! the area of a triangle, the ray-triangle test, and what a line of sight is
//! ([`SIGHT_FRACTION`]).
//!
//! A leaf: it imports nothing from the rest of the crate.

use parry3d_f64::math::Vector;
use parry3d_f64::query::details::local_ray_intersection_with_triangle;
use parry3d_f64::query::Ray;

/// A point or vector in metres, Z up.
pub type Point = [f64; 3];

/// The largest coordinate magnitude accepted anywhere (vertices, grid nodes, targets, UAVs,
/// query points), metres: `|c| <= 1e15`. At this size a coordinate still resolves 0.125 m and
/// every squared distance between two accepted points (at most `12e30`) is far from overflow;
/// beyond it the geometry loses its meaning (a mesh of 1e300 m has no representable area),
/// so inputs past it are refused with [`Error::InvalidInput`](crate::Error::InvalidInput) (or
/// [`Error::Mesh`](crate::Error::Mesh) for a surface) instead of giving a wrong answer.
pub const MAX_COORDINATE: f64 = 1e15;

/// A sensing range at least this long (metres) reaches from any accepted point to any other
/// (the diagonal of the cube of side `2 MAX_COORDINATE` is `3.5e15`): ranges are used up to
/// this value, so a larger finite `d_max` means "unlimited" and gives the same answers.
pub const UNLIMITED_RANGE: f64 = 4e15;

/// Whether every coordinate of `q` is finite and at most [`MAX_COORDINATE`] in magnitude.
#[inline]
#[must_use]
pub fn in_bounds(q: Point) -> bool {
    q.iter().all(|c| c.abs() <= MAX_COORDINATE)
}

/// The segment from a UAV to a target is tested up to this fraction of its length, so the
/// target's own triangles never count as an obstruction.
pub const SIGHT_FRACTION: f64 = 0.999;

/// Time of impact of `ray` on the triangle `[a, b, c]` (in units of its direction), if any:
/// parry's test, the leaf test of every path, but for one case where it errs.
///
/// From an origin exactly in the triangle's plane, parry's test reports a hit at time 0 for a
/// ray leaving towards the back of the triangle whenever the origin's mirror image lies in it
/// (its sign convention assumes the origin in front); that ray meets the plane at its origin
/// only, so it hits the triangle when the origin lies in the closed triangle, and that is the
/// answer given. (A UAV right above a vertical wall's corner, its `x, y` those of the corner,
/// is in the plane of both walls: it saw nothing through half of its directions.)
#[inline(always)]
pub(crate) fn triangle_hit(a: Vector, b: Vector, c: Vector, ray: &Ray) -> Option<f64> {
    let toi = local_ray_intersection_with_triangle(a, b, c, ray)?.0.time_of_impact;
    if toi == 0.0 && !in_closed_triangle(a, b, c, ray.origin) {
        return None;
    }
    Some(toi)
}

/// Whether `p`, a point of the plane of `[a, b, c]` (to rounding), lies in the closed
/// triangle: the signs of the three edge functions in the projection along the normal's
/// largest component.
#[cold]
fn in_closed_triangle(a: Vector, b: Vector, c: Vector, p: Vector) -> bool {
    let n = (b - a).cross(c - a);
    let (ax, ay, az) = (n.x.abs(), n.y.abs(), n.z.abs());
    let flat = |q: Vector| {
        if az >= ax && az >= ay {
            (q.x, q.y)
        } else if ay >= ax {
            (q.z, q.x)
        } else {
            (q.y, q.z)
        }
    };
    let (a, b, c, p) = (flat(a), flat(b), flat(c), flat(p));
    let edge = |u: (f64, f64), w: (f64, f64)| (w.0 - u.0) * (p.1 - u.1) - (w.1 - u.1) * (p.0 - u.0);
    let s = [edge(a, b), edge(b, c), edge(c, a)];
    s.iter().all(|&e| e >= 0.0) || s.iter().all(|&e| e <= 0.0)
}

/// `p` as a parry vector.
#[inline]
pub(crate) fn v(p: Point) -> Vector {
    Vector::new(p[0], p[1], p[2])
}

/// A parry vector as a [`Point`].
#[inline]
pub(crate) fn p(v: Vector) -> Point {
    [v.x, v.y, v.z]
}

/// Area of the triangle `abc`.
pub(crate) fn triangle_area(a: Vector, b: Vector, c: Vector) -> f64 {
    0.5 * (b - a).cross(c - a).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_from_a_triangles_plane_hits_it_only_from_inside_it() {
        // A vertical triangle, and a ray from a point of its plane right above its top corner
        // `a` (same x, y), leaving the plane at once: it meets the plane only at its origin,
        // outside the triangle. Parry's test calls it a hit at time 0 (it measures the origin
        // from `a` with the sign flipped); `triangle_hit` does not.
        let (a, b, c) = (Vector::new(10.9, 6.1, 4.8), Vector::new(10.9, 6.1, 2.6), Vector::new(11.7, 5.3, 2.4));
        let origin = Vector::new(10.9, 6.1, 6.7);
        let target = Vector::new(11.0, 4.0, 1.5);
        let ray = Ray::new(origin, target - origin);
        assert_eq!(local_ray_intersection_with_triangle(a, b, c, &ray).map(|h| h.0.time_of_impact), Some(0.0));
        assert_eq!(triangle_hit(a, b, c, &ray), None);
        // Ordinary hits pass unchanged.
        let n = (b - a).cross(c - a).normalize();
        let front = Ray::new((a + b + c) / 3.0 + n * 2.0, n * -4.0);
        assert_eq!(triangle_hit(a, b, c, &front), local_ray_intersection_with_triangle(a, b, c, &front).map(|h| h.0.time_of_impact));
        assert!(triangle_hit(a, b, c, &front).is_some_and(|t| t > 0.0));
    }
}
