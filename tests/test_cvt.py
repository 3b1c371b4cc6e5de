"""The constrained CVT (uavcov.placement._cvt) against scikit-learn's k-means, the surface, and bad input."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from sklearn.cluster import KMeans
from threadpoolctl import threadpool_limits

from uavcov import Terrain, errors
from uavcov.placement import PRESETS, CVTResult, cvt
from uavcov.placement._cvt import default_samples_per_iteration, seed_from_rng

SIDE = 100.0


@pytest.fixture(scope="module")
def square() -> Terrain:
    """The flat 100 m square, two triangles."""
    return Terrain.from_grid(np.zeros((2, 2)), spacing=SIDE)


@pytest.fixture(scope="module")
def dense() -> np.ndarray:
    """20 000 uniform points of the square (z = 0): the common yardstick for energies."""
    xy = np.random.default_rng(123).uniform(0.0, SIDE, size=(20_000, 2))
    return np.column_stack([xy, np.zeros(len(xy))])


def energy(generators: np.ndarray, points: np.ndarray) -> float:
    """Mean squared distance from the points to their nearest generator (m^2)."""
    d2 = ((points[:, None, :] - np.asarray(generators)[None, :, :]) ** 2).sum(axis=-1)
    return float(d2.min(axis=1).mean())


def hills(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    z = np.zeros_like(x)
    for cx, cy, height, sigma in ((15.0, 20.0, 18.0, 8.0), (45.0, 40.0, 12.0, 10.0), (40.0, 10.0, 8.0, 6.0)):
        z = z + height * np.exp(-((x - cx) ** 2 + (y - cy) ** 2) / (2.0 * sigma**2))
    return z


@pytest.fixture(scope="module")
def hilly() -> Terrain:
    """A 60 m square with three hills up to 18 m, 2 m grid (1800 triangles)."""
    xs = np.arange(0.0, 60.0 + 1e-9, 2.0)
    x, y = np.meshgrid(xs, xs)
    return Terrain.from_grid(hills(x, y), spacing=2.0)


# -- correctness against an independent reference ------------------------------------------------


def _kmeans(points: np.ndarray, **kwargs) -> KMeans:
    """k-means run to convergence (tol 1e-10) on the points' x-y, on one thread: OpenMP's
    spinning workers next to the Rust pool slow a 2-core machine down tenfold."""
    with threadpool_limits(1):
        return KMeans(tol=1e-10, max_iter=3000, **kwargs).fit(points[:, :2])


@pytest.mark.parametrize("n", [5, 8, 12, 20])
def test_energy_matches_kmeans(square: Terrain, dense: np.ndarray, n: int) -> None:
    """The converged CVT's energy is within 2 % of scikit-learn's k-means (Lloyd) energy.

    Both start from the same random generators, so they face the same local minima: k-means is
    run to convergence on the dense sample set (tol 1e-10), the CVT with its default settings and
    stopping rule. Five starts per N; the median ratio must be within 2 % and no single start
    worse than 4 % (a start can drift into a different basin than deterministic Lloyd's). The
    best of ten k-means++ runs bounds every CVT from below: an energy under it would mean the
    energies are not computed alike.
    """
    best = _kmeans(dense, n_clusters=n, n_init=10, random_state=0)
    floor = energy(np.column_stack([best.cluster_centers_, np.zeros(n)]), dense)
    ratios = []
    for seed in range(5):
        start = np.column_stack([np.random.default_rng(1000 + seed).uniform(0.0, SIDE, (n, 2)), np.zeros(n)])
        result = cvt(square, n, initial=start, rng=seed)
        assert result.converged, f"n={n} seed={seed}: not converged in {result.iterations} iterations"
        lloyd = _kmeans(dense, n_clusters=n, init=start[:, :2], n_init=1)
        reference = energy(np.column_stack([lloyd.cluster_centers_, np.zeros(n)]), dense)
        mine = energy(result.generators, dense)
        assert mine >= 0.99 * floor, (mine, floor)
        ratios.append(mine / reference)
    ratios = np.array(ratios)
    assert abs(np.median(ratios) - 1.0) <= 0.02, ratios
    assert ratios.max() <= 1.04, ratios


def test_energy_history_estimates_the_energy(square: Terrain, dense: np.ndarray) -> None:
    """The recorded Monte-Carlo energy agrees with the energy on an independent dense set."""
    result = cvt(square, 6, rng=4, tol=0.0, max_iterations=60)
    late = result.energy[-20:].mean()  # the generators barely move over the last 20 iterations
    assert late == pytest.approx(energy(result.generators, dense), rel=0.02)
    assert result.energy[0] > 1.2 * late  # from a random start the energy falls


def test_two_generators_split_a_rectangle(square: Terrain) -> None:
    """Analytic case: the CVT of 2 generators on a 2:1 rectangle is its two squares' centres."""
    rectangle = Terrain.from_grid(np.zeros((2, 3)), spacing=SIDE)  # 200 m x 100 m
    result = cvt(rectangle, 2, rng=0, tol=0.02)
    g = result.generators[np.argsort(result.generators[:, 0])]
    np.testing.assert_allclose(g[:, :2], [[50.0, 50.0], [150.0, 50.0]], atol=2.0)


def test_generators_lie_on_the_surface(hilly: Terrain) -> None:
    result = cvt(hilly, 9, rng=3)
    gap = np.linalg.norm(hilly.closest_point(result.generators) - result.generators, axis=1)
    assert gap.max() < 1e-6
    assert (result.generators[:, 2] > 0.5).any()  # on the hills, not on a flat plane


def test_regions_have_near_equal_area_on_hills(hilly: Terrain) -> None:
    """Region areas on a hilly surface: coefficient of variation under 0.2 (random: 0.2-1.3).

    Measured for N = 8 over seeds 0-7: CVT 0.07-0.14, random generators on the surface
    0.20-1.06. A CVT of a bounded region is not exactly equal-area (border regions differ).
    """
    targets = hilly.default_targets(density=2.0)
    cvt_cv, random_cv = [], []
    for seed in range(3):
        result = cvt(hilly, 8, rng=seed)
        areas = np.bincount(result.regions(targets.points), weights=targets.weights, minlength=8)
        assert areas.sum() == pytest.approx(hilly.area)
        cvt_cv.append(areas.std() / areas.mean())
        xy = np.random.default_rng(seed).uniform(0.0, 60.0, size=(8, 2))
        random = CVTResult(np.column_stack([xy, hilly.ground_height(xy)]), [], [], [], 0, False, 0)
        areas = np.bincount(random.regions(targets.points), weights=targets.weights, minlength=8)
        random_cv.append(areas.std() / areas.mean())
    print(f"coefficient of variation of region areas: CVT {np.round(cvt_cv, 3)}, random {np.round(random_cv, 3)}")
    assert max(cvt_cv) < 0.2
    assert np.mean(cvt_cv) < 0.5 * np.mean(random_cv)


def test_regions_match_brute_force(hilly: Terrain) -> None:
    result = cvt(hilly, 7, rng=1)
    points = np.random.default_rng(2).uniform([0, 0, 0], [60, 60, 20], size=(3000, 3))
    d2 = ((points[:, None, :] - result.generators[None]) ** 2).sum(-1)
    labels = result.regions(points)
    assert labels.dtype == np.int64 and labels.shape == (3000,)
    np.testing.assert_array_equal(labels, d2.argmin(axis=1))
    assert result.regions(np.empty((0, 3))).shape == (0,)


def test_density_pulls_generators(square: Terrain) -> None:
    """All density on the left half of the square: every generator there, and a callable
    evaluated at triangle centroids gives the same run as the equivalent per-triangle array."""
    fine = Terrain.from_grid(np.zeros((11, 11)), spacing=10.0)
    left = lambda p: (p[:, 0] < 50.0).astype(float)  # noqa: E731
    result = cvt(fine, 5, rng=2, density=left)
    assert (result.generators[:, 0] <= 50.0 + 1e-9).all()
    centroids = fine.vertices[fine.faces].mean(axis=1)
    same = cvt(fine, 5, rng=2, density=left(centroids))
    np.testing.assert_array_equal(result.generators, same.generators)
    # A density rising to the right moves the mean generator right of the centre.
    ramp = cvt(fine, 5, rng=2, density=lambda p: 1.0 + (p[:, 0] / 10.0) ** 2)
    assert ramp.generators[:, 0].mean() > 55.0


def test_annealed_refinement_reduces_jitter() -> None:
    """From the exact CVT of a 2:1 rectangle, the annealed preset's generators scatter less
    than the damped preset's (their sampling noise is averaged over more iterations)."""
    rectangle = Terrain.from_grid(np.zeros((2, 3)), spacing=SIDE)
    exact = np.array([[50.0, 50.0, 0.0], [150.0, 50.0, 0.0]])
    error = {}
    for preset in ("damped", "annealed"):
        error[preset] = np.mean(
            [
                np.linalg.norm(
                    cvt(rectangle, 2, preset=preset, initial=exact, rng=s, tol=0.0, max_iterations=40).generators - exact, axis=1
                ).mean()
                for s in range(12)
            ]
        )
    assert error["annealed"] < 0.7 * error["damped"], error


# -- the history and the result object ------------------------------------------------------------


def test_history_and_stopping_rule(hilly: Terrain) -> None:
    window = 4
    result = cvt(hilly, 6, rng=5, window=window, tol=0.15)
    k = result.iterations
    assert result.moves.shape == result.drift.shape == result.energy.shape == (k,)
    assert np.isnan(result.drift[: window - 1]).all()
    assert np.isfinite(result.drift[window - 1 :]).all()
    assert result.converged and result.drift[-1] < 0.15
    assert (result.drift[window - 1 : -1] >= 0.15).all()  # it stopped at the first chance
    # The net move over a window never exceeds the sum of the moves in it.
    for j in range(window - 1, k):
        assert result.drift[j] * window <= result.moves[j - window + 1 : j + 1].sum() + 1e-9
    capped = cvt(hilly, 6, rng=5, tol=0.0, max_iterations=7)
    assert capped.iterations == 7 and not capped.converged


def test_result_is_frozen_and_pickles(square: Terrain) -> None:
    result = cvt(square, 3, rng=0)
    with pytest.raises(ValueError, match="read-only"):
        result.generators[0, 0] = 1.0
    with pytest.raises(AttributeError):
        result.iterations = 3  # type: ignore[misc]
    back = pickle.loads(pickle.dumps(result))
    np.testing.assert_array_equal(back.generators, result.generators)
    np.testing.assert_array_equal(back.drift, result.drift)
    assert (back.iterations, back.converged, back.seed, back.n_generators) == (result.iterations, result.converged, result.seed, 3)


# -- determinism ------------------------------------------------------------------------------------


def _same(a: CVTResult, b: CVTResult) -> bool:
    return (
        np.array_equal(a.generators, b.generators)
        and np.array_equal(a.moves, b.moves)
        and np.array_equal(a.drift, b.drift, equal_nan=True)
        and np.array_equal(a.energy, b.energy)
        and a.iterations == b.iterations
    )


@pytest.mark.parametrize("surface_name", ["square", "hilly"])
def test_same_seed_any_thread_count(request: pytest.FixtureRequest, surface_name: str) -> None:
    """Both search paths: per-triangle candidates (coarse square) and brute force (fine grid)."""
    surface = request.getfixturevalue(surface_name)
    one = cvt(surface, 7, rng=11, n_threads=1, samples_per_iteration=5000)
    two = cvt(surface, 7, rng=11, n_threads=2, samples_per_iteration=5000)
    assert _same(one, two)


def test_rng_semantics(square: Terrain) -> None:
    assert _same(cvt(square, 4, rng=8), cvt(square, 4, rng=8))
    assert not np.array_equal(cvt(square, 4, rng=8).generators, cvt(square, 4, rng=9).generators)
    # A Generator is advanced by one draw: seeding it the same way reproduces the run.
    a = cvt(square, 4, rng=np.random.default_rng(8))
    assert a.seed == seed_from_rng(8)
    assert _same(a, cvt(square, 4, rng=8))
    generator = np.random.default_rng(8)
    first, second = cvt(square, 4, rng=generator), cvt(square, 4, rng=generator)
    assert first.seed != second.seed


def test_defaults() -> None:
    assert default_samples_per_iteration(5) == 2000
    assert default_samples_per_iteration(20) == 4000
    assert PRESETS["damped"] == ((0.5, 0.5), (0.5, 0.5))
    for (a1, a2), (b1, b2) in PRESETS.values():
        assert a1 + a2 == 1.0 and b1 + b2 == 1.0 and a2 > 0 and b2 > 0


# -- bad input --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, error",
    [
        ({"n": 0}, errors.InvalidInputError),
        ({"n": -3}, errors.InvalidInputError),
        ({"n": 2.5}, errors.InvalidTypeError),
        ({"n": 11, "samples_per_iteration": 10}, errors.InvalidInputError),
        ({"samples_per_iteration": 0}, errors.InvalidInputError),
        ({"alpha": (0.5, 0.6)}, errors.InvalidInputError),
        ({"alpha": (1.0, 0.0)}, errors.InvalidInputError),
        ({"beta": (1.0, 0.0)}, errors.InvalidInputError),
        ({"alpha": (-0.5, 1.5)}, errors.InvalidInputError),
        ({"alpha": (np.nan, 0.5)}, errors.InvalidInputError),
        ({"alpha": (0.5, 0.25, 0.25)}, errors.InvalidInputError),
        ({"alpha": "damped"}, errors.InvalidTypeError),
        ({"preset": "fast"}, errors.InvalidInputError),
        ({"preset": None}, errors.InvalidTypeError),
        ({"tol": -0.1}, errors.InvalidInputError),
        ({"tol": np.inf}, errors.InvalidInputError),
        ({"window": 0}, errors.InvalidInputError),
        ({"max_iterations": 0}, errors.InvalidInputError),
        ({"density": np.array([1.0, -1.0])}, errors.InvalidInputError),
        ({"density": np.array([1.0, np.nan])}, errors.InvalidInputError),
        ({"density": np.zeros(2)}, errors.InvalidInputError),
        ({"density": np.ones(3)}, errors.InvalidInputError),
        ({"density": lambda p: np.ones(len(p) + 1)}, errors.InvalidInputError),
        ({"density": lambda p: -np.ones(len(p))}, errors.InvalidInputError),
        ({"density": lambda p: 1 / 0}, errors.InvalidInputError),
        ({"initial": np.zeros((2, 3))}, errors.InvalidInputError),
        ({"initial": np.full((3, 3), np.nan)}, errors.InvalidInputError),
        ({"initial": np.zeros((3, 2))}, errors.InvalidInputError),
        ({"rng": "seed"}, errors.InvalidTypeError),
        ({"n_threads": 0}, errors.InvalidInputError),
    ],
)
def test_bad_input_raises(square: Terrain, kwargs: dict, error: type) -> None:
    arguments = {"n": 3, **kwargs}
    n = arguments.pop("n")
    with pytest.raises(error):
        cvt(square, n, **arguments)


def test_bad_surface_raises() -> None:
    with pytest.raises(errors.InvalidTypeError):
        cvt(np.zeros((3, 3)), 2)  # type: ignore[arg-type]
    # An empty or fully degenerate surface cannot even be built, so never reaches the CVT.
    with pytest.raises(errors.MeshError):
        cvt(Terrain(np.zeros((3, 3)), np.array([[0, 1, 2]])), 2)
    with pytest.raises(errors.MeshError):
        cvt(Terrain(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)), 2)


def test_regions_bad_input(square: Terrain) -> None:
    result = cvt(square, 3, rng=0)
    with pytest.raises(errors.InvalidInputError):
        result.regions(np.zeros((4, 2)))
    with pytest.raises(errors.InvalidInputError):
        result.regions([[np.nan, 0.0, 0.0]])
    with pytest.raises(errors.InvalidTypeError):
        result.regions("points")
