use super::*;

const X: Point = [1.0, 0.0, 0.0];
const Y: Point = [0.0, 1.0, 0.0];
const Z: Point = [0.0, 0.0, 1.0];
const DOWN: Point = [0.0, 0.0, -1.0];

#[test]
fn an_omnidirectional_sensor_is_a_ball_and_a_minimum_range_a_shell() {
    let ball = Sensor::omnidirectional(10.0).unwrap();
    assert!(ball.accepts([0.0; 3], [10.0, 0.0, 0.0]) && !ball.accepts([0.0; 3], [10.001, 0.0, 0.0]));
    assert!(ball.accepts([0.0; 3], [0.0; 3]));
    let shell = Sensor::new(3.0, 10.0, None).unwrap();
    assert!(!shell.accepts([0.0; 3], [0.0, 2.9, 0.0]) && shell.accepts([0.0; 3], [0.0, 3.0, 0.0]));
}

#[test]
fn the_frustum_boundary_is_inside_and_behind_is_outside() {
    // forward +y, 90 deg wide (tan 1), 2 * atan(0.5) high
    let f = Frustum::new(Y, X, Z, 1.0, 0.5).unwrap();
    assert!(f.contains([2.0, 2.0, 0.0]) && f.contains([-2.0, 2.0, 1.0]));
    assert!(!f.contains([2.5, 2.0, 0.0]) && !f.contains([0.0, 2.0, 1.5]));
    assert!(!f.contains([0.0, -1.0, 0.0]) && !f.contains([0.0; 3]));
    let nadir = Frustum::new(DOWN, X, Y, 1.0, 1.0).unwrap();
    assert!(nadir.contains([1.0, -1.0, -1.0]) && !nadir.contains([0.0, 0.0, 1.0]));
}

#[test]
fn a_box_the_frustum_misses_holds_no_point_it_contains() {
    let cams = [Frustum::new(Y, X, Z, 1.0, 0.5).unwrap(), Frustum::new(DOWN, X, Y, 0.6, 0.4).unwrap()];
    let mut state = 7u64;
    let mut next = || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 20.0 - 10.0
    };
    let (mut culled, mut kept) = (0, 0);
    for cam in cams {
        for _ in 0..400 {
            let c = [next(), next(), next()];
            let h = [next().abs() / 4.0, next().abs() / 4.0, next().abs() / 4.0];
            let (lo, hi) = ([c[0] - h[0], c[1] - h[1], c[2] - h[2]], [c[0] + h[0], c[1] + h[1], c[2] + h[2]]);
            if cam.misses_box([0.0; 3], lo, hi) {
                culled += 1;
                for k in 0..=10 {
                    for m in 0..=10 {
                        for n in 0..=10 {
                            let t = [f64::from(k) / 10.0, f64::from(m) / 10.0, f64::from(n) / 10.0];
                            let p = [lo[0] + t[0] * (hi[0] - lo[0]), lo[1] + t[1] * (hi[1] - lo[1]), lo[2] + t[2] * (hi[2] - lo[2])];
                            assert!(!cam.contains(p), "{p:?} in a culled box");
                        }
                    }
                }
            } else {
                kept += 1;
            }
        }
    }
    assert!(culled > 100 && kept > 100, "{culled} culled, {kept} kept");
}

#[test]
fn bad_sensors_are_errors() {
    assert!(Frustum::new([0.0, 2.0, 0.0], X, Z, 1.0, 1.0).is_err()); // not unit
    assert!(Frustum::new(Y, Y, Z, 1.0, 1.0).is_err()); // not orthogonal
    assert!(Frustum::new(Y, X, Z, 0.0, 1.0).is_err());
    assert!(Frustum::new(Y, X, Z, f64::INFINITY, 1.0).is_err());
    assert!(Frustum::new(Y, X, [f64::NAN, 0.0, 1.0], 1.0, 1.0).is_err());
    assert!(Sensor::new(0.0, 0.0, None).is_err());
    assert!(Sensor::new(-1.0, 5.0, None).is_err());
    assert!(Sensor::new(5.0, 5.0, None).is_err());
    assert!(Sensor::new(0.0, f64::NAN, None).is_err());
}
