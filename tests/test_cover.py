"""Candidate viewpoints, the seen-matrix, lazy greedy and the certified bound (uavcov.cover)."""

from __future__ import annotations

import dataclasses
import math
import pickle
from typing import Any

import numpy as np
import pytest

import uavcov
from uavcov.cover import CoverageProblem, GreedySettings, Viewpoints, coverage_bound, greedy_placement, viewpoint_lattice
from uavcov.cover._viewpoints import viewpoint_offsets
from uavcov.errors import InfeasibleError, InvalidInputError, InvalidTypeError, SurfaceTooLargeError
from uavcov.experiments._sweep import settings_hash
from uavcov.limits import Constraints
from uavcov.paper import TABLE1, oracle
from uavcov.placement import StartSettings
from uavcov.placement._starts import greedy_start
from uavcov.structures import girder_bridge
from uavcov.terrain import buildings_scene


def _hills(size: float = 30.0, spacing: float = 1.0, seed: int = 3) -> uavcov.Terrain:
    return uavcov.gaussian_hills(size=size, spacing=spacing, n_hills=4, rng=seed)


_LIMITS = Constraints(h_min=1.0, h_max=8.0, z_max=60.0, d_safe=1.0)


def _scenes() -> list[tuple[str, uavcov.Visibility, Viewpoints]]:
    """Small scenes: hills on the grid path, the same on the mesh path, and a buildings mesh."""
    hills = _hills(spacing=2.0)
    lattice = viewpoint_lattice(hills, _LIMITS, GreedySettings(spacing=3.0, n_heights=3))
    town = buildings_scene(size=24.0, n_buildings=3, spacing=1.0, rng=2)
    town_lattice = viewpoint_lattice(town, Constraints(h_min=1.0, z_max=16.0, d_safe=1.0), GreedySettings(spacing=3.0, n_heights=3))
    return [
        ("hills-grid", uavcov.Visibility(hills, 9.0), lattice),
        ("hills-mesh", uavcov.Visibility(hills, 9.0, method="mesh"), lattice),
        ("buildings", uavcov.Visibility(town, 8.0), town_lattice),
    ]


def _dense(problem: CoverageProblem) -> np.ndarray:
    return np.array([problem.seen(c) for c in range(problem.viewpoints.n)])


def _plain_greedy(m: np.ndarray, w: np.ndarray, pos: np.ndarray, k: int, d_safe: float) -> tuple[list[int], list[float]]:
    """Plain greedy: every gain recomputed, the lowest index among equal gains, sums in target order."""
    covered = np.zeros(m.shape[1], dtype=bool)
    picks: list[int] = []
    gains: list[float] = []
    while len(picks) < k:
        best, best_gain = -1, -1.0
        for c in range(m.shape[0]):
            if c in picks or any(np.sum((pos[c] - pos[p]) ** 2) < d_safe**2 for p in picks):
                continue
            new = w[m[c] & ~covered]
            gain = float(np.cumsum(new)[-1]) if new.size else 0.0  # sequential, in target order
            if gain > best_gain:
                best, best_gain = c, gain
        if best < 0:
            break
        covered |= m[best]
        picks.append(best)
        gains.append(best_gain)
    return picks, gains


def _optimum(m: np.ndarray, w: np.ndarray, k: int) -> float:
    """The best weighted union of k columns, by brute force over every k-subset."""
    # targets with the same column pattern merge (their weights summed): the same optimum
    patterns, inverse = np.unique(m.T, axis=0, return_inverse=True)
    weights = np.bincount(inverse.ravel(), weights=w, minlength=patterns.shape[0])
    cols = patterns.T
    best = 0.0
    if k == 1:
        return float((cols @ weights).max())
    for a in range(cols.shape[0]):
        pair = cols[a][None, :] | cols[a + 1 :]
        if k == 2:
            if pair.size:
                best = max(best, float((pair @ weights).max()))
            continue
        for i, b in enumerate(range(a + 1, cols.shape[0])):
            rest = cols[b + 1 :]
            if rest.size:
                best = max(best, float(((pair[i][None, :] | rest) @ weights).max()))
    return best


@pytest.mark.parametrize("k", [1, 2, 3])
def test_the_bound_is_never_below_the_true_optimum(k: int) -> None:
    for name, vis, full in _scenes():
        # brute force over ~10^6 triples: every other candidate for k = 3
        lattice = Viewpoints(full.positions[::2].copy(), None, "given", "every other lattice point") if k == 3 else full
        problem = CoverageProblem(vis, lattice, n_threads=2)
        m, w = _dense(problem), vis.targets.weights
        assert 60 <= m.shape[0] <= 500, (name, m.shape)
        best = _optimum(m, w, k) / w.sum()
        result = problem.greedy(k)
        assert result.bound >= best - 1e-12, (name, k, result.bound, best)
        assert result.coverage <= best + 1e-12
        assert result.coverage >= (1 - 1 / math.e) * best
        assert result.bound <= result.ceiling <= 1.0
        assert np.isclose(result.ceiling, w[m.any(axis=0)].sum() / w.sum(), rtol=1e-12)
        # the bound of any placement, here a random one off the lattice, also holds
        rng = np.random.default_rng(k)
        other = lattice.positions[rng.choice(lattice.n, size=k, replace=False)] + rng.uniform(-0.3, 0.3, size=(k, 3))
        other[:, 2] += 0.5
        any_bound = problem.bound(other)
        assert any_bound.bound >= best - 1e-12 or any_bound.bound >= any_bound.ceiling - 1e-15
        assert any_bound.coverage == vis.coverage(other)


def test_greedy_equals_plain_greedy_on_the_same_matrix() -> None:
    for name, vis, lattice in _scenes():
        problem = CoverageProblem(vis, lattice, n_threads=1)
        m, w = _dense(problem), vis.targets.weights
        for k, d_safe in [(1, 0.0), (4, 0.0), (6, 6.0), (5, 11.0)]:
            result = problem.greedy(k, d_safe)
            picks, gains = _plain_greedy(m, w, lattice.positions, k, d_safe)
            assert result.picks.tolist() == picks, (name, k, d_safe)
            np.testing.assert_array_equal(result.gains, np.array(gains) / np.cumsum(w)[-1])  # sums in order, as Rust
            assert result.coverage == vis.coverage(result.positions)
            if d_safe > 0:
                d = np.linalg.norm(result.positions[:, None] - result.positions[None], axis=2)
                assert (d[~np.eye(len(picks), dtype=bool)] >= d_safe).all()


def test_columns_are_the_seen_masks_of_each_candidate_alone() -> None:
    rng = np.random.default_rng(0)
    for name, vis, lattice in _scenes():
        problem = CoverageProblem(vis, lattice)
        for c in rng.choice(lattice.n, size=12, replace=False):
            np.testing.assert_array_equal(problem.seen(int(c)), vis.seen(lattice.positions[c : c + 1]), err_msg=f"{name} {c}")
    # a camera looking down from every lattice point, in four headings
    hills = _hills()
    camera = uavcov.Camera(sensor_width_mm=13.2, sensor_height_mm=8.8, focal_length_mm=8.8, image_width_px=5472, image_height_px=3648)
    sensor = uavcov.Sensor(12.0, camera=camera)
    cams = viewpoint_lattice(hills, _LIMITS, GreedySettings(spacing=6.0, n_heights=2, pitches=(-90.0, -45.0)), cameras=True)
    assert cams.poses is not None and cams.n == 8 * len(np.unique(cams.positions, axis=0))
    vis = uavcov.Visibility(hills, 12.0)
    problem = CoverageProblem(vis, cams, sensor)
    for c in rng.choice(cams.n, size=12, replace=False):
        np.testing.assert_array_equal(problem.seen(int(c)), vis.seen(cams.poses[c : c + 1], sensors=[sensor]))
    result = problem.greedy(3, 1.0)
    assert result.poses is not None and result.coverage == vis.coverage(result.poses, sensors=[sensor] * 3)


def test_results_are_the_same_for_any_thread_count_and_pickle() -> None:
    hills = _hills()
    vis = uavcov.Visibility(hills, 10.0)
    lattice = viewpoint_lattice(hills, _LIMITS, GreedySettings(spacing=3.0))
    one = CoverageProblem(vis, lattice, n_threads=1)
    two = CoverageProblem(vis, lattice, n_threads=2)
    np.testing.assert_array_equal(_dense(one), _dense(two))
    a, b = one.greedy(5, 1.0), two.greedy(5, 1.0)
    assert (a.picks.tolist(), a.gains.tolist(), a.coverage, a.bound) == (b.picks.tolist(), b.gains.tolist(), b.coverage, b.bound)
    assert one.bound(a.positions + 0.2) == two.bound(a.positions + 0.2)
    again = pickle.loads(pickle.dumps(two))
    assert again.greedy(5, 1.0).picks.tolist() == a.picks.tolist()
    assert pickle.loads(pickle.dumps(a)).coverage == a.coverage
    # the one-shot functions give the same
    assert greedy_placement(vis, lattice, 5, d_safe=1.0, n_threads=2).picks.tolist() == a.picks.tolist()
    assert coverage_bound(vis, a.positions, lattice).bound == one.bound(a.positions).bound


def test_the_lattice_keeps_to_the_flight_band_and_refines_by_nesting() -> None:
    hills = _hills()
    coarse = viewpoint_lattice(hills, _LIMITS, GreedySettings(spacing=5.0, n_heights=3))
    fine = viewpoint_lattice(hills, _LIMITS, GreedySettings(spacing=2.5, n_heights=5))
    clearance = hills.clearance(fine.positions)
    assert (clearance >= 1.0).all() and (clearance <= 8.0).all() and (fine.positions[:, 2] <= 60.0).all()
    # halving the spacing and doubling the height intervals keeps every coarse candidate
    keys = {tuple(np.round(p, 9)) for p in fine.positions}
    assert all(tuple(np.round(p, 9)) in keys for p in coarse.positions)
    vis = uavcov.Visibility(hills, 9.0)
    assert CoverageProblem(vis, fine).ceiling() >= CoverageProblem(vis, coarse).ceiling()


def test_bad_input_is_a_clear_error() -> None:
    hills = _hills()
    vis = uavcov.Visibility(hills, 10.0)
    good = np.array([[5.0, 5.0, 20.0], [10.0, 10.0, 20.0]])
    for bad in ([[np.nan, 1.0, 2.0]], [[1e300, 1.0, 2.0]], np.zeros((3, 4)), np.zeros((0, 3)), "abc", [1.0, 2.0, 3.0]):
        with pytest.raises(InvalidInputError):
            CoverageProblem(vis, bad)
    with pytest.raises(InvalidTypeError):
        CoverageProblem(vis, [["a", "b", "c"]])
    with pytest.raises(InvalidTypeError):
        CoverageProblem("not a visibility", good)  # type: ignore[arg-type]
    with pytest.raises(InvalidTypeError):
        CoverageProblem(vis, good, sensor=3.0)  # type: ignore[arg-type]
    problem = CoverageProblem(vis, good)
    for k in (0, -1, 10**9):
        with pytest.raises(InvalidInputError):
            problem.greedy(k)
    for d_safe in (np.nan, -1.0, np.inf):
        with pytest.raises(InvalidInputError):
            problem.greedy(2, d_safe)
    with pytest.raises(InvalidInputError):
        problem.bound([[np.nan, 0.0, 1.0]])
    with pytest.raises(InvalidInputError):
        problem.seen(2)
    # a matrix over 1 GiB is refused before anything is allocated or computed
    big = uavcov.Visibility(_hills(size=100.0), 10.0)  # 10 201 targets: 1280 bytes a candidate
    many = np.tile([[50.0, 50.0, 30.0]], (900_000, 1))
    with pytest.raises(SurfaceTooLargeError):
        CoverageProblem(big, many)
    with pytest.raises(InvalidInputError):
        viewpoint_lattice(hills, _LIMITS, GreedySettings(spacing=0.01, n_heights=1000))
    for bad_settings in ({"spacing": 0.0}, {"spacing": np.nan}, {"n_heights": 0}, {"yaws": ()}, {"pitches": (np.nan,)}):
        with pytest.raises(InvalidInputError):
            GreedySettings(**bad_settings)
    with pytest.raises(InfeasibleError):
        viewpoint_lattice(hills, Constraints(h_min=1.0, h_max=2.0, z_max=1.5), GreedySettings())


def test_the_greedy_start_is_greedy_on_s_prime_and_records_its_time(tmp_path: Any) -> None:
    hills = _hills(size=40.0)
    limits = Constraints(h_min=1.0, h_max=6.0, z_max=60.0, d_safe=1.0)
    spec = uavcov.MissionSettings(
        n_uavs=4, d_max=12.0, iterations=10, constraints=limits, start=StartSettings(kind="greedy", greedy=GreedySettings(spacing=4.0))
    )
    result = uavcov.run_mission(hills, spec, rng=0, n_threads=1)
    # the start is greedy's placement on S' (candidates and coverage on S') among one layer of
    # viewpoints at the start's altitude, flown at that altitude above the true ground as every start is
    layer = dataclasses.replace(limits, h_min=5.0, h_max=None).resolve(result.approximation)
    on_s_prime = greedy_start(result.approximation, 4, 12.0, layer, GreedySettings(spacing=4.0, n_heights=1))
    np.testing.assert_array_equal(result.start_positions[:, :2], on_s_prime.positions[:, :2])
    np.testing.assert_allclose(result.start_positions[:, 2], hills.ground_height(on_s_prime.positions[:, :2]) + 5.0, rtol=0, atol=1e-12)
    assert result.cvt is None and 0.0 < result.start_time_s < result.wall_time_s
    assert on_s_prime.coverage <= on_s_prime.bound
    # saved and read back, with the start's settings and time
    path = uavcov.save_mission(result, tmp_path / "greedy.npz")
    again = uavcov.load_mission(path)
    assert again.settings.start.greedy == GreedySettings(spacing=4.0) and again.start_time_s == result.start_time_s
    # other starts are untouched by the new field: the settings hash of the paper's experiments is the same
    assert StartSettings().greedy == GreedySettings()
    assert settings_hash(TABLE1) == "e0746840"
    assert settings_hash(TABLE1.with_changes(**{"start.greedy": GreedySettings(spacing=2.5)})) != "e0746840"


def test_the_oracle_places_admissibly_on_the_true_surface() -> None:
    small = TABLE1.with_changes(**{"terrain.size": 40.0})
    rows = oracle(small, seeds=[0, 1], team_sizes=[2, 4], settings=GreedySettings(spacing=5.0), n_threads=2)
    assert [(r.seed, r.n_uavs) for r in rows] == [(0, 2), (0, 4), (1, 2), (1, 4)]
    for row in rows:
        assert 0.0 < row.coverage <= row.bound <= row.ceiling <= 1.0
        assert "the best" in row.holds_for
    # the same as greedy by hand on the true surface
    terrain = small.terrain.make(1)
    limits = small.mission.constraints.resolve(terrain)
    lattice = viewpoint_lattice(terrain, limits, GreedySettings(spacing=5.0))
    by_hand = greedy_placement(uavcov.Visibility(terrain, small.d_max), lattice, 4, d_safe=limits.d_safe)
    assert (by_hand.coverage, by_hand.bound) == (rows[3].coverage, rows[3].online_bound)
    problem = CoverageProblem(uavcov.Visibility(terrain, small.d_max), lattice)
    assert rows[3].dual_bound == problem.dual_bound(4).bound
    assert rows[3].bound == min(rows[3].online_bound, rows[3].dual_bound)
    # a process per scenario gives the same rows (all but the times)
    untimed = {"matrix_time_s": 0.0, "greedy_time_s": 0.0, "dual_time_s": 0.0}
    parallel = oracle(small, seeds=[0, 1], team_sizes=[2, 4], settings=GreedySettings(spacing=5.0), n_threads=1, workers=2)
    assert [dataclasses.replace(r, **untimed) for r in parallel] == [dataclasses.replace(r, **untimed) for r in rows]
    assert uavcov.limits._constraints.feasible_mask(limits, terrain, by_hand.positions, by_hand.positions[None])[0]


def test_normal_offsets_reach_under_a_bridge_deck_and_greedy_sees_its_underside() -> None:
    bridge = girder_bridge(rng=0)
    limits = Constraints(clearance="standoff", h_min=2.0, z_max=25.0, d_safe=1.0, check_moves=True)
    candidates = viewpoint_offsets(bridge.surface, limits, [3.0, 6.0], spacing=4.0, n_threads=2)
    assert candidates.source == "normal offsets" and candidates.n > 0
    # every candidate keeps the standoff: an independent distance (trimesh's point-triangle closest
    # point, each of 60 sampled candidates against every triangle)
    trimesh = pytest.importorskip("trimesh")
    sample = candidates.positions[:: max(1, candidates.n // 60)]
    triangles = bridge.surface.vertices[bridge.surface.faces]
    pairs_p = np.repeat(sample, len(triangles), axis=0)
    closest = trimesh.triangles.closest_point(np.tile(triangles, (len(sample), 1, 1)), pairs_p)
    distance = np.linalg.norm(closest - pairs_p, axis=1).reshape(len(sample), -1).min(axis=1)
    assert distance.min() >= 2.0 - 1e-9
    # some fly under the deck: a vertical ray up from them meets the structure
    up = bridge.surface.segments_clear(candidates.positions, candidates.positions + [0.0, 0.0, 30.0])
    assert (~up).any()
    targets = bridge.targets(spacing=1.0)
    vis = uavcov.Visibility(bridge.surface, 15.0, targets, n_threads=2)
    placed = greedy_placement(vis, candidates, 6, d_safe=1.0, n_threads=2)
    assert placed.coverage <= placed.bound <= 1.0
    seen = vis.seen(placed.positions)
    assert bridge.coverage_by_part(seen, targets)["deck_underside"] > 0.0


@pytest.mark.parametrize("distances", [[], [0.0], [-1.0], [math.nan], [1e300], "3"])
def test_normal_offsets_refuse_bad_distances(distances: Any) -> None:
    bridge = girder_bridge(rng=0)
    limits = Constraints(clearance="standoff", h_min=2.0, z_max=25.0)
    with pytest.raises((InvalidInputError, InfeasibleError)):
        viewpoint_offsets(bridge.surface, limits, distances, spacing=4.0)
