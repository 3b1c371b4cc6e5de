"""Terrain construction, default targets and surface queries against independent geometry.

Heights of grid terrains are checked against the piecewise-linear interpolant computed straight
from the grid (``reference.grid_height``); mesh queries against brute force over all triangles.
"""

from __future__ import annotations

import numpy as np
import pytest

from conftest import GridCase, flat_grid_case, hills, make_grid_case, random_soup
from reference import (
    closest_point_on_mesh,
    grid_height,
    ground_height_mesh,
    mesh_area,
    segments_hit_mesh,
    triangle_areas,
)
from uavcov import Terrain


def _triangle_set(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Triangles as rows of 9 coordinates, vertex order and face order normalised."""
    tri = np.asarray(vertices)[np.asarray(faces)]  # (F, 3, 3)
    keys = [np.lexsort(t.T[::-1]) for t in tri]
    tri = np.stack([t[k] for t, k in zip(tri, keys, strict=True)]).reshape(len(tri), 9)
    return tri[np.lexsort(tri.T[::-1])]


def _sorted_rows(a: np.ndarray) -> np.ndarray:
    return a[np.lexsort(a.T[::-1])]


# --------------------------------------------------------------------------------------------
# construction


def test_terrain_from_arrays_keeps_the_mesh():
    vertices, faces = random_soup(1, n_triangles=50)
    terrain = Terrain(vertices, faces)
    assert terrain.vertices.dtype == np.float64 and terrain.faces.dtype == np.int64
    np.testing.assert_array_equal(terrain.vertices, vertices)
    np.testing.assert_array_equal(terrain.faces, faces)
    assert terrain.n_faces == 50
    assert terrain.area == pytest.approx(mesh_area(vertices, faces), rel=1e-12)
    np.testing.assert_allclose(terrain.bounds, [vertices.min(axis=0), vertices.max(axis=0)])
    assert terrain.grid is None


def test_terrain_accepts_int32_faces_and_int_vertices():
    vertices = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 1]], dtype=np.int32)
    terrain = Terrain(vertices, np.array([[0, 1, 2]], dtype=np.int32))
    assert terrain.vertices.dtype == np.float64 and terrain.faces.dtype == np.int64
    assert terrain.area == pytest.approx(mesh_area(vertices.astype(float), np.array([[0, 1, 2]])))


def test_terrain_copies_its_input():
    vertices, faces = random_soup(2, n_triangles=20)
    terrain = Terrain(vertices, faces)
    area = terrain.area
    vertices *= 2.0
    faces[:] = 0
    assert terrain.area == pytest.approx(area)
    assert terrain.n_faces == 20 and np.any(terrain.faces != 0)


def test_from_grid_triangles_match_reference(hill_grid: GridCase, hill_terrain: Terrain):
    t = hill_terrain
    assert t.grid is not None
    assert t.n_faces == hill_grid.faces.shape[0] == 2 * 16 * 13
    np.testing.assert_allclose(_triangle_set(t.vertices, t.faces), _triangle_set(hill_grid.vertices, hill_grid.faces), atol=1e-12)
    assert t.area == pytest.approx(mesh_area(hill_grid.vertices, hill_grid.faces), rel=1e-12)
    v = hill_grid.vertices
    np.testing.assert_allclose(t.bounds, [v.min(axis=0), v.max(axis=0)], atol=1e-12)


def test_from_grid_scalar_spacing_equals_pair():
    z = hills(*np.meshgrid(np.arange(6.0), np.arange(5.0)))
    a = Terrain.from_grid(z, 0.7, origin=(1.0, 2.0))
    b = Terrain.from_grid(z, (0.7, 0.7), origin=(1.0, 2.0))
    np.testing.assert_allclose(_triangle_set(a.vertices, a.faces), _triangle_set(b.vertices, b.faces))
    xs = 1.0 + 0.7 * np.arange(6)
    assert a.bounds[0][0] == pytest.approx(1.0) and a.bounds[1][0] == pytest.approx(xs[-1])
    assert a.bounds[1][1] == pytest.approx(2.0 + 0.7 * 4)


def _nan_grid() -> GridCase:
    z = np.array(hills(*np.meshgrid(np.arange(9.0), np.arange(7.0))))
    z[3, 4] = np.nan  # an interior hole: its 6 incident triangles go
    z[0, 0] = np.nan  # a corner: its 2 incident triangles go (cell (0,0) has both touching it)
    z[6, 8] = np.nan  # the opposite corner: 2 triangles
    return make_grid_case(z, (1.0, 1.5), (0.0, 0.0))


def test_from_grid_nan_is_nodata():
    case = _nan_grid()
    terrain = Terrain.from_grid(case.z, case.spacing, origin=case.origin)
    full = 2 * 8 * 6
    assert case.faces.shape[0] == full - 6 - 2 - 2
    assert terrain.n_faces == case.faces.shape[0]
    assert np.isfinite(terrain.vertices[terrain.faces]).all()
    np.testing.assert_allclose(_triangle_set(terrain.vertices, terrain.faces), _triangle_set(case.vertices, case.faces), atol=1e-12)
    assert terrain.area == pytest.approx(mesh_area(case.vertices, case.faces), rel=1e-12)
    assert np.isfinite(terrain.bounds).all()
    targets = terrain.default_targets()
    np.testing.assert_allclose(_sorted_rows(targets.points), _sorted_rows(case.valid_vertices()), atol=1e-12)
    assert targets.weights.sum() == pytest.approx(terrain.area, rel=1e-9)
    # Inside the hole (the triangles around vertex (3, 4)) there is no ground.
    hole = np.array([[4.2, 3 * 1.5 + 0.3], [3.7, 3 * 1.5 - 0.4]])
    assert np.isnan(terrain.ground_height(hole)).all()
    assert np.isinf(terrain.clearance(np.column_stack([hole, [50.0, 50.0]]))).all()


def test_from_mesh_duck_typed():
    vertices, faces = random_soup(3, n_triangles=30)

    class Duck:
        def __init__(self) -> None:
            self.vertices = vertices
            self.faces = faces

    terrain = Terrain.from_mesh(Duck())
    np.testing.assert_array_equal(terrain.vertices, vertices)
    np.testing.assert_array_equal(terrain.faces, faces)
    assert terrain.area == pytest.approx(mesh_area(vertices, faces))


def test_from_mesh_trimesh():
    trimesh = pytest.importorskip("trimesh")
    mesh = trimesh.creation.icosphere(subdivisions=2, radius=3.0)
    terrain = Terrain.from_mesh(mesh)
    assert terrain.n_faces == len(mesh.faces)
    assert terrain.area == pytest.approx(float(mesh.area), rel=1e-12)
    np.testing.assert_allclose(terrain.vertices, np.asarray(mesh.vertices))
    # A point at the centre is 3 m (minus the chord sag) from the sphere.
    d = np.linalg.norm(terrain.closest_point([[0.0, 0.0, 0.0]])[0])
    assert 2.8 < d <= 3.0 + 1e-12


# --------------------------------------------------------------------------------------------
# default targets


def test_grid_default_targets_are_the_vertices(hill_grid: GridCase, hill_terrain: Terrain):
    targets = hill_terrain.default_targets()
    assert targets.points.shape == (hill_grid.z.size, 3)
    np.testing.assert_allclose(_sorted_rows(targets.points), _sorted_rows(hill_grid.vertices), atol=1e-12)
    assert targets.weights.shape == (hill_grid.z.size,)
    assert np.all(targets.weights > 0)
    assert targets.weights.sum() == pytest.approx(hill_terrain.area, rel=1e-9)
    # The surface is not flat: weights stand for surface area, more than the plan area.
    plan = (hill_grid.xy_max[0] - hill_grid.origin[0]) * (hill_grid.xy_max[1] - hill_grid.origin[1])
    assert targets.weights.sum() > plan * 1.01


def test_grid_node_weight_is_a_third_of_incident_triangles(hill_grid: GridCase, hill_terrain: Terrain):
    areas = triangle_areas(hill_grid.vertices, hill_grid.faces)
    expected = np.zeros(hill_grid.vertices.shape[0])
    for corner in range(3):
        np.add.at(expected, hill_grid.faces[:, corner], areas / 3.0)
    targets = hill_terrain.default_targets()
    # Match nodes by position (the engine may order them differently).
    got = targets.weights[np.lexsort(targets.points.T[::-1])]
    ref = expected[np.lexsort(hill_grid.vertices.T[::-1])]
    np.testing.assert_allclose(got, ref, rtol=1e-9)


def test_face_areas(hill_grid: GridCase):
    vertices, faces = random_soup(14, n_triangles=30)
    np.testing.assert_allclose(Terrain(vertices, faces).face_areas, triangle_areas(vertices, faces), rtol=1e-12)


def test_flat_grid_interior_vertices_stand_for_one_cell():
    case = flat_grid_case(3.0, 0.5)
    terrain = Terrain.from_grid(case.z, 0.5, origin=case.origin)
    targets = terrain.default_targets()
    interior = (np.abs(targets.points[:, 0]) < 2.9) & (np.abs(targets.points[:, 1]) < 2.9)
    np.testing.assert_allclose(targets.weights[interior], 0.25, rtol=1e-12)
    assert targets.weights.sum() == pytest.approx(36.0, rel=1e-12)


def _hills_as_mesh(hill_grid: GridCase) -> Terrain:
    return Terrain(hill_grid.vertices, hill_grid.faces)


def _subdivision_centroids(vertices: np.ndarray, faces: np.ndarray, density: float):
    """The documented rule, rebuilt here: each triangle cut into m^2 congruent pieces
    (m = ceil(sqrt(area * density))) by the lattice of its edges divided in m, a target at each
    piece's centroid weighing area / m^2. Returns (points (T, 3), weights (T,))."""
    points, weights = [], []
    for (a, b, c), area in zip(vertices[faces], triangle_areas(vertices, faces), strict=True):
        m = int(np.ceil(np.sqrt(area * density)))
        for i in range(m):
            for j in range(m - i):
                # upright piece with corners at lattice (i, j), (i+1, j), (i, j+1)
                u, v = (i + 1.0 / 3.0) / m, (j + 1.0 / 3.0) / m
                points.append(a + u * (b - a) + v * (c - a))
                if i + j <= m - 2:  # inverted piece (i+1, j), (i, j+1), (i+1, j+1)
                    u, v = (i + 2.0 / 3.0) / m, (j + 2.0 / 3.0) / m
                    points.append(a + u * (b - a) + v * (c - a))
        weights.extend([area / m**2] * (m * m))
    return np.array(points), np.array(weights)


@pytest.mark.parametrize("density", [0.5, 4.0])
def test_mesh_default_targets_lie_on_surface_and_weigh_its_area(hill_grid: GridCase, density):
    terrain = _hills_as_mesh(hill_grid)
    targets = terrain.default_targets(density)
    n = targets.points.shape[0]
    assert targets.weights.shape == (n,)
    assert np.all(targets.weights > 0)
    assert targets.weights.sum() == pytest.approx(terrain.area, rel=1e-9)
    d, _ = closest_point_on_mesh(targets.points, hill_grid.vertices, hill_grid.faces)
    assert d.max() < 1e-9
    assert n >= density * terrain.area


@pytest.mark.parametrize("density", [0.5, 3.0])
def test_mesh_default_targets_follow_the_documented_subdivision(density):
    vertices, faces = random_soup(12, n_triangles=40)
    targets = Terrain(vertices, faces).default_targets(density)
    points, weights = _subdivision_centroids(vertices, faces, density)
    assert targets.points.shape == points.shape
    order_got = np.lexsort(targets.points.T[::-1])
    order_ref = np.lexsort(points.T[::-1])
    np.testing.assert_allclose(targets.points[order_got], points[order_ref], atol=1e-9)
    np.testing.assert_allclose(targets.weights[order_got], weights[order_ref], rtol=1e-9)


def test_mesh_default_density_is_one_per_square_metre():
    vertices, faces = random_soup(13, n_triangles=40)
    terrain = Terrain(vertices, faces)
    points, _ = _subdivision_centroids(vertices, faces, 1.0)
    assert terrain.default_targets().points.shape == points.shape


def test_grid_with_density_is_subdivided_not_nodes(hill_grid: GridCase, hill_terrain: Terrain):
    targets = hill_terrain.default_targets(5.0)
    points, _ = _subdivision_centroids(hill_grid.vertices, hill_grid.faces, 5.0)
    assert targets.points.shape == points.shape
    assert targets.weights.sum() == pytest.approx(hill_terrain.area, rel=1e-9)


def test_mesh_default_targets_are_area_weighted_per_region(hill_grid: GridCase):
    # The weights of the targets in any union of triangles equal its area: split the surface
    # by the plane x = xm through cell boundaries, so no triangle straddles it.
    terrain = _hills_as_mesh(hill_grid)
    targets = terrain.default_targets(4.0)
    xm = hill_grid.origin[0] + 8 * hill_grid.spacing[0]
    centroid_x = hill_grid.vertices[hill_grid.faces][:, :, 0].mean(axis=1)
    left_area = triangle_areas(hill_grid.vertices, hill_grid.faces)[centroid_x < xm].sum()
    left_weight = targets.weights[targets.points[:, 0] < xm].sum()
    assert left_weight == pytest.approx(left_area, rel=1e-9)


def test_mesh_default_targets_are_deterministic(hill_grid: GridCase):
    terrain = _hills_as_mesh(hill_grid)
    a, b = terrain.default_targets(2.0), terrain.default_targets(2.0)
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.weights, b.weights)
    assert terrain.default_targets(8.0).points.shape[0] > a.points.shape[0]


def test_mesh_default_targets_on_soup():
    vertices, faces = random_soup(4, n_triangles=200)
    terrain = Terrain(vertices, faces)
    targets = terrain.default_targets(3.0)
    assert targets.weights.sum() == pytest.approx(mesh_area(vertices, faces), rel=1e-9)
    d, _ = closest_point_on_mesh(targets.points, vertices, faces)
    assert d.max() < 1e-9


# --------------------------------------------------------------------------------------------
# ground height, clearance


def test_ground_height_matches_grid_interpolant(hill_grid: GridCase, hill_terrain: Terrain):
    rng = np.random.default_rng(0)
    ox, oy = hill_grid.origin
    xmax, ymax = hill_grid.xy_max
    xy = rng.uniform([ox, oy], [xmax, ymax], size=(2000, 2))
    got = hill_terrain.ground_height(xy)
    assert got.shape == (2000,)
    np.testing.assert_allclose(got, grid_height(xy, hill_grid.z, hill_grid.spacing, hill_grid.origin), atol=1e-9)
    # The interpolant is not the analytic function between vertices: a check that fails if
    # the engine interpolated the wrong diagonal.
    i, j = 5, 7
    x0 = ox + j * hill_grid.spacing[0]
    y0 = oy + i * hill_grid.spacing[1]
    fx, fy = 0.7, 0.2  # below the diagonal: triangle (i,j), (i,j+1), (i+1,j+1)
    p = [[x0 + fx * hill_grid.spacing[0], y0 + fy * hill_grid.spacing[1]]]
    z = hill_grid.z
    expected = z[i, j] + fx * (z[i, j + 1] - z[i, j]) + fy * (z[i + 1, j + 1] - z[i, j + 1])
    assert hill_terrain.ground_height(p)[0] == pytest.approx(expected, abs=1e-9)
    other = z[i, j] + fy * (z[i + 1, j] - z[i, j]) + fx * (z[i + 1, j + 1] - z[i + 1, j])
    assert abs(expected - other) > 1e-3  # the two diagonals really differ here


def test_ground_height_at_vertices_is_the_grid_value(hill_grid: GridCase, hill_terrain: Terrain):
    got = hill_terrain.ground_height(hill_grid.vertices[:, :2])
    np.testing.assert_allclose(got, hill_grid.vertices[:, 2], atol=1e-9)


def test_ground_height_outside_is_nan(hill_terrain: Terrain, hill_grid: GridCase):
    ox, oy = hill_grid.origin
    xmax, ymax = hill_grid.xy_max
    outside = np.array([[ox - 0.1, oy + 1.0], [xmax + 0.1, oy + 1.0], [ox + 1.0, ymax + 5.0], [-1e6, 1e6]])
    assert np.isnan(hill_terrain.ground_height(outside)).all()
    points = np.column_stack([outside, np.full(4, 100.0)])
    assert np.isposinf(hill_terrain.clearance(points)).all()


def test_clearance_is_height_above_ground(hill_grid: GridCase, hill_terrain: Terrain):
    rng = np.random.default_rng(1)
    ox, oy = hill_grid.origin
    xmax, ymax = hill_grid.xy_max
    xy = rng.uniform([ox, oy], [xmax, ymax], size=(500, 2))
    ground = grid_height(xy, hill_grid.z, hill_grid.spacing, hill_grid.origin)
    above = rng.uniform(0.0, 20.0, 500)
    got = hill_terrain.clearance(np.column_stack([xy, ground + above]))
    assert got.shape == (500,)
    np.testing.assert_allclose(got, above, atol=1e-9)


def test_clearance_under_the_surface_is_inf(hill_grid: GridCase, hill_terrain: Terrain):
    # Documented: inf where nothing lies below, including points under a single-layer surface.
    rng = np.random.default_rng(7)
    ox, oy = hill_grid.origin
    xmax, ymax = hill_grid.xy_max
    xy = rng.uniform([ox, oy], [xmax, ymax], size=(50, 2))
    ground = grid_height(xy, hill_grid.z, hill_grid.spacing, hill_grid.origin)
    assert np.isposinf(hill_terrain.clearance(np.column_stack([xy, ground - 0.5]))).all()


def test_ground_height_accepts_points_and_ignores_z(hill_grid: GridCase, hill_terrain: Terrain):
    rng = np.random.default_rng(8)
    ox, oy = hill_grid.origin
    xmax, ymax = hill_grid.xy_max
    xy = rng.uniform([ox, oy], [xmax, ymax], size=(50, 2))
    points = np.column_stack([xy, rng.uniform(-100.0, 100.0, 50)])
    np.testing.assert_array_equal(hill_terrain.ground_height(points), hill_terrain.ground_height(xy))


def test_ground_height_on_soup_is_highest_surface():
    vertices, faces = random_soup(5, n_triangles=200)
    terrain = Terrain(vertices, faces)
    rng = np.random.default_rng(2)
    xy = rng.uniform(-2.0, 22.0, size=(1000, 2))
    expected = ground_height_mesh(xy, vertices, faces)
    got = terrain.ground_height(xy)
    assert np.isnan(expected).any() and np.isfinite(expected).any()
    np.testing.assert_array_equal(np.isnan(got), np.isnan(expected))
    ok = np.isfinite(expected)
    np.testing.assert_allclose(got[ok], expected[ok], atol=1e-9)


def test_clearance_on_soup_is_first_surface_straight_down():
    vertices, faces = random_soup(6, n_triangles=200)
    terrain = Terrain(vertices, faces)
    rng = np.random.default_rng(3)
    points = np.column_stack([rng.uniform(0.0, 20.0, size=(1000, 2)), rng.uniform(-2.0, 12.0, 1000)])
    below = ground_height_mesh(points[:, :2], vertices, faces, below=points[:, 2])
    expected = np.where(np.isnan(below), np.inf, points[:, 2] - below)
    got = terrain.clearance(points)
    assert np.isinf(expected).any() and np.isfinite(expected).any()
    np.testing.assert_array_equal(np.isinf(got), np.isinf(expected))
    ok = np.isfinite(expected)
    np.testing.assert_allclose(got[ok], expected[ok], atol=1e-9)


# --------------------------------------------------------------------------------------------
# closest point, segments


@pytest.mark.parametrize("which", ["soup", "hills"])
def test_closest_point_matches_brute_force(which, hill_grid: GridCase):
    if which == "soup":
        vertices, faces = random_soup(8, n_triangles=200)
    else:
        vertices, faces = hill_grid.vertices, hill_grid.faces
    terrain = Terrain(vertices, faces)
    rng = np.random.default_rng(4)
    lo, hi = vertices.min(axis=0) - 3.0, vertices.max(axis=0) + 3.0
    points = rng.uniform(lo, hi, size=(300, 3))
    got = terrain.closest_point(points)
    assert got.shape == (300, 3)
    expected_d, _ = closest_point_on_mesh(points, vertices, faces)
    np.testing.assert_allclose(np.linalg.norm(points - got, axis=1), expected_d, atol=1e-9)
    on_surface, _ = closest_point_on_mesh(got, vertices, faces)
    assert on_surface.max() < 1e-9


def test_closest_point_of_surface_points_is_themselves(hill_grid: GridCase, hill_terrain: Terrain):
    targets = hill_terrain.default_targets()
    np.testing.assert_allclose(hill_terrain.closest_point(targets.points), targets.points, atol=1e-9)


def test_segments_clear_matches_reference():
    vertices, faces = random_soup(9, n_triangles=300)
    terrain = Terrain(vertices, faces)
    rng = np.random.default_rng(5)
    a = rng.uniform([0, 0, 0], [20, 20, 10], size=(1500, 3))
    b = a + rng.normal(scale=4.0, size=(1500, 3))
    got = terrain.segments_clear(a, b)
    assert got.shape == (1500,) and got.dtype == np.bool_
    hit, grazing = segments_hit_mesh(a, b, vertices, faces)
    assert 0 < hit.sum() < 1500
    decided = ~grazing
    np.testing.assert_array_equal(got[decided], ~hit[decided])


def test_segments_clear_hand_cases():
    vertices = np.array([[-5.0, -5.0, 0.0], [5.0, -5.0, 0.0], [0.0, 5.0, 0.0]])
    terrain = Terrain(vertices, np.array([[0, 1, 2]]))
    a = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [20.0, 0.0, 1.0]])
    b = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, 0.5], [1.0, 1.0, -3.0], [20.0, 0.0, -1.0]])
    np.testing.assert_array_equal(terrain.segments_clear(a, b), [False, True, False, True])


def test_queries_on_grid_and_same_mesh_agree(hill_grid: GridCase, hill_terrain: Terrain):
    # A later fast path for grids must give what the general mesh gives.
    mesh = Terrain(hill_grid.vertices, hill_grid.faces)
    rng = np.random.default_rng(6)
    ox, oy = hill_grid.origin
    xmax, ymax = hill_grid.xy_max
    points = np.column_stack([rng.uniform([ox, oy], [xmax, ymax], size=(300, 2)), rng.uniform(0, 15, 300)])
    np.testing.assert_allclose(hill_terrain.clearance(points), mesh.clearance(points), atol=1e-9)
    np.testing.assert_allclose(hill_terrain.ground_height(points[:, :2]), mesh.ground_height(points[:, :2]), atol=1e-9)
