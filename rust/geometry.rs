//! The vocabulary every surface shares: [`Point`], the conversions to and from parry's vectors,
//! the area of a triangle, and what a line of sight is ([`SIGHT_FRACTION`]).
//!
//! A leaf: it imports nothing from the rest of the crate.

use parry3d_f64::math::Vector;

/// A point or vector in metres, Z up.
pub type Point = [f64; 3];

/// The segment from a UAV to a target is tested up to this fraction of its length, so the
/// target's own triangles never count as an obstruction.
pub const SIGHT_FRACTION: f64 = 0.999;

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
