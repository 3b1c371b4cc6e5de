use super::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    (0..n).map(|_| rng.random::<f64>() * 2.0 - 1.0).collect()
}

#[test]
fn a_polynomial_in_its_own_terms_is_fitted_and_scored() {
    // y = 1 + 2 u0 - u1 + 3 u0 u1 on a 4 x 4 grid of points, fitted with every term it needs.
    let reg = Regressors::new(2, vec![[0, 1, 2]]).unwrap();
    let points: Vec<f64> = (0..16).flat_map(|k| [f64::from(k % 4) - 1.5, f64::from(k / 4) - 1.5]).collect();
    let y: Vec<f64> = points.chunks(2).map(|u| 1.0 + 2.0 * u[0] - u[1] + 3.0 * u[0] * u[1]).collect();
    let model = fit(&reg, &points, &y, 1e-12, None).unwrap();
    let score = reg.scores(&model.theta, &[0.5, 0.5]).unwrap();
    assert!((score[0] - (1.0 + 1.0 - 0.5 + 0.75)).abs() < 1e-6);
}

#[test]
fn design_rows_are_the_products_of_their_monomials() {
    let reg = Regressors::new(3, vec![[0, 0, 3], [0, 1, 2], [2, 2, 2], [1, 3, 3]]).unwrap();
    let phi = reg.design(&[2.0, 3.0, 5.0, -1.0, 0.5, 4.0]).unwrap();
    let expected = [[1.0, 2.0, 3.0, 5.0, 4.0, 30.0, 125.0, 3.0], [1.0, -1.0, 0.5, 4.0, 1.0, -2.0, 64.0, 0.5]];
    for (r, row) in expected.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            assert_eq!(phi[(r, c)], *v, "row {r} column {c}");
        }
    }
}

#[test]
fn an_exact_polynomial_is_recovered_and_scored() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let reg = Regressors::new(4, vec![[0, 1, 4], [2, 2, 3], [1, 3, 4], [0, 0, 0]]).unwrap();
    let truth: Vec<f64> = random(&mut rng, reg.len());
    let points = random(&mut rng, 60 * 4);
    let y = reg.scores(&truth, &points).unwrap();
    let model = fit(&reg, &points, &y, 1e-12, None).unwrap();
    for (a, b) in model.theta.iter().zip(&truth) {
        assert!((a - b).abs() < 1e-6, "{a} vs {b}");
    }
    let again = reg.scores(&model.theta, &points).unwrap();
    for (a, b) in again.iter().zip(&y) {
        assert!((a - b).abs() < 1e-6);
    }
}

#[test]
fn scores_are_each_candidates_own_sum_to_the_last_bit() {
    // Side by side, each sum keeps its own order: every score is the one a candidate scored
    // alone gets (`sum` of its products), whatever the count (a last block of 1-3 too).
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let reg = Regressors::new(5, vec![[0, 1, 5], [2, 2, 3], [1, 3, 4], [4, 4, 4], [0, 2, 5]]).unwrap();
    let theta: Vec<f64> = random(&mut rng, reg.len()).iter().map(|v| v * 1e3).collect();
    for n in [0, 1, 3, 4, 5, 17, 200] {
        let points: Vec<f64> = random(&mut rng, n * 5).iter().map(|v| v * 7.0).collect();
        let scores = reg.scores(&theta, &points).unwrap();
        let (mut augmented, mut row) = reg.scratch();
        for (score, u) in scores.iter().zip(points.chunks_exact(5)) {
            reg.row(u, &mut augmented, &mut row);
            let alone: f64 = row.iter().zip(&theta).map(|(a, b)| a * b).sum();
            assert_eq!(score.to_bits(), alone.to_bits());
        }
        assert_eq!(scores.len(), n);
    }
}

#[test]
fn inactive_monomials_get_zero_coefficients_and_leave_the_fit_unchanged() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let full = Regressors::new(3, vec![[0, 1, 3], [1, 2, 2], [0, 0, 3]]).unwrap();
    let kept = Regressors::new(3, vec![[0, 1, 3], [0, 0, 3]]).unwrap();
    let points = random(&mut rng, 20 * 3);
    let y = random(&mut rng, 20);
    let masked = fit(&full, &points, &y, 1e-2, Some(&[true, false, true])).unwrap();
    let direct = fit(&kept, &points, &y, 1e-2, None).unwrap();
    assert_eq!(masked.theta[5], 0.0);
    assert_eq!(masked.strength[1], 0.0);
    let pairs = [(0, 0), (1, 1), (2, 2), (3, 3), (4, 4), (6, 5)];
    for (m, d) in pairs {
        assert!((masked.theta[m] - direct.theta[d]).abs() < 1e-10);
    }
}

#[test]
fn an_empty_window_is_flat_and_a_huge_ridge_leaves_the_mean() {
    let reg = Regressors::new(2, vec![[0, 1, 2]]).unwrap();
    let flat = fit(&reg, &[], &[], 1e-3, None).unwrap();
    assert!(flat.theta.iter().all(|&v| v == 0.0) && flat.strength == vec![0.0]);
    let points = [0.0, 1.0, 1.0, 0.0, -1.0, 2.0];
    let shrunk = fit(&reg, &points, &[1.0, 2.0, 6.0], 1e12, None).unwrap();
    assert!((shrunk.theta[0] - 3.0).abs() < 1e-9 && shrunk.theta[1..].iter().all(|v| v.abs() < 1e-9));
}

#[test]
fn bad_input_is_an_error() {
    assert!(Regressors::new(0, vec![]).is_err());
    assert!(Regressors::new(2, vec![[0, 3, 1]]).is_err());
    let reg = Regressors::new(2, vec![]).unwrap();
    assert!(reg.design(&[1.0, 2.0, 3.0]).is_err());
    assert!(reg.design(&[1.0, f64::NAN]).is_err());
    assert!(reg.scores(&[1.0], &[1.0, 2.0]).is_err());
    assert!(fit(&reg, &[1.0, 2.0], &[1.0, 2.0], 1e-3, None).is_err());
    assert!(fit(&reg, &[1.0, 2.0], &[f64::INFINITY], 1e-3, None).is_err());
    assert!(fit(&reg, &[1.0, 2.0], &[1.0], 0.0, None).is_err());
    assert!(fit(&reg, &[1.0, 2.0], &[1.0], 1e-3, Some(&[true])).is_err());
}
