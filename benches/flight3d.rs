//! The standoff flight limits on a structure of about 10^5 triangles, beside one coverage
//! evaluation on the same mesh (issue 35: a CAO batch check must cost well under one).
//!
//! The structure: a 100 m x 60 m ground plane and a bridge (a 60 m x 8 m x 1 m deck 10 m up on
//! four 2 m x 6 m piers) and a 4 m x 4 m x 30 m tower, every face split into cells of about
//! 0.35 m (closed, outward-wound boxes; ~10^5 triangles). Twelve UAVs stand around it (under
//! the deck, beside the piers and the tower, above); 200 candidate configurations move each
//! UAV by up to 1 m per coordinate, as CAO's perturbations do. Measured on one thread:
//!
//! - `check_200x12/standoff_moves`: the fused standoff check with moves checked (the mission's
//!   case: the inside test is skipped after a clear move from outside);
//! - `check_200x12/standoff_no_moves`: without move checks, so every UAV gets the inside test;
//! - `check_200x12/vertical_moves`: today's vertical limits on the same mesh, for scale;
//! - `coverage/targets_10k_d25`: one coverage evaluation of ~10^4 area targets by the same 12
//!   UAVs, `d_max` = 25 m.
//!
//! `cargo bench --bench flight3d`

use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use uavcov::flight::{admissible_mask, Clearance, FlightLimits};
use uavcov::surface::mesh::Surface;
use uavcov::visibility::{Targets, Visibility};

type Point = [f64; 3];

/// An axis-aligned box `[lo, hi]`, each face split into cells of at most `step`, wound outward.
fn tessellated_box(v: &mut Vec<Point>, f: &mut Vec<[u32; 3]>, lo: Point, hi: Point, step: f64) {
    // each face: a fixed axis and side, two spanning axes ordered so (u x w) points outward
    for (axis, side) in [(0, 0), (0, 1), (1, 0), (1, 1), (2, 0), (2, 1)] {
        let (mut u, mut w) = ((axis + 1) % 3, (axis + 2) % 3);
        if side == 0 {
            std::mem::swap(&mut u, &mut w);
        }
        let nu = ((hi[u] - lo[u]) / step).ceil().max(1.0) as usize;
        let nw = ((hi[w] - lo[w]) / step).ceil().max(1.0) as usize;
        let base = v.len() as u32;
        for i in 0..=nu {
            for j in 0..=nw {
                let mut q = [0.0; 3];
                q[axis] = if side == 0 { lo[axis] } else { hi[axis] };
                q[u] = lo[u] + (hi[u] - lo[u]) * i as f64 / nu as f64;
                q[w] = lo[w] + (hi[w] - lo[w]) * j as f64 / nw as f64;
                v.push(q);
            }
        }
        let at = |i: usize, j: usize| base + (i * (nw + 1) + j) as u32;
        for i in 0..nu {
            for j in 0..nw {
                f.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                f.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
}

fn structure() -> Surface {
    let (mut v, mut f) = (Vec::new(), Vec::new());
    // the ground: the top face of a thin slab is all the UAVs see; a flat grid of 0.45 m cells
    let (nx, ny, cell) = (222_usize, 134_usize, 0.45);
    for i in 0..=ny {
        for j in 0..=nx {
            v.push([j as f64 * cell, i as f64 * cell, 0.0]);
        }
    }
    for i in 0..ny {
        for j in 0..nx {
            let a = (i * (nx + 1) + j) as u32;
            let (b, c, d) = (a + 1, a + nx as u32 + 2, a + nx as u32 + 1);
            f.push([a, b, c]);
            f.push([a, c, d]);
        }
    }
    let step = 0.35;
    for x in [22.0, 40.0, 58.0, 76.0] {
        tessellated_box(&mut v, &mut f, [x, 27.0, 0.0], [x + 2.0, 33.0, 10.0], step);
    }
    tessellated_box(&mut v, &mut f, [20.0, 26.0, 10.0], [80.0, 34.0, 11.0], step);
    tessellated_box(&mut v, &mut f, [48.0, 45.0, 0.0], [52.0, 49.0, 30.0], step);
    Surface::new(v, f).unwrap()
}

fn team() -> Vec<Point> {
    vec![
        [30.0, 30.0, 5.0],
        [48.0, 30.0, 6.0],
        [67.0, 30.0, 4.0],
        [30.0, 22.0, 8.0],
        [50.0, 38.0, 9.0],
        [70.0, 22.0, 12.0],
        [35.0, 30.0, 15.0],
        [60.0, 30.0, 16.0],
        [45.0, 47.0, 20.0],
        [55.0, 47.0, 10.0],
        [50.0, 52.0, 25.0],
        [15.0, 15.0, 8.0],
    ]
}

fn limits(clearance: Clearance, check_moves: bool) -> FlightLimits {
    FlightLimits { bounds: [0.0, 0.0, 100.0, 60.0], h_min: 2.0, h_max: Some(15.0), z_max: 40.0, d_safe: 2.0, check_moves, clearance }
}

fn bench(c: &mut Criterion) {
    let surface = Arc::new(structure());
    let now = team();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let candidates: Vec<Point> = (0..200 * now.len()).map(|k| now[k % now.len()].map(|x| x + 2.0 * rng.random::<f64>() - 1.0)).collect();
    let standoff = limits(Clearance::Standoff, true);
    assert!(standoff.admissible(&surface, &now, &now).unwrap(), "the benchmark's team is admissible");
    let accepted = admissible_mask(&surface, &standoff, &now, &candidates, 1).unwrap().iter().filter(|&&b| b).count();
    // every 10th of the one-per-triangle area targets: ~10^4 spread over the whole scene
    let all = Targets::of_surface(&surface, 1.0).unwrap();
    let targets = Targets::new(all.points().iter().step_by(10).copied().collect(), None).unwrap();
    eprintln!("{} triangles, {} targets, {accepted} of 200 candidates admissible", surface.n_triangles(), targets.len());
    let vis = Visibility::new(surface.clone(), targets, 25.0).unwrap();

    let mut group = c.benchmark_group("check_200x12");
    group.sample_size(20);
    for (name, l) in [
        ("standoff_moves", standoff),
        ("standoff_no_moves", limits(Clearance::Standoff, false)),
        ("vertical_moves", limits(Clearance::Vertical, true)),
    ] {
        group.bench_function(name, |b| b.iter(|| admissible_mask(&surface, &l, &now, &candidates, 1).unwrap()));
    }
    group.finish();
    let mut group = c.benchmark_group("coverage");
    group.sample_size(10);
    group.bench_function("targets_10k_d25", |b| b.iter(|| vis.coverage(&now, 1).unwrap()));
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
