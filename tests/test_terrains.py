"""Scenario generators and loaders (uavcov.terrain) against analytic and independent references."""

from __future__ import annotations

import math
import pickle
import sys

import numpy as np
import pytest

from reference import grid_height
from uavcov import GeoDem, Terrain, gaussian_hills, read_dem, sample_dem
from uavcov.errors import InfeasibleError, InvalidInputError, InvalidTypeError, MeshError
from uavcov.terrain import LocalFrame, buildings_scene, dem_from_array, metres_per_degree
from uavcov.terrain._buildings import Building, buildings_terrain, perturb_buildings, random_buildings
from uavcov.terrain._hills import GaussianMixture, random_gaussian_mixture
from uavcov.terrain._meshes import clean_mesh, load_mesh, mesh_terrain

# --------------------------------------------------------------------------------------------
# Gaussian hills


def mixture_by_hand(x: np.ndarray, y: np.ndarray, centres: np.ndarray, heights: np.ndarray, sigma: float) -> np.ndarray:
    z = np.zeros_like(x, dtype=float)
    for k in range(len(heights)):
        r2 = (x - centres[k, 0]) ** 2 + (y - centres[k, 1]) ** 2
        z += heights[k] * np.exp(-r2 / (2.0 * sigma * sigma))
    return z


def test_gaussian_hills_defaults_match_the_paper_setup():
    mixture = random_gaussian_mixture(rng=0)
    assert mixture.centres.shape == (7, 2)
    assert mixture.sigma == 10.0
    assert ((mixture.heights >= 5.0) & (mixture.heights <= 25.0)).all()
    assert ((mixture.centres >= 0.0) & (mixture.centres <= 100.0)).all()
    terrain = gaussian_hills(rng=0)
    assert terrain.grid is not None
    assert terrain.grid.shape == (101, 101)
    assert terrain.grid.spacing == (1.0, 1.0)
    np.testing.assert_allclose(terrain.bounds[:, :2], [[0.0, 0.0], [100.0, 100.0]])


def test_gaussian_hills_grid_is_the_analytic_mixture():
    mixture = random_gaussian_mixture(size=40.0, n_hills=4, heights=(2.0, 9.0), sigma=6.0, rng=11)
    terrain = gaussian_hills(size=40.0, spacing=2.0, n_hills=4, heights=(2.0, 9.0), sigma=6.0, rng=11)
    coords = np.arange(21) * 2.0
    x, y = np.meshgrid(coords, coords)
    expected = mixture_by_hand(x, y, mixture.centres, mixture.heights, 6.0)
    np.testing.assert_allclose(terrain.grid.z, expected, rtol=1e-12, atol=1e-12)
    xy = np.random.default_rng(1).uniform(0, 40, size=(50, 2))
    np.testing.assert_allclose(mixture.height(xy), mixture_by_hand(xy[:, 0], xy[:, 1], mixture.centres, mixture.heights, 6.0))


def test_gaussian_hills_ground_height_is_the_grid_interpolant():
    terrain = gaussian_hills(size=30.0, spacing=1.5, sigma=5.0, rng=4)
    xy = np.random.default_rng(2).uniform(0.0, 30.0, size=(300, 2))
    expected = grid_height(xy, terrain.grid.z, (1.5, 1.5), (0.0, 0.0))
    np.testing.assert_allclose(terrain.ground_height(xy), expected, atol=1e-9)


def test_gaussian_hills_seeded_and_spacing_independent():
    a = gaussian_hills(size=20.0, spacing=1.0, sigma=4.0, rng=5)
    b = gaussian_hills(size=20.0, spacing=1.0, sigma=4.0, rng=np.random.default_rng(5))
    c = gaussian_hills(size=20.0, spacing=1.0, sigma=4.0, rng=6)
    fine = gaussian_hills(size=20.0, spacing=0.5, sigma=4.0, rng=5)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    assert not np.allclose(a.grid.z, c.grid.z)
    # The same seed draws the same hills at any spacing: every second fine node is a coarse node.
    np.testing.assert_allclose(fine.grid.z[::2, ::2], a.grid.z, rtol=1e-12)


def test_gaussian_hills_zero_hills_is_flat():
    terrain = gaussian_hills(size=10.0, spacing=1.0, n_hills=0, rng=0)
    assert np.all(terrain.grid.z == 0.0)


@pytest.mark.parametrize(
    "kwargs, error",
    [
        (dict(spacing=0.0), InvalidInputError),
        (dict(spacing=-1.0), InvalidInputError),
        (dict(spacing=3.0), InvalidInputError),  # 100 is not a multiple of 3
        (dict(size=-5.0), InvalidInputError),
        (dict(sigma=0.0), InvalidInputError),
        (dict(heights=(25.0, 5.0)), InvalidInputError),
        (dict(heights=(5.0, float("nan"))), InvalidInputError),
        (dict(n_hills=-1), InvalidInputError),
        (dict(n_hills=2.5), InvalidTypeError),
        (dict(rng="seed"), InvalidTypeError),
    ],
)
def test_gaussian_hills_bad_input(kwargs, error):
    with pytest.raises(error):
        gaussian_hills(**kwargs)


def test_gaussian_mixture_checks_shapes_and_pickles():
    with pytest.raises(InvalidInputError):
        GaussianMixture(centres=np.zeros((3, 2)), heights=np.ones(2), sigma=1.0)
    with pytest.raises(InvalidInputError):
        GaussianMixture(centres=np.zeros((3, 3)), heights=np.ones(3), sigma=1.0)
    mixture = random_gaussian_mixture(rng=3)
    again = pickle.loads(pickle.dumps(mixture))
    np.testing.assert_array_equal(again.centres, mixture.centres)
    with pytest.raises(InvalidInputError):
        mixture.height(np.zeros((4, 3)))


# --------------------------------------------------------------------------------------------
# Buildings


def edge_face_counts(faces: np.ndarray) -> tuple[dict, dict]:
    """Undirected edge -> number of faces, and directed edge -> count."""
    undirected: dict = {}
    directed: dict = {}
    for f in faces:
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            key = (min(a, b), max(a, b))
            undirected[key] = undirected.get(key, 0) + 1
            directed[(a, b)] = directed.get((a, b), 0) + 1
    return undirected, directed


def test_random_buildings_respect_layout_rules():
    boxes = random_buildings(size=24.0, n_buildings=5, gap=2.0, margin=1.0, step=0.5, rng=8)
    assert len(boxes) == 5
    for k, b in enumerate(boxes):
        assert b.xmin >= 1.0 - 1e-9 and b.xmax <= 23.0 + 1e-9
        assert b.ymin >= 1.0 - 1e-9 and b.ymax <= 23.0 + 1e-9
        assert 3.0 <= b.height <= 10.0
        for value in (b.xmin, b.xmax, b.ymin, b.ymax):
            assert abs(value * 2 - round(value * 2)) < 1e-9  # multiples of 0.5
        for other in boxes[:k]:
            assert b.gap_to(other) >= 2.0 - 1e-9
    assert random_buildings(rng=8) == random_buildings(rng=8)
    assert random_buildings(rng=8) != random_buildings(rng=9)


def test_random_buildings_too_crowded_raises():
    with pytest.raises(InfeasibleError):
        random_buildings(size=24.0, n_buildings=40, footprint=(6.0, 7.0), max_attempts=50, rng=0)


SCENE = (
    Building(2.0, 2.0, 6.0, 5.0, 4.0),
    Building(9.0, 3.0, 12.5, 9.0, 7.25),
    Building(3.0, 9.0, 7.0, 11.0, 2.6),
)


def test_buildings_mesh_is_closed_and_consistently_oriented_except_the_rim():
    terrain = buildings_terrain(SCENE, size=14.0, spacing=0.5)
    v, f = terrain.vertices, terrain.faces
    undirected, directed = edge_face_counts(f)
    counts = np.array(list(undirected.values()))
    assert counts.max() == 2  # no non-manifold edge
    boundary = [e for e, c in undirected.items() if c == 1]
    for a, b in boundary:  # open edges are on the outer rim of the ground only
        for p in (v[a], v[b]):
            assert p[2] == 0.0
            assert min(p[0], p[1]) == 0.0 or max(p[0], p[1]) == 14.0
    assert len(boundary) == 4 * 28  # 14 m / 0.5 m edges on each side
    # Consistent orientation: an interior edge is walked once in each direction.
    for count in directed.values():
        assert count == 1
    # Topologically a disc: V - E + F = 1.
    assert len(v) - len(undirected) + len(f) == 1


def test_buildings_mesh_geometry():
    size = 14.0
    terrain = buildings_terrain(SCENE, size=size, spacing=0.5)
    v, f = terrain.vertices, terrain.faces
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    normal = np.cross(b - a, c - a)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    horizontal = np.isclose(np.abs(normal[:, 2]), 1.0)
    vertical = np.isclose(normal[:, 2], 0.0, atol=1e-12)
    assert np.all(horizontal | vertical)  # vertical walls, flat ground and roofs
    assert np.all(normal[horizontal, 2] > 0)  # ground and roofs face up
    centroid = (a + b + c) / 3.0
    for box in SCENE:
        centre = np.array([(box.xmin + box.xmax) / 2, (box.ymin + box.ymax) / 2])
        inside = (
            (centroid[:, 0] >= box.xmin - 1e-9)
            & (centroid[:, 0] <= box.xmax + 1e-9)
            & (centroid[:, 1] >= box.ymin - 1e-9)
            & (centroid[:, 1] <= box.ymax + 1e-9)
        )
        # No ground under a building: inside the footprint only roof and walls.
        assert not np.any(inside & horizontal & (centroid[:, 2] < box.height - 1e-9))
        walls = inside & vertical
        outward = centroid[walls, :2] - centre
        assert np.all(np.einsum("ij,ij->i", outward, normal[walls, :2]) > 0)  # walls face out
    expected_area = size * size + sum(2 * ((s.xmax - s.xmin) + (s.ymax - s.ymin)) * s.height for s in SCENE)
    assert terrain.area == pytest.approx(expected_area, rel=1e-12)
    np.testing.assert_allclose(terrain.bounds, [[0, 0, 0], [size, size, 7.25]])


def test_buildings_ground_height_sees_roofs_and_ground():
    terrain = buildings_terrain(SCENE, size=14.0, spacing=0.5)
    xy = np.random.default_rng(0).uniform(0.05, 13.95, size=(400, 2))
    expected = np.zeros(len(xy))
    for box in SCENE:
        inside = (xy[:, 0] > box.xmin) & (xy[:, 0] < box.xmax) & (xy[:, 1] > box.ymin) & (xy[:, 1] < box.ymax)
        expected[inside] = box.height
    near_wall = np.zeros(len(xy), dtype=bool)
    for box in SCENE:
        for edge_x in (box.xmin, box.xmax):
            near_wall |= np.abs(xy[:, 0] - edge_x) < 1e-6
        for edge_y in (box.ymin, box.ymax):
            near_wall |= np.abs(xy[:, 1] - edge_y) < 1e-6
    got = terrain.ground_height(xy)
    np.testing.assert_allclose(got[~near_wall], expected[~near_wall], atol=1e-9)


def test_buildings_scene_is_seeded():
    a = buildings_scene(rng=3)
    b = buildings_scene(rng=3)
    c = buildings_scene(rng=4)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    assert a.vertices.shape != c.vertices.shape or not np.array_equal(a.vertices, c.vertices)
    boxes = random_buildings(step=0.5, rng=3)
    np.testing.assert_array_equal(buildings_terrain(boxes).vertices, a.vertices)


@pytest.mark.parametrize(
    "boxes",
    [
        (Building(2.0, 2.0, 6.0, 6.0, 3.0), Building(5.0, 5.0, 8.0, 8.0, 3.0)),  # overlap
        (Building(2.0, 2.0, 6.0, 6.0, 3.0), Building(6.0, 2.0, 8.0, 6.0, 3.0)),  # touching walls
        (Building(10.0, 2.0, 16.0, 6.0, 3.0),),  # outside the 14 m square
        (Building(2.0, 2.0, 6.25, 6.0, 3.0),),  # not on the 0.5 m grid
    ],
)
def test_buildings_terrain_bad_layouts(boxes):
    with pytest.raises(InvalidInputError):
        buildings_terrain(boxes, size=14.0, spacing=0.5)


def test_building_bad_values():
    with pytest.raises(InvalidInputError):
        Building(2.0, 2.0, 2.0, 5.0, 3.0)
    with pytest.raises(InvalidInputError):
        Building(2.0, 2.0, 4.0, 5.0, 0.0)
    with pytest.raises(InvalidInputError):
        Building(2.0, 2.0, 4.0, float("nan"), 3.0)
    with pytest.raises(InvalidTypeError):
        buildings_terrain([(2.0, 2.0, 4.0, 5.0, 3.0)], size=14.0)


def test_perturb_buildings():
    exact = perturb_buildings(SCENE, size=14.0, position_error=0.0, size_error=0.0, height_error=0.0, step=0.5, rng=0)
    assert exact == SCENE
    noisy = perturb_buildings(SCENE, size=14.0, position_error=0.7, size_error=0.5, height_error=1.0, step=0.5, rng=1)
    assert noisy != SCENE
    assert noisy == perturb_buildings(SCENE, size=14.0, position_error=0.7, size_error=0.5, height_error=1.0, step=0.5, rng=1)
    buildings_terrain(noisy, size=14.0, spacing=0.5)  # a valid layout again
    shifts = [abs((n.xmin + n.xmax) - (s.xmin + s.xmax)) / 2 for n, s in zip(noisy, SCENE, strict=True)]
    assert max(shifts) < 5 * 0.7 + 0.5
    with pytest.raises(InvalidInputError):
        perturb_buildings(SCENE, size=14.0, height_error=-1.0)


# --------------------------------------------------------------------------------------------
# Geodesy and DEMs


# Lengths of one degree on WGS84, from standard geodesy tables (metres): (latitude, lon, lat).
def degree_lengths_series(latitude: float) -> tuple[float, float]:
    """Lengths (m) of one degree of longitude and latitude on WGS84, from the textbook series
    expansions in cos(k phi) (an independent route to the closed-form radii of curvature)."""
    phi = math.radians(latitude)
    lat_m = 111132.92 - 559.82 * math.cos(2 * phi) + 1.175 * math.cos(4 * phi) - 0.0023 * math.cos(6 * phi)
    lon_m = 111412.84 * math.cos(phi) - 93.5 * math.cos(3 * phi) + 0.118 * math.cos(5 * phi)
    return lon_m, lat_m


@pytest.mark.parametrize("latitude", [-75.0, -36.6, 0.0, 15.0, 30.0, 45.0, 60.0, 80.0])
def test_metres_per_degree_matches_wgs84_series(latitude):
    got_lon, got_lat = metres_per_degree(latitude)
    lon_m, lat_m = degree_lengths_series(latitude)
    assert got_lon == pytest.approx(lon_m, abs=0.1)
    assert got_lat == pytest.approx(lat_m, abs=0.1)
    if latitude == 0.0:  # the equator is a circle of the semi-major axis
        assert got_lon == pytest.approx(2 * math.pi * 6378137.0 / 360.0, rel=1e-12)


def test_metres_per_degree_bad_latitude():
    with pytest.raises(InvalidInputError):
        metres_per_degree(91.0)
    with pytest.raises(InvalidInputError):
        metres_per_degree(float("nan"))


def grid_dem(z, spacing, lower_left=(0.0, 0.0), crs="EPSG:4326", nodata=None):
    """A DEM of heights ``z`` (row 0 south) whose south-west node is ``lower_left``, in ``crs``."""
    z = np.asarray(z)
    dx, dy = (spacing, spacing) if np.isscalar(spacing) else spacing
    north = lower_left[1] + (z.shape[0] - 1) * dy
    transform = (dx, 0.0, lower_left[0] - 0.5 * dx, 0.0, -dy, north + 0.5 * dy)
    return dem_from_array(z[::-1], transform, crs, nodata=nodata)


def haversine(lon1, lat1, lon2, lat2, radius=6371008.8):
    p1, p2 = math.radians(lat1), math.radians(lat2)
    dl = math.radians(lon2 - lon1)
    h = math.sin((p2 - p1) / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * radius * math.asin(math.sqrt(h))


@pytest.mark.parametrize("latitude", [-33.9, 0.5, 36.6, 52.0, 69.7])
def test_dem_in_degrees_has_cell_sizes_of_its_latitude(latitude):
    step = 1.0 / 3600.0  # one arc-second
    z = np.random.default_rng(0).uniform(0.0, 50.0, size=(5, 6))
    loaded = grid_dem(z, step, lower_left=(10.0, latitude))
    dx, dy = loaded.terrain.grid.spacing
    assert loaded.frame.geographic
    centre = latitude + 2 * step
    assert loaded.frame.reference_latitude == pytest.approx(centre)
    # Against the spherical great-circle distance (an independent formula): within 0.7 %,
    # the most the WGS84 ellipsoid departs from a sphere.
    assert dx == pytest.approx(haversine(10.0, centre, 10.0 + step, centre), rel=7e-3)
    assert dy == pytest.approx(haversine(10.0, centre, 10.0, centre + step), rel=7e-3)
    # And the east-west size shrinks as cos(latitude).
    assert dx / dy == pytest.approx(math.cos(math.radians(centre)), rel=7e-3)


def test_dem_in_degrees_round_trips_to_source():
    z = np.arange(20.0).reshape(4, 5)
    loaded = grid_dem(z, (0.001, 0.002), lower_left=(-84.4, 36.45))
    local = loaded.terrain.vertices
    back = loaded.frame.to_source(local)
    lon = -84.4 + np.arange(5) * 0.001
    lat = 36.45 + np.arange(4) * 0.002
    np.testing.assert_allclose(np.sort(np.unique(back[:, 0].round(9))), lon, atol=1e-9)
    np.testing.assert_allclose(np.sort(np.unique(back[:, 1].round(9))), lat, atol=1e-9)
    np.testing.assert_allclose(loaded.frame.to_local(back), local, atol=1e-7)


def test_dem_in_metres_recentres_without_losing_precision():
    # A UTM tile with eastings of 500 km and northings of 5000 km, 0.5 m cells.
    east, north = 500_123.25, 5_000_456.75
    ny, nx = 30, 40
    xs = east + np.arange(nx) * 0.5
    ys = north + np.arange(ny) * 0.5
    x, y = np.meshgrid(xs, ys)
    z = 212.0 + 0.013 * (x - east) - 0.021 * (y - north) + 0.4 * np.sin((x - east) * 0.7)
    pytest.importorskip("pyproj")
    loaded = grid_dem(z, 0.5, lower_left=(east, north), crs="EPSG:32633")
    terrain = loaded.terrain
    np.testing.assert_allclose(loaded.frame.origin, [east, north, z.min()])
    np.testing.assert_allclose(terrain.bounds[0, :2], [0.0, 0.0], atol=0.0)
    np.testing.assert_allclose(terrain.bounds[1, :2], [19.5, 14.5], atol=1e-12)
    assert terrain.bounds[0, 2] == 0.0
    # Heights inside cells against the grid's own interpolant, in world coordinates.
    world_xy = np.random.default_rng(3).uniform([east, north], [east + 19.5, north + 14.5], size=(200, 2))
    local_xy = world_xy - [east, north]
    expected = grid_height(local_xy, z - z.min(), (0.5, 0.5), (0.0, 0.0))
    np.testing.assert_allclose(terrain.ground_height(local_xy), expected, atol=1e-9)
    # Results map back to world coordinates to well under a millimetre.
    world = np.column_stack([world_xy, expected + z.min()])
    np.testing.assert_allclose(loaded.frame.to_source(loaded.frame.to_local(world)), world, atol=1e-6, rtol=0)


def test_dem_raster_order_follows_the_transform():
    z = np.array([[3.0, 3.0, 3.0], [2.0, 2.0, 2.0], [1.0, 1.0, 1.0]])  # raster row 0, highest
    north_up = dem_from_array(z, (1.0, 0.0, -0.5, 0.0, -1.0, 2.5), "EPSG:4326")  # row 0 is north
    south_up = dem_from_array(z, (1.0, 0.0, -0.5, 0.0, 1.0, -0.5), "EPSG:4326")  # row 0 is south
    high = north_up.frame.to_source([[0.0, north_up.terrain.bounds[1, 1], 0.0]])[0, 1]
    assert high == pytest.approx(2.0) and north_up.terrain.bounds[1, 2] - north_up.terrain.bounds[0, 2] == pytest.approx(2.0)
    top_north = north_up.terrain.ground_height([[0.5 * north_up.terrain.bounds[1, 0], 0.95 * north_up.terrain.bounds[1, 1]]])[0]
    top_south = south_up.terrain.ground_height([[0.5 * south_up.terrain.bounds[1, 0], 0.95 * south_up.terrain.bounds[1, 1]]])[0]
    assert top_north == pytest.approx(1.9) and top_south == pytest.approx(0.1)


def test_dem_nodata_holes_are_left_out():
    z = np.full((6, 7), 10.0)
    z[2, 3] = -9999.0  # one sentinel hole
    z[5, 0] = np.nan  # and a NaN corner
    pytest.importorskip("pyproj")
    loaded = grid_dem(z, 1.0, nodata=-9999.0, crs="EPSG:32633")
    terrain = loaded.terrain
    assert loaded.nodata_cells == 2
    # The six triangles around the hole and the one touching the corner are gone.
    assert terrain.n_faces == 2 * 5 * 6 - 6 - 1
    assert np.isnan(terrain.ground_height([[3.0, 2.0], [3.2, 2.1], [0.1, 4.9]])).all()
    assert terrain.ground_height([[5.5, 0.5]])[0] == pytest.approx(0.0)  # not ground at -9999
    targets = terrain.default_targets()
    hole = np.hypot(targets.points[:, 0] - 3.0, targets.points[:, 1] - 2.0) < 1e-9
    assert not hole.any()
    assert np.all(targets.points[:, 2] == 0.0)  # no target at the sentinel height


@pytest.mark.parametrize(
    "z, spacing, lower_left",
    [
        (np.zeros((1, 5)), 1e-3, (0.0, 0.0)),  # one row
        (np.zeros((5, 1)), 1e-3, (0.0, 0.0)),  # one column
        (np.zeros((4, 4)), 0.0, (0.0, 0.0)),
        (np.zeros((4, 4)), -2.0, (0.0, 0.0)),
        (np.zeros((4, 4)), (1e-3, 0.0), (0.0, 0.0)),
        (np.full((3, 3), np.nan), 1e-3, (0.0, 0.0)),  # nothing but nodata
        (np.array([[1.0, np.nan, 1.0], [np.nan, 1.0, np.nan], [1.0, np.nan, 1.0]]), 1e-3, (0.0, 0.0)),  # no full cell
        (np.array([[1.0, np.inf], [1.0, 1.0]]), 1e-3, (0.0, 0.0)),
        (np.zeros((4, 4)), 1.0, (0.0, 89.0)),  # past the pole
    ],
)
def test_dem_bad_input(z, spacing, lower_left):
    with pytest.raises(InvalidInputError):
        grid_dem(z, spacing, lower_left)


def test_dem_bad_transforms_and_types():
    with pytest.raises(InvalidTypeError):
        dem_from_array(np.array([["a", "b"], ["c", "d"]]), (1.0, 0.0, 0.0, 0.0, -1.0, 0.0), "EPSG:4326")
    with pytest.raises(InvalidInputError, match="rotated"):
        dem_from_array(np.zeros((3, 3)), (1.0, 0.1, 0.0, 0.0, -1.0, 0.0), "EPSG:4326")
    with pytest.raises(InvalidInputError, match="six numbers"):
        dem_from_array(np.zeros((3, 3)), (1.0, 0.0, 0.0), "EPSG:4326")


def test_local_frame_checks_and_pickles():
    frame = LocalFrame(np.array([1.0, 2.0, 3.0]), np.array([2.0, 2.0, 1.0]))
    again = pickle.loads(pickle.dumps(frame))
    np.testing.assert_array_equal(again.to_local([[3.0, 4.0, 5.0]]), [[4.0, 4.0, 2.0]])
    with pytest.raises(InvalidInputError):
        LocalFrame(np.zeros(3), np.array([1.0, 0.0, 1.0]))
    with pytest.raises(InvalidInputError):
        frame.to_source(np.zeros((2, 2)))


def test_geo_dem_pickles():
    loaded = grid_dem(np.arange(9.0).reshape(3, 3), 1e-3, lower_left=(10.0, 20.0))
    again = pickle.loads(pickle.dumps(loaded))
    assert isinstance(again, GeoDem) and again.crs == loaded.crs
    np.testing.assert_array_equal(again.terrain.vertices, loaded.terrain.vertices)
    np.testing.assert_array_equal(again.frame.origin, loaded.frame.origin)


# --------------------------------------------------------------------------------------------
# The sample DEM matplotlib ships


def test_sample_dem_is_the_jacksboro_dem_in_metres():
    pytest.importorskip("matplotlib")
    loaded = sample_dem(window=None)
    assert loaded.is_wgs84 and loaded.raster.shape == (344, 403)
    terrain = loaded.terrain
    assert terrain.grid.shape == (344, 403)
    dx, dy = terrain.grid.spacing
    # 3 arc-seconds at 36.59 N: about 74.6 m east-west and 92.5 m north-south.
    assert dx == pytest.approx(74.6, abs=0.3)
    assert dy == pytest.approx(92.5, abs=0.3)
    assert loaded.frame.reference_latitude == pytest.approx(36.59, abs=0.01)
    assert terrain.bounds[0, 2] == 0.0
    assert terrain.bounds[1, 2] == pytest.approx(1076.0 - 236.0)
    lon, lat, elevation = loaded.frame.to_source([[0.0, 0.0, 0.0]])[0]
    assert lon == pytest.approx(-84.41375 + 0.0008333 / 2, abs=1e-6)
    assert lat == pytest.approx(36.44625 + 0.0008333 / 2, abs=1e-6)
    assert elevation == 236.0


def test_sample_dem_window_stride_and_orientation():
    pytest.importorskip("matplotlib")
    from matplotlib import cbook

    path = cbook.get_sample_data("jacksboro_fault_dem.npz", asfileobj=False)
    with np.load(path) as data:
        raw = np.asarray(data["elevation"], dtype=float)
    loaded = sample_dem(window=(10, 31, 100, 141), stride=2)
    grid = loaded.terrain.grid
    assert grid.shape == (11, 21)
    # Row 0 of the window is 10 rows north of the file's southern (last) row.
    expected = raw[::-1][10:31:2, 100:141:2]
    np.testing.assert_allclose(grid.z + loaded.frame.origin[2], expected)


@pytest.mark.parametrize("kwargs", [dict(window=(0, 1, 0, 10)), dict(window=(0, 10)), dict(stride=0), dict(window=(0.5, 10, 0, 10))])
def test_sample_dem_bad_input(kwargs):
    pytest.importorskip("matplotlib")
    with pytest.raises(InvalidInputError):
        sample_dem(**kwargs)


# --------------------------------------------------------------------------------------------
# GeoTIFF


def north_up(west: float, north: float, dx: float, dy: float):
    """The affine transform of a north-up raster (pixel corner at (west, north))."""
    affine = pytest.importorskip("affine")
    return affine.Affine(dx, 0.0, west, 0.0, -dy, north)


def write_geotiff(path, z, transform, crs, nodata=None):
    rasterio = pytest.importorskip("rasterio")
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        height=z.shape[0],
        width=z.shape[1],
        count=1,
        dtype="float32",
        crs=crs,
        transform=transform,
        nodata=nodata,
    ) as dst:
        dst.write(z.astype(np.float32), 1)


def test_geotiff_projected_with_nodata(tmp_path):
    pytest.importorskip("rasterio")
    z = np.random.default_rng(0).uniform(100.0, 120.0, size=(8, 10)).astype(np.float32)
    z[3, 4] = -32768.0
    west, north = 500_000.0, 4_100_000.0
    path = tmp_path / "utm.tif"
    write_geotiff(path, z, north_up(west, north, 2.0, 2.0), "EPSG:32617", nodata=-32768.0)
    loaded = read_dem(path)
    assert not loaded.frame.geographic
    assert loaded.nodata_cells == 1
    assert loaded.terrain.grid.spacing == (2.0, 2.0)
    valid = z[z > -1000]
    # The south-west pixel centre is the origin; file row 0 is north.
    np.testing.assert_allclose(loaded.frame.origin, [west + 1.0, north - 8 * 2.0 + 1.0, valid.min()])
    expected = z[::-1].astype(float) - valid.min()
    expected[expected < -1000] = np.nan
    np.testing.assert_allclose(loaded.terrain.grid.z, expected, rtol=0, atol=1e-4)


def test_geotiff_geographic_gets_metric_cells(tmp_path):
    pytest.importorskip("rasterio")
    step = 1.0 / 1200.0  # 3 arc-seconds
    z = np.linspace(0, 50, 6 * 7).reshape(6, 7)
    path = tmp_path / "geo.tif"
    write_geotiff(path, z, north_up(5.0, 45.0 + 6 * step, step, step), "EPSG:4326")
    loaded = read_dem(path)
    assert loaded.frame.geographic
    lon_m, lat_m = metres_per_degree(45.0 + 3.0 * step)  # centre of the 6 pixel-centre rows
    dx, dy = loaded.terrain.grid.spacing
    assert dx == pytest.approx(lon_m * step, rel=1e-9)
    assert dy == pytest.approx(lat_m * step, rel=1e-9)
    assert dx == pytest.approx(78846.8 * step, rel=1e-4)


def test_geotiff_in_feet_is_converted_to_metres(tmp_path):
    pytest.importorskip("rasterio")
    z = np.arange(20.0).reshape(4, 5)
    path = tmp_path / "feet.tif"
    write_geotiff(path, z, north_up(2_000_000.0, 600_000.0, 10.0, 10.0), "EPSG:2264")  # US survey feet
    loaded = read_dem(path)
    foot = 1200.0 / 3937.0
    assert loaded.terrain.grid.spacing == pytest.approx((10.0 * foot, 10.0 * foot), rel=1e-12)
    world = loaded.frame.to_source(loaded.terrain.vertices)
    assert world[:, 0].min() == pytest.approx(2_000_005.0)  # pixel centres, in the file's feet
    assert world[:, 1].max() == pytest.approx(599_995.0)


def test_geotiff_bad_files(tmp_path):
    pytest.importorskip("rasterio")
    with pytest.raises(InvalidInputError, match="does not exist"):
        read_dem(tmp_path / "missing.tif")
    junk = tmp_path / "junk.tif"
    junk.write_bytes(b"this is not a raster")
    with pytest.raises(InvalidInputError, match="cannot read"):
        read_dem(junk)
    with pytest.raises(InvalidTypeError):
        read_dem(12)


def test_geotiff_rotated_is_refused(tmp_path):
    pytest.importorskip("rasterio")
    from affine import Affine

    path = tmp_path / "rotated.tif"
    write_geotiff(path, np.zeros((4, 4)), Affine(1.0, 0.2, 0.0, 0.1, -1.0, 10.0), "EPSG:32617")
    with pytest.raises(InvalidInputError, match="rotated"):
        read_dem(path)


def test_geotiff_without_rasterio_says_what_to_install(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "rasterio", None)  # import rasterio now raises ImportError
    with pytest.raises(ImportError, match="rasterio"):
        read_dem(tmp_path / "any.tif")


# --------------------------------------------------------------------------------------------
# Meshes


def small_scene_mesh() -> Terrain:
    return buildings_terrain((Building(1.0, 1.0, 3.0, 2.0, 2.0),), size=5.0, spacing=1.0)


@pytest.mark.parametrize("suffix", ["obj", "stl", "ply"])
def test_mesh_files_round_trip(tmp_path, suffix):
    trimesh = pytest.importorskip("trimesh")
    truth = small_scene_mesh()
    offset = np.array([651_000.0, 4_300_000.0, 120.0])  # georeferenced coordinates
    mesh = trimesh.Trimesh(truth.vertices + offset, truth.faces, process=False)
    path = tmp_path / f"scene.{suffix}"
    mesh.export(path)
    loaded = load_mesh(path)
    np.testing.assert_allclose(loaded.frame.origin, offset, atol=1e-3)  # STL stores float32
    assert loaded.terrain.n_faces == truth.n_faces
    assert loaded.terrain.area == pytest.approx(truth.area, rel=1e-6)
    report = loaded.mesh_report
    # STL stores three corners per triangle: welding must recover the shared vertices.
    assert loaded.terrain.n_vertices == truth.n_vertices
    if suffix == "stl":
        assert report.merged_vertices == 3 * truth.n_faces - truth.n_vertices
    assert report.boundary_edges == 4 * 5  # the rim of the 5 m ground at 1 m spacing
    assert report.nonmanifold_edges == 0 and not report.repaired


def test_mesh_y_up(tmp_path):
    pytest.importorskip("trimesh")
    truth = small_scene_mesh()
    v = truth.vertices
    y_up = np.column_stack([v[:, 0], v[:, 2], -v[:, 1]])
    loaded = mesh_terrain(y_up, truth.faces, up="y")
    np.testing.assert_allclose(loaded.terrain.vertices, v - v.min(axis=0), atol=1e-12)


def test_mesh_duplicate_and_degenerate_faces_are_dropped_and_reported():
    truth = small_scene_mesh()
    faces = np.concatenate([truth.faces, truth.faces[:3][:, ::-1], [[0, 0, 1]], truth.faces[5:6]])
    loaded = mesh_terrain(truth.vertices, faces)
    report = loaded.mesh_report
    assert report.duplicate_faces == 4
    assert report.degenerate_faces == 1
    assert loaded.terrain.n_faces == truth.n_faces
    assert loaded.terrain.area == pytest.approx(truth.area)
    with pytest.raises(MeshError, match="duplicate"):
        mesh_terrain(truth.vertices, faces, on_defect="raise")


def test_open_mesh_is_accepted_and_reported():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 1], [7, 7, 7.0]])
    loaded = mesh_terrain(vertices, np.array([[0, 1, 2], [1, 3, 2]]))
    assert loaded.mesh_report.boundary_edges == 4
    assert loaded.mesh_report.unused_vertices == 1
    assert loaded.terrain.n_vertices == 4


def test_clean_mesh_bad_input():
    with pytest.raises(MeshError):
        clean_mesh(np.zeros((3, 3)), np.array([[0, 1, 5]]))
    with pytest.raises(MeshError):
        clean_mesh(np.zeros((3, 3)), np.zeros((0, 3), dtype=int))
    with pytest.raises(MeshError):
        clean_mesh(np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0.0]]), np.array([[0, 1, 2]]))  # flat only
    with pytest.raises(InvalidTypeError):
        clean_mesh(np.zeros((3, 3)), np.array([[0.0, 1.0, 2.0]]))
    with pytest.raises(InvalidInputError):
        clean_mesh(np.array([[0, 0, np.nan], [1, 0, 0], [0, 1, 0.0]]), np.array([[0, 1, 2]]))


def test_mesh_missing_or_unparseable_file(tmp_path):
    pytest.importorskip("trimesh")
    with pytest.raises(MeshError, match="does not exist"):
        load_mesh(tmp_path / "nothing.obj")
    with pytest.raises(MeshError):
        load_mesh(tmp_path)  # a directory
    for name, content in [
        ("bad.stl", b"solid x\n facet normal oops\n"),
        ("bad.ply", b"ply\nformat nonsense\n"),
        ("bad.obj", b"v 0 0 0\nv 1 0 0\n"),
        ("bad.xyz123", b"1 2 3"),
    ]:
        path = tmp_path / name
        path.write_bytes(content)
        with pytest.raises(MeshError):
            load_mesh(path)


def test_mesh_without_trimesh_says_what_to_install(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "trimesh", None)
    with pytest.raises(ImportError, match="trimesh"):
        load_mesh(tmp_path / "any.obj")


def test_mesh_terrain_bad_arguments():
    truth = small_scene_mesh()
    with pytest.raises(InvalidInputError):
        mesh_terrain(truth.vertices, truth.faces, up="x")
    with pytest.raises(InvalidInputError):
        mesh_terrain(truth.vertices, truth.faces, on_defect="ignore")
    with pytest.raises(MeshError):
        mesh_terrain(np.zeros((0, 3)), np.zeros((0, 3), dtype=int))
