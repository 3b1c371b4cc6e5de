//! The vocabulary every surface shares: [`Point`], the conversions to and from parry's vectors,
//! the area of a triangle, and what a line of sight is ([`SIGHT_FRACTION`]).
//!
//! A leaf: it imports nothing from the rest of the crate.

use parry3d_f64::math::Vector;

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
