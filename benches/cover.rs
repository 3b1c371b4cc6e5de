//! The seen-matrix, lazy greedy and the online bound at the size: 10^4 candidate
//! viewpoints x 10^4 targets (the 10 201 grid nodes of a 100 m x 100 m terrain at 1 m, seven
//! Gaussian hills 6-25 m tall, sigma 8 m), `d_max` = 25 m, candidates a 1 m x-y lattice 5 m above
//! the ground (10^4 of them), on 2 threads; greedy and the bound for k = 20. Side by side on
//! 1000 of the candidates: the matrix against its obvious peer, one `Visibility::seen` call
//! per candidate (each parallel over targets).
//!
//! Run with `nice cargo bench --bench cover`; the figures are recorded in benches/README.md.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use uavcov::cover::{bound, greedy, SeenMatrix};
use uavcov::{Point, Surface, Targets, Visibility};

#[path = "common/hills.rs"]
mod hills;

fn setup() -> (Visibility, Vec<Point>) {
    let n = 101;
    let z: Vec<f64> = (0..n * n).map(|k| hills::height((k % n) as f64, (k / n) as f64, 8.0)).collect();
    let surface = Arc::new(Surface::from_grid(z, n, n, 1.0, 1.0, 0.0, 0.0).unwrap());
    let vis = Visibility::new(surface.clone(), Targets::grid_nodes(surface).unwrap(), 25.0).unwrap();
    let candidates: Vec<Point> = (0..10_000)
        .map(|k| {
            let (x, y) = (0.5 + f64::from(k % 100), 0.5 + f64::from(k / 100));
            [x, y, hills::height(x, y, 8.0) + 5.0]
        })
        .collect();
    (vis, candidates)
}

fn bench(c: &mut Criterion) {
    let (vis, candidates) = setup();
    let mut group = c.benchmark_group("cover");
    group.sample_size(10);
    let some: Vec<Point> = candidates.iter().step_by(10).copied().collect();
    group.bench_function("matrix 1e3 x 1e4, 2 threads", |b| b.iter(|| black_box(SeenMatrix::build(&vis, &some, None, 2).unwrap())));
    group.bench_function("peer: 1e3 seen calls x 1e4, 2 threads", |b| {
        b.iter(|| black_box(some.iter().map(|&u| vis.seen(&[u], 2).unwrap()).filter(|s| s[0]).count()));
    });
    group.bench_function("matrix 1e4 x 1e4, 2 threads", |b| b.iter(|| black_box(SeenMatrix::build(&vis, &candidates, None, 2).unwrap())));
    let matrix = SeenMatrix::build(&vis, &candidates, None, 2).unwrap();
    eprintln!("matrix: {} candidates x {} targets, {} bytes", matrix.n_candidates(), matrix.n_targets(), matrix.bytes());
    group.bench_function("greedy k=20 (with its bound), 2 threads", |b| {
        b.iter(|| black_box(greedy(&matrix, &candidates, 20, 1.0, 2).unwrap()));
    });
    let picks = greedy(&matrix, &candidates, 20, 1.0, 2).unwrap();
    eprintln!("greedy: coverage {:.4}, bound {:.4}, ceiling {:.4}", picks.coverage, picks.bound, matrix.ceiling());
    let seen = vis.seen(&picks.picks.iter().map(|&c| candidates[c]).collect::<Vec<_>>(), 2).unwrap();
    group.bench_function("bound of a placement k=20, 2 threads", |b| b.iter(|| black_box(bound(&matrix, &seen, 20, 2).unwrap())));
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
