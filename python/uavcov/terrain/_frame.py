"""Local metric frames: recentred coordinates for the engine, and the map back to the source's.

Recentring matters because georeferenced input (eastings of 500 km, northings of 5000 km) would
otherwise spend most of the float64 mantissa on the offset, and the engine's geometric predicates
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
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import as_bool, as_finite_float, as_float_array, within_coordinate_bound
from ..errors import InvalidInputError

_WGS84_A = 6378137.0
_WGS84_F = 1.0 / 298.257223563
_WGS84_E2 = _WGS84_F * (2.0 - _WGS84_F)


def metres_per_degree(latitude: float) -> tuple[float, float]:
    """Metres per degree of longitude and of latitude at ``latitude`` (degrees), WGS84.

    From the prime-vertical radius ``N`` and the meridian radius ``M`` of the ellipsoid:
    ``(pi/180) N cos(phi)`` and ``(pi/180) M``.

    Examples
    --------
    >>> from uavcov.terrain import metres_per_degree
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
    Local coordinates, and the origin, lie within 1e15 m of zero (the engine's bound): a point
    beyond is refused, not mapped to a number that has lost its metres.

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
        Latitude (degrees, in [-90, 90]) of the equirectangular projection when geographic;
        None otherwise.
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
        within_coordinate_bound(origin, "origin")
        geographic = as_bool(self.geographic, "geographic")
        latitude = self.reference_latitude
        if latitude is not None:
            latitude = as_finite_float(latitude, "reference_latitude")
            if abs(latitude) > 90.0:
                raise InvalidInputError(f"reference_latitude must be in [-90, 90] degrees, got {latitude}")
        if geographic != (latitude is not None):
            raise InvalidInputError(
                f"a geographic frame needs its reference_latitude, and only a geographic one has one; got geographic={geographic}, "
                f"reference_latitude={latitude}"
            )
        object.__setattr__(self, "geographic", geographic)
        object.__setattr__(self, "reference_latitude", latitude)
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
        with np.errstate(over="ignore"):  # an overflow is refused just below, by name
            local: np.ndarray = (array - self.origin) * self.factors
        return within_coordinate_bound(local, "points in the local frame")

    def to_source(self, points: Any) -> np.ndarray:
        """Local metres ``(n, 3)`` back to source coordinates ``(n, 3)``."""
        array = within_coordinate_bound(_as_xyz(points, "points"), "points")
        source: np.ndarray = array / self.factors + self.origin
        return source


def _as_xyz(points: Any, name: str) -> np.ndarray:
    array = as_float_array(points, name)
    if array.ndim == 1 and array.shape[0] == 3:
        array = array.reshape(1, 3)
    if array.ndim != 2 or array.shape[1] != 3:
        raise InvalidInputError(f"{name} must have shape (n, 3), got {array.shape}")
    return array
