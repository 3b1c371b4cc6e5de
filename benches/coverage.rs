//! The reference case of `benches/README.md`: a 7-Gaussian terrain on 100 m x 100 m, all grid
//! nodes as targets, 12 UAVs 5-30 m above the ground, `d_max` = 25 m; one full coverage
//! evaluation at 1 m, 0.5 m and 0.25 m spacing, on 1 and 2 threads, on the grid path (the
//! default for a grid surface) and on the mesh path of the same grid (parry's BVH). And the same
//! team along a 200-step random walk (steps of up to 10 cm per coordinate) at 1 m, measured at
//! every step by `Visibility::coverage` afresh and by a `CoverageTracker` (one thread). And the
//! skylines: the second evaluation over a fresh surface at 1 m (one thread), which builds
//! the skyline of every target it tests, beside the third, which has them.
//!
//! `cargo bench --bench coverage`

use std::sync::Arc;

use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use uavcov::surface::mesh::Surface;
use uavcov::visibility::tracking::{CoverageTracker, Margin};
use uavcov::visibility::{Path, Targets, Visibility};

/// Heights of a sum of 7 Gaussian hills (heights 5-25 m, sigma 10 m) on a `spacing` grid.
fn hills(spacing: f64, seed: u64) -> (Vec<f64>, usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let hills: Vec<[f64; 3]> =
        (0..7).map(|_| [rng.random::<f64>() * 100.0, rng.random::<f64>() * 100.0, 5.0 + 20.0 * rng.random::<f64>()]).collect();
    let n = (100.0 / spacing).round() as usize + 1;
    let mut z = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (j as f64 * spacing, i as f64 * spacing);
            z.push(hills.iter().map(|h| h[2] * (-((x - h[0]).powi(2) + (y - h[1]).powi(2)) / 200.0).exp()).sum());
        }
    }
    (z, n)
}

fn reference_case(spacing: f64, path: Path) -> (Visibility, Vec<[f64; 3]>) {
    let (z, n) = hills(spacing, 0);
    let surface = Arc::new(Surface::from_grid(z, n, n, spacing, spacing, 0.0, 0.0).unwrap());
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let uavs = (0..12)
        .map(|_| {
            let (x, y) = (rng.random::<f64>() * 100.0, rng.random::<f64>() * 100.0);
            [x, y, surface.ground_height(x, y).unwrap() + 5.0 + 25.0 * rng.random::<f64>()]
        })
        .collect();
    let targets = Targets::grid_nodes(surface.clone()).unwrap();
    (Visibility::with_path(surface, targets, 25.0, path).unwrap(), uavs)
}

fn coverage(c: &mut Criterion) {
    let mut group = c.benchmark_group("coverage");
    group.sample_size(20);
    for spacing in [1.0, 0.5, 0.25] {
        for (name, path) in [("grid", Path::Auto), ("mesh", Path::Mesh)] {
            let (vis, uavs) = reference_case(spacing, path);
            for threads in [1, 2] {
                let id = BenchmarkId::new(format!("{name}_{spacing}m"), format!("{threads}_threads"));
                group.bench_with_input(id, &threads, |b, &t| b.iter(|| vis.coverage(&uavs, t).unwrap()));
            }
        }
    }
    group.finish();
}

fn along_a_path(c: &mut Criterion) {
    let (vis, uavs) = reference_case(1.0, Path::Auto);
    let vis = Arc::new(vis);
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut team = uavs;
    let path: Vec<Vec<[f64; 3]>> = (0..200)
        .map(|_| {
            for p in &mut team {
                for x in p.iter_mut() {
                    *x += 0.2 * (rng.random::<f64>() - 0.5);
                }
            }
            team.clone()
        })
        .collect();
    let mut group = c.benchmark_group("along_a_path");
    group.sample_size(10);
    group.bench_function("plain_1.0m_200_steps", |b| b.iter(|| path.iter().map(|t| vis.coverage(t, 1).unwrap()).sum::<f64>()));
    group.bench_function("tracker_1.0m_200_steps", |b| {
        b.iter(|| {
            let mut tracker = CoverageTracker::new(vis.clone(), Margin::Adaptive).unwrap();
            path.iter().map(|t| tracker.coverage(t, 1).unwrap()).sum::<f64>()
        });
    });
    group.finish();
}

fn skylines(c: &mut Criterion) {
    let (z, n) = hills(1.0, 0);
    let (_, uavs) = reference_case(1.0, Path::Auto);
    // A fresh surface each time: a surface keeps its nodes' skylines for every objective over it.
    let evaluated = |times: usize| {
        let surface = Arc::new(Surface::from_grid(z.clone(), n, n, 1.0, 1.0, 0.0, 0.0).unwrap());
        let vis = Visibility::new(surface.clone(), Targets::grid_nodes(surface).unwrap(), 25.0).unwrap();
        for _ in 0..times {
            vis.coverage(&uavs, 1).unwrap();
        }
        vis
    };
    let mut group = c.benchmark_group("skylines");
    group.sample_size(20);
    group.bench_function("second_evaluation_1.0m", |b| {
        b.iter_batched(|| evaluated(1), |vis| vis.coverage(&uavs, 1).unwrap(), BatchSize::PerIteration);
    });
    group.bench_function("third_evaluation_1.0m", |b| {
        b.iter_batched(|| evaluated(2), |vis| vis.coverage(&uavs, 1).unwrap(), BatchSize::PerIteration);
    });
    group.finish();
}

criterion_group!(benches, coverage, along_a_path, skylines);
criterion_main!(benches);
