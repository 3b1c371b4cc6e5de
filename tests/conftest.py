"""Shared fixtures: small random meshes and small grid terrains from analytic height functions.

Everything is small on purpose (a few hundred triangles): the brute-force reference in
``reference.py`` is O(pairs x triangles) and the whole suite must stay fast.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from reference import grid_mesh


def hills(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Three Gaussian hills over a gentle slope (metres), smooth and with real occlusions."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    z = 0.05 * x - 0.02 * y
    for cx, cy, height, sigma in ((4.0, 8.0, 6.0, 3.0), (12.0, 14.0, 9.0, 2.5), (14.0, 5.0, 4.0, 4.0)):
        z = z + height * np.exp(-((x - cx) ** 2 + (y - cy) ** 2) / (2.0 * sigma**2))
    return z


@dataclass(frozen=True)
class GridCase:
    """An elevation grid and its triangulation built by the reference (not by the engine)."""

    z: np.ndarray  # (ny, nx)
    spacing: tuple[float, float]  # (dx, dy)
    origin: tuple[float, float]  # (ox, oy)
    vertices: np.ndarray  # (ny*nx, 3), vertex (i, j) at index i*nx + j
    faces: np.ndarray  # (F, 3)

    @property
    def xy_max(self) -> tuple[float, float]:
        ny, nx = self.z.shape
        return (self.origin[0] + (nx - 1) * self.spacing[0], self.origin[1] + (ny - 1) * self.spacing[1])

    def valid_vertices(self) -> np.ndarray:
        return self.vertices[np.isfinite(self.vertices[:, 2])]


def make_grid_case(z: np.ndarray, spacing: tuple[float, float], origin: tuple[float, float]) -> GridCase:
    z = np.asarray(z, dtype=np.float64)
    vertices, faces = grid_mesh(z, spacing, origin)
    return GridCase(z=z, spacing=spacing, origin=origin, vertices=vertices, faces=faces)


def hills_grid_case(
    nx: int = 17, ny: int = 14, spacing: tuple[float, float] = (1.1, 1.3), origin: tuple[float, float] = (0.5, -0.7)
) -> GridCase:
    xs = origin[0] + np.arange(nx) * spacing[0]
    ys = origin[1] + np.arange(ny) * spacing[1]
    x, y = np.meshgrid(xs, ys)  # (ny, nx): row i is y, column j is x
    return make_grid_case(hills(x, y), spacing, origin)


def random_grid_case(seed: int, nx: int = 13, ny: int = 11) -> GridCase:
    """Rough random heights (0-6 m) on an anisotropic grid: many occluding ridges."""
    rng = np.random.default_rng(seed)
    z = rng.uniform(0.0, 6.0, size=(ny, nx))
    return make_grid_case(z, (1.5, 1.2), (-2.0, 3.0))


def random_soup(seed: int, n_triangles: int = 300, box: float = 20.0) -> tuple[np.ndarray, np.ndarray]:
    """A soup of random triangles (about 2 m across) in a ``box x box x box/2`` volume."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform([0.0, 0.0, 0.0], [box, box, box / 2], size=(n_triangles, 3))
    offsets = rng.normal(scale=1.2, size=(n_triangles, 3, 3))
    vertices = (centres[:, None, :] + offsets).reshape(-1, 3)
    faces = np.arange(3 * n_triangles, dtype=np.int64).reshape(-1, 3)
    return vertices, faces


def random_points_in_box(rng: np.random.Generator, n: int, box: float = 20.0) -> np.ndarray:
    return rng.uniform([0.0, 0.0, 0.0], [box, box, box / 2], size=(n, 3))


def uavs_above(case: GridCase, n: int, rng: np.random.Generator, low: float = 0.5, high: float = 8.0) -> np.ndarray:
    """``n`` random points above a grid terrain, ``low``-``high`` metres over the analytic ground."""
    from reference import grid_height

    ox, oy = case.origin
    xmax, ymax = case.xy_max
    xy = rng.uniform([ox, oy], [xmax, ymax], size=(n, 2))
    ground = grid_height(xy, case.z, case.spacing, case.origin)
    return np.column_stack([xy, ground + rng.uniform(low, high, size=n)])


def flat_grid_case(half: float, step: float) -> GridCase:
    """The plane z = 0 on [-half, half]^2 sampled every ``step`` metres."""
    n = round(2 * half / step) + 1
    return make_grid_case(np.zeros((n, n)), (step, step), (-half, -half))


@pytest.fixture(scope="session")
def hill_grid() -> GridCase:
    return hills_grid_case()


@pytest.fixture(scope="session")
def hill_terrain(hill_grid: GridCase):
    from uavcov import Terrain

    return Terrain.from_grid(hill_grid.z, hill_grid.spacing, origin=hill_grid.origin)


@pytest.fixture(scope="session")
def soup() -> tuple[np.ndarray, np.ndarray]:
    return random_soup(7)
