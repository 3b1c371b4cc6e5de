use super::*;

fn flat(n: usize) -> Arc<Surface> {
    Arc::new(Surface::from_grid(vec![0.0; n * n], n, n, 1.0, 1.0, 0.0, 0.0).unwrap())
}

#[test]
fn a_target_computed_alone_is_the_one_its_chunk_lists() {
    // A grid with a nodata block, whose unused nodes the chunks skip, and one without.
    let z = |k: usize| if (300..340).contains(&k) || k % 97 == 5 { f64::NAN } else { (k % 13) as f64 };
    for holes in [false, true] {
        let heights: Vec<f64> = (0..41 * 41).map(|k| if holes { z(k) } else { (k % 13) as f64 }).collect();
        let targets = Targets::grid_nodes(Arc::new(Surface::from_grid(heights, 41, 41, 1.0, 1.0, 0.0, 0.0).unwrap())).unwrap();
        let mut all = Vec::new();
        for c in 0..targets.n_chunks() {
            let (mut points, mut nodes) = (Vec::new(), Vec::new());
            targets.chunk_points(c, &mut points);
            targets.chunk_nodes(c, &mut nodes);
            for (t, (q, k)) in points.iter().zip(&nodes).enumerate() {
                assert_eq!(targets.chunk_target(c, t), (*q, Some(*k)));
            }
            all.extend(points);
        }
        assert_eq!(all.len() < 41 * 41, holes);
    }
}

#[test]
fn range_limits_a_flat_plane_to_a_disk() {
    let s = flat(41);
    let vis = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 10.0).unwrap();
    let seen = vis.seen(&[[20.0, 20.0, 6.0]], 1).unwrap();
    for (q, &v) in vis.targets().points().iter().zip(&seen) {
        let r2 = (q[0] - 20.0).powi(2) + (q[1] - 20.0).powi(2);
        assert_eq!(v, r2 + 36.0 <= 100.0, "{q:?}");
    }
}

#[test]
fn a_wall_hides_what_is_behind_it() {
    // Ground y in [0, 10] at z = 0 with a 5 m high wall along x = 5.
    let s = Arc::new(
        Surface::new(
            vec![
                [0.0, 0.0, 0.0],
                [10.0, 0.0, 0.0],
                [10.0, 10.0, 0.0],
                [0.0, 10.0, 0.0],
                [5.0, 0.0, 0.0],
                [5.0, 10.0, 0.0],
                [5.0, 10.0, 5.0],
                [5.0, 0.0, 5.0],
            ],
            vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]],
        )
        .unwrap(),
    );
    let targets = Targets::new(vec![[2.0, 5.0, 0.0], [8.0, 5.0, 0.0]], None).unwrap();
    let vis = Visibility::new(s, targets, 50.0).unwrap();
    assert_eq!(vis.seen(&[[1.0, 5.0, 1.0]], 1).unwrap(), vec![true, false]);
    let counts = vis.per_uav(&[[1.0, 5.0, 1.0], [9.0, 5.0, 1.0]], 2).unwrap();
    assert_eq!(counts.seen, vec![1, 1]);
    assert_eq!(counts.exclusive, vec![1, 1]);
}

#[test]
fn thread_count_does_not_change_results() {
    let n = 60;
    let z: Vec<f64> = (0..n * n).map(|k| ((k % n) as f64 * 0.3).sin() * 4.0 + ((k / n) as f64 * 0.2).cos() * 3.0).collect();
    let s = Arc::new(Surface::from_grid(z, n, n, 1.0, 1.0, 0.0, 0.0).unwrap());
    let vis = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 20.0).unwrap();
    let uavs = [[10.0, 10.0, 9.0], [40.0, 30.0, 8.0], [50.0, 50.0, 12.0]];
    let one = vis.seen(&uavs, 1).unwrap();
    assert_eq!(one, vis.seen(&uavs, 2).unwrap());
    assert_eq!(vis.coverage(&uavs, 1).unwrap(), vis.coverage(&uavs, 3).unwrap());
    assert_eq!(vis.per_uav(&uavs, 1).unwrap(), vis.per_uav(&uavs, 2).unwrap());
    assert!(one.iter().any(|&v| v) && one.iter().any(|&v| !v));
}

/// Rugged hills with a few nodata holes and terraces, on a grid with an odd origin.
fn rugged(n: usize) -> Arc<Surface> {
    let z: Vec<f64> = (0..n * n)
        .map(|k| {
            let (i, j) = ((k / n) as f64, (k % n) as f64);
            if (k * 7919) % 97 == 3 {
                return f64::NAN;
            }
            let h = 6.0 * (0.7 * i).sin() * (0.5 * j).cos() + 3.0 * (1.3 * j + 0.2 * i).sin();
            if i > 30.0 {
                (h / 2.0).round() * 2.0
            } else {
                h
            }
        })
        .collect();
    Arc::new(Surface::from_grid(z, n, n, 0.5, 0.5, 101.25, -7.5).unwrap())
}

#[test]
fn uavs_high_above_the_nodes_keep_the_mesh_paths_answers() {
    // Over rugged hills (heights within about 9 m), UAVs from level with the hilltops to
    // beyond the range: their horizons reach less far, the answers are the mesh path's.
    let s = rugged(50);
    let field = s.heightfield().unwrap();
    let g = field.grid();
    let (lo, hi) = ((102.0, 110.0), (-6.0, 3.0));
    let brute = (0..g.nx * g.ny)
        .map(|k| g.node_point(k))
        .filter(|q| q[2].is_finite() && (lo.0..=lo.1).contains(&q[0]) && (hi.0..=hi.1).contains(&q[1]))
        .fold(f64::NEG_INFINITY, |m, q| m.max(q[2]));
    let bound = field.highest_within(lo, hi);
    assert!(bound >= brute && bound <= g.z.iter().copied().fold(f64::NEG_INFINITY, f64::max), "{bound} {brute}");
    assert_eq!(field.highest_within((500.0, 600.0), hi), f64::NEG_INFINITY);
    let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 12.0).unwrap();
    let mesh = Visibility::with_path(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 12.0, Path::Mesh).unwrap();
    for z in [9.0, 12.0, 15.0, 18.0, 20.5, 21.5, 30.0] {
        let uavs: Vec<Point> = (0..4).map(|k| [104.0 + 5.0 * f64::from(k), -4.0 + 4.0 * f64::from(k), z + f64::from(k) * 0.25]).collect();
        let seen = mesh.seen(&uavs, 1).unwrap();
        for _ in 0..3 {
            assert_eq!(nodes.seen(&uavs, 2).unwrap(), seen, "UAVs at {z} m");
        }
        // Low enough, some nodes are seen; above range, none.
        assert!(z >= 15.0 || seen.iter().any(|&v| v), "UAVs at {z} m");
        assert!(z < 30.0 || !seen.iter().any(|&v| v), "UAVs at {z} m");
    }
}

#[test]
fn horizons_stop_short_by_a_skylines_reach_with_the_mesh_paths_answers() {
    // Grid-node targets have skylines that clear a sight line's last REACH cells, so the
    // grid path's horizons stop that much short of the range. UAVs a few metres over rugged
    // hills (grazing lines, long ones across the whole range), from the first evaluation
    // (no skylines yet) on, give the mesh path's answers.
    let s = rugged(50);
    let field = s.heightfield().unwrap();
    let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 14.0).unwrap();
    let points = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 14.0).unwrap();
    let reach = crate::surface::skyline::REACH as f64 * 0.5;
    assert_eq!(nodes.horizon_reach(field, 14.0), 14.0 - reach);
    assert_eq!(nodes.horizon_reach(field, 0.5 * reach), 0.0);
    assert_eq!(points.horizon_reach(field, 14.0), 14.0);
    let mesh = Visibility::with_path(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 14.0, Path::Mesh).unwrap();
    for z in [7.0, 9.0, 11.0] {
        let uavs: Vec<Point> = (0..5).map(|k| [102.0 + 5.5 * f64::from(k), 4.0 - 2.5 * f64::from(k), z - 0.3 * f64::from(k)]).collect();
        let seen = mesh.seen(&uavs, 1).unwrap();
        assert!(seen.iter().any(|&v| v) && !seen.iter().all(|&v| v), "UAVs at {z} m");
        for _ in 0..3 {
            assert_eq!(nodes.seen(&uavs, 2).unwrap(), seen, "UAVs at {z} m");
            assert_eq!(points.seen(&uavs, 1).unwrap(), seen, "UAVs at {z} m");
        }
    }
}

#[test]
fn grid_and_mesh_paths_give_identical_answers() {
    let s = rugged(50);
    let targets = Targets::of_surface(&s, 1.0).unwrap();
    let grid = Visibility::with_path(s.clone(), targets.clone(), 9.0, Path::Auto).unwrap();
    let mesh = Visibility::with_path(s.clone(), targets, 9.0, Path::Mesh).unwrap();
    assert_eq!((grid.path(), mesh.path()), (Path::Grid, Path::Mesh));
    let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 9.0).unwrap();
    assert!(nodes.targets().is_grid_nodes());
    assert_eq!(nodes.targets().points().as_ref(), grid.targets().points().as_ref());
    assert_eq!(nodes.targets().weights(), grid.targets().weights());
    let uavs: Vec<Point> = (0..6).map(|k| [103.0 + 4.0 * f64::from(k), -5.0 + 3.5 * f64::from(k), 4.0 + f64::from(k)]).collect();
    for n in 1..=uavs.len() {
        let u = &uavs[..n];
        let seen = mesh.seen(u, 1).unwrap();
        assert_eq!(grid.seen(u, 2).unwrap(), seen);
        assert_eq!(nodes.seen(u, 2).unwrap(), seen);
        assert_eq!(grid.coverage(u, 1).unwrap(), mesh.coverage(u, 2).unwrap());
        assert_eq!(nodes.coverage(u, 1).unwrap(), mesh.coverage(u, 1).unwrap());
        assert_eq!(grid.per_uav(u, 2).unwrap(), mesh.per_uav(u, 1).unwrap());
        assert_eq!(nodes.per_uav(u, 1).unwrap(), mesh.per_uav(u, 2).unwrap());
        let count = seen.iter().filter(|&&v| v).count();
        assert!(count > 0 && count < seen.len());
    }
}

#[test]
fn objectives_over_one_grids_nodes_share_its_skylines_with_the_same_answers() {
    let s = rugged(40);
    let nodes = || Targets::grid_nodes(s.clone()).unwrap();
    let first = Visibility::new(s.clone(), nodes(), 9.0).unwrap();
    let second = Visibility::new(s.clone(), nodes(), 6.0).unwrap();
    let store = |v: &Visibility| Arc::clone(&v.skylines.as_ref().expect("grid-node skylines").0);
    assert!(Arc::ptr_eq(&store(&first), &store(&second)));
    // Another surface with the same heights has its own store and, skylines or not, the
    // same answers: fill the shared store through `first`, then ask `second`.
    let alone = rugged(40);
    let fresh = Visibility::new(alone.clone(), Targets::grid_nodes(alone).unwrap(), 6.0).unwrap();
    assert!(!Arc::ptr_eq(&store(&first), &store(&fresh)));
    let configs: Vec<Vec<Point>> =
        (0..4).map(|k| (0..3).map(|u| [103.0 + 5.0 * f64::from(u + k), -4.0 + 4.0 * f64::from(u), 5.0 + f64::from(k)]).collect()).collect();
    for uavs in &configs {
        first.seen(uavs, 2).unwrap();
        first.seen(uavs, 1).unwrap();
    }
    for uavs in &configs {
        for _ in 0..2 {
            assert_eq!(second.seen(uavs, 2).unwrap(), fresh.seen(uavs, 1).unwrap());
            assert_eq!(second.per_uav(uavs, 1).unwrap(), fresh.per_uav(uavs, 2).unwrap());
        }
    }
    // The mesh path's skylines of the same nodes come from the triangles: its own store.
    let mesh = Visibility::with_path(s.clone(), nodes(), 9.0, Path::Mesh).unwrap();
    assert!(!Arc::ptr_eq(&store(&first), &store(&mesh)));
}

/// A camera looking along heading `yaw` (degrees clockwise from +y) with gimbal pitch
/// `pitch` (degrees, -90 straight down), `h` x `v` degrees wide.
fn camera(yaw: f64, pitch: f64, h: f64, v: f64) -> crate::visibility::sensor::Frustum {
    let (sy, cy) = yaw.to_radians().sin_cos();
    let (sp, cp) = pitch.to_radians().sin_cos();
    let forward = [sy * cp, cy * cp, sp];
    let right = [cy, -sy, 0.0];
    let up = [
        right[1] * forward[2] - right[2] * forward[1],
        right[2] * forward[0] - right[0] * forward[2],
        right[0] * forward[1] - right[1] * forward[0],
    ];
    crate::visibility::sensor::Frustum::new(forward, right, up, (h / 2.0).to_radians().tan(), (v / 2.0).to_radians().tan()).unwrap()
}

#[test]
fn sensors_give_each_uavs_sight_lines_within_its_reach_on_both_paths() {
    let s = rugged(50);
    let targets = Targets::of_surface(&s, 1.0).unwrap();
    let points = targets.points().into_owned();
    let grid = Visibility::with_path(s.clone(), targets.clone(), 9.0, Path::Auto).unwrap();
    let mesh = Visibility::with_path(s.clone(), targets, 9.0, Path::Mesh).unwrap();
    let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 9.0).unwrap();
    let uavs: Vec<Point> = (0..6).map(|k| [103.0 + 4.0 * f64::from(k), -5.0 + 3.5 * f64::from(k), 6.0 + f64::from(k)]).collect();
    let sensors = [
        Sensor::omnidirectional(9.0).unwrap(),
        Sensor::new(2.0, 12.0, Some(camera(0.0, -90.0, 84.0, 60.0))).unwrap(),
        Sensor::new(0.0, 15.0, Some(camera(359.0, -45.0, 60.0, 45.0))).unwrap(),
        Sensor::new(1.0, 7.0, Some(camera(90.0, 0.0, 120.0, 90.0))).unwrap(),
        Sensor::new(0.0, 20.0, Some(camera(200.0, -60.0, 30.0, 20.0))).unwrap(),
        Sensor::new(0.0, 10.0, None).unwrap(),
    ];
    // The reference: each UAV alone, omnidirectional with an ample range (its sight lines),
    // kept where its own sensor reaches.
    let wide = Visibility::with_path(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 25.0, Path::Mesh).unwrap();
    let alone: Vec<Vec<bool>> = uavs.iter().map(|&u| wide.seen(&[u], 1).unwrap()).collect();
    for n in 1..=uavs.len() {
        let (u, sens) = (&uavs[..n], &sensors[..n]);
        let expected: Vec<bool> = (0..points.len()).map(|t| (0..n).any(|i| alone[i][t] && sens[i].accepts(u[i], points[t]))).collect();
        assert_eq!(mesh.seen_by(u, Some(sens), 1).unwrap(), expected, "{n} UAVs");
        assert_eq!(grid.seen_by(u, Some(sens), 2).unwrap(), expected);
        assert_eq!(nodes.seen_by(u, Some(sens), 2).unwrap(), expected);
        assert_eq!(grid.per_uav_by(u, Some(sens), 1).unwrap(), mesh.per_uav_by(u, Some(sens), 2).unwrap());
        assert_eq!(nodes.coverage_by(u, Some(sens), 1).unwrap(), mesh.coverage_by(u, Some(sens), 1).unwrap());
        let count = expected.iter().filter(|&&v| v).count();
        assert!(count > 0 && count < expected.len());
    }
    // the paper's sensor given explicitly is the objective's own
    let omni = vec![Sensor::omnidirectional(9.0).unwrap(); 6];
    assert_eq!(grid.seen_by(&uavs, Some(&omni), 1).unwrap(), grid.seen(&uavs, 1).unwrap());
    assert!(grid.seen_by(&uavs, Some(&omni[..5]), 1).is_err());
}

#[test]
fn incidence_and_quality_on_a_flat_plane_follow_their_formulas() {
    let s = flat(41); // 40 m x 40 m at 1 m, z = 0
    let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 100.0).unwrap();
    let given = Targets::of_surface(&s, 1.0).unwrap();
    let up = vec![[0.0, 0.0, 1.0]; given.len()];
    let given = Visibility::with_path(s.clone(), given.with_normals(up).unwrap(), 100.0, Path::Mesh).unwrap();
    let uav = [20.0, 20.0, 10.0];
    // at most 45 deg off the normal: the disk of radius 10 m under the UAV
    let steep = [Sensor::omnidirectional(100.0).unwrap().with_incidence_limit(std::f64::consts::FRAC_1_SQRT_2).unwrap()];
    let points = nodes.targets().points().into_owned();
    let seen = nodes.seen_by(&[uav], Some(&steep), 1).unwrap();
    for (q, &v) in points.iter().zip(&seen) {
        let r2 = (q[0] - 20.0).powi(2) + (q[1] - 20.0).powi(2);
        if (r2 - 100.0).abs() > 1e-6 {
            assert_eq!(v, r2 < 100.0, "{q:?}");
        }
    }
    assert_eq!(given.seen_by(&[uav], Some(&steep), 1).unwrap(), seen);
    // quality: resolution good up to 12 m (0.001 m/px per metre, 0.012 m/px), times cos
    let rated = [Sensor::omnidirectional(100.0).unwrap().with_resolution(0.001, 0.012).unwrap()];
    let quality = nodes.quality_by(&[uav], Some(&rated), 2).unwrap();
    for (q, &got) in points.iter().zip(&quality) {
        let d = ((q[0] - 20.0).powi(2) + (q[1] - 20.0).powi(2) + 100.0).sqrt();
        let expected = (0.012 / (0.001 * d)).min(1.0) * (10.0 / d);
        assert!((got - expected).abs() < 1e-12, "{q:?}: {got} vs {expected}");
    }
    assert_eq!(given.quality_by(&[uav], Some(&rated), 1).unwrap(), quality);
    let mean = nodes.quality_coverage_by(&[uav], Some(&rated), 1).unwrap();
    assert!(mean > 0.2 && mean < nodes.coverage(&[uav], 1).unwrap());
    // the objective's own range: every seen target has quality 1
    let plain = nodes.quality_by(&[uav], None, 1).unwrap();
    assert!(plain.iter().zip(nodes.seen(&[uav], 1).unwrap()).all(|(&q, v)| q == if v { 1.0 } else { 0.0 }));
    // targets without normals cannot take an incidence limit
    let bare = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 100.0).unwrap();
    assert!(bare.seen_by(&[uav], Some(&steep), 1).is_err());
    assert!(bare.quality_by(&[uav], Some(&rated), 1).is_ok()); // quality without incidence
}

#[test]
fn incidence_and_quality_are_the_same_on_both_paths() {
    let s = rugged(50);
    let g = s.grid().unwrap();
    let normals: Vec<Point> = (0..g.nx * g.ny).filter(|&k| g.vertex_of_node[k] != u32::MAX).map(|k| g.node_normal(k).unwrap()).collect();
    let targets = Targets::of_surface(&s, 1.0).unwrap().with_normals(normals).unwrap();
    let grid = Visibility::with_path(s.clone(), targets.clone(), 9.0, Path::Auto).unwrap();
    let mesh = Visibility::with_path(s.clone(), targets, 9.0, Path::Mesh).unwrap();
    let nodes = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 9.0).unwrap();
    let uavs: Vec<Point> = (0..5).map(|k| [103.0 + 4.0 * f64::from(k), -5.0 + 3.5 * f64::from(k), 6.0 + f64::from(k)]).collect();
    let sensors: Vec<Sensor> = (0..5)
        .map(|k| {
            let s = Sensor::new(0.0, 8.0 + f64::from(k), (k % 2 == 1).then(|| camera(72.0 * f64::from(k), -60.0, 90.0, 70.0))).unwrap();
            s.with_incidence_limit(0.3 + 0.1 * f64::from(k)).unwrap().with_resolution(0.0005, 0.003).unwrap()
        })
        .collect();
    for n in 1..=5 {
        let (u, sens) = (&uavs[..n], &sensors[..n]);
        let seen = mesh.seen_by(u, Some(sens), 1).unwrap();
        assert_eq!(grid.seen_by(u, Some(sens), 2).unwrap(), seen);
        assert_eq!(nodes.seen_by(u, Some(sens), 2).unwrap(), seen);
        let quality = mesh.quality_by(u, Some(sens), 2).unwrap();
        assert_eq!(grid.quality_by(u, Some(sens), 1).unwrap(), quality);
        assert_eq!(nodes.quality_by(u, Some(sens), 1).unwrap(), quality);
        assert!(quality.iter().zip(&seen).all(|(&q, &v)| (q > 0.0) == v && q <= 1.0));
        assert_eq!(nodes.per_uav_by(u, Some(sens), 1).unwrap(), mesh.per_uav_by(u, Some(sens), 2).unwrap());
    }
}

#[test]
fn paths_are_checked() {
    let s = flat(5);
    let t = || Targets::of_surface(&s, 1.0).unwrap();
    assert_eq!("grid".parse::<Path>().unwrap(), Path::Grid);
    assert!("bvh".parse::<Path>().is_err());
    let mesh = Arc::new(Surface::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]).unwrap());
    assert!(Visibility::with_path(mesh.clone(), t(), 5.0, Path::Grid).is_err());
    assert!(Targets::grid_nodes(mesh.clone()).is_err());
    assert_eq!(Visibility::new(mesh, t(), 5.0).unwrap().path(), Path::Mesh);
    // Grid-node targets of one surface cannot be used on another.
    assert!(Visibility::new(flat(5), Targets::grid_nodes(s.clone()).unwrap(), 5.0).is_err());
}

#[test]
fn the_mesh_path_refuses_a_grid_too_large_for_it() {
    // 2300 x 2300 nodes: 10.6 million triangles, over MAX_TRIANGLES; the grid path is fine.
    let n = 2300;
    let s = Arc::new(Surface::from_grid(vec![0.0; n * n], n, n, 1.0, 1.0, 0.0, 0.0).unwrap());
    let targets = Targets::new(vec![[10.0, 10.0, 0.0]], None).unwrap();
    let err = Visibility::with_path(s.clone(), targets.clone(), 5.0, Path::Mesh).err().unwrap();
    assert!(matches!(err, crate::error::Error::TooLarge(_)), "{err:?}");
    let vis = Visibility::new(s, targets, 5.0).unwrap();
    assert_eq!(vis.seen(&[[10.0, 12.0, 3.0]], 1).unwrap(), vec![true]);
}

#[test]
fn bad_input_is_an_error() {
    let s = flat(3);
    let t = || Targets::of_surface(&s, 1.0).unwrap();
    assert!(Visibility::new(s.clone(), t(), 0.0).is_err());
    assert!(Visibility::new(s.clone(), t(), f64::NAN).is_err());
    let vis = Visibility::new(s.clone(), t(), 5.0).unwrap();
    assert!(vis.seen(&[], 1).is_err());
    assert!(vis.seen(&[[f64::NAN, 0.0, 1.0]], 1).is_err());
    assert!(Targets::new(vec![], None).is_err());
    assert!(Targets::new(vec![[0.0; 3]], Some(vec![-1.0])).is_err());
    assert!(Targets::new(vec![[0.0; 3]], Some(vec![0.0])).is_err());
}

#[test]
fn huge_ranges_are_unlimited_and_answer_like_the_mesh_path() {
    // The panic: `Visibility(t, 1e19).coverage([[5, 5, 3]])` on an 11 x 11 grid.
    let s = flat(11);
    let nodes = || Targets::grid_nodes(s.clone()).unwrap();
    let all = Visibility::new(s.clone(), nodes(), 100.0).unwrap().seen(&[[5.0, 5.0, 3.0]], 1).unwrap();
    for d_max in [6e18, 1e19, 1e300, f64::MAX] {
        for path in [Path::Grid, Path::Mesh] {
            let vis = Visibility::with_path(s.clone(), nodes(), d_max, path).unwrap();
            assert_eq!(vis.d_max(), d_max);
            assert_eq!(vis.seen(&[[5.0, 5.0, 3.0]], 1).unwrap(), all, "{d_max} {path:?}");
            assert_eq!(vis.coverage(&[[5.0, 5.0, 3.0], [1e15, -1e15, 1e15]], 2).unwrap(), 1.0);
            assert_eq!(vis.per_uav(&[[5.0, 5.0, 3.0]], 1).unwrap().coverage, 1.0);
        }
    }
}

#[test]
fn coordinates_beyond_the_bound_are_refused() {
    // The silent 1.0: the mesh path, d_max = 1e300 and a UAV at z = 3e300.
    let s = flat(11);
    let vis = Visibility::with_path(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 1e300, Path::Mesh).unwrap();
    for uav in [[5.0, 5.0, 3e300], [5.0, 1.000_000_1e15, 3.0]] {
        assert!(matches!(vis.coverage(&[uav], 1), Err(Error::InvalidInput(_))), "{uav:?}");
        assert!(matches!(vis.per_uav(&[uav], 1), Err(Error::InvalidInput(_))));
    }
    assert!(matches!(Targets::new(vec![[1e300, 0.0, 0.0]], None), Err(Error::InvalidInput(_))));
}

#[test]
fn grids_far_from_the_origin_give_the_mesh_paths_coverage() {
    // The hang: a grid at 1e10 m, one UAV above it.
    let n = 30;
    let z: Vec<f64> = (0..n * n).map(|k| ((k * 7919) % 23) as f64 * 0.4).collect();
    let s = Arc::new(Surface::from_grid(z, n, n, 1.0, 1.0, 1e10, 1e10).unwrap());
    let grid = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 25.0).unwrap();
    let mesh = Visibility::with_path(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 25.0, Path::Mesh).unwrap();
    let uavs = [[1e10 + 15.0, 1e10 + 15.0, 12.0], [1e10 + 3.0, 1e10 + 25.0, 9.0]];
    assert_eq!(grid.seen(&uavs, 2).unwrap(), mesh.seen(&uavs, 1).unwrap());
    assert_eq!(grid.per_uav(&uavs, 1).unwrap(), mesh.per_uav(&uavs, 2).unwrap());
}

#[test]
fn many_uavs_keep_to_the_horizon_and_counter_budgets() {
    // 5000 UAVs: horizons share HORIZON_BUDGET, counters are summed in batches; the answers
    // are those of the mesh path.
    let s = rugged(40);
    let targets = Targets::of_surface(&s, 1.0).unwrap();
    let grid = Visibility::new(s.clone(), targets.clone(), 1e9).unwrap();
    let mesh = Visibility::with_path(s.clone(), targets, 1e9, Path::Mesh).unwrap();
    let uavs: Vec<Point> = (0..5000).map(|k| [101.0 + f64::from(k % 50) * 0.4, -7.0 + f64::from(k / 50) * 0.2, 12.0]).collect();
    assert_eq!(grid.per_uav(&uavs, 2).unwrap(), mesh.per_uav(&uavs, 2).unwrap());
}
