"""A :class:`~uavcov.field.FlightPlan` written for flight controllers and GIS, and read back.

:func:`write_plan` writes one folder:

=======================  =====================================================================
file                     what, in which frame
=======================  =====================================================================
``positions.csv``        one row per UAV: local metres; (x, y) in the DEM's CRS; longitude,
                         latitude (WGS84); altitude above the DEM's datum (AMSL), above the
                         ground under the UAV (AGL) and above the take-off point (home)
``waypoints.csv``        every item of every ``.plan``: longitude, latitude (WGS84), altitude
                         above home and AMSL
``uav_NN.plan``          QGroundControl plan per UAV: take-off at home, transit at a safe
                         altitude, descent to the position, hold (loiter for ``hold_s``);
                         altitudes relative to home (``MAV_FRAME_GLOBAL_RELATIVE_ALT``, frame 3)
``plan.geojson``         positions (Points, altitude AMSL), footprints, the area, the take-off
                         point; RFC 7946: WGS84 longitude, latitude
``plan.kml``             the same for Google Earth / QGIS; altitudes ``absolute`` (AMSL)
``coverage.tif``         GeoTIFF in the DEM's grid and CRS: band 1 seen (1) or not (0), band 2
                         how many UAVs see the cell; 65535 outside the area and over nodata
``plan.json``            the settings, the CRSs and datums, the numbers (machine-readable)
``report.md``            one page: the map, the numbers, the settings
``report.png``           the map: elevation, seen cells, area, footprints, positions, take-off
=======================  =====================================================================

Why relative-to-home altitudes in the ``.plan``: a flight controller measures altitude from its
take-off point (barometer), and the difference between two DEM heights does not depend on the
DEM's vertical datum, which is often unknown; the home altitude written as
``plannedHomePosition`` is the DEM's height at the take-off point.

Every file is rendered in memory first and written under a temporary name, then renamed
(``os.replace``): bad input or a failing renderer leaves the folder as it was, and no reader ever
sees half a file. Each writer has a reader (``read_*``) that the round-trip tests use.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_write
from ..errors import InvalidInputError, InvalidTypeError, MissingExtraError, ResultsFolderError
from ..terrain import RasterGrid
from ._plan import FlightPlan

MAV_CMD_NAV_WAYPOINT = 16
MAV_CMD_NAV_LOITER_TIME = 19
MAV_CMD_NAV_TAKEOFF = 22
MAV_CMD_DO_MOUNT_CONTROL = 205
"""MAVLink: point the gimbal (param1 pitch, param3 yaw relative to the vehicle, degrees; param7 the mount mode)."""
MAV_MOUNT_MODE_MAVLINK_TARGETING = 2
MAV_FRAME_MISSION = 2
MAV_FRAME_GLOBAL_RELATIVE_ALT = 3
"""MAVLink: altitude relative to the home position (QGroundControl's AltitudeMode 1)."""
COVERAGE_NODATA = 65535
"""The coverage GeoTIFF's nodata value (outside the area of interest, or DEM nodata)."""

_KML = "http://www.opengis.net/kml/2.2"
_ALTITUDE_FRAME = (
    "relative to home: metres above the take-off point's ground (MAV_FRAME_GLOBAL_RELATIVE_ALT = 3, "
    "QGroundControl AltitudeMode 1); plannedHomePosition's altitude is the DEM's height there"
)


def _check(flight_plan: Any) -> FlightPlan:
    if not isinstance(flight_plan, FlightPlan):
        raise InvalidTypeError(f"expected a uavcov.field.FlightPlan, got {type(flight_plan).__name__}")
    return flight_plan


def _num(value: float) -> float | None:
    """A JSON number (QGroundControl writes NaN parameters as null)."""
    return None if math.isnan(value) else float(value)


# ---------------------------------------------------------------------------------------------
# QGroundControl


def _items(fp: FlightPlan, k: int) -> list[tuple[int, str, float, float, float]]:
    """(command, name, latitude, longitude, altitude above home) of UAV ``k``'s items."""
    home_lon, home_lat, home = fp.takeoff_wgs84
    lon, lat = fp.positions_wgs84[k]
    transit = float(fp.transit_amsl[k] - home)
    hold = float(fp.altitude_home[k])
    return [
        (MAV_CMD_NAV_TAKEOFF, "takeoff", float(home_lat), float(home_lon), transit),
        (MAV_CMD_NAV_WAYPOINT, "transit", float(lat), float(lon), transit),
        (MAV_CMD_NAV_WAYPOINT, "position", float(lat), float(lon), hold),
        (MAV_CMD_NAV_LOITER_TIME, "hold", float(lat), float(lon), hold),
    ]


def qgc_items(
    rows: Sequence[tuple[int, str, float, float, float]], hold_s: float, heading: float | None, pitch: float | None
) -> list[dict[str, Any]]:
    """QGroundControl ``SimpleItem`` dicts for ``(command, name, latitude, longitude, altitude above
    home)`` rows: a loiter holds ``hold_s`` seconds, the ``"position"`` waypoint turns the vehicle
    to ``heading`` and, with a ``pitch``, a ``DO_MOUNT_CONTROL`` before the loiter sets the gimbal."""
    items: list[dict[str, Any]] = []
    for command, name, lat, lon, alt in rows:
        p1 = hold_s if command == MAV_CMD_NAV_LOITER_TIME else 0.0
        if command == MAV_CMD_NAV_LOITER_TIME and pitch is not None:
            items.append(
                {
                    "autoContinue": True,
                    "command": MAV_CMD_DO_MOUNT_CONTROL,
                    "doJumpId": len(items) + 1,
                    "frame": MAV_FRAME_MISSION,
                    "params": [pitch, 0.0, 0.0, None, None, None, MAV_MOUNT_MODE_MAVLINK_TARGETING],
                    "type": "SimpleItem",
                }
            )
        p4 = heading if name == "position" else None
        items.append(
            {
                "AMSLAltAboveTerrain": None,
                "Altitude": alt,
                "AltitudeMode": 1,
                "autoContinue": True,
                "command": command,
                "doJumpId": len(items) + 1,
                "frame": MAV_FRAME_GLOBAL_RELATIVE_ALT,
                "params": [p1, 0.0, 0.0, p4, lat, lon, alt],
                "type": "SimpleItem",
            }
        )
    return items


def qgc_document(
    items: list[dict[str, Any]], home: tuple[float, float, float], cruise_speed: float, hover_speed: float, about: dict[str, Any]
) -> dict[str, Any]:
    """A QGroundControl ``.plan`` document around ``items``; ``home`` is (latitude, longitude, altitude)."""
    return {
        "fileType": "Plan",
        "version": 1,
        "groundStation": "QGroundControl",
        "mission": {
            "version": 2,
            "firmwareType": 12,  # PX4
            "vehicleType": 2,  # quadrotor
            "cruiseSpeed": cruise_speed,
            "hoverSpeed": hover_speed,
            "globalPlanAltitudeMode": 1,
            "plannedHomePosition": list(home),
            "items": items,
        },
        "geoFence": {"circles": [], "polygons": [], "version": 2},
        "rallyPoints": {"points": [], "version": 2},
        "uavcov": about,
    }


def qgc_plan(flight_plan: FlightPlan, uav: int) -> dict[str, Any]:
    """UAV ``uav``'s QGroundControl ``.plan`` document (a dict, JSON-ready).

    Items: take-off at home to the transit altitude, transit to above the position, descent to
    the position, loiter there ``hold_s`` seconds; every altitude relative to home (frame 3).
    With a camera, the descent's waypoint turns the vehicle to the camera's heading (param 4,
    degrees from true north) and a ``DO_MOUNT_CONTROL`` item before the loiter sets the gimbal's
    pitch (param 1, degrees, -90 straight down; yaw 0: the camera looks along the vehicle).
    """
    fp = _check(flight_plan)
    if not 0 <= uav < fp.n_uavs:
        raise InvalidInputError(f"uav must be in [0, {fp.n_uavs}), got {uav}")
    heading = None if fp.attitudes is None else float(fp.attitudes[uav, 0])
    pitch = None if fp.attitudes is None else float(fp.attitudes[uav, 1])
    items = qgc_items(_items(fp, uav), fp.settings.hold_s, heading, pitch)
    home_lon, home_lat, home = (float(v) for v in fp.takeoff_wgs84)
    about = {
        "uav": uav + 1,
        "altitude_frame": _ALTITUDE_FRAME,
        "home_altitude": f"the DEM's height at the take-off point: {fp.dem.vertical_datum}",
        "horizontal_crs": "WGS 84 (EPSG:4326), latitude and longitude in degrees",
        **(
            {}
            if fp.attitudes is None
            else {"camera": "heading: degrees clockwise from true north (position waypoint, param 4); gimbal pitch: degrees, -90 nadir"}
        ),
    }
    return qgc_document(items, (home_lat, home_lon, home), fp.settings.cruise_speed, fp.settings.hover_speed, about)


def read_qgc_plan(path: Any) -> dict[str, Any]:
    """A ``.plan`` file -> ``{"home": (lat, lon, alt), "items": [{"command", "frame", "lat",
    "lon", "alt"}, ...]}`` (``alt`` in the item's frame).

    Raises
    ------
    InvalidInputError
        Not a QGroundControl plan.
    """
    document = _read_json(path)
    if document.get("fileType") != "Plan" or not isinstance(document.get("mission"), dict):
        raise InvalidInputError(f"{path}: not a QGroundControl plan (fileType {document.get('fileType')!r})")
    mission = document["mission"]
    items = []
    for item in mission.get("items", []):
        params = item["params"]
        items.append(
            {
                "command": int(item["command"]),
                "frame": int(item["frame"]),
                "lat": params[4],
                "lon": params[5],
                "alt": params[6],
                "params": list(params),
            }
        )
    home = mission.get("plannedHomePosition")
    return {"home": tuple(home) if home else None, "items": items}


def _read_json(path: Any) -> dict[str, Any]:
    try:
        with open(os.fspath(path), encoding="utf-8") as handle:
            document = json.load(handle)
    except (OSError, json.JSONDecodeError) as exc:
        raise InvalidInputError(f"cannot read {path} as JSON: {exc}") from None
    if not isinstance(document, dict):
        raise InvalidInputError(f"{path}: expected a JSON object")
    return document


# ---------------------------------------------------------------------------------------------
# CSV


_POSITION_COLUMNS = (
    "uav",
    "x_local_m",
    "y_local_m",
    "z_local_m",
    "x_crs",
    "y_crs",
    "longitude",
    "latitude",
    "altitude_amsl_m",
    "altitude_agl_m",
    "altitude_home_m",
    "ground_amsl_m",
    "transit_amsl_m",
    "heading_deg",
    "pitch_deg",
)
"""``heading_deg`` (clockwise from true north) and ``pitch_deg`` are the camera's; NaN for the omnidirectional sensor."""


def _csv(rows: Sequence[Sequence[Any]], header: Sequence[str]) -> bytes:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    writer.writerows([[repr(v) if isinstance(v, float) else v for v in row] for row in rows])
    return buffer.getvalue().encode("utf-8")


def _positions_csv(fp: FlightPlan) -> bytes:
    rows = [
        [
            k + 1,
            *(float(v) for v in fp.positions_local[k]),
            *(float(v) for v in fp.positions_crs[k, :2]),
            *(float(v) for v in fp.positions_wgs84[k]),
            float(fp.altitude_amsl[k]),
            float(fp.altitude_agl[k]),
            float(fp.altitude_home[k]),
            float(fp.ground_amsl[k]),
            float(fp.transit_amsl[k]),
            *((math.nan, math.nan) if fp.attitudes is None else (float(v) for v in fp.attitudes[k])),
        ]
        for k in range(fp.n_uavs)
    ]
    return _csv(rows, _POSITION_COLUMNS)


def _waypoints_csv(fp: FlightPlan) -> bytes:
    home = float(fp.takeoff_wgs84[2])
    rows = []
    for k in range(fp.n_uavs):
        for seq, (command, name, lat, lon, alt) in enumerate(_items(fp, k), start=1):
            hold = fp.settings.hold_s if command == MAV_CMD_NAV_LOITER_TIME else 0.0
            rows.append([k + 1, seq, command, name, lon, lat, alt, alt + home, hold])
    header = ("uav", "seq", "command", "name", "longitude", "latitude", "altitude_home_m", "altitude_amsl_m", "hold_s")
    return _csv(rows, header)


def read_positions_csv(path: Any) -> dict[str, np.ndarray]:
    """``positions.csv`` -> one float array per column (``uav`` as int)."""
    try:
        with open(os.fspath(path), encoding="utf-8", newline="") as handle:
            rows = list(csv.DictReader(handle))
    except OSError as exc:
        raise InvalidInputError(f"cannot read {path}: {exc}") from None
    if not rows or set(_POSITION_COLUMNS) - set(rows[0]):
        raise InvalidInputError(f"{path}: not a positions.csv (columns {_POSITION_COLUMNS})")
    out = {name: np.array([float(r[name]) for r in rows]) for name in _POSITION_COLUMNS}
    out["uav"] = out["uav"].astype(np.int64)
    return out


# ---------------------------------------------------------------------------------------------
# GeoJSON and KML


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
    return (json.dumps(document, indent=1) + "\n").encode("utf-8")


def read_plan_geojson(path: Any) -> dict[str, Any]:
    """``plan.geojson`` -> ``{"positions": (N, 3) lon, lat, AMSL; "footprints": [(k, 2)], "area":
    [[rings]], "takeoff": (3,)}``, positions ordered by UAV."""
    document = _read_json(path)
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


# ---------------------------------------------------------------------------------------------
# The report


def _sensor_record(sensor: Any) -> dict[str, Any]:
    """One UAV's sensor for plan.json: its range, limits and camera (QGroundControl's fields)."""
    return {
        "d_max_m": sensor.d_max,
        "d_min_m": sensor.d_min,
        "camera": None if sensor.camera is None else vars(sensor.camera),
        "max_gsd_m": sensor.max_gsd_m,
        "max_incidence_deg": sensor.max_incidence_deg,
        "good_gsd_m": sensor.good_gsd_m,
    }


def _sensors_line(sensors: list[dict[str, Any]] | None, attitude: list[float]) -> str:
    """The report's words for the team's sensors (nothing for the omnidirectional one)."""
    if not sensors:
        return ""
    kinds = sorted({"omnidirectional" if r["camera"] is None else "camera" for r in sensors})
    cameras = [r["camera"] for r in sensors if r["camera"] is not None]
    words = f", sensors: {' and '.join(kinds)} ({len(cameras)} of {len(sensors)} with a camera)"
    return words + (f", first camera {cameras[0]}, attitude {attitude}" if cameras else "")


def _document(fp: FlightPlan, command: str | None, runtime_s: float | None) -> dict[str, Any]:
    settings = fp.settings
    return {
        "format": "uavcov.plan/1",
        "command": command,
        "runtime_s": runtime_s,
        "dem": {
            "source": fp.dem.source,
            "crs": fp.dem.crs_name,
            "crs_wkt": fp.dem.crs,
            "vertical_datum": fp.dem.vertical_datum,
            "nodata_cells": fp.dem.nodata_cells,
        },
        "area": fp.area.source if fp.area is not None else "the whole DEM",
        "altitudes": {
            "amsl": f"above the DEM's datum: {fp.dem.vertical_datum}",
            "agl": "above the DEM's ground under the UAV",
            "home": "above the take-off point's DEM ground (the .plan files' frame)",
        },
        "settings": {
            "n_uavs": settings.n_uavs,
            "d_max_m": settings.d_max,
            "h_min_m": settings.h_min,
            "h_max_m": settings.h_max,
            "separation_m": settings.d_safe,
            "prior": settings.prior,
            "iterations": settings.iterations,
            "sensors": None if settings.sensor is None else [_sensor_record(s) for s in settings.team_sensors() or []],
            "attitude_deg": list(settings.attitude),
            "cao_alpha0_m": fp.mission.settings.cao.alpha0,
            "hold_s": settings.hold_s,
            "seed": fp.mission.seed,
        },
        "results": {
            "coverage": fp.coverage,
            "initial_coverage": fp.initial_coverage,
            "area_m2": fp.area_m2,
            "targets": len(fp.targets),
            "seen_targets": int(fp.seen.sum()),
            "best_iteration": fp.mission.best_iteration,
            "takeoff": {"longitude": float(fp.takeoff_wgs84[0]), "latitude": float(fp.takeoff_wgs84[1]), "ground_amsl_m": fp.home_amsl},
        },
    }


_UNSEEN_WASH = (0.55, 0.1, 0.65)
"""The plan map's wash over unseen cells: purple, a hue the ``terrain`` colormap has nowhere."""


def _map_png(fp: FlightPlan) -> bytes:
    try:
        import matplotlib as mpl

        mpl.use("Agg", force=False)
        from matplotlib.figure import Figure
    except ImportError as exc:
        raise MissingExtraError("the report's map needs matplotlib: pip install 'uavcov[plot]'") from exc
    dem = fp.dem
    figure = Figure(figsize=(11.0, 5.0), dpi=100, layout="constrained")
    axes, curve = figure.subplots(1, 2, width_ratios=[1.6, 1.0])
    grid, raster = dem.terrain.grid, dem.raster
    if grid is not None and raster is not None:
        a, _, c, _, e, f = raster.transform
        rows, cols = raster.shape
        image = grid.z / dem.frame.factors[2] + dem.frame.origin[2]  # NaN (nodata) stays NaN
        image = image[::-1] if e < 0 else image
        extent = (c, c + cols * a, f + rows * e, f) if e < 0 else (c, c + cols * a, f, f + rows * e)
        shown = axes.imshow(image, extent=extent, cmap="terrain", origin="upper" if e < 0 else "lower", interpolation="nearest")
        seen = np.zeros((rows, cols))
        seen[:] = np.nan
        assert fp.target_pixels is not None
        seen[fp.target_pixels[:, 0], fp.target_pixels[:, 1]] = fp.seen
        # The unseen cells of the area in a colour the terrain colormap never uses (its greys and
        # browns are high ground), named in the legend.
        overlay = np.ma.masked_where(~(seen == 0), seen)
        unseen = mpl.colors.ListedColormap([_UNSEEN_WASH])
        axes.imshow(overlay, extent=extent, cmap=unseen, alpha=0.6, origin="upper" if e < 0 else "lower", interpolation="nearest")
    else:
        points = dem.to_crs(fp.targets.points)
        shown = axes.scatter(points[:, 0], points[:, 1], c=points[:, 2], s=2, cmap="terrain")
    figure.colorbar(shown, ax=axes, label="DEM height (m)", shrink=0.8)

    def crs_xy(local_xy: np.ndarray, z: float = 0.0) -> np.ndarray:
        return dem.to_crs(np.column_stack([local_xy, np.full(local_xy.shape[0], z)]))[:, :2]

    if fp.area is not None:
        for ring in fp.area.local_rings(dem):
            outline = crs_xy(np.vstack([ring, ring[:1]]))
            axes.plot(outline[:, 0], outline[:, 1], color="tab:blue", lw=1.5)
    for outline in fp.footprints_local():
        if outline.shape[0]:
            closed = crs_xy(np.vstack([outline, outline[:1]]))
            axes.plot(closed[:, 0], closed[:, 1], color="tab:red", lw=0.8, alpha=0.7)
    positions = fp.positions_crs
    axes.scatter(positions[:, 0], positions[:, 1], color="tab:red", edgecolor="black", zorder=3, s=30)
    for k, (x, y) in enumerate(positions[:, :2]):
        axes.annotate(str(k + 1), (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
    home = dem.to_crs(fp.takeoff_local.reshape(1, 3))[0]
    axes.scatter([home[0]], [home[1]], marker="^", color="yellow", edgecolor="black", s=80, zorder=4, label="take-off")
    from matplotlib.patches import Patch

    handles, _ = axes.get_legend_handles_labels()
    if grid is not None and raster is not None:
        handles.append(Patch(facecolor=_UNSEEN_WASH, alpha=0.6, edgecolor="0.3", linewidth=0.5, label="not seen"))
    axes.legend(handles=handles, loc="lower right", fontsize=8)
    if dem.geographic:
        mid = float(np.mean(positions[:, 1]))
        axes.set_aspect(1.0 / max(math.cos(math.radians(mid)), 1e-6))
        axes.set_xlabel("longitude (deg)")
        axes.tick_params(axis="x", labelrotation=30)
        axes.set_ylabel("latitude (deg)")
    else:
        axes.set_aspect("equal")
        axes.set_xlabel(f"x ({dem.crs_name})")
        axes.set_ylabel("y")
    axes.set_title(f"{fp.n_uavs} UAVs: {100 * fp.coverage:.1f} % of the area seen", fontsize=10)
    values = fp.mission.coverage
    curve.plot(np.arange(values.shape[0]), values, color="tab:blue")
    curve.set_xlabel("CAO iteration")
    curve.set_ylabel("coverage of the area")
    curve.set_title("CVT start, then CAO on the DEM", fontsize=10)
    curve.grid(alpha=0.3)
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", metadata={"Software": None})
    return buffer.getvalue()


def _report_md(fp: FlightPlan, document: dict[str, Any]) -> bytes:
    s = document["settings"]
    r = document["results"]
    home = r["takeoff"]
    lines = [
        "# uavcov plan",
        "",
        f"Command: `{document['command']}`" if document["command"] else "Made by `uavcov.field.write_plan`.",
        "",
        "![map](report.png)",
        "",
        "## Numbers",
        "",
        "| | |",
        "|---|---|",
        f"| coverage of the area (share of its ground seen by at least one UAV) | {r['coverage']:.3f} |",
        f"| at the CVT start (admissible) | {r['initial_coverage']:.3f} |",
        f"| area | {r['area_m2'] / 1e6:.3f} km^2, {r['targets']} DEM cells ({r['seen_targets']} seen) |",
        f"| best configuration at CAO iteration | {r['best_iteration']} of {s['iterations']} |",
        f"| take-off (home) | {home['longitude']:.7f}, {home['latitude']:.7f}, ground {home['ground_amsl_m']:.1f} m |",
    ]
    if document["runtime_s"] is not None:
        lines.append(f"| runtime (reading the DEM and planning; files not included) | {document['runtime_s']:.1f} s |")
    lines += [
        "",
        "| UAV | longitude | latitude | AMSL (m) | above ground (m) | above home (m) | transit AMSL (m) |",
        "|---|---|---|---|---|---|---|",
    ]
    for k in range(fp.n_uavs):
        lon, lat = fp.positions_wgs84[k]
        lines.append(
            f"| {k + 1} | {lon:.7f} | {lat:.7f} | {fp.altitude_amsl[k]:.1f} | {fp.altitude_agl[k]:.1f} | "
            f"{fp.altitude_home[k]:.1f} | {fp.transit_amsl[k]:.1f} |"
        )
    lines += [
        "",
        "## Frames",
        "",
        f"- DEM: `{document['dem']['source']}`, CRS {document['dem']['crs']}, {document['dem']['nodata_cells']} nodata cells.",
        f"- Heights: {fp.dem.vertical_datum}.",
        "- Longitude, latitude: WGS 84 (EPSG:4326) in every file (GeoJSON, KML, .plan, CSV).",
        "- AMSL: above the DEM's datum; above ground: above the DEM under the UAV; above home: above the take-off point's DEM ground.",
        f"- `.plan` altitudes: {_ALTITUDE_FRAME}.",
        (
            "- Transit: each UAV climbs at home, flies straight at h_min above the highest ground of its path, descends and "
            "holds. Transit paths are not deconflicted between UAVs: stagger the take-offs."
        ),
        (
            "- Footprints: what each sensor reaches on the horizontal plane through the ground under it (reach, not sight); "
            "`coverage.tif` holds what is seen."
        ),
        "",
        "## Settings",
        "",
        f"- area: {document['area']}",
        f"- team: {s['n_uavs']} UAVs, range d_max = {s['d_max_m']:g} m" + _sensors_line(s["sensors"], s["attitude_deg"]),
        (
            f"- flight limits: {s['h_min_m']:g} to {s['h_max_m']:g} m above ground, {s['separation_m']:g} m apart, "
            "inside the area's bounding box"
        ),
        f"- known beforehand: {'the full DEM' if s['prior'] == 'full' else str(s['prior']) + ' sparse points (+ the area hull)'}",
        (
            f"- method: CVT start on S' (paper Table 1 CVT), then {s['iterations']} CAO iterations on the DEM "
            f"(paper Table 1 constants, alpha0 = {s['cao_alpha0_m']:.4g} m), seed {s['seed']}"
        ),
        "",
    ]
    return "\n".join(lines).encode("utf-8")


def render_plan(flight_plan: FlightPlan, *, command: str | None = None, runtime_s: float | None = None) -> dict[str, bytes]:
    """Every file of :func:`write_plan` as ``{name: bytes}``, nothing written."""
    fp = _check(flight_plan)
    files: dict[str, bytes] = {}
    files["positions.csv"] = _positions_csv(fp)
    files["waypoints.csv"] = _waypoints_csv(fp)
    for k in range(fp.n_uavs):
        files[f"uav_{k + 1:02d}.plan"] = (json.dumps(qgc_plan(fp, k), indent=4) + "\n").encode("utf-8")
    files["plan.geojson"] = _geojson(fp)
    files["plan.kml"] = _kml(fp)
    coverage = _coverage_geotiff(fp)
    if coverage is not None:
        files["coverage.tif"] = coverage
    quality = _quality_geotiff(fp)
    if quality is not None:
        files["quality.tif"] = quality
    document = _document(fp, command, runtime_s)
    files["plan.json"] = (json.dumps(document, indent=2, default=str) + "\n").encode("utf-8")
    files["report.png"] = _map_png(fp)
    files["report.md"] = _report_md(fp, document)
    return files


def write_plan(flight_plan: FlightPlan, out: Any, *, command: str | None = None, runtime_s: float | None = None) -> list[Path]:
    """Write every file of a plan into the folder ``out`` (created if needed); see the module.

    Returns
    -------
    list of Path
        The files written.

    Raises
    ------
    ResultsFolderError
        ``out`` is a file, or cannot be created or written.
    """
    return write_files(render_plan(flight_plan, command=command, runtime_s=runtime_s), out)


def write_files(files: dict[str, bytes], out: Any) -> list[Path]:
    """Write ``{name: bytes}`` into the folder ``out`` (created if needed), each file atomically."""
    if not isinstance(out, (str, os.PathLike)):
        raise InvalidTypeError(f"out must be a path, got {type(out).__name__}")
    folder = Path(out)
    if folder.exists() and not folder.is_dir():
        raise ResultsFolderError(f"{folder} exists and is not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ResultsFolderError(f"cannot create {folder}: {exc}") from None
    written = []
    for name, data in files.items():
        target = folder / name
        try:
            atomic_write(target, data)
        except OSError as exc:
            raise ResultsFolderError(f"cannot write {target}: {exc}") from None
        written.append(target)
    return written
