"""Geo-referenced elevation models: a DEM's CRS <-> the local frame <-> WGS84, and its datums.

A :class:`GeoDem` is a :class:`~uavcov.loaders.LoadedTerrain` that also knows its coordinate
reference system (CRS), the raster grid it came from and what its heights are measured from.
Every plan output goes back out through it:

* local metres -> the DEM's CRS: :meth:`GeoDem.to_crs`, the inverse of the recentring of
  :mod:`uavcov.loaders` (projected CRSs keep their units; the local frame is recentred, so UTM
  eastings of 500 km and northings of 5000 km lose no precision in the engine);
* the DEM's CRS -> WGS84 (longitude, latitude): :meth:`GeoDem.to_wgs84`, through pyproj for a
  projected CRS or a geographic CRS other than WGS84, directly for WGS84 itself. Only the
  horizontal coordinates are transformed (a 2D transformation, so no geoid grid is needed and
  nothing is downloaded); heights pass through unchanged and keep the DEM's vertical datum.

Geographic DEMs are mapped to the local frame by the local equirectangular projection of
:mod:`uavcov.loaders` (about the centre latitude, WGS84 radii of curvature there). The map is
linear in degrees, so a position above grid node (i, j) in the local frame is above node (i, j)
in longitude and latitude, exactly; distances carry the projection's scale error
(``tan(latitude) * |dlatitude|``, 0.2 % at the edges of matplotlib's Jacksboro sample).

Vertical datums: a DEM's heights are whatever its file says (a compound CRS names the vertical
datum); a file that names none is stated as "unknown vertical datum", and altitudes computed from
it (``height + clearance``) are "above mean sea level" only as far as the DEM's heights are.
Heights in feet are not converted: elevations are taken as metres (as in :mod:`uavcov.loaders`).
"""

from __future__ import annotations

import functools
import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._validate import as_float_array, as_positive_int
from .errors import InvalidInputError, InvalidTypeError, MissingExtraError
from .loaders import LoadedTerrain, LocalFrame, _grid_terrain, load_mesh, sample_dem
from .surface import Terrain

__all__ = [
    "RasterGrid",
    "GeoDem",
    "dem_from_array",
    "read_dem",
    "read_mesh_dem",
    "sample_geo_dem",
    "WGS84",
    "SAMPLE_VERTICAL_DATUM",
]

WGS84 = "EPSG:4326"
"""The CRS of every longitude and latitude uavcov writes (GeoJSON, KML, QGroundControl)."""

SAMPLE_VERTICAL_DATUM = (
    "as in the source (matplotlib's jacksboro_fault_dem.npz): metres, unknown vertical datum (the sample documents none)"
)
"""What the heights of :func:`sample_geo_dem` are measured from: the sample states no datum."""

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

    def node_of_pixel(self, rows: np.ndarray, cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The terrain grid node ``(i, j)`` (row 0 south) of raster pixels ``(row, col)``."""
        north_up = self.transform[4] < 0.0
        i = (self.shape[0] - 1 - rows) if north_up else rows
        return np.asarray(i), np.asarray(cols)

    def pixel_of_node(self, i: np.ndarray, j: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The raster pixel ``(row, col)`` of terrain grid nodes ``(i, j)`` (its own inverse)."""
        return self.node_of_pixel(np.asarray(i), np.asarray(j))


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
    loaded : LoadedTerrain
        The terrain in the local frame (metres, Z up) and the frame back to the source.
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
    """

    loaded: LoadedTerrain
    crs: str
    crs_name: str
    geographic: bool
    vertical_datum: str
    raster: RasterGrid | None
    is_wgs84: bool

    @property
    def terrain(self) -> Terrain:
        """The terrain in the local frame."""
        return self.loaded.terrain

    @property
    def frame(self) -> LocalFrame:
        """Local <-> source coordinates."""
        return self.loaded.frame

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
            return source
        lon, lat = _transformer(self.crs, WGS84).transform(source[:, 0], source[:, 1])
        return np.column_stack([lon, lat, source[:, 2]])

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
    heights = as_float_array(z, "z", ndim=2, allow_nan=True)
    values = as_float_array(transform, "transform", ndim=1)
    if values.shape[0] < 6:
        raise InvalidInputError(f"transform must be the six numbers (a, b, c, d, e, f), got {values.shape[0]}")
    a, b, c, d, e, f = (float(v) for v in values[:6])
    if b != 0.0 or d != 0.0:
        raise InvalidInputError(f"{source} is rotated or sheared (transform {tuple(values[:6])}); warp it north-up first")
    if not (a > 0.0 and e != 0.0):
        raise InvalidInputError(f"{source} has an unusable pixel size ({a}, {e})")
    wkt, name, geographic, datum, factor, is_wgs84 = _crs_facts(crs)
    rows = heights.shape[0]
    # Pixel centres are the grid nodes: x_j = c + (j + 1/2) a, y_i = f + (i + 1/2) e.
    if e < 0.0:
        south_first = heights[::-1]
        y_south = f + (rows - 0.5) * e
    else:
        south_first = heights
        y_south = f + 0.5 * e
    loaded = _grid_terrain(
        south_first,
        (a, abs(e)),
        np.array([c + 0.5 * a, y_south]),
        geographic=geographic,
        unit_factor=factor,
        nodata=nodata,
        origin=None,
        scale=1.0,
        source=source,
    )
    grid = RasterGrid(transform=(a, b, c, d, e, f), shape=(int(heights.shape[0]), int(heights.shape[1])))
    return GeoDem(loaded, wkt, name, geographic, vertical_datum or datum, grid, is_wgs84)


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
        with rasterio.open(text) as dataset:
            if band > dataset.count:
                raise InvalidInputError(f"{text} has {dataset.count} band(s), asked for band {band}")
            rows, cols = dataset.height, dataset.width
            if rows * cols > 100_000_000:  # before reading: 800 MB of float64
                raise InvalidInputError(f"{text} has {rows} x {cols} pixels; crop it to at most 100 million for a plan")
            data = dataset.read(band, masked=True)
            transform = tuple(dataset.transform)[:6]
            file_crs = dataset.crs
    except InvalidInputError:
        raise
    except Exception as exc:  # noqa: BLE001 - rasterio raises its own hierarchy (and GDAL's) for unreadable files
        raise InvalidInputError(f"cannot read {text} as a raster: {exc}") from None
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
    loaded = load_mesh(path, up=up)
    return GeoDem(loaded, wkt, name, False, datum, None, is_wgs84)


def sample_geo_dem(window: Any = (150, 190, 150, 190), stride: int = 1) -> GeoDem:
    """matplotlib's Jacksboro DEM (:func:`uavcov.loaders.sample_dem`) as a geo-referenced DEM.

    Its coordinates are taken as WGS84 longitude and latitude (EPSG:4326; the sample states no
    datum, and its 3 arc-second cells are 75-93 m, far coarser than any datum shift); its heights
    are metres of an unknown vertical datum (:data:`SAMPLE_VERTICAL_DATUM`). The default window is
    40 x 40 nodes (about 3.0 km x 3.7 km) near the middle of the sample.
    """
    loaded = sample_dem(window, stride)
    grid = loaded.terrain.grid
    if grid is None:  # sample_dem always builds a grid
        raise InvalidInputError("the sample DEM has no grid")
    frame = loaded.frame
    ny, nx = grid.shape
    south_west = frame.to_source([[grid.origin[0], grid.origin[1], 0.0]])[0]
    dlon = grid.spacing[0] / frame.factors[0]
    dlat = grid.spacing[1] / frame.factors[1]
    north = south_west[1] + (ny - 1) * dlat
    transform = (float(dlon), 0.0, float(south_west[0] - 0.5 * dlon), 0.0, float(-dlat), float(north + 0.5 * dlat))
    raster = RasterGrid(transform=transform, shape=(ny, nx))
    return GeoDem(loaded, WGS84, "WGS 84 (EPSG:4326)", True, SAMPLE_VERTICAL_DATUM, raster, True)
