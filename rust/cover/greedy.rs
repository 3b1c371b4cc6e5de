//! Lazy greedy on a seen-matrix, and the online bound on its optimum.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::SeenMatrix;
use crate::error::{ensure, try_filled, Result};
use crate::geometry::Point;
use crate::threads;

/// Greedy's placement and what it is certified against.
#[derive(Debug, Clone, PartialEq)]
pub struct Greedy {
    /// The candidates picked, in the order picked (fewer than `k` when the separation leaves no
    /// candidate).
    pub picks: Vec<usize>,
    /// The weighted share of the targets each pick added, in the order picked.
    pub gains: Vec<f64>,
    /// The weighted share of the targets the picks see together.
    pub coverage: f64,
    /// An upper bound on the weighted share that any `k` candidates see together (with or
    /// without the separation): the smallest of the online bounds given each prefix of the
    /// picks (none, the first, the first two, ..., all), at most the coverable ceiling.
    pub bound: f64,
}

/// The online bound for one placement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    /// The weighted share of the targets the placement sees.
    pub coverage: f64,
    /// An upper bound on the weighted share that any `k` candidates see together: the
    /// placement's coverage plus the `k` largest marginal gains over the candidates given it, at
    /// most the coverable ceiling. It may fall below `coverage` when the placement is off the
    /// candidates and sees more than any `k` of them can.
    pub bound: f64,
}

/// A candidate and an upper bound on its marginal gain, exact when `stamp` is the number of
/// picks at the time: the heap's largest gain first, the lowest index among equal gains.
#[derive(Debug, PartialEq)]
struct Entry {
    gain: f64,
    candidate: usize,
    stamp: usize,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        self.gain.total_cmp(&other.gain).then(other.candidate.cmp(&self.candidate))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Every candidate's marginal gain (weight) given the targets in `covered`, in parallel.
fn gains(matrix: &SeenMatrix, covered: &[u64], n_threads: usize) -> Vec<f64> {
    threads::run(n_threads, || (0..matrix.n_candidates()).into_par_iter().map(|c| matrix.weight_of(matrix.col(c), Some(covered))).collect())
}

/// The sum of the `k` largest of `gains`, largest first.
fn top_sum(gains: &[f64], k: usize) -> f64 {
    let mut sorted = gains.to_vec();
    sorted.sort_by(|a, b| b.total_cmp(a));
    sorted.iter().take(k).fold(0.0, |acc, g| acc + g)
}

/// The online bound (weight) given the covered targets of weight `covered_weight`, capped by
/// the ceiling's weight. Every weight here is a sum of non-negative terms in target order, each
/// within `n_targets` roundings (relative `f64::EPSILON` each) of its exact value, so the bound
/// takes that much room, to stay above a subset's sum computed the same way.
fn online(matrix: &SeenMatrix, covered_weight: f64, gains: &[f64], k: usize, ceiling: f64) -> f64 {
    let room = 2.0 * matrix.n_targets() as f64 * f64::EPSILON * matrix.total_weight();
    (covered_weight + top_sum(gains, k) + room).min(ceiling)
}

/// Weighted greedy of `k` candidates (`positions[c]`: where candidate `c` is, m), each pick the
/// candidate of the largest marginal gain (the lowest index among equal gains) at least `d_safe`
/// from every earlier pick, by lazy evaluation: the picks and gains of plain greedy, exactly.
///
/// # Errors
/// [`crate::Error::InvalidInput`] when `k` is 0, `positions` is not one point per candidate or
/// `d_safe` is negative or not finite.
pub fn greedy(matrix: &SeenMatrix, positions: &[Point], k: usize, d_safe: f64, n_threads: usize) -> Result<Greedy> {
    let n = matrix.n_candidates();
    ensure!(k > 0, "k must be at least 1");
    ensure!(positions.len() == n, "{} positions for {n} candidates", positions.len());
    ensure!(d_safe.is_finite() && d_safe >= 0.0, "d_safe must be finite and >= 0, got {d_safe}");
    let mut covered = try_filled(0_u64, matrix.words(), "the covered targets")?;
    let mut excluded = try_filled(false, n, "the excluded candidates")?;
    let ceiling = matrix.weight_of(&union_of_all(matrix), None);
    let first = gains(matrix, &covered, n_threads);
    let empty_bound = online(matrix, 0.0, &first, k, ceiling);
    let mut heap: BinaryHeap<Entry> = first.iter().enumerate().map(|(candidate, &gain)| Entry { gain, candidate, stamp: 0 }).collect();
    let (mut picks, mut gains_w) = (Vec::with_capacity(k.min(n)), Vec::with_capacity(k.min(n)));
    while picks.len() < k {
        let Some(top) = heap.pop() else { break };
        if excluded[top.candidate] {
            continue;
        }
        if top.stamp < picks.len() {
            let gain = matrix.weight_of(matrix.col(top.candidate), Some(&covered));
            heap.push(Entry { gain, candidate: top.candidate, stamp: picks.len() });
            continue;
        }
        let c = top.candidate;
        for (a, b) in covered.iter_mut().zip(matrix.col(c)) {
            *a |= b;
        }
        picks.push(c);
        gains_w.push(top.gain);
        excluded[c] = true;
        let least = d_safe * d_safe;
        for (e, p) in excluded.iter_mut().zip(positions) {
            let d = [p[0] - positions[c][0], p[1] - positions[c][1], p[2] - positions[c][2]];
            *e |= d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < least;
        }
    }
    // The online bound holds given any set, so given every prefix of the picks: the smallest.
    let mut bound = empty_bound;
    let mut prefix = try_filled(0_u64, matrix.words(), "the covered targets")?;
    for &c in &picks {
        for (a, b) in prefix.iter_mut().zip(matrix.col(c)) {
            *a |= b;
        }
        let given = gains(matrix, &prefix, n_threads);
        bound = bound.min(online(matrix, matrix.weight_of(&prefix, None), &given, k, ceiling));
    }
    let total = matrix.total_weight();
    Ok(Greedy {
        picks,
        gains: gains_w.iter().map(|g| g / total).collect(),
        coverage: matrix.share(&covered),
        bound: (bound / total).min(1.0),
    })
}

/// The online bound for any placement of `k` UAVs whose true seen set is `seen` (one flag per
/// target: greedy's picks, or positions off the candidates such as an optimiser's final ones):
/// no `k` candidates see more than the placement's weight plus the `k` largest marginal gains
/// of the candidates given `seen` (Leskovec et al. 2007), nor more than the ceiling.
///
/// # Errors
/// [`crate::Error::InvalidInput`] when `k` is 0 or `seen` is not one flag per target.
pub fn bound(matrix: &SeenMatrix, seen: &[bool], k: usize, n_threads: usize) -> Result<Bound> {
    ensure!(k > 0, "k must be at least 1");
    let covered = matrix.pack(seen)?;
    let ceiling = matrix.weight_of(&union_of_all(matrix), None);
    let g = gains(matrix, &covered, n_threads);
    let value = online(matrix, matrix.weight_of(&covered, None), &g, k, ceiling);
    Ok(Bound { coverage: matrix.share(&covered), bound: (value / matrix.total_weight()).min(1.0) })
}

/// The targets at least one candidate sees.
pub(super) fn union_of_all(matrix: &SeenMatrix) -> Vec<u64> {
    let mut any = vec![0_u64; matrix.words()];
    for c in 0..matrix.n_candidates() {
        for (a, b) in any.iter_mut().zip(matrix.col(c)) {
            *a |= b;
        }
    }
    any
}
