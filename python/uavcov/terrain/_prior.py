"""Partial knowledge of the surface and the approximating surface S' built from it.

The paper assumes only a few points of the true surface S are known before the mission (plus
its (x, y) limits). :func:`sample_prior` draws such points from a true :class:`Terrain`;
:func:`approximate_surface` turns any set of known points into S', the piecewise-linear
interpolant on their Delaunay triangulation (``scipy.spatial.Delaunay`` of the (x, y)
coordinates), returned as a :class:`Terrain` that the CVT and the plots use.
``buildings_prior`` gives the simplified map of a buildings scene.

The rule outside the samples' hull
----------------------------------
S' is defined exactly on the convex hull of the samples' (x, y) and nowhere else: it has no
triangle outside the hull, so ``S'.ground_height`` is NaN there, ``S'.clearance`` is infinite,
and no CVT sample or coverage target lies there. No extrapolation is made. With the 4 corners
of the terrain's bounding rectangle among the samples (the default of :func:`sample_prior`,
and part of the paper's pyramid) the hull is that whole rectangle.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial import ConvexHull, Delaunay, QhullError, cKDTree

from .._validate import (
    MAX_SAMPLES,
    as_bool,
    as_count,
    as_float_array,
    as_generator,
    as_non_negative_float,
    as_points,
    as_positive_float,
    cells_along,
    not_a_terrain,
    within_coordinate_bound,
)
from ..engine import Terrain
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError
from ._buildings import Building, buildings_terrain, perturb_buildings

_KINDS = ("random", "pyramid", "points")


@dataclass(frozen=True, eq=False)
class Prior:
    """Points of the true surface known before the mission.

    Attributes
    ----------
    points : ndarray, shape (n, 3)
        Known surface points (m), read-only.
    kind : str
        How they were chosen: "random", "pyramid", "points" (user-given) or "corners"
        (building corners).
    """

    points: np.ndarray
    kind: str = "points"

    def __post_init__(self) -> None:
        # Finite and within the engine's bound: S' is made of them (approximate_surface would refuse them later).
        points = within_coordinate_bound(as_float_array(self.points, "points"), "points")
        if points.ndim != 2 or points.shape[1] != 3:
            raise InvalidInputError(f"points must have shape (n, 3), got {points.shape}")
        points = points.copy()
        points.setflags(write=False)
        object.__setattr__(self, "points", points)
        if not isinstance(self.kind, str):
            raise InvalidTypeError(f"kind must be a string, got {type(self.kind).__name__}")

    @property
    def n_points(self) -> int:
        """Number of known points."""
        return int(self.points.shape[0])

    def surface(self) -> Terrain:
        """The approximating surface S' of these points (see :func:`approximate_surface`)."""
        return approximate_surface(self.points)


def _check_terrain(terrain: Any) -> Terrain:
    if not isinstance(terrain, Terrain):
        raise not_a_terrain(terrain, "terrain")
    return terrain


def _rectangle(terrain: Terrain) -> tuple[float, float, float, float]:
    bounds = np.asarray(terrain.bounds, dtype=np.float64)
    return float(bounds[0, 0]), float(bounds[0, 1]), float(bounds[1, 0]), float(bounds[1, 1])


def _corner_points(terrain: Terrain) -> np.ndarray:
    """The 4 corners of the terrain's bounding rectangle, on the surface (rows with NaN z dropped)."""
    xmin, ymin, xmax, ymax = _rectangle(terrain)
    xy = np.array([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]])
    z = np.asarray(terrain.ground_height(xy), dtype=np.float64)
    missing = ~np.isfinite(z)
    if missing.any():
        warnings.warn(
            f"{int(missing.sum())} corner(s) of the terrain's bounding rectangle have no surface under them "
            "(nodata); they are left out, so S' will not cover the whole rectangle",
            stacklevel=3,
        )
    return np.column_stack([xy, z])[~missing]


def _random_surface_points(terrain: Terrain, n: int, generator: np.random.Generator, max_rounds: int) -> np.ndarray:
    """``n`` points uniform in (x, y) over the bounding rectangle, on the surface (redrawn over nodata)."""
    xmin, ymin, xmax, ymax = _rectangle(terrain)
    found: list[np.ndarray] = []
    count = 0
    for _ in range(max_rounds):
        if count >= n:
            break
        xy = generator.uniform([xmin, ymin], [xmax, ymax], size=(n - count, 2))
        z = np.asarray(terrain.ground_height(xy), dtype=np.float64)
        keep = np.isfinite(z)
        found.append(np.column_stack([xy[keep], z[keep]]))
        count += int(keep.sum())
    if count < n:
        raise InfeasibleError(
            f"found only {count} of {n} surface points after {max_rounds} rounds of uniform draws: "
            "the surface covers almost none of its bounding rectangle"
        )
    return np.concatenate(found)[:n]


def sample_prior(
    terrain: Terrain,
    n: int = 30,
    *,
    kind: str = "random",
    points: Any = None,
    corners: bool = True,
    rng: Any = None,
) -> Prior:
    """Known points of a true surface: the prior information of the paper.

    Parameters
    ----------
    terrain : Terrain
        The true surface S. Heights are read with ``terrain.ground_height`` (the highest
        surface point above each (x, y), so roofs on a buildings scene), so every prior point
        lies exactly on S.
    n : int
        Number of random points for ``kind="random"`` (the paper: 30). Ignored otherwise.
    kind : {"random", "pyramid", "points"}
        "random": ``n`` points uniform in (x, y) over the terrain's bounding rectangle (redrawn
        where the surface has nodata holes). "pyramid": the paper's minimal prior, the 4
        corners of the rectangle and its centre. "points": the user's ``points``.
    points : array_like, shape (m, 2) or (m, 3), optional
        For ``kind="points"``: (x, y) positions whose heights are read from the terrain, or
        full (x, y, z) points taken as given. Positions with no surface under them raise.
    corners : bool
        Add the 4 corners of the bounding rectangle (default), so that S' covers all of it.
        Corners over nodata are left out with a warning. Always on for "pyramid".
    rng : None, int or numpy.random.Generator
        Seed or generator (used by "random").

    Returns
    -------
    Prior
        Random points first, then the corners (and for the pyramid: corners, then centre).

    Examples
    --------
    >>> import uavcov
    >>> hills = uavcov.gaussian_hills(rng=0)
    >>> prior = uavcov.terrain.sample_prior(hills, 30, rng=0)  # 30 random points and the 4 corners
    >>> prior.n_points, prior.kind
    (34, 'random')
    >>> uavcov.terrain.sample_prior(hills, kind="pyramid").points[:, :2].tolist()
    [[0.0, 0.0], [100.0, 0.0], [100.0, 100.0], [0.0, 100.0], [50.0, 50.0]]
    """
    terrain = _check_terrain(terrain)
    if not isinstance(kind, str) or kind not in _KINDS:
        raise InvalidInputError(f"kind must be one of {_KINDS}, got {kind!r}")
    if points is not None and kind != "points":  # given points silently replaced by drawn ones would be a wrong prior
        raise InvalidInputError(f"points are the prior of kind='points' only, got them with kind={kind!r}")
    as_bool(corners, "corners")
    generator = as_generator(rng)

    if kind == "pyramid":
        xmin, ymin, xmax, ymax = _rectangle(terrain)
        centre = np.array([[0.5 * (xmin + xmax), 0.5 * (ymin + ymax)]])
        z = np.asarray(terrain.ground_height(centre), dtype=np.float64)
        if not np.isfinite(z).all():
            raise InvalidInputError("the centre of the terrain's bounding rectangle has no surface under it (nodata)")
        known = np.concatenate([_corner_points(terrain), np.column_stack([centre, z])])
        return Prior(known, kind="pyramid")

    if kind == "random":
        n = as_count(n, "n", MAX_SAMPLES, minimum=0)
        known = _random_surface_points(terrain, n, generator, max_rounds=100) if n else np.zeros((0, 3))
    else:
        if points is None:
            raise InvalidInputError("kind='points' needs points: an (m, 2) or (m, 3) array")
        given = as_float_array(points, "points")
        if given.ndim == 1 and given.shape[0] in (2, 3):
            given = given.reshape(1, -1)
        if given.ndim != 2 or given.shape[1] not in (2, 3) or given.shape[0] == 0:
            raise InvalidInputError(f"points must have shape (m, 2) or (m, 3) with m >= 1, got {given.shape}")
        if given.shape[1] == 2:
            z = np.asarray(terrain.ground_height(given), dtype=np.float64)
            missing = np.flatnonzero(~np.isfinite(z))
            if missing.size:
                raise InvalidInputError(
                    f"{missing.size} of the given points have no surface under them (outside the terrain or nodata), "
                    f"first at index {int(missing[0])}: {given[missing[0]].tolist()}"
                )
            given = np.column_stack([given, z])
        known = given

    if corners:
        corner_points = _corner_points(terrain)
        # A user point already at a corner is not added twice.
        if known.shape[0]:
            tree = cKDTree(known[:, :2])
            distance, _ = tree.query(corner_points[:, :2])
            corner_points = corner_points[distance > 0.0]
        known = np.concatenate([known, corner_points])
    return Prior(known, kind=kind)


def _deduplicate(points: np.ndarray) -> np.ndarray:
    """Merge samples at the same (x, y) (within a relative 1e-9); refuse them when heights differ."""
    extent = float(np.ptp(points[:, :2], axis=0).max())
    tolerance = 1e-9 * max(extent, 1.0)
    pairs = cKDTree(points[:, :2]).query_pairs(tolerance, output_type="ndarray")
    if pairs.shape[0] == 0:
        return points
    dz = np.abs(points[pairs[:, 0], 2] - points[pairs[:, 1], 2])
    conflict = dz > tolerance
    if conflict.any():
        i, j = pairs[np.argmax(conflict)]
        raise InvalidInputError(
            f"samples {int(i)} and {int(j)} share (x, y) = {points[i, :2].tolist()} but have heights "
            f"{points[i, 2]} and {points[j, 2]}: S' is a height function, one height per (x, y)"
        )
    drop = np.zeros(points.shape[0], dtype=bool)
    # For each pair keep the lower index; chains of near-duplicates all collapse to their first.
    drop[np.maximum(pairs[:, 0], pairs[:, 1])] = True
    return points[~drop]


def sample_node_prior(nodes: Any, n: int, *, rng: Any = None) -> Prior:
    """``n`` of a surface's own points drawn without replacement, plus the corners of their hull.

    The sparse prior of a region that is not a rectangle (an area of interest on a DEM): the
    hull's corners make S' span the region, as the 4 corners do for :func:`sample_prior`.

    Parameters
    ----------
    nodes : (m, 3) array_like
        The points one may know (metres), e.g. a DEM's nodes inside an area.
    n : int
        How many to draw (at most ``m``).
    rng : None, int or numpy.random.Generator

    Raises
    ------
    InvalidInputError
        More points asked for than there are, or points on one line (no hull).
    """
    points = as_points(nodes, "nodes")
    n = as_count(n, "n", MAX_SAMPLES)
    if n > len(points):
        raise InvalidInputError(f"the prior asks for {n} sparse points but there are only {len(points)} nodes")
    chosen = points[as_generator(rng).choice(len(points), size=n, replace=False)]
    try:
        hull = points[ConvexHull(points[:, :2]).vertices]
    except (QhullError, ValueError) as exc:
        raise InvalidInputError(f"the nodes span no surface (all on a line?): {exc}") from None
    return Prior(np.unique(np.concatenate([chosen, hull]), axis=0), kind="nodes")


def approximate_surface(samples: Any) -> Terrain:
    """S': the piecewise-linear interpolant of known points on their Delaunay triangulation.

    Parameters
    ----------
    samples : Prior or array_like, shape (n, 3)
        Known surface points (m), with at least 3 distinct (x, y) positions not all on a line.

    Returns
    -------
    Terrain
        Vertices are the samples (duplicates merged), faces the triangles of
        ``scipy.spatial.Delaunay(samples[:, :2])``, oriented counter-clockwise seen from above
        (normals up). Its height at any (x, y) inside the samples' convex hull equals
        ``scipy.interpolate.LinearNDInterpolator(samples[:, :2], samples[:, 2])``; outside the
        hull it is undefined (``ground_height`` is NaN): see the module notes.

    Raises
    ------
    InvalidInputError
        Fewer than 3 samples, NaN or infinite coordinates, all samples on a line, or two
        samples at the same (x, y) with different heights. Exact (or within 1e-9 of the
        extent) duplicates with the same height are merged silently.

    Examples
    --------
    The pyramid of the paper: four corners on the ground and a summit, four triangles.

    >>> import uavcov
    >>> pyramid = [[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0], [5, 5, 4]]
    >>> s = uavcov.terrain.approximate_surface(pyramid)
    >>> s.n_faces, s.ground_height([[5.0, 5.0], [2.5, 5.0], [20.0, 5.0]]).tolist()
    (4, [4.0, 2.0, nan])
    """
    raw = samples.points if isinstance(samples, Prior) else samples
    points = as_float_array(raw, "samples", allow_nan=True)
    if points.ndim != 2 or points.shape[1] != 3:
        raise InvalidInputError(f"samples must have shape (n, 3), got {points.shape}")
    if not np.isfinite(points).all():
        bad = np.flatnonzero(~np.isfinite(points).all(axis=1))
        raise InvalidInputError(
            f"{bad.size} sample(s) have NaN or infinite coordinates (a height read over nodata?), first at index {int(bad[0])}"
        )
    within_coordinate_bound(points, "samples")  # the engine's bound, before a KD-tree overflows
    if points.shape[0] < 3:
        raise InvalidInputError(f"S' needs at least 3 samples, got {points.shape[0]}")
    points = _deduplicate(points)
    if points.shape[0] < 3:
        raise InvalidInputError(f"S' needs at least 3 distinct (x, y) samples, got {points.shape[0]}")
    xy = points[:, :2]
    centred = xy - xy.mean(axis=0)
    singular = np.linalg.svd(centred, compute_uv=False)
    if singular[1] <= 1e-10 * singular[0]:
        raise InvalidInputError("all samples lie on one line in (x, y): they span no surface")
    try:
        triangulation = Delaunay(xy)
    except QhullError as exc:
        raise InvalidInputError(f"the samples cannot be triangulated: {exc}") from exc
    if len(getattr(triangulation, "coplanar", ())):
        raise InvalidInputError(
            f"{len(triangulation.coplanar)} sample(s) coincide with others for Qhull and would be unused; remove near-duplicate samples"
        )
    faces = np.array(triangulation.simplices, dtype=np.int64)
    a, b, c = xy[faces[:, 0]], xy[faces[:, 1]], xy[faces[:, 2]]
    signed = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    faces = faces[signed != 0.0]  # flat slivers hold no interior point; the interpolant ignores them
    clockwise = signed[signed != 0.0] < 0.0
    faces[clockwise] = faces[clockwise][:, [0, 2, 1]]
    return Terrain(np.ascontiguousarray(points), np.ascontiguousarray(faces))


@dataclass(frozen=True)
class ApproximationError:
    """Height error of S' against the true surface, over the centres of a regular (x, y) lattice.

    Attributes
    ----------
    rms : float
        Root mean square of ``S'(x, y) - S(x, y)`` (m) over the comparison points inside S'.
    mean : float
        Mean signed error (m).
    max_abs : float
        Largest absolute error (m).
    n_points : int
        Points compared.
    n_outside : int
        Points on S but outside S' (left out of the statistics).
    """

    rms: float
    mean: float
    max_abs: float
    n_points: int
    n_outside: int


def approximation_error(truth: Terrain, approx: Terrain, resolution: float | None = None) -> ApproximationError:
    """Compare S' with the true surface S at the centres of a regular lattice of cells.

    The bounding rectangle of S is cut into square-ish cells of side about ``resolution``;
    each cell centre is one comparison point with equal weight, so the statistics average
    uniformly over the horizontal area of S (the midpoint rule). Heights are ``ground_height``
    of both surfaces (the highest surface point over each (x, y)). Centres over nodata in S are
    skipped; centres outside S' are counted in ``n_outside`` and skipped. Cell centres never
    fall on the rectangle's edges, where a point-in-triangle test is a matter of rounding.

    Parameters
    ----------
    truth, approx : Terrain
    resolution : float, optional
        Cell side (m). Default: 1/100 of the larger side of the rectangle (1 m on the paper's
        100 m terrains: 10,000 points).
    """
    truth = _check_terrain(truth)
    approx = _check_terrain(approx)
    xmin, ymin, xmax, ymax = _rectangle(truth)
    step = max(xmax - xmin, ymax - ymin) / 100.0 if resolution is None else as_positive_float(resolution, "resolution")
    nx = max(1, round(cells_along(xmax - xmin, step, "resolution")))
    ny = max(1, round(cells_along(ymax - ymin, step, "resolution")))
    xs = xmin + (np.arange(nx) + 0.5) * ((xmax - xmin) / nx)
    ys = ymin + (np.arange(ny) + 0.5) * ((ymax - ymin) / ny)
    x, y = np.meshgrid(xs, ys)
    xy = np.column_stack([x.ravel(), y.ravel()])
    true_z = np.asarray(truth.ground_height(xy), dtype=np.float64)
    approx_z = np.asarray(approx.ground_height(xy), dtype=np.float64)
    on_truth = np.isfinite(true_z)
    inside = on_truth & np.isfinite(approx_z)
    if not inside.any():
        raise InvalidInputError("S' and the true surface do not overlap at any comparison point")
    error = approx_z[inside] - true_z[inside]
    return ApproximationError(
        rms=float(np.sqrt(np.mean(error**2))),
        mean=float(np.mean(error)),
        max_abs=float(np.max(np.abs(error))),
        n_points=int(inside.sum()),
        n_outside=int((on_truth & ~inside).sum()),
    )


def _check_buildings(buildings: Sequence[Building]) -> tuple[Building, ...]:
    boxes = tuple(buildings)
    for b in boxes:
        if not isinstance(b, Building):
            raise InvalidTypeError(f"buildings must be Building objects, got {type(b).__name__}")
    return boxes


def building_corner_prior(
    buildings: Sequence[Building],
    size: float = 24.0,
    known_fraction: float = 0.5,
    height_error: float = 0.0,
    rng: Any = None,
) -> Prior:
    """A sparse prior of a buildings scene: the ground corners and the roof corners of some buildings.

    Parameters
    ----------
    buildings : sequence of Building
        The true boxes.
    size : float
        Side of the ground square (m); its 4 corners (at z = 0) are always known.
    known_fraction : float
        Share of buildings whose 4 roof corners are known, in [0, 1]; ``round(fraction * k)``
        buildings are chosen at random.
    height_error : float
        Standard deviation (m) of a normal error added to each known building's height.
    rng : None, int or numpy.random.Generator

    Notes
    -----
    S' of this prior (:func:`approximate_surface`) is a height function, so it cannot have
    vertical walls: between a known roof and the ground it slopes, and unknown buildings are
    absent. That is the "only some corners" kind of map of the paper's Fig. 7.
    """
    boxes = _check_buildings(buildings)
    size = as_positive_float(size, "size")
    fraction = as_non_negative_float(known_fraction, "known_fraction")
    if fraction > 1.0:
        raise InvalidInputError(f"known_fraction must be in [0, 1], got {fraction}")
    sigma = as_non_negative_float(height_error, "height_error")
    generator = as_generator(rng)
    count = round(fraction * len(boxes))
    chosen = np.sort(generator.choice(len(boxes), size=count, replace=False)) if count else np.zeros(0, dtype=int)
    ground = np.array([[0.0, 0.0, 0.0], [size, 0.0, 0.0], [size, size, 0.0], [0.0, size, 0.0]])
    roofs = []
    for index in chosen:
        corners = boxes[int(index)].corners()
        corners[:, 2] = max(corners[0, 2] + sigma * float(generator.normal()), 0.0)
        roofs.append(corners)
    known = np.concatenate([ground, *roofs]) if roofs else ground
    return Prior(known, kind="corners")


def buildings_prior(
    buildings: Sequence[Building],
    size: float = 24.0,
    *,
    kind: str = "boxes",
    spacing: float = 1.0,
    position_error: float = 0.5,
    size_error: float = 0.5,
    height_error: float = 1.0,
    known_fraction: float = 0.5,
    rng: Any = None,
) -> Terrain:
    """The simplified map of a buildings scene, as the surface the CVT runs on.

    Parameters
    ----------
    buildings : sequence of Building
        The true boxes (from ``uavcov.terrain._buildings.random_buildings``).
    size : float
        Side of the ground square (m).
    kind : {"boxes", "corners"}
        "boxes": the ground plus every building as a box with position, size and height errors
        (``uavcov.terrain._buildings.perturb_buildings``, snapped to ``spacing``), meshed like the
        true scene but coarser. "corners": S' of ``building_corner_prior`` (ground corners
        and the roof corners of ``known_fraction`` of the buildings, heights off by
        ``height_error``).
    spacing : float
        Mesh spacing of the "boxes" map (m); the map's footprints are multiples of it.
    position_error, size_error, height_error : float
        Standard deviations of the errors (m); zeros give the exact map (on the coarse grid).
    known_fraction : float
        For "corners", the share of buildings with known corners.
    rng : None, int or numpy.random.Generator

    Returns
    -------
    Terrain
    """
    boxes = _check_buildings(buildings)
    generator = as_generator(rng)
    if kind == "boxes":
        spacing = as_positive_float(spacing, "spacing")
        mapped = perturb_buildings(
            boxes,
            size=size,
            position_error=position_error,
            size_error=size_error,
            height_error=height_error,
            step=spacing,
            gap=spacing,
            rng=generator,
        )
        return buildings_terrain(mapped, size=size, spacing=spacing)
    if kind == "corners":
        prior = building_corner_prior(boxes, size=size, known_fraction=known_fraction, height_error=height_error, rng=generator)
        return approximate_surface(prior)
    raise InvalidInputError(f"kind must be 'boxes' or 'corners', got {kind!r}")
