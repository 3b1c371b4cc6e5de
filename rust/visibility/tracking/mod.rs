//! Coverage along a team's path: what one evaluation proves about its sight lines, carried to
//! the next ones, so that a team that moves a little retests only the lines its moves may change.
//!
//! An optimiser measures coverage at a configuration that differs from the last one by small
//! moves. A [`CoverageTracker`] keeps, for each target, a *certificate*: the UAV that sees it
//! with room to spare, or the UAVs that cannot see it with room to spare. Each UAV has an
//! *anchor* (where it was when its certificates were made) and a *margin* `D`. With `L` the
//! steepest slope of the surface within the range plus `D` of the anchor (horizontally), a UAV
//! displaced by `(dx, dy, dz)` from its anchor has moved a *distance* `|dz| + L hypot(dx, dy)`,
//! and its certificates hold while that distance stays below `D` (less a rounding allowance)
//! and `hypot(dx, dy)` at most `D`, so that every sight line involved stays where `L` holds;
//! beyond it the anchor moves to the UAV and its certificates are made anew. The margin is
//! fixed, or each anchor's own ([`Margin::Adaptive`]): a few of its UAV's recent steps, so
//! that an anchor holds for a few measurements whatever the optimiser's step, and a share of
//! its height above the surface, so that the lowered anchor still sees what the UAV sees.
//!
//! - *Seen with room to spare*: the sight line from the target to the anchor lowered by `D` is
//!   clear. A point of the new line at the fraction `s` of the way from the target lies
//!   `s (dx, dy, dz + D)` from the lowered line's: it is higher by `s (dz + D)`, and the surface
//!   under it higher by at most `L s hypot(dx, dy)`, so it clears the surface by at least
//!   `s (D - distance)` more than the lowered line did, which is positive on the whole tested
//!   stretch (`s >= 1 - SIGHT_FRACTION`). The lowered anchor must be above the surface, or a
//!   line starting below it and never crossing it would pass.
//! - *Blocked with room to spare*: the sight line to the anchor raised by `D` meets the surface
//!   at some `s`. The new line there is at least `s (D - distance)` below the surface; it starts
//!   above the surface (the UAV is checked to be), so it crosses it before: blocked.
//!
//! Both arguments need the surface's height on the straight path between the two points, which
//! the grid's interpolant gives when both UAV positions are over the grid (the targets are) and
//! the grid has no nodata. The allowance: the exact test is parry's triangle test to a few ulps
//! (its shortcuts clear a line only by margins of `1e-9` of the coordinates); the arguments ask
//! a clearance of `1e-8` of the coordinates' magnitude, times `1 + L`, at every point of the new
//! line, which the margin left at the fraction `1 - SIGHT_FRACTION` provides. So every answer a
//! certificate gives is the exact test's, to the last bit; where no certificate holds, the
//! target is tested exactly, as [`Visibility::seen`] does.
//!
//! The answers never depend on the margin, the order of the UAVs, the thread count or the
//! configurations seen before: only the work does. Certificates cost lines to make and pay only
//! while their anchor holds: a UAV makes them at a new anchor when its last one held for three
//! evaluations, or once the new one has held three itself, and an evaluation where no UAV has
//! any is [`Visibility::seen`] itself. A point
//! from which only a few lines are tested (most UAVs and anchors of an evaluation, when
//! certificates settle the rest) tests them without building its whole horizon. A target seen
//! within `range - 2 D` of its seer's anchor is in range of every position the anchor allows
//! (`hypot(dx, dy) <= D` and `|dz| <= D`), so its certificate is checked without computing the
//! target's coordinates, and a chunk's skylines are locked only when one of its targets needs a
//! sight line. A target at the edge of what a UAV sees, which neither certificate settles, is
//! tested from the UAV's own position at every evaluation; what its anchor's two lines showed
//! (the lowered anchor misses it, the raised one sees it) is kept while the anchor holds, so
//! those lines are tested once.
//!
//! ```
//! use std::sync::Arc;
//! use uavcov::visibility::tracking::{CoverageTracker, Margin};
//! use uavcov::{Surface, Targets, Visibility};
//! // A ridge across a 40 m x 40 m grid; two UAVs drift a few centimetres per step.
//! let z: Vec<f64> = (0..41 * 41).map(|k| if (k % 41) == 20 { 6.0 } else { 0.0 }).collect();
//! let surface = Arc::new(Surface::from_grid(z, 41, 41, 1.0, 1.0, 0.0, 0.0)?);
//! let vis = Arc::new(Visibility::new(surface.clone(), Targets::grid_nodes(surface)?, 30.0)?);
//! let mut tracker = CoverageTracker::new(vis.clone(), Margin::Adaptive)?;
//! for step in 0..20 {
//!     let drift = 0.05 * f64::from(step);
//!     let team = [[10.0 + drift, 10.0, 8.0], [30.0, 30.0 - drift, 4.0]];
//!     assert_eq!(tracker.seen(&team, 1)?, vis.seen(&team, 1)?);
//! }
//! # Ok::<(), uavcov::Error>(())
//! ```

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

use rayon::prelude::*;

use crate::error::{ensure, try_filled, Result};
use crate::geometry::{Point, SIGHT_FRACTION};
use crate::surface::grid::Grid;
use crate::surface::heightfield::{HeightField, Horizon};
use crate::surface::skyline::Skyline;
use crate::threads;
use crate::visibility::{squared_distance, Reach, Visibility, CHUNK, HORIZON_BUDGET};

/// The clearance certificates ask, as a share of the coordinates' magnitude (the exact test's
/// shortcuts clear lines by margins of 1e-9 of it).
const ALLOWANCE: f64 = 1e-8;

/// No UAV certifies the target as seen.
const NO_SEER: u32 = u32::MAX;

/// Set in a seer when the target lies so deep in its anchor's range that every position the
/// anchor allows reaches it: the certificate then holds without the target's coordinates.
const DEEP: u32 = 1 << 31;

/// How far a UAV may move from its anchor before its certificates are made anew (see the
/// [module documentation](self)). It changes the work, never an answer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Margin {
    /// The same distance for every anchor, metres.
    Fixed(f64),
    /// Each anchor its own: [`STEPS_HELD`] times its UAV's recent step, within
    /// [`ADAPTIVE_MARGINS`], and at most [`HEIGHT_SHARE`] of its height above the surface.
    Adaptive,
}

/// An adaptive margin is this many of the UAV's recent steps (a step being the anchor's
/// distance: height change plus slope times horizontal move; recent: each step weighs half,
/// the earlier ones the other half): an anchor then holds for a few evaluations of a random walk.
pub const STEPS_HELD: f64 = 2.5;

/// The range of adaptive margins, metres (the least before a step is known).
pub const ADAPTIVE_MARGINS: (f64, f64) = (1.0, 4.0);

/// An adaptive margin is at most this share of the UAV's height above the surface: the lowered
/// anchor keeps most of the UAV's view, and its "seen" certificates most of the UAV's targets.
pub const HEIGHT_SHARE: f64 = 0.3;

/// Coverage of one team, evaluated again and again as it moves: [`Visibility::seen`] and
/// [`Visibility::coverage`] to the last bit, with most sight lines settled by what earlier
/// evaluations proved (see the [module documentation](self)).
///
/// Certificates apply on the grid path over a grid without nodata, with the objective's one
/// range; elsewhere every call is a plain [`Visibility::seen`]. A different team size starts
/// afresh.
#[derive(Debug)]
pub struct CoverageTracker {
    vis: Arc<Visibility>,
    margin: Margin,
    /// The surface's steepest slope, `None` when certificates cannot be used.
    slope: Option<f64>,
    /// The steepest slope by tile of the grid, for each anchor's own.
    tiles: SlopeTiles,
    /// Magnitude of the surface's coordinates plus its extent, metres.
    scale: f64,
    /// Evaluations made (the next one is `now + 1`).
    now: u32,
    anchors: Vec<Anchor>,
    /// Each UAV's last position and recent step, for adaptive margins.
    paces: Vec<Pace>,
    certificates: Vec<Certificate>,
    /// Targets the last evaluation settled by a certificate.
    settled: usize,
    /// An evaluation is under way (still set after a panic: the state is then made afresh).
    busy: bool,
}

/// Where a UAV's certificates were made, and the horizons that make them.
#[derive(Debug, Default)]
struct Anchor {
    at: Point,
    /// The steepest slope within the objective's range plus the margin of it (horizontally).
    slope: f64,
    /// The evaluation that set it (0: never).
    set_at: u32,
    /// Its margin, metres.
    margin: f64,
    /// Squared horizontal distance from it within which the targets it sees stay in range of
    /// every position it allows (negative: none does).
    deep: f64,
    /// The anchor lowered by the margin (`None`: no "seen" certificate).
    lowered: Option<Viewpoint>,
    /// The anchor raised by the margin (`None`: no "blocked" certificate).
    raised: Option<Viewpoint>,
}

impl Anchor {
    /// Its raised and lowered viewpoints, which make its certificates: the raised one when the
    /// margin clears the rounding allowance, the lowered one when it is also above the surface
    /// (`ground`, under the anchor) by the allowance. `scale` and `slope` are the tracker's.
    fn arm(&mut self, ground: Option<f64>, scale: f64, slope: f64) {
        let (p, margin) = (self.at, self.margin);
        let tol = ALLOWANCE * (scale + 2.0 * p[2].abs() + margin) * (1.0 + slope);
        if let Some(g) = ground.filter(|_| margin > 2.0 * tol / (1.0 - SIGHT_FRACTION)) {
            self.raised = Some(Viewpoint::new([p[0], p[1], p[2] + margin], FEW_LINES));
            if p[2] - margin - g > tol {
                // Its whole horizon at once: an anchor is armed where its UAV's certificates are
                // void, so the lowered viewpoint soon tests hundreds of lines (0.97x the
                // reference mission's measuring time, benches/README.md).
                self.lowered = Some(Viewpoint::new([p[0], p[1], p[2] - margin], 0));
            }
        }
    }
}

/// Where a UAV was at the last evaluation and how far it moves from one to the next.
#[derive(Debug, Clone, Copy)]
struct Pace {
    last: Point,
    /// The recent step, metres (`None` before the second evaluation).
    step: Option<f64>,
}

/// Sight lines from one point: the first [`FEW_LINES`] through a horizon of the cells right
/// around it (built at once: the target's skyline settles a line's end, the walk the rest), the
/// others through a horizon of its whole range, built then (it costs about as much as that many
/// walks, and most points of an evaluation test only a few lines).
#[derive(Debug)]
struct Viewpoint {
    at: Point,
    /// Lines tested before the full horizon is built.
    few: usize,
    tested: AtomicUsize,
    small: OnceLock<Option<Horizon>>,
    full: OnceLock<Option<Horizon>>,
}

/// An anchor held for this many evaluations: its UAV moves little enough for certificates to pay.
const LASTING: u32 = 3;

/// Sight lines from a point tested before its full horizon is built.
const FEW_LINES: usize = 64;

impl Viewpoint {
    fn new(at: Point, few: usize) -> Self {
        Self { at, few, tested: AtomicUsize::new(0), small: OnceLock::new(), full: OnceLock::new() }
    }

    /// The exact test of the sight line from this point to `q` (with `q`'s skyline `sky`); the
    /// full horizon reaches `radius` metres in at most `budget` bounds.
    #[inline]
    fn sees(&self, field: &HeightField, (radius, budget): (f64, usize), q: Point, sky: Option<&Skyline>) -> bool {
        let horizon = match self.full.get() {
            Some(h) => h,
            None if self.tested.fetch_add(1, Ordering::Relaxed) < self.few => {
                self.small.get_or_init(|| field.horizon(self.at, 0.0, budget).ok())
            }
            None => self.full.get_or_init(|| field.horizon(self.at, radius, budget).ok()),
        };
        match horizon {
            Some(h) => match sky {
                Some(s) => field.line_of_sight_to_node(h, q, s),
                None => field.line_of_sight_from(h, q),
            },
            // Refused by the system: the walk alone, the same answer.
            None => field.line_of_sight(self.at, q),
        }
    }
}

/// What the UAVs' anchors prove about one target.
#[derive(Debug, Clone, Copy)]
struct Certificate {
    /// The UAV whose lowered anchor sees the target (with [`DEEP`] set when the target is deep
    /// in range), or [`NO_SEER`].
    seer: u32,
    /// The evaluation that made this certificate: it holds for UAVs whose anchor is older.
    stamp: u32,
    /// UAVs (the first 64) whose raised anchor does not see the target.
    blocked: u64,
    /// UAVs (the first 64) whose lowered anchor does not see the target: a target near the
    /// edge of what a UAV sees is tested from where the UAV is at every evaluation, and the
    /// anchor's own lines, which give no certificate there, need not be tested again.
    lowered_misses: u64,
    /// UAVs (the first 64) whose raised anchor sees the target (no "blocked" certificate).
    raised_sees: u64,
}

const NONE: Certificate = Certificate { seer: NO_SEER, stamp: 0, blocked: 0, lowered_misses: 0, raised_sees: 0 };

/// A UAV in the current evaluation.
#[derive(Debug, Clone, Copy, Default)]
struct Status {
    /// Over the grid: its certificates may be used.
    over: bool,
    /// Over the grid and above the surface: its "blocked" certificates may be used.
    above: bool,
}

impl CoverageTracker {
    /// A tracker of `vis` whose certificates allow each UAV to move `margin` (see the
    /// [module documentation](self)) before they are made anew. The margin changes the work,
    /// never an answer.
    ///
    /// # Errors
    /// [`Error::InvalidInput`](crate::Error::InvalidInput) when a fixed margin is not finite
    /// and positive; [`Error::TooLarge`](crate::Error::TooLarge) when the system refuses the
    /// memory (32 bytes per target).
    pub fn new(vis: Arc<Visibility>, margin: Margin) -> Result<Self> {
        if let Margin::Fixed(m) = margin {
            ensure!(m.is_finite() && m > 0.0, "margin must be finite and > 0, got {m}");
        }
        let field = vis.grid_field();
        let slope = field.and_then(|f| f.grid().max_slope()).filter(|s| s.is_finite());
        let (lo, hi) = vis.surface().bounds();
        let xy = lo[0].abs().max(lo[1].abs()).max(hi[0].abs()).max(hi[1].abs()) + (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let scale = xy + lo[2].abs() + hi[2].abs() + (hi[2] - lo[2]);
        let n = if slope.is_some() { vis.targets().len() } else { 0 };
        let certificates = try_filled(NONE, n, "the tracker's certificates")?;
        let tiles = match (slope, field) {
            (Some(_), Some(f)) => SlopeTiles::new(f.grid())?,
            _ => SlopeTiles::default(),
        };
        Ok(Self { vis, margin, slope, tiles, scale, now: 0, anchors: Vec::new(), paces: Vec::new(), certificates, settled: 0, busy: false })
    }

    /// The objective this tracker evaluates.
    #[must_use]
    pub fn visibility(&self) -> &Arc<Visibility> {
        &self.vis
    }

    /// The margin.
    #[must_use]
    pub fn margin(&self) -> Margin {
        self.margin
    }

    /// Whether certificates are in use (grid path, no nodata).
    #[must_use]
    pub fn certifies(&self) -> bool {
        self.slope.is_some()
    }

    /// How many targets the last evaluation found seen from a certificate, without a sight line.
    #[must_use]
    pub fn settled(&self) -> usize {
        self.settled
    }

    /// [`Visibility::coverage`] for the team at `uavs`.
    ///
    /// # Errors
    /// As [`Visibility::seen`].
    pub fn coverage(&mut self, uavs: &[Point], n_threads: usize) -> Result<f64> {
        let seen = self.seen(uavs, n_threads)?;
        Ok(self.vis.share(&seen))
    }

    /// [`Visibility::seen`] for the team at `uavs`.
    ///
    /// # Errors
    /// As [`Visibility::seen`].
    pub fn seen(&mut self, uavs: &[Point], n_threads: usize) -> Result<Vec<bool>> {
        Visibility::check_uavs(uavs)?;
        let vis = Arc::clone(&self.vis);
        self.settled = 0;
        let (Some(slope), Some(field)) = (self.slope, vis.grid_field()) else {
            return vis.seen(uavs, n_threads);
        };
        if self.busy || uavs.len() != self.anchors.len() || self.now == u32::MAX {
            self.anchors = uavs.iter().map(|_| Anchor::default()).collect();
            self.paces = uavs.iter().map(|&p| Pace { last: p, step: None }).collect();
            self.certificates.fill(NONE);
            self.now = 0;
        }
        self.now += 1;
        self.busy = true;
        let result = self.evaluate(field, slope, uavs, n_threads);
        // After an error (a refused horizon) the anchors may be half made: start afresh.
        self.busy = result.is_err();
        result
    }

    /// The UAVs' status, with the anchors of those that moved their margin set anew.
    fn move_anchors(&mut self, slope: f64, uavs: &[Point]) -> Vec<Status> {
        let (now, scale, range) = (self.now, self.scale, self.vis.range());
        let surface = self.vis.surface();
        let grid = self.vis.grid_field().map(HeightField::grid);
        let mut status = vec![Status::default(); uavs.len()];
        for (u, ((&p, anchor), pace)) in uavs.iter().zip(&mut self.anchors).zip(&mut self.paces).enumerate() {
            let ground = surface.ground_height(p[0], p[1]);
            let step = (p[2] - pace.last[2]).abs() + anchor.slope * (p[0] - pace.last[0]).hypot(p[1] - pace.last[1]);
            *pace = Pace { last: p, step: Some(pace.step.map_or(step, |s| 0.5 * (s + step))) };
            let tol = ALLOWANCE * (scale + anchor.at[2].abs() + p[2].abs() + anchor.margin) * (1.0 + slope);
            status[u] = Status { over: ground.is_some(), above: ground.is_some_and(|g| p[2] - g > tol) };
            let need = 2.0 * tol / (1.0 - SIGHT_FRACTION);
            let drift = (p[0] - anchor.at[0]).hypot(p[1] - anchor.at[1]);
            let moved = (p[2] - anchor.at[2]).abs() + anchor.slope * drift;
            if anchor.set_at > 0 && drift <= anchor.margin && moved <= anchor.margin - need {
                // An anchor made without certificates gets them once it has held LASTING
                // evaluations itself.
                if now - anchor.set_at == LASTING && anchor.lowered.is_none() && anchor.raised.is_none() {
                    anchor.arm(surface.ground_height(anchor.at[0], anchor.at[1]), scale, slope);
                }
                continue;
            }
            // Certificates cost lines to make and pay only while their anchor holds: they are
            // made at once when the UAV's last anchor held for LASTING evaluations.
            let lasted = anchor.set_at > 0 && now - anchor.set_at >= LASTING;
            let margin = match self.margin {
                Margin::Fixed(m) => m,
                Margin::Adaptive => {
                    let (least, most) = ADAPTIVE_MARGINS;
                    let m = pace.step.filter(|_| anchor.set_at > 0).map_or(least, |s| (STEPS_HELD * s).clamp(least, most));
                    ground.map_or(m, |g| m.min(HEIGHT_SHARE * (p[2] - g)).max(0.0))
                }
            };
            let local = grid.map_or(slope, |g| self.tiles.around(g, p, range + margin).min(slope));
            // Within `range - 2 margin` of the anchor a target is within range of every position
            // the anchor allows (`hypot(dx, dy) <= margin`, `|dz| <= margin`).
            let deep = range - 2.0 * margin - ALLOWANCE * scale;
            let deep = if deep > 0.0 { deep * deep } else { -1.0 };
            *anchor = Anchor { at: p, slope: local, set_at: now, margin, deep, lowered: None, raised: None };
            if lasted {
                anchor.arm(ground, scale, slope);
            }
        }
        status
    }

    fn evaluate(&mut self, field: &HeightField, slope: f64, uavs: &[Point], n_threads: usize) -> Result<Vec<bool>> {
        let status = self.move_anchors(slope, uavs);
        if self.anchors.iter().all(|a| a.lowered.is_none() && a.raised.is_none()) {
            // No UAV holds still enough for certificates (every older one is void): the plain
            // evaluation, without the tracker's bookkeeping.
            return self.vis.seen(uavs, n_threads);
        }
        let n = uavs.len();
        let reach = self.vis.reach(uavs, None)?;
        // Each horizon within a third of the budget of one evaluation's (current, lowered, raised).
        let budget = HORIZON_BUDGET / (3 * n);
        // A UAV without certificates tests every line of its targets: its horizon pays at once.
        let current: Vec<Viewpoint> = uavs
            .iter()
            .zip(&self.anchors)
            .map(|(&p, a)| Viewpoint::new(p, if a.lowered.is_some() || a.raised.is_some() { FEW_LINES } else { 0 }))
            .collect();
        let team = Team {
            uavs,
            reach,
            status: &status,
            anchors: &self.anchors,
            current: &current,
            field,
            own: (self.vis.horizon_reach(field, self.vis.range()), budget),
            now: self.now,
        };
        let vis: &Visibility = &self.vis;
        let mut seen = try_filled(false, vis.targets().len(), "the seen mask")?;
        let settled: Vec<usize> = threads::run(n_threads, || {
            self.certificates
                .par_chunks_mut(CHUNK)
                .zip(seen.par_chunks_mut(CHUNK))
                .enumerate()
                .map_init(Vec::new, |near, (c, (chunk, out))| {
                    vis.in_range_of(c, uavs, reach, near);
                    if near.is_empty() {
                        return 0;
                    }
                    // The chunk's skylines are locked only once a target needs a sight line.
                    let mut skylines = None;
                    let mut settled = 0;
                    for (t, (certificate, seen)) in chunk.iter_mut().zip(out.iter_mut()).enumerate() {
                        if team.certified_deep(certificate) {
                            settled += 1;
                            *seen = true;
                            continue;
                        }
                        let (q, node) = vis.targets().chunk_target(c, t);
                        *seen = if team.certified_seen(certificate, q) {
                            settled += 1;
                            true
                        } else {
                            let view = skylines.get_or_insert_with(|| vis.chunk_skylines(c));
                            let sky = view.as_mut().map(|s| s.get(t, || vis.skyline(q, node)));
                            team.retest(certificate, q, near, sky.as_ref())
                        };
                    }
                    settled
                })
                .collect()
        });
        self.settled = settled.iter().sum();
        Ok(seen)
    }
}

/// The steepest slope of each tile of `TILE x TILE` cells of a grid without nodata.
#[derive(Debug, Default)]
struct SlopeTiles {
    cols: usize,
    steepest: Vec<f64>,
}

/// Cells a side of a [`SlopeTiles`] tile.
const TILE: usize = 8;

impl SlopeTiles {
    fn new(g: &Grid) -> Result<Self> {
        let (rows, cols) = ((g.ny - 1).div_ceil(TILE), (g.nx - 1).div_ceil(TILE));
        let mut steepest = try_filled(0.0f64, rows * cols, "the tracker's slope tiles")?;
        for i in 0..g.ny - 1 {
            for j in 0..g.nx - 1 {
                let tile = &mut steepest[(i / TILE) * cols + j / TILE];
                *tile = tile.max(g.cell_slope(i, j));
            }
        }
        Ok(Self { cols, steepest })
    }

    /// The steepest slope of the cells within `r` metres of `p` along x and along y (and a cell
    /// more each way, for rounding).
    fn around(&self, g: &Grid, p: Point, r: f64) -> f64 {
        let span = |c: f64, start: f64, step: f64, cells: usize| {
            let lo = ((c - r - start) / step).floor() - 1.0;
            let hi = ((c + r - start) / step).floor() + 1.0;
            let last = (cells - 1) as f64;
            (lo.clamp(0.0, last) as usize / TILE, hi.clamp(0.0, last) as usize / TILE)
        };
        let (i0, i1) = span(p[1], g.y0, g.dy, g.ny - 1);
        let (j0, j1) = span(p[0], g.x0, g.dx, g.nx - 1);
        (i0..=i1).flat_map(|i| &self.steepest[i * self.cols + j0..=i * self.cols + j1]).fold(0.0, |m, &s| m.max(s))
    }
}

/// What one evaluation knows of the team, for the targets' certificates.
struct Team<'a> {
    uavs: &'a [Point],
    reach: Reach<'a>,
    status: &'a [Status],
    anchors: &'a [Anchor],
    /// The UAVs where they are.
    current: &'a [Viewpoint],
    field: &'a HeightField,
    /// Horizons' radius ([`Visibility::horizon_reach`] of the range) and budget, from the UAVs
    /// (an anchor's reach its margin farther).
    own: (f64, usize),
    now: u32,
}

impl Team<'_> {
    /// The radius and budget of an anchor's horizons.
    #[inline]
    fn anchored(&self, anchor: &Anchor) -> (f64, usize) {
        (self.own.0 + anchor.margin, self.own.1)
    }

    /// Whether the target's certificate says it is seen deep in range, and still holds.
    #[inline]
    fn certified_deep(&self, certificate: &Certificate) -> bool {
        certificate.seer != NO_SEER && certificate.seer & DEEP != 0 && self.holds(certificate, (certificate.seer & !DEEP) as usize)
    }

    /// Whether the target's certificate says it is seen, and still holds.
    #[inline]
    fn certified_seen(&self, certificate: &Certificate, q: Point) -> bool {
        let u = (certificate.seer & !DEEP) as usize;
        certificate.seer != NO_SEER && self.holds(certificate, u) && self.reach.accepts(u, self.uavs[u], q, None)
    }

    /// Whether UAV `u`'s anchor is still the one that made the certificate.
    #[inline]
    fn holds(&self, certificate: &Certificate, u: usize) -> bool {
        u < self.uavs.len() && self.status[u].over && self.anchors[u].set_at <= certificate.stamp
    }

    /// Whether any UAV sees target `q` (with its skyline `sky`), trying the UAVs in range
    /// (`near`) in order, its certificate made anew; the UAV that sees it moves to the front.
    fn retest(&self, certificate: &mut Certificate, q: Point, near: &mut [usize], sky: Option<&Skyline>) -> bool {
        // What anchors that moved since proved is void.
        let known = certificate.blocked | certificate.lowered_misses | certificate.raised_sees;
        let stale = if known == 0 {
            0
        } else {
            self.anchors.iter().take(64).enumerate().filter(|(_, a)| a.set_at > certificate.stamp).fold(0u64, |m, (u, _)| m | (1 << u))
        };
        let mut blocked = certificate.blocked & !stale;
        let mut lowered_misses = certificate.lowered_misses & !stale;
        let mut raised_sees = certificate.raised_sees & !stale;
        let mut seer = NO_SEER;
        let mut seen = false;
        for k in 0..near.len() {
            let u = near[k];
            let bit = if u < 64 { 1u64 << u } else { 0 };
            let status = self.status[u];
            if (blocked & bit != 0 && status.above) || !self.reach.accepts(u, self.uavs[u], q, None) {
                continue;
            }
            let anchor = &self.anchors[u];
            if let (true, false, Some(lowered)) = (status.over, lowered_misses & bit != 0, &anchor.lowered) {
                if lowered.sees(self.field, self.anchored(anchor), q, sky) {
                    let deep = if squared_distance(anchor.at, q) <= anchor.deep { DEEP } else { 0 };
                    seer = u32::try_from(u).ok().filter(|&u| u < DEEP).map_or(NO_SEER, |u| u | deep);
                    seen = true;
                    near.swap(0, k);
                    break;
                }
                lowered_misses |= bit;
            }
            if self.current[u].sees(self.field, self.own, q, sky) {
                seen = true;
                near.swap(0, k);
                break;
            }
            if let (true, false, Some(raised)) = (bit != 0, raised_sees & bit != 0, &anchor.raised) {
                if raised.sees(self.field, self.anchored(anchor), q, sky) {
                    raised_sees |= bit;
                } else {
                    blocked |= bit;
                }
            }
        }
        *certificate = Certificate { seer, stamp: self.now, blocked, lowered_misses, raised_sees };
        seen
    }
}

#[cfg(test)]
mod tests;
