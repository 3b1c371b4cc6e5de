//! # uavcov
//!
//! The geometric core of uavcov, a library for multi-UAV visual coverage of partially known 3D
//! surfaces (Renzaglia et al., "Multi-UAV Visual Coverage of Partially Known 3D Surfaces:
//! Voronoi-based Initialization to Improve Local Optimizers", arXiv:1901.10272).
//!
//! - [`mesh`]: the surface, a triangle mesh with parry's BVH: segment, vertical and
//!   closest-point queries.
//! - [`heightfield`]: the exact fast path for elevation grids, without a triangle list.
//! - [`skyline`]: how steeply the surface rises around a grid node, so sight lines to grid-node
//!   targets settle their last cells with one comparison.
//! - [`sampling`]: coverage targets and area-uniform samples on a surface.
//! - [`visibility`]: the coverage objective, parallel over targets.
//! - [`threads`]: cached thread pools so results never depend on their size.
//! - [`cvt`]: constrained centroidal Voronoi tessellation of a surface (probabilistic MacQueen).
//!
//! The Python binding (`uavcov._core`) sits behind the `python` feature; everything here is
//! plain Rust, so `cargo test` and `cargo bench` need no Python.

pub mod cvt;
pub mod error;
pub mod heightfield;
pub mod mesh;
pub mod sampling;
pub mod skyline;
pub mod threads;
pub mod visibility;

#[cfg(feature = "python")]
mod python;

pub use error::{Error, Result};
pub use mesh::Surface;
pub use visibility::{Targets, UavCounts, Visibility};
