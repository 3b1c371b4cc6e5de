"""A team's flight around a structure, modelled in a local ENU frame round a geo-referenced anchor, in WGS84.

A structure's positions are metres east, north and up of a surveyed :class:`GeoAnchor`;
``structure_flight`` maps them, the take-off pad and every waypoint to WGS84
(``enu_to_wgs84``), turns each camera's heading to true north at its UAV, and checks, when
given the structure's mesh, that no leg of any route crosses it. ``write_structure_flight``
writes the files a ground station reads:

=======================  =====================================================================
file                     what, in which frame
=======================  =====================================================================
``positions.csv``        one row per UAV: local east, north, up metres; longitude, latitude
                         (WGS84 degrees), height above the ellipsoid and above home; the
                         camera's true heading and gimbal pitch
``waypoints.csv``        every item of every ``.plan``: local metres, WGS84, height above home
``uav_NN.plan``          QGroundControl plan per UAV: take-off at the pad, the route's
                         waypoints, the position (heading), the gimbal's pitch, a hold;
                         altitudes relative to home (``MAV_FRAME_GLOBAL_RELATIVE_ALT``)
``plan.geojson``         positions, routes and the pad: RFC 7946 longitude, latitude, and the
                         height above the ellipsoid as the third coordinate
``plan.json``            the anchor, the frames, every number (machine-readable)
=======================  =====================================================================

The default route climbs straight up over the pad to the position's height, then flies straight
to it; give ``routes`` where that crosses the structure (under a deck, the check refuses it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import MAX_UAVS, as_count, as_float_array, as_non_negative_float, as_positive_float, read_only
from ..engine import Terrain
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError
from ._geodesy import GeoAnchor, enu_to_wgs84, local_to_true_heading
from ._plan_tables import _csv
from ._qgc import MAV_CMD_NAV_LOITER_TIME, MAV_CMD_NAV_TAKEOFF, MAV_CMD_NAV_WAYPOINT, qgc_document, qgc_items
from ._results_folder import write_files
from ._strict_json import json_bytes

# A take-off leg starts on the pad: it is checked from this far above it, so that the pad's own
# ground does not count as a crossing.
_LIFT_OFF_M = 0.01
STRUCTURE_PLAN_FORMAT = "uavcov.structure_plan/1"
_ALTITUDE_FRAME = "relative to home: metres above the take-off pad (MAV_FRAME_GLOBAL_RELATIVE_ALT = 3, QGroundControl AltitudeMode 1)"


@dataclass(frozen=True, eq=False)
class StructureFlight:
    """A static configuration around a structure, in its local frame and in WGS84. Frozen, picklable.

    Attributes
    ----------
    anchor : GeoAnchor
        The local frame's origin.
    positions_local : (N, 3) float64
        East, north, up metres from the anchor.
    positions_wgs84 : (N, 3) float64
        Longitude, latitude (degrees), height above the WGS84 ellipsoid (metres).
    takeoff_local, takeoff_wgs84 : (3,) float64
        The pad, in both frames.
    routes_local : tuple of (k, 3) float64
        Per UAV, the waypoints after take-off, the position last.
    attitudes_local : (N, 2) float64 or None
        Heading (clockwise from the local frame's north) and gimbal pitch, degrees.
    attitudes : (N, 2) float64 or None
        The same with the heading from true north at each UAV, in ``[0, 360)``.
    hold_s, cruise_speed, hover_speed : float
        Seconds of hold at the position; metres per second.
    """

    anchor: GeoAnchor
    positions_local: np.ndarray
    positions_wgs84: np.ndarray
    takeoff_local: np.ndarray
    takeoff_wgs84: np.ndarray
    routes_local: tuple[np.ndarray, ...]
    attitudes_local: np.ndarray | None
    attitudes: np.ndarray | None
    hold_s: float
    cruise_speed: float
    hover_speed: float

    @property
    def n_uavs(self) -> int:
        """Team size."""
        return int(self.positions_local.shape[0])

    def route_wgs84(self, uav: int) -> np.ndarray:
        """UAV ``uav``'s route (the position last) as longitude, latitude, ellipsoidal height."""
        index = as_count(uav, "uav", len(self.routes_local) - 1, minimum=0)  # -1 would be the last UAV's, silently
        return enu_to_wgs84(self.routes_local[index], self.anchor)


def _local(value: Any, name: str, shape: tuple[int, ...]) -> np.ndarray:
    array = as_float_array(value, name)
    if array.shape != shape and not (len(shape) == 2 and array.ndim == 2 and shape[0] < 0 and array.shape[1] == shape[1]):
        raise InvalidInputError(f"{name} must have shape {tuple('n' if s < 0 else s for s in shape)}, got {array.shape}")
    if not np.isfinite(array).all():
        raise InvalidInputError(f"{name} must be finite")
    return array


def structure_flight(
    positions: Any,
    anchor: GeoAnchor,
    *,
    takeoff: Any,
    attitudes: Any = None,
    routes: Any = None,
    surface: Terrain | None = None,
    hold_s: float = 30.0,
    cruise_speed: float = 5.0,
    hover_speed: float = 2.0,
) -> StructureFlight:
    """The flight plan of a team placed around a structure, in WGS84 from a local anchor.

    Parameters
    ----------
    positions : (N, 3) array_like of float
        Local east, north, up metres from ``anchor``.
    anchor : GeoAnchor
    takeoff : (3,) array_like of float
        The take-off pad, local metres (on the ground).
    attitudes : (N, 2) array_like of float, optional
        Camera heading (from the local north) and gimbal pitch, degrees (pitch in ``[-90, 90]``).
    routes : sequence of (k, 3) array_like, optional
        Per UAV, waypoints between take-off and the position (local metres); by default a climb
        over the pad to the position's height.
    surface : Terrain, optional
        The structure: when given, every leg of every route (take-off climb included) must cross
        none of its triangles.
    hold_s : float, default 30
        Seconds (>= 0).
    cruise_speed, hover_speed : float
        Metres per second (> 0).

    Raises
    ------
    InfeasibleError
        A leg of some route crosses ``surface`` (the message names the UAV and the leg).
    InvalidInputError
        Non-finite or misshapen input, points beyond 100 km of the anchor, a pitch outside
        ``[-90, 90]``.
    """
    if not isinstance(anchor, GeoAnchor):
        raise InvalidTypeError(f"anchor must be a uavcov.field.GeoAnchor, got {type(anchor).__name__}")
    local = _local(positions, "positions", (-1, 3))
    n = local.shape[0]
    if not 1 <= n <= MAX_UAVS:
        raise InvalidInputError(f"a plan needs 1 to {MAX_UAVS} UAVs, got {n}")
    pad = _local(takeoff, "takeoff", (3,))
    angles = None if attitudes is None else _local(attitudes, "attitudes", (n, 2))
    if angles is not None and (np.abs(angles[:, 1]) > 90.0).any():
        raise InvalidInputError("a gimbal pitch must be in [-90, 90] degrees")
    if routes is None:
        legs = [np.array([[pad[0], pad[1], p[2]], p]) for p in local]
    else:
        if not isinstance(routes, (list, tuple)) or len(routes) != n:
            raise InvalidInputError(f"routes must hold one (k, 3) array of waypoints per UAV ({n})")
        legs = [np.vstack([_local(r, f"routes[{k}]", (-1, 3)), local[k]]) for k, r in enumerate(routes)]
    if surface is not None:
        if not isinstance(surface, Terrain):
            raise InvalidTypeError(f"surface must be a uavcov Terrain, got {type(surface).__name__}")
        for k, route in enumerate(legs):
            path = np.vstack([pad + [0.0, 0.0, _LIFT_OFF_M], route])
            clear = surface.segments_clear(path[:-1], path[1:])
            if not clear.all():
                leg = int(np.flatnonzero(~clear)[0])
                raise InfeasibleError(
                    f"UAV {k + 1}'s route crosses the structure on leg {leg + 1} ({path[leg].tolist()} -> {path[leg + 1].tolist()}): "
                    "give routes that go round it"
                )
    every = np.vstack([local, pad, *legs])
    enu_to_wgs84(every, anchor)  # every point within the local frame's reach
    true_attitudes = None
    if angles is not None:
        true_attitudes = np.column_stack([local_to_true_heading(local, angles[:, 0], anchor), angles[:, 1]])
    return StructureFlight(
        anchor=anchor,
        positions_local=read_only(local.copy()),
        positions_wgs84=read_only(enu_to_wgs84(local, anchor)),
        takeoff_local=read_only(pad.copy()),
        takeoff_wgs84=read_only(enu_to_wgs84(pad[None], anchor)[0]),
        routes_local=tuple(read_only(r) for r in legs),
        attitudes_local=None if angles is None else read_only(angles.copy()),
        attitudes=None if true_attitudes is None else read_only(true_attitudes),
        hold_s=as_non_negative_float(hold_s, "hold_s"),
        cruise_speed=as_positive_float(cruise_speed, "cruise_speed"),
        hover_speed=as_positive_float(hover_speed, "hover_speed"),
    )


def _rows(plan: StructureFlight, k: int) -> list[tuple[int, str, float, float, float]]:
    """(command, name, latitude, longitude, height above home) of UAV ``k``'s items."""
    home = float(plan.takeoff_wgs84[2])
    route = plan.route_wgs84(k)
    pad_lon, pad_lat = (float(v) for v in plan.takeoff_wgs84[:2])
    rows = [(MAV_CMD_NAV_TAKEOFF, "takeoff", pad_lat, pad_lon, float(route[0, 2] - home))]
    for lon, lat, h in route[:-1]:
        rows.append((MAV_CMD_NAV_WAYPOINT, "transit", float(lat), float(lon), float(h - home)))
    lon, lat, h = (float(v) for v in route[-1])
    rows.append((MAV_CMD_NAV_WAYPOINT, "position", lat, lon, h - home))
    rows.append((MAV_CMD_NAV_LOITER_TIME, "hold", lat, lon, h - home))
    return rows


def structure_qgc_plan(plan: StructureFlight, uav: int) -> dict[str, Any]:
    """UAV ``uav``'s QGroundControl ``.plan`` document (a dict, JSON-ready)."""
    if not isinstance(plan, StructureFlight):
        raise InvalidTypeError(f"expected a uavcov.field.StructureFlight, got {type(plan).__name__}")
    if not 0 <= uav < plan.n_uavs:
        raise InvalidInputError(f"uav must be in [0, {plan.n_uavs}), got {uav}")
    heading = None if plan.attitudes is None else float(plan.attitudes[uav, 0])
    pitch = None if plan.attitudes is None else float(plan.attitudes[uav, 1])
    items = qgc_items(_rows(plan, uav), plan.hold_s, heading, pitch)
    lon, lat, h = (float(v) for v in plan.takeoff_wgs84)
    about = {
        "uav": uav + 1,
        "altitude_frame": _ALTITUDE_FRAME,
        "home_altitude": "the pad's height above the WGS84 ellipsoid (not above mean sea level)",
        "horizontal_crs": "WGS 84 (EPSG:4326), latitude and longitude in degrees",
        "anchor": [plan.anchor.longitude, plan.anchor.latitude, plan.anchor.height],
        **({} if pitch is None else {"camera": "heading: degrees from true north (param 4); gimbal pitch: degrees, -90 nadir, +90 zenith"}),
    }
    return qgc_document(items, (lat, lon, h), plan.cruise_speed, plan.hover_speed, about)


_POSITION_COLUMNS = (
    "uav",
    "east_m",
    "north_m",
    "up_m",
    "longitude",
    "latitude",
    "height_ellipsoid_m",
    "height_home_m",
    "heading_deg",
    "pitch_deg",
)


def render_structure_flight(plan: StructureFlight) -> dict[str, bytes]:
    """Every file of ``write_structure_flight`` as ``{name: bytes}``, nothing written."""
    if not isinstance(plan, StructureFlight):
        raise InvalidTypeError(f"expected a uavcov.field.StructureFlight, got {type(plan).__name__}")
    home = float(plan.takeoff_wgs84[2])
    files: dict[str, bytes] = {}
    rows = []
    for k in range(plan.n_uavs):
        angles = (math.nan, math.nan) if plan.attitudes is None else (float(v) for v in plan.attitudes[k])
        lon, lat, h = (float(v) for v in plan.positions_wgs84[k])
        rows.append([k + 1, *(float(v) for v in plan.positions_local[k]), lon, lat, h, h - home, *angles])
    files["positions.csv"] = _csv(rows, _POSITION_COLUMNS)
    waypoints = []
    for k in range(plan.n_uavs):
        for seq, (local, (lon, lat, h)) in enumerate(zip(plan.routes_local[k], plan.route_wgs84(k), strict=True), start=1):
            waypoints.append([k + 1, seq, *(float(v) for v in local), float(lon), float(lat), float(h), float(h) - home])
    header = ("uav", "seq", "east_m", "north_m", "up_m", "longitude", "latitude", "height_ellipsoid_m", "height_home_m")
    files["waypoints.csv"] = _csv(waypoints, header)
    for k in range(plan.n_uavs):
        files[f"uav_{k + 1:02d}.plan"] = json_bytes(structure_qgc_plan(plan, k), indent=4, what=f"uav_{k + 1:02d}.plan")
    features: list[dict[str, Any]] = [
        {
            "type": "Feature",
            "geometry": {"type": "Point", "coordinates": [float(v) for v in plan.takeoff_wgs84]},
            "properties": {"kind": "takeoff"},
        }
    ]
    for k in range(plan.n_uavs):
        features.append(
            {
                "type": "Feature",
                "geometry": {"type": "Point", "coordinates": [float(v) for v in plan.positions_wgs84[k]]},
                "properties": {"kind": "position", "uav": k + 1},
            }
        )
        line = np.vstack([plan.takeoff_wgs84[None], plan.route_wgs84(k)])
        features.append(
            {
                "type": "Feature",
                "geometry": {"type": "LineString", "coordinates": line.tolist()},
                "properties": {"kind": "route", "uav": k + 1},
            }
        )
    files["plan.geojson"] = json_bytes({"type": "FeatureCollection", "features": features}, indent=1, what="plan.geojson")
    document = {
        "anchor": {"longitude": plan.anchor.longitude, "latitude": plan.anchor.latitude, "height_ellipsoid_m": plan.anchor.height},
        "local_frame": "east, north, up metres from the anchor (x east, y north, z up)",
        "heights": "above the WGS84 ellipsoid; the .plan files' altitudes are relative to the take-off pad",
        "takeoff_local": plan.takeoff_local.tolist(),
        "takeoff_wgs84": plan.takeoff_wgs84.tolist(),
        "positions_local": plan.positions_local.tolist(),
        "positions_wgs84": plan.positions_wgs84.tolist(),
        "attitudes": None if plan.attitudes is None else plan.attitudes.tolist(),
        "attitudes_local": None if plan.attitudes_local is None else plan.attitudes_local.tolist(),
        "hold_s": plan.hold_s,
        "cruise_speed": plan.cruise_speed,
        "hover_speed": plan.hover_speed,
        "format": STRUCTURE_PLAN_FORMAT,
    }
    files["plan.json"] = json_bytes(document, indent=2, what="plan.json")
    return files


def write_structure_flight(plan: StructureFlight, out: Any) -> list[Path]:
    """Write every file of a structure's plan into the folder ``out`` (see the module); returns them.

    Raises
    ------
    ResultsFolderError
        ``out`` is a file, or cannot be created or written.
    """
    return write_files(render_structure_flight(plan), out)
