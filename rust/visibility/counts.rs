//! Per-UAV counts: how many targets each UAV sees, and how many only it sees, in one pass that
//! tests every UAV in range for every target.

use rayon::prelude::*;

use super::{Visibility, CHUNK};
use crate::error::{try_filled, try_with_capacity, Error, Result};
use crate::geometry::Point;
use crate::surface::mesh::Blockers;
use crate::threads;
use crate::visibility::sensor::Sensor;

/// Most per-UAV counters (`UavCounts`, 32 bytes per UAV) held at once by [`Visibility::per_uav`]
/// (128 MiB): its chunks are evaluated in batches of this many counters and summed in chunk
/// order, so the batch size never changes a result.
const COUNTS_BUDGET: usize = 1 << 22;

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
    /// The weighted share of targets seen by at least one UAV: what [`Visibility::coverage`]
    /// returns for the same UAVs, to the last bit.
    pub coverage: f64,
}

impl UavCounts {
    fn zeros(n: usize, total_weight: f64) -> Result<Self> {
        Ok(Self {
            seen: try_filled(0, n, "per-UAV counts")?,
            exclusive: try_filled(0, n, "per-UAV counts")?,
            seen_weight: try_filled(0.0, n, "per-UAV counts")?,
            exclusive_weight: try_filled(0.0, n, "per-UAV counts")?,
            total_weight,
            coverage: 0.0,
        })
    }
}

impl Visibility {
    /// Per-UAV counts, and the coverage: every UAV in range is tested for every target (no early
    /// stop), so one call answers what a per-robot optimiser needs.
    ///
    /// # Errors
    /// As [`Visibility::seen`].
    pub fn per_uav(&self, uavs: &[Point], n_threads: usize) -> Result<UavCounts> {
        self.per_uav_by(uavs, None, n_threads)
    }

    /// [`Visibility::per_uav`] with a sensor per UAV (see [`Visibility::seen_by`]).
    ///
    /// # Errors
    /// As [`Visibility::seen_by`].
    pub fn per_uav_by(&self, uavs: &[Point], sensors: Option<&[Sensor]>, n_threads: usize) -> Result<UavCounts> {
        Self::check_uavs(uavs)?;
        let n = uavs.len();
        let reach = self.reach(uavs, sensors)?;
        let normals = if self.normals_for(reach, false)? { self.targets.normals()? } else { None };
        let mut total = UavCounts::zeros(n, self.targets.total_weight)?;
        let mut mask = try_with_capacity(self.targets.len(), "the seen mask")?;
        // Chunks in batches whose counters fit in COUNTS_BUDGET, each batch summed in chunk order
        // into the total: the same sums, in the same order, as one batch of every chunk.
        let batch = (COUNTS_BUDGET / n).max(1);
        threads::run(n_threads, || {
            let engine = self.engine(uavs, reach)?;
            let mut first = 0;
            while first < self.targets.n_chunks() {
                let last = (first + batch).min(self.targets.n_chunks());
                let partials: Result<Vec<(UavCounts, Vec<bool>)>> = (first..last)
                    .into_par_iter()
                    .map_init(
                        || (Vec::with_capacity(n), Vec::with_capacity(CHUNK), Vec::with_capacity(CHUNK), vec![Blockers::default(); n]),
                        |(seers, points, nodes, blockers), c| {
                            let mut out = UavCounts::zeros(n, 0.0)?;
                            let mut seen = vec![false; self.targets.chunk_len(c)];
                            let b = self.targets.chunk_bounds[c];
                            let near: Vec<usize> = (0..n).filter(|&i| reach.may_reach_box(i, uavs[i], b)).collect();
                            if near.is_empty() {
                                return Ok((out, seen));
                            }
                            points.clear();
                            self.targets.chunk_points(c, points);
                            let mut skylines = self.skylines_of(c, nodes);
                            for (k, &q) in points.iter().enumerate() {
                                let w = self.targets.weights[c * CHUNK + k];
                                let normal = normals.map(|n| n[c * CHUNK + k]);
                                let in_range = |i: &usize| reach.accepts(*i, uavs[*i], q, normal);
                                let sky = match &mut skylines {
                                    Some(s) if near.iter().any(in_range) => Some(s.get(k, || self.skyline(q, nodes.get(k).copied()))),
                                    _ => None,
                                };
                                seers.clear();
                                seers.extend(
                                    near.iter().copied().filter(|i| in_range(i) && engine.line_of_sight(*i, q, sky.as_ref(), blockers)),
                                );
                                for &i in seers.iter() {
                                    out.seen[i] += 1;
                                    out.seen_weight[i] += w;
                                }
                                if let [only] = seers[..] {
                                    out.exclusive[only] += 1;
                                    out.exclusive_weight[only] += w;
                                }
                                seen[k] = !seers.is_empty();
                            }
                            Ok((out, seen))
                        },
                    )
                    .collect();
                for (part, seen) in partials? {
                    for i in 0..n {
                        total.seen[i] += part.seen[i];
                        total.exclusive[i] += part.exclusive[i];
                        total.seen_weight[i] += part.seen_weight[i];
                        total.exclusive_weight[i] += part.exclusive_weight[i];
                    }
                    mask.extend(seen);
                }
                first = last;
            }
            Ok::<_, Error>(())
        })?;
        // The same mask and the same sum as `coverage`, so the same value.
        total.coverage = self.share(&mask);
        Ok(total)
    }
}
