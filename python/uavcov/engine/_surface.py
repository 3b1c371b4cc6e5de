"""The surface to cover: a triangle mesh, Z up, metres, with fast geometric queries.

A :class:`Terrain` is built from vertices and faces, from any mesh object with ``.vertices`` and
``.faces`` (``trimesh.Trimesh`` among them), or from a regular elevation grid. The Rust core keeps
a bounding volume hierarchy over the triangles and answers every query in parallel without the
GIL.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _core
from .._validate import (
    as_bool,
    as_bounds,
    as_finite_float,
    as_float_array,
    as_index_array,
    as_n_threads,
    as_non_negative_float,
    as_points,
    as_positive_float,
    as_str,
    not_a_terrain,
    read_only,
    within_coordinate_bound,
)
from ..errors import InvalidInputError, InvalidTypeError, MeshError
from ._targets import Targets

DEFAULT_TARGET_DENSITY = 1.0
"""Targets per m^2 on a general mesh when none is asked for: one per square metre, the paper's
1 m discretisation."""


@dataclass(frozen=True, eq=False)
class GridInfo:
    """The regular elevation grid a terrain was built from.

    Attributes
    ----------
    z : (ny, nx) float64 array
        Heights in metres, read-only; NaN marks nodata. Node ``(i, j)`` stands at
        ``x = origin[0] + j * spacing[0]``, ``y = origin[1] + i * spacing[1]``.
    spacing : (float, float)
        Cell size ``(dx, dy)`` in metres.
    origin : (float, float)
        ``(x, y)`` of node ``(0, 0)`` in metres.
    """

    z: np.ndarray
    spacing: tuple[float, float]
    origin: tuple[float, float]

    @property
    def shape(self) -> tuple[int, int]:
        """``(ny, nx)``."""
        return self.z.shape

    def node_xy(self) -> tuple[np.ndarray, np.ndarray]:
        """The x coordinates of the columns ``(nx,)`` and y coordinates of the rows ``(ny,)``."""
        ny, nx = self.shape
        return (
            self.origin[0] + np.arange(nx) * self.spacing[0],
            self.origin[1] + np.arange(ny) * self.spacing[1],
        )


class Terrain:
    """A surface to cover: a triangle mesh in metres, Z up.

    Parameters
    ----------
    vertices : (V, 3) array_like of float
        Vertex coordinates, metres; at most 1e15 m in magnitude (a coordinate there still
        resolves 0.125 m), so that squared distances stay exact enough to decide sight lines.
    faces : (F, 3) array_like of int
        Triangles as indices into ``vertices``.
    drop_degenerate : bool, default False
        Leave out zero-area triangles instead of raising :class:`~uavcov.errors.MeshError`
        (meshes read from files often carry a few).

    Raises
    ------
    MeshError
        No triangle, an index out of range, a non-finite coordinate, a coordinate beyond 1e15 m,
        a zero-area triangle, or a total area that is not a positive finite number.
    InvalidTypeError
        Faces that are not integers.

    Examples
    --------
    >>> import numpy as np, uavcov
    >>> t = uavcov.Terrain.from_grid(np.zeros((11, 11)), spacing=1.0)
    >>> float(t.area)
    100.0
    >>> t.ground_height([[5.0, 5.0]])
    array([0.])
    """

    __slots__ = ("_faces", "_grid", "_surface", "_vertices")

    def __init__(self, vertices: Any, faces: Any, *, drop_degenerate: bool = False) -> None:
        v = as_float_array(vertices, "vertices", allow_nan=True, nonfinite_error=MeshError)
        if v.ndim != 2 or v.shape[1] != 3:
            raise MeshError(f"vertices must have shape (V, 3), got {v.shape}")
        if not np.isfinite(v).all():
            raise MeshError("vertices contain NaN or infinite coordinates")
        f = as_index_array(faces, "faces")
        if f.shape[0] == 0:
            raise MeshError("the mesh has no face")
        if f.min() < 0 or f.max() >= v.shape[0]:
            raise MeshError(f"face indices must lie in [0, {v.shape[0]}), found {f.min()}..{f.max()}")
        if as_bool(drop_degenerate, "drop_degenerate"):
            f = f[~degenerate_faces(v, f)]
            if f.shape[0] == 0:
                raise MeshError("every face of the mesh is degenerate (zero area)")
        self._init(_core.Surface(v, f), None)

    def _init(self, surface: _core.Surface, grid: GridInfo | None) -> None:
        self._surface = surface
        self._grid = grid
        # A grid terrain keeps only its heights; vertices and faces are made on first access
        # (32 and 24 bytes a node, more than the rest of a large map).
        self._vertices: np.ndarray | None = None if grid is not None else read_only(surface.vertices())
        self._faces: np.ndarray | None = None if grid is not None else read_only(surface.faces())

    @classmethod
    def from_mesh(cls, mesh: Any, *, drop_degenerate: bool = False) -> Terrain:
        """Build from any object with ``.vertices`` ``(V, 3)`` and ``.faces`` ``(F, 3)``.

        A ``trimesh.Trimesh`` works without uavcov depending on trimesh.
        """
        if not (hasattr(mesh, "vertices") and hasattr(mesh, "faces")):
            raise InvalidTypeError(f"a mesh needs .vertices and .faces attributes, {type(mesh).__name__} has not both")
        return cls(np.asarray(mesh.vertices), np.asarray(mesh.faces), drop_degenerate=drop_degenerate)

    @classmethod
    def from_grid(cls, z: Any, spacing: Any, origin: Any = (0.0, 0.0)) -> Terrain:
        """Build from a regular elevation grid.

        Parameters
        ----------
        z : (ny, nx) array_like of float
            Heights in metres. Node ``(i, j)`` stands at ``x = origin[0] + j * dx``,
            ``y = origin[1] + i * dy``: rows go north. A raster stored with row 0 at the top
            (every north-up GeoTIFF) is ``z[::-1]`` with ``origin`` its south-west node, or
            goes with its geotransform and CRS to :func:`uavcov.terrain.dem_from_array`. NaN is
            nodata: no triangle touches a NaN node and no target stands there.
        spacing : float or (float, float)
            Cell size, metres: one value for square cells or ``(dx, dy)``.
        origin : (float, float), default (0, 0)
            ``(x, y)`` of node ``(0, 0)``, metres.

        Raises
        ------
        InvalidInputError
            Fewer than 2 rows or columns, a spacing that is not positive, a node or height beyond
            1e15 m, or a spacing the coordinates cannot resolve (node coordinates must strictly
            increase: 0.01 m cells 9e14 m from the origin are refused). Recentre far grids
            (:class:`uavcov.terrain.LocalFrame` does for DEMs).

        Notes
        -----
        Each cell is split along its diagonal from node ``(i, j)`` to ``(i + 1, j + 1)``.
        """
        heights = as_float_array(z, "z", ndim=2, allow_nan=True)
        if heights.shape[0] < 2 or heights.shape[1] < 2:
            raise InvalidInputError(f"an elevation grid needs at least 2 rows and 2 columns, got {heights.shape}")
        dx, dy = _pair(spacing, "spacing", positive=True)
        x0, y0 = _pair(origin, "origin", positive=False)
        surface = _core.Surface.from_grid(heights, dx, dy, x0, y0)
        terrain = cls.__new__(cls)
        terrain._init(surface, GridInfo(read_only(heights.copy()), (dx, dy), (x0, y0)))
        return terrain

    def __reduce__(self) -> tuple[Any, ...]:
        if self._grid is not None:
            return (Terrain.from_grid, (self._grid.z, self._grid.spacing, self._grid.origin))
        return (Terrain, (self.vertices, self.faces))

    def __repr__(self) -> str:
        kind = f"grid {self._grid.shape[0]}x{self._grid.shape[1]}" if self._grid else "mesh"
        return f"Terrain({kind}, {self.n_vertices} vertices, {self.n_faces} faces, area {self.area:.1f} m^2)"

    # -- what the terrain is -------------------------------------------------------------------

    @property
    def vertices(self) -> np.ndarray:
        """``(V, 3)`` float64 vertex coordinates, metres (read-only)."""
        if self._vertices is None:
            self._vertices = read_only(self._surface.vertices())
        return self._vertices

    @property
    def faces(self) -> np.ndarray:
        """``(F, 3)`` int64 vertex indices of each triangle (read-only)."""
        if self._faces is None:
            self._faces = read_only(self._surface.faces())
        return self._faces

    @property
    def n_vertices(self) -> int:
        """Number of vertices."""
        return int(self._surface.n_vertices)

    @property
    def n_faces(self) -> int:
        """Number of triangles."""
        return int(self._surface.n_faces)

    @property
    def area(self) -> float:
        """Total surface area, m^2."""
        return float(self._surface.area)

    @property
    def face_areas(self) -> np.ndarray:
        """``(F,)`` area of each triangle, m^2."""
        return read_only(self._surface.face_areas())

    @property
    def face_normals(self) -> np.ndarray:
        """``(F, 3)`` right-hand unit normal of each triangle (outward on a mesh wound
        counter-clockwise seen from outside; zero for a degenerate triangle).

        Examples
        --------
        >>> import numpy as np, uavcov
        >>> flat = uavcov.Terrain.from_grid(np.zeros((2, 2)), spacing=1.0)
        >>> flat.face_normals.tolist()
        [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]
        """
        return read_only(self._surface.face_normals())

    @property
    def bounds(self) -> np.ndarray:
        """``(2, 3)`` array ``[[xmin, ymin, zmin], [xmax, ymax, zmax]]``, metres."""
        return read_only(self._surface.bounds())

    @property
    def grid(self) -> GridInfo | None:
        """The elevation grid this terrain was built from, or None for a general mesh."""
        return self._grid

    @property
    def core(self) -> _core.Surface:
        """The Rust surface (``uavcov._core.Surface``), for library internals."""
        return self._surface

    # -- targets -------------------------------------------------------------------------------

    def default_targets(self, density: float | None = None) -> Targets:
        """The points whose visibility defines coverage, each weighted by the area it stands for.

        Parameters
        ----------
        density : float, optional
            Targets per m^2. When omitted, a grid terrain gives its nodes (each weighted by a third
            of the triangles around it) and a mesh gives one point per m^2. When given, points are
            spread evenly over every triangle at this density (grid or not): each triangle is cut
            into ``m^2`` congruent pieces, ``m = ceil(sqrt(area * density))``, with a target at
            each piece's centroid.

        Returns
        -------
        Targets
            Weights sum to :attr:`area`.
        """
        if density is None and self._grid is not None:
            points, weights = self._surface.vertex_targets()
        else:
            rate = DEFAULT_TARGET_DENSITY if density is None else as_positive_float(density, "density")
            points, weights = self._surface.area_targets(rate)
        return Targets(points, weights)

    def vertex_normals(self) -> np.ndarray:
        """Unit surface normals at a grid terrain's vertices, the points of its default targets.

        Each is the area-weighted sum of the normals of the (up to six) triangles around the
        node, normalised, pointing up: the normal the engine rates incidence with when it makes
        the grid's own targets. Give them to a subset of those targets
        (``Targets(points[keep], weights[keep], normals[keep])``) and incidence limits and view
        quality come out as on the whole grid.

        Returns
        -------
        (V, 3) float64 ndarray
            In the order of :meth:`default_targets` (and :attr:`vertices`).

        Raises
        ------
        InvalidInputError
            The terrain is a general mesh (its normals are the caller's to give).

        Examples
        --------
        >>> import numpy as np
        >>> slope = Terrain.from_grid(np.add.outer(np.zeros(3), np.arange(3.0)), spacing=1.0)  # z = x
        >>> np.round(slope.vertex_normals()[4], 4).tolist()  # (-1, 0, 1) / sqrt(2)
        [-0.7071, 0.0, 0.7071]
        """
        if self._grid is None:
            raise InvalidInputError("vertex_normals is for grid terrains (Terrain.from_grid); a mesh's targets take the normals you give")
        normals: np.ndarray = self._surface.vertex_normals()
        return normals

    # -- geometric queries ---------------------------------------------------------------------

    def ground_height(self, xy: Any, *, n_threads: int | None = None) -> np.ndarray:
        """Height of the highest surface point straight below each ``(x, y)``.

        Parameters
        ----------
        xy : (n, 2) array_like of float
            Horizontal positions, metres; ``(n, 3)`` points are accepted and their z ignored.
        n_threads : int, optional
            Threads for the Rust side, 1 to 1024; ``None`` (the default) is rayon's default:
            ``RAYON_NUM_THREADS`` if set, else every core. Results do not depend on it.

        Returns
        -------
        (n,) float64 array
            Heights in metres; NaN where no surface lies below.

        Examples
        --------
        >>> import numpy as np, uavcov
        >>> ramp = uavcov.Terrain.from_grid([[0.0, 1.0], [0.0, 1.0]], spacing=10.0)  # z = x / 10
        >>> ramp.ground_height([[2.5, 5.0], [20.0, 5.0]])  # the second point is off the grid
        array([0.25,  nan])
        """
        array = as_float_array(xy, "xy")
        if array.ndim == 1 and array.shape[0] in (2, 3):
            array = array.reshape(1, -1)
        if array.ndim != 2 or array.shape[1] not in (2, 3):
            raise InvalidInputError(f"xy must have shape (n, 2), got {array.shape}")
        return self._surface.ground_height(np.ascontiguousarray(array[:, :2]), as_n_threads(n_threads))

    def clearance(self, points: Any, *, n_threads: int | None = None) -> np.ndarray:
        """Distance from each point straight down to the surface.

        Parameters
        ----------
        points : (n, 3) array_like of float
        n_threads : int, optional
            Threads for the Rust side, 1 to 1024; ``None`` (the default) is rayon's default:
            ``RAYON_NUM_THREADS`` if set, else every core. Results do not depend on it.

        Returns
        -------
        (n,) float64 array
            Metres; ``inf`` where nothing lies below (off the surface or under it).

        Examples
        --------
        >>> import numpy as np, uavcov
        >>> flat = uavcov.Terrain.from_grid(np.zeros((11, 11)), spacing=1.0)
        >>> flat.clearance([[5.0, 5.0, 3.0], [5.0, 5.0, -1.0]])  # under the surface: nothing below
        array([ 3., inf])
        """
        return self._surface.clearance(as_points(points, "points", allow_empty=True), as_n_threads(n_threads))

    def closest_point(self, points: Any, *, n_threads: int | None = None) -> np.ndarray:
        """The surface point closest to each point: ``(n, 3)`` in, ``(n, 3)`` out, metres.

        ``n_threads`` as in :meth:`ground_height`.

        Examples
        --------
        >>> import numpy as np, uavcov
        >>> flat = uavcov.Terrain.from_grid(np.zeros((11, 11)), spacing=1.0)
        >>> flat.closest_point([[5.0, 5.0, 3.0], [12.0, 5.0, 0.0]])
        array([[ 5.,  5.,  0.],
               [10.,  5.,  0.]])
        """
        return self._surface.closest_point(as_points(points, "points", allow_empty=True), as_n_threads(n_threads))

    def closest_face(self, points: Any, *, n_threads: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The surface point closest to each point and the triangle it lies on (parry's point
        projection with its feature): ``(n, 3)`` in; ``(n, 3)`` points, metres, and ``(n,)``
        int64 face indices out.

        On an edge or a vertex the face is one of the triangles sharing it. ``n_threads`` as in
        :meth:`ground_height`.

        Examples
        --------
        >>> import numpy as np, uavcov
        >>> flat = uavcov.Terrain.from_grid(np.zeros((2, 2)), spacing=1.0)
        >>> point, face = flat.closest_face([[0.2, 0.7, 3.0]])
        >>> point.tolist(), flat.face_normals[face].tolist()
        ([[0.2, 0.7, 0.0]], [[0.0, 0.0, 1.0]])
        """
        closest, face = self._surface.closest_face(as_points(points, "points", allow_empty=True), as_n_threads(n_threads))
        return closest, np.asarray(face, dtype=np.int64)

    def faces_at_closest(self, points: Any, *, n_threads: int | None = None) -> tuple[np.ndarray, list[np.ndarray]]:
        """The surface point closest to each point and *every* triangle holding it.

        Inside a face, that face; on an edge or a vertex, every triangle sharing it; where two
        solids touch face to face (a pier's top under a deck), the triangles of both. A
        triangle holds the point when it lies within ``1e-9`` of the mesh's scale (largest
        coordinate magnitude plus largest extent, at least 1 m) of it (parry's point
        projection, then its BVH). ``n_threads`` as in :meth:`ground_height`.

        Returns
        -------
        closest : (n, 3) float64 ndarray
            Metres (as :meth:`closest_point`).
        faces : list of (k,) int64 ndarray
            Each point's triangles, in increasing order.

        Examples
        --------
        >>> import numpy as np, uavcov
        >>> flat = uavcov.Terrain.from_grid(np.zeros((2, 2)), spacing=1.0)
        >>> point, faces = flat.faces_at_closest([[0.2, 0.7, 3.0], [0.5, 0.5, 1.0]])
        >>> point.tolist(), [f.tolist() for f in faces]  # the second on the diagonal: both triangles
        ([[0.2, 0.7, 0.0], [0.5, 0.5, 0.0]], [[1], [0, 1]])
        """
        closest, start, faces = self._surface.faces_at_closest(as_points(points, "points", allow_empty=True), as_n_threads(n_threads))
        if not closest.shape[0]:
            return closest, []
        held = np.asarray(faces, dtype=np.int64)
        return closest, np.split(held, np.asarray(start, dtype=np.int64)[1:-1])

    def distance(self, points: Any, *, n_threads: int | None = None) -> np.ndarray:
        """The least 3D distance from each point to the surface: ``(n, 3)`` in, ``(n,)`` out, metres.

        The standoff of ``Constraints(clearance="standoff")``; ``n_threads`` as in
        :meth:`ground_height`. An elevation grid builds its triangle mesh on first use.

        Examples
        --------
        >>> import numpy as np, uavcov
        >>> flat = uavcov.Terrain.from_grid(np.zeros((11, 11)), spacing=1.0)
        >>> flat.distance([[5.0, 5.0, 3.0], [13.0, 9.0, 4.0]])
        array([3., 5.])
        """
        return self._surface.distance(as_points(points, "points", allow_empty=True), as_n_threads(n_threads))

    def inside(self, points: Any, *, n_threads: int | None = None) -> np.ndarray:
        """Whether each point is inside a closed solid of the mesh: ``(n, 3)`` in, ``(n,)`` bool out.

        A ray from the point crosses a closed solid's surface an odd number of times when it
        starts inside, and the faces it crosses do not cancel by their winding (+1 leaving an
        outward-wound face, -1 entering one) where two solids overlap or a face is given twice:
        a point is inside when they do not cancel along the ray (which an odd count never
        does); the answer is the vote of three fixed, skewed, upward rays (two of three),
        which keeps a ground plane below the point out of the count and survives a ray grazing
        an edge. Meant for meshes whose solids are closed (watertight) components; an open
        surface above a point (a hillside) may count as a wall and make it "inside", and so does
        a ground plane over a point under it (the flight limits refuse both).
        ``n_threads`` as in :meth:`ground_height`.

        Examples
        --------
        >>> import numpy as np, uavcov
        >>> box = uavcov.Terrain(
        ...     [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]],
        ...     [
        ...         [0, 2, 3],
        ...         [0, 3, 1],
        ...         [4, 5, 7],
        ...         [4, 7, 6],
        ...         [0, 1, 5],
        ...         [0, 5, 4],
        ...         [2, 6, 7],
        ...         [2, 7, 3],
        ...         [0, 4, 6],
        ...         [0, 6, 2],
        ...         [1, 3, 7],
        ...         [1, 7, 5],
        ...     ],
        ... )
        >>> box.inside([[0.5, 0.4, 0.3], [0.5, 0.4, 1.3]])
        array([ True, False])
        """
        return self._surface.inside(as_points(points, "points", allow_empty=True), as_n_threads(n_threads))

    def segments_clear(self, a: Any, b: Any, *, n_threads: int | None = None) -> np.ndarray:
        """Whether each closed segment ``a[k] -> b[k]`` crosses no triangle.

        Parameters
        ----------
        a, b : (n, 3) array_like of float
            Segment ends, metres.
        n_threads : int, optional
            Threads for the Rust side, 1 to 1024; ``None`` (the default) is rayon's default:
            ``RAYON_NUM_THREADS`` if set, else every core. Results do not depend on it.

        Returns
        -------
        (n,) bool array
            True where the segment touches no triangle, ends included.

        Examples
        --------
        >>> import numpy as np, uavcov
        >>> flat = uavcov.Terrain.from_grid(np.zeros((11, 11)), spacing=1.0)
        >>> flat.segments_clear([[2.0, 2.0, 1.0], [2.0, 2.0, 1.0]], [[8.0, 8.0, 5.0], [8.0, 8.0, -1.0]])
        array([ True, False])
        """
        pa = as_points(a, "a", allow_empty=True)
        pb = as_points(b, "b", allow_empty=True)
        if pa.shape != pb.shape:
            raise InvalidInputError(f"a and b must have the same shape, got {pa.shape} and {pb.shape}")
        return self._surface.segments_clear(pa, pb, as_n_threads(n_threads))

    def admissible_mask(
        self,
        current: Any,
        candidates: Any,
        *,
        bounds: tuple[float, float, float, float],
        h_min: float,
        h_max: float | None,
        z_max: float,
        d_safe: float,
        check_moves: bool,
        n_threads: int | None = None,
        clearance: str = "vertical",
    ) -> np.ndarray:
        """Which candidate configurations keep the flight limits of eq. 2, in one Rust pass.

        The fused form of ``uavcov.limits._constraints.feasible_mask``'s checks (x-y ``bounds``,
        ``z_max``, clearance in ``[h_min, h_max]``, pairs ``d_safe`` apart, moves from
        ``current`` crossing no triangle when ``check_moves``), with the same answers; that
        function calls it when the world is a ``Terrain`` and takes the limits from a
        :class:`~uavcov.limits.Constraints`, which is the way to use it.

        Parameters
        ----------
        current : (N, 3) array_like of float
            Positions now, metres.
        candidates : (M, N, 3) or (M * N, 3) array_like of float
            Candidate configurations, metres.
        bounds, h_min, h_max, z_max, d_safe, check_moves
            The resolved limits (``Constraints.flight_box`` and the fields of that name).
        n_threads : int, optional
            As in :meth:`clearance`; results do not depend on it.
        clearance : {"vertical", "standoff"}, default "vertical"
            What ``h_min`` and ``h_max`` bound (``Constraints.clearance``).

        Returns
        -------
        (M,) bool array
        """
        check = self.admissible_check(
            bounds=bounds,
            h_min=h_min,
            h_max=h_max,
            z_max=z_max,
            d_safe=d_safe,
            check_moves=check_moves,
            n_threads=n_threads,
            clearance=clearance,
        )
        return check(current, candidates)

    def admissible_check(
        self,
        *,
        bounds: tuple[float, float, float, float],
        h_min: float,
        h_max: float | None,
        z_max: float,
        d_safe: float,
        check_moves: bool,
        n_threads: int | None = None,
        clearance: str = "vertical",
    ) -> Callable[[Any, Any], np.ndarray]:
        """:meth:`admissible_mask` with these limits checked once: ``check(current, candidates)``.

        An optimiser asks for a mask hundreds of times a mission with the same limits; the
        callable checks only the positions on each call.
        """
        # The limits a Constraints holds, refused as it refuses them: a negative h_min or d_safe
        # would admit positions under the surface or UAVs on top of each other.
        xmin, ymin, xmax, ymax = as_bounds(bounds)
        floor = as_non_negative_float(h_min, "h_min")
        ceiling = None if h_max is None else as_finite_float(h_max, "h_max")
        if ceiling is not None and ceiling < floor:
            raise InvalidInputError(f"h_max = {ceiling} m is below h_min = {floor} m: no position would be admissible")
        separation = as_non_negative_float(d_safe, "d_safe")
        limits = (floor, ceiling, as_finite_float(z_max, "z_max"), separation, as_bool(check_moves, "check_moves"))
        threads = as_n_threads(n_threads)
        if not isinstance(clearance, str) or clearance not in ("vertical", "standoff"):
            raise InvalidInputError(f'clearance must be "vertical" or "standoff", got {clearance!r}')
        rust = self._surface.admissible_mask

        def check(current: Any, candidates: Any) -> np.ndarray:
            cur = as_points(current, "current")
            cand = as_float_array(candidates, "candidates")
            n_uavs = cur.shape[0]
            if cand.ndim == 3 and cand.shape[1:] == cur.shape:
                cand = cand.reshape(-1, 3)
            if n_uavs == 0 or cand.ndim != 2 or cand.shape[1] != 3 or cand.shape[0] % n_uavs:
                raise InvalidInputError(f"candidates must have shape (M, {n_uavs}, 3), got {cand.shape}")
            return rust(cur, cand, (xmin, ymin, xmax, ymax), *limits, threads, clearance)

        return check


def as_mesh_surface(surface: Any, purpose: str) -> Terrain:
    """``surface`` itself when it is a :class:`Terrain` with faces of positive area.

    What every query of faces and normals needs first (a start on S', the normals a viewpoint
    flies out along).

    Parameters
    ----------
    surface : Terrain
    purpose : str
        What needs the faces, for the message (e.g. ``"a start"``).

    Raises
    ------
    InvalidTypeError
        Not a Terrain.
    InvalidInputError
        No face, or no area.
    """
    purpose = as_str(purpose, "purpose")
    if not isinstance(surface, Terrain):
        raise not_a_terrain(surface, "surface")
    if surface.n_faces == 0 or surface.area <= 0.0:
        raise InvalidInputError(f"surface has no area: {purpose} needs a mesh with faces")
    return surface


def _pair(value: Any, name: str, *, positive: bool) -> tuple[float, float]:
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        values = (value, value)
    elif isinstance(value, (str, bytes, dict)):
        raise InvalidTypeError(f"{name} must be a number or a pair of numbers, got {type(value).__name__} {value!r}")
    else:
        try:
            values = tuple(value)
        except TypeError:
            raise InvalidTypeError(f"{name} must be a number or a pair of numbers, got {type(value).__name__}") from None
        if len(values) != 2:
            raise InvalidInputError(f"{name} must be a number or a pair of numbers, got {len(values)} values")
    check = as_positive_float if positive else as_finite_float
    return (check(values[0], name), check(values[1], name))


def degenerate_faces(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Which faces have zero area relative to the mesh's size: the rule the Rust core enforces,
    so a mesh cleaned by it is never refused (a Terrain cannot be built to ask it first).

    Parameters
    ----------
    vertices : (V, 3) float64 ndarray
        Finite, metres, within 1e15 m of the origin (the engine's bound).
    faces : (F, 3) int64 ndarray
        Indices into ``vertices``.

    Returns
    -------
    (F,) bool ndarray
        Area at most ``1e-13`` times the squared diagonal of the vertices' bounding box (ten
        times the core's threshold, so rounding never lets one through to it).
    """
    vertices, faces = as_points(vertices, "vertices", allow_empty=True), as_index_array(faces, "faces")
    within_coordinate_bound(vertices, "vertices")  # beyond, an area overflows and a real triangle would read as degenerate
    if faces.size and (faces.min() < 0 or faces.max() >= vertices.shape[0]):
        raise InvalidInputError(f"faces index vertices 0-{vertices.shape[0] - 1}, got indices {faces.min()}-{faces.max()}")
    if not faces.size:
        return np.zeros(0, dtype=bool)
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    diagonal = float(np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0)))
    # A margin of 10 over the core's threshold, so rounding never lets one through to it.
    degenerate: np.ndarray = area <= 1e-13 * max(diagonal, 1e-300) ** 2
    return degenerate
