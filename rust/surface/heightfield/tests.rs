//! The grid path against the mesh path of the same grid, its oracle: segments, first hits,
//! horizons, skylines, vertical and closest-point queries and the mesh tables must agree.

use super::*;
use crate::surface::grid::pseudo_angle;
use crate::surface::mesh::Surface;
use crate::surface::skyline::{sector_of, Stencil};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A grid surface and the mesh path of the same grid.
fn both(z: Vec<f64>, ny: usize, nx: usize, dx: f64, dy: f64, x0: f64, y0: f64) -> (Surface, Surface) {
    let grid = Surface::from_grid(z, ny, nx, dx, dy, x0, y0).unwrap();
    let mesh_of_grid = grid.triangle_mesh().unwrap();
    let faces = mesh_of_grid.trimesh().indices().to_vec();
    let mesh = Surface::new(grid.vertices().collect(), faces).unwrap();
    (grid, mesh)
}

/// Heights of four kinds: smooth hills, rough noise, terraces (flat plateaus, cliffs), spikes.
fn heights(rng: &mut ChaCha8Rng, ny: usize, nx: usize, kind: usize, holes: bool) -> Vec<f64> {
    let phase: [f64; 4] = [0, 1, 2, 3].map(|_| rng.random::<f64>() * 6.0);
    (0..ny * nx)
        .map(|k| {
            let (i, j) = ((k / nx) as f64, (k % nx) as f64);
            let smooth = 3.0 * (0.4 * i + phase[0]).sin() + 2.0 * (0.3 * j + phase[1]).cos();
            let h = match kind {
                0 => smooth,
                1 => smooth + 4.0 * rng.random::<f64>(),
                2 => (smooth * 0.8).round() * 2.0,
                _ => {
                    if rng.random::<f64>() < 0.1 {
                        8.0
                    } else {
                        0.0
                    }
                }
            };
            if holes && rng.random::<f64>() < 0.08 {
                f64::NAN
            } else {
                h
            }
        })
        .collect()
}

/// End points that stress the boundaries: grid nodes (exactly), points on grid lines and
/// diagonals, points above nodes, random points, some outside the grid.
fn point(rng: &mut ChaCha8Rng, g: &Grid, zmin: f64, zmax: f64) -> Point {
    let i = rng.random_range(0..g.ny);
    let j = rng.random_range(0..g.nx);
    let node = g.node_point(i * g.nx + j);
    let lift = zmin + (zmax - zmin + 6.0) * rng.random::<f64>() - 1.0;
    let u = rng.random::<f64>();
    match rng.random_range(0..7) {
        0 if !node[2].is_nan() => node,
        1 => [node[0], node[1], lift],
        2 => [node[0], node[1] + u * g.dy, lift],
        3 => [node[0] + u * g.dx, node[1], lift],
        4 => [node[0] + u * g.dx, node[1] + u * g.dy, lift],
        5 => [node[0] + (u - 0.5) * 6.0 * g.dx, node[1] - 3.0 * g.dy, lift],
        _ => [
            g.x0 + (rng.random::<f64>() * 1.2 - 0.1) * (g.nx - 1) as f64 * g.dx,
            g.y0 + (rng.random::<f64>() * 1.2 - 0.1) * (g.ny - 1) as f64 * g.dy,
            lift,
        ],
    }
}

#[test]
fn segments_agree_with_the_mesh_path_exactly() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut blocked = 0;
    let mut total = 0;
    for case in 0..48 {
        let (ny, nx) = if case % 8 == 7 {
            (rng.random_range(30..90), rng.random_range(30..90))
        } else {
            (rng.random_range(2..24), rng.random_range(2..24))
        };
        let (dx, dy) = if case % 3 == 0 { (1.0, 1.0) } else { (0.1 + rng.random::<f64>(), 0.1 + rng.random::<f64>()) };
        let (x0, y0) = if case % 4 == 0 { (0.0, 0.0) } else { (rng.random::<f64>() * 1e3 - 500.0, 12.25) };
        let z = heights(&mut rng, ny, nx, case % 4, case % 5 == 1);
        if z.chunks(nx).zip(z.chunks(nx).skip(1)).all(|(a, b)| a.iter().chain(b).any(|h| h.is_nan())) {
            continue; // every cell touches nodata: no triangle at all
        }
        let Ok(grid) = Surface::from_grid(z.clone(), ny, nx, dx, dy, x0, y0) else {
            continue;
        };
        let (grid, mesh) = (grid, both(z, ny, nx, dx, dy, x0, y0).1);
        let g = grid.grid().unwrap().clone();
        let (lo, hi) = grid.bounds();
        for _ in 0..400 {
            let a = point(&mut rng, &g, lo[2], hi[2]);
            let b = point(&mut rng, &g, lo[2], hi[2]);
            let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            for t_max in [SIGHT_FRACTION, 1.0] {
                let expect = mesh.ray_hits(a, d, t_max);
                assert_eq!(grid.ray_hits(a, d, t_max), expect, "case {case}: {a:?} -> {b:?} up to {t_max}");
                let field = grid.heightfield().unwrap();
                assert_eq!(field.ray_hits_quadtree(a, d, t_max), expect, "quadtree, case {case}");
                blocked += usize::from(expect);
                total += 1;
            }
            assert_eq!(grid.line_of_sight(a, b), mesh.line_of_sight(a, b));
            // A ray starting on a triangle's plane outside the triangle gets a spurious hit at
            // t = 0 from parry, which the mesh path keeps or prunes depending on its
            // traversal order; first hits are compared only from points off the grid nodes.
            if (0..g.ny * g.nx).any(|k| g.node_point(k) == a) {
                continue;
            }
            let (fg, fm) = (grid.first_hit(a, d, 1.0), mesh.first_hit(a, d, 1.0));
            match (fg, fm) {
                (Some(x), Some(y)) => assert!((x - y).abs() <= 1e-12, "case {case} {a:?} {b:?}: {x} vs {y}"),
                _ => assert_eq!(fg, fm, "case {case} {a:?} {b:?}"),
            }
        }
    }
    // Both outcomes are well represented, so agreement means something.
    assert!(blocked > total / 5 && blocked < 4 * total / 5, "{blocked} of {total}");
}

#[test]
fn horizons_give_the_mesh_paths_sight_lines() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let (mut seen, mut total) = (0, 0);
    for case in 0..40 {
        let (ny, nx) = if case % 4 == 3 {
            (rng.random_range(30..80), rng.random_range(30..80))
        } else {
            (rng.random_range(2..24), rng.random_range(2..24))
        };
        let (dx, dy) = if case % 3 == 0 { (0.5, 0.5) } else { (0.2 + rng.random::<f64>(), 0.2 + rng.random::<f64>()) };
        let (x0, y0) = if case % 5 == 0 { (0.0, 0.0) } else { (rng.random::<f64>() * 1e3 - 500.0, -3.75) };
        let z = heights(&mut rng, ny, nx, case % 4, case % 6 == 1);
        let Ok(grid) = Surface::from_grid(z.clone(), ny, nx, dx, dy, x0, y0) else {
            continue;
        };
        let mesh = both(z, ny, nx, dx, dy, x0, y0).1;
        let field = grid.heightfield().unwrap();
        let g = field.grid().clone();
        let (lo, hi) = grid.bounds();
        for _ in 0..12 {
            let uav = point(&mut rng, &g, lo[2], hi[2]);
            // Sometimes shorter than the farthest targets: those must fall back to the walk.
            let radius = rng.random::<f64>() * 1.5 * ((nx as f64 * dx).powi(2) + (ny as f64 * dy).powi(2)).sqrt();
            let horizon = field.horizon(uav, radius, usize::MAX).unwrap();
            for _ in 0..150 {
                let q = point(&mut rng, &g, lo[2], hi[2]);
                let expect = mesh.line_of_sight(uav, q);
                assert_eq!(field.line_of_sight_from(&horizon, q), expect, "case {case}: {uav:?} -> {q:?}, radius {radius}");
                seen += usize::from(expect);
                total += 1;
            }
        }
    }
    assert!(seen > total / 5 && seen < 4 * total / 5, "{seen} of {total}");
}

#[test]
fn skylines_give_the_mesh_paths_sight_lines_to_nodes() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (mut seen, mut total, mut steep, mut under) = (0, 0, 0, 0);
    for case in 0..40 {
        let (ny, nx) = if case % 4 == 3 {
            (rng.random_range(30..80), rng.random_range(30..80))
        } else {
            (rng.random_range(2..24), rng.random_range(2..24))
        };
        let (dx, dy) = if case % 3 == 0 { (0.5, 0.5) } else { (0.2 + rng.random::<f64>(), 0.2 + rng.random::<f64>()) };
        let (x0, y0) = if case % 5 == 0 { (0.0, 0.0) } else { (rng.random::<f64>() * 1e3 - 500.0, -3.75) };
        let z = heights(&mut rng, ny, nx, case % 4, case % 6 == 1);
        let Ok(grid) = Surface::from_grid(z.clone(), ny, nx, dx, dy, x0, y0) else {
            continue;
        };
        let mesh = both(z, ny, nx, dx, dy, x0, y0).1;
        let field = grid.heightfield().unwrap();
        let g = field.grid().clone();
        let (lo, hi) = grid.bounds();
        let nodes: Vec<usize> = (0..ny * nx).filter(|&k| g.vertex_of_node[k] != u32::MAX).collect();
        let stencil = Stencil::of_grid(&g);
        for _ in 0..12 {
            let uav = point(&mut rng, &g, lo[2], hi[2]);
            let radius = rng.random::<f64>() * 1.5 * ((nx as f64 * dx).powi(2) + (ny as f64 * dy).powi(2)).sqrt();
            let horizon = field.horizon(uav, radius, usize::MAX).unwrap();
            for _ in 0..150 {
                let k = nodes[rng.random_range(0..nodes.len())];
                let q = g.node_point(k);
                let sky = stencil.skyline(&g, k / nx, k % nx);
                let expect = mesh.line_of_sight(uav, q);
                assert_eq!(field.line_of_sight_to_node(&horizon, q, &sky), expect, "case {case}: {uav:?} -> {q:?}, radius {radius}");
                // Where the line goes under the surface, the stretch tested alone finds its hit.
                if field.hits_where_it_goes_under(uav, q) {
                    assert!(!expect, "case {case}: {uav:?} -> {q:?} is seen");
                    under += 1;
                }
                // How often the skyline settles the last cells (the line arrives more steeply).
                let (ex, ey) = (uav[0] - q[0], uav[1] - q[1]);
                let r = (ex * ex + ey * ey).sqrt();
                if r > 0.0 && (uav[2] - q[2]) / r > sky.slope(sector_of(pseudo_angle(ex, ey))) {
                    steep += 1;
                }
                seen += usize::from(expect);
                total += 1;
            }
        }
    }
    assert!(seen > total / 5 && seen < 4 * total / 5, "{seen} of {total}");
    assert!(steep > total / 8, "the skylines decided too rarely to be tested: {steep} of {total}");
    assert!(under > total / 20, "lines going under the surface were found too rarely to be tested: {under} of {total}");
}

#[test]
fn vertical_and_closest_point_queries_agree_with_the_mesh_path() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for case in 0..12 {
        let (ny, nx) = (rng.random_range(2..30), rng.random_range(2..30));
        let z = heights(&mut rng, ny, nx, case % 4, case % 3 == 2);
        let Ok(grid) = Surface::from_grid(z.clone(), ny, nx, 0.5, 0.7, 3.0, -2.0) else {
            continue;
        };
        let mesh = both(z, ny, nx, 0.5, 0.7, 3.0, -2.0).1;
        assert_eq!(grid.bounds(), mesh.bounds());
        assert_eq!(grid.area(), mesh.area());
        let g = grid.grid().unwrap().clone();
        let (lo, hi) = grid.bounds();
        for _ in 0..300 {
            let q = point(&mut rng, &g, lo[2], hi[2]);
            let (hg, hm) = (grid.ground_height(q[0], q[1]), mesh.ground_height(q[0], q[1]));
            match (hg, hm) {
                (Some(x), Some(y)) => assert!((x - y).abs() <= 1e-12, "{q:?}: {x} vs {y}"),
                _ => assert_eq!(hg, hm, "{q:?}"),
            }
            let (cg, cm) = (grid.clearance(q), mesh.clearance(q));
            assert!(cg == cm || (cg - cm).abs() <= 1e-12, "{q:?}: {cg} vs {cm}");
            let (pg, pm) = (grid.closest_point(q), mesh.closest_point(q));
            let dist = |r: Point| ((r[0] - q[0]).powi(2) + (r[1] - q[1]).powi(2) + (r[2] - q[2]).powi(2)).sqrt();
            assert!((dist(pg) - dist(pm)).abs() <= 1e-9, "{q:?}: {pg:?} vs {pm:?}");
        }
    }
}

#[test]
fn mesh_tables_match_the_mesh_path() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let z = heights(&mut rng, 9, 11, 1, true);
    let (grid, mesh) = both(z, 9, 11, 0.5, 0.25, 1.0, 2.0);
    assert_eq!(grid.n_vertices(), mesh.n_vertices());
    assert_eq!(grid.n_triangles(), mesh.n_triangles());
    assert_eq!(grid.faces(), mesh.faces());
    assert_eq!(grid.areas(), mesh.areas());
    assert!(grid.vertices().eq(mesh.vertices()));
    for f in 0..grid.n_triangles() {
        assert_eq!(grid.triangle(f), mesh.triangle(f));
    }
    let field = grid.heightfield().unwrap();
    let mut w = vec![0.0; mesh.n_vertices()];
    for (t, &a) in mesh.faces().iter().zip(mesh.areas()) {
        for &k in t {
            w[k as usize] += a / 3.0;
        }
    }
    assert_eq!(field.vertex_weights(), w);
}

#[test]
fn a_ridge_hides_what_is_behind_it_and_grazing_it_from_above_does_not() {
    // A 1 m ridge along column 5 of a flat 11 x 11 grid.
    let z: Vec<f64> = (0..121).map(|k| if k % 11 == 5 { 1.0 } else { 0.0 }).collect();
    let hf = HeightField::new(z, 11, 11, 1.0, 1.0, 0.0, 0.0).unwrap();
    assert!(!hf.line_of_sight([2.0, 5.0, 0.5], [8.0, 5.0, 0.0]));
    assert!(hf.line_of_sight([2.0, 5.0, 3.0], [8.0, 5.0, 0.0]));
    // Along the ridge line, exactly over its nodes and above them: nothing is crossed.
    assert!(hf.line_of_sight([5.0, 0.0, 1.5], [5.0, 10.0, 1.0]));
    // Touching the ridge's top edge counts as crossing it (as on the mesh path); a hair
    // above it does not.
    assert!(hf.ray_hits([4.0, 5.0, 1.0], [2.0, 0.0, 0.0], 1.0));
    assert!(!hf.ray_hits([4.0, 5.0, 1.0 + 1e-9], [2.0, 0.0, 0.0], 1.0));
    assert!(!hf.line_of_sight([4.0, 5.0, 0.9], [6.0, 5.0, 0.9]));
}

#[test]
fn memory_scales_with_nodes() {
    let hf = HeightField::new(vec![0.0; 201 * 201], 201, 201, 0.5, 0.5, 0.0, 0.0).unwrap();
    let per_node = hf.memory_bytes() as f64 / (201.0 * 201.0);
    assert!(per_node < 18.0, "{per_node} bytes per node");
    assert!(HeightField::new(vec![0.0; 4], 2, 2, 1.0, f64::NAN, 0.0, 0.0).is_err());
    assert!(matches!(HeightField::new(vec![f64::NAN; 4], 2, 2, 1.0, 1.0, 0.0, 0.0), Err(Error::Mesh(_))));
    assert!(matches!(HeightField::new(vec![f64::INFINITY; 4], 2, 2, 1.0, 1.0, 0.0, 0.0), Err(Error::InvalidInput(_))));
}

/// Rough heights on an `n x n` grid at `origin`, and the same grid as a plain mesh.
fn far(n: usize, origin: f64) -> (Surface, Surface) {
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    let z = heights(&mut rng, n, n, 1, false);
    both(z, n, n, 1.0, 1.0, origin, origin)
}

#[test]
fn grids_far_from_the_origin_answer_like_the_mesh_path_without_spinning() {
    // At 1e10 m with 1 m cells the walk's margins (1e-9 of the coordinates) span 20 cells: the
    // bisection never reached its leaves and took minutes per sight line; such segments now
    // take the quadtree's any-hit test, the same answer.
    for origin in [1e9, 1e10, 1e13] {
        let (grid, mesh) = far(24, origin);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let start = std::time::Instant::now();
        for _ in 0..400 {
            let a = [origin + rng.random_range(-5.0..28.0), origin + rng.random_range(-5.0..28.0), rng.random_range(-2.0..12.0)];
            let b = [origin + rng.random_range(0.0..23.0), origin + rng.random_range(0.0..23.0), rng.random_range(-2.0..8.0)];
            let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            assert_eq!(grid.ray_hits(a, d, 0.999), mesh.ray_hits(a, d, 0.999), "origin {origin}: {a:?} -> {b:?}");
        }
        assert!(start.elapsed().as_secs_f64() < 20.0, "origin {origin}: {:?}", start.elapsed());
    }
}

#[test]
fn segments_from_very_far_away_stay_bounded_and_exact() {
    // A UAV 1e14 m away: 2^16 halvings still leave pieces of a billion cells, which go to the
    // quadtree instead of testing every cell of the grid for each piece.
    let (grid, mesh) = far(40, 0.0);
    for a in [[1e14, 20.0, 30.0], [20.0, -3e13, 1e12], [7e8, 9e8, 1e3]] {
        for b in [[10.0, 10.0, 0.0], [33.5, 2.25, 1.0]] {
            let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            assert_eq!(grid.ray_hits(a, d, 0.999), mesh.ray_hits(a, d, 0.999), "{a:?} -> {b:?}");
        }
    }
}

#[test]
fn horizons_of_huge_ranges_are_bounded() {
    // d_max = 1e19 made `PI * radius / w` saturate to usize::MAX, whose next multiple of 4 wrapped
    // to 0 sectors, and `sectors - 1` to a range start of usize::MAX (the panic).
    let (grid, mesh) = far(11, 0.0);
    let field = grid.heightfield().unwrap();
    for radius in [1e19, 1e300, f64::MAX, 6e18, 1e6] {
        let h = field.horizon([5.0, 5.0, 30.0], radius, usize::MAX).unwrap();
        assert!(h.sectors >= 64 && h.sectors <= 4096 && h.bins >= 1 && h.bins <= 4096, "{radius}");
        assert!(h.slope.len() == h.sectors * h.bins);
        for target in [[1.0, 2.0, field.grid().z[2 * 11 + 1]], [9.0, 9.0, 0.0]] {
            assert_eq!(field.line_of_sight_from(&h, target), mesh.line_of_sight([5.0, 5.0, 30.0], target));
        }
    }
    // A budget of bounds shrinks the horizon, never the answers.
    let small = field.horizon([5.0, 5.0, 30.0], 1e19, 64).unwrap();
    assert_eq!((small.bins, small.sectors), (1, 64));
}

#[test]
fn grids_beyond_the_coordinate_bound_or_their_resolution_are_refused() {
    let z = vec![0.0; 9];
    let refused = |dx: f64, x0: f64, y0: f64| HeightField::new(z.clone(), 3, 3, dx, dx, x0, y0).err();
    // 1e300 m: every node at the same place, area 0 (was accepted).
    assert!(matches!(refused(1.0, 1e300, 1e300), Some(Error::InvalidInput(_))));
    assert!(matches!(refused(1.0, 0.0, -2e15), Some(Error::InvalidInput(_))));
    assert!(matches!(refused(1e15, 0.0, 0.0), Some(Error::InvalidInput(_)))); // its far corner
                                                                              // Spacing below the coordinates' resolution (0.125 m at 1e15 m): nodes coincide.
    assert!(matches!(refused(0.01, 9e14, 0.0), Some(Error::InvalidInput(_))));
    // Area underflows to 0.
    assert!(matches!(refused(1e-300, 0.0, 0.0), Some(Error::Mesh(_))));
    assert!(matches!(HeightField::new(vec![0.0, 2e15, 0.0, 0.0], 2, 2, 1.0, 1.0, 0.0, 0.0), Err(Error::InvalidInput(_))));
    // At the bound itself, and with a resolvable spacing, the grid is fine.
    assert!(HeightField::new(z.clone(), 3, 3, 1.0, 1.0, 1e15 - 2.0, -1e15).is_ok());
}
