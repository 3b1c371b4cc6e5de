use std::sync::Arc;

use super::*;
use crate::surface::mesh::Surface;
use crate::visibility::{Path, Targets};

/// A bumpy 30 m x 30 m grid at 1 m.
fn rugged(n: usize) -> Arc<Surface> {
    let z: Vec<f64> = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64, (k / n) as f64);
            3.0 * (0.4 * x).sin() * (0.3 * y).cos() + 0.1 * ((k * 7919) % 11) as f64
        })
        .collect();
    Arc::new(Surface::from_grid(z, n, n, 1.0, 1.0, 0.0, 0.0).unwrap())
}

fn lattice(n: usize, step: f64, z: f64) -> Vec<Point> {
    (0..n * n).map(|k| [1.0 + step * (k % n) as f64, 1.0 + step * (k / n) as f64, z + (k % 3) as f64]).collect()
}

/// Plain greedy over dense columns: every gain recomputed at every step, the lowest index
/// among equal gains, sums in target order.
fn plain_greedy(cols: &[Vec<bool>], w: &[f64], pos: &[Point], k: usize, d_safe: f64) -> (Vec<usize>, Vec<f64>) {
    let mut covered = vec![false; w.len()];
    let (mut picks, mut gains) = (Vec::new(), Vec::new());
    while picks.len() < k {
        let mut best: Option<(usize, f64)> = None;
        for (c, col) in cols.iter().enumerate() {
            let far =
                picks.iter().all(|&p: &usize| p != c && (0..3).map(|i| (pos[c][i] - pos[p][i]).powi(2)).sum::<f64>() >= d_safe * d_safe);
            if !far {
                continue;
            }
            let g = (0..w.len()).filter(|&t| col[t] && !covered[t]).fold(0.0, |a, t| a + w[t]);
            if best.is_none_or(|(_, b)| g > b) {
                best = Some((c, g));
            }
        }
        let Some((c, g)) = best else { break };
        for t in 0..w.len() {
            covered[t] |= cols[c][t];
        }
        picks.push(c);
        gains.push(g);
    }
    (picks, gains)
}

fn union_weight(cols: &[Vec<bool>], w: &[f64], set: &[usize]) -> f64 {
    (0..w.len()).filter(|&t| set.iter().any(|&c| cols[c][t])).fold(0.0, |a, t| a + w[t])
}

#[test]
fn columns_are_the_seen_masks_of_each_candidate_alone_on_both_paths() {
    let s = rugged(30);
    let cands = lattice(6, 5.0, 5.0);
    for path in [Path::Grid, Path::Mesh] {
        let vis = Visibility::with_path(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 9.0, path).unwrap();
        let m = SeenMatrix::build(&vis, &cands, None, 2).unwrap();
        assert_eq!(m.n_candidates(), cands.len());
        for (c, &p) in cands.iter().enumerate() {
            assert_eq!(m.column(c).unwrap(), vis.seen(&[p], 1).unwrap(), "{path:?} candidate {c}");
        }
        assert_eq!(m.bits, SeenMatrix::build(&vis, &cands, None, 1).unwrap().bits);
    }
    // grid-node targets (their skylines fill as the columns are built) and sensors
    let vis = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 9.0).unwrap();
    let sensors: Vec<Sensor> = (0..cands.len()).map(|c| Sensor::new(0.5 * (c % 3) as f64, 6.0 + (c % 4) as f64, None).unwrap()).collect();
    let m = SeenMatrix::build(&vis, &cands, Some(&sensors), 2).unwrap();
    for (c, &p) in cands.iter().enumerate() {
        assert_eq!(m.column(c).unwrap(), vis.seen_by(&[p], Some(&sensors[c..=c]), 1).unwrap(), "sensor candidate {c}");
    }
    assert_eq!(m.bits, SeenMatrix::build(&vis, &cands, Some(&sensors), 1).unwrap().bits);
}

#[test]
fn lazy_greedy_is_plain_greedy_and_the_bound_is_above_the_optimum() {
    let s = rugged(30);
    let vis = Visibility::new(s.clone(), Targets::of_surface(&s, 1.0).unwrap(), 7.0).unwrap();
    let cands = lattice(7, 4.0, 3.0);
    let m = SeenMatrix::build(&vis, &cands, None, 2).unwrap();
    let cols: Vec<Vec<bool>> = (0..m.n_candidates()).map(|c| m.column(c).unwrap()).collect();
    let w = vis.targets().weights().to_vec();
    let total = m.total_weight();
    for (k, d_safe) in [(1, 0.0), (2, 0.0), (3, 0.0), (3, 9.0), (5, 4.5)] {
        let g = greedy(&m, &cands, k, d_safe, 2).unwrap();
        let (picks, gains) = plain_greedy(&cols, &w, &cands, k, d_safe);
        assert_eq!(g.picks, picks, "k {k} d_safe {d_safe}");
        assert_eq!(g.gains, gains.iter().map(|x| x / total).collect::<Vec<_>>());
        assert_eq!(g.coverage, vis.coverage(&g.picks.iter().map(|&c| cands[c]).collect::<Vec<_>>(), 1).unwrap());
        assert_eq!(g, greedy(&m, &cands, k, d_safe, 1).unwrap());
        if k <= 3 {
            // brute force over every k-subset (without the separation: the bound holds for both)
            let n = cands.len();
            let mut best = 0.0_f64;
            for a in 0..n {
                for b in (a + 1)..n.max(a + 1) {
                    for c in (b + 1)..n {
                        let set: Vec<usize> = [a, b, c][..k].to_vec();
                        best = best.max(union_weight(&cols, &w, &set));
                        if k < 3 {
                            break;
                        }
                    }
                    if k < 2 {
                        break;
                    }
                }
            }
            assert!(g.bound >= best / total - 1e-15, "k {k}: bound {} below the optimum {}", g.bound, best / total);
            assert!(g.coverage <= best / total + 1e-15 && g.coverage >= (1.0 - 1.0 / std::f64::consts::E) * best / total);
        }
        assert!(g.bound <= m.ceiling() && g.coverage <= g.bound, "{} {} {}", g.bound, m.ceiling(), g.coverage);
    }
}

#[test]
fn the_bound_of_any_placement_holds_and_reads_its_own_seen_set() {
    let s = rugged(30);
    let vis = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 7.0).unwrap();
    let cands = lattice(5, 6.0, 4.0);
    let m = SeenMatrix::build(&vis, &cands, None, 2).unwrap();
    let team = [[7.3, 11.1, 5.5], [20.2, 4.4, 6.0]];
    let seen = vis.seen(&team, 1).unwrap();
    let b = bound(&m, &seen, 2, 2).unwrap();
    assert_eq!(b.coverage, vis.coverage(&team, 1).unwrap());
    let g = greedy(&m, &cands, 2, 0.0, 1).unwrap();
    assert!(b.bound >= g.coverage && b.bound <= m.ceiling());
    assert_eq!(b, bound(&m, &seen, 2, 1).unwrap());
}

#[test]
fn bad_input_and_huge_sizes_are_errors() {
    let s = rugged(10);
    let vis = Visibility::new(s.clone(), Targets::grid_nodes(s.clone()).unwrap(), 7.0).unwrap();
    assert!(SeenMatrix::build(&vis, &[], None, 1).is_err());
    assert!(SeenMatrix::build(&vis, &[[f64::NAN, 0.0, 1.0]], None, 1).is_err());
    assert!(SeenMatrix::build(&vis, &[[1e300, 0.0, 1.0]], None, 1).is_err());
    assert!(SeenMatrix::build(&vis, &[[1.0, 0.0, 1.0]], Some(&[]), 1).is_err());
    assert!(matches!(check_size(usize::MAX / 2, 3), Err(Error::TooLarge(_))));
    assert!(matches!(check_size(1 << 20, 1 << 10), Err(Error::TooLarge(_))));
    let m = SeenMatrix::build(&vis, &[[1.0, 1.0, 5.0]], None, 1).unwrap();
    assert!(greedy(&m, &[[1.0, 1.0, 5.0]], 0, 0.0, 1).is_err());
    assert!(greedy(&m, &[], 1, 0.0, 1).is_err());
    assert!(greedy(&m, &[[1.0, 1.0, 5.0]], 1, f64::NAN, 1).is_err());
    assert!(bound(&m, &[true], 1, 1).is_err());
    assert!(m.column(1).is_err());
    assert!(SeenMatrix::from_columns(&[vec![true]], vec![1.0, 2.0]).is_err());
    assert!(SeenMatrix::from_columns(&[vec![true]], vec![0.0]).is_err());
    // k beyond the candidates: every candidate, then stop
    assert_eq!(greedy(&m, &[[1.0, 1.0, 5.0]], 4, 0.0, 1).unwrap().picks, vec![0]);
}
