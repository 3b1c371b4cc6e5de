use super::*;
use crate::cao::pcg64::tests::seed_12345;

#[test]
fn counts_of_distinct_monomials() {
    assert_eq!([0, 1, 2, 3, 36].map(n_distinct), [0, 2, 7, 16, 9102]);
    assert_eq!(n_distinct(MAX_DIM), 13_204_693_770_824_133_676_212_682_752);
}

#[test]
fn the_strongest_in_index_order_ties_by_position() {
    let s = [1.0, 3.0, f64::NAN, 3.0, -0.0, 0.0, 2.0];
    assert_eq!(strongest(&s, 0), Vec::<usize>::new());
    assert_eq!(strongest(&s, 1), [1]);
    assert_eq!(strongest(&s, 3), [1, 3, 6]);
    assert_eq!(strongest(&s, 5), [0, 1, 3, 4, 6]);
    assert_eq!(strongest(&s, 7), [0, 1, 2, 3, 4, 5, 6]);
}

#[test]
fn draws_distinct_sorted_triples_or_defers_to_numpy() {
    let mut rng = seed_12345();
    let terms = [[0, 1, 36], [2, 2, 2], [5, 7, 9]];
    let out = redraw(&terms, &[1.0, 0.5, 2.0], 2, 10, 36, &mut rng).unwrap().unwrap();
    assert_eq!(&out[..2], &[[0, 1, 36], [5, 7, 9]]);
    assert_eq!(out.len(), 12);
    let keys: HashSet<_> = out.iter().collect();
    assert_eq!(keys.len(), 12);
    assert!(out.iter().all(|t| t[0] <= t[1] && t[1] <= t[2] && t[2] <= 36));
    assert_ne!(rng, seed_12345());
    // 3 variables have 16 monomials: drawing 5 of them is numpy's `choice` (4 is not).
    let mut rng = seed_12345();
    assert_eq!(redraw(&[], &[], 0, 5, 3, &mut rng), Ok(None));
    assert_eq!(rng, seed_12345());
    assert_eq!(redraw(&[], &[], 0, 0, 0, &mut rng), Ok(Some(vec![])));
}

#[test]
fn bad_input_is_an_error() {
    let mut rng = seed_12345();
    assert!(matches!(redraw(&[[0, 0, 0]], &[], 0, 1, 9, &mut rng), Err(Error::InvalidInput(_))));
    assert!(matches!(redraw(&[[0, 0, 0]], &[1.0], 2, 1, 9, &mut rng), Err(Error::InvalidInput(_))));
    assert!(matches!(redraw(&[[0, 0, 10]], &[1.0], 1, 1, 9, &mut rng), Err(Error::InvalidInput(_))));
    assert!(matches!(redraw(&[[-1, 0, 1]], &[1.0], 1, 1, 9, &mut rng), Err(Error::InvalidInput(_))));
    assert!(matches!(redraw(&[], &[], 0, 17, 3, &mut rng), Err(Error::InvalidInput(_))));
    assert!(matches!(redraw(&[], &[], 0, 1, MAX_DIM + 1, &mut rng), Err(Error::InvalidInput(_))));
    assert!(matches!(redraw(&[], &[], 0, MAX_MONOMIALS + 1, 1 << 20, &mut rng), Err(Error::TooLarge(_))));
    assert_eq!(rng, seed_12345());
}
