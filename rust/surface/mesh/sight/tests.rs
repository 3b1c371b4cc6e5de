use super::*;
use crate::surface::mesh::Surface;
use crate::surface::skyline::sector_edges;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A test scene of one of four kinds: a rough terrain grid, a ground with boxes (vertical
/// walls, flat roofs), the terrain with a floating slab over part of it (an overhang), and a
/// soup of random triangles of every tilt.
fn scene(rng: &mut ChaCha8Rng, kind: usize) -> Surface {
    let mut v: Vec<Point> = Vec::new();
    let mut f: Vec<[u32; 3]> = Vec::new();
    let n: u32 = 14;
    let ground = |v: &mut Vec<Point>, f: &mut Vec<[u32; 3]>, rng: &mut ChaCha8Rng, rough: f64| {
        let base = v.len() as u32;
        for i in 0..n {
            for j in 0..n {
                let (y, x) = (f64::from(i), f64::from(j));
                let z = rough * ((0.5 * y).sin() + (0.4 * x).cos()) + rough * rng.random::<f64>();
                v.push([x, y, z]);
            }
        }
        for i in 0..n - 1 {
            for j in 0..n - 1 {
                let k = base + i * n + j;
                f.push([k, k + 1, k + n + 1]);
                f.push([k, k + n + 1, k + n]);
            }
        }
    };
    match kind {
        0 => ground(&mut v, &mut f, rng, 1.5),
        1 => {
            ground(&mut v, &mut f, rng, 0.0);
            for _ in 0..4 {
                let (x, y) = (rng.random_range(1.0..9.0), rng.random_range(1.0..9.0));
                let (w, d, h) = (rng.random_range(1.0..3.0), rng.random_range(1.0..3.0), rng.random_range(1.0..5.0));
                let b = v.len() as u32;
                for &(px, py) in &[(x, y), (x + w, y), (x + w, y + d), (x, y + d)] {
                    v.push([px, py, 0.0]);
                    v.push([px, py, h]);
                }
                for s in 0..4u32 {
                    let (a0, a1, b0, b1) = (b + 2 * s, b + 2 * s + 1, b + 2 * ((s + 1) % 4), b + 2 * ((s + 1) % 4) + 1);
                    f.push([a0, b0, b1]);
                    f.push([a0, b1, a1]);
                }
                f.push([b + 1, b + 3, b + 5]);
                f.push([b + 1, b + 5, b + 7]);
            }
        }
        2 => {
            ground(&mut v, &mut f, rng, 1.0);
            let b = v.len() as u32;
            for &(px, py) in &[(3.0, 3.0), (9.0, 3.5), (8.5, 9.0), (3.5, 8.0)] {
                v.push([px, py, 5.0 + rng.random::<f64>()]);
            }
            f.push([b, b + 1, b + 2]);
            f.push([b, b + 2, b + 3]);
        }
        _ => {
            for _ in 0..60 {
                let b = v.len() as u32;
                let c = [rng.random_range(0.0..12.0), rng.random_range(0.0..12.0), rng.random_range(0.0..4.0)];
                for _ in 0..3 {
                    v.push([c[0] + rng.random_range(-1.5..1.5), c[1] + rng.random_range(-1.5..1.5), c[2] + rng.random_range(-1.5..1.5)]);
                }
                if rng.random::<f64>() < 0.3 {
                    let (x, y) = (v[b as usize][0], v[b as usize][1]);
                    v[b as usize + 1][0] = x; // a vertical triangle
                    v[b as usize + 1][1] = y;
                }
                f.push([b, b + 1, b + 2]);
            }
        }
    }
    Surface::new(v, f).unwrap()
}

/// Points on the triangles (at corners, on edges, inside), and random points.
fn on_surface(rng: &mut ChaCha8Rng, corners: &[[parry3d_f64::math::Vector; 3]]) -> Point {
    let [a, b, c] = corners[rng.random_range(0..corners.len())];
    let (mut u, mut w) = (rng.random::<f64>(), rng.random::<f64>());
    match rng.random_range(0..6) {
        0 => (u, w) = (0.0, 0.0),
        1 => w = 0.0,
        2 => w = 1.0 - u,
        _ if u + w > 1.0 => (u, w) = (1.0 - u, 1.0 - w),
        _ => {}
    }
    let p = a + (b - a) * u + (c - a) * w;
    [p.x, p.y, p.z]
}

#[test]
fn skylines_bound_every_point_of_the_surface_within_reach() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let edges = sector_edges();
    let mut checked = 0;
    for case in 0..40 {
        let s = scene(&mut rng, case % 4);
        let mesh = s.triangle_mesh().unwrap();
        let reach = mesh.skyline_reach();
        for _ in 0..30 {
            let q = on_surface(&mut rng, &mesh.corners);
            let sky = mesh.skyline(q, &edges);
            for _ in 0..400 {
                let p = on_surface(&mut rng, &mesh.corners);
                let (x, y) = (p[0] - q[0], p[1] - q[1]);
                let rho = x.hypot(y);
                if rho > reach || rho < 1e-6 {
                    continue;
                }
                let slope = (p[2] - q[2]) / rho;
                let bound = sky.slope(sector_of(pseudo_angle(x, y)));
                assert!(slope <= bound, "case {case}: {q:?} -> {p:?}: slope {slope} above {bound}");
                checked += 1;
            }
        }
    }
    assert!(checked > 100_000, "{checked}");
}

#[test]
fn horizons_and_skylines_give_the_plain_tests_answer() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let edges = sector_edges();
    let (mut seen, mut total, mut settled, mut reused) = (0, 0, 0, 0);
    for case in 0..80 {
        let s = scene(&mut rng, case % 4);
        let mesh = s.triangle_mesh().unwrap();
        let (lo, hi) = mesh.bounds();
        for _ in 0..10 {
            let uav = if rng.random::<f64>() < 0.5 {
                let g = on_surface(&mut rng, &mesh.corners);
                [g[0], g[1], g[2] + rng.random_range(0.0..3.0)]
            } else {
                [
                    rng.random_range(lo[0] - 2.0..hi[0] + 2.0),
                    rng.random_range(lo[1] - 2.0..hi[1] + 2.0),
                    rng.random_range(lo[2]..hi[2] + 8.0),
                ]
            };
            let radius = rng.random_range(0.0..25.0);
            let horizon = mesh.horizon(uav, radius, usize::MAX).unwrap();
            // Blockers carried from line to line, as an evaluation does, and none.
            let (mut blocker, mut blocker_sky) = (Blockers::default(), Blockers::default());
            for _ in 0..150 {
                let q = on_surface(&mut rng, &mesh.corners);
                let expect = mesh.line_of_sight(uav, q);
                let tried = blocker;
                assert_eq!(mesh.line_of_sight_from(&horizon, q, &mut Blockers::default()), expect, "case {case}: {uav:?} -> {q:?}");
                assert_eq!(mesh.line_of_sight_from(&horizon, q, &mut blocker), expect, "case {case}: {uav:?} -> {q:?}, {tried:?} first");
                reused += usize::from(!expect && tried != Blockers::default() && blocker.0[0] == tried.0[0]);
                let sky = mesh.skyline(q, &edges);
                let why = format!("case {case}: {uav:?} -> {q:?} with its skyline");
                assert_eq!(mesh.line_of_sight_to_target(&horizon, q, &sky, &mut Blockers::default()), expect, "{why}");
                assert_eq!(mesh.line_of_sight_to_target(&horizon, q, &sky, &mut blocker_sky), expect, "{why}, {blocker_sky:?} first");
                let (ex, ey) = (uav[0] - q[0], uav[1] - q[1]);
                let r = ex.hypot(ey);
                if r > 0.0 && (uav[2] - q[2]) / r > sky.slope(sector_of(pseudo_angle(ex, ey))) {
                    settled += 1;
                }
                seen += usize::from(expect);
                total += 1;
            }
        }
    }
    assert!(seen > total / 5 && seen < 4 * total / 5, "{seen} of {total}");
    assert!(settled > total / 8, "the skylines decided too rarely to be tested: {settled} of {total}");
    assert!(reused > total / 50, "the last blocker decided too rarely to be tested: {reused} of {total}");
}
