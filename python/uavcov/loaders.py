"""Real terrain: elevation grids from numpy arrays (:func:`load_dem`) or GeoTIFF files
(:func:`load_geotiff`, needs ``rasterio``), meshes from OBJ / STL / PLY files (:func:`load_mesh`,
needs ``trimesh``) or arrays (:func:`mesh_terrain`), and :func:`sample_dem`, a real DEM that
matplotlib ships, usable offline.

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
from typing import Any

import numpy as np

from ._validate import (
    as_finite_float,
    as_float_array,
    as_index_array,
    as_positive_float,
    as_positive_int,
    as_spacing,
)
from .errors import InvalidInputError, InvalidTypeError, MeshError, MissingExtraError
from .surface import Terrain

__all__ = [
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


_WGS84_A = 6378137.0
_WGS84_F = 1.0 / 298.257223563
_WGS84_E2 = _WGS84_F * (2.0 - _WGS84_F)


def metres_per_degree(latitude: float) -> tuple[float, float]:
    """Metres per degree of longitude and of latitude at ``latitude`` (degrees), WGS84.

    From the prime-vertical radius ``N`` and the meridian radius ``M`` of the ellipsoid:
    ``(pi/180) N cos(phi)`` and ``(pi/180) M``.

    Examples
    --------
    >>> from uavcov import metres_per_degree
    >>> [round(v, 1) for v in metres_per_degree(45.0)]
    [78846.8, 111131.8]
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
    def identity(cls) -> LocalFrame:
        """The frame of data that is already local (generated scenes)."""
        return cls(np.zeros(3), np.ones(3))

    def to_local(self, points: Any) -> np.ndarray:
        """Source coordinates ``(n, 3)`` to local metres ``(n, 3)``."""
        array = _as_xyz(points, "points")
        local: np.ndarray = (array - self.origin) * self.factors
        return local

    def to_source(self, points: Any) -> np.ndarray:
        """Local metres ``(n, 3)`` back to source coordinates ``(n, 3)``."""
        array = _as_xyz(points, "points")
        source: np.ndarray = array / self.factors + self.origin
        return source


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

    Examples
    --------
    A 2 x 3 grid every 30 m in a projected frame (UTM-like eastings and northings), recentred:

    >>> import numpy as np, uavcov
    >>> z = np.array([[100.0, 101.0, 102.0], [100.0, 103.0, 104.0]])
    >>> dem = uavcov.load_dem(z, 30.0, lower_left=(500000.0, 4000000.0))
    >>> dem.terrain.bounds.tolist()
    [[0.0, 0.0, 0.0], [60.0, 30.0, 4.0]]
    >>> dem.frame.to_source([[60.0, 30.0, 4.0]]).tolist()
    [[500060.0, 4000030.0, 104.0]]
    """
    heights = as_float_array(z, "z", ndim=2, allow_nan=True)
    spacing_xy = as_spacing(spacing)
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
        raise InvalidInputError(f"z has no grid cell with four valid corners ({nodata_cells} of {heights.size} samples are nodata)")

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
    MissingExtraError
        When rasterio is not installed (``pip install uavcov[geotiff]``).
    InvalidInputError
        When the file does not exist, does not parse, or is rotated.
    """
    try:
        import rasterio
    except ImportError as exc:
        raise MissingExtraError("reading GeoTIFF files needs rasterio: pip install 'uavcov[geotiff]' (or pip install rasterio)") from exc
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
        from rasterio.errors import CRSError

        try:
            unit_factor = float(crs.linear_units_factor[1])
        except CRSError:  # a CRS without a linear unit: keep metres
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
    points = as_float_array(vertices, "vertices", nonfinite_error=MeshError)
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
    points = as_float_array(vertices, "vertices", nonfinite_error=MeshError)
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
    MissingExtraError
        When trimesh is not installed (``pip install uavcov[mesh]``).
    MeshError
        When the file does not exist, does not parse, or holds no triangles.
    """
    try:
        import trimesh
    except ImportError as exc:
        raise MissingExtraError("reading mesh files needs trimesh: pip install 'uavcov[mesh]' (or pip install trimesh)") from exc
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
    try:
        return mesh_terrain(
            np.asarray(vertices, dtype=np.float64),
            np.asarray(faces, dtype=np.int64),
            up=up,
            origin=origin,
            scale=scale,
            on_defect=on_defect,
            source=path_text,
        )
    except MeshError as exc:  # name the file in every mesh error
        if path_text in str(exc):
            raise
        raise MeshError(f"{path_text}: {exc}") from exc


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
    MissingExtraError
        When matplotlib is not installed (``pip install uavcov[plot]``).
    """
    try:
        from matplotlib import cbook
    except ImportError as exc:
        raise MissingExtraError("sample_dem reads a file that matplotlib ships: pip install matplotlib") from exc
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
            raise InvalidInputError(f"window must be four integers (row_start, row_stop, col_start, col_stop), got {window!r}")
        rows, cols = slice(int(bounds[0]), int(bounds[1])), slice(int(bounds[2]), int(bounds[3]))
    row_index = np.arange(ny)[rows][::stride]
    col_index = np.arange(nx)[cols][::stride]
    if row_index.size < 2 or col_index.size < 2:
        raise InvalidInputError(
            f"window {window!r} with stride {stride} keeps {row_index.size} x {col_index.size} samples; at least 2 x 2 are needed"
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
