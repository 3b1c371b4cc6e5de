//! Reference values printed by numpy 2.4.6 (`np.random.default_rng(seed)`), e.g.
//! `g = np.random.default_rng(12345); g.bit_generator.state; g.bit_generator.random_raw(3)`.

use super::Pcg64;

/// `default_rng(12345).bit_generator.state["state"]` (the reference values of this crate's
/// tests of numpy's draws were printed from it).
pub(crate) fn seed_12345() -> Pcg64 {
    Pcg64::new(33_261_208_707_367_790_463_622_745_601_869_196_757, 268_209_174_141_567_072_605_526_753_992_732_310_247)
}

#[test]
fn raw_draws_match_numpy() {
    let mut rng = seed_12345();
    let raw: Vec<u64> = (0..3).map(|_| rng.next_u64()).collect();
    assert_eq!(raw, [0x3a32_b18d_b2ff_c19d, 0x5117_1315_c9e4_c4de, 0xcc20_2482_3444_efd9]);
}

#[test]
fn doubles_match_numpy() {
    // default_rng(12345).random(2)
    let mut rng = seed_12345();
    assert_eq!([rng.next_f64(), rng.next_f64()], [0.227_336_022_467_169_66, 0.316_758_339_709_752_87]);
}

#[test]
fn integers_and_doubles_match_numpy() {
    // g = default_rng(12345); g.integers(0, 36, 5); g.bit_generator.state; then
    // g.integers(-3, 2**32 - 3, 2), g.random(1), g.integers(0, 2**31 + 1, 3) and the state.
    let mut rng = seed_12345();
    let mut a = [0; 5];
    rng.fill_integers(0, 35, &mut a);
    assert_eq!(a, [25, 8, 28, 11, 7]);
    assert_eq!((rng.has_uint32, rng.uinteger), (true, 3_424_658_562)); // 5 halves of 3 words
    assert_eq!(rng.state, 123_100_685_240_869_032_725_484_100_130_172_923_898);
    let mut b = [0; 2];
    rng.fill_integers(-3, u32::MAX, &mut b);
    assert_eq!(b, [3_424_658_559, 2_760_304_909]); // the buffered half first
    let mut c = [0.0];
    rng.fill_f64(&mut c);
    assert_eq!(c, [0.391_109_550_601_909]);
    let mut d = [0; 3];
    rng.fill_integers(0, 1 << 31, &mut d);
    assert_eq!(d, [1_452_245_847, 714_712_467, 457_721_135]);
    assert_eq!((rng.has_uint32, rng.uinteger), (true, 802_017_220));
    assert_eq!(rng.state, 216_098_700_122_296_263_478_885_786_697_608_317_821);
}

#[test]
fn normals_match_numpy() {
    // default_rng(12345).standard_normal(3)
    let mut rng = seed_12345();
    let mut z = [0.0; 3];
    rng.fill_standard_normal(&mut z);
    assert_eq!(z, [-1.423_825_036_454_631_2, 1.263_728_458_129_110_4, -0.870_661_737_959_085_7]);
}

#[test]
fn many_normals_match_numpy() {
    // g = default_rng(12345); z = g.standard_normal(1_000_000): z[-1], the sum of the
    // values' bit patterns (mod 2^64) and the state afterwards. A million values cross the
    // tail and the wedges thousands of times.
    let mut rng = seed_12345();
    let mut z = vec![0.0; 1_000_000];
    rng.fill_standard_normal(&mut z);
    let bits = z.iter().fold(0u64, |acc, v| acc.wrapping_add(v.to_bits()));
    assert_eq!(z[999_999], LAST);
    assert_eq!(bits, BITS_SUM);
    assert_eq!(rng.state, STATE_AFTER);
    assert_eq!(rng.inc, seed_12345().inc);
}

const LAST: f64 = -1.269_747_225_305_364_8;
const BITS_SUM: u64 = 8_291_136_010_535_550_849;
const STATE_AFTER: u128 = 31_154_849_455_577_373_942_963_553_150_307_301_233;
