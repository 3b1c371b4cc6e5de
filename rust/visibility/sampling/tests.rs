use super::*;

fn square_mesh() -> Surface {
    Surface::new(vec![[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [4.0, 4.0, 0.0], [0.0, 4.0, 0.0]], vec![[0, 1, 2], [0, 2, 3]]).unwrap()
}

#[test]
fn mesh_targets_cover_the_area_evenly() {
    let s = square_mesh();
    let (pts, w) = default_targets(&s, 4.0).unwrap();
    // area 8 per triangle, density 4 -> m = ceil(sqrt(32)) = 6 -> 36 points per triangle.
    assert_eq!(pts.len(), 72);
    assert!((w.iter().sum::<f64>() - 16.0).abs() < 1e-12);
    assert!(pts.iter().all(|q| q[0] > 0.0 && q[0] < 4.0 && q[1] > 0.0 && q[1] < 4.0 && q[2] == 0.0));
    // No two targets coincide.
    for i in 0..pts.len() {
        for j in 0..i {
            assert!(pts[i] != pts[j]);
        }
    }
}

#[test]
fn bad_density_is_an_error() {
    let s = square_mesh();
    assert!(default_targets(&s, 0.0).is_err());
    assert!(default_targets(&s, f64::NAN).is_err());
}

#[test]
fn densities_too_large_are_errors_not_overflows() {
    // `sqrt(area density)` past usize::MAX used to saturate, and its square to wrap to 1.
    let s = square_mesh();
    for density in [1e7, 1e30, 1e300, f64::MAX] {
        assert!(matches!(default_targets(&s, density), Err(crate::Error::InvalidInput(_))), "{density}");
    }
}
