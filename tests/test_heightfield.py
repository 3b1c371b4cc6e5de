"""The elevation-grid path gives the mesh path's answer, target by target.

A grid terrain answers every query through its height field (``method="grid"``, the default for
grids); ``method="mesh"`` builds the grid's triangle mesh and parry's BVH instead, and
``Terrain(t.vertices, t.faces)`` is the same triangles as a general mesh. The grid path claims
the very same answer for every segment (it tests the same triangles with the same function and
only skips what it proves clear), so the checks below ask for exact equality, not a tolerance,
on the terrains where a shortcut would most likely slip: the paper's Gaussian hills, rugged
terrain of many small steep hills, terraces (flat plateaus and cliffs), nodata holes, and sight
lines that pass exactly over grid nodes, along grid lines and along cell diagonals.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from uavcov import Targets, Terrain, Visibility, gaussian_hills
from uavcov.errors import InvalidInputError, InvalidTypeError, SurfaceTooLargeError

PROPERTY_SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


# --------------------------------------------------------------------------------------------
# terrains


def rugged_grid(n: int = 61, spacing: float = 0.5, seed: int = 0) -> np.ndarray:
    """Many small steep hills: 60 narrow bumps 1-4 m high, sigma 0.6-1.5 m, plus noise."""
    rng = np.random.default_rng(seed)
    x = np.arange(n) * spacing
    xx, yy = np.meshgrid(x, x)
    z = rng.uniform(0.0, 0.3, size=(n, n))
    for _ in range(60):
        cx, cy = rng.uniform(0.0, x[-1], 2)
        h, s = rng.uniform(1.0, 4.0), rng.uniform(0.6, 1.5)
        z += h * np.exp(-((xx - cx) ** 2 + (yy - cy) ** 2) / (2 * s**2))
    return z


def terraces(n: int = 41, seed: int = 1) -> np.ndarray:
    """Flat plateaus at whole metres joined by one-cell cliffs, heights exactly representable."""
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, 1.0, n)
    xx, yy = np.meshgrid(x, x)
    smooth = 4.0 * np.sin(5.0 * xx + rng.uniform(0, 3)) * np.cos(4.0 * yy + rng.uniform(0, 3)) + 3.0 * xx
    return np.round(smooth)


def with_holes(z: np.ndarray, share: float, seed: int) -> np.ndarray:
    out = z.copy()
    out[np.random.default_rng(seed).random(z.shape) < share] = np.nan
    return out


def node_xyz(terrain: Terrain) -> np.ndarray:
    """Every node of a grid terrain, NaN heights included, as (ny * nx, 3)."""
    g = terrain.grid
    xs, ys = g.node_xy()
    xx, yy = np.meshgrid(xs, ys)
    return np.column_stack([xx.ravel(), yy.ravel(), g.z.ravel()])


def awkward_uavs(terrain: Terrain, n: int, rng: np.random.Generator) -> np.ndarray:
    """UAVs exactly above grid nodes, on grid lines and on cell diagonals, and anywhere."""
    g = terrain.grid
    (dx, dy), (ox, oy) = g.spacing, g.origin
    ny, nx = g.shape
    i = rng.integers(0, ny - 1, n)
    j = rng.integers(0, nx - 1, n)
    u = rng.random(n)
    kind = rng.integers(0, 4, n)
    x = ox + j * dx + np.where(kind == 1, u * dx, 0.0) + np.where(kind == 2, u * dx, 0.0)
    y = oy + i * dy + np.where(kind == 2, u * dy, 0.0)
    free = kind == 3
    x[free] = rng.uniform(ox, ox + (nx - 1) * dx, free.sum())
    y[free] = rng.uniform(oy, oy + (ny - 1) * dy, free.sum())
    ground = terrain.ground_height(np.column_stack([x, y]))
    ground = np.where(np.isnan(ground), np.nanmax(g.z), ground)
    # Heights above ground in whole or half metres, so sight lines often pass exactly through
    # nodes of the terraces and graze their edges.
    return np.column_stack([x, y, ground + rng.integers(1, 12, n) * 0.5])


def assert_paths_agree(terrain: Terrain, uavs: np.ndarray, d_max: float, targets: Targets | None = None) -> np.ndarray:
    """Seen masks, coverage and per-UAV counts of the grid and mesh paths are identical.

    Every grid-path query is repeated: grid-node targets get their skylines on a chunk's second
    evaluation, so the first answers come from the walk alone and the later ones through the
    skylines.
    """
    grid = Visibility(terrain, d_max, targets, method="grid")
    mesh = Visibility(terrain, d_max, targets, method="mesh")
    auto = Visibility(terrain, d_max, targets)
    assert (grid._core.path, mesh._core.path, auto._core.path) == ("grid", "mesh", "grid")
    seen = mesh.seen(uavs)
    coverage = mesh.coverage(uavs)
    b = mesh.per_uav(uavs)
    for _ in range(2):
        np.testing.assert_array_equal(grid.seen(uavs), seen)
        np.testing.assert_array_equal(auto.seen(uavs), seen)
        assert grid.coverage(uavs) == coverage
        a = grid.per_uav(uavs)
        assert a.coverage == b.coverage == coverage
        np.testing.assert_array_equal(a.seen, b.seen)
        np.testing.assert_array_equal(a.exclusive, b.exclusive)
        np.testing.assert_allclose(a.seen_share, b.seen_share, rtol=1e-12, atol=0)
        np.testing.assert_allclose(a.exclusive_share, b.exclusive_share, rtol=1e-12, atol=0)
    return seen


def assert_mixed(seen: np.ndarray) -> None:
    """Some targets seen and some not, so agreement says something."""
    assert 0 < seen.sum() < seen.size


# --------------------------------------------------------------------------------------------
# identical masks on the terrains of the issue


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_paper_terrains(seed):
    terrain = gaussian_hills(spacing=1.0, rng=seed)
    rng = np.random.default_rng(seed)
    xy = rng.uniform(0.0, 100.0, (12, 2))
    uavs = np.column_stack([xy, terrain.ground_height(xy) + rng.uniform(5.0, 30.0, 12)])
    assert_mixed(assert_paths_agree(terrain, uavs, 25.0))


def test_paper_terrain_at_half_a_metre_with_awkward_uavs():
    terrain = gaussian_hills(size=40.0, spacing=0.5, rng=5)
    uavs = awkward_uavs(terrain, 10, np.random.default_rng(5))
    assert_mixed(assert_paths_agree(terrain, uavs, 15.0))


def test_rugged_terrain():
    terrain = Terrain.from_grid(rugged_grid(), 0.5)
    uavs = awkward_uavs(terrain, 12, np.random.default_rng(1))
    assert_mixed(assert_paths_agree(terrain, uavs, 12.0))


def test_plateaus_and_cliffs():
    terrain = Terrain.from_grid(terraces(), 1.0, origin=(-3.0, 7.0))
    uavs = awkward_uavs(terrain, 14, np.random.default_rng(2))
    assert_mixed(assert_paths_agree(terrain, uavs, 18.0))


def test_nodata_holes():
    terrain = Terrain.from_grid(with_holes(rugged_grid(41, 1.0, seed=3), 0.06, 3), 1.0)
    uavs = awkward_uavs(terrain, 10, np.random.default_rng(3))
    assert_mixed(assert_paths_agree(terrain, uavs, 15.0))


def test_sight_lines_exactly_over_nodes_along_grid_lines_and_diagonals():
    # Targets at nodes and at points of grid lines and cell diagonals (on the surface), UAVs
    # exactly above nodes: every sight line runs along a grid line, a diagonal, or through nodes.
    terrain = Terrain.from_grid(terraces(21, seed=4), 1.0)
    nodes = node_xyz(terrain)
    ny, nx = terrain.grid.shape
    along = []
    for i in range(0, ny - 1, 3):
        for j in range(0, nx - 1, 3):
            a, b, c = nodes[i * nx + j], nodes[i * nx + j + 1], nodes[(i + 1) * nx + j + 1]
            along += [0.5 * (a + b), 0.5 * (a + c), 0.25 * a + 0.75 * c]
    targets = Targets(np.vstack([nodes, np.array(along)]))
    pick = np.random.default_rng(4).choice(ny * nx, 8, replace=False)
    uavs = nodes[pick] + np.array([0.0, 0.0, 1.5])
    seen = assert_paths_agree(terrain, uavs, 14.0, targets)
    assert_mixed(seen)
    # Single UAVs too: with several, an edge case of one can hide behind another's success.
    for k in range(len(uavs)):
        assert_paths_agree(terrain, uavs[k : k + 1], 14.0, targets)


def test_one_and_two_threads_give_the_same_answer():
    terrain = Terrain.from_grid(rugged_grid(81, 0.5, seed=6), 0.5)
    uavs = awkward_uavs(terrain, 12, np.random.default_rng(6))
    one = Visibility(terrain, 15.0, n_threads=1)
    two = Visibility(terrain, 15.0, n_threads=2)
    np.testing.assert_array_equal(one.seen(uavs), two.seen(uavs))
    assert one.coverage(uavs) == two.coverage(uavs)
    a, b = one.per_uav(uavs), two.per_uav(uavs)
    for field in ("seen", "exclusive", "seen_share", "exclusive_share"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field))


# --------------------------------------------------------------------------------------------
# property tests over random grids and UAVs


@st.composite
def grids(draw):
    ny = draw(st.integers(2, 18))
    nx = draw(st.integers(2, 18))
    dx = draw(st.sampled_from([0.5, 1.0, 1.3]))
    dy = draw(st.sampled_from([0.5, 1.0, 0.7]))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    kind = draw(st.sampled_from(["lattice", "float", "spikes"]))
    if kind == "lattice":  # whole metres: coplanar cells, exact ties with node heights
        z = rng.integers(0, 4, size=(ny, nx)).astype(float)
    elif kind == "float":
        z = rng.uniform(0.0, 5.0, size=(ny, nx))
    else:
        z = np.where(rng.random((ny, nx)) < 0.15, 6.0, 0.0)
    if draw(st.booleans()):
        z = with_holes(z, 0.1, seed)
    origin = (draw(st.sampled_from([0.0, -7.25, 1e3])), draw(st.sampled_from([0.0, 3.5])))
    return z, (dx, dy), origin, seed


@PROPERTY_SETTINGS
@given(grids(), st.integers(1, 6), st.floats(2.0, 30.0))
def test_random_grids_and_uavs(case, n_uavs, d_max):
    z, spacing, origin, seed = case
    if not np.isfinite(z).any() or _no_triangle(z):
        return
    terrain = Terrain.from_grid(z, spacing, origin=origin)
    uavs = awkward_uavs(terrain, n_uavs, np.random.default_rng(seed))
    assert_paths_agree(terrain, uavs, d_max)


@PROPERTY_SETTINGS
@given(grids(), st.integers(0, 2**32 - 1))
def test_random_segments_and_vertical_queries_match_the_same_mesh(case, seed):
    z, spacing, origin, _ = case
    if not np.isfinite(z).any() or _no_triangle(z):
        return
    grid = Terrain.from_grid(z, spacing, origin=origin)
    mesh = Terrain(grid.vertices, grid.faces)
    rng = np.random.default_rng(seed)
    nodes = grid.vertices
    # Segment ends at vertices, above vertices, and anywhere in (and a bit beyond) the box.
    lo, hi = grid.bounds
    anywhere = rng.uniform(lo - 1.0, hi + 3.0, size=(60, 3))
    at_nodes = nodes[rng.integers(0, len(nodes), 60)]
    above = at_nodes + np.column_stack([np.zeros((60, 2)), rng.integers(0, 4, 60) * 0.5])
    ends = np.vstack([anywhere, at_nodes, above])
    a = ends[rng.permutation(len(ends))]
    b = ends[rng.permutation(len(ends))]
    np.testing.assert_array_equal(grid.segments_clear(a, b), mesh.segments_clear(a, b))
    np.testing.assert_allclose(grid.ground_height(a[:, :2]), mesh.ground_height(a[:, :2]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(grid.clearance(anywhere), mesh.clearance(anywhere), rtol=0, atol=1e-12)
    # Closest points: the same distance (the point itself may differ between equally near ones).
    distance = lambda t: np.linalg.norm(t.closest_point(anywhere) - anywhere, axis=1)  # noqa: E731
    np.testing.assert_allclose(distance(grid), distance(mesh), rtol=0, atol=1e-9)


def _no_triangle(z: np.ndarray) -> bool:
    ok = np.isfinite(z)
    upper = ok[:-1, :-1] & ok[:-1, 1:] & ok[1:, 1:]
    lower = ok[:-1, :-1] & ok[1:, 1:] & ok[1:, :-1]
    return not (upper.any() or lower.any())


# --------------------------------------------------------------------------------------------
# the grid path's own API


def test_default_grid_targets_equal_the_terrain_default_targets():
    terrain = Terrain.from_grid(with_holes(rugged_grid(31, 1.0, seed=7), 0.05, 7), 1.0)
    uavs = awkward_uavs(terrain, 5, np.random.default_rng(7))
    implicit = Visibility(terrain, 10.0)
    explicit = Visibility(terrain, 10.0, terrain.default_targets())
    np.testing.assert_array_equal(implicit.seen(uavs), explicit.seen(uavs))
    assert implicit.coverage(uavs) == explicit.coverage(uavs)
    np.testing.assert_array_equal(implicit.per_uav(uavs).seen, explicit.per_uav(uavs).seen)
    np.testing.assert_array_equal(implicit.targets.points, explicit.targets.points)
    np.testing.assert_array_equal(implicit.targets.weights, explicit.targets.weights)
    assert implicit._core.n_targets == len(explicit.targets)


def test_grid_terrain_tables_equal_the_mesh_ones():
    z = with_holes(rugged_grid(23, 0.5, seed=8), 0.1, 8)
    grid = Terrain.from_grid(z, (0.5, 0.75), origin=(2.0, -1.0))
    mesh = Terrain(grid.vertices, grid.faces)
    assert (grid.n_vertices, grid.n_faces) == (mesh.n_vertices, mesh.n_faces)
    assert grid.area == mesh.area
    np.testing.assert_array_equal(grid.face_areas, mesh.face_areas)
    np.testing.assert_array_equal(grid.bounds, mesh.bounds)
    ours = grid.default_targets()
    np.testing.assert_array_equal(ours.points, mesh.vertices)
    # The weight of a node is a third of the triangles around it, summed in face order.
    expected = np.zeros(mesh.n_vertices)
    for face, area in zip(mesh.faces, mesh.face_areas, strict=True):
        for k in face:
            expected[k] += area / 3.0
    np.testing.assert_array_equal(ours.weights, expected)


def test_method_is_checked_and_survives_pickling():
    grid = gaussian_hills(size=20.0, spacing=1.0, rng=0)
    mesh = Terrain(grid.vertices, grid.faces)
    with pytest.raises(InvalidInputError, match="method"):
        Visibility(grid, 5.0, method="bvh")
    with pytest.raises(InvalidTypeError):
        Visibility(grid, 5.0, method=None)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="grid"):
        Visibility(mesh, 5.0, method="grid")
    assert Visibility(mesh, 5.0)._core.path == "mesh"
    vis = Visibility(grid, 8.0, method="mesh")
    back = pickle.loads(pickle.dumps(vis))
    assert back._core.path == "mesh"
    uavs = [[10.0, 10.0, 30.0], [3.0, 15.0, 12.0]]
    np.testing.assert_array_equal(back.seen(uavs), vis.seen(uavs))
    implicit = pickle.loads(pickle.dumps(Visibility(grid, 8.0)))
    np.testing.assert_array_equal(implicit.seen(uavs), vis.seen(uavs))


def test_the_mesh_path_refuses_a_grid_too_large_for_it():
    # 2300 x 2300 nodes: 10.6 million triangles, over the mesh path's limit; the grid path copes.
    terrain = Terrain.from_grid(np.zeros((2300, 2300)), 1.0)
    targets = Targets([[100.0, 100.0, 0.0], [2000.0, 2000.0, 0.0]])
    with pytest.raises(SurfaceTooLargeError, match="limit"):
        Visibility(terrain, 10.0, targets, method="mesh")
    vis = Visibility(terrain, 10.0, targets)
    np.testing.assert_array_equal(vis.seen([[103.0, 100.0, 4.0]]), [True, False])
