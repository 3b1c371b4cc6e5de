"""A local east-north-up frame anchored at a WGS84 point, and its exact map to WGS84.

A structure is modelled in metres, x east, y north, z up, with its origin at a surveyed anchor
(longitude, latitude, ellipsoidal height). ``enu_to_wgs84`` maps such points to WGS84 by the
standard chain: the anchor to Earth-centred Earth-fixed (ECEF) coordinates, the ENU offset rotated
into ECEF, and ECEF back to geodetic coordinates by Bowring's iteration (converged to round-off:
the tests compare with pyproj's ``+proj=topocentric`` pipeline to 1e-9 degrees and 1e-6 m).
Heights are above the WGS84 ellipsoid, not above mean sea level: the difference (the geoid
undulation, tens of metres) cancels in the ``.plan`` files, whose altitudes are relative to home.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import as_float_array
from ..errors import InvalidInputError

WGS84_A = 6378137.0
"""The WGS84 ellipsoid's semi-major axis, metres."""
WGS84_F = 1.0 / 298.257223563
"""The WGS84 ellipsoid's flattening."""
_E2 = WGS84_F * (2.0 - WGS84_F)
_B = WGS84_A * (1.0 - WGS84_F)
_EP2 = _E2 / (1.0 - _E2)

MAX_LOCAL_M = 100_000.0
"""The largest coordinate of a local frame, metres: a structure's frame is a few kilometres at most."""
_MAX_HEIGHT_M = 100_000.0


@dataclass(frozen=True)
class GeoAnchor:
    """The WGS84 point at the origin of a local ENU frame.

    Parameters
    ----------
    longitude, latitude : float
        Degrees, ``[-180, 180]`` and ``[-90, 90]``.
    height : float, default 0
        Metres above the WGS84 ellipsoid, ``[-100 km, 100 km]``.
    """

    longitude: float
    latitude: float
    height: float = 0.0

    def __post_init__(self) -> None:
        for name, bound in (("longitude", 180.0), ("latitude", 90.0), ("height", _MAX_HEIGHT_M)):
            value = getattr(self, name)
            if isinstance(value, (bool, np.timedelta64)) or not isinstance(value, (int, float, np.floating, np.integer)):
                raise InvalidInputError(f"anchor {name} must be a number, got {value!r}")
            number = float(value) if not isinstance(value, int) or abs(value) <= _MAX_HEIGHT_M else math.inf  # float(10**400) overflows
            if not math.isfinite(number) or abs(number) > bound:
                raise InvalidInputError(f"anchor {name} must be finite and within [-{bound:g}, {bound:g}], got {value!r}")
            object.__setattr__(self, name, number)

    def ecef(self) -> np.ndarray:
        """The anchor in ECEF coordinates, metres."""
        ecef: np.ndarray = _geodetic_to_ecef(np.array([self.longitude]), np.array([self.latitude]), np.array([self.height]))[0]
        return ecef

    def rotation(self) -> np.ndarray:
        """The ``(3, 3)`` matrix whose rows are the local east, north and up unit vectors in ECEF."""
        return _enu_axes(math.radians(self.longitude), math.radians(self.latitude))


def _enu_axes(lon: float, lat: float) -> np.ndarray:
    sl, cl, sp, cp = math.sin(lon), math.cos(lon), math.sin(lat), math.cos(lat)
    return np.array([[-sl, cl, 0.0], [-sp * cl, -sp * sl, cp], [cp * cl, cp * sl, sp]])


def _geodetic_to_ecef(lon_deg: np.ndarray, lat_deg: np.ndarray, h: np.ndarray) -> np.ndarray:
    lon, lat = np.radians(lon_deg), np.radians(lat_deg)
    n = WGS84_A / np.sqrt(1.0 - _E2 * np.sin(lat) ** 2)
    return np.column_stack([(n + h) * np.cos(lat) * np.cos(lon), (n + h) * np.cos(lat) * np.sin(lon), (n * (1.0 - _E2) + h) * np.sin(lat)])


def _ecef_to_geodetic(xyz: np.ndarray) -> np.ndarray:
    """(longitude, latitude, height) by Bowring's iteration from his first guess."""
    x, y, z = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    p = np.hypot(x, y)
    lon = np.arctan2(y, x)
    theta = np.arctan2(z * WGS84_A, p * _B)
    lat = np.arctan2(z + _EP2 * _B * np.sin(theta) ** 3, p - _E2 * WGS84_A * np.cos(theta) ** 3)
    for _ in range(5):  # each step squares the error; from Bowring's guess two already reach 1e-15
        n = WGS84_A / np.sqrt(1.0 - _E2 * np.sin(lat) ** 2)
        lat = np.arctan2(z + _E2 * n * np.sin(lat), p)
    # The height along the normal, well conditioned at every latitude (no division by cos or sin).
    h = p * np.cos(lat) + z * np.sin(lat) - WGS84_A * np.sqrt(1.0 - _E2 * np.sin(lat) ** 2)
    return np.column_stack([np.degrees(lon), np.degrees(lat), h])


def _as_local(points: Any) -> np.ndarray:
    local = as_float_array(points, "points")
    if local.ndim != 2 or local.shape[1] != 3:
        raise InvalidInputError(f"points must be (n, 3) local east, north, up metres, got shape {local.shape}")
    if not np.isfinite(local).all() or (np.abs(local) > MAX_LOCAL_M).any():
        raise InvalidInputError(f"local points must be finite and within {MAX_LOCAL_M:g} m of the anchor")
    return local


def enu_to_wgs84(points: Any, anchor: GeoAnchor) -> np.ndarray:
    """Local east, north, up metres around ``anchor`` -> WGS84 longitude, latitude, ellipsoidal height.

    Parameters
    ----------
    points : (n, 3) array_like of float
        Metres, within 100 km of the anchor.
    anchor : GeoAnchor

    Returns
    -------
    (n, 3) float64 ndarray
        Longitude and latitude in degrees, height above the ellipsoid in metres.

    Examples
    --------
    >>> anchor = GeoAnchor(longitude=7.0, latitude=46.0, height=500.0)
    >>> enu_to_wgs84([[0.0, 0.0, 0.0]], anchor).round(6).tolist()  # ECEF's rounding: 1e-9 m
    [[7.0, 46.0, 500.0]]
    >>> enu_to_wgs84([[1000.0, 0.0, 0.0]], anchor).round(6).tolist()  # 1 km east: the Earth curves away
    [[7.012908, 45.999999, 500.078251]]
    """
    if not isinstance(anchor, GeoAnchor):
        raise InvalidInputError(f"anchor must be a uavcov.field.GeoAnchor, got {type(anchor).__name__}")
    local = _as_local(points)
    ecef = anchor.ecef() + local @ anchor.rotation()
    return _ecef_to_geodetic(ecef)


def local_to_true_heading(points: Any, yaw_deg: Any, anchor: GeoAnchor) -> np.ndarray:
    """A heading in the anchor's frame (clockwise from its north) as a compass reads it at each point.

    Away from the anchor, the local frame's north and the true north at a point differ by the
    meridians' convergence (about ``d_lon sin(latitude)``: 1e-4 degrees 100 m east at 45
    degrees); the heading is turned by it exactly, through ECEF.
    """
    local = _as_local(points)
    degrees = as_float_array(yaw_deg, "yaw_deg", ndim=1)
    if degrees.shape[0] != local.shape[0] or not np.isfinite(degrees).all():
        raise InvalidInputError("yaw_deg must be one finite heading per point")
    yaw = np.radians(np.fmod(degrees, 360.0))  # reduced exactly first: radians(1e300) keeps no heading
    geodetic = enu_to_wgs84(local, anchor)
    direction = np.column_stack([np.sin(yaw), np.cos(yaw), np.zeros_like(yaw)]) @ anchor.rotation()
    out = np.empty(local.shape[0])
    for k, (lon, lat, _) in enumerate(geodetic):
        east, north, _ = _enu_axes(math.radians(lon), math.radians(lat)) @ direction[k]
        out[k] = math.degrees(math.atan2(east, north)) % 360.0
    return out
