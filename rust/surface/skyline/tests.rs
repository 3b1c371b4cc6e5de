use super::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A grid of heights `z` (row-major, `ny` x `nx`) at the origin, as a height field keeps it.
fn grid(z: Vec<f64>, ny: usize, nx: usize, dx: f64, dy: f64) -> Grid {
    Grid { ny, nx, dx, dy, x0: 0.0, y0: 0.0, z, vertex_of_node: Vec::new() }
}

#[test]
fn a_plane_rising_along_x_has_its_own_slope_towards_x() {
    // A plane rising 0.5 m per metre along +x.
    let g = grid((0..49).map(|k| 0.5 * f64::from(k % 7)).collect(), 7, 7, 1.0, 1.0);
    let sky = Stencil::of_grid(&g).skyline(&g, 3, 3);
    assert!(sky.slope(0) >= 0.5 && sky.slope(0) < 0.6); // towards +x: the plane's own slope
    assert!(sky.slope(SECTORS / 2) < 0.0); // towards -x the surface falls away
}

#[test]
fn levels_round_up_and_are_tight() {
    assert!(LEVELS.windows(2).all(|w| w[0] < w[1]));
    assert!(LEVELS[0] < -60.0 && LEVELS[254] > 60.0 && LEVELS[255] == f64::INFINITY);
    for &s in &[-1e9, -81.0, -3.0, -0.5, -1e-12, 0.0, 1e-12, 0.3, 1.0, 7.5, 80.0, 1e9] {
        let q = level_above(&LEVELS, s) as usize;
        assert!(LEVELS[q] >= s, "{s}");
        assert!(q == 0 || LEVELS[q - 1] < s, "{s}");
    }
    assert_eq!(level_above(&LEVELS, f64::NAN), 255);
    assert_eq!(level_above(&LEVELS, f64::INFINITY), 255);
    assert_eq!(level_above(&LEVELS, f64::NEG_INFINITY), 0);
}

#[test]
fn spans_fit_the_run_past_the_wrap() {
    for (dx, dy) in [(1.0, 1.0), (0.5, 0.8), (2.0, 0.25), (10.0, 0.1), (0.01, 7.0)] {
        let stencil = Stencil::new(dx, dy);
        let longest = stencil.groups.iter().map(|g| g.len).chain(stencil.through.iter().map(|(_, s)| s.len())).max();
        assert!(longest.is_some_and(|len| len <= WRAP), "{dx} x {dy}: {longest:?}");
    }
}

#[test]
fn levels_from_the_formula_are_those_found_by_halving() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut slopes: Vec<f64> = LEVELS.iter().flat_map(|&l| [l, l.next_down(), l.next_up(), -l]).collect();
    slopes.extend((0..100_000).map(|_| rng.random_range(-1.0..1.0) * 10f64.powf(rng.random_range(-12.0..8.0))));
    slopes.extend([0.0, -0.0, 1e6, -1e6, 1e6_f64.next_up(), f64::MAX, f64::MIN, f64::NAN, f64::INFINITY, f64::NEG_INFINITY]);
    for s in slopes {
        assert_eq!(level_above(&LEVELS, s), level_by_halving(&LEVELS, s), "{s}");
    }
}

#[test]
fn direction_inverts_the_pseudo_angle() {
    for k in 0..400 {
        let s = 4.0 * f64::from(k) / 400.0;
        let (x, y) = direction(s);
        assert!((pseudo_angle(x, y) - s).abs() < 1e-12 || (s == 4.0), "{s}");
        assert!(((x * x + y * y) - 1.0).abs() < 1e-12);
    }
}

/// The skyline of node `(i, j)` as first written, cell by cell, with the cells off the grid
/// and the triangles with a nodata corner skipped explicitly, and each plane entered by a
/// loop over its span.
fn reference(g: &Grid, i: usize, j: usize) -> Skyline {
    let edges = sector_edges();
    let (nx, z) = (g.nx, &g.z);
    let zt = z[i * nx + j];
    let (inv_dx, inv_dy) = (1.0 / g.dx, 1.0 / g.dy);
    let (rows, cols) = ((g.ny - 1) as isize, (nx - 1) as isize);
    let mut bound = [f64::NEG_INFINITY; SECTORS];
    for cell in cells(g.dx, g.dy) {
        let (ci, cj) = (i as isize + cell.di, j as isize + cell.dj);
        if ci < 0 || cj < 0 || ci >= rows || cj >= cols {
            continue;
        }
        let row = ci as usize * nx + cj as usize;
        let (za, zb, zc, zd) = (z[row], z[row + 1], z[row + nx + 1], z[row + nx]);
        if za.is_nan() || zc.is_nan() {
            continue;
        }
        let planes = [((zb - za) * inv_dx, (zc - zb) * inv_dy), ((zc - zd) * inv_dx, (zd - za) * inv_dy)];
        for ((shape, (gx, gy)), present) in cell.tris.iter().zip(planes).zip([!zb.is_nan(), !zd.is_nan()]) {
            if !present {
                continue;
            }
            let (lift, span) = match *shape {
                Shape::Through(span) => (0.0, span),
                Shape::Away { inv_near, inv_far, span } => {
                    let h0 = za - zt - gx * (cell.dj as f64 * g.dx) - gy * (cell.di as f64 * g.dy);
                    (if h0 > 0.0 { h0 * inv_near } else { h0 * inv_far }, span)
                }
            };
            let steepest = (gx * gx + gy * gy).sqrt();
            for t in 0..span.len() {
                let k = (span.first + t) % SECTORS;
                let ((ex, ey), (fx, fy)) = (edges[k], edges[k + 1]);
                let inside = ex * gy - ey * gx >= 0.0 && fx * gy - fy * gx < 0.0;
                let top = lift + if inside { steepest } else { (gx * ex + gy * ey).max(gx * fx + gy * fy) };
                if top > bound[k] {
                    bound[k] = top;
                }
            }
        }
    }
    finish(&bound)
}

/// The stencil's groups give the reference's skylines to the last bit, at every node (the
/// edges and nodata included), on rugged, steep, flat and far-off grids.
#[test]
fn skylines_are_the_reference_ones() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut nodes = 0;
    for case in 0..48 {
        let (ny, nx) = (14 + case % 5, 15 + case % 7);
        let (dx, dy) = [(1.0, 1.0), (0.5, 0.8), (2.0, 0.25)][case % 3];
        let (base, amplitude) = [(0.0, 2.0), (1e6, 300.0), (-40.0, 1e-9), (0.0, 0.0)][case / 3 % 4];
        let holes = if case % 4 == 3 { 0.08 } else { 0.0 };
        let z: Vec<f64> = (0..ny * nx)
            .map(|_| if rng.random::<f64>() < holes { f64::NAN } else { base + amplitude * rng.random_range(-1.0..1.0) })
            .collect();
        let g = &grid(z.clone(), ny, nx, dx, dy);
        let stencil = Stencil::of_grid(g);
        for i in 0..ny {
            for j in 0..nx {
                if !z[i * nx + j].is_nan() {
                    nodes += 1;
                    let expected = reference(g, i, j);
                    assert_eq!(stencil.skyline(g, i, j), expected, "case {case} node ({i}, {j})");
                    // The portable build too, wherever the CPU takes the AVX2 one.
                    assert_eq!(stencil.skyline_anywhere(g, i, j), expected, "case {case} node ({i}, {j})");
                }
            }
        }
    }
    assert!(nodes > 10_000, "{nodes} nodes");
}

/// Brute force: dense samples of every triangle within reach must lie under the bound of
/// their direction's sector.
#[test]
fn bounds_hold_for_points_sampled_on_the_surface() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for case in 0..40 {
        let (ny, nx) = (9, 10);
        let (dx, dy) = if case % 3 == 0 { (0.5, 0.8) } else { (1.0, 1.0) };
        let z: Vec<f64> =
            (0..ny * nx).map(|_| if case % 5 == 4 && rng.random::<f64>() < 0.1 { f64::NAN } else { rng.random_range(-2.0..2.0) }).collect();
        if z.iter().all(|h| h.is_nan()) {
            continue; // no triangle at all
        }
        let g = &grid(z.clone(), ny, nx, dx, dy);
        let stencil = Stencil::of_grid(g);
        let reach = REACH as f64 * dx.min(dy);
        for i in 0..ny {
            for j in 0..nx {
                let zt = z[i * nx + j];
                if zt.is_nan() {
                    continue;
                }
                let sky = stencil.skyline(g, i, j);
                for ci in 0..ny - 1 {
                    for cj in 0..nx - 1 {
                        for tri in g.cell_triangles(ci, cj).into_iter().flatten() {
                            for _ in 0..30 {
                                let (mut u, mut w) = (rng.random::<f64>(), rng.random::<f64>());
                                if u + w > 1.0 {
                                    (u, w) = (1.0 - u, 1.0 - w);
                                }
                                let p = tri[0] + (tri[1] - tri[0]) * u + (tri[2] - tri[0]) * w;
                                let (px, py) = (p.x - j as f64 * dx, p.y - i as f64 * dy);
                                let rho = (px * px + py * py).sqrt();
                                if rho > reach || rho < 1e-9 {
                                    continue;
                                }
                                let k = sector_of(pseudo_angle(px, py));
                                let slope = (p.z - zt) / rho;
                                assert!(slope <= sky.slope(k) + 1e-9, "case {case} node ({i}, {j}) slope {slope} > {}", sky.slope(k));
                            }
                        }
                    }
                }
            }
        }
    }
}
