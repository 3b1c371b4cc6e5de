//! The regular elevation grid a surface is built from, and the plane geometry that the grid's
//! queries share (`pseudo_angle`, the cheap monotone angle of the horizons and skylines).
//!
//! A leaf below [`crate::surface::heightfield`] and the internal `skyline` module: it imports only
//! [`crate::geometry`].
//!
//! ```
//! use uavcov::surface::grid::Grid;
//! // A 2 x 3 grid (rows along y, columns along x) of 1 m cells starting at (10, 20).
//! let z = vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
//! let g = Grid { ny: 2, nx: 3, dx: 1.0, dy: 1.0, x0: 10.0, y0: 20.0, z, vertex_of_node: vec![] };
//! assert_eq!(g.node_point(4), [11.0, 21.0, 4.0]);
//! assert_eq!(g.cell_nodes(0, 1), [1, 2, 5, 4]);
//! let [upper, lower] = g.cell_triangles(0, 0);
//! assert!(upper.is_some() && lower.is_some());
//! // the heights rise 1 m per metre along x and 3 m per metre along y: normal (-1, -3, 1) / |.|
//! let n = g.node_normal(1).unwrap();
//! assert!((n[0] + 1.0 / 11f64.sqrt()).abs() < 1e-12 && (n[2] - 1.0 / 11f64.sqrt()).abs() < 1e-12);
//! ```

use parry3d_f64::math::Vector;

use crate::geometry::{v, Point};

/// The regular elevation grid a surface was built from, kept for the grid fast path and targets.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Number of rows (along y).
    pub ny: usize,
    /// Number of columns (along x).
    pub nx: usize,
    /// Cell size along x, metres.
    pub dx: f64,
    /// Cell size along y, metres.
    pub dy: f64,
    /// x of column 0, metres.
    pub x0: f64,
    /// y of row 0, metres.
    pub y0: f64,
    /// Heights, row-major `(ny, nx)`; NaN marks nodata.
    pub z: Vec<f64>,
    /// For each grid node, its index among the surface vertices, or `u32::MAX` when unused.
    pub vertex_of_node: Vec<u32>,
}

/// A monotone stand-in for the angle of `(x, y)`, in `[0, 4)`: the diamond angle, which needs a
/// division instead of an arctangent.
#[inline(always)]
pub(crate) fn pseudo_angle(x: f64, y: f64) -> f64 {
    if y >= 0.0 {
        if x >= 0.0 {
            y / (x + y)
        } else {
            1.0 - x / (y - x)
        }
    } else if x < 0.0 {
        2.0 - y / (-x - y)
    } else {
        3.0 + x / (x - y)
    }
}

/// `x` rounded down and clamped to `[0, last]`, as an index (NaN gives 0): `(x as
/// usize).min(last)`, the same value for every `x`, in two comparisons and one conversion where
/// the saturating cast takes about a dozen instructions. For the indices computed for every box
/// of a horizon and every sight line (sectors and distance bins).
#[inline(always)]
#[allow(unsafe_code, reason = "an unchecked conversion of a value clamped just before it")]
pub(crate) fn floor_index(x: f64, last: u32) -> usize {
    let top = f64::from(last);
    let x = if x > 0.0 { x } else { 0.0 }; // NaN fails the comparison: 0
    let x = if x < top { x } else { top };
    // SAFETY: `x` lies in `[0, last]` and `last` fits in a `u32`.
    unsafe { x.to_int_unchecked::<u32>() as usize }
}

impl Grid {
    /// The position of node `k` (row-major), as the mesh path computes it.
    #[inline(always)]
    #[must_use]
    pub fn node_point(&self, k: usize) -> Point {
        let (i, j) = (k / self.nx, k % self.nx);
        [self.x0 + j as f64 * self.dx, self.y0 + i as f64 * self.dy, self.z[k]]
    }

    /// Nodes `[a, b, c, d] = [(i, j), (i, j+1), (i+1, j+1), (i+1, j)]` of cell `(i, j)`.
    #[inline(always)]
    #[must_use]
    pub fn cell_nodes(&self, i: usize, j: usize) -> [usize; 4] {
        let a = i * self.nx + j;
        [a, a + 1, a + self.nx + 1, a + self.nx]
    }

    /// The unit normal of the surface at node `k` (pointing up): the sum of the normals of the
    /// (up to six) triangles around it, each weighted by its area (the cross product of two
    /// edges), normalised. `None` when no triangle around the node is whole.
    #[must_use]
    pub fn node_normal(&self, k: usize) -> Option<Point> {
        let (i, j) = (k / self.nx, k % self.nx);
        let mut sum = [0.0f64; 3];
        let mut add = |t: Option<[Vector; 3]>| {
            if let Some([a, b, c]) = t {
                let (e, f) = (b - a, c - a);
                sum[0] += e.y * f.z - e.z * f.y;
                sum[1] += e.z * f.x - e.x * f.z;
                sum[2] += e.x * f.y - e.y * f.x;
            }
        };
        // node (i, j) is corner a of cell (i, j), b of (i, j - 1), c of (i - 1, j - 1), d of (i - 1, j)
        if i + 1 < self.ny && j + 1 < self.nx {
            let [t0, t1] = self.cell_triangles(i, j);
            add(t0);
            add(t1);
        }
        if i + 1 < self.ny && j > 0 {
            add(self.cell_triangles(i, j - 1)[0]);
        }
        if i > 0 && j > 0 {
            let [t0, t1] = self.cell_triangles(i - 1, j - 1);
            add(t0);
            add(t1);
        }
        if i > 0 && j + 1 < self.nx {
            add(self.cell_triangles(i - 1, j)[1]);
        }
        let norm = (sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]).sqrt();
        (norm > 0.0 && norm.is_finite()).then(|| [sum[0] / norm, sum[1] / norm, sum[2] / norm])
    }

    /// The steepest slope of the surface (rise over horizontal run, the largest gradient norm of
    /// its triangles), or `None` when there is nodata. A bound for how much the height under a
    /// point changes when the point moves: `|h(a) - h(b)| <= slope |a - b|` on the whole grid.
    ///
    /// ```
    /// use uavcov::surface::grid::Grid;
    /// // Rising 1 m per metre along x and 3 m per metre along y: every triangle has slope sqrt(10).
    /// let g = Grid { ny: 2, nx: 3, dx: 1.0, dy: 1.0, x0: 0.0, y0: 0.0, z: vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0], vertex_of_node: vec![] };
    /// assert!((g.max_slope().unwrap() - 10f64.sqrt()).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn max_slope(&self) -> Option<f64> {
        if self.z.iter().any(|h| h.is_nan()) {
            return None;
        }
        let mut steepest = 0.0f64;
        for i in 0..self.ny - 1 {
            for j in 0..self.nx - 1 {
                steepest = steepest.max(self.cell_slope(i, j));
            }
        }
        Some(steepest)
    }

    /// The steeper slope of cell `(i, j)`'s two triangles (NaN with nodata at a corner).
    #[inline]
    #[must_use]
    pub fn cell_slope(&self, i: usize, j: usize) -> f64 {
        let [a, b, c, d] = self.cell_nodes(i, j).map(|k| self.z[k]);
        let (inv_dx, inv_dy) = (1.0 / self.dx, 1.0 / self.dy);
        // [a, b, c] rises along x from a to b and along y from b to c; [a, c, d] along x from d
        // to c and along y from a to d.
        let upper = ((b - a) * inv_dx).hypot((c - b) * inv_dy);
        let lower = ((c - d) * inv_dx).hypot((d - a) * inv_dy);
        if upper.is_nan() || lower.is_nan() {
            f64::NAN
        } else {
            upper.max(lower)
        }
    }

    /// The corners of the two triangles of cell `(i, j)`, `[a, b, c]` and `[a, c, d]`, or `None`
    /// for a triangle with a nodata corner.
    #[inline(always)]
    #[must_use]
    pub fn cell_triangles(&self, i: usize, j: usize) -> [Option<[Vector; 3]>; 2] {
        let [a, b, c, d] = self.cell_nodes(i, j).map(|k| v(self.node_point(k)));
        let ok = |q: Vector| !q.z.is_nan();
        [(ok(a) && ok(b) && ok(c)).then_some([a, b, c]), (ok(a) && ok(c) && ok(d)).then_some([a, c, d])]
    }
}
