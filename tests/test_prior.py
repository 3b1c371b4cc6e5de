"""Prior samples and the approximating surface S' (uavcov.terrain._prior) against scipy and brute force."""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import LinearNDInterpolator
from scipy.spatial import ConvexHull, Delaunay

from reference import grid_height
from uavcov import Terrain, gaussian_hills
from uavcov.errors import InvalidInputError, InvalidTypeError
from uavcov.terrain import Prior, approximate_surface, approximation_error, sample_prior
from uavcov.terrain._buildings import Building, buildings_terrain
from uavcov.terrain._hills import random_gaussian_mixture
from uavcov.terrain._prior import building_corner_prior, buildings_prior


@pytest.fixture(scope="module")
def hills() -> Terrain:
    return gaussian_hills(size=100.0, spacing=2.0, rng=21)


def interior_points(samples: np.ndarray, n: int, rng: np.random.Generator, margin: float = 1e-6) -> np.ndarray:
    """Random (x, y) inside the samples' convex hull, at least ``margin`` (relative) from its edges."""
    hull = ConvexHull(samples[:, :2])
    lo, hi = samples[:, :2].min(axis=0), samples[:, :2].max(axis=0)
    xy = rng.uniform(lo, hi, size=(20 * n, 2))
    distance = xy @ hull.equations[:, :2].T + hull.equations[:, 2]  # <= 0 inside
    inside = (distance < -margin * float(np.ptp(samples[:, :2]))).all(axis=1)
    return xy[inside][:n]


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_surface_equals_scipy_linear_interpolator(hills, seed):
    rng = np.random.default_rng(seed)
    prior = sample_prior(hills, n=int(rng.integers(3, 60)), corners=bool(seed % 2), rng=seed)
    surface = approximate_surface(prior)
    xy = interior_points(prior.points, 500, rng)
    assert len(xy) > 100
    expected = LinearNDInterpolator(prior.points[:, :2], prior.points[:, 2])(xy)
    np.testing.assert_allclose(surface.ground_height(xy), expected, rtol=1e-9, atol=1e-9)


def test_surface_on_scattered_points_equals_scipy():
    rng = np.random.default_rng(9)
    points = np.column_stack([rng.normal(size=(80, 2)) * [30.0, 10.0], rng.uniform(-5, 5, size=80)])
    surface = approximate_surface(points)
    xy = interior_points(points, 400, rng)
    expected = LinearNDInterpolator(points[:, :2], points[:, 2])(xy)
    np.testing.assert_allclose(surface.ground_height(xy), expected, rtol=1e-9, atol=1e-9)
    assert surface.n_vertices == 80
    assert surface.n_faces == len(Delaunay(points[:, :2]).simplices)


def test_surface_faces_point_up_and_cover_the_hull():
    points = np.array([[0, 0, 1], [4, 0, 2], [4, 3, 0], [0, 3, 5], [1, 1, 1], [3, 2, 2.0]])
    surface = approximate_surface(points)
    v, f = surface.vertices, surface.faces
    normal = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    assert np.all(normal[:, 2] > 0)
    # The projected area is the hull's area (12 m^2): no gap, no overlap.
    assert 0.5 * normal[:, 2].sum() == pytest.approx(12.0)


def test_outside_the_hull_is_nan():
    points = np.array([[2, 2, 1], [8, 2, 2], [8, 8, 3], [2, 8, 4], [5, 5, 9.0]])
    surface = approximate_surface(points)
    outside = np.array([[1.0, 5.0], [9.0, 5.0], [5.0, 1.0], [5.0, 9.5], [0.0, 0.0], [50.0, 50.0]])
    assert np.isnan(surface.ground_height(outside)).all()
    assert np.isinf(surface.clearance(np.column_stack([outside, np.full(len(outside), 20.0)]))).all()
    assert np.isfinite(surface.ground_height([[5.0, 5.0], [2.5, 7.5]])).all()


def test_corners_make_the_hull_the_whole_rectangle(hills):
    prior = sample_prior(hills, n=10, rng=5)
    surface = prior.surface()
    xy = np.random.default_rng(0).uniform(1e-6, 100.0 - 1e-6, size=(2000, 2))
    assert np.isfinite(surface.ground_height(xy)).all()
    np.testing.assert_allclose(surface.bounds[:, :2], hills.bounds[:, :2])


def test_prior_points_lie_on_the_true_surface(hills):
    prior = sample_prior(hills, n=200, rng=3)
    assert prior.n_points == 204 and prior.kind == "random"
    expected = grid_height(prior.points[:, :2], hills.grid.z, hills.grid.spacing, hills.grid.origin)
    np.testing.assert_allclose(prior.points[:, 2], expected, atol=1e-9)
    corners = prior.points[-4:, :2]
    np.testing.assert_array_equal(corners, [[0, 0], [100, 0], [100, 100], [0, 100]])
    np.testing.assert_allclose(prior.points[-4:, 2], hills.grid.z[[0, 0, -1, -1], [0, -1, -1, 0]])


def test_prior_is_seeded(hills):
    a = sample_prior(hills, n=30, rng=7)
    b = sample_prior(hills, n=30, rng=np.random.default_rng(7))
    c = sample_prior(hills, n=30, rng=8)
    np.testing.assert_array_equal(a.points, b.points)
    assert not np.array_equal(a.points, c.points)
    assert sample_prior(hills, n=30, corners=False, rng=7).n_points == 30


def test_pyramid_prior(hills):
    prior = sample_prior(hills, kind="pyramid")
    assert prior.n_points == 5 and prior.kind == "pyramid"
    np.testing.assert_allclose(prior.points[4, :2], [50.0, 50.0])
    assert prior.points[4, 2] == pytest.approx(grid_height(np.array([[50.0, 50.0]]), hills.grid.z, (2.0, 2.0))[0])
    surface = prior.surface()
    assert surface.n_faces == 4  # the four faces of the pyramid


def test_user_points(hills):
    xy = np.array([[10.0, 20.0], [55.5, 70.25], [90.0, 5.0], [0.0, 0.0]])
    prior = sample_prior(hills, kind="points", points=xy)
    assert prior.n_points == 7  # the user's (0, 0) corner is not added twice
    np.testing.assert_allclose(prior.points[:4, 2], grid_height(xy, hills.grid.z, (2.0, 2.0)), atol=1e-9)
    xyz = np.array([[10.0, 20.0, 3.0], [55.0, 70.0, 1.0], [90.0, 5.0, 2.0]])
    given = sample_prior(hills, kind="points", points=xyz, corners=False)
    np.testing.assert_array_equal(given.points, xyz)
    with pytest.raises(InvalidInputError, match="no surface"):
        sample_prior(hills, kind="points", points=[[10.0, 20.0], [150.0, 20.0]])
    with pytest.raises(InvalidInputError):
        sample_prior(hills, kind="points")
    with pytest.raises(InvalidInputError):
        sample_prior(hills, kind="points", points=np.zeros((3, 4)))


def test_prior_bad_arguments(hills):
    with pytest.raises(InvalidInputError):
        sample_prior(hills, kind="grid")
    with pytest.raises(InvalidInputError):
        sample_prior(hills, n=-1)
    with pytest.raises(InvalidTypeError):
        sample_prior(hills, n=3.5)
    with pytest.raises(InvalidTypeError):
        sample_prior(np.zeros((5, 5)))
    with pytest.raises(InvalidTypeError):
        sample_prior(hills, rng="x")


def test_prior_avoids_nodata_holes():
    z = np.zeros((21, 21))
    z[5:16, 5:16] = np.nan  # a big hole in the middle
    z[20, 20] = np.nan  # and a nodata corner
    terrain = Terrain.from_grid(z, 1.0)
    with pytest.warns(UserWarning, match="corner"):
        prior = sample_prior(terrain, n=100, rng=0)
    assert prior.n_points == 103  # the nodata corner is left out
    assert np.isfinite(prior.points).all()
    hole = (prior.points[:, :2] > 5.0).all(axis=1) & (prior.points[:, :2] < 15.0).all(axis=1)
    assert not hole.any()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(InvalidInputError, match="centre"):
            sample_prior(terrain, kind="pyramid")


def test_prior_pickles(hills):
    prior = sample_prior(hills, n=5, rng=0)
    again = pickle.loads(pickle.dumps(prior))
    np.testing.assert_array_equal(again.points, prior.points)
    assert again.kind == prior.kind
    assert not prior.points.flags.writeable


# --------------------------------------------------------------------------------------------
# Bad samples


def test_fewer_than_three_samples():
    with pytest.raises(InvalidInputError, match="at least 3"):
        approximate_surface(np.array([[0, 0, 0], [1, 0, 0.0]]))
    with pytest.raises(InvalidInputError):
        approximate_surface(np.zeros((0, 3)))


def test_collinear_samples():
    line = np.column_stack([np.linspace(0, 10, 7), np.linspace(0, 5, 7), np.arange(7.0)])
    with pytest.raises(InvalidInputError, match="line"):
        approximate_surface(line)


def test_duplicate_samples_are_merged_when_consistent():
    points = np.array([[0, 0, 1], [4, 0, 2], [0, 4, 3], [4, 4, 4], [4, 0, 2], [0, 0, 1.0]])
    surface = approximate_surface(points)
    assert surface.n_vertices == 4
    np.testing.assert_allclose(surface.ground_height([[1.0, 2.0]]), LinearNDInterpolator(points[:4, :2], points[:4, 2])([[1.0, 2.0]]))
    with pytest.raises(InvalidInputError, match="at least 3 distinct"):
        approximate_surface(np.array([[0, 0, 1], [0, 0, 1], [1, 1, 2.0]]))


def test_duplicate_samples_with_different_heights():
    points = np.array([[0, 0, 1], [4, 0, 2], [0, 4, 3], [4, 0, 2.5]])
    with pytest.raises(InvalidInputError, match="share"):
        approximate_surface(points)


def test_nan_heights():
    points = np.array([[0, 0, 1], [4, 0, np.nan], [0, 4, 3], [4, 4, 1.0]])
    with pytest.raises(InvalidInputError, match="NaN"):
        approximate_surface(points)
    with pytest.raises(InvalidInputError):
        approximate_surface(np.array([[0, 0, 1], [4, 0, np.inf], [0, 4, 3.0]]))


def test_wrong_shapes_and_types():
    with pytest.raises(InvalidInputError):
        approximate_surface(np.zeros((5, 2)))
    with pytest.raises(InvalidTypeError):
        approximate_surface("points")
    with pytest.raises(InvalidInputError):
        Prior(np.zeros((3, 2)))


# --------------------------------------------------------------------------------------------
# Approximation error


def test_approximation_error_against_brute_force(hills):
    prior = sample_prior(hills, n=30, rng=4)
    surface = prior.surface()
    result = approximation_error(hills, surface, resolution=2.0)
    centres = np.arange(50) * 2.0 + 1.0
    x, y = np.meshgrid(centres, centres)
    xy = np.column_stack([x.ravel(), y.ravel()])
    error = LinearNDInterpolator(prior.points[:, :2], prior.points[:, 2])(xy) - grid_height(xy, hills.grid.z, (2.0, 2.0))
    assert result.n_points == 2500 and result.n_outside == 0
    assert result.rms == pytest.approx(float(np.sqrt(np.mean(error**2))), rel=1e-9)
    assert result.mean == pytest.approx(float(np.mean(error)), rel=1e-9, abs=1e-12)
    assert result.max_abs == pytest.approx(float(np.max(np.abs(error))), rel=1e-9)


def test_approximation_error_of_exact_surface_is_zero():
    # A plane is reproduced exactly by any triangulation of its points.
    z = np.fromfunction(lambda i, j: 0.3 * j - 0.2 * i + 4.0, (11, 11))
    truth = Terrain.from_grid(z, 1.0)
    prior = sample_prior(truth, n=6, rng=1)
    result = approximation_error(truth, prior.surface())
    assert result.rms < 1e-9 and result.max_abs < 1e-9


def test_approximation_error_counts_points_outside():
    truth = Terrain.from_grid(np.zeros((11, 11)), 1.0)
    partial = approximate_surface(np.array([[0, 0, 0], [10, 0, 0], [0, 10, 0.0]]))  # half the square
    result = approximation_error(truth, partial, resolution=1.0)
    assert result.n_points + result.n_outside == 100
    assert result.n_outside == 45  # cell centres above the diagonal x + y = 10
    assert result.rms == 0.0


def test_error_falls_as_samples_grow():
    """The trend the docs' table shows, on fewer and coarser terrains so it runs fast."""
    counts = (5, 30, 50, 200)
    rms = np.zeros((6, len(counts)))
    for seed in range(6):
        truth = gaussian_hills(spacing=2.0, rng=seed)
        for k, n in enumerate(counts):
            rms[seed, k] = approximation_error(truth, sample_prior(truth, n=n, rng=1000 + seed).surface()).rms
    mean = rms.mean(axis=0)
    assert np.all(np.diff(mean) < 0), mean
    assert mean[-1] < 0.25 * mean[0]


def test_error_of_the_analytic_mixture_is_small_with_many_samples():
    # Interpolation error of a smooth surface falls like h^2: 2000 samples on 100 m (h ~ 2 m)
    # against sigma = 10 m hills gives errors of a few centimetres to decimetres.
    mixture = random_gaussian_mixture(rng=2)
    truth = mixture.terrain(100.0, 1.0)
    result = approximation_error(truth, sample_prior(truth, n=2000, rng=0).surface())
    assert result.rms < 0.15


# --------------------------------------------------------------------------------------------
# Buildings prior

BOXES = (
    Building(2.0, 2.0, 6.0, 5.0, 4.0),
    Building(9.0, 3.0, 12.0, 9.0, 7.0),
    Building(3.0, 9.0, 7.0, 11.0, 2.5),
)


def test_exact_box_map_is_the_scene():
    truth = buildings_terrain(BOXES, size=14.0, spacing=0.5)
    exact = buildings_prior(BOXES, size=14.0, kind="boxes", spacing=1.0, position_error=0.0, size_error=0.0, height_error=0.0)
    assert exact.area == pytest.approx(truth.area)
    xy = np.random.default_rng(0).uniform(0.1, 13.9, size=(300, 2))
    np.testing.assert_allclose(exact.ground_height(xy), truth.ground_height(xy), atol=1e-9)


def test_noisy_box_map_differs_but_is_a_scene():
    truth = buildings_terrain(BOXES, size=14.0, spacing=0.5)
    noisy = buildings_prior(BOXES, size=14.0, spacing=1.0, rng=3)
    again = buildings_prior(BOXES, size=14.0, spacing=1.0, rng=3)
    np.testing.assert_array_equal(noisy.vertices, again.vertices)
    xy = np.random.default_rng(0).uniform(0.1, 13.9, size=(500, 2))
    assert not np.allclose(noisy.ground_height(xy), truth.ground_height(xy))
    assert np.isfinite(noisy.ground_height(xy)).all()


def test_corner_prior():
    prior = building_corner_prior(BOXES, size=14.0, known_fraction=2 / 3, rng=0)
    assert prior.n_points == 4 + 2 * 4 and prior.kind == "corners"
    roofs = prior.points[4:]
    heights = sorted(set(roofs[:, 2]))
    assert set(heights) <= {4.0, 7.0, 2.5} and len(heights) == 2
    surface = buildings_prior(BOXES, size=14.0, kind="corners", known_fraction=2 / 3, height_error=0.0, rng=0)
    np.testing.assert_allclose(surface.ground_height(roofs[:, :2] + 1e-9 * np.sign(7.0 - roofs[:, :2])), roofs[:, 2], atol=1e-6)
    ground_only = building_corner_prior(BOXES, size=14.0, known_fraction=0.0, rng=0)
    assert ground_only.n_points == 4
    with pytest.raises(InvalidInputError):
        building_corner_prior(BOXES, known_fraction=1.5)


def test_buildings_prior_bad_arguments():
    with pytest.raises(InvalidInputError):
        buildings_prior(BOXES, size=14.0, kind="sketch")
    with pytest.raises(InvalidTypeError):
        buildings_prior([(1, 2, 3, 4, 5)], size=14.0)
    with pytest.raises(InvalidInputError):
        buildings_prior(BOXES, size=14.0, spacing=-1.0)


def test_prior_of_a_buildings_scene_reads_roofs_and_ground():
    truth = buildings_terrain(BOXES, size=14.0, spacing=0.5)
    prior = sample_prior(truth, n=300, rng=2)
    np.testing.assert_array_equal(prior.points[-4:, 2], 0.0)  # the ground corners
    expected = np.zeros(prior.n_points)
    for box in BOXES:
        inside = (
            (prior.points[:, 0] > box.xmin)
            & (prior.points[:, 0] < box.xmax)
            & (prior.points[:, 1] > box.ymin)
            & (prior.points[:, 1] < box.ymax)
        )
        expected[inside] = box.height
    np.testing.assert_allclose(prior.points[:, 2], expected, atol=1e-9)
    assert (prior.points[:, 2] > 0).sum() > 30  # some samples do land on roofs


@settings(max_examples=40, deadline=None)
@given(
    cells=st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=3, max_size=25, unique=True),
    seed=st.integers(0, 2**31 - 1),
)
def test_surface_equals_scipy_on_lattice_points(cells, seed):
    """Lattice points are full of cocircular quadruples and collinear triples: S' must still be
    scipy's interpolant wherever that is defined, and refuse only truly collinear sets."""
    xy = np.array(cells, dtype=float)
    rng = np.random.default_rng(seed)
    points = np.column_stack([xy, rng.uniform(-3.0, 3.0, size=len(xy))])
    centred = xy - xy.mean(axis=0)
    if np.linalg.matrix_rank(centred) < 2:
        with pytest.raises(InvalidInputError):
            approximate_surface(points)
        return
    surface = approximate_surface(points)
    query = interior_points(points, 200, rng)
    if len(query) == 0:
        return
    expected = LinearNDInterpolator(points[:, :2], points[:, 2])(query)
    np.testing.assert_allclose(surface.ground_height(query), expected, rtol=1e-9, atol=1e-9)
