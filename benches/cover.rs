//! The seen-matrix, lazy greedy and the online bound at the size: 10^4 candidate
//! viewpoints x 10^4 targets (the 10 201 grid nodes of a 100 m x 100 m terrain at 1 m, seven
//! Gaussian hills 5-25 m tall), d_max = 25 m, candidates a 1 m x-y lattice at 30 m (10^4 of
//! them), on 2 threads; greedy and the bound for k = 20.
//!
//! Run with `nice cargo bench --bench cover`; the figures are recorded in benches/README.md.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use uavcov::cover::{bound, greedy, SeenMatrix};
use uavcov::{Point, Surface, Targets, Visibility};

fn height(x: f64, y: f64) -> f64 {
    const HILLS: [(f64, f64, f64); 7] = [
        (20.0, 30.0, 18.0),
        (75.0, 20.0, 9.0),
        (50.0, 55.0, 25.0),
        (85.0, 80.0, 14.0),
        (15.0, 85.0, 6.0),
        (60.0, 90.0, 11.0),
        (35.0, 10.0, 21.0),
    ];
    HILLS.iter().map(|&(cx, cy, h)| h * (-((x - cx).powi(2) + (y - cy).powi(2)) / (2.0 * 8.0 * 8.0)).exp()).sum()
}

fn setup() -> (Visibility, Vec<Point>) {
    let n = 101;
    let z: Vec<f64> = (0..n * n).map(|k| height((k % n) as f64, (k / n) as f64)).collect();
    let surface = Arc::new(Surface::from_grid(z, n, n, 1.0, 1.0, 0.0, 0.0).unwrap());
    let vis = Visibility::new(surface.clone(), Targets::grid_nodes(surface).unwrap(), 25.0).unwrap();
    let candidates: Vec<Point> = (0..10_000).map(|k| [0.5 + f64::from(k % 100), 0.5 + f64::from(k / 100), 30.0]).collect();
    (vis, candidates)
}

fn bench(c: &mut Criterion) {
    let (vis, candidates) = setup();
    let mut group = c.benchmark_group("cover");
    group.sample_size(10);
    group.bench_function("matrix 1e4 x 1e4, 2 threads", |b| b.iter(|| black_box(SeenMatrix::build(&vis, &candidates, None, 2).unwrap())));
    let matrix = SeenMatrix::build(&vis, &candidates, None, 2).unwrap();
    eprintln!("matrix: {} candidates x {} targets, {} bytes", matrix.n_candidates(), matrix.n_targets(), matrix.bytes());
    group.bench_function("greedy k=20 (with its bound), 2 threads", |b| {
        b.iter(|| black_box(greedy(&matrix, &candidates, 20, 1.0, 2).unwrap()))
    });
    let picks = greedy(&matrix, &candidates, 20, 1.0, 2).unwrap();
    eprintln!("greedy: coverage {:.4}, bound {:.4}, ceiling {:.4}", picks.coverage, picks.bound, matrix.ceiling());
    let seen = vis.seen(&picks.picks.iter().map(|&c| candidates[c]).collect::<Vec<_>>(), 2).unwrap();
    group.bench_function("bound of a placement k=20, 2 threads", |b| b.iter(|| black_box(bound(&matrix, &seen, 20, 2).unwrap())));
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
