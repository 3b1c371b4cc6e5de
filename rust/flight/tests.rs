use super::*;

fn ground() -> Surface {
    Surface::from_grid(vec![0.0; 21 * 21], 21, 21, 1.0, 1.0, 0.0, 0.0).expect("a flat grid")
}

fn limits() -> FlightLimits {
    FlightLimits {
        bounds: [0.0, 0.0, 20.0, 20.0],
        h_min: 1.0,
        h_max: Some(5.0),
        z_max: 30.0,
        d_safe: 2.0,
        check_moves: true,
        clearance: Clearance::Vertical,
    }
}

#[test]
fn each_rule_refuses_on_its_own() {
    let s = ground();
    let l = limits();
    let now = [[5.0, 5.0, 3.0], [10.0, 10.0, 3.0]];
    let ok = [[5.5, 5.0, 3.0], [10.0, 10.5, 4.0]];
    assert!(l.admissible(&s, &now, &ok).unwrap());
    let cases: [[Point; 2]; 6] = [
        [[-0.1, 5.0, 3.0], ok[1]], // out of the square
        [[5.0, 5.0, 0.5], ok[1]],  // under h_min
        [[5.0, 5.0, 5.5], ok[1]],  // over h_max
        [[9.0, 10.0, 3.0], ok[1]], // 1 m from the other UAV
        [[5.0, 5.0, -1.0], ok[1]], // under the ground: no surface below
        [[f64::NAN, 5.0, 3.0], ok[1]],
    ];
    for config in cases {
        assert!(!l.admissible(&s, &now, &config).unwrap(), "{config:?}");
    }
    let high = FlightLimits { h_max: None, z_max: 4.0, ..l };
    assert!(!high.admissible(&s, &now, &[[5.0, 5.0, 4.5], ok[1]]).unwrap());
    assert!(FlightLimits { h_max: None, ..l }.admissible(&s, &now, &[[5.0, 5.0, 5.5], ok[1]]).unwrap());
}

#[test]
fn clearances_judged_from_a_cells_plane_are_the_exact_querys() {
    // Hills with a nodata cell; points above, below and at the limits (to a few ulps), on
    // grid lines, diagonals, the border and inside cells: the same verdict as the vertical
    // query, most of them without it.
    let n = 31;
    let z: Vec<f64> =
        (0..n * n).map(|k| if k == 5 * n + 7 { f64::NAN } else { 3.0 * ((k % n) as f64 * 0.4).sin() + 0.1 * (k / n) as f64 }).collect();
    let s = Surface::from_grid(z, n, n, 1.0, 1.0, 0.0, 0.0).unwrap();
    let field = s.heightfield().unwrap();
    let l = FlightLimits {
        bounds: [0.0, 0.0, 30.0, 30.0],
        h_min: 1.0,
        h_max: Some(5.0),
        z_max: 100.0,
        d_safe: 0.0,
        check_moves: false,
        clearance: Clearance::Vertical,
    };
    let (mut fast, mut total) = (0, 0);
    for k in 0..4000_u32 {
        let t = f64::from(k);
        let (x, y) = match k % 4 {
            0 => ((t * 0.618_034) % 30.0, (t * 0.414_214) % 30.0),
            1 => (f64::from(k % 31), (t * 0.3) % 30.0),                   // on a grid line
            2 => ((t * 0.01) % 30.0, (t * 0.01) % 30.0),                  // on diagonals
            _ => (if k % 8 == 3 { 0.0 } else { 30.0 }, (t * 0.7) % 30.0), // on the border
        };
        let Some(ground) = s.ground_height(x, y) else { continue };
        for dz in [-0.5, 0.0, 0.5, 1.0, 3.0, 5.0, 7.0] {
            for ulps in [-3.0, 0.0, 3.0] {
                let q = [x, y, ground + dz + ulps * f64::EPSILON * (ground.abs() + dz.abs())];
                total += 1;
                let exact = l.clear_enough(s.clearance(q));
                assert_eq!(l.clear_enough_over(&s, q), exact, "{q:?}");
                if field
                    .interior_height(x, y)
                    .is_some_and(|(h, b)| ((q[2] - h) - 1.0).abs() > 2.0 * b && ((q[2] - h) - 5.0).abs() > 2.0 * b)
                {
                    fast += 1;
                }
            }
        }
    }
    assert!(fast > total / 10, "{fast} of {total} judged from the plane");
}

#[test]
fn moves_through_a_wall_are_refused_only_when_checked() {
    // a 10 m wall along x = 10 (grid nodes at x = 10 raised)
    let mut z = vec![0.0; 21 * 21];
    for row in 0..21 {
        z[row * 21 + 10] = 10.0;
    }
    let s = Surface::from_grid(z, 21, 21, 1.0, 1.0, 0.0, 0.0).unwrap();
    let l = FlightLimits { h_max: None, d_safe: 0.0, ..limits() };
    let now = [[8.0, 5.0, 3.0]];
    let across = [[12.0, 5.0, 3.0]];
    assert!(!l.admissible(&s, &now, &across).unwrap());
    assert!(FlightLimits { check_moves: false, ..l }.admissible(&s, &now, &across).unwrap());
    assert!(l.admissible(&s, &now, &now).unwrap()); // staying crosses nothing
}

#[test]
fn the_mask_is_the_same_for_any_thread_count_and_refuses_bad_shapes() {
    let s = ground();
    let l = limits();
    let now = [[5.0, 5.0, 3.0], [10.0, 10.0, 3.0], [15.0, 15.0, 3.0]];
    let mut candidates = Vec::new();
    for k in 0..300_u32 {
        let t = f64::from(k);
        for (i, q) in now.iter().enumerate() {
            #[allow(clippy::cast_precision_loss)]
            let phase = t * 0.37 + i as f64;
            candidates.push([q[0] + 3.0 * phase.sin(), q[1] + 3.0 * (1.3 * phase).cos(), q[2] + 2.5 * (0.7 * phase).sin()]);
        }
    }
    let one = admissible_mask(&s, &l, &now, &candidates, 1).unwrap();
    assert_eq!(one.len(), 300);
    assert!(one.iter().any(|&b| b) && one.iter().any(|&b| !b));
    assert_eq!(admissible_mask(&s, &l, &now, &candidates, 2).unwrap(), one);
    assert_eq!(admissible_mask(&s, &l, &now, &candidates, 4).unwrap(), one);
    assert!(admissible_mask(&s, &l, &[], &candidates, 1).is_err());
    assert!(admissible_mask(&s, &l, &now, &candidates[..4], 1).is_err());
    let far = FlightLimits { z_max: 1e300, h_max: None, ..l };
    assert!(admissible_mask(&s, &far, &now[..1], &[[5.0, 5.0, 1e200]], 1).is_err());
}

fn standoff() -> FlightLimits {
    FlightLimits {
        bounds: [-20.0, -10.0, 20.0, 10.0],
        h_min: 2.0,
        h_max: Some(8.0),
        z_max: 30.0,
        d_safe: 2.0,
        check_moves: true,
        clearance: Clearance::Standoff,
    }
}

#[test]
fn under_the_deck_is_admissible_only_with_a_standoff() {
    let s = crate::surface::mesh::standoff::tests::bridge();
    let now = [[0.0, 0.0, 5.0]];
    assert!(standoff().admissible(&s, &now, &now).unwrap());
    // straight down, a point inside a pier is 5 m over its floor: only the standoff refuses it
    let pier = [[-11.0, 0.0, 5.0]];
    let vertical = FlightLimits { clearance: Clearance::Vertical, h_max: None, ..standoff() };
    assert!(vertical.admissible(&s, &pier, &pier).unwrap());
    assert!(!standoff().admissible(&s, &pier, &pier).unwrap());
    let l = standoff();
    let refused = [
        [0.0, 0.0, 9.0],    // 1 m under the deck
        [-11.0, 0.0, 5.0],  // inside a pier
        [0.0, 0.0, -3.0],   // under the ground
        [0.0, 0.0, 20.0],   // 9 m over the deck, beyond h_max
        [-18.0, 9.0, 20.0], // over 11 m from everything
    ];
    for q in refused {
        assert!(!FlightLimits { check_moves: false, ..l }.admissible(&s, &[q], &[q]).unwrap(), "{q:?}");
    }
    // up through the deck: both ends keep their standoff, the move crosses it
    assert!(l.admissible(&s, &[[0.0, 0.0, 14.0]], &[[0.0, 0.0, 14.0]]).unwrap());
    assert!(!l.admissible(&s, &now, &[[0.0, 0.0, 14.0]]).unwrap());
    assert!(FlightLimits { check_moves: false, ..l }.admissible(&s, &now, &[[0.0, 0.0, 14.0]]).unwrap());
}

#[test]
fn the_standoff_mask_is_the_same_for_any_thread_count_and_as_the_full_inside_test() {
    let s = crate::surface::mesh::standoff::tests::bridge();
    let l = standoff();
    let now = [[0.0, 0.0, 5.0], [-5.0, 6.0, 13.0], [14.0, -6.0, 4.0]];
    let mut candidates = Vec::new();
    for k in 0..400_u32 {
        let t = f64::from(k);
        for (i, q) in now.iter().enumerate() {
            #[allow(clippy::cast_precision_loss)]
            let phase = t * 0.37 + i as f64;
            candidates.push([q[0] + 4.0 * phase.sin(), q[1] + 4.0 * (1.3 * phase).cos(), q[2] + 4.0 * (0.7 * phase).sin()]);
        }
    }
    let one = admissible_mask(&s, &l, &now, &candidates, 1).unwrap();
    assert!(one.iter().filter(|&&b| b).count() > 20 && one.iter().filter(|&&b| !b).count() > 20);
    assert_eq!(admissible_mask(&s, &l, &now, &candidates, 2).unwrap(), one);
    assert_eq!(admissible_mask(&s, &l, &now, &candidates, 3).unwrap(), one);
    // the shortcuts (no inside test after a clear move from outside, no sphere query when the
    // old distance bounds the new one) change no answer
    for (config, &ok) in candidates.chunks(3).zip(&one) {
        let full = l.admissible_from(&s, &now, &Now::default(), config).unwrap();
        assert_eq!(full, ok, "{config:?}");
    }
}
