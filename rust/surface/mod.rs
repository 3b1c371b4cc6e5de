//! The surface to cover and the exact line-of-sight tests on it.
//!
//! - [`mesh`]: [`Surface`], a triangle mesh with parry's BVH (or an elevation grid's
//!   [`heightfield::HeightField`]): segment, vertical and closest-point queries.
//! - [`heightfield`]: the exact fast path for elevation grids, without a triangle list.
//! - [`grid`]: the elevation grid itself (shape, spacing, heights, node numbering).
//!
//! Two modules are internal, the bounds both paths use to settle most of a sight line cheaply:
//! `horizon` (per UAV, an upper bound on how steeply the surface rises in each direction and
//! distance) and `skyline` (per target, how steeply the surface rises around it).
//!
//! Imports run downwards: `grid` <- `skyline` <- `horizon` <- `heightfield` <- `mesh`.

pub mod grid;
pub mod heightfield;
pub(crate) mod horizon;
pub mod mesh;
pub(crate) mod skyline;

pub use mesh::Surface;
