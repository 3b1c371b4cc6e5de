"""QGroundControl ``.plan`` documents: the MAVLink items of a UAV's flight, and their reader."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from ..errors import InvalidInputError, InvalidTypeError
from ._plan import FlightPlan
from ._strict_json import read_json

MAV_CMD_NAV_WAYPOINT = 16
MAV_CMD_NAV_LOITER_TIME = 19
MAV_CMD_NAV_TAKEOFF = 22
MAV_CMD_DO_MOUNT_CONTROL = 205
"""MAVLink: point the gimbal (param1 pitch, param3 yaw relative to the vehicle, degrees; param7 the mount mode)."""
MAV_MOUNT_MODE_MAVLINK_TARGETING = 2
MAV_FRAME_MISSION = 2
MAV_FRAME_GLOBAL_RELATIVE_ALT = 3
"""MAVLink: altitude relative to the home position (QGroundControl's AltitudeMode 1)."""

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
    document = read_json(path)
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
