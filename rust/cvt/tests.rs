use super::*;

fn rectangle(width: f64, height: f64) -> Surface {
    Surface::new(vec![[0.0, 0.0, 0.0], [width, 0.0, 0.0], [width, height, 0.0], [0.0, height, 0.0]], vec![[0, 1, 2], [0, 2, 3]]).unwrap()
}

/// A hilly 100 m square: a 21 x 21 grid of two Gaussian bumps.
fn hills() -> Surface {
    let (nx, ny, step) = (21, 21, 5.0);
    let z: Vec<f64> = (0..nx * ny)
        .map(|k| {
            let (x, y) = ((k % nx) as f64 * step, (k / nx) as f64 * step);
            let bump = |cx: f64, cy: f64, h: f64, s: f64| h * (-((x - cx).powi(2) + (y - cy).powi(2)) / (2.0 * s * s)).exp();
            bump(30.0, 40.0, 20.0, 12.0) + bump(70.0, 65.0, 12.0, 15.0)
        })
        .collect();
    Surface::from_grid(z, ny, nx, step, step, 0.0, 0.0).unwrap()
}

fn sorted_x(t: &Tessellation) -> Vec<f64> {
    let mut x: Vec<f64> = t.generators.iter().map(|g| g[0]).collect();
    x.sort_by(f64::total_cmp);
    x
}

#[test]
fn coefficients_follow_the_paper() {
    let w = Weights::new([0.3, 0.7], [0.8, 0.2]).unwrap();
    let (keep, toward) = w.coefficients(4);
    assert!((keep - (0.3 * 4.0 + 0.8) / 5.0).abs() < 1e-15);
    assert!((toward - (0.7 * 4.0 + 0.2) / 5.0).abs() < 1e-15);
    // The coefficients always sum to 1: the update is an affine combination.
    for j in 1..50 {
        let (a, b) = Weights::ANNEALED.coefficients(j);
        assert!((a + b - 1.0).abs() < 1e-14);
    }
    assert_eq!(Weights::DAMPED.coefficients(1), (0.5, 0.5));
    assert_eq!(Weights::DAMPED.coefficients(1000), (0.5, 0.5));
    assert_eq!(Weights::LLOYD.coefficients(9), (0.0, 1.0));
    let (_, late) = Weights::ANNEALED.coefficients(1_000_000);
    assert!((late - 0.1).abs() < 1e-5);
}

#[test]
fn one_generator_goes_to_the_centroid() {
    // The CVT of one generator is the centroid; a non-square rectangle so x and y differ.
    let s = rectangle(80.0, 30.0);
    let mut settings = CvtOptions::for_generators(1);
    settings.weights = Weights::ANNEALED; // its averaging makes the final point precise
    settings.tolerance = 0.0;
    settings.max_iterations = 200;
    let t = constrained_cvt(&s, 1, &settings.with_seed(3).with_threads(1), None, None).unwrap();
    let g = t.generators[0];
    assert!((g[0] - 40.0).abs() < 0.3 && (g[1] - 15.0).abs() < 0.2 && g[2] == 0.0, "{g:?}");
    // Energy per unit area of a w x h rectangle about its centre: (w^2 + h^2) / 12.
    let exact = (80.0f64.powi(2) + 30.0f64.powi(2)) / 12.0;
    let late: f64 = t.energy[100..].iter().sum::<f64>() / 100.0;
    assert!((late / exact - 1.0).abs() < 0.01, "{late} vs {exact}");
    assert_eq!(t.iterations, 200);
    assert!(!t.converged);
}

#[test]
fn two_generators_split_a_rectangle_into_squares() {
    let s = rectangle(200.0, 100.0);
    for seed in 0..4 {
        let t = constrained_cvt(&s, 2, &CvtOptions::for_generators(2).with_seed(seed).with_threads(1), None, None).unwrap();
        assert!(t.converged, "seed {seed}: {} iterations", t.iterations);
        let x = sorted_x(&t);
        assert!((x[0] - 50.0).abs() < 2.0 && (x[1] - 150.0).abs() < 2.0, "seed {seed}: {x:?}");
        for g in &t.generators {
            assert!((g[1] - 50.0).abs() < 2.0, "seed {seed}: {g:?}");
        }
    }
}

#[test]
fn history_is_consistent() {
    let s = hills();
    let settings = CvtOptions::for_generators(6);
    let t = constrained_cvt(&s, 6, &settings.with_seed(11).with_threads(1), None, None).unwrap();
    assert_eq!(t.moves.len(), t.iterations);
    assert_eq!(t.energy.len(), t.iterations);
    assert_eq!(t.drift.len(), t.iterations);
    assert!(t.drift[..settings.window - 1].iter().all(|d| d.is_nan()));
    let last = *t.drift.last().unwrap();
    assert_eq!(t.converged, last < settings.tolerance);
    assert!(t.converged, "{} iterations, last drift {last}", t.iterations);
    // The net move over a window is at most the sum of the moves in it (triangle inequality).
    for k in settings.window - 1..t.iterations {
        let sum: f64 = t.moves[k + 1 - settings.window..=k].iter().sum();
        assert!(t.drift[k] * settings.window as f64 <= sum + 1e-9);
    }
    // The energy falls from a random start.
    assert!(t.energy.last().unwrap() < &(0.8 * t.energy[0]));
}

#[test]
fn generators_stay_on_a_hilly_surface() {
    let s = hills();
    let t = constrained_cvt(&s, 9, &CvtOptions::for_generators(9).with_seed(5).with_threads(2), None, None).unwrap();
    for &g in &t.generators {
        let c = s.closest_point(g);
        assert!(distance(c, g) < 1e-9, "{g:?} vs {c:?}");
    }
}

#[test]
fn identical_for_any_thread_count() {
    let s = hills();
    let mut settings = CvtOptions::for_generators(7);
    settings.samples_per_iteration = 5 * CHUNK + 17; // a ragged last chunk
    let one = constrained_cvt(&s, 7, &settings.with_seed(42).with_threads(1), None, None).unwrap();
    let two = constrained_cvt(&s, 7, &settings.with_seed(42).with_threads(2), None, None).unwrap();
    let three = constrained_cvt(&s, 7, &settings.with_seed(42).with_threads(3), None, None).unwrap();
    // Bit for bit (drift holds NaN, which `==` would call unequal to itself).
    let bits = |t: &Tessellation| format!("{t:?}");
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(bits(&one), bits(&three));
    let other = constrained_cvt(&s, 7, &settings.with_seed(43).with_threads(1), None, None).unwrap();
    assert_ne!(one.generators, other.generators);
    // The same on a coarse surface, where the search runs over per-triangle candidates.
    let coarse = rectangle(120.0, 80.0);
    let one = constrained_cvt(&coarse, 7, &settings.with_seed(42).with_threads(1), None, None).unwrap();
    let two = constrained_cvt(&coarse, 7, &settings.with_seed(42).with_threads(2), None, None).unwrap();
    assert_eq!(bits(&one), bits(&two));
}

#[test]
fn density_pulls_generators() {
    // All the density on the left half: every generator ends there.
    let s = rectangle(200.0, 100.0);
    let centroid_x = |f: usize| {
        let [a, b, c] = s.triangle(f);
        (a.x + b.x + c.x) / 3.0
    };
    // Triangle 0 = (0,0),(200,0),(200,100): centroid x = 133; triangle 1: centroid x = 67.
    assert!(centroid_x(0) > 100.0 && centroid_x(1) < 100.0);
    let t = constrained_cvt(&s, 3, &CvtOptions::for_generators(3).with_seed(1).with_threads(1), Some(&[0.0, 1.0]), None).unwrap();
    for g in &t.generators {
        // Inside triangle 1: below the diagonal y = x / 2 is triangle 0.
        assert!(g[1] >= g[0] / 2.0 - 1e-9, "{g:?}");
    }
}

#[test]
fn starved_generators_keep_still() {
    // A 100 m square plus a far triangle of zero density: every sample lands on the square,
    // nearer to the generator there, so the far generator gets none and must not move.
    let s = Surface::new(
        vec![
            [0.0, 0.0, 0.0],
            [100.0, 0.0, 0.0],
            [100.0, 100.0, 0.0],
            [0.0, 100.0, 0.0],
            [1000.0, 0.0, 0.0],
            [1010.0, 0.0, 0.0],
            [1000.0, 10.0, 0.0],
        ],
        vec![[0, 1, 2], [0, 2, 3], [4, 5, 6]],
    )
    .unwrap();
    let mut settings = CvtOptions::for_generators(2);
    settings.max_iterations = 8;
    settings.tolerance = 0.0;
    let initial = [[10.0, 10.0, 0.0], [1002.0, 3.0, 0.0]];
    let t = constrained_cvt(&s, 2, &settings.with_seed(9).with_threads(1), Some(&[1.0, 1.0, 0.0]), Some(&initial)).unwrap();
    assert_eq!(t.generators[1], initial[1]);
    assert!(distance(t.generators[0], [50.0, 50.0, 0.0]) < 3.0, "{:?}", t.generators[0]);
    // The first damped step takes the square's generator half way from (10, 10) to about
    // (50, 50), some 28 m; the still one counts as a zero move in the mean.
    assert!(t.moves[0] > 12.0 && t.moves[0] < 16.5, "{}", t.moves[0]);
}

#[test]
fn sampler_follows_area_times_density() {
    // Four triangles of areas 1, 2, 3, 4 m^2 (fans on one base), with density 4, 0, 1, 2.
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for (k, height) in [1.0, 2.0, 3.0, 4.0].into_iter().enumerate() {
        let x0 = 10.0 * k as f64;
        let v = vertices.len() as u32;
        vertices.extend([[x0, 0.0, 0.0], [x0 + 2.0, 0.0, 0.0], [x0, height, 1.0]]);
        faces.push([v, v + 1, v + 2]);
    }
    let s = Surface::new(vertices, faces).unwrap();
    let density = [4.0, 0.0, 1.0, 2.0];
    let sampler = TriangleSampler::new(&s, Some(&density)).unwrap();
    let mut rng = stream(5, 0, 0, 0);
    let draws = 200_000;
    let mut counts = [0usize; 4];
    for _ in 0..draws {
        let (y, f) = sampler.sample(&mut rng);
        counts[f] += 1;
        // The point lies in the triangle it names.
        let [a, b, c] = s.triangle(f);
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        assert!((0..3).all(|i| y[i] >= lo[i] - 1e-12 && y[i] <= hi[i] + 1e-12));
    }
    let weights: Vec<f64> = s.areas().iter().zip(density).map(|(a, d)| a * d).collect();
    let total: f64 = weights.iter().sum();
    assert_eq!(counts[1], 0);
    for f in 0..4 {
        let p = weights[f] / total;
        let sigma = (f64::from(draws) * p * (1.0 - p)).sqrt();
        assert!((counts[f] as f64 - f64::from(draws) * p).abs() <= 5.0 * sigma + 1e-9, "{f}: {counts:?}");
    }
    // Uniform within a triangle: the share in the half nearer the base edge's first vertex.
    let sampler = TriangleSampler::new(&s, Some(&[1.0, 0.0, 0.0, 0.0])).unwrap();
    let left = (0..draws).filter(|_| sampler.sample(&mut rng).0[0] < 1.0).count() as f64 / f64::from(draws);
    // Triangle (0,0),(2,0),(0,1) in x-y: the part with x < 1 holds 3/4 of its area.
    assert!((left - 0.75).abs() < 0.005, "{left}");
}

#[test]
fn candidate_search_matches_brute_force() {
    let s = hills();
    let sampler = TriangleSampler::new(&s, None).unwrap();
    let triangles = triangle_corners(&s);
    let mut rng = stream(8, 0, 0, 0);
    for n in [1, 3, 17, 40] {
        let generators: Vec<Point> = (0..n).map(|_| sampler.sample(&mut rng).0).collect();
        let candidates = Candidates::new(&triangles, &generators, None, &sampler).unwrap();
        assert!(candidates.list.len() < n * s.n_triangles() || n < 3);
        // With a facing term: each generator facing a random unit direction, lambda 4 m.
        let facings: Vec<Point> = (0..n).map(|_| sampler::unit(sampler.sample(&mut rng).0.map(|c| c - 40.0))).collect();
        let facing = Facing { weight2: 16.0, normals: &facings };
        let facing_candidates = Candidates::new(&triangles, &generators, Some(&facing), &sampler).unwrap();
        for _ in 0..20_000 {
            let (y, f) = sampler.sample(&mut rng);
            let (subset, terms) = candidates.of(f);
            assert!(terms.is_empty());
            assert_eq!(nearest_in(&generators, subset, terms, y), nearest(&generators, y));
            let (subset, terms) = facing_candidates.of(f);
            assert_eq!(nearest_in(&generators, subset, terms, y), nearest_facing(&generators, &facing, sampler.normal(f), y));
        }
    }
    // Exact ties go to the lower index either way.
    let twins = [[10.0, 10.0, s.closest_point([10.0, 10.0, 0.0])[2]]; 2];
    let candidates = Candidates::new(&triangles, &twins, None, &sampler).unwrap();
    let y = s.closest_point([12.0, 11.0, 0.0]);
    let f = (0..s.n_triangles()).find(|&f| candidates.of(f).0.len() == 2).unwrap();
    let (subset, terms) = candidates.of(f);
    assert_eq!(nearest_in(&twins, subset, terms, y).0, 0);
}

#[test]
fn nearest_matches_brute_force() {
    let generators = [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 5.0]];
    let points: Vec<Point> = (0..3000).map(|k| [f64::from(k % 17) - 3.0, f64::from(k % 13), f64::from(k % 7) - 2.0]).collect();
    let labels = nearest_generator(&generators, &points, 2).unwrap();
    for (p, &l) in points.iter().zip(&labels) {
        let d: Vec<f64> = generators.iter().map(|&g| distance(g, *p)).collect();
        let best = d.iter().copied().fold(f64::INFINITY, f64::min);
        assert_eq!(d[l], best);
        assert_eq!(l, d.iter().position(|&x| x == best).unwrap()); // ties to the lower index
    }
    assert!(nearest_generator(&[], &points, 1).is_err());
    assert!(nearest_generator(&generators, &[[f64::NAN, 0.0, 0.0]], 1).is_err());
}

#[test]
fn bad_input_is_an_error() {
    let s = rectangle(10.0, 10.0);
    let ok = CvtOptions::for_generators(3);
    let run = |n: usize, settings: &CvtOptions| constrained_cvt(&s, n, &settings.with_seed(0).with_threads(1), None, None);
    assert!(matches!(run(0, &ok), Err(Error::InvalidInput(_))));
    let mut few = ok;
    few.samples_per_iteration = 2;
    assert!(matches!(run(3, &few), Err(Error::InvalidInput(_))));
    few.samples_per_iteration = 0;
    assert!(matches!(run(3, &few), Err(Error::InvalidInput(_))));
    for (alpha, beta) in [
        ([0.5, 0.6], [0.5, 0.5]),
        ([1.0, 0.0], [0.5, 0.5]),
        ([0.5, 0.5], [1.0, 0.0]),
        ([-0.5, 1.5], [0.5, 0.5]),
        ([f64::NAN, 0.5], [0.5, 0.5]),
    ] {
        let mut bad = ok;
        bad.weights = Weights { alpha, beta };
        assert!(matches!(run(3, &bad), Err(Error::InvalidInput(_))), "{alpha:?} {beta:?}");
        assert!(Weights::new(alpha, beta).is_err());
    }
    for edit in [
        |s: &mut CvtOptions| s.tolerance = -1.0,
        |s: &mut CvtOptions| s.tolerance = f64::NAN,
        |s: &mut CvtOptions| s.window = 0,
        |s: &mut CvtOptions| s.max_iterations = 0,
    ] {
        let mut bad = ok;
        edit(&mut bad);
        assert!(matches!(run(3, &bad), Err(Error::InvalidInput(_))));
    }
    for density in [vec![0.0, 0.0], vec![1.0, -1.0], vec![1.0, f64::NAN], vec![1.0]] {
        assert!(matches!(constrained_cvt(&s, 3, &ok.with_seed(0).with_threads(1), Some(&density), None), Err(Error::InvalidInput(_))));
    }
    let two = [[1.0, 1.0, 0.0], [2.0, 2.0, 0.0]];
    assert!(constrained_cvt(&s, 3, &ok.with_seed(0).with_threads(1), None, Some(&two)).is_err());
    let nan = [[1.0, 1.0, 0.0], [2.0, 2.0, 0.0], [f64::NAN, 0.0, 0.0]];
    assert!(constrained_cvt(&s, 3, &ok.with_seed(0).with_threads(1), None, Some(&nan)).is_err());
}

#[test]
fn extreme_sizes_are_errors_or_bounded() {
    let s = rectangle(10.0, 10.0);
    let base = CvtOptions::for_generators(3).with_seed(0).with_threads(1);
    // A window and iteration count of usize::MAX: no overflow (`window + 1`, `n * window`).
    let endless = CvtOptions { window: usize::MAX, max_iterations: 3, ..base };
    let t = constrained_cvt(&s, 3, &endless, None, None).unwrap();
    assert_eq!(t.iterations, 3);
    assert!(t.drift.iter().all(|d| d.is_nan()));
    // Initial generators beyond the coordinate bound are refused.
    let far = [[1e300, 0.0, 0.0]; 3];
    assert!(matches!(constrained_cvt(&s, 3, &base, None, Some(&far)), Err(Error::InvalidInput(_))));
}

/// A 30 m x 10 m floor (z = 0) meeting a 10 m x 10 m wall (x = 30) at a right angle.
fn floor_and_wall() -> Surface {
    let v = vec![[0.0, 0.0, 0.0], [30.0, 0.0, 0.0], [30.0, 10.0, 0.0], [0.0, 10.0, 0.0], [30.0, 0.0, 10.0], [30.0, 10.0, 10.0]];
    // The wall faces the floor (-x), the floor up.
    Surface::new(v, vec![[0, 1, 2], [0, 2, 3], [1, 5, 2], [1, 4, 5]]).unwrap()
}

#[test]
fn facing_term_gathers_one_face_per_region() {
    let s = floor_and_wall();
    let base = CvtOptions { tolerance: 0.0, max_iterations: 80, ..CvtOptions::for_generators(2) }.with_seed(4).with_threads(1);
    let by_position = constrained_cvt(&s, 2, &base, None, None).unwrap();
    // By position alone, the generator nearer the wall takes half the surface: the wall and
    // the floor's last 10 m, so no generator sits on the wall's centre.
    assert!(by_position.generators.iter().all(|g| (g[0] - 30.0).abs() > 0.5 || (g[2] - 5.0).abs() > 2.0), "{by_position:?}");
    let facing = CvtOptions { normal_weight: 50.0, ..base };
    let t = constrained_cvt(&s, 2, &facing, None, None).unwrap();
    let (floor, wall) = if t.generators[0][2] < t.generators[1][2] { (0, 1) } else { (1, 0) };
    // Each region is one face: the generators at the faces' centroids, facing their normals.
    let (g, w) = (t.generators[floor], t.generators[wall]);
    assert!((g[0] - 15.0).abs() < 1.0 && (g[1] - 5.0).abs() < 1.0 && g[2] == 0.0, "{g:?}");
    assert!((w[0] - 30.0).abs() < 1e-9 && (w[1] - 5.0).abs() < 1.0 && (w[2] - 5.0).abs() < 1.0, "{w:?}");
    assert!(distance(t.normals[floor], [0.0, 0.0, 1.0]) < 1e-9 && distance(t.normals[wall], [-1.0, 0.0, 0.0]) < 1e-9, "{:?}", t.normals);
    // The same run on any number of threads, and refused weights.
    let bits = |t: &Tessellation| format!("{t:?}"); // drift holds NaN
    assert_eq!(bits(&constrained_cvt(&s, 2, &facing.with_threads(3), None, None).unwrap()), bits(&t));
    for bad in [-1.0, f64::NAN, f64::INFINITY, 1e300] {
        assert!(constrained_cvt(&s, 2, &CvtOptions { normal_weight: bad, ..base }, None, None).is_err(), "{bad}");
    }
}

#[test]
fn facing_runs_do_not_depend_on_threads_on_fine_meshes() {
    // A fine mesh takes the brute-force search (more than q / 4 triangles).
    let s = hills();
    let options = CvtOptions { samples_per_iteration: 500, max_iterations: 20, normal_weight: 8.0, ..CvtOptions::for_generators(6) };
    let one = constrained_cvt(&s, 6, &options.with_seed(2).with_threads(1), None, None).unwrap();
    let four = constrained_cvt(&s, 6, &options.with_seed(2).with_threads(4), None, None).unwrap();
    assert_eq!(format!("{one:?}"), format!("{four:?}")); // drift holds NaN
    assert!(one.normals.iter().all(|m| (distance(*m, [0.0; 3]) - 1.0).abs() < 1e-9 && m[2] > 0.0));
}
