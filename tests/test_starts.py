"""The initial positions of the paper's comparison (uavcov.placement._starts): CVT, random and corner,
through their one door, :func:`uavcov.placement.start_configuration`."""

from __future__ import annotations

import numpy as np
import pytest

from uavcov import Terrain, errors
from uavcov.limits import Constraints
from uavcov.placement import CORNERS, START_KINDS, CVTSettings, StartSettings, cvt, start_configuration


def _slope(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return 0.1 * x + 0.05 * y + 3.0 * np.sin(x / 7.0)


@pytest.fixture(scope="module")
def terrain() -> Terrain:
    """A 40 m x 30 m rolling surface on a 1 m grid, origin (10, -5)."""
    xs, ys = np.arange(0.0, 40.5, 1.0), np.arange(0.0, 30.5, 1.0)
    x, y = np.meshgrid(xs, ys)
    return Terrain.from_grid(_slope(x + 10.0, y - 5.0), spacing=1.0, origin=(10.0, -5.0))


def place(kind: str, surface: Terrain, n: int, *, altitude: float = 0.0, corner: str = "sw", spacing: float = 3.0, **kwargs):
    """``n`` positions of ``kind`` on ``surface``, ``altitude`` metres above it (S' and the real
    surface one and the same, heights measured from S')."""
    spec = StartSettings(kind=kind, altitude=altitude, altitude_reference="prior", corner=corner, corner_spacing=spacing)
    positions, _ = start_configuration(spec, surface, surface, n, **kwargs)
    return positions


def test_kinds_share_one_interface(terrain: Terrain) -> None:
    for kind in START_KINDS:
        if kind == "greedy":  # a placement in the flight band, for a sensing range
            with pytest.raises(errors.InvalidInputError, match="d_max"):
                place(kind, terrain, 6, rng=1)
            limits = Constraints(h_min=1.0, h_max=5.0, z_max=60.0, d_safe=2.0)
            positions = place(kind, terrain, 6, altitude=3.0, rng=1, d_max=10.0, constraints=limits)
            clearance = terrain.clearance(positions)  # one layer of candidates, at the start's altitude
            assert positions.shape == (6, 3)
            np.testing.assert_allclose(clearance, 3.0, atol=1e-9)
            continue
        positions = place(kind, terrain, 6, rng=1)
        assert positions.shape == (6, 3) and positions.dtype == np.float64
        # All on the surface: z is the ground height below.
        np.testing.assert_allclose(positions[:, 2], terrain.ground_height(positions[:, :2]), atol=1e-9)


def test_cvt_start_is_the_cvt(terrain: Terrain) -> None:
    positions = place("cvt", terrain, 5, rng=3, altitude=5.0, cvt_settings=CVTSettings(preset="lloyd"))
    expected = cvt(terrain, 5, rng=3, preset="lloyd").generators
    np.testing.assert_array_equal(positions[:, :2], expected[:, :2])
    np.testing.assert_allclose(positions[:, 2], expected[:, 2] + 5.0)


def test_random_start_is_uniform_over_the_region(terrain: Terrain) -> None:
    positions = place("random", terrain, 4000, rng=7)
    lo, hi = terrain.bounds[0], terrain.bounds[1]
    assert (positions[:, :2] >= lo[:2]).all() and (positions[:, :2] <= hi[:2]).all()
    # Uniform in x-y: each quarter of the rectangle holds a quarter of the points (4 sigma).
    centre = (lo[:2] + hi[:2]) / 2
    quarter = (positions[:, 0] < centre[0]) & (positions[:, 1] < centre[1])
    assert abs(quarter.mean() - 0.25) < 4 * np.sqrt(0.25 * 0.75 / 4000)
    np.testing.assert_array_equal(positions, place("random", terrain, 4000, rng=7))
    assert not np.array_equal(positions, place("random", terrain, 4000, rng=8))


def test_random_start_avoids_nodata() -> None:
    z = np.zeros((21, 21))
    z[:, :10] = np.nan  # the western half has no surface
    holey = Terrain.from_grid(z, spacing=1.0)
    positions = place("random", holey, 500, rng=0)
    assert (positions[:, 0] >= 10.0).all()
    assert np.isfinite(positions).all()


@pytest.mark.parametrize("corner", CORNERS)
def test_corner_lattice(terrain: Terrain, corner: str) -> None:
    n, spacing = 7, 3.0
    positions = place("corner", terrain, n, corner=corner, spacing=spacing, altitude=2.0)
    (xmin, ymin, _), (xmax, ymax, _) = terrain.bounds
    x_edge = xmin if corner in ("sw", "nw") else xmax
    y_edge = ymin if corner in ("sw", "se") else ymax
    # 7 UAVs: 3 columns, 3 rows; every point a multiple of the spacing from the corner + s/2.
    dx = np.abs(positions[:, 0] - x_edge) - spacing / 2
    dy = np.abs(positions[:, 1] - y_edge) - spacing / 2
    np.testing.assert_allclose(dx / spacing, np.round(dx / spacing), atol=1e-9)
    np.testing.assert_allclose(dy / spacing, np.round(dy / spacing), atol=1e-9)
    assert dx.max() == pytest.approx(2 * spacing) and dy.max() == pytest.approx(2 * spacing)
    # Compact: nearest neighbours exactly one spacing apart in x-y, no duplicates.
    d = np.linalg.norm(positions[:, None, :2] - positions[None, :, :2], axis=-1)
    np.fill_diagonal(d, np.inf)
    np.testing.assert_allclose(d.min(axis=1), spacing)
    np.testing.assert_allclose(positions[:, 2], terrain.ground_height(positions[:, :2]) + 2.0)


def test_corner_is_deterministic(terrain: Terrain) -> None:
    a = place("corner", terrain, 9, rng=1)
    b = place("corner", terrain, 9, rng=2)
    np.testing.assert_array_equal(a, b)


def test_corner_that_does_not_fit(terrain: Terrain) -> None:
    with pytest.raises(errors.InfeasibleError):
        place("corner", terrain, 200, spacing=3.0)  # 15 x 14 lattice: 45 m > 40 m
    z = np.zeros((11, 11))
    z[0, 0] = np.nan  # nodata at the south-west corner
    with pytest.raises(errors.InfeasibleError, match=r"at x-y \(0\.5, 0\.5\) m stands over no surface .*StartSettings\(corner="):
        place("corner", Terrain.from_grid(z, spacing=1.0), 1, spacing=1.0)  # plain numbers, and what to do


@pytest.mark.parametrize(
    "settings, kwargs, error",
    [
        ({"kind": "grid"}, {}, errors.InvalidInputError),
        ({"kind": 3}, {}, errors.InvalidInputError),
        ({"kind": "random"}, {"n": 0}, errors.InvalidInputError),
        ({"kind": "random"}, {"n": 1.5}, errors.InvalidTypeError),
        ({"kind": "random", "altitude": -1.0}, {}, errors.InvalidInputError),
        ({"kind": "random", "altitude": np.nan}, {}, errors.InvalidInputError),
        ({"kind": "corner", "corner_spacing": 0.0}, {}, errors.InvalidInputError),
        ({"kind": "corner", "corner": "north"}, {}, errors.InvalidInputError),
        ({"kind": "corner", "corner": 1}, {}, errors.InvalidInputError),
        ({"kind": "random"}, {"rng": "seed"}, errors.InvalidTypeError),
        ({"kind": "cvt"}, {"cvt_settings": {"preset": "lloyd"}}, errors.InvalidTypeError),
        ({"kind": "cvt"}, {"n_threads": 0}, errors.InvalidInputError),
        ({"kind": "greedy"}, {}, errors.InvalidInputError),  # no sensing range
    ],
)
def test_bad_input_raises(terrain: Terrain, settings: dict, kwargs: dict, error: type) -> None:
    arguments = {"n": 4, **kwargs}
    n = arguments.pop("n")
    with pytest.raises(error):
        start_configuration(StartSettings(**settings), terrain, terrain, n, **arguments)


def test_bad_surface_raises(terrain: Terrain) -> None:
    with pytest.raises(errors.InvalidTypeError, match="approximation"):
        start_configuration(StartSettings(kind="random"), np.zeros((4, 3)), terrain, 3)  # type: ignore[arg-type]
    with pytest.raises(errors.InvalidTypeError, match="terrain"):
        start_configuration(StartSettings(kind="random"), terrain, "hills", 3)  # type: ignore[arg-type]
    with pytest.raises(errors.InvalidTypeError, match="StartSettings"):
        start_configuration("random", terrain, terrain, 3)  # type: ignore[arg-type]
