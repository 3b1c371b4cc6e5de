//! Constrained centroidal Voronoi tessellation (CVT) of a surface by the probabilistic MacQueen
//! method of Ju, Du and Gunzburger (paper section IV-A).
//!
//! Each iteration draws `q` points on the surface, uniform by (density-weighted) area, gives each
//! to its nearest generator (3D distance), and moves every generator `z` that received samples
//! towards their mean `y*` by the paper's rule
//!
//! ```text
//! z <- ((a1 j + b1) z + (a2 j + b2) y*) / (j + 1),   j <- j + 1,
//! ```
//!
//! then projects it onto the surface (closest point): the constrained centroid of a region is
//! the surface point closest to its ordinary centroid. A generator with no sample neither moves
//! nor counts the iteration in its `j`. Weights `a1 + a2 = b1 + b2 = 1`, `a2, b2 > 0` (the
//! paper's constraints); uavcov also asks `a1, b1 >= 0`, so a generator never overshoots the
//! sample mean. The weight on the sample mean is `w_j = (a2 j + b2) / (j + 1)`: it starts at
//! `(a2 + b2) / 2` and tends to `a2`, so `a` sets the long-run step and `b` the first steps.
//!
//! ## Facing
//!
//! With `normal_weight = lambda > 0` (metres) a sample's distance to a generator also counts how
//! far its triangle's outward normal is from the generator's facing, `lambda^2 |n - m|^2`, and
//! the facing `m` follows its region's mean normal by the same rule (see `facing.rs`): regions
//! gather surface that faces one way. `lambda = 0` (the default) is the paper's CVT, bit for bit.
//!
//! ## Stopping
//!
//! The mean per-iteration move is dominated by sampling noise once the generators are near a
//! CVT: on a 100 m square with the default `q = max(2000, 200 N)` and `a = b = (0.5, 0.5)` it
//! levels off at 0.3-0.5 m, whatever the tolerance. The stopping rule therefore measures the
//! *net* move over a window of `W` iterations, where jitter cancels and drift adds up: after
//! iteration `k >= W`, `drift_k = mean_i |z_i(k) - z_i(k - W)| / W` (metres per iteration), and
//! the run stops at the first `k` with `drift_k < tolerance`, or after `max_iterations`.
//!
//! ## Determinism
//!
//! Iteration `k` draws its samples in fixed chunks of 1024 (`CHUNK`); chunk `c` has its own ChaCha8
//! stream keyed by `(seed, k, c)`, and per-chunk sums are combined in chunk order. The result is
//! bit-identical for any number of threads.
//!
//! ## Speed
//!
//! Triangles are drawn from an alias table in O(1). On coarse surfaces (at most `q / 4`
//! triangles, such as the paper's S'), each sample's nearest generator is searched among the
//! few that can win anywhere on its triangle (see `Candidates`), which gives exactly the
//! brute-force answer; fine meshes use the brute-force scan. `benches/cvt.rs` times it.
//!
//! ```
//! use uavcov::cvt::{constrained_cvt, CvtOptions};
//! use uavcov::surface::mesh::Surface;
//! // A 200 m x 100 m flat rectangle: the CVT of 2 generators is the two squares' centres.
//! let s = Surface::new(
//!     vec![[0.0, 0.0, 0.0], [200.0, 0.0, 0.0], [200.0, 100.0, 0.0], [0.0, 100.0, 0.0]],
//!     vec![[0, 1, 2], [0, 2, 3]],
//! ).unwrap();
//! let options = CvtOptions { tolerance: 0.02, ..CvtOptions::for_generators(2) }.with_seed(7).with_threads(1);
//! let cvt = constrained_cvt(&s, 2, &options, None, None).unwrap();
//! let mut x: Vec<f64> = cvt.generators.iter().map(|g| g[0]).collect();
//! x.sort_by(f64::total_cmp);
//! assert!((x[0] - 50.0).abs() < 2.0 && (x[1] - 150.0).abs() < 2.0);
//! ```

mod candidates;
mod facing;
mod sampler;

use std::collections::VecDeque;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use self::candidates::{triangle_corners, Candidates};
use self::facing::Facing;
use self::sampler::{unit, TriangleSampler};
use crate::error::{ensure, try_copy, try_filled, try_with_capacity, Error, Result};
use crate::geometry::{in_bounds, Point, MAX_COORDINATE};
use crate::surface::mesh::Surface;
use crate::threads;

/// Samples per chunk of work: each chunk has its own random stream, so results do not depend on
/// how chunks are spread over threads; 1024 keeps rayon's per-task cost (~1 us) negligible.
pub(crate) const CHUNK: usize = 1024;

/// Most generator slots of per-chunk sums held at once (56 bytes each: 448 MiB). An iteration's
/// chunks are sampled in batches of `PARTIAL_BUDGET / N` and summed in chunk order, so the
/// batch size never changes a result; it only keeps `N x q` from deciding the memory (30,000
/// generators at the default `q` would have needed 5.6 GB at once).
const PARTIAL_BUDGET: usize = 1 << 23;

/// Random-stream purposes, part of each stream's key so no two uses share a stream.
const STREAM_INITIAL: u64 = 1;
const STREAM_ITERATION: u64 = 2;

/// The `(alpha, beta)` weights of the update rule (`[a1, a2]`, `[b1, b2]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weights {
    /// `[a1, a2]`: the long-run weights of the current generator and the sample mean.
    pub alpha: [f64; 2],
    /// `[b1, b2]`: the weights of the first updates.
    pub beta: [f64; 2],
}

impl Weights {
    /// `a = b = (0.5, 0.5)`: `j` drops out and every update is a damped sampled Lloyd step,
    /// `z <- (z + y*) / 2` (the starting point of `paper-setup.md`; the default).
    pub const DAMPED: Self = Self { alpha: [0.5, 0.5], beta: [0.5, 0.5] };

    /// `a = b = (0, 1)`: `z <- y*`, the sampled ("random") Lloyd iteration. Converges in about
    /// half the iterations of [`Weights::DAMPED`], with three times the jitter variance.
    pub const LLOYD: Self = Self { alpha: [0.0, 1.0], beta: [0.0, 1.0] };

    /// `a = (0.9, 0.1)`, `b = (0, 1)`: MacQueen-like annealing. The step
    /// `w_j = (0.1 j + 1) / (j + 1)` starts near 1/2, falls like `1 / j` and levels off at 0.1,
    /// which averages sampling noise over about 20 iterations (jitter variance about a sixth of
    /// [`Weights::DAMPED`]'s). Because its steps shrink by schedule, a move-based stop fires
    /// before the far-from-converged modes have settled: use it to refine a converged CVT
    /// (start from its generators), or with a smaller tolerance.
    pub const ANNEALED: Self = Self { alpha: [0.9, 0.1], beta: [0.0, 1.0] };

    /// Weights checked against the paper's constraints.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] unless every value is finite, `a1 + a2 = b1 + b2 = 1` (to 1e-9),
    /// `a2, b2 > 0` and `a1, b1 >= 0`.
    pub fn new(alpha: [f64; 2], beta: [f64; 2]) -> Result<Self> {
        for (name, [w1, w2]) in [("alpha", alpha), ("beta", beta)] {
            ensure!(w1.is_finite() && w2.is_finite(), "{name} must be finite, got ({w1}, {w2})");
            let (sums_to_one, positive, non_negative) = ((w1 + w2 - 1.0).abs() <= 1e-9, w2 > 0.0, w1 >= 0.0);
            ensure!(sums_to_one, "{name}: {name}1 + {name}2 must be 1 (the paper's constraint), got {w1} + {w2} = {}", w1 + w2);
            ensure!(positive, "{name}2 must be > 0 (the paper's constraint), got {w2}");
            ensure!(non_negative, "{name}1 must be >= 0 so the update never overshoots the sample mean, got {w1}");
        }
        Ok(Self { alpha, beta })
    }

    /// The coefficients `((a1 j + b1) / (j + 1), (a2 j + b2) / (j + 1))` of the current generator
    /// and of the sample mean at a generator's `j`-th update.
    #[inline]
    #[must_use]
    pub fn coefficients(&self, j: u64) -> (f64, f64) {
        let jf = j as f64;
        let keep = (self.alpha[0] * jf + self.beta[0]) / (jf + 1.0);
        let toward = (self.alpha[1] * jf + self.beta[1]) / (jf + 1.0);
        (keep, toward)
    }
}

/// How a CVT run samples, moves and stops, which random streams it draws and on how many
/// threads: everything [`constrained_cvt`] takes besides the surface and its inputs.
///
/// ```
/// use uavcov::cvt::{CvtOptions, Weights};
/// let options = CvtOptions { tolerance: 0.05, weights: Weights::LLOYD, ..CvtOptions::for_generators(8) }.with_seed(3);
/// assert_eq!((options.samples_per_iteration, options.seed, options.n_threads), (2000, 3, 0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CvtOptions {
    /// `q`, samples drawn per iteration.
    pub samples_per_iteration: usize,
    /// The update rule's weights.
    pub weights: Weights,
    /// Stop once the net move per iteration over the window is below this, metres (>= 0; 0 runs
    /// to `max_iterations`).
    pub tolerance: f64,
    /// `W`, the iterations over which the net move is measured (>= 1).
    pub window: usize,
    /// Most iterations (>= 1).
    pub max_iterations: usize,
    /// The seed of every random stream: the run is a function of it and the inputs only.
    pub seed: u64,
    /// Threads for the samples (`0`: one per core); the result never depends on it.
    pub n_threads: usize,
    /// `lambda`, metres (finite, >= 0): the weight of the facing term (see [`facing`](self#facing));
    /// `0` is the paper's CVT.
    pub normal_weight: f64,
}

impl CvtOptions {
    /// The starting values of `paper-setup.md` for `n` generators: `q = max(2000, 200 n)`,
    /// [`Weights::DAMPED`], 0.1 m over a window of 5 iterations, at most 300 iterations; seed 0,
    /// one thread per core.
    #[must_use]
    pub fn for_generators(n: usize) -> Self {
        Self {
            samples_per_iteration: default_samples(n),
            weights: Weights::DAMPED,
            tolerance: 0.1,
            window: 5,
            max_iterations: 300,
            seed: 0,
            n_threads: 0,
            normal_weight: 0.0,
        }
    }

    /// The same options with another seed.
    #[must_use]
    pub fn with_seed(self, seed: u64) -> Self {
        Self { seed, ..self }
    }

    /// The same options on `n_threads` threads (`0`: one per core).
    #[must_use]
    pub fn with_threads(self, n_threads: usize) -> Self {
        Self { n_threads, ..self }
    }

    fn check(&self, n: usize) -> Result<()> {
        ensure!(n >= 1, "the number of generators must be >= 1, got {n}");
        let q = self.samples_per_iteration;
        ensure!(q >= 1, "samples_per_iteration must be >= 1, got {q}");
        ensure!(n <= q, "{n} generators need at least as many samples per iteration, got samples_per_iteration = {q}");
        Weights::new(self.weights.alpha, self.weights.beta)?;
        ensure!(self.tolerance.is_finite() && self.tolerance >= 0.0, "tolerance must be finite and >= 0 m, got {}", self.tolerance);
        ensure!(self.window >= 1, "window must be >= 1 iteration, got {}", self.window);
        ensure!(self.max_iterations >= 1, "max_iterations must be >= 1, got {}", self.max_iterations);
        let lambda = self.normal_weight;
        let in_range = (0.0..=MAX_COORDINATE).contains(&lambda);
        ensure!(in_range, "normal_weight must be finite, >= 0 and at most {MAX_COORDINATE:e} m, got {lambda:?}");
        Ok(())
    }
}

/// The default samples per iteration for `n` generators: `max(2000, 200 n)`.
pub(crate) fn default_samples(n: usize) -> usize {
    n.saturating_mul(200).max(2000)
}

/// The result of a CVT run.
#[derive(Debug, Clone, PartialEq)]
pub struct Tessellation {
    /// The generators, on the surface, metres.
    pub generators: Vec<Point>,
    /// Each generator's facing: the unit direction of its region's mean outward normal (the
    /// normal part of the generator, updated like its position; zero where the region's
    /// normals cancel). Computed whatever the normal weight.
    pub normals: Vec<Point>,
    /// Per iteration, the mean over generators of the distance each moved, metres.
    pub moves: Vec<f64>,
    /// Per iteration `k` (1-based), the net move per iteration over the last `W` iterations,
    /// `mean_i |z_i(k) - z_i(k - W)| / W`, metres; NaN while `k < W`. The stopping statistic.
    pub drift: Vec<f64>,
    /// Per iteration, a Monte-Carlo estimate of the CVT energy per unit (density-weighted) area
    /// of the generators at the start of the iteration: the mean squared distance, m^2, from
    /// that iteration's samples to their nearest generator, the facing term included. Times the
    /// (weighted) area it estimates the integral of `rho |y - z|^2` (plus the facing term's).
    pub energy: Vec<f64>,
    /// Iterations run.
    pub iterations: usize,
    /// Whether the run stopped on the tolerance (not on `max_iterations`).
    pub converged: bool,
}

/// Per-chunk sums of the samples given to each generator (positions and normals).
struct Partial {
    sums: Vec<[f64; 3]>,
    normal_sums: Vec<[f64; 3]>,
    counts: Vec<u64>,
    squared_distance: f64,
}

/// The random stream of one use: keyed by all four values, so streams never overlap.
fn stream(seed: u64, purpose: u64, iteration: u64, chunk: u64) -> ChaCha8Rng {
    let mut key = [0u8; 32];
    for (k, word) in [seed, purpose, iteration, chunk].into_iter().enumerate() {
        key[8 * k..8 * k + 8].copy_from_slice(&word.to_le_bytes());
    }
    ChaCha8Rng::from_seed(key)
}

/// Index of the generator nearest to `y` and the squared distance; ties go to the lower index.
#[inline]
fn nearest(generators: &[Point], y: Point) -> (usize, f64) {
    let mut best = 0;
    let mut best_d = f64::INFINITY;
    for (i, g) in generators.iter().enumerate() {
        let (dx, dy, dz) = (g[0] - y[0], g[1] - y[1], g[2] - y[2]);
        let d = dx * dx + dy * dy + dz * dz;
        if d < best_d {
            best_d = d;
            best = i;
        }
    }
    (best, best_d)
}

/// [`nearest`] over the generators `subset` (ascending indices) only, each with its facing term
/// on the sample's triangle (`terms`, aligned with `subset`; empty without a facing term).
#[inline]
fn nearest_in(generators: &[Point], subset: &[u32], terms: &[f64], y: Point) -> (usize, f64) {
    let mut best = 0;
    let mut best_d = f64::INFINITY;
    for (k, &i) in subset.iter().enumerate() {
        let g = generators[i as usize];
        let (dx, dy, dz) = (g[0] - y[0], g[1] - y[1], g[2] - y[2]);
        let mut d = dx * dx + dy * dy + dz * dz;
        if let Some(t) = terms.get(k) {
            d += t;
        }
        if d < best_d {
            best_d = d;
            best = i as usize;
        }
    }
    (best, best_d)
}

/// [`nearest`] with the facing term of a sample whose triangle's normal is `normal`.
#[inline]
fn nearest_facing(generators: &[Point], facing: &Facing<'_>, normal: Point, y: Point) -> (usize, f64) {
    let mut best = 0;
    let mut best_d = f64::INFINITY;
    for (i, g) in generators.iter().enumerate() {
        let (dx, dy, dz) = (g[0] - y[0], g[1] - y[1], g[2] - y[2]);
        let d = dx * dx + dy * dy + dz * dz + facing.term(i, normal);
        if d < best_d {
            best_d = d;
            best = i;
        }
    }
    (best, best_d)
}

fn distance(a: Point, b: Point) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Runs the constrained CVT of `n` generators on `surface`.
///
/// * `density`: optional per-triangle density (finite, >= 0, not all zero); samples and random
///   initial generators are drawn with probability proportional to `area * density`.
/// * `initial`: optional `n` starting generators, projected onto the surface first; by default
///   `n` random points drawn like the samples.
/// * `options`: the samples, update weights, stopping rule, seed and threads; the whole run is
///   a function of the inputs and `options.seed`, never of `options.n_threads`.
///
/// # Errors
/// [`Error::InvalidInput`] for `n = 0`, `n > q`, `q = 0`, weights outside the constraints (see
/// [`Weights::new`]), a negative or non-finite tolerance, `window = 0`, `max_iterations = 0`, a
/// density of the wrong length, negative, non-finite or zero everywhere, or initial generators
/// that are not `n` finite points; [`Error::Mesh`] for a surface without area.
#[expect(clippy::too_many_lines, reason = "one loop of iterations; its steps share the run's state")]
pub fn constrained_cvt(
    surface: &Surface,
    n: usize,
    options: &CvtOptions,
    density: Option<&[f64]>,
    initial: Option<&[Point]>,
) -> Result<Tessellation> {
    let &CvtOptions { seed, n_threads, .. } = options;
    options.check(n)?;
    if surface.n_triangles() == 0 || !(surface.area().is_finite() && surface.area() > 0.0) {
        return Err(Error::Mesh("the surface has no area to tessellate".into()));
    }
    let sampler = TriangleSampler::new(surface, density)?;
    let mut generators: Vec<Point> = try_with_capacity(n, "the generators")?;
    if let Some(points) = initial {
        ensure!(points.len() == n, "{} initial generators given for n = {n}", points.len());
        ensure!(points.iter().all(|q| q.iter().all(|c| c.is_finite())), "initial generators must be finite");
        ensure!(points.iter().all(|&q| in_bounds(q)), "initial generators must be at most {MAX_COORDINATE:e} m in magnitude");
        generators.extend(points.iter().map(|&q| surface.closest_point(q)));
    } else {
        let mut rng = stream(seed, STREAM_INITIAL, 0, 0);
        generators.extend((0..n).map(|_| surface.closest_point(sampler.sample(&mut rng).0)));
    }
    let q = options.samples_per_iteration;
    let n_chunks = q.div_ceil(CHUNK);
    let window = options.window;
    let mut updates = try_filled(1u64, n, "the generators' update counts")?; // the paper's j_i, starting at 1
                                                                             // The history holds at most `window + 1` copies of the generators (and never more than the
                                                                             // iterations run plus one), each allocated with `try_reserve`.
    let full = window.saturating_add(1);
    let history_refused =
        || Error::TooLarge(format!("a history of {window} iterations of {n} generators needs more memory than the system gives"));
    let mut history: VecDeque<Vec<Point>> = VecDeque::new();
    history.try_reserve(1).map_err(|_| history_refused())?;
    history.push_back(try_copy(&generators, "the generators' history")?);
    let (mut moves, mut drift, mut energy) = (Vec::new(), Vec::new(), Vec::new());
    let mut converged = false;
    // Candidate lists cost 3 N distances per triangle each iteration: worth it when triangles get
    // a few samples each (the paper's S' has ~60), not on fine meshes (brute force there).
    let corners = (sampler.n_triangles() * 4 <= q).then(|| triangle_corners(surface));
    let batch = (PARTIAL_BUDGET / n).max(1);
    let mut sums = try_filled([0.0; 3], n, "the CVT's sample sums")?;
    let mut normal_sums = try_filled([0.0; 3], n, "the CVT's sample sums")?;
    let mut counts = try_filled(0u64, n, "the CVT's sample counts")?;
    // Each generator's facing, zero at first: the first iteration is by position alone.
    let mut facings = try_filled([0.0; 3], n, "the generators' facings")?;
    let weight2 = options.normal_weight * options.normal_weight;

    threads::run(n_threads, || {
        for k in 0..options.max_iterations {
            let current = &generators;
            let facing = (weight2 > 0.0).then_some(Facing { weight2, normals: &facings });
            let candidates = match corners.as_ref() {
                Some(t) => Some(Candidates::new(t, current, facing.as_ref(), &sampler)?),
                None => None,
            };
            sums.fill([0.0; 3]);
            normal_sums.fill([0.0; 3]);
            counts.fill(0);
            let mut squared_distance = 0.0;
            // Batches of chunks, each summed in chunk order: the same sums as all chunks at once.
            let mut first = 0;
            while first < n_chunks {
                let last = (first + batch).min(n_chunks);
                let partials: Result<Vec<Partial>> = (first..last)
                    .into_par_iter()
                    .map(|c| {
                        let mut rng = stream(seed, STREAM_ITERATION, k as u64, c as u64);
                        let count = CHUNK.min(q - c * CHUNK);
                        let mut part = Partial {
                            sums: try_filled([0.0; 3], n, "the CVT's per-chunk sums")?,
                            normal_sums: try_filled([0.0; 3], n, "the CVT's per-chunk sums")?,
                            counts: try_filled(0, n, "the CVT's per-chunk counts")?,
                            squared_distance: 0.0,
                        };
                        for _ in 0..count {
                            let (y, f) = sampler.sample(&mut rng);
                            let normal = sampler.normal(f);
                            let (i, d) = match (&candidates, &facing) {
                                (Some(c), _) => {
                                    let (subset, terms) = c.of(f);
                                    nearest_in(current, subset, terms, y)
                                }
                                (None, Some(facing)) => nearest_facing(current, facing, normal, y),
                                (None, None) => nearest(current, y),
                            };
                            let s = &mut part.sums[i];
                            s[0] += y[0];
                            s[1] += y[1];
                            s[2] += y[2];
                            let m = &mut part.normal_sums[i];
                            m[0] += normal[0];
                            m[1] += normal[1];
                            m[2] += normal[2];
                            part.counts[i] += 1;
                            part.squared_distance += d;
                        }
                        Ok(part)
                    })
                    .collect();
                for part in &partials? {
                    for (total, chunk) in sums.iter_mut().zip(&part.sums).chain(normal_sums.iter_mut().zip(&part.normal_sums)) {
                        for (t, c) in total.iter_mut().zip(chunk) {
                            *t += c;
                        }
                    }
                    for (total, chunk) in counts.iter_mut().zip(&part.counts) {
                        *total += chunk;
                    }
                    squared_distance += part.squared_distance;
                }
                first = last;
            }
            energy.push(squared_distance / q as f64);

            let mut moved = 0.0;
            for i in 0..n {
                if counts[i] == 0 {
                    continue;
                }
                let inv = 1.0 / counts[i] as f64;
                let mean = [sums[i][0] * inv, sums[i][1] * inv, sums[i][2] * inv];
                let (keep, toward) = options.weights.coefficients(updates[i]);
                let z = generators[i];
                let free = [keep * z[0] + toward * mean[0], keep * z[1] + toward * mean[1], keep * z[2] + toward * mean[2]];
                let projected = surface.closest_point(free);
                moved += distance(z, projected);
                generators[i] = projected;
                let (m, total) = (facings[i], normal_sums[i]);
                facings[i] = [0, 1, 2].map(|c| keep * m[c] + toward * total[c] * inv);
                updates[i] += 1;
            }
            moves.push(moved / n as f64);

            // The oldest copy is reused for the newest once the window is full.
            let mut copy = if history.len() == full { history.pop_front() } else { None }.unwrap_or_default();
            copy.clear();
            copy.try_reserve_exact(n).map_err(|_| history_refused())?;
            copy.extend_from_slice(&generators);
            history.try_reserve(1).map_err(|_| history_refused())?;
            history.push_back(copy);
            if history.len() == full {
                let old = &history[0];
                let net: f64 = generators.iter().zip(old).map(|(&a, &b)| distance(a, b)).sum();
                // In floating point, so that no product overflows (exact below 2^53, as before).
                let d = net / (n as f64 * window as f64);
                drift.push(d);
                if d < options.tolerance {
                    converged = true;
                    break;
                }
            } else {
                drift.push(f64::NAN);
            }
        }
        Ok::<_, Error>(())
    })?;
    let normals = facings.into_iter().map(unit).collect();
    Ok(Tessellation { iterations: moves.len(), generators, normals, moves, drift, energy, converged })
}

/// For each point, the index of its nearest generator (3D distance; ties to the lower index):
/// the Voronoi region it belongs to.
///
/// # Errors
/// [`Error::InvalidInput`] when there is no generator or a coordinate is not finite.
pub fn nearest_generator(generators: &[Point], points: &[Point], n_threads: usize) -> Result<Vec<usize>> {
    ensure!(!generators.is_empty(), "there must be at least one generator");
    ensure!(generators.iter().all(|q| q.iter().all(|c| c.is_finite())), "generator coordinates must be finite");
    ensure!(points.iter().all(|q| q.iter().all(|c| c.is_finite())), "point coordinates must be finite");
    Ok(threads::run(n_threads, || points.par_iter().with_min_len(CHUNK).map(|&y| nearest(generators, y).0).collect()))
}

#[cfg(test)]
mod tests;
