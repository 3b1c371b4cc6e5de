use super::*;

fn plane() -> Surface {
    Surface::from_grid(vec![0.0; 9], 3, 3, 1.0, 1.0, 0.0, 0.0).unwrap()
}

#[test]
fn grid_triangulation_counts_and_area() {
    let s = plane();
    assert_eq!(s.n_vertices(), 9);
    assert_eq!(s.n_triangles(), 8);
    assert!((s.area() - 4.0).abs() < 1e-12);
}

#[test]
fn nodata_removes_touching_triangles() {
    let mut z = vec![0.0; 9];
    z[0] = f64::NAN; // corner (0, 0): used only by the two triangles of cell (0, 0)
    let s = Surface::from_grid(z, 3, 3, 1.0, 1.0, 0.0, 0.0).unwrap();
    assert_eq!(s.n_triangles(), 6);
    assert_eq!(s.n_vertices(), 8);
}

#[test]
fn vertical_queries_on_a_tilted_grid() {
    // z = x + 2 y on a 3 x 3 grid: planar, so every query is exact.
    let z: Vec<f64> = (0..9).map(|k| f64::from(k % 3) + 2.0 * f64::from(k / 3)).collect();
    let s = Surface::from_grid(z, 3, 3, 1.0, 1.0, 0.0, 0.0).unwrap();
    let h = s.ground_height(0.3, 1.2).unwrap();
    assert!((h - 2.7).abs() < 1e-12);
    assert!((s.clearance([0.3, 1.2, 5.0]) - 2.3).abs() < 1e-12);
    assert_eq!(s.ground_height(-0.1, 0.5), None);
    assert_eq!(s.clearance([0.3, 1.2, 1.0]), f64::INFINITY);
}

#[test]
fn ground_height_on_the_border_edge_of_a_mesh() {
    // A thin triangle whose long edge lies on x = 0: the vertical ray there grazes the edge.
    let s = Surface::new(vec![[0.149, 97.346, 4.94], [0.0, 100.0, 4.37], [0.0, 0.0, 1e-5]], vec![[0, 1, 2]]).unwrap();
    let h = s.ground_height(0.0, 50.0).expect("a point on the edge has a ground height");
    let expected = 1e-5 + (4.37 - 1e-5) * 0.5;
    assert!((h - expected).abs() < 1e-6, "{h} vs {expected}");
    assert_eq!(s.ground_height(-0.001, 50.0), None);
}

#[test]
fn segments_and_sight() {
    let s = plane();
    assert!(s.segment_clear([0.5, 0.5, 1.0], [1.5, 1.5, 2.0]));
    assert!(!s.segment_clear([0.5, 0.5, 1.0], [0.5, 0.5, -1.0]));
    // A target on the surface is visible from above: its own triangle is not in the way.
    assert!(s.line_of_sight([1.0, 1.0, 3.0], [0.25, 0.5, 0.0]));
    // From below, the surface hides a point above it.
    assert!(!s.line_of_sight([1.0, 1.0, -1.0], [1.2, 1.1, 1.0]));
}

#[test]
fn closest_point_projects_onto_the_plane() {
    let s = plane();
    let q = s.closest_point([0.7, 1.3, 4.0]);
    assert!((q[0] - 0.7).abs() < 1e-12 && (q[1] - 1.3).abs() < 1e-12 && q[2].abs() < 1e-12);
}

#[test]
fn bad_meshes_are_errors() {
    assert!(matches!(Surface::new(vec![[0.0; 3]], vec![]), Err(Error::Mesh(_))));
    let tri = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert!(matches!(Surface::new(tri.clone(), vec![[0, 1, 3]]), Err(Error::Mesh(_))));
    assert!(matches!(Surface::new(tri.clone(), vec![[0, 1, 1]]), Err(Error::Mesh(_))));
    let mut bad = tri.clone();
    bad[0][2] = f64::NAN;
    assert!(matches!(Surface::new(bad, vec![[0, 1, 2]]), Err(Error::Mesh(_))));
    assert!(matches!(Surface::from_grid(vec![0.0; 2], 1, 2, 1.0, 1.0, 0.0, 0.0), Err(Error::InvalidInput(_))));
    assert!(matches!(Surface::from_grid(vec![0.0; 4], 2, 2, 0.0, 1.0, 0.0, 0.0), Err(Error::InvalidInput(_))));
    assert!(matches!(Surface::from_grid(vec![f64::NAN; 4], 2, 2, 1.0, 1.0, 0.0, 0.0), Err(Error::Mesh(_))));
}

#[test]
fn meshes_beyond_the_coordinate_bound_are_refused() {
    let tri = |scale: f64| vec![[0.0, 0.0, 0.0], [scale, 0.0, 0.0], [0.0, scale, 0.0]];
    assert!(matches!(Surface::new(tri(1e300), vec![[0, 1, 2]]), Err(Error::Mesh(_))));
    assert!(matches!(Surface::new(tri(2e15), vec![[0, 1, 2]]), Err(Error::Mesh(_))));
    let s = Surface::new(tri(1e15), vec![[0, 1, 2]]).unwrap();
    assert!(s.area().is_finite() && s.area() > 0.0);
    // Squared distances at the bound stay finite: the closest point of a far query is a corner.
    assert_eq!(s.closest_point([-1e15, -1e15, -1e15]), [0.0, 0.0, 0.0]);
}
