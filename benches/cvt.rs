//! Constrained CVT on the paper's approximating surface: N = 20 generators on S' built from 34
//! known points (30 random interior points plus the 4 corners of a 100 m square), with the
//! default settings (q = 4000, a = b = (0.5, 0.5), 0.1 m over 5 iterations, cap 300).
//!
//! S' is the piecewise-linear interpolant on the Delaunay triangulation of the 34 points' (x, y),
//! built here by a small Bowyer-Watson triangulation (O(n^2), plenty for 34 points) so the bench
//! needs neither Python nor scipy. Heights come from a fixed mixture of 7 Gaussian hills
//! (heights 5-25 m, sigma 10 m, as in paper-setup.md).
//!
//! Run with `cargo bench --bench cvt`; the figures are recorded in benches/README.md. The last
//! two cases time 50 iterations with and without a normal weight (`CvtOptions::normal_weight`).

use criterion::{criterion_group, criterion_main, Criterion};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use uavcov::cvt::{constrained_cvt, CvtOptions};
use uavcov::surface::mesh::Surface;

#[path = "common/hills.rs"]
mod hills;

/// The hills at sigma 10 m (paper-setup.md), so every run sees the same terrain.
fn height(x: f64, y: f64) -> f64 {
    hills::height(x, y, 10.0)
}

const SIZE: f64 = 100.0;

/// Circumcircle test: whether `p` lies strictly inside the circle through `a`, `b`, `c`.
fn in_circumcircle(a: [f64; 2], b: [f64; 2], c: [f64; 2], p: [f64; 2]) -> bool {
    let (ax, ay) = (a[0] - p[0], a[1] - p[1]);
    let (bx, by) = (b[0] - p[0], b[1] - p[1]);
    let (cx, cy) = (c[0] - p[0], c[1] - p[1]);
    let det =
        (ax * ax + ay * ay) * (bx * cy - cx * by) - (bx * bx + by * by) * (ax * cy - cx * ay) + (cx * cx + cy * cy) * (ax * by - bx * ay);
    let orientation = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if orientation > 0.0 {
        det > 0.0
    } else {
        det < 0.0
    }
}

/// Delaunay triangulation of `points` by Bowyer-Watson insertion into a large super-triangle.
fn delaunay(points: &[[f64; 2]]) -> Vec<[u32; 3]> {
    let n = points.len();
    let mut all = points.to_vec();
    let big = 100.0 * SIZE;
    all.extend([[-big, -big], [big, -big], [0.0, big]]);
    let mut triangles: Vec<[usize; 3]> = vec![[n, n + 1, n + 2]];
    for (i, &p) in points.iter().enumerate() {
        let (bad, good): (Vec<[usize; 3]>, Vec<[usize; 3]>) =
            triangles.into_iter().partition(|t| in_circumcircle(all[t[0]], all[t[1]], all[t[2]], p));
        // The hole's boundary: edges of the removed triangles that no other removed one shares.
        let mut edges: Vec<[usize; 2]> = Vec::new();
        for t in &bad {
            for e in [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]] {
                let twin = edges.iter().position(|f| (f[0] == e[1] && f[1] == e[0]) || *f == e);
                match twin {
                    Some(k) => {
                        edges.swap_remove(k);
                    }
                    None => edges.push(e),
                }
            }
        }
        triangles = good;
        triangles.extend(edges.into_iter().map(|[a, b]| [a, b, i]));
    }
    triangles.into_iter().filter(|t| t.iter().all(|&k| k < n)).map(|t| t.map(|k| k as u32)).collect()
}

/// S' from 30 random interior points (seeded) and the 4 corners.
fn approximating_surface(seed: u64) -> Surface {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut xy = vec![[0.0, 0.0], [SIZE, 0.0], [SIZE, SIZE], [0.0, SIZE]];
    xy.extend((0..30).map(|_| [SIZE * rng.random::<f64>(), SIZE * rng.random::<f64>()]));
    let faces = delaunay(&xy);
    let vertices = xy.iter().map(|&[x, y]| [x, y, height(x, y)]).collect();
    Surface::new(vertices, faces).expect("a valid triangulation")
}

fn bench(c: &mut Criterion) {
    let surface = approximating_surface(2019);
    // The triangulation must tile the square: its xy area is exactly 100 m x 100 m.
    let xy_area: f64 = (0..surface.n_triangles())
        .map(|f| {
            let [a, b, c] = surface.triangle(f);
            0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)).abs()
        })
        .sum();
    assert!((xy_area - SIZE * SIZE).abs() < 1e-6, "the triangulation covers {xy_area} m^2");
    let n = 20;
    let settings = CvtOptions::for_generators(n);
    let seeds = 32u64;
    let runs: Vec<_> =
        (0..seeds).map(|s| constrained_cvt(&surface, n, &settings.with_seed(s).with_threads(1), None, None).unwrap()).collect();
    let mut iterations: Vec<usize> = runs.iter().map(|t| t.iterations).collect();
    iterations.sort_unstable();
    let converged = runs.iter().filter(|t| t.converged).count();
    eprintln!(
        "S': {} triangles, {:.0} m^2; N = {n}, q = {}: over {seeds} seeds {converged} converged, iterations min {} median {} max {}",
        surface.n_triangles(),
        surface.area(),
        settings.samples_per_iteration,
        iterations[0],
        iterations[iterations.len() / 2],
        iterations[iterations.len() - 1],
    );

    let mut group = c.benchmark_group("cvt");
    // Cycle through the seeds, so the figure is the mean over their different run lengths.
    for threads in [1usize, 2] {
        let mut seed = 0u64;
        group.bench_function(format!("N20_34pt_S'_converge_{threads}thread"), |b| {
            b.iter(|| {
                seed = (seed + 1) % seeds;
                black_box(constrained_cvt(&surface, n, &settings.with_seed(seed).with_threads(threads), None, None).unwrap())
            });
        });
    }
    // The cost of one iteration: 50 iterations without the stopping test.
    let mut fixed = settings;
    fixed.tolerance = 0.0;
    fixed.max_iterations = 50;
    group.bench_function("N20_34pt_S'_50_iterations_1thread", |b| {
        b.iter(|| black_box(constrained_cvt(&surface, n, &fixed.with_seed(1).with_threads(1), None, None).unwrap()));
    });
    // The same with a normal weight (the structures' 10 m): the facing term's cost, side by side.
    let facing = CvtOptions { normal_weight: 10.0, ..fixed };
    group.bench_function("N20_34pt_S'_50_iterations_normal_weight_1thread", |b| {
        b.iter(|| black_box(constrained_cvt(&surface, n, &facing.with_seed(1).with_threads(1), None, None).unwrap()));
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
