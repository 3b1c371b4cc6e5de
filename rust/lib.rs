//! # uavcov
//!
//! The geometric core of uavcov, a library for multi-UAV visual coverage of partially known 3D
//! surfaces (Renzaglia et al., "Multi-UAV Visual Coverage of Partially Known 3D Surfaces:
//! Voronoi-based Initialization to Improve Local Optimizers", arXiv:1901.10272).
//!
//! - [`mesh`]: the surface, a triangle mesh with parry's BVH: segment, vertical and
//!   closest-point queries.
//! - [`heightfield`]: the exact fast path for elevation grids, without a triangle list.
//! - [`grid`]: the elevation grid itself (shape, spacing, heights, node numbering).
//! - [`geometry`]: [`Point`] and what a line of sight is.
//! - [`sampling`]: coverage targets on a surface.
//! - [`sensor`]: what one UAV's sensor reaches before occlusion: its range and, for a camera,
//!   its pinhole field of view.
//! - [`visibility`]: the coverage objective, parallel over targets.
//! - [`tracking`]: coverage of a moving team, each evaluation reusing what the last ones proved
//!   about its sight lines.
//! - [`cvt`]: constrained centroidal Voronoi tessellation of a surface (probabilistic MacQueen).
//! - [`flight`]: the admissible UAV configurations of the paper's eq. 2, for a batch of
//!   candidates in one pass.
//! - [`surrogate`]: CAO's estimator: polynomial regressors, their ridge fit, candidate scores
//!   (dense linear algebra with nalgebra).
//!
//! Two modules are internal: `skyline` (how steeply the surface rises around a grid node, so
//! sight lines to grid-node targets settle their last cells with one comparison) and `threads`
//! (cached thread pools, so results never depend on their size).
//!
//! Modules import downwards only: `geometry` <- `grid` <- `skyline` <- `heightfield` <- `mesh`
//! <- `sampling` <- `visibility` <- `tracking` (`visibility` also imports `sensor`), and `mesh` <- `cvt`, `mesh` <- `flight`; `surrogate` stands
//! alone.
//!
//! The Python binding (`uavcov._core`) sits behind the `python` feature; everything here is
//! plain Rust, so `cargo test` and `cargo bench` need no Python.
//!
//! ## Limits on hostile input
//!
//! Every input gives the right answer or an [`Error`], never a panic, an abort or unbounded
//! work:
//!
//! - Coordinates (vertices, grid nodes and heights, targets, UAVs, query points) are at most
//!   [`geometry::MAX_COORDINATE`] (1e15 m) in magnitude; a grid's spacing must resolve its
//!   coordinates (neighbouring nodes distinct) and every surface has a positive finite area.
//! - Any finite `d_max` is accepted; from [`geometry::UNLIMITED_RANGE`] (4e15 m) on it is an
//!   unlimited range, with the same answers.
//! - Line-of-sight work is bounded on both methods: a UAV's horizon holds at most 4096 x 4096
//!   bounds (and all UAVs of one evaluation 2^26), and the grid method's walk hands a segment
//!   it cannot resolve (margins wider than a cell, or 16 halvings deep) to the tile quadtree.
//! - Allocations whose size the input decides are checked (`try_reserve`), so a refusal by the
//!   system is [`Error::TooLarge`]; the CVT's and per-UAV counts' per-chunk sums are held in
//!   batches of bounded size (256 and 128 MiB). Fixed limits: [`mesh::MAX_TRIANGLES`] for the
//!   mesh method and the CVT, [`sampling::MAX_TARGETS`] area targets, 2^32 grid nodes.
//! - The binding catches any residual panic as [`Error::Internal`] (raised as
//!   `uavcov.errors.UavcovError`), so none reaches Python as a `PanicException`.
//!
//! ```
//! use std::sync::Arc;
//! use uavcov::{Surface, Targets, Visibility};
//! // A flat 20 m x 20 m grid at 1 m, every node a target, and one UAV 10 m above its centre.
//! let surface = Arc::new(Surface::from_grid(vec![0.0; 21 * 21], 21, 21, 1.0, 1.0, 0.0, 0.0)?);
//! let targets = Targets::grid_nodes(surface.clone())?;
//! let vis = Visibility::new(surface, targets, 15.0)?;
//! let coverage = vis.coverage(&[[10.0, 10.0, 10.0]], 1)?;
//! assert!(coverage > 0.5 && coverage < 1.0); // the corners are out of range
//! # Ok::<(), uavcov::Error>(())
//! ```

pub mod cvt;
pub mod error;
pub mod flight;
pub mod geometry;
pub mod grid;
pub mod heightfield;
mod horizon;
pub mod mesh;
pub mod sampling;
pub mod sensor;
mod skyline;
pub mod surrogate;
mod threads;
pub mod tracking;
pub mod visibility;

#[cfg(feature = "python")]
mod python;

pub use error::{Error, Result};
pub use geometry::Point;
pub use mesh::Surface;
pub use visibility::{Path, Targets, UavCounts, Visibility};
