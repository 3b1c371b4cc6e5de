"""Visibility against the brute-force reference and against geometry worked out by hand.

The reference (``reference.py``) is checked first on hand-made cases, then the engine's seen
mask, coverage and per-UAV counts are compared with it on random triangle soups and random grid
terrains. Pairs the reference flags as grazing (within 1e-6 of a triangle boundary) are the only
ones excluded.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import (
    GridCase,
    flat_grid_case,
    hills_grid_case,
    make_grid_case,
    random_grid_case,
    random_points_in_box,
    random_soup,
    uavs_above,
)
from reference import (
    SHORTEN,
    grid_height,
    grid_mesh,
    segments_hit_mesh,
    visibility_reference,
)
from uavcov import Targets, Terrain, Visibility

PROPERTY_SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])

# --------------------------------------------------------------------------------------------
# the reference itself, on cases whose answer is known by hand

_UNIT = (np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]), np.array([[0, 1, 2]]))


def test_reference_ray_through_interior_hits():
    hit, grazing = segments_hit_mesh([[0.2, 0.3, 1.0]], [[0.25, 0.2, -1.0]], *_UNIT)
    assert hit.tolist() == [True]
    assert grazing.tolist() == [False]


def test_reference_ray_beside_triangle_misses():
    hit, grazing = segments_hit_mesh([[0.8, 0.8, 1.0]], [[0.8, 0.8, -1.0]], *_UNIT)
    assert hit.tolist() == [False]
    assert grazing.tolist() == [False]


def test_reference_segment_stopping_short_misses():
    hit, grazing = segments_hit_mesh([[0.2, 0.2, 1.0]], [[0.2, 0.2, 0.01]], *_UNIT)
    assert hit.tolist() == [False]
    assert grazing.tolist() == [False]


def test_reference_segment_ending_on_triangle_is_grazing():
    hit, grazing = segments_hit_mesh([[0.2, 0.2, 1.0]], [[0.2, 0.2, 0.0]], *_UNIT)
    assert hit.tolist() == [True]
    assert grazing.tolist() == [True]


def test_reference_ray_through_edge_is_grazing():
    hit, grazing = segments_hit_mesh([[0.5, 0.0, 1.0], [0.5, -2e-6, 1.0]], [[0.5, 0.0, -1.0], [0.5, -2e-6, -1.0]], *_UNIT)
    assert grazing.tolist() == [True, False]
    assert hit[1] == False  # noqa: E712 - 2e-6 outside the edge is a clear miss


def test_reference_coplanar_segment_is_grazing():
    _, grazing = segments_hit_mesh([[-1.0, 0.2, 0.0]], [[2.0, 0.2, 0.0]], *_UNIT)
    assert grazing.tolist() == [True]


def test_reference_shortened_sight_line():
    # UAV at height 10 over a big horizontal triangle; a target at depth delta under it is seen
    # iff the shortened end 10 - 0.999 (10 + delta) stays above z = 0, i.e. delta < 10/0.999 - 10.
    vertices = np.array([[-50.0, -50.0, 0.0], [50.0, -50.0, 0.0], [0.0, 60.0, 0.0]])
    faces = np.array([[0, 1, 2]])
    limit = 10.0 / SHORTEN - 10.0
    depths = np.array([0.0, 0.5 * limit, 0.9 * limit, 1.1 * limit, 2.0])
    targets = np.column_stack([np.full(5, 1.0), np.full(5, 2.0), -depths])
    ref = visibility_reference(vertices, faces, [[1.0, 2.0, 10.0]], targets, 100.0)
    assert ref.visible[0].tolist() == [True, True, True, False, False]
    assert not ref.uncertain.any()


def test_reference_range_limit():
    vertices = np.array([[-50.0, -50.0, 0.0], [50.0, -50.0, 0.0], [0.0, 60.0, 0.0]])
    faces = np.array([[0, 1, 2]])
    targets = np.array([[3.0, 0.0, 0.0], [0.0, 4.1, 0.0], [3.0, 4.0, 0.0]])
    ref = visibility_reference(vertices, faces, [[0.0, 0.0, 0.01]], targets, 5.0)
    assert ref.visible[0, :2].tolist() == [True, True]
    # |p - q| = sqrt(25 + 1e-4) exceeds 5 by 1e-5, far more than the 5e-9 tolerance.
    assert ref.visible[0, 2] == False  # noqa: E712
    assert not ref.uncertain.any()


# --------------------------------------------------------------------------------------------
# helpers


def _check_against_reference(vis: Visibility, vertices, faces, uavs, targets: Targets, d_max: float) -> None:
    ref = visibility_reference(vertices, faces, uavs, targets.points, d_max)
    seen = vis.seen(uavs)
    assert seen.shape == (targets.points.shape[0],)
    assert seen.dtype == np.bool_
    decided = ~ref.seen_uncertain
    mismatch = np.nonzero((seen != ref.seen) & decided)[0]
    assert mismatch.size == 0, (
        f"{mismatch.size} targets disagree with the reference, e.g. target {targets.points[mismatch[0]]} "
        f"engine={seen[mismatch[0]]} reference={ref.seen[mismatch[0]]}"
    )
    # The test must be able to fail: make sure it compares something non-trivial, with targets
    # lost to occlusion (not only to range).
    assert 0 < ref.seen.sum() < ref.seen.size
    in_range = (np.linalg.norm(uavs[:, None, :] - targets.points[None, :, :], axis=2) <= d_max).any(axis=0)
    assert (in_range & ~ref.seen).sum() > 0

    w = targets.weights
    cov = vis.coverage(uavs)
    assert isinstance(cov, float)
    assert cov == pytest.approx(w[seen].sum() / w.sum(), rel=1e-12, abs=1e-15)
    slack = w[ref.seen_uncertain].sum() / w.sum()
    assert abs(cov - w[ref.seen].sum() / w.sum()) <= slack + 1e-12

    counts = vis.per_uav(uavs)
    n = uavs.shape[0]
    assert counts.seen.shape == (n,) and counts.exclusive.shape == (n,)
    per_pair_slack = ref.uncertain.sum(axis=1)
    assert np.all(np.abs(counts.seen - ref.per_uav_seen()) <= per_pair_slack)
    target_slack = ref.target_uncertain.sum()
    assert np.all(np.abs(counts.exclusive - ref.exclusive()) <= target_slack)
    # From a target chunk's second evaluation on, sight lines also go through the targets'
    # skylines (both methods): the answers stay the first evaluation's.
    assert np.array_equal(vis.seen(uavs), seen)
    # Consistency of the counts with the engine's own mask.
    assert counts.seen.max() <= seen.sum() and counts.exclusive.sum() <= seen.sum()


# --------------------------------------------------------------------------------------------
# agreement with the reference


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_seen_matches_reference_on_random_soup(seed):
    vertices, faces = random_soup(100 + seed, n_triangles=300)
    rng = np.random.default_rng(seed)
    uavs = random_points_in_box(rng, 5)
    points = random_points_in_box(rng, 500)
    weights = rng.uniform(0.1, 2.0, size=points.shape[0])
    targets = Targets.from_points(points, weights)
    terrain = Terrain(vertices, faces)
    vis = Visibility(terrain, 9.0, targets=targets)
    _check_against_reference(vis, vertices, faces, uavs, targets, 9.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_seen_matches_reference_on_random_grid(seed):
    case = random_grid_case(seed)
    terrain = Terrain.from_grid(case.z, case.spacing, origin=case.origin)
    targets = terrain.default_targets()
    rng = np.random.default_rng(10 + seed)
    uavs = uavs_above(case, 4, rng, low=0.5, high=4.0)
    vis = Visibility(terrain, 7.0, targets=targets)
    _check_against_reference(vis, case.vertices, case.faces, uavs, targets, 7.0)


def test_seen_matches_reference_on_hills_with_random_targets(hill_grid: GridCase, hill_terrain: Terrain):
    rng = np.random.default_rng(5)
    ox, oy = hill_grid.origin
    xmax, ymax = hill_grid.xy_max
    xy = rng.uniform([ox, oy], [xmax, ymax], size=(400, 2))
    # Targets on the surface and some a little above it (as in a partially known surface).
    z = grid_height(xy, hill_grid.z, hill_grid.spacing, hill_grid.origin) + rng.choice([0.0, 0.3], size=400)
    targets = Targets.from_points(np.column_stack([xy, z]))
    uavs = uavs_above(hill_grid, 6, rng, low=1.0, high=6.0)
    vis = Visibility(hill_terrain, 10.0, targets=targets)
    _check_against_reference(vis, hill_grid.vertices, hill_grid.faces, uavs, targets, 10.0)


def test_default_visibility_targets_are_terrain_default_targets(hill_grid: GridCase, hill_terrain: Terrain):
    rng = np.random.default_rng(6)
    uavs = uavs_above(hill_grid, 3, rng)
    explicit = Visibility(hill_terrain, 8.0, targets=hill_terrain.default_targets())
    implicit = Visibility(hill_terrain, 8.0)
    np.testing.assert_array_equal(explicit.seen(uavs), implicit.seen(uavs))
    assert explicit.coverage(uavs) == implicit.coverage(uavs)


# --------------------------------------------------------------------------------------------
# analytic cases


@pytest.mark.parametrize("step", [1.0, 0.5])
def test_flat_plane_sees_a_disk(step):
    # Plane z = 0 on [-30, 30]^2; a UAV at height h sees exactly the grid vertices within
    # horizontal radius r = sqrt(d_max^2 - h^2). Each interior vertex stands for a step x step
    # square centred on it, within delta = step / sqrt(2) of the vertex, so the union of the
    # squares of the seen vertices lies between the disks of radius r - delta and r + delta:
    # |covered area - pi r^2| <= pi (2 r delta + delta^2).
    case = flat_grid_case(30.0, step)
    terrain = Terrain.from_grid(case.z, step, origin=case.origin)
    h, d_max = 6.0, 20.0
    uav = np.array([[0.13, -0.21, h]])
    r = math.sqrt(d_max**2 - h**2)
    vis = Visibility(terrain, d_max)
    targets = terrain.default_targets()
    seen = vis.seen(uav)

    horizontal = np.hypot(targets.points[:, 0] - uav[0, 0], targets.points[:, 1] - uav[0, 1])
    np.testing.assert_array_equal(seen, horizontal <= r)

    covered_area = vis.coverage(uav) * terrain.area
    delta = step / math.sqrt(2.0)
    assert terrain.area == pytest.approx(3600.0, rel=1e-12)
    assert abs(covered_area - math.pi * r**2) <= math.pi * (2 * r * delta + delta**2)


def _wall_scene() -> tuple[np.ndarray, np.ndarray]:
    """Flat ground on [-10, 10]^2 and a wall in the plane x = 0, from z = -1 to 10, |y| <= 20."""
    ground_v, ground_f = grid_mesh(np.zeros((11, 11)), (2.0, 2.0), (-10.0, -10.0))
    wall_v = np.array([[0.0, -20.0, -1.0], [0.0, 20.0, -1.0], [0.0, 20.0, 10.0], [0.0, -20.0, 10.0]])
    vertices = np.vstack([ground_v, wall_v])
    k = ground_v.shape[0]
    faces = np.vstack([ground_f, [[k, k + 1, k + 2], [k, k + 2, k + 3]]])
    return vertices, faces


def test_wall_hides_everything_behind_it():
    vertices, faces = _wall_scene()
    terrain = Terrain(vertices, faces)
    rng = np.random.default_rng(11)
    behind = np.column_stack([rng.uniform(0.2, 9.8, 300), rng.uniform(-9.8, 9.8, 300), np.zeros(300)])
    front = np.column_stack([rng.uniform(-9.8, -0.2, 300), rng.uniform(-9.8, 9.8, 300), np.zeros(300)])
    targets = Targets.from_points(np.vstack([behind, front]))
    vis = Visibility(terrain, 100.0, targets=targets)
    uavs = np.array([[-5.0, 0.3, 3.0], [-1.0, -7.0, 9.0], [-9.0, 8.0, 0.5]])
    seen = vis.seen(uavs)
    assert not seen[:300].any()
    assert seen[300:].all()
    assert vis.coverage(uavs) == pytest.approx(0.5)
    # From (-0.5, 0, 12), 2 m over the wall top, the sight line to (x, y, 0) passes x = 0 at
    # height 12 x / (x + 0.5), which clears the top (z = 10) iff x >= 2.5.
    over = vis.seen([[-0.5, 0.0, 12.0]])[:300]
    x = behind[:, 0]
    decided = np.abs(x - 2.5) > 1e-3
    np.testing.assert_array_equal(over[decided], (x >= 2.5)[decided])
    assert 0 < over.sum() < 300


def test_uav_below_flat_surface_sees_nothing_on_far_side():
    case = flat_grid_case(10.0, 1.0)
    terrain = Terrain.from_grid(case.z, 1.0, origin=case.origin)
    rng = np.random.default_rng(12)
    xy = rng.uniform(-9.0, 9.0, size=(400, 2))
    above = np.column_stack([xy, rng.uniform(0.1, 3.0, 400)])
    below = np.column_stack([xy, -rng.uniform(0.1, 3.0, 400)])
    vis = Visibility(terrain, 50.0, targets=Targets.from_points(np.vstack([above, below])))
    seen = vis.seen([[0.3, -0.2, -5.0]])
    assert not seen[:400].any()
    assert seen[400:].all()  # nothing between a UAV and targets on its own side


def test_uav_below_terrain_sees_nothing_above_it(hill_grid: GridCase, hill_terrain: Terrain):
    # A segment from below the graph of a function to a point above it, with its projection in
    # the (convex) domain, must cross the graph.
    rng = np.random.default_rng(13)
    ox, oy = hill_grid.origin
    xmax, ymax = hill_grid.xy_max
    xy = rng.uniform([ox, oy], [xmax, ymax], size=(500, 2))
    above = np.column_stack([xy, grid_height(xy, hill_grid.z, hill_grid.spacing, hill_grid.origin) + 1.0])
    vis = Visibility(hill_terrain, 100.0, targets=Targets.from_points(above))
    uav_xy = np.array([[6.0, 7.0], [15.0, 10.0]])
    uavs = np.column_stack([uav_xy, grid_height(uav_xy, hill_grid.z, hill_grid.spacing, hill_grid.origin) - 2.0])
    assert not vis.seen(uavs).any()
    assert vis.coverage(uavs) == 0.0


def test_sight_lines_through_shared_edges_and_vertices_are_blocked():
    # A closed surface has no cracks: a sight line from below to above the plane z = 0 that
    # crosses it exactly on an edge or vertex shared by several triangles is still blocked.
    # Integer coordinates make these crossings exact in floating point. (The reference marks
    # them as grazing, so this is checked here by geometry rather than against it.)
    case = flat_grid_case(5.0, 1.0)  # nodes at integer x, y in [-5, 5]
    terrain = Terrain.from_grid(case.z, 1.0, origin=case.origin)
    uav = np.array([[0.0, 0.0, -4.0]])
    crossings = np.array(
        [
            [0.0, 0.0],  # straight up through a vertex
            [1.0, 1.0],  # through a vertex, obliquely
            [2.0, -1.0],
            [0.5, 0.5],  # through the middle of a cell diagonal
            [1.5, 2.5],
            [0.5, 0.0],  # through the middle of a horizontal edge
            [-2.0, 1.5],  # through the middle of a vertical edge
        ]
    )
    # Each target is the mirror image of the UAV through the crossing point: the segment from
    # the UAV to it, shortened by 0.1 %, still crosses z = 0 exactly at that point.
    targets = np.column_stack([2 * crossings - uav[0, :2], np.full(len(crossings), 4.0)])
    vis = Visibility(terrain, 100.0, targets=Targets.from_points(targets))
    assert not vis.seen(uav).any()
    assert not terrain.segments_clear(np.repeat(uav, len(targets), axis=0), targets).any()


# --------------------------------------------------------------------------------------------
# properties


def _uavs_from_unit(case: GridCase, unit: list[tuple[float, float, float]]) -> np.ndarray:
    ox, oy = case.origin
    xmax, ymax = case.xy_max
    u = np.asarray(unit, dtype=np.float64).reshape(-1, 3)
    inset = 0.001 + 0.998 * u[:, :2]  # keep off the border, where the height may round to NaN
    xy = np.column_stack([ox + inset[:, 0] * (xmax - ox), oy + inset[:, 1] * (ymax - oy)])
    return np.column_stack([xy, grid_height(xy, case.z, case.spacing, case.origin) + u[:, 2]])


_unit_uav = st.tuples(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.3, 12.0))


@PROPERTY_SETTINGS
@given(config=st.lists(_unit_uav, min_size=1, max_size=5), extra=_unit_uav)
def test_adding_a_uav_never_lowers_coverage(hill_grid, hill_terrain, config, extra):
    vis = Visibility(hill_terrain, 8.0)
    uavs = _uavs_from_unit(hill_grid, config)
    more = np.vstack([uavs, _uavs_from_unit(hill_grid, [extra])])
    seen, seen_more = vis.seen(uavs), vis.seen(more)
    assert np.all(seen_more >= seen)
    assert vis.coverage(more) >= vis.coverage(uavs) - 1e-12


@PROPERTY_SETTINGS
@given(
    config=st.lists(_unit_uav, min_size=1, max_size=4),
    d1=st.floats(0.5, 30.0),
    d2=st.floats(0.5, 30.0),
)
def test_coverage_never_decreases_with_d_max(hill_grid, hill_terrain, config, d1, d2):
    lo, hi = sorted((d1, d2))
    uavs = _uavs_from_unit(hill_grid, config)
    near, far = Visibility(hill_terrain, lo), Visibility(hill_terrain, hi)
    assert np.all(far.seen(uavs) >= near.seen(uavs))
    assert far.coverage(uavs) >= near.coverage(uavs) - 1e-12


@pytest.fixture(scope="module")
def fine_hills() -> tuple[GridCase, Terrain]:
    case = hills_grid_case(nx=60, ny=50, spacing=(0.31, 0.37), origin=(0.0, 0.0))
    return case, Terrain.from_grid(case.z, case.spacing, origin=case.origin)


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(config=st.lists(_unit_uav, min_size=1, max_size=6), d_max=st.floats(1.0, 25.0))
def test_results_identical_for_one_and_two_threads(fine_hills, config, d_max):
    case, terrain = fine_hills
    uavs = _uavs_from_unit(case, config)
    one = Visibility(terrain, d_max, n_threads=1)
    two = Visibility(terrain, d_max, n_threads=2)
    np.testing.assert_array_equal(one.seen(uavs), two.seen(uavs))
    assert one.coverage(uavs) == two.coverage(uavs)
    c1, c2 = one.per_uav(uavs), two.per_uav(uavs)
    np.testing.assert_array_equal(c1.seen, c2.seen)
    np.testing.assert_array_equal(c1.exclusive, c2.exclusive)


def test_coverage_function_equals_method(hill_grid, hill_terrain):
    from uavcov.engine import coverage

    uavs = uavs_above(hill_grid, 4, np.random.default_rng(9))
    expected = Visibility(hill_terrain, 9.0).coverage(uavs)
    assert coverage(hill_terrain, uavs, 9.0) == expected
    assert coverage(hill_terrain, uavs, 9.0, n_threads=1) == expected
    assert 0.0 < expected < 1.0


@pytest.mark.parametrize("method", ["grid", "mesh"])
@pytest.mark.parametrize("n_threads", [1, 2])
def test_per_uav_coverage_is_the_coverage_to_the_last_bit(hill_terrain, method, n_threads):
    rng = np.random.default_rng(7)
    vis = Visibility(hill_terrain, 12.0, method=method, n_threads=n_threads)
    lo, hi = hill_terrain.bounds
    values = []
    for _ in range(4):  # repeated configurations: the grid path's later calls use the skylines
        xy = rng.uniform(lo[:2], hi[:2], (5, 2))
        uavs = np.column_stack([xy, hill_terrain.ground_height(xy) + rng.uniform(1.0, 8.0, 5)])
        for _ in range(3):
            counts = vis.per_uav(uavs)
            assert counts.coverage == vis.coverage(uavs)
            values.append(counts.coverage)
    assert min(values) > 0.0 and max(values) < 1.0


def test_coverage_of_nothing_is_plain_zero(hill_terrain):
    # Nothing in range: 0.0, printed as "0.0" (not "-0.0").
    cov = Visibility(hill_terrain, 5.0).coverage([[1e6, 1e6, 0.0]])
    assert cov == 0.0 and math.copysign(1.0, cov) == 1.0


def test_repeated_calls_are_identical(hill_grid, hill_terrain):
    uavs = uavs_above(hill_grid, 5, np.random.default_rng(3))
    vis = Visibility(hill_terrain, 9.0)
    first = vis.seen(uavs)
    for _ in range(3):
        np.testing.assert_array_equal(vis.seen(uavs), first)


# --------------------------------------------------------------------------------------------
# per-UAV counts


def test_per_uav_counts_match_reference_exactly(hill_grid: GridCase, hill_terrain: Terrain):
    rng = np.random.default_rng(21)
    uavs = uavs_above(hill_grid, 5, rng, low=1.0, high=5.0)
    targets = hill_terrain.default_targets()
    vis = Visibility(hill_terrain, 9.0, targets=targets)
    ref = visibility_reference(hill_grid.vertices, hill_grid.faces, uavs, targets.points, 9.0)
    assert not ref.uncertain.any()  # this configuration has no grazing pair: exact comparison
    counts = vis.per_uav(uavs)
    assert counts.seen.dtype == np.int64 and counts.exclusive.dtype == np.int64
    np.testing.assert_array_equal(counts.seen, ref.per_uav_seen())
    np.testing.assert_array_equal(counts.exclusive, ref.exclusive())
    assert counts.exclusive.sum() > 0 and np.any(counts.exclusive < counts.seen)
    # The shares weigh the same targets by their weights.
    w = targets.weights
    only = ref.visible & (ref.visible.sum(axis=0) == 1)[None, :]
    np.testing.assert_allclose(counts.seen_share, (ref.visible * w).sum(axis=1) / w.sum(), rtol=1e-12)
    np.testing.assert_allclose(counts.exclusive_share, (only * w).sum(axis=1) / w.sum(), rtol=1e-12)


def test_per_uav_exclusive_of_identical_uavs_is_zero(hill_grid: GridCase, hill_terrain: Terrain):
    uav = uavs_above(hill_grid, 1, np.random.default_rng(22), low=3.0, high=4.0)
    vis = Visibility(hill_terrain, 9.0)
    counts = vis.per_uav(np.vstack([uav, uav]))
    assert counts.seen[0] == counts.seen[1] > 0
    np.testing.assert_array_equal(counts.exclusive, [0, 0])
    single = vis.per_uav(uav)
    assert single.exclusive[0] == single.seen[0] == vis.seen(uav).sum()


# --------------------------------------------------------------------------------------------
# user targets


def test_user_targets_without_weights_count_equally():
    case = flat_grid_case(10.0, 1.0)
    terrain = Terrain.from_grid(case.z, 1.0, origin=case.origin)
    points = np.array([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [8.0, 0.0, 0.0], [0.0, 9.0, 0.0]])
    targets = Targets.from_points(points)
    assert targets.points.shape == (4, 3)
    assert targets.weights.shape == (4,)
    assert np.all(targets.weights == targets.weights[0]) and targets.weights[0] > 0
    vis = Visibility(terrain, 5.0, targets=targets)
    uav = [[0.0, 0.0, 3.0]]  # within 5 m of the first two targets only
    np.testing.assert_array_equal(vis.seen(uav), [True, True, False, False])
    assert vis.coverage(uav) == pytest.approx(0.5)


def test_user_targets_with_weights_weight_the_coverage():
    case = flat_grid_case(10.0, 1.0)
    terrain = Terrain.from_grid(case.z, 1.0, origin=case.origin)
    points = np.array([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [8.0, 0.0, 0.0], [0.0, 9.0, 0.0]])
    weights = np.array([1.0, 2.0, 3.0, 4.0])
    targets = Targets.from_points(points, weights)
    np.testing.assert_array_equal(targets.weights, weights)
    np.testing.assert_array_equal(Targets(points, weights).weights, weights)
    vis = Visibility(terrain, 5.0, targets=targets)
    assert vis.coverage([[0.0, 0.0, 3.0]]) == pytest.approx(0.3)
    assert vis.coverage([[8.0, 0.0, 3.0]]) == pytest.approx(0.3)
    assert vis.coverage([[0.0, 0.0, 3.0], [8.0, 0.0, 3.0], [0.0, 9.0, 2.0]]) == pytest.approx(1.0)


def test_targets_pickle_and_are_frozen():
    import dataclasses
    import pickle

    targets = Targets.from_points(np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]), np.array([1.0, 2.0]))
    back = pickle.loads(pickle.dumps(targets))
    np.testing.assert_array_equal(back.points, targets.points)
    np.testing.assert_array_equal(back.weights, targets.weights)
    with pytest.raises(dataclasses.FrozenInstanceError):
        targets.points = np.zeros((1, 3))  # type: ignore[misc]


def test_per_uav_counts_pickle(hill_grid, hill_terrain):
    import pickle

    uavs = uavs_above(hill_grid, 2, np.random.default_rng(4))
    counts = Visibility(hill_terrain, 8.0).per_uav(uavs)
    back = pickle.loads(pickle.dumps(counts))
    np.testing.assert_array_equal(back.seen, counts.seen)
    np.testing.assert_array_equal(back.exclusive, counts.exclusive)


def test_engine_copies_inputs(hill_grid, hill_terrain):
    # Mutating the caller's arrays after the call must not change a stored result.
    uavs = uavs_above(hill_grid, 3, np.random.default_rng(8))
    vis = Visibility(hill_terrain, 9.0)
    seen = vis.seen(uavs)
    before = seen.copy()
    uavs[:] = 0.0
    np.testing.assert_array_equal(seen, before)
    points = hill_terrain.default_targets().points.copy()
    targets = Targets.from_points(points)
    vis_user = Visibility(hill_terrain, 9.0, targets=targets)
    first = vis_user.seen(uavs_above(hill_grid, 3, np.random.default_rng(8)))
    points[:] = 1e3
    np.testing.assert_array_equal(vis_user.seen(uavs_above(hill_grid, 3, np.random.default_rng(8))), first)


def test_make_grid_case_is_consistent():
    # Guard the fixture itself: the reference triangulation covers the grid's area exactly.
    case = make_grid_case(np.zeros((3, 4)), (2.0, 0.5), (1.0, 1.0))
    from reference import mesh_area

    assert case.faces.shape == (2 * 2 * 3, 3)
    assert mesh_area(case.vertices, case.faces) == pytest.approx(6.0 * 1.0)
