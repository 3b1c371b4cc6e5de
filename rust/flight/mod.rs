//! The admissible UAV configurations of the paper's eq. 2, judged for a batch of candidates in
//! one pass.
//!
//! A configuration (one position per UAV) is admissible when every UAV is inside the closed x-y
//! bounds and at most `z_max` high, has a clearance of at least `h_min` (and at most `h_max`
//! when set), every pair is at least `d_safe` apart, and, with `check_moves`, every UAV that
//! moves does so along a segment that crosses no triangle.
//!
//! The clearance has two meanings ([`Clearance`]). [`Clearance::Vertical`] (height fields,
//! the paper's): the distance straight down to the highest surface below. [`Clearance::Standoff`]
//! (structures): the least 3D distance to any triangle, with some surface straight below (not
//! under the ground) and the UAV inside no closed solid; a UAV may fly under a bridge deck. The
//! standoff is judged with sphere queries on the BVH that stop at the first triangle found
//! within `h_min` (or `h_max`); the inside test (three rays, see [`crate::surface::mesh::Surface::inside`])
//! is asked only of a UAV that did not reach its position by a checked clear move from a
//! position outside every solid: a closed surface separates its inside from the outside, so a
//! straight move that crosses no triangle cannot enter a solid. The
//! rules are `uavcov.constraints`'s; this is the same test fused, so that an optimiser's batch of
//! candidates costs one call instead of one per kind of check.
//!
//! ```
//! use uavcov::flight::{admissible_mask, Clearance, FlightLimits};
//! use uavcov::Surface;
//! // A flat 10 m x 10 m ground, two UAVs 2 m up, and three candidate configurations.
//! let ground = Surface::from_grid(vec![0.0; 11 * 11], 11, 11, 1.0, 1.0, 0.0, 0.0)?;
//! let limits = FlightLimits { bounds: [0.0, 0.0, 10.0, 10.0], h_min: 1.0, h_max: Some(4.0), z_max: 50.0, d_safe: 1.0, check_moves: true, clearance: Clearance::Vertical };
//! let now = [[2.0, 2.0, 2.0], [6.0, 6.0, 2.0]];
//! let candidates = [
//!     [2.5, 2.0, 2.0], [6.0, 6.5, 3.0], // admissible
//!     [2.0, 2.0, 5.0], [6.0, 6.0, 2.0], // the first UAV above h_max
//!     [5.5, 6.0, 2.0], [6.0, 6.0, 2.0], // 0.5 m apart, under d_safe
//! ];
//! assert_eq!(admissible_mask(&ground, &limits, &now, &candidates, 1)?, vec![true, false, false]);
//! # Ok::<(), uavcov::Error>(())
//! ```

use rayon::prelude::*;

use crate::error::{try_with_capacity, Error, Result};
use crate::geometry::{in_bounds, Point, MAX_COORDINATE};
use crate::surface::mesh::Surface;
use crate::threads;

/// What `h_min` and `h_max` bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Clearance {
    /// The distance straight down to the highest surface below (height fields; the default).
    #[default]
    Vertical,
    /// The least 3D distance to any surface, above the ground and outside every closed solid.
    Standoff,
}

impl std::str::FromStr for Clearance {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s {
            "vertical" => Ok(Self::Vertical),
            "standoff" => Ok(Self::Standoff),
            _ => Err(Error::InvalidInput(format!("clearance must be \"vertical\" or \"standoff\", got {s:?}"))),
        }
    }
}

/// The flight limits of eq. 2, resolved against one surface (metres, the surface's frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlightLimits {
    /// `[xmin, ymin, xmax, ymax]`, closed.
    pub bounds: [f64; 4],
    /// Least clearance straight down to the surface.
    pub h_min: f64,
    /// Most clearance straight down to the surface (`None`: no ceiling above ground).
    pub h_max: Option<f64>,
    /// Highest absolute altitude.
    pub z_max: f64,
    /// Least distance between two UAVs.
    pub d_safe: f64,
    /// Whether every move must cross no triangle.
    pub check_moves: bool,
    /// What `h_min` and `h_max` bound.
    pub clearance: Clearance,
}

impl FlightLimits {
    /// Inside the x-y bounds and under `z_max` (a NaN coordinate is neither).
    fn inside(&self, q: Point) -> bool {
        let [xmin, ymin, xmax, ymax] = self.bounds;
        q[0] >= xmin && q[0] <= xmax && q[1] >= ymin && q[1] <= ymax && q[2] <= self.z_max
    }

    /// Every pair at least `d_safe` apart, the squared distance summed x, then y, then z.
    fn separated(&self, config: &[Point]) -> bool {
        if config.len() < 2 || self.d_safe <= 0.0 {
            return true;
        }
        let least = self.d_safe * self.d_safe;
        config.iter().enumerate().all(|(i, a)| {
            config[i + 1..].iter().all(|b| {
                let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
                d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= least
            })
        })
    }

    /// A clearance the limits accept (finite: there is a surface below).
    fn clear_enough(&self, clearance: f64) -> bool {
        clearance.is_finite() && clearance >= self.h_min && self.h_max.is_none_or(|h| clearance <= h)
    }

    /// [`Self::clear_enough`] of `q`'s clearance over `surface`. Over a grid, a point well inside
    /// one of its triangles is judged from that triangle's plane unless its height above it is
    /// within the rounding bound of a limit; the exact vertical query decides the rest. The
    /// answers are the exact query's: within the bound of a limit, that query decides; beyond it,
    /// both clearances lie on the same side of every limit, and the query hits the triangle.
    fn clear_enough_over(&self, surface: &Surface, q: Point) -> bool {
        if let Some((h, bound)) = surface.heightfield().and_then(|f| f.interior_height(q[0], q[1])) {
            let c = q[2] - h;
            let bound = bound + 1e-9 * q[2].abs();
            let low = c - bound >= self.h_min && c - bound > 0.0;
            let high = self.h_max.is_none_or(|m| c + bound <= m);
            if low && high {
                return true;
            }
            if c + bound < self.h_min || self.h_max.is_some_and(|m| c - bound > m) {
                return false; // under the floor (or the surface) or over the ceiling either way
            }
        }
        self.clear_enough(surface.clearance(q))
    }

    /// Whether `config` is admissible, moving from `current` (same length).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when a UAV that passes the bounds has a coordinate beyond
    /// [`MAX_COORDINATE`] (a `z_max` that large lets one through): the surface is not queried
    /// so far out.
    pub fn admissible(&self, surface: &Surface, current: &[Point], config: &[Point]) -> Result<bool> {
        let now = self.now(surface, current)?;
        self.admissible_from(surface, current, &now, config)
    }

    /// What the standoff limits learn once about `current` for a whole batch (empty otherwise).
    fn now(&self, surface: &Surface, current: &[Point]) -> Result<Now> {
        if self.clearance != Clearance::Standoff {
            return Ok(Now::default());
        }
        let distance = current.iter().map(|&q| surface.distance(q)).collect::<Result<_>>()?;
        let outside = if self.check_moves {
            current.iter().map(|&q| surface.inside(q).map(|inside| !inside)).collect::<Result<_>>()?
        } else {
            vec![]
        };
        Ok(Now { distance, outside })
    }

    /// The standoff of `b` within the limits, and some surface below it. `from` is `b`'s UAV's
    /// current position and its distance to the surface, when known: the distance is
    /// 1-Lipschitz, so a UAV that moved by `s` is within `s` of its old distance, and when that
    /// whole interval keeps the limits (by more than the rounding of the two distances) the
    /// sphere queries would say so too and are skipped.
    fn standoff_ok(&self, surface: &Surface, b: Point, from: Option<(Point, f64)>) -> Result<bool> {
        let known = from.is_some_and(|(a, d)| {
            let step = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt();
            let slack = 1e-9 * (1.0 + d + step + a.iter().chain(&b).fold(0.0_f64, |m, c| m.max(c.abs())));
            d - step - slack >= self.h_min && self.h_max.is_none_or(|h| d + step + slack <= h)
        });
        if !known {
            if self.h_min > 0.0 && surface.within(b, self.h_min, false)? {
                return Ok(false);
            }
            if let Some(h) = self.h_max {
                if !surface.within(b, h, true)? {
                    return Ok(false);
                }
            }
        }
        Ok(surface.surface_below(b))
    }

    /// [`Self::admissible`] given [`Self::now`] of `current`.
    fn admissible_from(&self, surface: &Surface, current: &[Point], now: &Now, config: &[Point]) -> Result<bool> {
        if !config.iter().all(|&q| self.inside(q)) || !self.separated(config) {
            return Ok(false);
        }
        if let Some(q) = config.iter().find(|q| !in_bounds(**q)) {
            return Err(Error::InvalidInput(format!("a candidate has a coordinate beyond {MAX_COORDINATE:e} m in magnitude: {q:?}")));
        }
        if self.clearance == Clearance::Standoff {
            return self.standoff_admissible(surface, current, now, config);
        }
        if !config.iter().all(|&q| self.clear_enough_over(surface, q)) {
            return Ok(false);
        }
        if self.check_moves {
            // a UAV that stays has nothing to cross
            return Ok(current.iter().zip(config).all(|(&a, &b)| a == b || surface.segment_clear(a, b)));
        }
        Ok(true)
    }
}

impl FlightLimits {
    /// The standoff rules for a configuration already inside the bounds and separated.
    fn standoff_admissible(&self, surface: &Surface, current: &[Point], now: &Now, config: &[Point]) -> Result<bool> {
        for (i, &q) in config.iter().enumerate() {
            let from = now.distance.get(i).map(|&d| (current[i], d));
            if !self.standoff_ok(surface, q, from)? {
                return Ok(false);
            }
        }
        for (i, (&a, &b)) in current.iter().zip(config).enumerate() {
            let moved_clear = self.check_moves && (a == b || surface.segment_clear(a, b));
            if self.check_moves && !moved_clear {
                return Ok(false);
            }
            // reached by a clear move from outside every solid: outside too (see the module docs)
            let known_outside = moved_clear && now.outside.get(i).copied().unwrap_or(false);
            if !known_outside && surface.inside(b)? {
                return Ok(false);
            }
        }
        Ok(true)
    }
}

/// What the standoff limits know of the current positions: each UAV's distance to the surface,
/// and (moves checked) whether it is outside every solid. Empty: nothing known, every query made.
#[derive(Debug, Default)]
struct Now {
    distance: Vec<f64>,
    outside: Vec<bool>,
}

/// Which of the candidate configurations are admissible.
///
/// `candidates` holds `M` configurations of `current.len()` UAVs one after the other
/// (`M * N` points); the answer has `M` entries, the same for any `n_threads` (0: every core).
///
/// # Errors
/// [`Error::InvalidInput`] when there is no UAV, `candidates` is not a whole number of
/// configurations, `current` is not finite, or as [`FlightLimits::admissible`].
pub fn admissible_mask(
    surface: &Surface,
    limits: &FlightLimits,
    current: &[Point],
    candidates: &[Point],
    n_threads: usize,
) -> Result<Vec<bool>> {
    let n = current.len();
    if n == 0 {
        return Err(Error::InvalidInput("current holds no UAV".into()));
    }
    if candidates.len() % n != 0 {
        return Err(Error::InvalidInput(format!("{} candidate points are not a whole number of {n}-UAV configurations", candidates.len())));
    }
    if let Some(q) = current.iter().find(|q| !in_bounds(**q) || q.iter().any(|c| !c.is_finite())) {
        return Err(Error::InvalidInput(format!("current has a coordinate that is not finite or beyond {MAX_COORDINATE:e} m: {q:?}")));
    }
    let mut out: Vec<bool> = try_with_capacity(candidates.len() / n, "the admissible mask")?;
    let now = limits.now(surface, current)?;
    let judged: Result<Vec<bool>> =
        threads::run(n_threads, || candidates.par_chunks(n).map(|config| limits.admissible_from(surface, current, &now, config)).collect());
    out.extend(judged?);
    Ok(out)
}

#[cfg(test)]
mod tests;
