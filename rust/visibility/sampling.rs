//! Coverage targets on a surface, with the area each stands for. (The CVT draws its random
//! samples with its own alias-table sampler, in [`crate::cvt`].)
//!
//! ```
//! use uavcov::surface::mesh::Surface;
//! use uavcov::visibility::sampling::default_targets;
//! let s = Surface::from_grid(vec![0.0; 9], 3, 3, 1.0, 1.0, 0.0, 0.0).unwrap();
//! let (points, weights) = default_targets(&s, 1.0).unwrap();
//! assert_eq!(points.len(), 9); // a grid's targets are its nodes
//! assert!((weights.iter().sum::<f64>() - 4.0).abs() < 1e-12);
//! ```

use crate::error::{ensure, try_with_capacity, Result};
use crate::geometry::{p, Point};
use crate::surface::mesh::Surface;

/// Most targets [`area_targets`] makes (32 bytes each: 3.2 GB).
pub const MAX_TARGETS: usize = 100_000_000;

/// Targets of a surface with the area (m^2) each stands for; weights sum to the surface area.
///
/// A grid surface gives its nodes, each standing for a third of the triangles around it. A general
/// mesh gives `density` points per m^2 spread evenly: each triangle is cut into `m^2` congruent
/// sub-triangles (`m = ceil(sqrt(area density))`) and gets a point at each one's centroid. The
/// points are deterministic and never lie on an edge, where visibility is ill-defined.
///
/// # Errors
/// [`Error::InvalidInput`](crate::Error::InvalidInput) when `density` is not finite and positive (meshes only), or when the
/// mesh would get more than [`MAX_TARGETS`] (100 million) targets;
/// [`Error::TooLarge`](crate::Error::TooLarge) when the system refuses their memory.
pub fn default_targets(surface: &Surface, density: f64) -> Result<(Vec<Point>, Vec<f64>)> {
    if surface.grid().is_some() {
        return Ok(vertex_targets(surface));
    }
    area_targets(surface, density)
}

/// `density` points per m^2 spread evenly over any surface (the mesh rule of [`default_targets`]).
///
/// # Errors
/// As [`default_targets`].
pub fn area_targets(surface: &Surface, density: f64) -> Result<(Vec<Point>, Vec<f64>)> {
    ensure!(density.is_finite() && density > 0.0, "target density must be finite and > 0 points per m^2, got {density}");
    // Counted in floating point first, so that no count can overflow before the limit is checked.
    let sides: Vec<f64> = surface.try_areas()?.iter().map(|&a| (a * density).sqrt().ceil().max(1.0)).collect();
    let total: f64 = sides.iter().map(|m| m * m).sum();
    ensure!(
        total.is_finite() && total <= MAX_TARGETS as f64,
        "density {density} per m^2 gives {total:e} targets, over {MAX_TARGETS}; lower it"
    );
    let per_triangle: Vec<usize> = sides.into_iter().map(|m| m as usize).collect();
    let total: usize = per_triangle.iter().map(|m| m * m).sum();
    let mut points = try_with_capacity(total, "the targets")?;
    let mut weights = try_with_capacity(total, "the target weights")?;
    for (f, &m) in per_triangle.iter().enumerate() {
        let [a, b, c] = surface.triangle(f);
        let (ab, ac) = (b - a, c - a);
        let w = surface.areas()[f] / (m * m) as f64;
        let inv = 1.0 / m as f64;
        let mut push = |u: f64, v: f64| {
            points.push(p(a + ab * (u * inv) + ac * (v * inv)));
            weights.push(w);
        };
        for i in 0..m {
            for j in 0..m - i {
                push(i as f64 + 1.0 / 3.0, j as f64 + 1.0 / 3.0); // upward sub-triangle
                if i + j + 2 <= m {
                    push(i as f64 + 2.0 / 3.0, j as f64 + 2.0 / 3.0); // downward sub-triangle
                }
            }
        }
    }
    Ok((points, weights))
}

/// The vertices of a surface, each weighted by a third of the area of the triangles around it.
pub fn vertex_targets(surface: &Surface) -> (Vec<Point>, Vec<f64>) {
    if let Some(field) = surface.heightfield() {
        // Same weights to the last bit, without building the grid's face and area tables.
        return (surface.vertices().collect(), field.vertex_weights());
    }
    let mut weights = vec![0.0; surface.n_vertices()];
    for (t, &area) in surface.faces().iter().zip(surface.areas()) {
        for &k in t {
            weights[k as usize] += area / 3.0;
        }
    }
    (surface.vertices().collect(), weights)
}

#[cfg(test)]
mod tests;
