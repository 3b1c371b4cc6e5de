"""The area of interest of a plan: polygons from GeoJSON or KML, or a bounding box.

An :class:`AreaOfInterest` holds polygons (an exterior ring and holes each) in WGS84 longitude
and latitude (GeoJSON's and KML's own CRS) or in the DEM's CRS (a bounding box given in it).
:meth:`AreaOfInterest.contains` tells which local points lie inside, after the rings are mapped
into the local frame through the DEM (:class:`uavcov.terrain.GeoDem`); rings are straight between
their vertices in the local frame (not geodesics: for a local area the difference is far under a
cell). Inside is the even-odd rule: a point inside a hole is outside; a point on an edge may go
either way.
"""

from __future__ import annotations

import json
import math
import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import as_finite_float, as_float_array, as_optional_str, as_tuple
from ..errors import InvalidInputError, InvalidTypeError
from ..terrain import GeoDem, wrap_longitude
from ._strict_json import unique_names

AREA_FRAMES = ("wgs84", "dem")
"""What an area's coordinates are in: WGS84 (longitude, latitude) or the DEM's CRS."""

_MAX_VERTICES = 1_000_000


def _ring(value: Any, where: str) -> np.ndarray:
    ring = as_float_array(value, where)
    if ring.ndim != 2 or ring.shape[1] < 2:
        raise InvalidInputError(f"{where} must be a list of (x, y) positions, got shape {ring.shape}")
    ring = np.ascontiguousarray(ring[:, :2])
    if ring.shape[0] > 1 and np.array_equal(ring[0], ring[-1]):
        ring = ring[:-1]
    if ring.shape[0] < 3:
        raise InvalidInputError(f"{where} has {ring.shape[0]} distinct vertices; a polygon ring needs 3")
    ring.setflags(write=False)
    return ring


@dataclass(frozen=True, eq=False)
class AreaOfInterest:
    """Polygons that restrict a plan: coverage targets and the CVT region lie inside.

    Attributes
    ----------
    polygons : tuple of tuple of ndarray
        Each polygon is its rings, ``(k, 2)`` arrays: the exterior first, then holes.
    frame : {"wgs84", "dem"}
        The coordinates: WGS84 (longitude, latitude in degrees) or the DEM's CRS.
    source : str
        Where it came from (a file, "bbox").
    """

    polygons: tuple[tuple[np.ndarray, ...], ...]
    frame: str = "wgs84"
    source: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.frame, str) or self.frame not in AREA_FRAMES:
            raise InvalidInputError(f"frame must be one of {AREA_FRAMES}, got {self.frame!r}")
        source = as_optional_str(self.source, "source") or ""
        polygons = [as_tuple(rings, f"polygons[{p}]") for p, rings in enumerate(as_tuple(self.polygons, "polygons"))]
        if not polygons:
            raise InvalidInputError(f"{source or 'the area'} holds no polygon")
        checked = tuple(tuple(_ring(r, f"polygon {p} ring {k}") for k, r in enumerate(rings)) for p, rings in enumerate(polygons))
        if any(not rings for rings in checked):
            raise InvalidInputError(f"{self.source or 'the area'} has a polygon without rings")
        if sum(r.shape[0] for rings in checked for r in rings) > _MAX_VERTICES:
            raise InvalidInputError(f"{self.source or 'the area'} has more than {_MAX_VERTICES:,} vertices")
        if self.frame == "wgs84":
            for rings in checked:
                for ring in rings:
                    if (np.abs(ring[:, 1]) > 90.0).any() or (np.abs(ring[:, 0]) > 360.0).any():
                        raise InvalidInputError(
                            f"{self.source or 'the area'}: coordinates are not longitude, latitude in degrees "
                            f"(first vertex {ring[0].tolist()})"
                        )
        object.__setattr__(self, "polygons", checked)

    def local_rings(self, dem: GeoDem) -> list[np.ndarray]:
        """Every ring as ``(k, 2)`` local metres of ``dem`` (holes and exteriors alike)."""
        if not isinstance(dem, GeoDem):
            raise InvalidTypeError(f"dem must be a uavcov.terrain.GeoDem, got {type(dem).__name__}")
        rings = [ring for rings in self.polygons for ring in rings]
        if self.frame == "wgs84":
            return [dem.from_wgs84(ring)[:, :2] for ring in rings]
        return [dem.crs_to_local_xy(ring) for ring in rings]

    def wgs84_polygons(self, dem: GeoDem) -> list[list[np.ndarray]]:
        """The polygons in WGS84 (longitude, latitude), for the files a plan writes: longitudes in
        ``[-180, 180]``, as GeoJSON and KML require."""
        if self.frame == "wgs84":
            return [[np.column_stack([wrap_longitude(r[:, 0]), r[:, 1]]) for r in rings] for rings in self.polygons]
        return [
            [dem.to_wgs84(np.column_stack([dem.crs_to_local_xy(r), np.zeros(r.shape[0])]))[:, :2] for r in rings] for rings in self.polygons
        ]

    def contains(self, xy: Any, dem: GeoDem) -> np.ndarray:
        """``(n, 2)`` local metres -> ``(n,)`` bool: inside the area (even-odd over every ring)."""
        return points_in_rings(xy, self.local_rings(dem))


def points_in_rings(xy: Any, rings: list[np.ndarray]) -> np.ndarray:
    """Even-odd point-in-polygon test: ``(n, 2)`` points, rings of ``(k, 2)`` -> ``(n,)`` bool.

    A point is inside when a ray from it to +x crosses the rings' edges an odd number of times
    (so a hole, a ring inside another, is outside).
    """
    points = as_float_array(xy, "xy")
    if points.ndim != 2 or points.shape[1] != 2:
        raise InvalidInputError(f"xy must have shape (n, 2), got {points.shape}")
    x, y = points[:, 0], points[:, 1]
    inside = np.zeros(points.shape[0], dtype=bool)
    for ring in rings:
        x0, y0 = ring[:, 0], ring[:, 1]
        x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
        for k in range(ring.shape[0]):
            straddles = (y0[k] > y) != (y1[k] > y)
            if not straddles.any():
                continue
            # x of the edge at the point's y (only where the edge straddles it: no division by 0)
            t = (y[straddles] - y0[k]) / (y1[k] - y0[k])
            crossing = x0[k] + t * (x1[k] - x0[k]) > x[straddles]
            index = np.flatnonzero(straddles)[crossing]
            inside[index] = ~inside[index]
    return inside


def bbox_area(xmin: float, ymin: float, xmax: float, ymax: float, *, frame: str = "wgs84") -> AreaOfInterest:
    """A rectangle as an area: ``(xmin, ymin, xmax, ymax)`` in longitude, latitude (``frame="wgs84"``)
    or in the DEM's CRS (``frame="dem"``)."""
    # one number each (numpy would read True as 1 degree)
    x0, y0, x1, y1 = (as_finite_float(v, name) for v, name in zip((xmin, ymin, xmax, ymax), ("xmin", "ymin", "xmax", "ymax"), strict=True))
    if not (x0 < x1 and y0 < y1):
        raise InvalidInputError(f"a bounding box needs xmin < xmax and ymin < ymax, got {(x0, y0, x1, y1)}")
    ring = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])
    return AreaOfInterest(((ring,),), frame=frame, source="bbox")


def read_area(path: Any) -> AreaOfInterest:
    """An area from a GeoJSON file (Polygon or MultiPolygon geometries, Features, FeatureCollections)
    or a KML file (every ``Polygon``, its ``outerBoundaryIs`` and ``innerBoundaryIs``); both in
    WGS84 longitude, latitude (RFC 7946, KML 2.2).

    Raises
    ------
    InvalidInputError
        No such file, does not parse, holds no polygon, a GeoJSON ``crs`` member other than WGS84.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidTypeError(f"path must be a string or os.PathLike, got {type(path).__name__}")
    text_path = os.fspath(path)
    if not os.path.isfile(text_path):
        raise InvalidInputError(f"area file {text_path!r} does not exist or is not a file")
    if os.path.getsize(text_path) > 200_000_000:
        raise InvalidInputError(f"area file {text_path!r} is larger than 200 MB")
    try:
        with open(text_path, encoding="utf-8") as handle:
            text = handle.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise InvalidInputError(f"cannot read {text_path!r}: {exc}") from None
    polygons = _kml_polygons(text, text_path) if text.lstrip().startswith("<") else _geojson_polygons(text, text_path)
    if not polygons:
        raise InvalidInputError(f"{text_path!r} holds no polygon")
    return AreaOfInterest(tuple(tuple(rings) for rings in polygons), frame="wgs84", source=text_path)


_MAX_NESTING = 32
"""How deep GeoJSON geometries may nest (collections of collections): far beyond any real file."""


def _member(node: dict[str, Any], key: str, kind: type, what: str, where: str) -> Any:
    """``node[key]``, which must be a ``kind`` (JSON's list or object), else a clear error."""
    value = node.get(key)
    if not isinstance(value, kind):
        expected = "an array" if kind is list else "an object"
        raise InvalidInputError(f"{where!r}: the {what}'s {key!r} must be {expected}, got {_json_kind(value)}")
    return value


def _json_kind(value: Any) -> str:
    names = {dict: "an object", list: "an array", str: "a string", bool: "a boolean", type(None): "null", int: "a number"}
    return names.get(type(value), "a number")


def _position(value: Any, where: str) -> list[float]:
    """A GeoJSON position: 2 or 3 finite numbers (longitude, latitude[, height]) -> (longitude, latitude)."""
    if not isinstance(value, list) or not 2 <= len(value) <= 3:
        raise InvalidInputError(f"{where!r}: a position must be [longitude, latitude] (an array of 2 or 3 numbers), got {_short(value)}")
    numbers = [_finite(v) for v in value]
    if None in numbers:
        raise InvalidInputError(f"{where!r}: a position must hold finite numbers, got {_short(value)}")
    return [float(v) for v in numbers[:2]]  # type: ignore[arg-type]


def _finite(value: Any) -> float | None:
    """``value`` as a finite float, or None (a string, a boolean, NaN, an integer beyond float)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    try:
        number = float(value)
    except OverflowError:
        return None
    return number if math.isfinite(number) else None


def _short(value: Any) -> str:
    text = json.dumps(value) if not isinstance(value, float) or math.isfinite(value) else repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _polygon(coordinates: Any, where: str) -> list[list[list[float]]]:
    """A GeoJSON Polygon's coordinates: an array of rings, each an array of positions."""
    if not isinstance(coordinates, list) or not coordinates:
        raise InvalidInputError(f"{where!r}: a Polygon's coordinates must be an array of rings, got {_short(coordinates)}")
    rings = []
    for ring in coordinates:
        if not isinstance(ring, list):
            raise InvalidInputError(f"{where!r}: a Polygon ring must be an array of positions, got {_short(ring)}")
        rings.append([_position(p, where) for p in ring])
    return rings


def _geojson_polygons(text: str, where: str) -> list[list[Any]]:
    """Every polygon of a GeoJSON text, each member checked against RFC 7946 before it is used."""
    try:
        document = json.loads(text, object_pairs_hook=unique_names)
    except ValueError as exc:  # JSONDecodeError, or a name given twice
        raise InvalidInputError(f"{where!r} is neither GeoJSON nor KML: {exc}") from None
    except RecursionError:
        raise InvalidInputError(f"{where!r} nests arrays or objects too deeply to be a GeoJSON area") from None
    if not isinstance(document, dict):
        raise InvalidInputError(f"{where!r} is not a GeoJSON object (it is {_json_kind(document)})")
    crs = document.get("crs")
    if crs is not None:
        properties = crs.get("properties") if isinstance(crs, dict) else None
        name = properties.get("name") if isinstance(properties, dict) else None
        if not isinstance(name, str):
            raise InvalidInputError(f'{where!r}: a \'crs\' member must be an object naming its CRS ({{"properties": {{"name": ...}}}})')
        if not any(key in name.upper() for key in ("CRS84", "4326")):
            raise InvalidInputError(f"{where!r} declares the CRS {name!r}; GeoJSON areas must be WGS84 longitude, latitude")
    polygons: list[list[Any]] = []

    def visit(node: Any, depth: int) -> None:
        if depth > _MAX_NESTING:
            raise InvalidInputError(f"{where!r} nests GeoJSON collections more than {_MAX_NESTING} deep")
        if node is None:
            return  # a Feature without geometry
        if not isinstance(node, dict) or not isinstance(node.get("type"), str):
            raise InvalidInputError(f"{where!r}: expected a GeoJSON object with a 'type', got {_short(node)}")
        kind = node["type"]
        if kind == "FeatureCollection":
            for feature in _member(node, "features", list, kind, where):
                visit(feature, depth + 1)
        elif kind == "Feature":
            if "geometry" not in node:
                raise InvalidInputError(f"{where!r}: a Feature must have a 'geometry' member")
            visit(node["geometry"], depth + 1)
        elif kind == "GeometryCollection":
            for geometry in _member(node, "geometries", list, kind, where):
                visit(geometry, depth + 1)
        elif kind == "Polygon":
            polygons.append(_polygon(_member(node, "coordinates", list, kind, where), where))
        elif kind == "MultiPolygon":
            polygons.extend(_polygon(p, where) for p in _member(node, "coordinates", list, kind, where))
        elif kind not in ("Point", "MultiPoint", "LineString", "MultiLineString"):
            raise InvalidInputError(f"{where!r}: {kind!r} is not a GeoJSON type")

    visit(document, 0)
    return polygons


def _kml_polygons(text: str, where: str) -> list[list[Any]]:
    try:
        root = ET.fromstring(text)  # ElementTree expands no external entities
    except ET.ParseError as exc:
        raise InvalidInputError(f"{where!r} is not valid KML: {exc}") from None

    def local(tag: str) -> str:
        return tag.rsplit("}", 1)[-1]

    polygons: list[list[Any]] = []
    for polygon in (e for e in root.iter() if local(e.tag) == "Polygon"):
        rings: list[Any] = []
        for boundary_name in ("outerBoundaryIs", "innerBoundaryIs"):
            for boundary in (e for e in polygon if local(e.tag) == boundary_name):
                rings.extend(_kml_coordinates(c.text or "", where) for c in boundary.iter() if local(c.tag) == "coordinates")
        if rings:
            polygons.append(rings)
    return polygons


def _kml_coordinates(text: str, where: str) -> list[list[float]]:
    positions = []
    for token in text.split():
        values = token.split(",")
        try:
            numbers = [float(v) for v in values]
        except ValueError:
            numbers = []
        if not 2 <= len(numbers) <= 3 or not all(math.isfinite(v) for v in numbers):
            raise InvalidInputError(f"{where!r}: KML coordinates must be 'lon,lat[,alt]' tuples of finite numbers, got {token[:60]!r}")
        positions.append(numbers[:2])
    return positions
