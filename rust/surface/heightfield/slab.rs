//! The slab test of the mesh path (`mesh::slab_test`), taken apart so that the height field's
//! tiles and cells can share its pieces: the prepared ray ([`Cast`]), one axis's parameter
//! interval ([`axis`]), and NaN-free `min` and `max`. Every box test of the grid path is built
//! from these, which is what makes its answers the mesh path's to the last bit.

use parry3d_f64::query::Ray;

/// A ray prepared the way the mesh path prepares it.
pub(super) struct Cast {
    pub(super) ray: Ray,
    pub(super) inv: [f64; 3],
}

/// The `[near, far]` parameter interval of one axis of the slab test, exactly as
/// `mesh::slab_test` computes it (an axis the ray does not move along is a position test).
#[inline(always)]
pub(super) fn axis(lo: f64, hi: f64, origin: f64, inv: f64) -> (f64, f64) {
    if inv.is_infinite() {
        if origin < lo || origin > hi {
            (f64::INFINITY, f64::NEG_INFINITY)
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        }
    } else {
        let (a, b) = ((lo - origin) * inv, (hi - origin) * inv);
        if a < b {
            (a, b)
        } else {
            (b, a)
        }
    }
}

/// `a.min(b)` for values that are never NaN: one instruction instead of a NaN-aware sequence.
/// A NaN `a` gives `b` (the comparison fails), which is `f64::min`'s answer too.
#[inline(always)]
pub(super) fn min(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// `a.max(b)` for values that are never NaN; a NaN `a` gives `b`, as for `min`.
#[inline(always)]
pub(super) fn max(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}
