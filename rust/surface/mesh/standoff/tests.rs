use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;

/// A closed, outward-wound box `[lo, hi]` appended to `v`, `f`.
pub(crate) fn push_box(v: &mut Vec<Point>, f: &mut Vec<[u32; 3]>, lo: Point, hi: Point) {
    let base = u32::try_from(v.len()).unwrap();
    for k in 0..8 {
        v.push([if k & 1 == 0 { lo[0] } else { hi[0] }, if k & 2 == 0 { lo[1] } else { hi[1] }, if k & 4 == 0 { lo[2] } else { hi[2] }]);
    }
    // corners: bit 0 x, bit 1 y, bit 2 z
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    for [a, b, c, d] in quads {
        f.push([base + a, base + b, base + c]);
        f.push([base + a, base + c, base + d]);
    }
}

/// A 40 m x 20 m ground plane, two piers and a deck 10-11 m up (the bridge).
pub(crate) fn bridge() -> Surface {
    let mut v = vec![[-20.0, -10.0, 0.0], [20.0, -10.0, 0.0], [20.0, 10.0, 0.0], [-20.0, 10.0, 0.0]];
    let mut f = vec![[0, 1, 2], [0, 2, 3]];
    push_box(&mut v, &mut f, [-12.0, -3.0, 0.0], [-10.0, 3.0, 10.0]);
    push_box(&mut v, &mut f, [10.0, -3.0, 0.0], [12.0, 3.0, 10.0]);
    push_box(&mut v, &mut f, [-15.0, -3.0, 10.0], [15.0, 3.0, 11.0]);
    Surface::new(v, f).unwrap()
}

/// Distance from `q` to the closest point of any of `s`'s triangles, by brute force.
fn brute_distance(s: &Surface, q: Point) -> f64 {
    (0..s.n_triangles())
        .map(|k| {
            let [a, b, c] = s.triangle(k);
            let p = Triangle::new(a, b, c).project_local_point(v(q), true).point;
            (p - v(q)).length()
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn box_faces_are_outward() {
    let s = bridge();
    for k in 0..s.n_triangles() {
        let [a, b, c] = s.triangle(k);
        let n = (b - a).cross(c - a);
        let centre = (a + b + c) / 3.0;
        // outward: a step along the normal leaves the solid, a step against it enters one
        // (faces where a pier meets the deck or the ground excepted: both sides are solid)
        let (out, back) = (centre + n.normalize() * 0.01, centre - n.normalize() * 0.01);
        if centre.z != 10.0 && centre.z != 0.0 {
            assert!(!s.inside([out.x, out.y, out.z]).unwrap(), "face {k}");
            assert!(s.inside([back.x, back.y, back.z]).unwrap(), "face {k}");
        }
    }
}

#[test]
fn under_the_deck_is_outside_and_far_enough() {
    let s = bridge();
    let under = [0.0, 0.0, 5.0];
    assert!(!s.inside(under).unwrap());
    assert!((s.distance(under).unwrap() - 5.0).abs() < 1e-12);
    assert!(s.surface_below(under));
    assert!(s.inside([0.0, 0.0, 10.5]).unwrap()); // in the deck
    assert!(s.inside([-11.0, 0.0, 5.0]).unwrap()); // in a pier
    assert!(s.inside([-11.0, 0.0, 10.0 + 1e-9]).unwrap()); // in the deck over a pier
    assert!(!s.surface_below([0.0, 0.0, -1.0]));
    assert!(!s.inside([0.0, 0.0, 12.0]).unwrap());
}

#[test]
fn sphere_tests_and_distances_match_brute_force() {
    let s = bridge();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..3000 {
        let q = [-22.0 + 44.0 * rng.random::<f64>(), -12.0 + 24.0 * rng.random::<f64>(), -2.0 + 16.0 * rng.random::<f64>()];
        let d = brute_distance(&s, q);
        assert!((s.distance(q).unwrap() - d).abs() <= 1e-12 * (1.0 + d), "{q:?}");
        for r in [0.5, 1.0, 2.0, 4.0] {
            if (d - r).abs() > 1e-9 {
                assert_eq!(s.within(q, r, false).unwrap(), d < r, "{q:?} {r}");
                assert_eq!(s.within(q, r, true).unwrap(), d <= r, "{q:?} {r}");
            }
        }
    }
}

#[test]
fn overlapping_solids_and_a_face_given_twice_are_inside() {
    // Two closed boxes that overlap (a union exported as is): a point in both crosses an even
    // number of faces, but they do not cancel by their winding.
    let (mut v, mut f) = (Vec::new(), Vec::new());
    push_box(&mut v, &mut f, [0.0, 0.0, 0.0], [20.0, 20.0, 12.0]);
    push_box(&mut v, &mut f, [6.0, 6.0, 0.0], [26.0, 26.0, 14.0]);
    let s = Surface::new(v, f).unwrap();
    assert!(s.inside([13.0, 13.0, 6.0]).unwrap());
    assert!(s.inside([3.0, 3.0, 6.0]).unwrap() && s.inside([23.0, 23.0, 6.0]).unwrap());
    assert!(!s.inside([13.0, 13.0, 20.0]).unwrap() && !s.inside([3.0, 23.0, 6.0]).unwrap());
    // One box whose twelve faces are all given twice.
    let (mut v, mut f) = (Vec::new(), Vec::new());
    push_box(&mut v, &mut f, [0.0, 0.0, 0.0], [10.0, 10.0, 10.0]);
    f.extend(f.clone());
    let s = Surface::new(v, f).unwrap();
    assert!(s.inside([5.0, 4.0, 3.0]).unwrap());
    assert!(!s.inside([5.0, 4.0, 13.0]).unwrap() && !s.inside([-1.0, 4.0, 3.0]).unwrap());
}
