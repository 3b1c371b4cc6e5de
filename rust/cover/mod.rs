//! Which candidate viewpoint sees which target: the seen-matrix of a weighted maximum-coverage
//! problem, its lazy greedy and the online bound on its optimum.
//!
//! With a fixed set of candidate viewpoints, coverage is a weighted maximum-coverage problem,
//! monotone and submodular: [`SeenMatrix`] holds, for each candidate, the targets it sees as a
//! bitset (its column, the answers of [`Visibility::seen_by`] for that viewpoint alone, exact and
//! so the same for any thread count); [`greedy`] picks `k` of them by lazy evaluation (Minoux
//! 1978; CELF, Leskovec et al. 2007), kept `d_safe` apart; [`bound`] certifies, for any placement
//! `A` (greedy's, or any positions whose true seen set is given), that no `k` candidates cover
//! more than `f(A)` plus the sum of the `k` largest marginal gains over the candidates given `A`
//! (Leskovec et al. 2007, their eq. of the online bound), nor more than the weight any candidate
//! sees ([`SeenMatrix::ceiling`]).
//!
//! What the bound holds for: the best `k` of *these candidates* (with or without the separation,
//! which only removes sets), on *these targets*. A placement off the candidates may do better;
//! a finer lattice of candidates moves the bound (measured in benches/README.md).
//!
//! ```
//! use std::sync::Arc;
//! use uavcov::{cover, Surface, Targets, Visibility};
//! let surface = Arc::new(Surface::from_grid(vec![0.0; 21 * 21], 21, 21, 1.0, 1.0, 0.0, 0.0)?);
//! let vis = Visibility::new(surface.clone(), Targets::grid_nodes(surface)?, 8.0)?;
//! let candidates: Vec<_> = (0..5).flat_map(|i| (0..5).map(move |j| [5.0 * f64::from(i), 5.0 * f64::from(j), 4.0])).collect();
//! let matrix = cover::SeenMatrix::build(&vis, &candidates, None, 2)?;
//! let picks = cover::greedy(&matrix, &candidates, 3, 2.0, 2)?;
//! assert_eq!(picks.picks.len(), 3);
//! assert!(picks.coverage <= picks.bound && picks.bound <= matrix.ceiling());
//! # Ok::<(), uavcov::Error>(())
//! ```

mod greedy;

pub use greedy::{bound, greedy, Bound, Greedy};

use rayon::prelude::*;

use crate::error::{ensure, try_filled, Error, Result};
use crate::geometry::Point;
use crate::threads;
use crate::visibility::sensor::Sensor;
use crate::visibility::{Visibility, HORIZON_BUDGET};

/// Most bytes a seen-matrix may take (1 GiB): 10^4 candidates x 10^4 targets take 12.5 MB.
pub const MAX_MATRIX_BYTES: usize = 1 << 30;

/// For each candidate viewpoint, the targets it sees, as bits; and the targets' weights.
#[derive(Debug, Clone)]
pub struct SeenMatrix {
    n_targets: usize,
    /// 64-bit words per column.
    words: usize,
    /// Column `c` is `bits[c * words..(c + 1) * words]`; target `t` is bit `t % 64` of word `t / 64`.
    bits: Vec<u64>,
    weights: Vec<f64>,
    total_weight: f64,
}

impl SeenMatrix {
    /// The columns of `candidates` (each with its own sensor, or `None`: the objective's range),
    /// built in parallel over candidates on `n_threads` threads (`0`: one per core); each column
    /// is computed whole by one thread, so the matrix is the same for any thread count.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for no candidate, a coordinate that is not finite or beyond the
    /// bound, or not one sensor per candidate; [`Error::TooLarge`] when the matrix would exceed
    /// [`MAX_MATRIX_BYTES`] or the system refuses its memory.
    pub fn build(vis: &Visibility, candidates: &[Point], sensors: Option<&[Sensor]>, n_threads: usize) -> Result<Self> {
        ensure!(!candidates.is_empty(), "there must be at least one candidate viewpoint");
        Visibility::check_uavs(candidates)?;
        if let Some(s) = sensors {
            ensure!(s.len() == candidates.len(), "{} sensors for {} candidates: give one per candidate", s.len(), candidates.len());
        }
        let n_targets = vis.targets().len();
        let words = n_targets.div_ceil(64);
        let cells = check_size(candidates.len(), words)?;
        let mut bits = try_filled(0_u64, cells, "the seen-matrix")?;
        let weights = vis.targets().weights().to_vec();
        let total_weight = weights.iter().sum();
        threads::run(n_threads, || {
            // Each thread holds one candidate's horizon at a time: the evaluation budget, shared.
            let horizon_bounds = HORIZON_BUDGET / rayon::current_num_threads().max(1);
            bits.par_chunks_mut(words)
                .enumerate()
                .try_for_each(|(c, column)| vis.seen_bits(candidates[c], sensors.map(|s| &s[c]), horizon_bounds, column))
        })?;
        Ok(Self { n_targets, words, bits, weights, total_weight })
    }

    /// A matrix from given columns (`columns[c][t]`: candidate `c` sees target `t`), for
    /// coverage problems built elsewhere.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for no candidate, a column of another length than `weights`, or
    /// weights that are negative, not finite or all zero; [`Error::TooLarge`] as [`SeenMatrix::build`].
    pub fn from_columns(columns: &[Vec<bool>], weights: Vec<f64>) -> Result<Self> {
        ensure!(!columns.is_empty(), "there must be at least one candidate viewpoint");
        ensure!(!weights.is_empty(), "there must be at least one target");
        ensure!(columns.iter().all(|c| c.len() == weights.len()), "every column must have one entry per target ({})", weights.len());
        ensure!(weights.iter().all(|w| w.is_finite() && *w >= 0.0), "target weights must be finite and >= 0");
        let total_weight: f64 = weights.iter().sum();
        ensure!(total_weight.is_finite() && total_weight > 0.0, "target weights are all zero or sum to infinity");
        let n_targets = weights.len();
        let words = n_targets.div_ceil(64);
        let mut bits = try_filled(0_u64, check_size(columns.len(), words)?, "the seen-matrix")?;
        for (c, column) in columns.iter().enumerate() {
            for (t, _) in column.iter().enumerate().filter(|(_, &v)| v) {
                bits[c * words + t / 64] |= 1 << (t % 64);
            }
        }
        Ok(Self { n_targets, words, bits, weights, total_weight })
    }

    /// Number of candidates.
    #[must_use]
    pub fn n_candidates(&self) -> usize {
        self.bits.len() / self.words
    }

    /// Number of targets.
    #[must_use]
    pub fn n_targets(&self) -> usize {
        self.n_targets
    }

    /// Total weight of the targets (the denominator of a share).
    #[must_use]
    pub fn total_weight(&self) -> f64 {
        self.total_weight
    }

    /// The bytes the bits take.
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.bits.len() * 8
    }

    /// Whether candidate `c` sees each target.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when `c` is not a candidate.
    pub fn column(&self, c: usize) -> Result<Vec<bool>> {
        ensure!(c < self.n_candidates(), "candidate {c} of {}", self.n_candidates());
        let col = self.col(c);
        Ok((0..self.n_targets).map(|t| col[t / 64] >> (t % 64) & 1 == 1).collect())
    }

    /// The coverable ceiling: the weighted share of the targets that at least one candidate
    /// sees, which no placement on the candidates can exceed.
    #[must_use]
    pub fn ceiling(&self) -> f64 {
        self.share(&greedy::union_of_all(self))
    }

    pub(crate) fn col(&self, c: usize) -> &[u64] {
        &self.bits[c * self.words..(c + 1) * self.words]
    }

    pub(crate) fn words(&self) -> usize {
        self.words
    }

    /// The weight of the targets set in `mask` and not in `covered`, summed in target order.
    pub(crate) fn weight_of(&self, mask: &[u64], covered: Option<&[u64]>) -> f64 {
        let mut total = 0.0;
        for (k, &m) in mask.iter().enumerate() {
            let mut word = m & !covered.map_or(0, |c| c[k]);
            while word != 0 {
                total += self.weights[k * 64 + word.trailing_zeros() as usize];
                word &= word - 1;
            }
        }
        total
    }

    /// The weighted share of the targets set in `mask`: `Visibility::share`'s sum, in its order.
    pub(crate) fn share(&self, mask: &[u64]) -> f64 {
        (self.weight_of(mask, None) / self.total_weight).min(1.0)
    }

    /// `seen` (one bool per target) as bits.
    pub(crate) fn pack(&self, seen: &[bool]) -> Result<Vec<u64>> {
        ensure!(seen.len() == self.n_targets, "{} seen flags for {} targets", seen.len(), self.n_targets);
        let mut out = try_filled(0_u64, self.words, "a seen mask")?;
        for (t, _) in seen.iter().enumerate().filter(|(_, &v)| v) {
            out[t / 64] |= 1 << (t % 64);
        }
        Ok(out)
    }
}

/// The words of a matrix of `n_candidates` columns of `words` words, within [`MAX_MATRIX_BYTES`].
fn check_size(n_candidates: usize, words: usize) -> Result<usize> {
    match n_candidates.checked_mul(words).filter(|&w| w <= MAX_MATRIX_BYTES / 8) {
        Some(cells) => Ok(cells),
        None => Err(Error::TooLarge(format!(
            "a seen-matrix of {n_candidates} candidates x {} targets would exceed {} MiB: use fewer candidates or targets",
            words * 64,
            MAX_MATRIX_BYTES >> 20
        ))),
    }
}

#[cfg(test)]
mod tests;
