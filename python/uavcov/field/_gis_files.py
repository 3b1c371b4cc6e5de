"""A plan for GIS: GeoJSON and KML (WGS84 longitude, latitude), and GeoTIFFs in the DEM's grid."""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import InvalidInputError, MissingExtraError
from ..terrain import RasterGrid
from ._plan import FlightPlan
from ._strict_json import json_bytes, read_json

COVERAGE_NODATA = 65535
"""The coverage GeoTIFF's nodata value (outside the area of interest, or DEM nodata)."""

_KML = "http://www.opengis.net/kml/2.2"


def _ring_list(ring: np.ndarray) -> list[list[float]]:
    closed = np.vstack([ring, ring[:1]])
    return [[float(x), float(y)] for x, y in closed]


def _footprints_wgs84(fp: FlightPlan) -> list[np.ndarray]:
    outlines = []
    for k, outline in enumerate(fp.footprints_local()):
        if outline.shape[0] == 0:
            outlines.append(outline)
            continue
        z = np.full(outline.shape[0], fp.positions_local[k, 2])
        outlines.append(fp.dem.to_wgs84(np.column_stack([outline, z]))[:, :2])
    return outlines


def _area_wgs84(fp: FlightPlan) -> list[list[np.ndarray]]:
    if fp.area is not None:
        return fp.area.wgs84_polygons(fp.dem)
    bounds = fp.dem.terrain.bounds
    (x0, y0), (x1, y1) = bounds[0, :2], bounds[1, :2]
    ring = np.array([[x0, y0, 0.0], [x1, y0, 0.0], [x1, y1, 0.0], [x0, y1, 0.0]])
    return [[fp.dem.to_wgs84(ring)[:, :2]]]


def _geojson(fp: FlightPlan) -> bytes:
    features: list[dict[str, Any]] = []
    for k in range(fp.n_uavs):
        lon, lat = (float(v) for v in fp.positions_wgs84[k])
        features.append(
            {
                "type": "Feature",
                "geometry": {"type": "Point", "coordinates": [lon, lat, float(fp.altitude_amsl[k])]},
                "properties": {
                    "kind": "position",
                    "uav": k + 1,
                    "altitude_amsl_m": float(fp.altitude_amsl[k]),
                    "altitude_agl_m": float(fp.altitude_agl[k]),
                    "altitude_home_m": float(fp.altitude_home[k]),
                    "x_crs": float(fp.positions_crs[k, 0]),
                    "y_crs": float(fp.positions_crs[k, 1]),
                    **({} if fp.attitudes is None else {"heading_deg": float(fp.attitudes[k, 0]), "pitch_deg": float(fp.attitudes[k, 1])}),
                },
            }
        )
    for k, outline in enumerate(_footprints_wgs84(fp)):
        if outline.shape[0]:
            features.append(
                {
                    "type": "Feature",
                    "geometry": {"type": "Polygon", "coordinates": [_ring_list(outline)]},
                    "properties": {"kind": "footprint", "uav": k + 1},
                }
            )
    features.extend(
        {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [_ring_list(r) for r in rings]}, "properties": {"kind": "area"}}
        for rings in _area_wgs84(fp)
    )
    home_lon, home_lat, home = (float(v) for v in fp.takeoff_wgs84)
    features.append(
        {"type": "Feature", "geometry": {"type": "Point", "coordinates": [home_lon, home_lat, home]}, "properties": {"kind": "takeoff"}}
    )
    document = {
        "type": "FeatureCollection",
        "features": features,
        "uavcov": {
            "crs": "WGS 84 longitude, latitude (RFC 7946)",
            "altitudes": f"third coordinate: altitude above the DEM's datum ({fp.dem.vertical_datum})",
        },
    }
    return json_bytes(document, indent=1, what="plan.geojson")


def read_plan_geojson(path: Any) -> dict[str, Any]:
    """``plan.geojson`` -> ``{"positions": (N, 3) lon, lat, AMSL; "footprints": [(k, 2)], "area":
    [[rings]], "takeoff": (3,)}``, positions ordered by UAV."""
    document = read_json(path)
    positions: dict[int, list[float]] = {}
    footprints: dict[int, np.ndarray] = {}
    area: list[list[np.ndarray]] = []
    takeoff = None
    for feature in document.get("features", []):
        kind = feature.get("properties", {}).get("kind")
        geometry = feature.get("geometry", {})
        if kind == "position":
            positions[int(feature["properties"]["uav"])] = geometry["coordinates"]
        elif kind == "footprint":
            footprints[int(feature["properties"]["uav"])] = np.array(geometry["coordinates"][0])
        elif kind == "area":
            area.append([np.array(r) for r in geometry["coordinates"]])
        elif kind == "takeoff":
            takeoff = np.array(geometry["coordinates"])
    return {
        "positions": np.array([positions[k] for k in sorted(positions)], dtype=np.float64).reshape(-1, 3),
        "footprints": [footprints[k] for k in sorted(footprints)],
        "area": area,
        "takeoff": takeoff,
    }


def _sub(parent: ET.Element, tag: str, text: str | None = None) -> ET.Element:
    element = ET.SubElement(parent, f"{{{_KML}}}{tag}")
    if text is not None:
        element.text = text
    return element


def _kml_ring(parent: ET.Element, ring: np.ndarray) -> None:
    _sub(_sub(parent, "LinearRing"), "coordinates", " ".join(f"{x!r},{y!r}" for x, y in _ring_list(ring)))


def _kml(fp: FlightPlan) -> bytes:
    ET.register_namespace("", _KML)
    root = ET.Element(f"{{{_KML}}}kml")
    document = _sub(root, "Document")
    _sub(document, "name", "uavcov plan")
    _sub(
        document,
        "description",
        f"WGS 84 longitude, latitude; altitudes absolute: above the DEM's datum ({fp.dem.vertical_datum})",
    )
    folder = _sub(document, "Folder")
    _sub(folder, "name", "positions")
    for k in range(fp.n_uavs):
        lon, lat = (float(v) for v in fp.positions_wgs84[k])
        placemark = _sub(folder, "Placemark")
        _sub(placemark, "name", f"UAV {k + 1}")
        _sub(
            placemark,
            "description",
            f"{fp.altitude_amsl[k]:.2f} m AMSL, {fp.altitude_agl[k]:.2f} m above ground, {fp.altitude_home[k]:.2f} m above home",
        )
        point = _sub(placemark, "Point")
        _sub(point, "altitudeMode", "absolute")
        _sub(point, "coordinates", f"{lon!r},{lat!r},{float(fp.altitude_amsl[k])!r}")
    folder = _sub(document, "Folder")
    _sub(folder, "name", "footprints")
    for k, outline in enumerate(_footprints_wgs84(fp)):
        if outline.shape[0]:
            placemark = _sub(folder, "Placemark")
            _sub(placemark, "name", f"footprint {k + 1}")
            polygon = _sub(placemark, "Polygon")
            _sub(polygon, "altitudeMode", "clampToGround")
            _kml_ring(_sub(polygon, "outerBoundaryIs"), outline)
    folder = _sub(document, "Folder")
    _sub(folder, "name", "area")
    for rings in _area_wgs84(fp):
        placemark = _sub(folder, "Placemark")
        _sub(placemark, "name", "area of interest")
        polygon = _sub(placemark, "Polygon")
        _kml_ring(_sub(polygon, "outerBoundaryIs"), rings[0])
        for hole in rings[1:]:
            _kml_ring(_sub(polygon, "innerBoundaryIs"), hole)
    placemark = _sub(document, "Placemark")
    _sub(placemark, "name", "take-off")
    point = _sub(placemark, "Point")
    _sub(point, "altitudeMode", "absolute")
    home_lon, home_lat, home = (float(v) for v in fp.takeoff_wgs84)
    _sub(point, "coordinates", f"{home_lon!r},{home_lat!r},{home!r}")
    ET.indent(root)
    text: bytes = ET.tostring(root, encoding="utf-8", xml_declaration=True)
    return text + b"\n"


def read_plan_kml(path: Any) -> np.ndarray:
    """``plan.kml`` -> ``(N, 3)`` (longitude, latitude, AMSL) of the positions folder, by UAV."""
    try:
        root = ET.parse(os.fspath(path)).getroot()
    except (OSError, ET.ParseError) as exc:
        raise InvalidInputError(f"cannot read {path} as KML: {exc}") from None
    ns = {"k": _KML}
    for folder in root.iter(f"{{{_KML}}}Folder"):
        if folder.findtext("k:name", namespaces=ns) == "positions":
            points = [
                [float(v) for v in (p.findtext("k:Point/k:coordinates", namespaces=ns) or "").split(",")]
                for p in folder.findall("k:Placemark", ns)
            ]
            return np.array(points, dtype=np.float64).reshape(-1, 3)
    raise InvalidInputError(f"{path}: no 'positions' folder")


# ---------------------------------------------------------------------------------------------
# The coverage GeoTIFF


def _target_geotiff(
    fp: FlightPlan,
    raster: RasterGrid,
    pixels: np.ndarray,
    values: Sequence[np.ndarray],
    dtype: str,
    nodata: float,
    descriptions: Sequence[str],
    **tags: str,
) -> bytes:
    """A GeoTIFF in the DEM's grid (``raster``) and CRS with one band per ``values`` (one value per
    target, at its ``pixels``; ``nodata`` in every other cell), written in memory."""
    try:
        import rasterio
        from rasterio.io import MemoryFile
        from rasterio.transform import Affine
    except ImportError as exc:
        raise MissingExtraError("writing GeoTIFFs needs rasterio: pip install 'uavcov[geo]'") from exc
    rows, cols = raster.shape
    bands = np.full((len(values), rows, cols), nodata, dtype=dtype)
    r, c = pixels[:, 0], pixels[:, 1]
    for band, value in zip(bands, values, strict=True):
        band[r, c] = value.astype(dtype)
    profile = {
        "driver": "GTiff",
        "height": rows,
        "width": cols,
        "count": len(values),
        "dtype": dtype,
        "crs": rasterio.crs.CRS.from_user_input(fp.dem.crs),
        "transform": Affine(*raster.transform),
        "nodata": nodata,
        "compress": "deflate",
    }
    with MemoryFile() as memory:
        with memory.open(**profile) as dataset:
            dataset.write(bands)
            for k, text in enumerate(descriptions, start=1):
                dataset.set_band_description(k, text)
            dataset.update_tags(vertical_datum=fp.dem.vertical_datum, **tags)
        return bytes(memory.read())


def _coverage_geotiff(fp: FlightPlan) -> bytes | None:
    if fp.dem.raster is None or fp.target_pixels is None:
        return None  # a mesh has no grid
    return _target_geotiff(
        fp,
        fp.dem.raster,
        fp.target_pixels,
        [fp.seen, fp.seen_count],
        "uint16",
        COVERAGE_NODATA,
        ["seen by at least one UAV (1) or not (0)", "number of UAVs that see the cell"],
        coverage=f"{fp.coverage:.6f}",
    )


def _quality_geotiff(fp: FlightPlan) -> bytes | None:
    if fp.dem.raster is None or fp.target_pixels is None or fp.quality is None:
        return None
    description = "best view quality over the team, 0-1 (0: not seen; resolution x cos incidence)"
    return _target_geotiff(fp, fp.dem.raster, fp.target_pixels, [fp.quality], "float32", float("nan"), [description])


def read_coverage_geotiff(path: Any) -> tuple[np.ndarray, tuple[float, ...], str]:
    """``coverage.tif`` -> (bands ``(2, rows, cols)`` uint16, transform ``(a, b, c, d, e, f)``, CRS WKT);
    ``quality.tif`` the same with one float32 band (NaN outside the area)."""
    try:
        import rasterio
    except ImportError as exc:
        raise MissingExtraError("reading GeoTIFFs needs rasterio: pip install 'uavcov[geo]'") from exc
    with rasterio.open(os.fspath(path)) as dataset:
        return dataset.read(), tuple(dataset.transform)[:6], dataset.crs.to_wkt()
