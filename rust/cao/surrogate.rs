//! CAO's estimator (the paper's eqs. 3-4): polynomial regressors of normalised coordinates,
//! their ridge least-squares fit on a window of past measurements, and the scores of candidate
//! configurations.
//!
//! The regressors of a point `u` of `dim` coordinates are a constant, the `dim` coordinates, and
//! monomials of degree 2 or 3, each named by three indices into `u` augmented with a one (index
//! `dim`): `(i, j, dim)` is `u_i u_j`, `(i, j, l)` is `u_i u_j u_l`. The optimiser draws and
//! redraws the monomials (with the caller's random stream, so runs stay reproducible); this
//! module only evaluates and fits them, in one call per iteration.
//!
//! The fit minimises `mean((phi theta - y)^2) + ridge |theta[1..]|^2` (the constant is not
//! penalised) through its normal equations, with `y` centred first so the solve carries only the
//! variations. Every penalised column makes the system positive definite, so a Cholesky
//! factorisation solves it; LU and then an SVD pseudo-inverse guard against round-off on extreme
//! inputs.

use nalgebra::{DMatrix, DVector};

use crate::error::{try_filled, Error, Result};

/// Candidates whose scores [`Regressors::scores`] sums side by side.
const TOGETHER: usize = 4;

/// Pivots below this share of the largest singular value count as zero in the pseudo-inverse.
const PSEUDO_INVERSE_EPS: f64 = 1e-13;

/// The regressors of one estimator: the dimension of its points and its nonlinear monomials.
#[derive(Debug, Clone)]
pub(crate) struct Regressors {
    dim: usize,
    terms: Vec<[usize; 3]>,
}

/// A fitted estimator: its coefficients and what each nonlinear monomial contributed.
#[derive(Debug, Clone)]
pub(crate) struct Fit {
    /// `1 + dim + terms` coefficients: the constant, the linear terms, the monomials.
    pub(crate) theta: Vec<f64>,
    /// Per monomial, `|theta_j|` times the root-mean-square of its column over the window (what
    /// it contributes to the fit; the optimiser keeps the strongest). Zero on an empty window.
    pub(crate) strength: Vec<f64>,
}

impl Regressors {
    /// Regressors of `dim`-coordinate points with the monomials `terms`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when `dim` is 0 or an index exceeds `dim` (the one).
    pub(crate) fn new(dim: usize, terms: Vec<[usize; 3]>) -> Result<Self> {
        if dim == 0 {
            return Err(Error::InvalidInput("the estimator's points need at least one coordinate".into()));
        }
        if let Some(t) = terms.iter().find(|t| t.iter().any(|&i| i > dim)) {
            return Err(Error::InvalidInput(format!("monomial {t:?} has an index beyond {dim} (the coordinates and the one)")));
        }
        Ok(Self { dim, terms })
    }

    /// Number of regressors, `1 + dim + terms`.
    #[must_use]
    pub(crate) fn len(&self) -> usize {
        1 + self.dim + self.terms.len()
    }

    /// Number of points in `points` (row-major, `dim` values each).
    fn count(&self, points: &[f64], what: &str) -> Result<usize> {
        if points.len() % self.dim != 0 {
            return Err(Error::InvalidInput(format!("{what} hold {} values, not a multiple of {} coordinates", points.len(), self.dim)));
        }
        if points.iter().any(|v| !v.is_finite()) {
            return Err(Error::InvalidInput(format!("{what} contain NaN or infinite values")));
        }
        Ok(points.len() / self.dim)
    }

    /// Writes the regressors of `u` into `row` (`self.len()` values); `augmented` is scratch of
    /// `dim + 1` values whose last is one.
    fn row(&self, u: &[f64], augmented: &mut [f64], row: &mut [f64]) {
        augmented[..self.dim].copy_from_slice(u);
        row[0] = 1.0;
        row[1..=self.dim].copy_from_slice(u);
        for (out, t) in row[1 + self.dim..].iter_mut().zip(&self.terms) {
            *out = augmented[t[0]] * augmented[t[1]] * augmented[t[2]];
        }
    }

    /// Scratch for [`Regressors::row`]: the augmented point and one row.
    fn scratch(&self) -> (Vec<f64>, Vec<f64>) {
        let mut augmented = vec![0.0; self.dim + 1];
        augmented[self.dim] = 1.0;
        (augmented, vec![0.0; self.len()])
    }

    /// The design matrix `(n, len)` of `n` points given row-major.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a ragged or non-finite input, [`Error::TooLarge`] when the
    /// matrix cannot be allocated.
    #[cfg(test)] // the fit and the scores build the transpose, or no matrix at all
    pub(crate) fn design(&self, points: &[f64]) -> Result<DMatrix<f64>> {
        Ok(self.design_transposed(points)?.transpose())
    }

    /// The transpose `(len, n)` of the design matrix: one point's regressors per column,
    /// which is how a column-major matrix stores them, so the rows are written in place.
    fn design_transposed(&self, points: &[f64]) -> Result<DMatrix<f64>> {
        let n = self.count(points, "the points")?;
        let width = self.len();
        let size = n.checked_mul(width).ok_or_else(|| Error::TooLarge("a design matrix beyond the address space".into()))?;
        let mut data = try_filled(0.0, size, "the design matrix")?;
        let mut augmented = self.scratch().0;
        for (u, row) in points.chunks_exact(self.dim).zip(data.chunks_exact_mut(width)) {
            self.row(u, &mut augmented, row);
        }
        Ok(DMatrix::from_vec(width, n, data))
    }

    /// `theta . phi(u)` for each of the points (row-major), without building their design matrix.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a ragged or non-finite input or a `theta` of the wrong length.
    pub(crate) fn scores(&self, theta: &[f64], points: &[f64]) -> Result<Vec<f64>> {
        if theta.len() != self.len() {
            return Err(Error::InvalidInput(format!("theta has {} coefficients, the estimator {}", theta.len(), self.len())));
        }
        let n = self.count(points, "the candidates")?;
        let mut out = try_filled(0.0, n, "the candidates' scores")?;
        let (mut augmented, _) = self.scratch();
        let width = self.len();
        let mut rows = try_filled(0.0, TOGETHER * width, "the candidates' regressors")?;
        let step = TOGETHER * self.dim;
        for (scores, block) in out.chunks_mut(TOGETHER).zip(points.chunks(step)) {
            for (u, row) in block.chunks_exact(self.dim).zip(rows.chunks_exact_mut(width)) {
                self.row(u, &mut augmented, row);
            }
            // Each score is the sum of its products in order, as one candidate alone would
            // have it (a fold from -0.0, `sum`'s), but the candidates' sums run side by side:
            // one sum's additions wait on each other, several sums' do not.
            let mut sums = [-0.0f64; TOGETHER];
            for (j, &c) in theta.iter().enumerate() {
                for (sum, row) in sums.iter_mut().zip(rows.chunks_exact(width)) {
                    *sum += row[j] * c;
                }
            }
            scores.copy_from_slice(&sums[..scores.len()]);
        }
        Ok(out)
    }
}

/// Fits `regressors` to the values `y` measured at `points` (row-major), ridge-regularised.
///
/// `active`, when given, marks which monomials take part (one flag per monomial): the others
/// are zero columns, whose coefficients a ridge fit sets to exactly zero, so this is the fit on
/// the active columns alone. An empty window gives a flat estimator (all coefficients zero).
///
/// # Errors
/// [`Error::InvalidInput`] for inputs of mismatched sizes, non-finite values, or a `ridge` that
/// is not positive and finite.
pub(crate) fn fit(regressors: &Regressors, points: &[f64], y: &[f64], ridge: f64, active: Option<&[bool]>) -> Result<Fit> {
    if !(ridge.is_finite() && ridge > 0.0) {
        return Err(Error::InvalidInput(format!("ridge must be positive and finite, got {ridge}")));
    }
    if let Some(a) = active {
        if a.len() != regressors.terms.len() {
            return Err(Error::InvalidInput(format!("{} active flags for {} monomials", a.len(), regressors.terms.len())));
        }
    }
    let mut transposed = regressors.design_transposed(points)?;
    let n = transposed.ncols();
    if y.len() != n {
        return Err(Error::InvalidInput(format!("{} values for {n} points", y.len())));
    }
    if y.iter().any(|v| !v.is_finite()) {
        return Err(Error::InvalidInput("the measured values contain NaN or infinite values".into()));
    }
    let first = 1 + regressors.dim;
    if let Some(a) = active {
        for (j, _) in a.iter().enumerate().filter(|(_, on)| !**on) {
            transposed.row_mut(first + j).fill(0.0);
        }
    }
    let width = transposed.nrows();
    if n == 0 {
        return Ok(Fit { theta: vec![0.0; width], strength: vec![0.0; width - first] });
    }
    let mean = y.iter().sum::<f64>() / n as f64;
    let centred = DVector::from_iterator(n, y.iter().map(|v| v - mean));
    // Both the design and its transpose, so the product is a general one (nalgebra hands those
    // to matrixmultiply's blocked kernel; `tr_mul` takes a column-by-column dot product, 4x
    // slower).
    let phi = transposed.transpose();
    let mut gram = &transposed * &phi;
    let rhs = &transposed * &centred;
    let penalty = ridge * n as f64;
    for j in 1..width {
        gram[(j, j)] += penalty;
    }
    let mut theta = solve(gram, &rhs);
    theta[0] += mean;
    let strength = (first..width)
        .map(|j| {
            let rms = (phi.column(j).iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
            theta[j].abs() * rms
        })
        .collect();
    Ok(Fit { theta: theta.iter().copied().collect(), strength })
}

/// Solves the symmetric positive (semi-)definite system `gram theta = rhs`.
fn solve(gram: DMatrix<f64>, rhs: &DVector<f64>) -> DVector<f64> {
    if let Some(chol) = gram.clone().cholesky() {
        let theta = chol.solve(rhs);
        if theta.iter().all(|v| v.is_finite()) {
            return theta;
        }
    }
    if let Some(theta) = gram.clone().lu().solve(rhs) {
        if theta.iter().all(|v| v.is_finite()) {
            return theta;
        }
    }
    match gram.svd(true, true).pseudo_inverse(PSEUDO_INVERSE_EPS) {
        Ok(inverse) => inverse * rhs,
        Err(_) => DVector::zeros(rhs.len()),
    }
}

#[cfg(test)]
mod tests;
