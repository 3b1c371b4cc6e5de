//! For each triangle, the generators that can be nearest to some point of it: the exact pruning
//! of the nearest-generator search on coarse surfaces.

use rayon::prelude::*;

use super::facing::Facing;
use super::sampler::TriangleSampler;
use crate::error::{try_with_capacity, Error, Result};
use crate::geometry::{p, Point};
use crate::surface::mesh::Surface;

/// For each triangle, the generators that can be nearest to some point of it.
///
/// The distance of a sample `y` on triangle `f` to generator `g` is `|y - g|^2 + c_g`, where the
/// facing term `c_g` (zero without one, see [`Facing`]) is constant over the triangle. Take
/// `h`, the generator nearest to the triangle's centroid. Where `g` is at least as near as `h`
/// is `|y - g|^2 + c_g <= |y - h|^2 + c_h`, linear in `y`: a closed half-space, which meets the
/// triangle exactly when it holds one of the triangle's corners (the triangle is the convex
/// hull of its corners). So a generator that is farther than `h` from all three corners is
/// never nearest anywhere on the triangle, and searching the rest (in index order) gives exactly
/// the brute-force answer, ties included. A relative slack of 1e-9 keeps rounding on the safe
/// side (an extra candidate costs only time).
pub(super) struct Candidates {
    offsets: Vec<usize>,
    pub(super) list: Vec<u32>,
    /// The facing term `c_g` of each listed generator on its triangle (empty without one).
    terms: Vec<f64>,
}

/// Corners and centroid of each triangle, for [`Candidates`].
pub(super) fn triangle_corners(surface: &Surface) -> Vec<([Point; 3], Point)> {
    (0..surface.n_triangles())
        .map(|f| {
            let [a, b, c] = surface.triangle(f);
            ([p(a), p(b), p(c)], p((a + b + c) / 3.0))
        })
        .collect()
}

pub(super) fn squared_distance(a: Point, b: Point) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
}

/// One task's list ends, candidates and facing terms.
type TaskLists = (Vec<usize>, Vec<u32>, Vec<f64>);

impl Candidates {
    /// Triangles per parallel task when building the lists.
    const TASK: usize = 256;

    /// # Errors
    /// [`Error::TooLarge`] when the system refuses the memory of the lists.
    pub(super) fn new(
        triangles: &[([Point; 3], Point)],
        generators: &[Point],
        facing: Option<&Facing<'_>>,
        sampler: &TriangleSampler,
    ) -> Result<Self> {
        let refused = || Error::TooLarge("the CVT's candidate lists need more memory than the system gives".into());
        // Each task lists its triangles' candidates; the tasks are joined in order, so the lists
        // do not depend on the thread count.
        let parts: Result<Vec<TaskLists>> = triangles
            .par_chunks(Self::TASK)
            .enumerate()
            .map(|(task, chunk)| {
                let mut ends = Vec::with_capacity(chunk.len());
                let (mut list, mut terms): (Vec<u32>, Vec<f64>) = (Vec::new(), Vec::new());
                let mut term: Vec<f64> = Vec::new();
                term.try_reserve_exact(generators.len()).map_err(|_| refused())?;
                term.resize(generators.len(), 0.0);
                for (k, &(corners, centroid)) in chunk.iter().enumerate() {
                    // Room for every generator first: a refusal is an error, not an abort.
                    list.try_reserve(generators.len()).map_err(|_| refused())?;
                    if let Some(facing) = facing {
                        terms.try_reserve(generators.len()).map_err(|_| refused())?;
                        let normal = sampler.normal(task * Self::TASK + k);
                        for (i, t) in term.iter_mut().enumerate() {
                            *t = facing.term(i, normal);
                        }
                    }
                    let h = nearest_with(generators, &term, centroid);
                    let to_h = corners.map(|v| squared_distance(v, generators[h]) + term[h]);
                    for (i, &g) in generators.iter().enumerate() {
                        let wins_somewhere =
                            corners.iter().zip(&to_h).any(|(&v, &dh)| squared_distance(v, g) + term[i] <= dh * (1.0 + 1e-9) + 1e-300);
                        if wins_somewhere {
                            list.push(i as u32);
                            if facing.is_some() {
                                terms.push(term[i]);
                            }
                        }
                    }
                    ends.push(list.len());
                }
                Ok((ends, list, terms))
            })
            .collect();
        let parts = parts?;
        let mut offsets = Vec::with_capacity(triangles.len() + 1);
        offsets.push(0);
        let total = parts.iter().map(|(_, l, _)| l.len()).sum();
        let mut list = try_with_capacity(total, "the CVT's candidate lists")?;
        let mut terms = try_with_capacity(if facing.is_some() { total } else { 0 }, "the CVT's candidate lists")?;
        for (ends, part, part_terms) in parts {
            let base = list.len();
            offsets.extend(ends.into_iter().map(|e| base + e));
            list.extend(part);
            terms.extend(part_terms);
        }
        Ok(Self { offsets, list, terms })
    }

    /// The candidates of triangle `f` (ascending indices) and their facing terms (empty without
    /// a facing term).
    #[inline]
    pub(super) fn of(&self, f: usize) -> (&[u32], &[f64]) {
        let range = self.offsets[f]..self.offsets[f + 1];
        let terms = if self.terms.is_empty() { &[][..] } else { &self.terms[range.clone()] };
        (&self.list[range], terms)
    }
}

/// The generator nearest to `y` by `|y - g|^2 + term[g]`; ties go to the lower index.
fn nearest_with(generators: &[Point], term: &[f64], y: Point) -> usize {
    let mut best = 0;
    let mut best_d = f64::INFINITY;
    for (i, &g) in generators.iter().enumerate() {
        let d = squared_distance(g, y) + term[i];
        if d < best_d {
            best_d = d;
            best = i;
        }
    }
    best
}
