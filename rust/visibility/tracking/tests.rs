use super::*;
use crate::surface::mesh::Surface;
use crate::visibility::{Path, Targets};

/// A deterministic stream in [0, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Hills, a ridge and 20 cm of noise on a `n x n` grid of 1 m cells: sight lines of every kind.
fn hills(n: usize, nodata: bool) -> Arc<Surface> {
    let mut rng = Lcg(7);
    let z: Vec<f64> = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64, (k / n) as f64);
            let h = 6.0 * (x / 7.0).sin() * (y / 9.0).cos() + if (x - 20.0).abs() < 1.5 { 5.0 } else { 0.0 } + 0.2 * rng.next();
            if nodata && k == n + 3 {
                f64::NAN
            } else {
                h
            }
        })
        .collect();
    Arc::new(Surface::from_grid(z, n, n, 1.0, 1.0, 0.0, 0.0).unwrap())
}

fn objective(surface: &Arc<Surface>, path: Path) -> Arc<Visibility> {
    let targets = Targets::grid_nodes(surface.clone()).unwrap();
    Arc::new(Visibility::with_path(surface.clone(), targets, 25.0, path).unwrap())
}

/// A team's random walk: steps shrinking from 2 m to 2 cm, some UAVs grazing the surface,
/// one diving under it and one leaving the grid for a while.
fn walk(surface: &Surface, n_uavs: usize, steps: usize, seed: u64) -> Vec<Vec<Point>> {
    let mut rng = Lcg(seed);
    let side = surface.bounds().1[0];
    let mut team: Vec<Point> = (0..n_uavs).map(|_| [side * (0.1 + 0.8 * rng.next()), side * (0.1 + 0.8 * rng.next()), 0.0]).collect();
    let mut out = Vec::new();
    for step in 0..steps {
        let size = 2.0 / (1.0 + step as f64 / 3.0);
        for (u, p) in team.iter_mut().enumerate() {
            p[0] = (p[0] + size * (rng.next() - 0.5)).clamp(0.0, side);
            p[1] = (p[1] + size * (rng.next() - 0.5)).clamp(0.0, side);
            let ground = surface.ground_height(p[0], p[1]).unwrap();
            let height = match u {
                0 => 0.05 + 0.1 * rng.next(),
                1 => -0.5,
                _ => 1.0 + 6.0 * (u as f64 / n_uavs as f64),
            };
            p[2] = ground + height;
        }
        let mut at = team.clone();
        if (20..40).contains(&step) {
            at[n_uavs - 1][0] = -3.0;
        }
        out.push(at);
    }
    out
}

#[test]
fn a_walking_team_is_seen_as_the_exact_test_sees_it() {
    let surface = hills(61, false);
    let vis = objective(&surface, Path::Auto);
    // The smallest margin is below the rounding allowance here: no certificate, same answers.
    for margin in [Margin::Fixed(0.005), Margin::Fixed(0.5), Margin::Fixed(1.0), Margin::Fixed(4.0), Margin::Adaptive] {
        let mut tracker = CoverageTracker::new(vis.clone(), margin).unwrap();
        assert!(tracker.certifies());
        let mut settled = 0;
        for team in walk(&surface, 6, 120, 3) {
            assert_eq!(tracker.seen(&team, 2).unwrap(), vis.seen(&team, 1).unwrap(), "margin {margin:?}");
            assert_eq!(tracker.coverage(&team, 1).unwrap().to_bits(), vis.coverage(&team, 1).unwrap().to_bits());
            settled += tracker.settled();
        }
        // Certificates settle most targets once the steps are small.
        if margin == Margin::Fixed(0.005) {
            assert_eq!(settled, 0);
        } else {
            assert!(settled > 120 * 61 * 61 / 10, "margin {margin:?}: {settled} settled");
        }
    }
}

#[test]
fn answers_do_not_depend_on_threads_or_on_what_came_before() {
    let surface = hills(61, false);
    let vis = objective(&surface, Path::Auto);
    let (mut one, mut three) =
        (CoverageTracker::new(vis.clone(), Margin::Adaptive).unwrap(), CoverageTracker::new(vis.clone(), Margin::Adaptive).unwrap());
    let path = walk(&surface, 4, 60, 11);
    for team in &path {
        assert_eq!(one.seen(team, 1).unwrap(), three.seen(team, 3).unwrap());
        assert_eq!(one.settled(), three.settled());
    }
    // Another team size starts afresh; jumping back along the path changes nothing.
    let pair = &path[5][..2];
    assert_eq!(one.seen(pair, 1).unwrap(), vis.seen(pair, 1).unwrap());
    assert_eq!(one.settled(), 0);
    for team in path.iter().rev().step_by(7) {
        assert_eq!(one.seen(team, 1).unwrap(), vis.seen(team, 1).unwrap());
    }
}

#[test]
fn targets_at_the_edge_of_range_are_measured_as_the_uav_circles() {
    // A flat grid seen from 2 m: every target in range is seen, so only the range decides,
    // and as the UAV circles within its margin targets cross the edge of its 10 m range.
    let surface = Arc::new(Surface::from_grid(vec![0.0; 61 * 61], 61, 61, 1.0, 1.0, 0.0, 0.0).unwrap());
    let given: Vec<Point> = (0..900).map(|k| [20.0 + f64::from(k % 30) * 0.7, 20.0 + f64::from(k / 30) * 0.7, 0.0]).collect();
    for targets in [Targets::grid_nodes(surface.clone()).unwrap(), Targets::new(given, None).unwrap()] {
        let vis = Arc::new(Visibility::with_path(surface.clone(), targets, 10.0, Path::Auto).unwrap());
        let mut tracker = CoverageTracker::new(vis.clone(), Margin::Fixed(1.0)).unwrap();
        // Still for four measurements, then a jump past the margin: certificates are made there.
        let mut path = vec![[30.0, 30.0, 2.0]; 4];
        path.extend((0..40).map(|k| {
            let angle = f64::from(k) * 0.3;
            [31.5 + 0.9 * angle.cos(), 30.0 + 0.9 * angle.sin(), 2.0]
        }));
        for p in &path {
            assert_eq!(tracker.seen(&[*p], 1).unwrap(), vis.seen(&[*p], 1).unwrap());
        }
        assert!(tracker.settled() > 0);
        let deep = tracker.certificates.iter().filter(|c| c.seer != NO_SEER && c.seer & DEEP != 0).count();
        let shallow = tracker.certificates.iter().filter(|c| c.seer != NO_SEER && c.seer & DEEP == 0).count();
        assert!(deep > 0 && shallow > 0, "deep {deep}, shallow {shallow}");
    }
}

#[test]
fn what_an_anchor_showed_is_forgotten_when_it_moves() {
    // Flat ground with a wall 3 m high along x = 30: from x = 27 at 2 m the ground past the
    // wall is hidden, from x = 40 every target in range is in plain view.
    let z: Vec<f64> = (0..61 * 61).map(|k| if k % 61 == 30 { 3.0 } else { 0.0 }).collect();
    let surface = Arc::new(Surface::from_grid(z, 61, 61, 1.0, 1.0, 0.0, 0.0).unwrap());
    let targets = Targets::grid_nodes(surface.clone()).unwrap();
    let vis = Arc::new(Visibility::with_path(surface, targets, 10.0, Path::Auto).unwrap());
    let mut tracker = CoverageTracker::new(vis.clone(), Margin::Fixed(1.0)).unwrap();
    // Certificates are made where an anchor moves after holding: behind the wall, then past it.
    let path: Vec<Point> = [[20.0, 30.0, 2.0], [27.0, 30.0, 2.0], [40.0, 30.0, 2.0]].iter().flat_map(|p| [*p; 5]).collect();
    let mut seen = 0;
    for (k, p) in path.iter().enumerate() {
        let mask = tracker.seen(&[*p], 1).unwrap();
        assert_eq!(mask, vis.seen(&[*p], 1).unwrap());
        seen = mask.iter().filter(|s| **s).count();
        if k == 9 {
            // Behind the wall the lowered anchor misses the targets past it.
            assert!(tracker.certificates.iter().any(|c| c.lowered_misses != 0));
        }
    }
    // Past the wall it sees them: every target seen is settled by a certificate.
    assert!(seen > 200);
    assert_eq!(tracker.settled(), seen);
}

#[test]
fn an_adaptive_margin_follows_the_steps_of_its_uav() {
    // Hills seen from 6 m: a UAV that bobs 1.5 m up and down at every evaluation leaves a
    // fixed 1 m margin each time (no anchor ever holds), while its adaptive margin grows to
    // the steps it takes and its anchors hold.
    let surface = hills(61, false);
    let vis = objective(&surface, Path::Auto);
    let ground = surface.ground_height(30.0, 30.0).unwrap();
    let path: Vec<Point> = (0..30).map(|k| [30.0, 30.0, ground + if k % 2 == 0 { 6.0 } else { 7.5 }]).collect();
    let mut settled = Vec::new();
    for margin in [Margin::Fixed(1.0), Margin::Adaptive] {
        let mut tracker = CoverageTracker::new(vis.clone(), margin).unwrap();
        let mut total = 0;
        for p in &path {
            assert_eq!(tracker.seen(&[*p], 1).unwrap(), vis.seen(&[*p], 1).unwrap(), "{margin:?}");
            total += tracker.settled();
        }
        settled.push(total);
    }
    assert_eq!(settled[0], 0);
    assert!(settled[1] > 0);
    // Under a low UAV the margin stays within its share of the height above the surface.
    let mut tracker = CoverageTracker::new(vis.clone(), Margin::Adaptive).unwrap();
    for p in &path {
        let low = [p[0], p[1], p[2] - 5.0];
        assert_eq!(tracker.seen(&[low], 1).unwrap(), vis.seen(&[low], 1).unwrap());
        let anchor = &tracker.anchors[0];
        assert!(anchor.margin <= HEIGHT_SHARE * (anchor.at[2] - ground) + 1e-12, "{}", anchor.margin);
    }
}

#[test]
fn without_certificates_it_is_the_plain_objective() {
    let with_nodata = hills(41, true);
    let plain = hills(41, false);
    for vis in [objective(&with_nodata, Path::Auto), objective(&plain, Path::Mesh)] {
        let mut tracker = CoverageTracker::new(vis.clone(), Margin::Fixed(1.0)).unwrap();
        assert!(!tracker.certifies());
        for team in walk(&plain, 3, 10, 5) {
            let team: Vec<Point> = team.into_iter().map(|p| [p[0], p[1], p[2] + 1.0]).collect();
            assert_eq!(tracker.seen(&team, 1).unwrap(), vis.seen(&team, 1).unwrap());
            assert_eq!(tracker.settled(), 0);
        }
    }
}

#[test]
fn bad_input_is_an_error() {
    let vis = objective(&hills(21, false), Path::Auto);
    for margin in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(CoverageTracker::new(vis.clone(), Margin::Fixed(margin)).is_err());
    }
    let mut tracker = CoverageTracker::new(vis, Margin::Adaptive).unwrap();
    assert!(tracker.seen(&[], 1).is_err());
    assert!(tracker.seen(&[[1.0, f64::NAN, 3.0]], 1).is_err());
    assert!(tracker.seen(&[[1.0, 2.0, 1e300]], 1).is_err());
    assert!(tracker.seen(&[[1.0, 2.0, 30.0]], 1).is_ok());
}
