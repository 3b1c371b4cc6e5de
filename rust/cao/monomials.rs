//! CAO's random monomials: which ones survive a refresh, and the fresh ones drawn with numpy's
//! PCG64 stream, exactly as `uavcov.cao._refresh_terms_numpy` and `_draw_monomials` draw them.
//!
//! A monomial is a sorted index triple into the `dim` coordinates augmented with a constant
//! (index `dim`): `(i, j, dim)` is `u_i u_j`, `(i, j, l)` is `u_i u_j u_l`. Every iteration CAO
//! keeps its strongest monomials and redraws the others, which took numpy about 20 us in a
//! dozen small calls (an argsort, then a batch of integers and one of doubles per round of the
//! rejection loop); here it is one call. A seeded run must not change, so the draws are numpy's
//! (the same words, the same rounds and batch sizes, the same early stop) and the generator is
//! left where numpy leaves it, 32-bit buffer included.
//!
//! With few variables most monomials are taken and rejection would be slow; numpy then samples
//! without replacement (`rng.choice`), which is not reproduced: [`redraw`] answers `None` and
//! leaves the generator alone, and the caller draws with numpy.

use std::cmp::Ordering;
use std::collections::HashSet;
use std::hash::{BuildHasherDefault, Hasher};

use crate::cao::pcg64::Pcg64;
use crate::error::{ensure, try_with_capacity, Error, Result};

/// At most this many monomials in or out of one call (2^28): far beyond any surrogate (each is a
/// column of the design matrix), and checked before allocating.
pub(crate) const MAX_MONOMIALS: usize = 1 << 28;

/// Variables at most (2^32): numpy draws their indices on its 32-bit path, the one reproduced.
pub(crate) const MAX_DIM: u64 = 1 << 32;

/// How many distinct monomials of degree 2 and 3 `dim` variables have:
/// `C(dim + 1, 2) + C(dim + 2, 3)`.
#[must_use]
pub(crate) fn n_distinct(dim: u64) -> u128 {
    let d = u128::from(dim);
    // Each product of consecutive integers is divisible by the factorial; at most ~2^97.
    (d + 1) * d / 2 + (d + 2) * (d + 1) * d / 6
}

/// The indices of the `keep` strongest monomials, in index order: the first `keep` of a stable
/// sort by decreasing strength, as numpy's `argsort(-strength, kind="stable")` orders them
/// (equal strengths by position, `-0.0` equal to `0.0`, NaN after every number).
#[must_use]
pub(crate) fn strongest(strength: &[f64], keep: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..strength.len()).collect();
    order.sort_by(|&i, &j| by_decreasing(strength[i], strength[j])); // stable
    order.truncate(keep);
    order.sort_unstable();
    order
}

/// numpy's ascending order of `-a` and `-b`: NaNs last (equal to each other), numbers by value.
fn by_decreasing(a: f64, b: f64) -> Ordering {
    match (a.is_nan(), b.is_nan()) {
        (true, true) => Ordering::Equal,
        (true, false) => Ordering::Greater,
        (false, true) => Ordering::Less,
        (false, false) => b.partial_cmp(&a).unwrap_or(Ordering::Equal),
    }
}

/// The monomials kept by CAO's refresh (the `keep` strongest of `terms`, in index order)
/// followed by `count` fresh ones distinct from them and from each other, drawn from `rng` as
/// `_draw_monomials` draws them; `None` (with `rng` untouched) when numpy samples without
/// replacement instead, i.e. when `4 (distinct kept + count) > n_distinct(dim)`.
///
/// # Errors
///
/// [`Error::InvalidInput`] when `strength` and `terms` differ in length, `keep` exceeds it, an
/// index is outside `[0, dim]`, `dim` exceeds [`MAX_DIM`], or fewer than `count` monomials are
/// left to draw; [`Error::TooLarge`] past [`MAX_MONOMIALS`] or when memory is refused.
pub(crate) fn redraw(
    terms: &[[i64; 3]],
    strength: &[f64],
    keep: usize,
    count: usize,
    dim: u64,
    rng: &mut Pcg64,
) -> Result<Option<Vec<[i64; 3]>>> {
    ensure!(strength.len() == terms.len(), "strength has {} values for {} terms", strength.len(), terms.len());
    ensure!(keep <= terms.len(), "cannot keep {keep} of {} terms", terms.len());
    ensure!(dim <= MAX_DIM, "dim must be at most {MAX_DIM}, got {dim}");
    if terms.len() > MAX_MONOMIALS || count > MAX_MONOMIALS {
        return Err(Error::TooLarge(format!("{} terms and {count} new ones in one call, more than {MAX_MONOMIALS}", terms.len())));
    }
    let max_index = dim as i64; // <= 2^32
    if let Some(row) = terms.iter().find(|row| row.iter().any(|&v| !(0..=max_index).contains(&v))) {
        return Err(Error::InvalidInput(format!("terms must hold indices in [0, {dim}], got {row:?}")));
    }
    let mut out = try_with_capacity(keep + count, "the monomials")?;
    out.extend(strongest(strength, keep).into_iter().map(|i| terms[i]));
    if count == 0 {
        return Ok(Some(out));
    }
    // A triple as one integer, `(a (dim + 1) + b) (dim + 1) + c`, so membership is a set of
    // integers (the reference's key; at most ~2^97).
    let base = u128::from(dim) + 1;
    let key = |[a, b, c]: [u64; 3]| (u128::from(a) * base + u128::from(b)) * base + u128::from(c);
    let mut taken = KeySet::default();
    taken.try_reserve(keep + count).map_err(|_| Error::TooLarge(format!("a set of {} monomials", keep + count)))?;
    taken.extend(out.iter().map(|row| key(row.map(|v| v as u64))));
    let total = n_distinct(dim);
    // `taken` may exceed `total` (unsorted triples are distinct keys), so no subtraction.
    let wanted = taken.len() as u128 + count as u128;
    ensure!(wanted <= total, "cannot draw {count} new monomials of {dim} variables");
    if 4 * wanted > total {
        return Ok(None);
    }
    // dim >= 2 here (one variable has 2 monomials, too few for the rejection path), so the
    // index range [0, dim) is `span = dim - 1` in [1, 2^32 - 1].
    let span = (dim - 1) as u32;
    let mut rows: Vec<[u32; 3]> = try_with_capacity(2 * count + 4, "a batch of index triples")?;
    let mut fresh = 0;
    while fresh < count {
        // numpy draws a whole batch, `integers(0, dim, (2 need + 4, 3))` and then
        // `random(2 need + 4)`, before testing any of it: the indices first, in row order.
        let batch = 2 * (count - fresh) + 4;
        rows.clear();
        rows.extend((0..batch).map(|_| {
            let a = rng.bounded_u32(span);
            let b = rng.bounded_u32(span);
            [a, b, rng.bounded_u32(span)]
        }));
        let mut used = 0;
        for row in &rows {
            used += 1;
            let mut triple = row.map(u64::from);
            if rng.next_f64() < 0.5 {
                triple[2] = dim; // degree 2: the third factor is the constant
            }
            triple.sort_unstable();
            if taken.insert(key(triple)) {
                out.push(triple.map(|v| v as i64));
                fresh += 1;
                if fresh == count {
                    break;
                }
            }
        }
        // The doubles numpy drew for the rows the loop did not reach.
        for _ in used..batch {
            rng.next_u64();
        }
    }
    Ok(Some(out))
}

/// A set of monomial keys with a multiplicative hash: the keys are few and not adversarial, and
/// std's `SipHash` would cost more than the draws.
type KeySet = HashSet<u128, BuildHasherDefault<KeyHasher>>;

/// Fibonacci hashing of a `u128` key (its halves folded); bytes for anything else.
#[derive(Debug, Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }

    fn write_u128(&mut self, key: u128) {
        // The high bits of the product feed hashbrown's bucket index and its control byte, so
        // both halves of the key must reach them: fold, multiply, then mix the top down.
        let folded = (key as u64) ^ ((key >> 64) as u64).rotate_left(29);
        let h = folded.wrapping_mul(0x9e37_79b9_7f4a_7c15);
        self.0 = h ^ (h >> 32);
    }
}

#[cfg(test)]
mod tests;
