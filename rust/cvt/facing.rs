//! The facing term of a normal-weighted CVT: how far a sample's surface normal is from a
//! generator's facing, in metres.
//!
//! With a normal weight `lambda > 0` (metres) the CVT runs in position-and-normal space: a sample
//! `y` on a triangle of outward unit normal `n` is at squared distance
//! `|y - z|^2 + lambda^2 |n - m|^2` from a generator at `z` facing `m`, and `m` follows its
//! region's mean normal by the same update rule as `z` follows its mean position (`m` is not
//! projected: it is the region's mean facing, shorter than 1 where the region bends). Two
//! samples a few metres apart on faces at right angles are then `lambda sqrt 2` apart: a region
//! gathers surface that faces one way, which is what a camera flown out along its generator's
//! facing sees. `lambda = 0` is the paper's CVT; every facing starts at zero, so the first
//! iteration is by position alone.

use super::candidates::squared_distance;
use crate::geometry::Point;

/// The facing term: `weight2 = lambda^2` and each generator's facing `m_i`.
pub(super) struct Facing<'a> {
    pub(super) weight2: f64,
    pub(super) normals: &'a [Point],
}

impl Facing<'_> {
    /// `lambda^2 |n - m_i|^2`, m^2.
    #[inline]
    pub(super) fn term(&self, i: usize, normal: Point) -> f64 {
        self.weight2 * squared_distance(normal, self.normals[i])
    }
}
