//! numpy's PCG64 bit generator and its `Generator.standard_normal`, `Generator.random` and
//! `Generator.integers` (the 32-bit bounded path), reproduced bit for bit.
//!
//! CAO draws its perturbations from a numpy `Generator` seeded by the user, and runs must stay
//! reproducible: the same seed must give the same mission whether these draws come from numpy
//! or from here. So [`Pcg64`] is numpy's generator state exactly (the 128-bit LCG state and
//! increment of `bit_generator.state`), and [`Pcg64::fill_standard_normal`] returns the doubles
//! numpy's sampler returns and leaves the state where numpy leaves it. It is faster (about 2.4
//! ns a value against numpy's 8, `benches/normal_draws.py`) because the loop is compiled with
//! the generator inlined, without numpy's per-value function-pointer calls, and applies the
//! random sign without a branch.
//!
//! [`Pcg64::bounded_u32`] is `Generator.integers(low, high)` for the default int64 dtype when
//! `high - low <= 2^32`: numpy then draws 32-bit words (the low half of a 64-bit output, its high
//! half kept for the next 32-bit draw, [`Pcg64::next_u32`]) and maps them onto the range by
//! Lemire's multiply-and-reject method. CAO draws its monomials this way.
//!
//! The sampler is numpy's 256-layer ziggurat (tables in `ziggurat_tables`, generated and
//! checked by `scripts/ziggurat_tables.py`). Its rare paths call the platform's `exp` and
//! `log1p`, as numpy does, so both agree where both use the same libm (one process, or one
//! machine).

use crate::cao::ziggurat_tables::{F, INV_R, K, R, W};

/// The 128-bit LCG multiplier of PCG64 (O'Neill's `PCG_DEFAULT_MULTIPLIER_128`).
const MULTIPLIER: u128 = 0x2360_ED05_1FC6_5DA4_4385_DF64_9FCC_F645;

/// numpy's `PCG64` bit generator: a 128-bit LCG whose output is the XSL-RR of the state after
/// each step.
///
/// `state` and `inc` are the integers of numpy's `bit_generator.state["state"]`, `has_uint32`
/// and `uinteger` the dict's two other entries: the high half of a 64-bit output that a 32-bit
/// draw left for the next one. 64-bit draws neither read nor change that half.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Pcg64 {
    /// The LCG state.
    pub(crate) state: u128,
    /// The LCG increment (numpy keeps it odd).
    pub(crate) inc: u128,
    /// Whether `uinteger` is the next 32-bit draw.
    pub(crate) has_uint32: bool,
    /// The buffered 32-bit half. Reading it clears `has_uint32` but leaves the value, as numpy
    /// does: the stale value is part of numpy's state dict, so it is kept to compare equal.
    pub(crate) uinteger: u32,
}

impl Pcg64 {
    /// A generator at `state` with increment `inc`, as numpy's state dict gives them, with no
    /// buffered 32-bit half (a fresh `default_rng`'s).
    #[must_use]
    pub(crate) fn new(state: u128, inc: u128) -> Self {
        Self { state, inc, has_uint32: false, uinteger: 0 }
    }

    /// A generator at numpy's whole state: the LCG's `state` and `inc`, and the 32-bit buffer.
    #[must_use]
    pub(crate) fn with_buffer(state: u128, inc: u128, has_uint32: bool, uinteger: u32) -> Self {
        Self { state, inc, has_uint32, uinteger }
    }

    /// The next 64-bit output (numpy's `random_raw`): step, then output from the new state.
    #[inline(always)]
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_mul(MULTIPLIER).wrapping_add(self.inc);
        let hi = (self.state >> 64) as u64;
        let lo = self.state as u64;
        (hi ^ lo).rotate_right((hi >> 58) as u32)
    }

    /// A double in `[0, 1)` from the top 53 bits of one draw, as numpy's `next_double`.
    #[inline]
    pub(crate) fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }

    /// The next 32-bit output (numpy's `next_uint32`): the buffered half if there is one, else
    /// the low half of a new 64-bit output, whose high half is buffered for the next call.
    #[inline]
    pub(crate) fn next_u32(&mut self) -> u32 {
        if self.has_uint32 {
            self.has_uint32 = false;
            return self.uinteger;
        }
        let word = self.next_u64();
        self.has_uint32 = true;
        self.uinteger = (word >> 32) as u32;
        word as u32
    }

    /// A value in `[0, span]` as numpy's `Generator.integers(low, low + span + 1)` draws it for
    /// the default int64 dtype (`span + 1 <= 2^32`, so numpy takes its 32-bit path): nothing is
    /// drawn for `span = 0`, one 32-bit word is the value for `span = 2^32 - 1`, and any other
    /// span is Lemire's method on 32-bit words.
    #[inline]
    pub(crate) fn bounded_u32(&mut self, span: u32) -> u32 {
        if span == 0 {
            return 0;
        }
        if span == u32::MAX {
            return self.next_u32();
        }
        // Lemire: the high half of `word * n` is uniform on [0, n) once the words whose low
        // half falls below 2^32 mod n are rejected (the values they would add make some
        // outputs one count likelier). Only a low half below n can be below that threshold,
        // so the modulo (a division) is computed only then, as numpy does.
        let n = span + 1;
        let mut m = u64::from(self.next_u32()) * u64::from(n);
        if (m as u32) < n {
            let threshold = n.wrapping_neg() % n; // (2^32 - n) mod n = 2^32 mod n
            while (m as u32) < threshold {
                m = u64::from(self.next_u32()) * u64::from(n);
            }
        }
        (m >> 32) as u32
    }

    /// Fills `out` as numpy's `Generator.integers(low, high, out.len())` does for the default
    /// int64 dtype when `high - low <= 2^32`; `span` is `high - low - 1`, and `low + span` must
    /// fit (numpy's own bound on `high`).
    pub(crate) fn fill_integers(&mut self, low: i64, span: u32, out: &mut [i64]) {
        for v in out.iter_mut() {
            *v = low + i64::from(self.bounded_u32(span));
        }
    }

    /// Fills `out` as numpy's `Generator.random(out.len())` does (one 64-bit draw a value).
    pub(crate) fn fill_f64(&mut self, out: &mut [f64]) {
        for v in out.iter_mut() {
            *v = self.next_f64();
        }
    }

    /// One standard normal value, numpy's `random_standard_normal`.
    #[inline(always)]
    pub(crate) fn standard_normal(&mut self) -> f64 {
        let r = self.next_u64();
        let (idx, rabs, x) = point(r);
        // About 99 % of draws end here; the rest go out of line, so this stays small enough
        // for the loop to keep everything in registers.
        if rabs < K[idx] {
            return x;
        }
        self.standard_normal_slow(idx, rabs, x)
    }

    /// The rejection paths: the tail for layer 0, the wedge test for the others, and a fresh
    /// draw when the point is rejected.
    #[cold]
    #[inline(never)]
    fn standard_normal_slow(&mut self, mut idx: usize, mut rabs: u64, mut x: f64) -> f64 {
        loop {
            if idx == 0 {
                loop {
                    let xx = -INV_R * (-self.next_f64()).ln_1p();
                    let yy = -(-self.next_f64()).ln_1p();
                    if yy + yy > xx * xx {
                        // numpy takes the tail's sign from bit 8 of the 52-bit part (bit 17 of
                        // the draw), not from the sign bit; kept, as it decides the output.
                        return if (rabs >> 8) & 1 == 1 { -(R + xx) } else { R + xx };
                    }
                }
            }
            // Evaluated as numpy evaluates it (no fused multiply-add), so that a point on the
            // boundary falls on the same side.
            if (F[idx - 1] - F[idx]) * self.next_f64() + F[idx] < (-0.5 * x * x).exp() {
                return x;
            }
            (idx, rabs, x) = point(self.next_u64());
            if rabs < K[idx] {
                return x;
            }
        }
    }

    /// Fills `out` with standard normal values, in order: the values and final state of
    /// numpy's `standard_normal(out.len())` from the same state.
    pub(crate) fn fill_standard_normal(&mut self, out: &mut [f64]) {
        // A local copy, so the state lives in registers across the loop rather than being
        // stored through `self` after every draw.
        let mut rng = self.clone();
        for v in out.iter_mut() {
            *v = rng.standard_normal();
        }
        *self = rng;
    }
}

/// The ziggurat's point of one 64-bit draw: `(layer, 52-bit part, signed abscissa)`. Bits 0..8
/// pick the layer, bit 8 the sign, bits 9..61 the position along the layer; the top 3 bits are
/// unused.
#[inline(always)]
fn point(r: u64) -> (usize, u64, f64) {
    let idx = (r & 0xff) as usize;
    let rabs = (r >> 9) & 0x000f_ffff_ffff_ffff;
    // The sign goes on by flipping the sign bit, exactly what negation does (0.0 becomes -0.0
    // too), but without a branch: the sign is a coin toss, and a mispredicted branch on it
    // half the time cost more than all the rest of a draw.
    let x = f64::from_bits((rabs as f64 * W[idx]).to_bits() ^ ((r >> 8) & 1) << 63);
    (idx, rabs, x)
}

#[cfg(test)]
pub(crate) mod tests;
