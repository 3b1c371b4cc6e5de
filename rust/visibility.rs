//! Who sees what: the coverage objective of the paper (its eq. 1, discretised on targets).
//!
//! A target `q` is seen from a UAV at `p` when `|p - q| <= d_max` and the segment from `p`
//! towards `q`, stopped 0.1 % of its length short of `q`, crosses no triangle. Coverage is the
//! weighted share of targets seen by at least one UAV.
//!
//! Work is split into fixed chunks of neighbouring targets, stolen by rayon's threads; each
//! chunk first drops the UAVs out of range of its bounding box, and a target stops at the first
//! UAV that sees it. Chunks are combined in order, so results are identical for any thread count.
//!
//! ```
//! use uavcov::mesh::Surface;
//! use uavcov::visibility::{Targets, Visibility};
//! let s = Surface::from_grid(vec![0.0; 121], 11, 11, 1.0, 1.0, 0.0, 0.0).unwrap();
//! let targets = Targets::of_surface(&s, 1.0).unwrap();
//! let vis = Visibility::new(std::sync::Arc::new(s), targets, 100.0).unwrap();
//! // One UAV high above a flat square sees all of it.
//! assert_eq!(vis.coverage(&[[5.0, 5.0, 20.0]], 1).unwrap(), 1.0);
//! ```

use std::sync::Arc;

use rayon::prelude::*;

use crate::error::{ensure, Result};
use crate::mesh::{Point, Surface};
use crate::sampling::default_targets;
use crate::threads;

/// Targets per chunk: small enough to balance very unequal UAV footprints, large enough that
/// the per-chunk culling and rayon's ~1 us per task stay negligible.
const CHUNK: usize = 256;

/// Points to see and the area (m^2) each stands for.
#[derive(Debug, Clone)]
pub struct Targets {
    points: Vec<Point>,
    weights: Vec<f64>,
    total_weight: f64,
    /// Bounding box `(mins, maxs)` of each chunk of `CHUNK` consecutive targets.
    chunk_bounds: Vec<(Point, Point)>,
}

impl Targets {
    /// User-given targets; weights default to 1 each.
    ///
    /// # Errors
    /// When a coordinate is not finite, weights have the wrong length or a negative or non-finite
    /// value, or all weights are zero.
    pub fn new(points: Vec<Point>, weights: Option<Vec<f64>>) -> Result<Self> {
        ensure!(!points.is_empty(), "there must be at least one target");
        ensure!(points.iter().all(|q| q.iter().all(|c| c.is_finite())), "target coordinates must be finite");
        let weights = weights.unwrap_or_else(|| vec![1.0; points.len()]);
        ensure!(weights.len() == points.len(), "{} weights for {} targets", weights.len(), points.len());
        ensure!(weights.iter().all(|w| w.is_finite() && *w >= 0.0), "target weights must be finite and >= 0");
        let total_weight: f64 = weights.iter().sum();
        ensure!(total_weight > 0.0, "target weights are all zero");
        let chunk_bounds = points.chunks(CHUNK).map(bounds).collect();
        Ok(Self { points, weights, total_weight, chunk_bounds })
    }

    /// The surface's default targets (see [`default_targets`]).
    pub fn of_surface(surface: &Surface, density: f64) -> Result<Self> {
        let (points, weights) = default_targets(surface, density)?;
        Self::new(points, Some(weights))
    }

    /// The target points.
    pub fn points(&self) -> &[Point] {
        &self.points
    }

    /// The weight of each target.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Number of targets.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Always false: a target set is never empty.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

fn bounds(points: &[Point]) -> (Point, Point) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for q in points {
        for k in 0..3 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    (lo, hi)
}

fn squared_distance_to_box(q: Point, (lo, hi): (Point, Point)) -> f64 {
    (0..3).map(|k| (lo[k] - q[k]).max(0.0).max(q[k] - hi[k]).powi(2)).sum()
}

#[inline]
fn squared_distance(a: Point, b: Point) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
}

/// How many targets each UAV sees, and how many only it sees.
#[derive(Debug, Clone, PartialEq)]
pub struct UavCounts {
    /// Targets each UAV sees.
    pub seen: Vec<u64>,
    /// Targets each UAV is the only one to see (its marginal contribution).
    pub exclusive: Vec<u64>,
    /// Weight of the targets each UAV sees.
    pub seen_weight: Vec<f64>,
    /// Weight of the targets only each UAV sees.
    pub exclusive_weight: Vec<f64>,
    /// Total weight of all targets (the denominator of a share).
    pub total_weight: f64,
}

/// The coverage objective for one surface, one target set and one sensing range.
pub struct Visibility {
    surface: Arc<Surface>,
    targets: Targets,
    d_max: f64,
}

impl Visibility {
    /// # Errors
    /// When `d_max` is not finite and positive.
    pub fn new(surface: Arc<Surface>, targets: Targets, d_max: f64) -> Result<Self> {
        ensure!(d_max.is_finite() && d_max > 0.0, "d_max must be finite and > 0, got {d_max}");
        Ok(Self { surface, targets, d_max })
    }

    /// The surface.
    pub fn surface(&self) -> &Arc<Surface> {
        &self.surface
    }

    /// The targets.
    pub fn targets(&self) -> &Targets {
        &self.targets
    }

    /// The sensing range, m.
    pub fn d_max(&self) -> f64 {
        self.d_max
    }

    fn check_uavs(uavs: &[Point]) -> Result<()> {
        ensure!(!uavs.is_empty(), "there must be at least one UAV");
        ensure!(uavs.iter().all(|q| q.iter().all(|c| c.is_finite())), "UAV coordinates must be finite");
        Ok(())
    }

    /// The UAVs within range of any point of a chunk's bounding box, nearest first: the nearest
    /// UAV is the likeliest to see a target, and a target stops at the first UAV that does.
    fn in_range_of(&self, chunk: usize, uavs: &[Point], into: &mut Vec<Point>) {
        into.clear();
        let d2 = self.d_max * self.d_max;
        let b = self.targets.chunk_bounds[chunk];
        into.extend(uavs.iter().copied().filter(|&u| squared_distance_to_box(u, b) <= d2));
        let centre = [0, 1, 2].map(|k| 0.5 * (b.0[k] + b.1[k]));
        into.sort_by(|&u, &w| squared_distance(u, centre).total_cmp(&squared_distance(w, centre)));
    }

    fn sees(&self, uav: Point, target: Point) -> bool {
        squared_distance(uav, target) <= self.d_max * self.d_max && self.surface.line_of_sight(uav, target)
    }

    /// For each target, whether at least one UAV sees it.
    pub fn seen(&self, uavs: &[Point], n_threads: usize) -> Result<Vec<bool>> {
        Self::check_uavs(uavs)?;
        let chunks: Vec<Vec<bool>> = threads::run(n_threads, || {
            self.targets
                .points
                .par_chunks(CHUNK)
                .enumerate()
                .map_init(Vec::new, |near, (c, chunk)| {
                    self.in_range_of(c, uavs, near);
                    chunk.iter().map(|&q| near.iter().any(|&u| self.sees(u, q))).collect()
                })
                .collect()
        });
        Ok(chunks.concat())
    }

    /// The weighted share of targets seen by at least one UAV, in `[0, 1]`.
    pub fn coverage(&self, uavs: &[Point], n_threads: usize) -> Result<f64> {
        let seen = self.seen(uavs, n_threads)?;
        Ok(self.share(&seen))
    }

    /// The weighted share of the targets flagged in `mask`.
    pub fn share(&self, mask: &[bool]) -> f64 {
        // A fold from +0.0, not `sum()`, whose empty sum is -0.0.
        let covered = mask.iter().zip(&self.targets.weights).filter(|(s, _)| **s).fold(0.0, |acc, (_, w)| acc + w);
        (covered / self.targets.total_weight).min(1.0)
    }

    /// Per-UAV counts: every UAV in range is tested for every target (no early stop).
    pub fn per_uav(&self, uavs: &[Point], n_threads: usize) -> Result<UavCounts> {
        Self::check_uavs(uavs)?;
        let n = uavs.len();
        let d2 = self.d_max * self.d_max;
        let partials: Vec<UavCounts> = threads::run(n_threads, || {
            self.targets
                .points
                .par_chunks(CHUNK)
                .enumerate()
                .map_init(
                    || Vec::with_capacity(n),
                    |seers, (c, chunk)| {
                        let mut out = UavCounts::zeros(n, 0.0);
                        let b = self.targets.chunk_bounds[c];
                        let near: Vec<usize> =
                            (0..n).filter(|&i| squared_distance_to_box(uavs[i], b) <= d2).collect();
                        for (k, &q) in chunk.iter().enumerate() {
                            let w = self.targets.weights[c * CHUNK + k];
                            seers.clear();
                            seers.extend(near.iter().copied().filter(|&i| self.sees(uavs[i], q)));
                            for &i in seers.iter() {
                                out.seen[i] += 1;
                                out.seen_weight[i] += w;
                            }
                            if let [only] = seers[..] {
                                out.exclusive[only] += 1;
                                out.exclusive_weight[only] += w;
                            }
                        }
                        out
                    },
                )
                .collect()
        });
        let mut total = UavCounts::zeros(n, self.targets.total_weight);
        for part in partials {
            for i in 0..n {
                total.seen[i] += part.seen[i];
                total.exclusive[i] += part.exclusive[i];
                total.seen_weight[i] += part.seen_weight[i];
                total.exclusive_weight[i] += part.exclusive_weight[i];
            }
        }
        Ok(total)
    }
}

impl UavCounts {
    fn zeros(n: usize, total_weight: f64) -> Self {
        Self {
            seen: vec![0; n],
            exclusive: vec![0; n],
            seen_weight: vec![0.0; n],
            exclusive_weight: vec![0.0; n],
            total_weight,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(n: usize) -> Arc<Surface> {
        Arc::new(Surface::from_grid(vec![0.0; n * n], n, n, 1.0, 1.0, 0.0, 0.0).unwrap())
    }

    #[test]
    fn range_limits_a_flat_plane_to_a_disk() {
        let s = flat(41);
        let vis = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 10.0).unwrap();
        let seen = vis.seen(&[[20.0, 20.0, 6.0]], 1).unwrap();
        for (q, &v) in vis.targets().points().iter().zip(&seen) {
            let r2 = (q[0] - 20.0).powi(2) + (q[1] - 20.0).powi(2);
            assert_eq!(v, r2 + 36.0 <= 100.0, "{q:?}");
        }
    }

    #[test]
    fn a_wall_hides_what_is_behind_it() {
        // Ground y in [0, 10] at z = 0 with a 5 m high wall along x = 5.
        let s = Arc::new(Surface::new(
            vec![
                [0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0], [0.0, 10.0, 0.0],
                [5.0, 0.0, 0.0], [5.0, 10.0, 0.0], [5.0, 10.0, 5.0], [5.0, 0.0, 5.0],
            ],
            vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]],
        )
        .unwrap());
        let targets = Targets::new(vec![[2.0, 5.0, 0.0], [8.0, 5.0, 0.0]], None).unwrap();
        let vis = Visibility::new(s, targets, 50.0).unwrap();
        assert_eq!(vis.seen(&[[1.0, 5.0, 1.0]], 1).unwrap(), vec![true, false]);
        let counts = vis.per_uav(&[[1.0, 5.0, 1.0], [9.0, 5.0, 1.0]], 2).unwrap();
        assert_eq!(counts.seen, vec![1, 1]);
        assert_eq!(counts.exclusive, vec![1, 1]);
    }

    #[test]
    fn thread_count_does_not_change_results() {
        let n = 60;
        let z: Vec<f64> = (0..n * n).map(|k| ((k % n) as f64 * 0.3).sin() * 4.0 + ((k / n) as f64 * 0.2).cos() * 3.0).collect();
        let s = Arc::new(Surface::from_grid(z, n, n, 1.0, 1.0, 0.0, 0.0).unwrap());
        let vis = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 20.0).unwrap();
        let uavs = [[10.0, 10.0, 9.0], [40.0, 30.0, 8.0], [50.0, 50.0, 12.0]];
        let one = vis.seen(&uavs, 1).unwrap();
        assert_eq!(one, vis.seen(&uavs, 2).unwrap());
        assert_eq!(vis.coverage(&uavs, 1).unwrap(), vis.coverage(&uavs, 3).unwrap());
        assert_eq!(vis.per_uav(&uavs, 1).unwrap(), vis.per_uav(&uavs, 2).unwrap());
        assert!(one.iter().any(|&v| v) && one.iter().any(|&v| !v));
    }

    #[test]
    fn bad_input_is_an_error() {
        let s = flat(3);
        let t = || Targets::of_surface(&s, 1.0).unwrap();
        assert!(Visibility::new(s.clone(), t(), 0.0).is_err());
        assert!(Visibility::new(s.clone(), t(), f64::NAN).is_err());
        let vis = Visibility::new(s.clone(), t(), 5.0).unwrap();
        assert!(vis.seen(&[], 1).is_err());
        assert!(vis.seen(&[[f64::NAN, 0.0, 1.0]], 1).is_err());
        assert!(Targets::new(vec![], None).is_err());
        assert!(Targets::new(vec![[0.0; 3]], Some(vec![-1.0])).is_err());
        assert!(Targets::new(vec![[0.0; 3]], Some(vec![0.0])).is_err());
    }
}
