//! Points uniform by (density-weighted) area on a surface, with the triangle each lies in.

use rand::Rng;

use crate::error::{ensure, try_filled, Error, Result};
use crate::geometry::{p, Point};
use crate::surface::mesh::{Surface, MAX_TRIANGLES};

/// Points uniform by (density-weighted) area, with the triangle each lies in.
///
/// It picks the triangle in O(1) with Walker's alias table (no binary search over cumulative
/// areas, whose mispredicted branches cost more than the rest of a draw), uses two 64-bit random
/// words per point, and tells which triangle it drew, which the nearest-generator search and the
/// facing term use.
pub(super) struct TriangleSampler {
    /// `(a, b - a, c - a)` of each triangle.
    frames: Vec<[Point; 3]>,
    /// Slot `f` keeps triangle `f` when the draw's fraction is below `keep[f] / 2^64`...
    keep: Vec<u64>,
    /// ...and takes `alias[f]` otherwise.
    alias: Vec<u32>,
    /// Each triangle's outward (right-hand) unit normal; zero for a triangle without area,
    /// which is never drawn.
    normals: Vec<Point>,
}

impl TriangleSampler {
    pub(super) fn new(surface: &Surface, density: Option<&[f64]>) -> Result<Self> {
        let n = surface.n_triangles();
        if n > MAX_TRIANGLES {
            return Err(Error::TooLarge(format!(
                "the CVT samples surfaces of at most {MAX_TRIANGLES} triangles (about 100 bytes each), got {n}; \
                 tessellate a coarser surface"
            )));
        }
        let areas = surface.try_areas()?;
        if let Some(d) = density {
            ensure!(d.len() == n, "density has {} values for {n} triangles", d.len());
            ensure!(d.iter().all(|x| x.is_finite() && *x >= 0.0), "density must be finite and >= 0 everywhere");
        }
        let weights: Vec<f64> = areas.iter().enumerate().map(|(f, &a)| a * density.map_or(1.0, |d| d[f])).collect();
        let total: f64 = weights.iter().sum();
        ensure!(total.is_finite() && total > 0.0, "the sampling density is zero over the whole surface");
        ensure!(u32::try_from(n).is_ok(), "too many triangles for the CVT sampler: {n}");
        // Vose's construction: scaled weights average 1; each slot below 1 is topped up from
        // one above 1, which becomes its alias.
        let mut scaled: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
        let mut keep = try_filled(u64::MAX, n, "the CVT sampler")?;
        let mut alias: Vec<u32> = (0..n as u32).collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&f| scaled[f] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            keep[s] = (scaled[s] * 2f64.powi(64)) as u64; // saturating cast; scaled[s] < 1
            alias[s] = l as u32;
            scaled[l] -= 1.0 - scaled[s];
            if scaled[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // Leftovers (in either list, by rounding) keep their own triangle always.
        let frames: Vec<[Point; 3]> = (0..n)
            .map(|f| {
                let [a, b, c] = surface.triangle(f);
                [p(a), p(b - a), p(c - a)]
            })
            .collect();
        let normals = frames.iter().map(|&[_, u, v]| unit(cross(u, v))).collect();
        Ok(Self { frames, keep, alias, normals })
    }

    pub(super) fn n_triangles(&self) -> usize {
        self.frames.len()
    }

    /// Triangle `f`'s outward unit normal.
    #[inline]
    pub(super) fn normal(&self, f: usize) -> Point {
        self.normals[f]
    }

    #[inline]
    pub(super) fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> (Point, usize) {
        const SCALE: f64 = 1.0 / 4_294_967_296.0; // 2^-32: 32 bits per barycentric coordinate
                                                  // The high word of r * F is a uniform slot, the low word an independent fraction.
        let x = u128::from(rng.next_u64()) * self.frames.len() as u128;
        let slot = (x >> 64) as usize;
        let f = if (x as u64) < self.keep[slot] { slot } else { self.alias[slot] as usize };
        let bits = rng.next_u64();
        let (r, s) = ((bits >> 32) as f64 * SCALE, (bits & 0xffff_ffff) as f64 * SCALE);
        // The spacings (min, max - min, 1 - max) of two uniform numbers are uniform on the
        // simplex; min and max need no branch (reflecting u + v > 1 mispredicts half the time).
        let (u, v) = (r.min(s), r.max(s) - r.min(s));
        let [a, ab, ac] = self.frames[f];
        ([a[0] + u * ab[0] + v * ac[0], a[1] + u * ab[1] + v * ac[1], a[2] + u * ab[2] + v * ac[2]], f)
    }
}

fn cross(u: Point, v: Point) -> Point {
    [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
}

/// `v / |v|`, or zero for a zero (or non-finite-length) vector.
pub(super) fn unit(v: Point) -> Point {
    let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if length > 0.0 && length.is_finite() {
        [v[0] / length, v[1] / length, v[2] / length]
    } else {
        [0.0; 3]
    }
}
