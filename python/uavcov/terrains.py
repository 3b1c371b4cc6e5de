"""The true surfaces: the paper's scenarios and real terrain loaded from files.

Three families, all returning a :class:`~uavcov.surface.Terrain` in a local metric frame
(metres, Z up):

* **Gaussian hills** (the paper's 40 test terrains): a mixture of Gaussians on a square,
  sampled on an elevation grid. :func:`gaussian_hills` draws one; :class:`GaussianMixture`
  is the underlying analytic height function.
* **A buildings scene** (the paper's realistic environment, Figs. 7-8): flat ground with box
  buildings, a true 3D mesh with vertical walls. :func:`random_buildings` draws the boxes,
  :func:`buildings_terrain` meshes them, :func:`buildings_scene` does both, and
  :func:`perturb_buildings` makes the coarse, erroneous map a prior is built from.
* **Real terrain**: elevation grids from numpy arrays (:func:`load_dem`) or GeoTIFF files
  (:func:`load_geotiff`, needs ``rasterio``), meshes from OBJ / STL / PLY files
  (:func:`load_mesh`, needs ``trimesh``) or arrays (:func:`mesh_terrain`), and
  :func:`sample_dem`, a real DEM that matplotlib ships, usable offline.

Loaders return a :class:`LoadedTerrain`: the terrain plus the :class:`LocalFrame` that maps
local coordinates back to the source's (projected metres or geographic degrees). Recentring
matters because georeferenced input (eastings of 500 km, northings of 5000 km) would otherwise
spend most of the float64 mantissa on the offset, and the engine's geometric predicates
(cross products of coordinate differences) would lose millimetres to rounding.

Geographic input is mapped by a local equirectangular projection about the centre latitude of
the data, with the WGS84 radii of curvature there (metres per degree of latitude from the
meridian radius, of longitude from the prime-vertical radius times cos(latitude)). The grid stays
regular; the east-west scale error at a latitude ``dphi`` (radians) from the centre is about
``tan(phi_ref) * |dphi|`` (0.2 % at the edges of matplotlib's 0.29-degree Jacksboro DEM). Fine
for a local coverage mission; use a projected DEM for areas of many kilometres.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from ._validate import (
    as_generator,
    as_finite_float,
    as_float_array,
    as_index_array,
    as_non_negative_float,
    as_non_negative_int,
    as_positive_float,
    as_positive_int,
)
from .errors import InfeasibleError, InvalidInputError, InvalidTypeError, MeshError
from .surface import Terrain

__all__ = [
    "GaussianMixture",
    "random_gaussian_mixture",
    "gaussian_hills",
    "Building",
    "random_buildings",
    "buildings_terrain",
    "buildings_scene",
    "perturb_buildings",
    "LocalFrame",
    "MeshReport",
    "LoadedTerrain",
    "metres_per_degree",
    "load_dem",
    "load_geotiff",
    "mesh_terrain",
    "clean_mesh",
    "load_mesh",
    "sample_dem",
]



def _as_range(value: Any, name: str, *, positive: bool = False) -> tuple[float, float]:
    """A ``(low, high)`` pair of finite floats with ``low <= high`` (a single number means both)."""
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        low = high = as_finite_float(value, name)
    else:
        pair = as_float_array(value, name, ndim=1)
        if pair.shape != (2,):
            raise InvalidInputError(f"{name} must be a number or a (low, high) pair, got shape {pair.shape}")
        low, high = float(pair[0]), float(pair[1])
    if low > high:
        raise InvalidInputError(f"{name} must have low <= high, got ({low}, {high})")
    if positive and low <= 0.0:
        raise InvalidInputError(f"{name} must be > 0, got ({low}, {high})")
    return low, high


def _as_spacing(spacing: Any, name: str = "spacing") -> tuple[float, float]:
    """``spacing`` as ``(dx, dy)``, both finite and > 0."""
    if isinstance(spacing, (int, float, np.integer, np.floating)) and not isinstance(spacing, bool):
        value = as_positive_float(spacing, name)
        return value, value
    pair = as_float_array(spacing, name, ndim=1)
    if pair.shape != (2,):
        raise InvalidInputError(f"{name} must be a number or a (dx, dy) pair, got shape {pair.shape}")
    if not (pair > 0.0).all():
        raise InvalidInputError(f"{name} must be > 0, got {tuple(pair)}")
    return float(pair[0]), float(pair[1])


def _cells(length: float, step: float, name: str) -> int:
    """Number of cells of size ``step`` in ``length``; the division must be (nearly) exact."""
    count = length / step
    cells = int(round(count))
    if cells < 1 or abs(count - cells) > 1e-9 * max(1.0, count):
        raise InvalidInputError(f"{name} ({length} m) must be a positive multiple of the spacing ({step} m)")
    return cells


# ---------------------------------------------------------------------------------------------
# Gaussian hills


@dataclass(frozen=True, eq=False)
class GaussianMixture:
    """A height field that is a sum of isotropic Gaussian bumps over flat ground at z = 0.

    ``z(x, y) = sum_k heights[k] * exp(-|(x, y) - centres[k]|^2 / (2 sigma^2))``

    Attributes
    ----------
    centres : ndarray, shape (k, 2)
        Bump centres (m).
    heights : ndarray, shape (k,)
        Peak height of each bump alone (m); overlapping bumps add up.
    sigma : float
        The common standard deviation (m).
    """

    centres: np.ndarray
    heights: np.ndarray
    sigma: float

    def __post_init__(self) -> None:
        centres = as_float_array(self.centres, "centres")
        heights = as_float_array(self.heights, "heights")
        if centres.size == 0 and heights.size == 0:  # no hills: flat ground
            centres, heights = np.zeros((0, 2)), np.zeros(0)
        if centres.ndim != 2 or centres.shape[1] != 2:
            raise InvalidInputError(f"centres must have shape (k, 2), got {centres.shape}")
        if heights.ndim != 1 or heights.shape[0] != centres.shape[0]:
            raise InvalidInputError(f"heights must have shape ({centres.shape[0]},), got {heights.shape}")
        sigma = as_positive_float(self.sigma, "sigma")
        centres.setflags(write=False)
        heights.setflags(write=False)
        object.__setattr__(self, "centres", centres)
        object.__setattr__(self, "heights", heights)
        object.__setattr__(self, "sigma", sigma)

    def height(self, xy: Any) -> np.ndarray:
        """Heights ``(n,)`` (m) at points ``xy`` of shape ``(n, 2)`` (or ``(2,)``)."""
        points = as_float_array(xy, "xy")
        if points.ndim == 1 and points.shape[0] == 2:
            points = points.reshape(1, 2)
        if points.ndim != 2 or points.shape[1] != 2:
            raise InvalidInputError(f"xy must have shape (n, 2), got {points.shape}")
        return self._evaluate(points[:, 0], points[:, 1])

    def _evaluate(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        z = np.zeros(np.broadcast(x, y).shape)
        scale = -0.5 / self.sigma**2
        for (cx, cy), h in zip(self.centres, self.heights):
            z += h * np.exp(scale * ((x - cx) ** 2 + (y - cy) ** 2))
        return z

    def grid(self, size: float, spacing: float) -> np.ndarray:
        """Heights ``(n, n)`` on the square ``[0, size]^2`` every ``spacing`` m.

        Entry ``[i, j]`` is the height at ``x = j * spacing``, ``y = i * spacing`` (the layout of
        :meth:`Terrain.from_grid`). ``size`` must be a multiple of ``spacing``.
        """
        size = as_positive_float(size, "size")
        spacing = as_positive_float(spacing, "spacing")
        cells = _cells(size, spacing, "size")
        coords = np.arange(cells + 1) * spacing
        x, y = np.meshgrid(coords, coords)
        return self._evaluate(x, y)

    def terrain(self, size: float, spacing: float) -> Terrain:
        """The mixture sampled on ``[0, size]^2`` as a grid :class:`Terrain`."""
        spacing = as_positive_float(spacing, "spacing")
        return Terrain.from_grid(self.grid(size, spacing), spacing, origin=(0.0, 0.0))


def random_gaussian_mixture(
    size: float = 100.0,
    n_hills: int = 7,
    heights: Any = (5.0, 25.0),
    sigma: float = 10.0,
    rng: Any = None,
) -> GaussianMixture:
    """Draw the paper's terrain model: ``n_hills`` Gaussians with random centres and heights.

    Parameters
    ----------
    size : float
        Side of the square ``[0, size]^2`` the centres are drawn in, uniformly (m).
    n_hills : int
        Number of Gaussians (the paper: 7). 0 gives flat ground.
    heights : (float, float) or float
        Peak heights are uniform in this range (m). The paper says only "varying heights";
        [5, 25] m is the starting value of the calibration.
    sigma : float
        The common standard deviation (m); the paper's "fixed variance" is ``sigma**2``.
    rng : None, int or numpy.random.Generator
        Seed or generator. The centres are drawn first (``(n_hills, 2)`` uniforms), then the
        heights (``n_hills`` uniforms), so a seed gives the same hills at every grid spacing.
    """
    size = as_positive_float(size, "size")
    n_hills = as_non_negative_int(n_hills, "n_hills")
    low, high = _as_range(heights, "heights")
    sigma = as_positive_float(sigma, "sigma")
    generator = as_generator(rng)
    centres = generator.uniform(0.0, size, size=(n_hills, 2))
    peak = generator.uniform(low, high, size=n_hills)
    return GaussianMixture(centres=centres, heights=peak, sigma=sigma)


def gaussian_hills(
    size: float = 100.0,
    spacing: float = 1.0,
    n_hills: int = 7,
    heights: Any = (5.0, 25.0),
    sigma: float = 10.0,
    rng: Any = None,
) -> Terrain:
    """The paper's test terrain: a mixture of Gaussians on ``[0, size]^2`` as a grid Terrain.

    Parameters
    ----------
    size : float
        Side of the square (m); default 100 m as in the paper.
    spacing : float
        Grid spacing (m); ``size`` must be a multiple of it. 1 m gives 101 x 101 vertices.
    n_hills, heights, sigma, rng
        See :func:`random_gaussian_mixture` (defaults: 7 hills, heights uniform in [5, 25] m,
        sigma = 10 m). These are starting values to calibrate, not the paper's (unpublished) ones.

    Returns
    -------
    Terrain
        Vertex ``(i, j)`` at ``(j * spacing, i * spacing)``, height from the mixture. Use
        :func:`random_gaussian_mixture` with the same ``rng`` for the analytic height function.
    """
    mixture = random_gaussian_mixture(size=size, n_hills=n_hills, heights=heights, sigma=sigma, rng=rng)
    return mixture.terrain(size, spacing)


# ---------------------------------------------------------------------------------------------
# Buildings


@dataclass(frozen=True)
class Building:
    """An axis-aligned box building standing on the ground at z = 0 (metres)."""

    xmin: float
    ymin: float
    xmax: float
    ymax: float
    height: float

    def __post_init__(self) -> None:
        for name in ("xmin", "ymin", "xmax", "ymax", "height"):
            object.__setattr__(self, name, as_finite_float(getattr(self, name), name))
        if not (self.xmax > self.xmin and self.ymax > self.ymin):
            raise InvalidInputError(f"a building needs xmax > xmin and ymax > ymin, got {self}")
        if self.height <= 0.0:
            raise InvalidInputError(f"a building needs a height > 0, got {self.height}")

    def corners(self) -> np.ndarray:
        """The four roof corners ``(4, 3)``, counter-clockwise from ``(xmin, ymin)``."""
        return np.array(
            [
                [self.xmin, self.ymin, self.height],
                [self.xmax, self.ymin, self.height],
                [self.xmax, self.ymax, self.height],
                [self.xmin, self.ymax, self.height],
            ]
        )

    def gap_to(self, other: "Building") -> float:
        """Horizontal clearance between the two footprints (m); negative when they overlap."""
        gap_x = max(other.xmin - self.xmax, self.xmin - other.xmax)
        gap_y = max(other.ymin - self.ymax, self.ymin - other.ymax)
        return max(gap_x, gap_y)


def _snap(value: float, step: float) -> float:
    return round(value / step) * step


def _layout_ok(buildings: Sequence[Building], size: float, margin: float, gap: float) -> bool:
    tol = 1e-9 * size
    for index, b in enumerate(buildings):
        low, high = margin - tol, size - margin + tol
        if b.xmin < low or b.ymin < low or b.xmax > high or b.ymax > high:
            return False
        for other in buildings[:index]:
            if b.gap_to(other) < gap - tol:
                return False
    return True


def random_buildings(
    size: float = 24.0,
    n_buildings: int = 5,
    footprint: Any = (3.0, 7.0),
    heights: Any = (3.0, 10.0),
    gap: float = 2.0,
    margin: float = 1.0,
    step: float = 0.5,
    max_attempts: int = 1000,
    rng: Any = None,
) -> tuple[Building, ...]:
    """Draw non-overlapping box buildings on a ``size x size`` square of ground.

    Parameters
    ----------
    size : float
        Side of the ground square ``[0, size]^2`` (m); the paper's scene is 24 m.
    n_buildings : int
        Number of buildings (the paper shows "several").
    footprint : (float, float)
        Each footprint side is uniform in this range (m), then snapped to ``step`` (at least
        one ``step``).
    heights : (float, float)
        Heights are uniform in this range (m) (not snapped).
    gap : float
        Least horizontal clearance between two buildings (m), so UAVs and sight lines can pass.
    margin : float
        Least distance from a building to the edge of the ground (m).
    step : float
        Footprint corners are multiples of ``step`` (m), so that a ground grid of spacing
        ``step`` (or a divisor of it) meets every wall along grid lines.
    max_attempts : int
        Each building is placed by rejection; after this many failed draws for one building
        :class:`~uavcov.errors.InfeasibleError` is raised (the square is too crowded).
    rng : None, int or numpy.random.Generator
        Seed or generator.

    Returns
    -------
    tuple of Building
    """
    size = as_positive_float(size, "size")
    n_buildings = as_non_negative_int(n_buildings, "n_buildings")
    side_low, side_high = _as_range(footprint, "footprint", positive=True)
    h_low, h_high = _as_range(heights, "heights", positive=True)
    gap = as_non_negative_float(gap, "gap")
    margin = as_non_negative_float(margin, "margin")
    step = as_positive_float(step, "step")
    max_attempts = as_positive_int(max_attempts, "max_attempts")
    if side_low > size - 2 * margin:
        raise InfeasibleError(f"a footprint of {side_low} m does not fit in {size} m with margin {margin} m")
    generator = as_generator(rng)
    placed: list[Building] = []
    for _ in range(n_buildings):
        for _attempt in range(max_attempts):
            width, depth = (max(step, _snap(s, step)) for s in generator.uniform(side_low, side_high, size=2))
            x0 = _snap(generator.uniform(margin, max(margin, size - margin - width)), step)
            y0 = _snap(generator.uniform(margin, max(margin, size - margin - depth)), step)
            height = float(generator.uniform(h_low, h_high))
            candidate = Building(x0, y0, x0 + width, y0 + depth, height)
            if _layout_ok(placed + [candidate], size, margin, gap):
                placed.append(candidate)
                break
        else:
            raise InfeasibleError(
                f"could not place building {len(placed) + 1} of {n_buildings} after {max_attempts} draws: "
                f"use fewer or smaller buildings, a smaller gap or a larger size"
            )
    return tuple(placed)


class _VertexPool:
    """Vertices keyed by their rounded coordinates, so coincident vertices share one index."""

    def __init__(self, quantum: float) -> None:
        self.quantum = quantum
        self.index: dict[tuple[int, int, int], int] = {}
        self.points: list[tuple[float, float, float]] = []

    def get(self, x: float, y: float, z: float) -> int:
        key = (round(x / self.quantum), round(y / self.quantum), round(z / self.quantum))
        found = self.index.get(key)
        if found is None:
            found = len(self.points)
            self.index[key] = found
            self.points.append((x, y, z))
        return found


def _quad(pool: _VertexPool, faces: list[tuple[int, int, int]], corners: Sequence[tuple[float, float, float]]) -> None:
    """Two triangles for a planar quad given counter-clockwise as seen from its outer side."""
    a, b, c, d = (pool.get(*p) for p in corners)
    faces.append((a, b, c))
    faces.append((a, c, d))


def _subdivisions(length: float, step: float) -> int:
    return max(1, int(math.ceil(length / step - 1e-9)))


def buildings_terrain(buildings: Sequence[Building], size: float = 24.0, spacing: float = 0.5) -> Terrain:
    """Mesh flat ground ``[0, size]^2`` at z = 0 with box buildings standing on it.

    The result is one conforming triangle mesh: the ground is a grid of ``spacing`` with the
    building footprints cut out, each wall is a grid of ``spacing``-wide columns whose bottom
    edges are exactly the ground's edges along the footprint, and each roof is a grid whose
    border is the walls' top edges. So every edge inside the scene is shared by exactly two
    triangles with opposite orientations (the scene is a closed, consistently oriented surface
    except along the outer rim of the ground), and normals point up or out of the buildings.

    The coverage targets this gives are what a camera can possibly see: roofs, walls and the
    ground between buildings; the ground under a building is not part of the surface.

    Parameters
    ----------
    buildings : sequence of Building
        Boxes inside the square, with disjoint footprints that may not touch. Every footprint
        corner must be a multiple of ``spacing``.
    size : float
        Side of the ground square (m); a multiple of ``spacing``.
    spacing : float
        Grid spacing of ground, walls (horizontally) and roofs (m). Wall rows are at most
        ``spacing`` tall.

    Returns
    -------
    Terrain
    """
    size = as_positive_float(size, "size")
    spacing = as_positive_float(spacing, "spacing")
    cells = _cells(size, spacing, "size")
    boxes = tuple(buildings)
    for b in boxes:
        if not isinstance(b, Building):
            raise InvalidTypeError(f"buildings must be Building objects, got {type(b).__name__}")
        for value in (b.xmin, b.ymin, b.xmax, b.ymax):
            if abs(value / spacing - round(value / spacing)) > 1e-6:
                raise InvalidInputError(f"footprint corner {value} of {b} is not a multiple of spacing {spacing}")
    # Corners are on the spacing grid, so two footprints are either apart by >= spacing or touch.
    if not _layout_ok(boxes, size, 0.0, 0.5 * spacing):
        raise InvalidInputError("buildings must lie inside the ground square and must not overlap or touch")

    pool = _VertexPool(quantum=spacing * 1e-6)
    faces: list[tuple[int, int, int]] = []

    # Ground: skip the cells that lie inside a footprint.
    blocked = np.zeros((cells, cells), dtype=bool)
    for b in boxes:
        j0, j1 = int(round(b.xmin / spacing)), int(round(b.xmax / spacing))
        i0, i1 = int(round(b.ymin / spacing)), int(round(b.ymax / spacing))
        blocked[i0:i1, j0:j1] = True
    for i in range(cells):
        for j in range(cells):
            if blocked[i, j]:
                continue
            x0, x1 = j * spacing, (j + 1) * spacing
            y0, y1 = i * spacing, (i + 1) * spacing
            _quad(pool, faces, [(x0, y0, 0.0), (x1, y0, 0.0), (x1, y1, 0.0), (x0, y1, 0.0)])

    for b in boxes:
        rows = _subdivisions(b.height, spacing)
        levels = np.linspace(0.0, b.height, rows + 1)
        # Walls, each walked counter-clockwise around the footprint seen from above, so the
        # quad (p, q, q_up, p_up) is counter-clockwise seen from outside.
        ring = [(b.xmin, b.ymin), (b.xmax, b.ymin), (b.xmax, b.ymax), (b.xmin, b.ymax)]
        for (xa, ya), (xb, yb) in zip(ring, ring[1:] + ring[:1]):
            columns = int(round(max(abs(xb - xa), abs(yb - ya)) / spacing))
            xs = np.linspace(xa, xb, columns + 1)
            ys = np.linspace(ya, yb, columns + 1)
            for c in range(columns):
                for r in range(rows):
                    z0, z1 = levels[r], levels[r + 1]
                    p, q = (xs[c], ys[c]), (xs[c + 1], ys[c + 1])
                    _quad(pool, faces, [(*p, z0), (*q, z0), (*q, z1), (*p, z1)])
        # Roof.
        xs = np.linspace(b.xmin, b.xmax, int(round((b.xmax - b.xmin) / spacing)) + 1)
        ys = np.linspace(b.ymin, b.ymax, int(round((b.ymax - b.ymin) / spacing)) + 1)
        for i in range(len(ys) - 1):
            for j in range(len(xs) - 1):
                x0, x1, y0, y1, h = xs[j], xs[j + 1], ys[i], ys[i + 1], b.height
                _quad(pool, faces, [(x0, y0, h), (x1, y0, h), (x1, y1, h), (x0, y1, h)])

    vertices = np.array(pool.points, dtype=np.float64)
    return Terrain(vertices, np.array(faces, dtype=np.int64))


def buildings_scene(
    size: float = 24.0,
    n_buildings: int = 5,
    footprint: Any = (3.0, 7.0),
    heights: Any = (3.0, 10.0),
    gap: float = 2.0,
    margin: float = 1.0,
    spacing: float = 0.5,
    rng: Any = None,
) -> Terrain:
    """The paper's realistic scene: flat ground with random box buildings, as a 3D mesh.

    ``buildings_scene(..., rng=s)`` is ``buildings_terrain(random_buildings(..., rng=s), ...)``;
    call those two yourself when you need the boxes (for example to build the prior map with
    :func:`uavcov.prior.buildings_prior`). Parameters are those of :func:`random_buildings`
    (footprints snapped to ``spacing``) and :func:`buildings_terrain`. The defaults (24 m
    square, 5 buildings 3-7 m wide and 3-10 m tall, 2 m apart) are starting values: the paper
    gives only the 24 m x 24 m size and "several buildings".
    """
    boxes = random_buildings(
        size=size,
        n_buildings=n_buildings,
        footprint=footprint,
        heights=heights,
        gap=gap,
        margin=margin,
        step=spacing,
        rng=rng,
    )
    return buildings_terrain(boxes, size=size, spacing=spacing)


def perturb_buildings(
    buildings: Sequence[Building],
    size: float = 24.0,
    position_error: float = 0.5,
    size_error: float = 0.5,
    height_error: float = 1.0,
    step: float = 0.5,
    gap: float = 0.5,
    max_attempts: int = 100,
    rng: Any = None,
) -> tuple[Building, ...]:
    """A coarse, erroneous map of ``buildings``: what a prior map of the scene may look like.

    Each box is moved by a normal error of standard deviation ``position_error`` per axis,
    each footprint side changes by a normal error of ``size_error``, each height by one of
    ``height_error`` (all m); then footprints are snapped to ``step``. A perturbed box that
    leaves the square, overlaps (closer than ``gap``) another, or gets a side or height under
    ``step`` is redrawn, up to ``max_attempts`` times, then
    :class:`~uavcov.errors.InfeasibleError` is raised. Zero errors give the exact map.
    """
    size = as_positive_float(size, "size")
    sigma_position = as_non_negative_float(position_error, "position_error")
    sigma_size = as_non_negative_float(size_error, "size_error")
    sigma_height = as_non_negative_float(height_error, "height_error")
    step = as_positive_float(step, "step")
    gap = as_non_negative_float(gap, "gap")
    max_attempts = as_positive_int(max_attempts, "max_attempts")
    generator = as_generator(rng)
    result: list[Building] = []
    for b in buildings:
        if not isinstance(b, Building):
            raise InvalidTypeError(f"buildings must be Building objects, got {type(b).__name__}")
        for _attempt in range(max_attempts):
            dx, dy = generator.normal(0.0, 1.0, size=2) * sigma_position
            dw, dd = generator.normal(0.0, 1.0, size=2) * sigma_size
            dh = float(generator.normal(0.0, 1.0)) * sigma_height
            cx, cy = 0.5 * (b.xmin + b.xmax) + dx, 0.5 * (b.ymin + b.ymax) + dy
            width, depth = (b.xmax - b.xmin) + dw, (b.ymax - b.ymin) + dd
            height = b.height + dh
            if min(width, depth, height) < step:
                continue
            x0, x1 = _snap(cx - width / 2, step), _snap(cx + width / 2, step)
            y0, y1 = _snap(cy - depth / 2, step), _snap(cy + depth / 2, step)
            if x1 <= x0 or y1 <= y0:
                continue
            candidate = Building(x0, y0, x1, y1, height)
            if _layout_ok(result + [candidate], size, 0.0, gap):
                result.append(candidate)
                break
        else:
            raise InfeasibleError(
                f"could not perturb {b} into a valid box after {max_attempts} draws: lower the errors or the gap"
            )
    return tuple(result)


# ---------------------------------------------------------------------------------------------
# Local frames and loaded terrain

_WGS84_A = 6378137.0
_WGS84_F = 1.0 / 298.257223563
_WGS84_E2 = _WGS84_F * (2.0 - _WGS84_F)


def metres_per_degree(latitude: float) -> tuple[float, float]:
    """Metres per degree of longitude and of latitude at ``latitude`` (degrees), WGS84.

    From the prime-vertical radius ``N`` and the meridian radius ``M`` of the ellipsoid:
    ``(pi/180) N cos(phi)`` and ``(pi/180) M``. At 45 degrees: (78846.8, 111132.95).
    """
    latitude = as_finite_float(latitude, "latitude")
    if abs(latitude) > 90.0:
        raise InvalidInputError(f"latitude must be in [-90, 90] degrees, got {latitude}")
    phi = math.radians(latitude)
    w = 1.0 - _WGS84_E2 * math.sin(phi) ** 2
    prime_vertical = _WGS84_A / math.sqrt(w)
    meridian = _WGS84_A * (1.0 - _WGS84_E2) / w**1.5
    per_rad = math.pi / 180.0
    return per_rad * prime_vertical * math.cos(phi), per_rad * meridian


@dataclass(frozen=True, eq=False)
class LocalFrame:
    """The map between source coordinates and the library's local metric frame.

    ``local = (source - origin) * factors`` per axis; ``source = local / factors + origin``.

    Attributes
    ----------
    origin : ndarray, shape (3,)
        The source point that becomes the local origin, in source units ((x, y, z) in metres for
        projected data, (longitude, latitude, z) in degrees and metres for geographic data).
    factors : ndarray, shape (3,)
        Local metres per source unit along each axis, including the model ``scale``.
    geographic : bool
        True when x, y are degrees of longitude and latitude.
    reference_latitude : float or None
        Latitude (degrees) of the equirectangular projection when geographic.
    """

    origin: np.ndarray
    factors: np.ndarray
    geographic: bool = False
    reference_latitude: float | None = None

    def __post_init__(self) -> None:
        origin = as_float_array(self.origin, "origin", ndim=1)
        factors = as_float_array(self.factors, "factors", ndim=1)
        if origin.shape != (3,) or factors.shape != (3,):
            raise InvalidInputError("origin and factors must both have shape (3,)")
        if not (factors > 0.0).all():
            raise InvalidInputError(f"factors must be > 0, got {factors}")
        origin.setflags(write=False)
        factors.setflags(write=False)
        object.__setattr__(self, "origin", origin)
        object.__setattr__(self, "factors", factors)

    @classmethod
    def identity(cls) -> "LocalFrame":
        """The frame of data that is already local (generated scenes)."""
        return cls(np.zeros(3), np.ones(3))

    def to_local(self, points: Any) -> np.ndarray:
        """Source coordinates ``(n, 3)`` to local metres ``(n, 3)``."""
        array = _as_xyz(points, "points")
        return (array - self.origin) * self.factors

    def to_source(self, points: Any) -> np.ndarray:
        """Local metres ``(n, 3)`` back to source coordinates ``(n, 3)``."""
        array = _as_xyz(points, "points")
        return array / self.factors + self.origin


def _as_xyz(points: Any, name: str) -> np.ndarray:
    array = as_float_array(points, name)
    if array.ndim == 1 and array.shape[0] == 3:
        array = array.reshape(1, 3)
    if array.ndim != 2 or array.shape[1] != 3:
        raise InvalidInputError(f"{name} must have shape (n, 3), got {array.shape}")
    return array


@dataclass(frozen=True)
class MeshReport:
    """What :func:`clean_mesh` found and repaired in a mesh (all counts).

    Attributes
    ----------
    merged_vertices : int
        Vertices dropped because another vertex has exactly the same coordinates (STL files
        store every triangle's corners separately).
    unused_vertices : int
        Vertices no face refers to, dropped.
    degenerate_faces : int
        Faces with a repeated vertex or zero area, dropped.
    duplicate_faces : int
        Faces over the same three vertices as an earlier face (in any order), dropped.
    boundary_edges : int
        Edges of only one face. A terrain is an open sheet, so these are expected and kept.
    nonmanifold_edges : int
        Edges of three faces or more; kept (visibility needs no manifold), reported.
    """

    merged_vertices: int = 0
    unused_vertices: int = 0
    degenerate_faces: int = 0
    duplicate_faces: int = 0
    boundary_edges: int = 0
    nonmanifold_edges: int = 0

    @property
    def repaired(self) -> bool:
        """True when faces were dropped (degenerate or duplicate)."""
        return self.degenerate_faces + self.duplicate_faces > 0


@dataclass(frozen=True)
class LoadedTerrain:
    """A terrain read from real data, with what is needed to map results back.

    Attributes
    ----------
    terrain : Terrain
        The surface in the local metric frame (metres, Z up).
    frame : LocalFrame
        Local <-> source coordinates; ``frame.to_source(uav_positions)`` gives world positions.
    source : str
        Where the data came from (a path or a short description).
    nodata_cells : int
        Elevation samples that were nodata (left out of the surface and its targets); 0 for meshes.
    mesh_report : MeshReport or None
        What was repaired, for mesh input.
    """

    terrain: Terrain
    frame: LocalFrame
    source: str = ""
    nodata_cells: int = 0
    mesh_report: MeshReport | None = field(default=None)


_METRE_NAMES = {"m", "metre", "metres", "meter", "meters"}
_DEGREE_NAMES = {"deg", "degree", "degrees"}


def _geographic(units: Any) -> bool:
    if not isinstance(units, str):
        raise InvalidTypeError(f"units must be a string, got {type(units).__name__}")
    name = units.strip().lower()
    if name in _METRE_NAMES:
        return False
    if name in _DEGREE_NAMES:
        return True
    raise InvalidInputError(f"units must be 'metre' or 'degree', got {units!r}")


def load_dem(
    z: Any,
    spacing: Any,
    *,
    lower_left: Any = (0.0, 0.0),
    units: str = "metre",
    first_row: str = "south",
    nodata: float | None = None,
    origin: Any = None,
    scale: float = 1.0,
    source: str = "array",
) -> LoadedTerrain:
    """An elevation grid (numpy array) as a Terrain in a local metric frame.

    Parameters
    ----------
    z : array_like, shape (ny, nx)
        Elevations (m) at the grid points; ``ny, nx >= 2``. NaN (and ``nodata``) mark nodata.
    spacing : float or (float, float)
        ``(dx, dy)`` between grid points, > 0, in ``units``.
    lower_left : (float, float)
        Source coordinates of the south-west grid point (the smallest x and y), in ``units``.
    units : {"metre", "degree"}
        Horizontal units: projected metres, or geographic degrees (x = longitude, y = latitude)
        converted to metres by a local equirectangular projection about the centre latitude
        (see the module notes). Elevations are metres either way.
    first_row : {"south", "north"}
        Which edge row 0 of ``z`` lies on: "south" is the layout of :meth:`Terrain.from_grid`
        (row i at ``y = y0 + i dy``); "north" is the image / GeoTIFF layout.
    nodata : float, optional
        A sentinel value that marks nodata, as well as NaN.
    origin : (float, float, float), optional
        Source point that becomes the local origin. Default: the south-west grid point and the
        lowest valid elevation, so the terrain spans ``[0, W] x [0, H]`` with its lowest point at
        z = 0, like the generated scenes.
    scale : float
        Uniform model scale applied to all three axes after conversion to metres (1 = true
        size); slopes and shapes are kept.
    source : str
        Recorded in the result.

    Returns
    -------
    LoadedTerrain

    Notes
    -----
    Nodata handling: a nodata sample removes every grid triangle that touches it (that is what
    :meth:`Terrain.from_grid` does with NaN), so no coverage target and no prior sample lies
    in a hole, and holes are not filled with ground at height zero. At least one grid cell must
    have four valid corners.
    """
    heights = as_float_array(z, "z", ndim=2, allow_nan=True)
    spacing_xy = _as_spacing(spacing)
    corner = as_float_array(lower_left, "lower_left", ndim=1)
    if corner.shape != (2,):
        raise InvalidInputError(f"lower_left must be an (x, y) pair, got shape {corner.shape}")
    geographic = _geographic(units)
    if not isinstance(first_row, str) or first_row.lower() not in ("south", "north"):
        raise InvalidInputError(f"first_row must be 'south' or 'north', got {first_row!r}")
    if first_row.lower() == "north":
        heights = heights[::-1]
    return _grid_terrain(
        heights,
        spacing_xy,
        corner,
        geographic=geographic,
        unit_factor=1.0,
        nodata=nodata,
        origin=origin,
        scale=scale,
        source=source,
    )


def _grid_terrain(
    heights: np.ndarray,
    spacing: tuple[float, float],
    corner: np.ndarray,
    *,
    geographic: bool,
    unit_factor: float,
    nodata: float | None,
    origin: Any,
    scale: float,
    source: str,
) -> LoadedTerrain:
    """Build the grid Terrain and its frame from checked input (row 0 is the south edge).

    ``unit_factor`` is metres per horizontal source unit for projected data (1 for metres).
    """
    ny, nx = heights.shape
    if ny < 2 or nx < 2:
        raise InvalidInputError(f"z must have at least 2 rows and 2 columns, got shape {heights.shape}")
    scale = as_positive_float(scale, "scale")
    dx, dy = spacing
    heights = np.array(heights, dtype=np.float64)  # a copy we may write NaN into
    if nodata is not None:
        sentinel = as_finite_float(nodata, "nodata")
        heights[heights == sentinel] = np.nan
    valid = np.isfinite(heights)
    nodata_cells = int(heights.size - valid.sum())
    complete = valid[:-1, :-1] & valid[1:, :-1] & valid[:-1, 1:] & valid[1:, 1:]
    if not complete.any():
        raise InvalidInputError(
            f"z has no grid cell with four valid corners ({nodata_cells} of {heights.size} samples are nodata)"
        )

    reference_latitude: float | None = None
    mx = my = unit_factor
    if geographic:
        lat_low, lat_high = float(corner[1]), float(corner[1] + (ny - 1) * dy)
        if lat_low < -90.0 or lat_high > 90.0:
            raise InvalidInputError(f"latitudes {lat_low}..{lat_high} are outside [-90, 90] degrees")
        centre_latitude = 0.5 * (lat_low + lat_high)
        mx, my = metres_per_degree(centre_latitude)
        reference_latitude = centre_latitude
    factors = np.array([mx, my, 1.0]) * scale

    if origin is None:
        frame_origin = np.array([corner[0], corner[1], float(np.min(heights[valid]))])
    else:
        frame_origin = as_float_array(origin, "origin", ndim=1)
        if frame_origin.shape != (3,):
            raise InvalidInputError(f"origin must be an (x, y, z) triple, got shape {frame_origin.shape}")
    frame = LocalFrame(frame_origin, factors, geographic=geographic, reference_latitude=reference_latitude)

    # Subtract the origin in float64 before scaling: this is the step that keeps precision for
    # georeferenced coordinates.
    local_z = (heights - frame_origin[2]) * factors[2]
    local_corner = (corner - frame_origin[:2]) * factors[:2]
    terrain = Terrain.from_grid(
        local_z,
        (dx * factors[0], dy * factors[1]),
        origin=(float(local_corner[0]), float(local_corner[1])),
    )
    return LoadedTerrain(terrain=terrain, frame=frame, source=source, nodata_cells=nodata_cells)


def load_geotiff(path: Any, *, band: int = 1, origin: Any = None, scale: float = 1.0) -> LoadedTerrain:
    """A GeoTIFF (or any raster GDAL reads) elevation model as a Terrain; needs ``rasterio``.

    The raster must be north-up without rotation. Pixel values are taken at pixel centres.
    Geographic CRSs (degrees) go through the local projection of :func:`load_dem`; projected
    CRSs are converted from their linear unit to metres. A raster without a CRS is taken as
    metres. The raster's nodata value and mask become nodata. Elevations are taken as metres.

    Raises
    ------
    ImportError
        When rasterio is not installed (``pip install uavcov[geotiff]``).
    InvalidInputError
        When the file does not exist, does not parse, or is rotated.
    """
    try:
        import rasterio
    except ImportError as exc:
        raise ImportError(
            "reading GeoTIFF files needs rasterio: pip install 'uavcov[geotiff]' (or pip install rasterio)"
        ) from exc
    band = as_positive_int(band, "band")
    path_text = _existing_path(path, "GeoTIFF", InvalidInputError)
    try:
        with rasterio.open(path_text) as dataset:
            if band > dataset.count:
                raise InvalidInputError(f"{path_text} has {dataset.count} band(s), asked for band {band}")
            data = dataset.read(band, masked=True)
            transform = dataset.transform
            crs = dataset.crs
    except InvalidInputError:
        raise
    except Exception as exc:  # rasterio raises its own hierarchy for unreadable files
        raise InvalidInputError(f"cannot read {path_text} as a raster: {exc}") from exc
    heights = np.ma.filled(data.astype(np.float64), np.nan)
    a, b, c, d, e, f = transform.a, transform.b, transform.c, transform.d, transform.e, transform.f
    if b != 0.0 or d != 0.0:
        raise InvalidInputError(f"{path_text} is rotated or sheared (transform {transform}); warp it north-up first")
    if a <= 0.0 or e == 0.0:
        raise InvalidInputError(f"{path_text} has an unusable pixel size ({a}, {e})")
    ny = heights.shape[0]
    # Pixel centres: x_j = c + (j + 1/2) a, y_i = f + (i + 1/2) e.
    x_west = c + 0.5 * a
    if e < 0.0:
        first_row = "north"
        y_south = f + (ny - 0.5) * e
    else:
        first_row = "south"
        y_south = f + 0.5 * e
    geographic = bool(crs is not None and crs.is_geographic)
    unit_factor = 1.0
    if crs is not None and not geographic:
        try:
            unit_factor = float(crs.linear_units_factor[1])
        except Exception:  # a CRS without a linear unit: keep metres
            unit_factor = 1.0
    if first_row == "north":
        heights = heights[::-1]
    return _grid_terrain(
        heights,
        (a, abs(e)),
        np.array([x_west, y_south]),
        geographic=geographic,
        unit_factor=unit_factor,
        nodata=None,  # the mask already made nodata NaN
        origin=origin,
        scale=scale,
        source=path_text,
    )


def _existing_path(path: Any, what: str, error: type[Exception]) -> str:
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidTypeError(f"path must be a string or os.PathLike, got {type(path).__name__}")
    text = os.fspath(path)
    if not os.path.exists(text):
        raise error(f"{what} file {text!r} does not exist")
    if os.path.isdir(text):
        raise error(f"{what} path {text!r} is a directory, not a file")
    return text


def clean_mesh(vertices: Any, faces: Any) -> tuple[np.ndarray, np.ndarray, MeshReport]:
    """Repair a triangle mesh: merge coincident vertices, drop degenerate and duplicate faces.

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
        Finite coordinates (m).
    faces : array_like, shape (F, 3)
        Integer vertex indices in ``[0, V)``.

    Returns
    -------
    vertices : ndarray, shape (V', 3)
    faces : ndarray, shape (F', 3)
        Only referenced vertices, in the order they first appear, renumbered; the kept faces in
        their input order and orientation. A mesh without defects comes back unchanged.
    report : MeshReport

    Raises
    ------
    MeshError
        Indices out of range, or no face left.

    Notes
    -----
    Merging is exact (bitwise equal coordinates), which is what STL and unwelded OBJ/PLY
    exports produce. Open boundaries are kept: a terrain is an open sheet. Duplicate faces are
    dropped because a doubled triangle would double the coverage targets on it.
    """
    points = as_float_array(vertices, "vertices")
    if points.ndim != 2 or points.shape[1] != 3:
        raise MeshError(f"vertices must have shape (V, 3), got {points.shape}")
    triangles = as_index_array(faces, "faces")
    if triangles.shape[0] == 0:
        raise MeshError("the mesh has no faces")
    if points.shape[0] == 0 or triangles.min() < 0 or triangles.max() >= points.shape[0]:
        raise MeshError(f"face indices must be in [0, {points.shape[0]}), got [{triangles.min()}, {triangles.max()}]")

    sorted_points, first, inverse = np.unique(points, axis=0, return_index=True, return_inverse=True)
    # Keep vertices in the order of their first appearance, so a clean mesh comes back as given.
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.shape[0])
    unique_points = sorted_points[order]
    inverse = rank[inverse.reshape(-1)]
    merged = points.shape[0] - unique_points.shape[0]
    triangles = inverse[triangles]

    a, b, c = (unique_points[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    diagonal = float(np.linalg.norm(unique_points.max(axis=0) - unique_points.min(axis=0)))
    t0, t1, t2 = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    repeated = (t0 == t1) | (t1 == t2) | (t0 == t2)
    # The zero-area rule of Terrain (relative to the bounding-box diagonal), so that nothing
    # this keeps is refused there.
    degenerate = repeated | (area <= 1e-13 * diagonal * diagonal)
    triangles = triangles[~degenerate]
    if triangles.shape[0] == 0:
        raise MeshError("every face of the mesh is degenerate (zero area)")

    keys = np.sort(triangles, axis=1)
    _, first = np.unique(keys, axis=0, return_index=True)
    keep = np.zeros(triangles.shape[0], dtype=bool)
    keep[first] = True
    duplicates = int((~keep).sum())
    triangles = triangles[keep]

    used = np.unique(triangles)
    renumber = np.full(unique_points.shape[0], -1, dtype=np.int64)
    renumber[used] = np.arange(used.shape[0])
    triangles = renumber[triangles]
    unused = unique_points.shape[0] - used.shape[0]

    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    report = MeshReport(
        merged_vertices=int(merged),
        unused_vertices=int(unused),
        degenerate_faces=int(degenerate.sum()),
        duplicate_faces=duplicates,
        boundary_edges=int((counts == 1).sum()),
        nonmanifold_edges=int((counts > 2).sum()),
    )
    return np.ascontiguousarray(unique_points[used]), np.ascontiguousarray(triangles), report


_UP_AXES = ("z", "y")


def mesh_terrain(
    vertices: Any,
    faces: Any,
    *,
    up: str = "z",
    origin: Any = None,
    scale: float = 1.0,
    on_defect: str = "repair",
    source: str = "arrays",
) -> LoadedTerrain:
    """A triangle mesh (arrays in metres) as a Terrain in a local frame, repaired by :func:`clean_mesh`.

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
    faces : array_like, shape (F, 3)
    up : {"z", "y"}
        The source's up axis. "y" (common in OBJ exports) maps source (x, y, z) to (x, -z, y).
    origin : (float, float, float), optional
        Source point that becomes the local origin; default: the minimum corner of the
        bounding box (after the up-axis change, so given in the Z-up source axes).
    scale : float
        Uniform model scale (1 = true size).
    on_defect : {"repair", "raise"}
        "repair" drops degenerate and duplicate faces and reports them in ``mesh_report``;
        "raise" raises :class:`~uavcov.errors.MeshError` when there are any.
    source : str
        Recorded in the result.
    """
    if not isinstance(up, str) or up.lower() not in _UP_AXES:
        raise InvalidInputError(f"up must be 'z' or 'y', got {up!r}")
    if on_defect not in ("repair", "raise"):
        raise InvalidInputError(f"on_defect must be 'repair' or 'raise', got {on_defect!r}")
    scale = as_positive_float(scale, "scale")
    points = as_float_array(vertices, "vertices")
    if points.ndim != 2 or points.shape[1] != 3:
        raise MeshError(f"vertices must have shape (V, 3), got {points.shape}")
    if up.lower() == "y":
        points = np.column_stack([points[:, 0], -points[:, 2], points[:, 1]])
    if points.shape[0] == 0:
        raise MeshError("the mesh has no vertices")
    if origin is None:
        frame_origin = points.min(axis=0)
    else:
        frame_origin = as_float_array(origin, "origin", ndim=1)
        if frame_origin.shape != (3,):
            raise InvalidInputError(f"origin must be an (x, y, z) triple, got shape {frame_origin.shape}")
    frame = LocalFrame(frame_origin, np.full(3, scale))
    # Recentre before anything else so the geometry below works on small numbers.
    local = frame.to_local(points)
    clean_vertices, clean_faces, report = clean_mesh(local, faces)
    if on_defect == "raise" and report.repaired:
        raise MeshError(
            f"{source}: {report.degenerate_faces} degenerate and {report.duplicate_faces} duplicate faces "
            "(pass on_defect='repair' to drop them)"
        )
    terrain = Terrain(clean_vertices, clean_faces)
    return LoadedTerrain(terrain=terrain, frame=frame, source=source, mesh_report=report)


def load_mesh(
    path: Any,
    *,
    up: str = "z",
    origin: Any = None,
    scale: float = 1.0,
    on_defect: str = "repair",
) -> LoadedTerrain:
    """Read an OBJ, STL or PLY file (anything trimesh reads) as a Terrain; needs ``trimesh``.

    Multi-part files are concatenated into one surface. Vertices are welded exactly,
    degenerate and duplicate faces dropped (or refused with ``on_defect="raise"``), open
    boundaries kept; see :func:`mesh_terrain` for the parameters and :class:`MeshReport` for
    what is reported.

    Raises
    ------
    ImportError
        When trimesh is not installed (``pip install uavcov[mesh]``).
    MeshError
        When the file does not exist, does not parse, or holds no triangles.
    """
    try:
        import trimesh
    except ImportError as exc:
        raise ImportError(
            "reading mesh files needs trimesh: pip install 'uavcov[mesh]' (or pip install trimesh)"
        ) from exc
    path_text = _existing_path(path, "mesh", MeshError)
    try:
        # process=False: we weld and clean ourselves, with a report, rather than silently.
        loaded = trimesh.load(path_text, force="mesh", process=False)
    except Exception as exc:  # trimesh raises many kinds (ValueError, KeyError, IndexError ...)
        raise MeshError(f"cannot parse {path_text!r} as a mesh: {exc}") from exc
    vertices = getattr(loaded, "vertices", None)
    faces = getattr(loaded, "faces", None)
    if vertices is None or faces is None or len(faces) == 0:
        raise MeshError(f"{path_text!r} holds no triangles")
    return mesh_terrain(
        np.asarray(vertices, dtype=np.float64),
        np.asarray(faces, dtype=np.int64),
        up=up,
        origin=origin,
        scale=scale,
        on_defect=on_defect,
        source=path_text,
    )


# ---------------------------------------------------------------------------------------------
# A real DEM that matplotlib ships


def sample_dem(window: Any = None, stride: int = 1, scale: float = 1.0) -> LoadedTerrain:
    """A real terrain available offline: the Jacksboro fault DEM that matplotlib ships.

    The file (``jacksboro_fault_dem.npz`` in matplotlib's sample data) is a 344 x 403 grid of
    elevations (236-1076 m) every 3 arc-seconds over 84.41-84.08 W, 36.45-36.73 N (Tennessee,
    USA), stored north row first. It is converted like any geographic DEM (:func:`load_dem`
    with ``units="degree"``): cells are about 74.6 m east-west and 92.5 m north-south.

    Parameters
    ----------
    window : (int, int, int, int), optional
        ``(row_start, row_stop, col_start, col_stop)`` of the grid to keep, rows counted from
        the south edge and columns from the west edge (Python slice rules). Default: all.
    stride : int
        Keep every ``stride``-th row and column of the window.
    scale : float
        Uniform model scale; for example ``scale=0.01`` turns a 3 km window into a 30 m model
        with the same slopes.

    Returns
    -------
    LoadedTerrain
        ``frame.to_source`` gives (longitude, latitude, elevation).

    Raises
    ------
    ImportError
        When matplotlib is not installed (``pip install uavcov[plot]``).
    """
    try:
        from matplotlib import cbook
    except ImportError as exc:
        raise ImportError("sample_dem reads a file that matplotlib ships: pip install matplotlib") from exc
    stride = as_positive_int(stride, "stride")
    path = cbook.get_sample_data("jacksboro_fault_dem.npz", asfileobj=False)
    with np.load(path) as data:
        elevation = np.asarray(data["elevation"], dtype=np.float64)[::-1]  # south row first
        dx = float(data["dx"])
        dy = float(data["dy"])
        west = float(data["xmin"])
        # The file's "ymin" is the northern edge and "ymax" the southern one (matplotlib's own
        # examples pair ymin with row 0, which is north); take the smaller as the south edge.
        south = min(float(data["ymin"]), float(data["ymax"]))
    ny, nx = elevation.shape
    if window is None:
        rows, cols = slice(0, ny), slice(0, nx)
    else:
        bounds = tuple(window)
        if len(bounds) != 4 or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) for v in bounds):
            raise InvalidInputError(
                f"window must be four integers (row_start, row_stop, col_start, col_stop), got {window!r}"
            )
        rows, cols = slice(int(bounds[0]), int(bounds[1])), slice(int(bounds[2]), int(bounds[3]))
    row_index = np.arange(ny)[rows][::stride]
    col_index = np.arange(nx)[cols][::stride]
    if row_index.size < 2 or col_index.size < 2:
        raise InvalidInputError(
            f"window {window!r} with stride {stride} keeps {row_index.size} x {col_index.size} samples; "
            "at least 2 x 2 are needed"
        )
    heights = elevation[np.ix_(row_index, col_index)]
    # Grid points are cell centres: half a cell in from the file's edges.
    lower_left = (west + (col_index[0] + 0.5) * dx, south + (row_index[0] + 0.5) * dy)
    return load_dem(
        heights,
        (dx * stride, dy * stride),
        lower_left=lower_left,
        units="degree",
        scale=scale,
        source="matplotlib sample data: jacksboro_fault_dem.npz",
    )
