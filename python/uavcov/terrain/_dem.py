"""Geo-referenced elevation models: a DEM's CRS <-> the local frame <-> WGS84, and its datums.

A :class:`GeoDem` is a terrain in a local metric frame (:class:`~uavcov.terrain.LocalFrame`) that
also knows its coordinate reference system (CRS), the raster grid it came from and what its heights are measured from.
Every plan output goes back out through it:

* local metres -> the DEM's CRS: :meth:`GeoDem.to_crs`, the inverse of the recentring of
  :mod:`uavcov.terrain` (projected CRSs keep their units; the local frame is recentred, so UTM
  eastings of 500 km and northings of 5000 km lose no precision in the engine);
* the DEM's CRS -> WGS84 (longitude, latitude): :meth:`GeoDem.to_wgs84`, through pyproj for a
  projected CRS or a geographic CRS other than WGS84, directly for WGS84 itself. Only the
  horizontal coordinates are transformed (a 2D transformation, so no geoid grid is needed and
  nothing is downloaded); heights pass through unchanged and keep the DEM's vertical datum.

Geographic DEMs are mapped to the local frame by the local equirectangular projection of
:mod:`uavcov.terrain` (about the centre latitude, WGS84 radii of curvature there). The map is
linear in degrees, so a position above grid node (i, j) in the local frame is above node (i, j)
in longitude and latitude, exactly; distances carry the projection's scale error
(``tan(latitude) * |dlatitude|``, 0.2 % at the edges of matplotlib's Jacksboro sample).

Vertical datums: a DEM's heights are whatever its file says (a compound CRS names the vertical
datum); a file that names none is stated as "unknown vertical datum", and altitudes computed from
it (``height + clearance``) are "above mean sea level" only as far as the DEM's heights are.
Heights in feet are not converted: elevations are taken as metres (as in :mod:`uavcov.terrain`).
"""

from __future__ import annotations

import functools
import os
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import (
    as_finite_float,
    as_float_array,
    as_index_array,
    as_optional_str,
    as_positive_float,
    as_positive_int,
    as_tuple,
    within_coordinate_bound,
)
from ..engine import Terrain
from ..errors import InvalidInputError, InvalidTypeError, MissingExtraError
from ._frame import LocalFrame, metres_per_degree
from ._meshes import MeshReport, load_mesh

WGS84 = "EPSG:4326"
"""The CRS of every longitude and latitude uavcov writes (GeoJSON, KML, QGroundControl)."""

SAMPLE_VERTICAL_DATUM = (
    "as in the source (matplotlib's jacksboro_fault_dem.npz): metres, unknown vertical datum (the sample documents none)"
)
"""What the heights of :func:`sample_dem` are measured from: the sample states no datum."""

_UNKNOWN_VERTICAL = "metres, unknown vertical datum (the DEM's CRS names none); taken as heights above mean sea level"


@dataclass(frozen=True)
class RasterGrid:
    """Where the grid nodes of a DEM lie in its raster (GDAL's layout: row 0 at the top).

    Attributes
    ----------
    transform : (float, float, float, float, float, float)
        The affine ``(a, b, c, d, e, f)`` of rasterio/GDAL: the pixel corner at column ``col``,
        row ``row`` is at ``x = c + col * a``, ``y = f + row * e`` (``b = d = 0``: north-up).
        Pixel centres are the grid nodes of the terrain.
    shape : (int, int)
        ``(rows, cols)``.
    """

    transform: tuple[float, float, float, float, float, float]
    shape: tuple[int, int]

    def __post_init__(self) -> None:
        # checked, not converted: a grid compares and hashes as given
        if as_float_array(self.transform, "transform", ndim=1).shape != (6,):
            raise InvalidInputError(f"transform must be six numbers (a, b, c, d, e, f), got {self.transform!r}")
        sides = as_tuple(self.shape, "shape")
        if len(sides) != 2:
            raise InvalidInputError(f"shape must be (rows, cols), got {self.shape!r}")
        for side in sides:
            as_positive_int(side, "shape")

    def node_of_pixel(self, rows: np.ndarray, cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The terrain grid node ``(i, j)`` (row 0 south) of raster pixels ``(row, col)``.

        Raises ``InvalidTypeError`` for indices that are not integers, ``InvalidInputError`` for
        indices outside the raster or of two shapes.
        """
        rows, cols = self._indices(rows, cols, ("rows", "cols"))
        north_up = self.transform[4] < 0.0
        i = (self.shape[0] - 1 - rows) if north_up else rows
        return np.asarray(i), np.asarray(cols)

    def pixel_of_node(self, i: np.ndarray, j: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The raster pixel ``(row, col)`` of terrain grid nodes ``(i, j)`` (its own inverse)."""
        i, j = self._indices(i, j, ("i", "j"))
        return self.node_of_pixel(i, j)

    def _indices(self, first: Any, second: Any, names: tuple[str, str]) -> tuple[np.ndarray, np.ndarray]:
        """Integer index arrays of one shape, each within its side of the raster."""
        pair = [as_index_array(value, name, columns=None) for value, name in zip((first, second), names, strict=True)]
        if pair[0].shape != pair[1].shape:
            raise InvalidInputError(f"{names[0]} and {names[1]} must have one shape, got {pair[0].shape} and {pair[1].shape}")
        for array, name, side in zip(pair, names, self.shape, strict=True):
            if array.size and (array.min() < 0 or array.max() >= side):
                raise InvalidInputError(f"{name} must lie in [0, {side}), got values from {array.min()} to {array.max()}")
        return pair[0], pair[1]


def wrap_longitude(lon: Any) -> np.ndarray:
    """Longitudes (degrees) in ``[-180, 180]``, as GeoJSON, KML and QGroundControl require.

    Values already in range are returned bit for bit; the others are reduced exactly
    (``fmod`` is exact in floating point), so 180.006 becomes -179.994.
    """
    values = as_float_array(lon, "longitude", allow_nan=True)  # NaN (no data) passes through as NaN
    outside = np.abs(values) > 180.0
    if not outside.any():
        return values
    reduced = np.fmod(values, 360.0)
    reduced = np.where(reduced > 180.0, reduced - 360.0, np.where(reduced < -180.0, reduced + 360.0, reduced))
    return np.where(outside, reduced, values)


def _unwrap_longitude(lon: np.ndarray, centre: float) -> np.ndarray:
    """Longitudes moved by whole turns to within 180 degrees of ``centre`` (those already there unchanged)."""
    far = np.abs(lon - centre) > 180.0
    if not far.any():
        return lon
    return np.where(far, lon + 360.0 * np.round((centre - lon) / 360.0), lon)


def _check_domain(crs: str, is_wgs84: bool, x: np.ndarray, y: np.ndarray, tolerance: float, source: str, name: str) -> None:
    """Refuse source coordinates outside the CRS's domain: every point must have a finite longitude
    and latitude that maps back to it (pyproj returns inf, or another point, outside a projection's
    domain), longitudes within [-360, 360] and latitudes within [-90, 90]."""
    if is_wgs84:
        lon, lat = x, y
    else:
        lon, lat = (np.asarray(v, dtype=np.float64) for v in _transformer(crs, WGS84).transform(x, y))
    bad = ~(np.isfinite(lon) & np.isfinite(lat)) | (np.abs(lon) > 360.0) | (np.abs(lat) > 90.0)
    if not is_wgs84 and not bad.any():
        back_x, back_y = (np.asarray(v, dtype=np.float64) for v in _transformer(WGS84, crs).transform(lon, lat))
        bad = ~(np.isfinite(back_x) & np.isfinite(back_y)) | (np.hypot(back_x - x, back_y - y) > tolerance)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise InvalidInputError(
            f"{source} lies outside the domain of its CRS ({name}): its point ({x[k]:.10g}, {y[k]:.10g}) has no "
            "longitude and latitude there; check the geotransform and the CRS"
        )


def _extent_samples(x0: float, x1: float, y0: float, y1: float) -> tuple[np.ndarray, np.ndarray]:
    """The corners, edge midpoints and centre of a box: where a DEM's extent meets its CRS's domain."""
    xs, ys = np.meshgrid([x0, 0.5 * (x0 + x1), x1], [y0, 0.5 * (y0 + y1), y1])
    return xs.ravel(), ys.ravel()


@functools.lru_cache(maxsize=16)
def _transformer(source: str, target: str) -> Any:
    from pyproj import Transformer

    return Transformer.from_crs(source, target, always_xy=True)


def _pyproj_crs(crs: Any) -> Any:
    try:
        from pyproj import CRS
        from pyproj.exceptions import CRSError
    except ImportError as exc:
        raise MissingExtraError("coordinate reference systems need pyproj: pip install 'uavcov[geo]'") from exc
    if isinstance(crs, (str, int)) or hasattr(crs, "to_wkt"):
        try:
            return CRS.from_user_input(crs.to_wkt() if hasattr(crs, "to_wkt") else crs)
        except CRSError as exc:
            raise InvalidInputError(f"{crs!r} is not a coordinate reference system pyproj knows: {exc}") from None
    raise InvalidTypeError(f"crs must be a string such as 'EPSG:32633', an EPSG code or a CRS object, got {type(crs).__name__}")


def _is_wgs84_text(crs: str) -> bool:
    return crs.strip().upper() in ("EPSG:4326", "OGC:CRS84", "4326")


@dataclass(frozen=True, eq=False)
class GeoDem:
    """A terrain with its coordinate reference system, its raster grid and its vertical datum.

    Attributes
    ----------
    terrain : Terrain
        The surface in the local metric frame (metres, Z up).
    frame : LocalFrame
        Local <-> source coordinates (``frame.to_source`` is :meth:`to_crs`).
    crs : str
        The horizontal CRS of the source coordinates, as WKT or an authority code.
    crs_name : str
        A readable name (``"WGS 84 / UTM zone 33N (EPSG:32633)"``).
    geographic : bool
        True when the source coordinates are longitude and latitude in degrees.
    vertical_datum : str
        What the heights are measured from (see the module notes).
    raster : RasterGrid or None
        The DEM's raster grid (None for a mesh): where coverage GeoTIFFs go.
    is_wgs84 : bool
        True when the CRS is WGS84 geographic (no transformation to longitude, latitude).
    source : str
        Where the DEM came from (a path or a short description).
    nodata_cells : int
        Elevation samples that were nodata (left out of the surface and its targets); 0 for meshes.
    mesh_report : MeshReport or None
        What was repaired, for a mesh DEM.
    """

    terrain: Terrain
    frame: LocalFrame
    crs: str
    crs_name: str
    geographic: bool
    vertical_datum: str
    raster: RasterGrid | None
    is_wgs84: bool
    source: str = ""
    nodata_cells: int = 0
    mesh_report: MeshReport | None = None

    def __repr__(self) -> str:
        # The CRS's WKT and the frame's arrays run to thousands of characters: name them instead.
        nodata = f", {self.nodata_cells} nodata cells" if self.nodata_cells else ""
        return f"GeoDem({self.source!r}, {self.crs_name}, {self.terrain!r}{nodata}, heights: {self.vertical_datum})"

    def to_crs(self, local: Any) -> np.ndarray:
        """Local ``(n, 3)`` metres -> ``(n, 3)`` (x, y, height) in the DEM's CRS and vertical datum."""
        return self.frame.to_source(local)

    def from_crs(self, points: Any) -> np.ndarray:
        """``(n, 3)`` (x, y, height) in the DEM's CRS -> local ``(n, 3)`` metres."""
        return self.frame.to_local(points)

    def to_wgs84(self, local: Any) -> np.ndarray:
        """Local ``(n, 3)`` metres -> ``(n, 3)`` (longitude, latitude in degrees, height in the DEM's
        vertical datum)."""
        source = self.to_crs(local)
        if self.is_wgs84:
            lon, lat = source[:, 0], source[:, 1]
        else:
            lon, lat = _transformer(self.crs, WGS84).transform(source[:, 0], source[:, 1])
        lon, lat = np.asarray(lon, dtype=np.float64), np.asarray(lat, dtype=np.float64)
        if not (np.isfinite(lon).all() and np.isfinite(lat).all() and (np.abs(lat) <= 90.0).all()):
            raise InvalidInputError(
                f"points of {self.source or 'the DEM'} lie outside the domain of its CRS ({self.crs_name}): "
                "they have no longitude and latitude"
            )
        return np.column_stack([wrap_longitude(lon), lat, source[:, 2]])

    def from_wgs84(self, lonlat: Any) -> np.ndarray:
        """``(n, 2)`` or ``(n, 3)`` (longitude, latitude[, height]) -> local ``(n, 3)`` metres
        (height 0 in the DEM's datum when not given)."""
        array = as_float_array(lonlat, "lonlat")
        if array.ndim == 1:
            array = array.reshape(1, -1)
        if array.ndim != 2 or array.shape[1] not in (2, 3):
            raise InvalidInputError(f"lonlat must have shape (n, 2) or (n, 3), got {array.shape}")
        if (np.abs(array[:, 1]) > 90.0).any() or (np.abs(array[:, 0]) > 360.0).any():
            raise InvalidInputError("longitudes must be in [-360, 360] and latitudes in [-90, 90] degrees")
        height = array[:, 2] if array.shape[1] == 3 else np.zeros(array.shape[0])
        if self.is_wgs84:
            x, y = array[:, 0], array[:, 1]
        else:
            x, y = _transformer(WGS84, self.crs).transform(array[:, 0], array[:, 1])
        if self.geographic:  # a DEM across the antimeridian may count longitudes past 180: meet it there
            centre = float(self.frame.to_source(self.terrain.bounds.mean(axis=0, keepdims=True))[0, 0])
            x = _unwrap_longitude(np.asarray(x, dtype=np.float64), centre)
        return self.from_crs(np.column_stack([x, y, height]))

    def crs_to_local_xy(self, xy: Any) -> np.ndarray:
        """``(n, 2)`` (x, y) in the DEM's CRS -> ``(n, 2)`` local metres."""
        array = as_float_array(xy, "xy")
        if array.ndim == 1:
            array = array.reshape(1, -1)
        if array.ndim != 2 or array.shape[1] != 2:
            raise InvalidInputError(f"xy must have shape (n, 2), got {array.shape}")
        return self.from_crs(np.column_stack([array, np.zeros(array.shape[0])]))[:, :2]


def _crs_facts(crs: Any) -> tuple[str, str, bool, str, float, bool]:
    """(WKT, name, geographic, vertical datum statement, metres per horizontal unit, is WGS84)."""
    if isinstance(crs, str) and _is_wgs84_text(crs):
        try:
            parsed = _pyproj_crs(crs)
        except MissingExtraError:  # WGS84 needs no pyproj
            return WGS84, "WGS 84 (EPSG:4326)", True, _UNKNOWN_VERTICAL, 1.0, True
    else:
        parsed = _pyproj_crs(crs)
    horizontal = parsed
    vertical = None
    if parsed.is_compound:
        for sub in parsed.sub_crs_list:
            if sub.is_vertical:
                vertical = sub
            else:
                horizontal = sub
    if horizontal.is_vertical or not (horizontal.is_geographic or horizontal.is_projected):
        raise InvalidInputError(f"the CRS {parsed.name!r} is neither projected nor geographic; a DEM needs a horizontal CRS")
    code = horizontal.to_epsg()
    name = f"{horizontal.name} (EPSG:{code})" if code else horizontal.name
    datum = _UNKNOWN_VERTICAL
    if vertical is not None:
        vcode = vertical.to_epsg()
        datum = f"metres above {vertical.name}" + (f" (EPSG:{vcode})" if vcode else "")
    factor = 1.0
    if horizontal.is_projected:
        factor = float(horizontal.axis_info[0].unit_conversion_factor)
    is_wgs84 = code == 4326
    text = WGS84 if is_wgs84 else horizontal.to_wkt()
    return text, name, bool(horizontal.is_geographic), datum, factor, is_wgs84


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
) -> tuple[Terrain, LocalFrame, int]:
    """The grid Terrain, its frame and its count of nodata samples, from checked input (row 0 is the south edge).

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
    return terrain, frame, nodata_cells


def dem_from_array(
    z: Any,
    transform: Any,
    crs: Any,
    *,
    nodata: float | None = None,
    vertical_datum: str | None = None,
    source: str = "array",
) -> GeoDem:
    """A DEM from a raster array, its affine transform and its CRS.

    Parameters
    ----------
    z : array_like, shape (rows, cols)
        Heights (m) at pixel centres, in raster order (row 0 at the top when ``transform``'s ``e``
        is negative, as in every north-up GeoTIFF); NaN (and ``nodata``) mark nodata.
    transform : (a, b, c, d, e, f)
        rasterio/GDAL affine (``b = d = 0``; see :class:`RasterGrid`), in the CRS's units.
    crs : str, int or CRS
        Anything pyproj reads (``"EPSG:32633"``, WKT, ...). WGS84 (``"EPSG:4326"``) needs no pyproj.
    nodata : float, optional
        A sentinel height that marks nodata.
    vertical_datum : str, optional
        What the heights are measured from, when the CRS does not say.

    Returns
    -------
    GeoDem
    """
    vertical_datum = as_optional_str(vertical_datum, "vertical_datum")
    if not isinstance(source, str):
        raise InvalidTypeError(f"source must be a string, got {type(source).__name__}")
    heights = within_coordinate_bound(as_float_array(z, "z", ndim=2, allow_nan=True), "z")  # NaN is nodata
    values = as_float_array(transform, "transform", ndim=1)
    if values.shape[0] < 6:
        raise InvalidInputError(f"transform must be the six numbers (a, b, c, d, e, f), got {values.shape[0]}")
    a, b, c, d, e, f = (float(v) for v in values[:6])
    if b != 0.0 or d != 0.0:
        raise InvalidInputError(f"{source} is rotated or sheared (transform {tuple(values[:6])}); warp it north-up first")
    if not (a > 0.0 and e != 0.0):
        raise InvalidInputError(f"{source} has an unusable pixel size ({a}, {e})")
    wkt, name, geographic, datum, factor, is_wgs84 = _crs_facts(crs)
    rows, cols = heights.shape
    x_edges, y_edges = (c, c + cols * a), (f, f + rows * e)
    if geographic and (max(abs(v) for v in x_edges) > 360.0 or cols * a > 360.0):
        raise InvalidInputError(
            f"{source}: longitudes {min(x_edges):.10g}..{max(x_edges):.10g} are not on the Earth "
            "(a geographic DEM lies within [-360, 360] degrees and spans at most 360)"
        )
    if not geographic:
        _check_domain(wkt, is_wgs84, *_extent_samples(*x_edges, *y_edges), 1e-3 * min(a, abs(e)), source, name)
    # Pixel centres are the grid nodes: x_j = c + (j + 1/2) a, y_i = f + (i + 1/2) e.
    if e < 0.0:
        south_first = heights[::-1]
        y_south = f + (rows - 0.5) * e
    else:
        south_first = heights
        y_south = f + 0.5 * e
    terrain, frame, nodata_cells = _grid_terrain(
        south_first,
        (a, abs(e)),
        np.array([c + 0.5 * a, y_south]),
        geographic=geographic,
        unit_factor=factor,
        nodata=nodata,
        origin=None,
        scale=1.0,
    )
    grid = RasterGrid(transform=(a, b, c, d, e, f), shape=(int(heights.shape[0]), int(heights.shape[1])))
    return GeoDem(terrain, frame, wkt, name, geographic, vertical_datum or datum, grid, is_wgs84, source, nodata_cells)


def read_dem(path: Any, *, crs: Any = None, band: int = 1) -> GeoDem:
    """A GeoTIFF (or any raster GDAL reads) DEM with its CRS; needs ``rasterio`` (and ``pyproj``
    unless the CRS is WGS84).

    Parameters
    ----------
    path : str or os.PathLike
    crs : str, int or CRS, optional
        The CRS of a file that states none (refused otherwise: a DEM without a CRS cannot be
        placed on the Earth). A file that has one must agree with it.
    band : int
        The band of heights (1-based).

    Raises
    ------
    MissingExtraError
        rasterio (or pyproj) is not installed: ``pip install 'uavcov[geo]'``.
    InvalidInputError
        No such file, not a raster, no CRS, rotated, every sample nodata.
    """
    try:
        import rasterio
    except ImportError as exc:
        raise MissingExtraError("reading GeoTIFF DEMs needs rasterio: pip install 'uavcov[geo]'") from exc
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidTypeError(f"path must be a string or os.PathLike, got {type(path).__name__}")
    text = os.fspath(path)
    if not os.path.isfile(text):
        raise InvalidInputError(f"DEM file {text!r} does not exist or is not a file")
    band = as_positive_int(band, "band")
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")  # rasterio's warnings become this function's errors, in the user's words
            with rasterio.open(text) as dataset:
                if band > dataset.count:
                    raise InvalidInputError(f"{text} has {dataset.count} band(s), asked for band {band}")
                kind = np.dtype(dataset.dtypes[band - 1]).kind
                if kind not in "iuf":
                    raise InvalidInputError(f"{text} holds {dataset.dtypes[band - 1]} values, not heights (a DEM's band is real numbers)")
                rows, cols = dataset.height, dataset.width
                if rows * cols > 100_000_000:  # before reading: 800 MB of float64
                    raise InvalidInputError(f"{text} has {rows} x {cols} pixels; crop it to at most 100 million for a plan")
                georeferenced = not (dataset.transform.is_identity and not dataset.gcps[0])
                data = dataset.read(band, masked=True)
                transform = tuple(dataset.transform)[:6]
                file_crs = dataset.crs
    except InvalidInputError:
        raise
    except Exception as exc:  # noqa: BLE001 - rasterio raises its own hierarchy (and GDAL's) for unreadable files
        raise InvalidInputError(f"cannot read {text} as a raster: {exc}") from None
    if not georeferenced or any(type(w.message).__name__ == "NotGeoreferencedWarning" for w in caught):
        raise InvalidInputError(
            f"{text} is not geo-referenced (it has no geotransform): a DEM is a GeoTIFF (or a raster GDAL reads) "
            "that places its pixels on the Earth"
        )
    if file_crs is None:
        if crs is None:
            raise InvalidInputError(f"{text} states no CRS: give its CRS (for example crs='EPSG:32633', --crs on the command line)")
        chosen = crs
    else:
        chosen = file_crs.to_wkt()
        if crs is not None and not _pyproj_crs(crs).equals(_pyproj_crs(chosen), ignore_axis_order=True):
            raise InvalidInputError(f"{text} states its CRS ({file_crs}), which differs from the crs given ({crs})")
    heights = np.ma.filled(data.astype(np.float64), np.nan)
    return dem_from_array(heights, transform, chosen, source=text)


def read_mesh_dem(path: Any, crs: Any, *, up: str = "z") -> GeoDem:
    """A terrain mesh (OBJ, STL, PLY; vertices in a projected CRS's units) with its CRS; needs
    ``trimesh`` and ``pyproj``. It has no raster grid: plans on it write no coverage GeoTIFF.

    Raises
    ------
    InvalidInputError
        A geographic CRS (a mesh in degrees is not a metric surface) or a CRS not in metres.
    """
    wkt, name, geographic, datum, factor, is_wgs84 = _crs_facts(crs)
    if geographic or factor != 1.0:
        raise InvalidInputError(f"a mesh's vertices must be in a projected CRS in metres, got {name}")
    mesh = load_mesh(path, up=up)
    (x0, y0, _), (x1, y1, _) = mesh.frame.to_source(mesh.terrain.bounds)
    _check_domain(wkt, is_wgs84, *_extent_samples(x0, x1, y0, y1), 1e-3, mesh.source, name)
    return GeoDem(mesh.terrain, mesh.frame, wkt, name, False, datum, None, is_wgs84, mesh.source, 0, mesh.mesh_report)


def sample_dem(window: Any = (150, 190, 150, 190), stride: int = 1) -> GeoDem:
    """A real DEM available offline: the Jacksboro fault DEM that matplotlib ships, geo-referenced.

    The file (``jacksboro_fault_dem.npz`` in matplotlib's sample data) is a 344 x 403 grid of
    elevations (236-1076 m) every 3 arc-seconds over 84.41-84.08 W, 36.45-36.73 N (Tennessee,
    USA), stored north row first; cells are about 74.6 m east-west and 92.5 m north-south. Its
    coordinates are taken as WGS84 longitude and latitude (EPSG:4326; the sample states no datum,
    and its cells are far coarser than any datum shift); its heights are metres of an unknown
    vertical datum (``SAMPLE_VERTICAL_DATUM``).

    Parameters
    ----------
    window : (int, int, int, int) or None
        ``(row_start, row_stop, col_start, col_stop)`` of the grid to keep, rows counted from
        the south edge and columns from the west edge (Python slice rules); ``None`` keeps all.
        The default is 40 x 40 nodes (about 3.0 km x 3.7 km) near the middle of the sample.
    stride : int
        Keep every ``stride``-th row and column of the window.

    Raises
    ------
    MissingExtraError
        When matplotlib is not installed (``pip install uavcov[plot]``).

    Examples
    --------
    >>> dem = sample_dem(window=(0, 5, 0, 6))
    >>> dem.terrain.grid.shape, dem.is_wgs84
    ((5, 6), True)
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
        bounds = as_tuple(window, "window")
        if len(bounds) != 4 or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v >= 0 for v in bounds):
            raise InvalidInputError(f"window must be four integers >= 0 (row_start, row_stop, col_start, col_stop), got {window!r}")
        rows, cols = slice(int(bounds[0]), int(bounds[1])), slice(int(bounds[2]), int(bounds[3]))
    row_index = np.arange(ny)[rows][::stride]
    col_index = np.arange(nx)[cols][::stride]
    if row_index.size < 2 or col_index.size < 2:
        raise InvalidInputError(
            f"window {window!r} with stride {stride} keeps {row_index.size} x {col_index.size} samples; at least 2 x 2 are needed"
        )
    heights = elevation[np.ix_(row_index, col_index)]
    # Grid points are cell centres: half a cell in from the file's edges.
    lower_left = np.array([west + (col_index[0] + 0.5) * dx, south + (row_index[0] + 0.5) * dy])
    terrain, frame, nodata_cells = _grid_terrain(
        heights, (dx * stride, dy * stride), lower_left, geographic=True, unit_factor=1.0, nodata=None, origin=None, scale=1.0
    )
    # The raster's pixels from the grid as the engine holds it, back in degrees.
    grid = terrain.grid
    if grid is None:  # from_grid always keeps its grid
        raise InvalidInputError("the sample DEM has no grid")
    ny, nx = grid.shape
    south_west = frame.to_source([[grid.origin[0], grid.origin[1], 0.0]])[0]
    dlon = grid.spacing[0] / frame.factors[0]
    dlat = grid.spacing[1] / frame.factors[1]
    north = south_west[1] + (ny - 1) * dlat
    transform = (float(dlon), 0.0, float(south_west[0] - 0.5 * dlon), 0.0, float(-dlat), float(north + 0.5 * dlat))
    raster = RasterGrid(transform=transform, shape=(ny, nx))
    source = "matplotlib sample data: jacksboro_fault_dem.npz"
    return GeoDem(terrain, frame, WGS84, "WGS 84 (EPSG:4326)", True, SAMPLE_VERTICAL_DATUM, raster, True, source, nodata_cells)
