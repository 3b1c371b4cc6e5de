"""A buildings scene, the paper's realistic environment (its Figs. 7-8): flat ground with box
buildings, a true 3D mesh with vertical walls.

``random_buildings`` draws the boxes, ``buildings_terrain`` meshes them,
:func:`buildings_scene` does both, and ``perturb_buildings`` makes the coarse, erroneous map
a prior is built from.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import (
    MAX_GRID_CELLS,
    as_cell_count,
    as_finite_float,
    as_generator,
    as_non_negative_float,
    as_non_negative_int,
    as_positive_float,
    as_positive_int,
    as_range,
    cells_along,
)
from ..engine import Terrain
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError


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

    def gap_to(self, other: Building) -> float:
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
    side_low, side_high = as_range(footprint, "footprint", positive=True)
    h_low, h_high = as_range(heights, "heights", positive=True)
    gap = as_non_negative_float(gap, "gap")
    margin = as_non_negative_float(margin, "margin")
    step = as_positive_float(step, "step")
    cells_along(size, step, "size")  # corners snap to multiples of step: a subnormal one overflows them
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
            if _layout_ok([*placed, candidate], size, margin, gap):
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
    return max(1, math.ceil(length / step - 1e-9))


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
    cells = as_cell_count(size, spacing, "size")
    boxes = tuple(buildings)
    for b in boxes:
        if not isinstance(b, Building):
            raise InvalidTypeError(f"buildings must be Building objects, got {type(b).__name__}")
        if b.height / spacing > MAX_GRID_CELLS:  # its walls' rows, checked before they are made
            raise InvalidInputError(
                f"a building of height {b.height} m has more than {MAX_GRID_CELLS:,} rows of spacing {spacing} m (uavcov's size limit)"
            )
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
        j0, j1 = round(b.xmin / spacing), round(b.xmax / spacing)
        i0, i1 = round(b.ymin / spacing), round(b.ymax / spacing)
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
        for (xa, ya), (xb, yb) in zip(ring, ring[1:] + ring[:1], strict=True):
            columns = round(max(abs(xb - xa), abs(yb - ya)) / spacing)
            xs = np.linspace(xa, xb, columns + 1)
            ys = np.linspace(ya, yb, columns + 1)
            for c in range(columns):
                for r in range(rows):
                    z0, z1 = levels[r], levels[r + 1]
                    p, q = (xs[c], ys[c]), (xs[c + 1], ys[c + 1])
                    _quad(pool, faces, [(*p, z0), (*q, z0), (*q, z1), (*p, z1)])
        # Roof.
        xs = np.linspace(b.xmin, b.xmax, round((b.xmax - b.xmin) / spacing) + 1)
        ys = np.linspace(b.ymin, b.ymax, round((b.ymax - b.ymin) / spacing) + 1)
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
    ``uavcov.terrain._prior.buildings_prior``). Parameters are those of ``random_buildings``
    (footprints snapped to ``spacing``) and ``buildings_terrain``. The defaults (24 m
    square, 5 buildings 3-7 m wide and 3-10 m tall, 2 m apart) are starting values: the paper
    gives only the 24 m x 24 m size and "several buildings".

    Examples
    --------
    >>> import uavcov
    >>> boxes = uavcov.terrain._buildings.random_buildings(rng=0)
    >>> len(boxes), uavcov.terrain.buildings_scene(rng=0).n_faces == uavcov.terrain._buildings.buildings_terrain(boxes).n_faces
    (5, True)
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
            if _layout_ok([*result, candidate], size, 0.0, gap):
                result.append(candidate)
                break
        else:
            raise InfeasibleError(f"could not perturb {b} into a valid box after {max_attempts} draws: lower the errors or the gap")
    return tuple(result)
