"""What each UAV's sensor reaches before occlusion: a range, and for a camera a pinhole frustum.

The paper's UAVs "have omni-directional sensing capabilities" up to ``d_max``; that stays the
default everywhere. A :class:`Sensor` per UAV lets a team mix ranges, add a minimum range, and
see through a :class:`Camera`: a pinhole with the sensor size, focal length and image size of a
survey planner's camera definition (QGroundControl's names), on a gimbal that sets its heading
(yaw) and pitch. A target is reached when it lies within range and inside the camera's field of
view; whether it is *seen* is then the line of sight, exactly as for the paper's sensor, on the
grid method and the mesh method alike.

Angles at the API are degrees. A pose is ``(x, y, z, yaw, pitch)``: yaw is the heading,
clockwise from north (+y) as a compass reads it (0 north, 90 east), any finite value (it wraps);
pitch is the gimbal's, from -90 (straight down, nadir) through 0 (level with the horizon) to +90
(straight up, zenith: looking up under a deck). The image's width runs along the camera's right,
its height along its up (at nadir, the top of the image points along the heading; at zenith, the
bottom). Which pitches a real gimbal reaches is its :class:`Gimbal`'s ``pitch_range``
(``GIMBAL_PITCH_LIMITS`` gives capability classes); a mission refuses a pitch above the
horizon unless its gimbal's range reaches it.

Examples
--------
>>> import numpy as np, uavcov
>>> flat = uavcov.Terrain.from_grid(np.zeros((41, 41)), spacing=1.0)
>>> vis = uavcov.Visibility(flat, d_max=100.0)
>>> camera = uavcov.Camera.from_fov(60.0, 45.0)
>>> poses = [[20.0, 20.0, 10.0, 0.0, -90.0]]  # x, y, z, yaw, pitch: 10 m up, looking down
>>> omni = vis.coverage([poses[0][:3]])
>>> nadir = vis.coverage(poses, sensors=[uavcov.Sensor(100.0, camera=camera)])
>>> omni, round(nadir, 3)  # the footprint: about 11.5 m x 8.3 m of the 40 m x 40 m square
(1.0, 0.062)
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from .._validate import as_bool, as_float_array, as_non_negative_float, as_positive_float, as_positive_int
from ..errors import InvalidInputError, InvalidTypeError

# Columns of a packed sensor row (``uavcov._core``): d_min, d_max, forward (3), right (3), up (3),
# tan(hfov / 2), tan(vfov / 2) (the camera's eleven NaN for an omnidirectional sensor), the cosine
# of the largest incidence angle, the GSD per metre of distance and the GSD of full quality (NaN
# where not set).
_COLUMNS = 16


_MAX_PIXELS_A_SIDE = 1_000_000  # pixels along one side of an image: far beyond any camera made


@dataclass(frozen=True)
class Camera:
    """A pinhole camera, by its sensor and lens (the fields of QGroundControl's camera definitions).

    Parameters
    ----------
    sensor_width_mm, sensor_height_mm : float
        The image sensor's size, millimetres (> 0).
    focal_length_mm : float
        Millimetres (> 0).
    image_width_px, image_height_px : int
        The image's size, pixels (1 to 1 000 000 a side).

    Examples
    --------
    >>> c = Camera(13.2, 8.8, 8.8, 5472, 3648)  # a 1-inch survey camera
    >>> round(c.hfov_deg, 1), round(c.vfov_deg, 1), round(100 * c.gsd_m(50.0), 2)  # cm per pixel at 50 m
    (73.7, 53.1, 1.37)
    """

    sensor_width_mm: float
    sensor_height_mm: float
    focal_length_mm: float
    image_width_px: int
    image_height_px: int

    def __post_init__(self) -> None:
        for name in ("sensor_width_mm", "sensor_height_mm", "focal_length_mm"):
            object.__setattr__(self, name, as_positive_float(getattr(self, name), name))
        for name in ("image_width_px", "image_height_px"):
            pixels = as_positive_int(getattr(self, name), name)
            if pixels > _MAX_PIXELS_A_SIDE:  # 10**400 px made the ground sample distance an OverflowError
                raise InvalidInputError(f"{name} must be at most {_MAX_PIXELS_A_SIDE:,} pixels (beyond any camera), got {pixels:,}")
            object.__setattr__(self, name, pixels)

    @classmethod
    def from_fov(cls, hfov_deg: float, vfov_deg: float, image_width_px: int = 4000, image_height_px: int = 3000) -> Camera:
        """A camera of the given horizontal and vertical fields of view, degrees in ``(0, 180)``
        (a 10 mm lens, the sensor sized to match)."""
        h = _fov(hfov_deg, "hfov_deg")
        v = _fov(vfov_deg, "vfov_deg")
        focal = 10.0
        return cls(2 * focal * math.tan(h / 2), 2 * focal * math.tan(v / 2), focal, image_width_px, image_height_px)

    @property
    def tan_half_fov(self) -> tuple[float, float]:
        """``(tan(hfov / 2), tan(vfov / 2))``: the frustum's slopes."""
        f = 2.0 * self.focal_length_mm
        return self.sensor_width_mm / f, self.sensor_height_mm / f

    @property
    def hfov_deg(self) -> float:
        """Horizontal field of view (along the image's width), degrees."""
        return math.degrees(2.0 * math.atan(self.tan_half_fov[0]))

    @property
    def vfov_deg(self) -> float:
        """Vertical field of view (along the image's height), degrees."""
        return math.degrees(2.0 * math.atan(self.tan_half_fov[1]))

    def gsd_m(self, distance_m: float) -> float:
        """Ground sample distance at ``distance_m`` along the optical axis, metres per pixel (the
        width of one pixel's footprint on a surface facing the camera)."""
        distance = as_non_negative_float(distance_m, "distance_m")
        return distance * self.sensor_width_mm / (self.focal_length_mm * self.image_width_px)


@dataclass(frozen=True)
class Sensor:
    """One UAV's sensor.

    Parameters
    ----------
    d_max : float
        Greatest range, metres (> 0, finite).
    d_min : float, default 0
        Least range, metres, in ``[0, d_max)``.
    camera : Camera, optional
        Sees only inside this camera's field of view (its pose's yaw and pitch orient it).
        ``None`` is the paper's omnidirectional sensor.
    max_gsd_m : float, optional
        The coarsest useful ground sample distance, metres per pixel: targets farther than the
        distance at which the camera's GSD reaches it are not reached (needs ``camera``).
    max_incidence_deg : float, optional
        The largest angle, degrees in ``[0, 90]``, between a target's surface normal and the
        direction to the UAV: targets seen more obliquely are not reached (the targets need
        normals, which a grid terrain's own targets have).
    good_gsd_m : float, optional
        The GSD of full view quality, metres per pixel: :meth:`~uavcov.Visibility.quality` rates
        a view ``min(1, good_gsd_m / gsd)`` times the cosine of its incidence (needs ``camera``).
    """

    d_max: float
    d_min: float = 0.0
    camera: Camera | None = None
    max_gsd_m: float | None = None
    max_incidence_deg: float | None = None
    good_gsd_m: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "d_max", as_positive_float(self.d_max, "d_max"))
        d_min = as_non_negative_float(self.d_min, "d_min")
        if d_min >= self.d_max:
            raise InvalidInputError(f"d_min must be below d_max = {self.d_max} m, got {d_min}")
        object.__setattr__(self, "d_min", d_min)
        if self.camera is not None and not isinstance(self.camera, Camera):
            raise InvalidTypeError(f"camera must be a uavcov.Camera or None, got {type(self.camera).__name__}")
        if self.max_gsd_m is not None:
            if self.camera is None:
                raise InvalidInputError("max_gsd_m needs a camera (the GSD comes from its lens and sensor)")
            object.__setattr__(self, "max_gsd_m", as_positive_float(self.max_gsd_m, "max_gsd_m"))
            if self.reach_m <= self.d_min:
                raise InvalidInputError(
                    f"max_gsd_m = {self.max_gsd_m} m/px is reached {self.reach_m:.4g} m away, "
                    f"within d_min = {self.d_min} m: nothing is in range"
                )
        if self.max_incidence_deg is not None:
            angle = as_non_negative_float(self.max_incidence_deg, "max_incidence_deg")
            if angle > 90.0:
                raise InvalidInputError(f"max_incidence_deg must be in [0, 90], got {angle}")
            object.__setattr__(self, "max_incidence_deg", angle)
        if self.good_gsd_m is not None:
            if self.camera is None:
                raise InvalidInputError("good_gsd_m needs a camera (the GSD comes from its lens and sensor)")
            object.__setattr__(self, "good_gsd_m", as_positive_float(self.good_gsd_m, "good_gsd_m"))

    @property
    def reach_m(self) -> float:
        """The range the sensor uses: ``d_max``, or less where ``max_gsd_m`` binds first."""
        if self.max_gsd_m is None or self.camera is None:
            return self.d_max
        per_metre = self.camera.gsd_m(1.0)
        return min(self.d_max, self.max_gsd_m / per_metre)


@dataclass(frozen=True)
class Gimbal:
    """Which camera angles a mission optimises beside the positions, and within what bounds.

    The optimiser (centralised CAO) perturbs every decision variable by the same relative step:
    a position by ``alpha_k`` metres, an angle by ``alpha_k / alpha_0 * alpha0_deg`` degrees (its
    state is the angle over ``alpha0_deg / alpha_0`` degrees per metre), so the angles' step starts
    at ``alpha0_deg`` and decays as the positions' does.

    Parameters
    ----------
    free_yaw : bool, default False
        Optimise each UAV's heading (any value: it wraps; results report it in ``[0, 360)``).
    pitch_range : (float, float), optional
        ``(lowest, highest)`` gimbal pitch in degrees within ``[-90, 90]`` (above 0 the camera
        looks above the horizon, which only some gimbals can: ``GIMBAL_PITCH_LIMITS``):
        optimise each UAV's pitch within it (a candidate outside is infeasible, as a position
        outside its band is). ``None`` keeps the pitch fixed.
    alpha0_deg : float, default 10.0
        The angles' first step, degrees (> 0): the standard deviation of a heading's or pitch's
        perturbation at iteration 0 (chosen on development seeds: docs/cameras.md).

    Examples
    --------
    >>> Gimbal(free_yaw=True, pitch_range=(-90.0, -30.0)).free_angles
    ('yaw', 'pitch')
    """

    free_yaw: bool = False
    pitch_range: tuple[float, float] | None = None
    alpha0_deg: float = 10.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "free_yaw", as_bool(self.free_yaw, "free_yaw"))
        if self.pitch_range is not None:
            bounds = as_float_array(self.pitch_range, "pitch_range") if not isinstance(self.pitch_range, (str, bytes)) else None
            if bounds is None or bounds.shape != (2,):
                raise InvalidInputError(f"pitch_range must be (lowest, highest) in degrees, got {self.pitch_range!r}")
            low, high = float(bounds[0]), float(bounds[1])
            if not -90.0 <= low <= high <= 90.0:
                raise InvalidInputError(f"pitch_range must satisfy -90 <= lowest <= highest <= 90 degrees, got ({low}, {high})")
            object.__setattr__(self, "pitch_range", (low, high))
        object.__setattr__(self, "alpha0_deg", as_positive_float(self.alpha0_deg, "alpha0_deg"))

    @classmethod
    def preset(cls, capability: str, *, free_yaw: bool = False, alpha0_deg: float = 10.0) -> Gimbal:
        """A gimbal whose pitch is optimised over a capability class's range (``GIMBAL_PITCH_LIMITS``).

        Examples
        --------
        >>> Gimbal.preset("upward").pitch_range
        (-90.0, 90.0)
        """
        return cls(free_yaw=free_yaw, pitch_range=gimbal_pitch_limits(capability), alpha0_deg=alpha0_deg)

    @property
    def free_angles(self) -> tuple[str, ...]:
        """The angles optimised, in the order they follow the position: ``"yaw"``, ``"pitch"``."""
        return (("yaw",) if self.free_yaw else ()) + (("pitch",) if self.pitch_range is not None else ())


GIMBAL_PITCH_LIMITS: Mapping[str, tuple[float, float]] = MappingProxyType(
    {
        "nadir": (-90.0, 0.0),
        "three_axis": (-90.0, 30.0),
        "upward": (-90.0, 90.0),
    }
)
"""Pitch ranges, degrees, by the capability class of a gimbal (not any vendor's specification).

``"nadir"``
    A mapping gimbal: straight down to level, today's range everywhere in uavcov.
``"three_axis"``
    A typical stabilised 3-axis camera gimbal under the airframe, which tilts a little above the
    horizon before the airframe blocks the view; +30 is a round figure for that class, not a
    measured specification: give the range of your gimbal's manual with
    ``Gimbal(pitch_range=...)``.
``"upward"``
    An inspection gimbal mounted so that nothing of the airframe is above the camera (top
    mounted, or on a nose boom): straight down to straight up, what looking up under a deck
    needs.
"""


def gimbal_pitch_limits(capability: Any) -> tuple[float, float]:
    """The pitch range of a capability class of ``GIMBAL_PITCH_LIMITS``, degrees."""
    if not isinstance(capability, str):
        raise InvalidTypeError(f"a gimbal capability must be a string, got {type(capability).__name__}")
    if capability not in GIMBAL_PITCH_LIMITS:
        raise InvalidInputError(f"unknown gimbal capability {capability!r}: one of {tuple(GIMBAL_PITCH_LIMITS)}")
    return GIMBAL_PITCH_LIMITS[capability]


def _fov(value: Any, name: str) -> float:
    degrees = as_positive_float(value, name)
    if degrees >= 180.0:
        raise InvalidInputError(f"{name} must be in (0, 180) degrees, got {degrees}")
    if math.tan(math.radians(degrees) / 2) == 0.0:  # a subnormal angle: the sensor it sizes would be 0 mm wide
        raise InvalidInputError(f"{name} must be in (0, 180) degrees, got {degrees}, too narrow for a float to hold its sensor")
    return math.radians(degrees)


def _reduce_degrees(angle: Any) -> np.ndarray:
    """An angle in degrees reduced exactly into ``(-360, 360)`` before any trigonometry.

    ``fmod`` is exact in floating point, so a heading of 1e300 degrees points where
    ``fmod(1e300, 360)`` does; converting first (``radians(1e300)``) would round away every digit
    that says where. Angles already in ``(-360, 360)`` come back unchanged, bit for bit.
    """
    return np.fmod(np.asarray(angle, dtype=np.float64), 360.0)


def camera_axes(yaw_deg: Any, pitch_deg: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The camera's unit axes in the world frame (x east, y north, z up), each ``(N, 3)``.

    ``forward`` is the optical axis, ``right`` the image's width (level: the gimbal does not
    roll), ``up = right x forward`` the image's height.

    Raises
    ------
    InvalidInputError
        A non-finite angle, or a pitch outside ``[-90, 90]`` degrees (nadir to zenith; beyond
        the zenith, turn the heading round instead).

    Examples
    --------
    >>> forward, right, up = camera_axes([0.0], [90.0])  # straight up, the image's top to the south
    >>> (forward[0].round(12) + 0.0).tolist(), (up[0].round(12) + 0.0).tolist()
    ([0.0, 0.0, 1.0], [0.0, -1.0, 0.0])
    """
    yaw = np.atleast_1d(as_float_array(yaw_deg, "yaw"))
    pitch = np.atleast_1d(as_float_array(pitch_deg, "pitch"))
    if yaw.shape != pitch.shape or yaw.ndim != 1:
        raise InvalidInputError(f"yaw and pitch must be (N,) arrays of the same length, got {yaw.shape} and {pitch.shape}")
    if not (np.isfinite(yaw).all() and np.isfinite(pitch).all()):
        raise InvalidInputError("yaw and pitch must be finite")
    if ((pitch < -90.0) | (pitch > 90.0)).any():
        raise InvalidInputError(f"pitch must be in [-90, 90] degrees (nadir to zenith), got {pitch.tolist()}")
    y, p = np.radians(_reduce_degrees(yaw)), np.radians(pitch)
    sy, cy, sp, cp = np.sin(y), np.cos(y), np.sin(p), np.cos(p)
    forward = np.column_stack([sy * cp, cy * cp, sp])
    right = np.column_stack([cy, -sy, np.zeros_like(y)])
    up = np.cross(right, forward)
    return forward, right, up


def pack_sensors(sensors: Sequence[Sensor], poses: Any) -> tuple[np.ndarray, np.ndarray]:
    """The UAVs' positions ``(N, 3)`` and their sensors packed for ``uavcov._core`` ``(N, 16)``.

    ``poses`` is ``(N, 3)`` positions when no sensor is a camera, else ``(N, 5)``
    ``(x, y, z, yaw, pitch)`` (yaw and pitch in degrees; ignored for an omnidirectional sensor).
    """
    if isinstance(sensors, Sensor) or not isinstance(sensors, Sequence):
        raise InvalidTypeError(f"sensors must be a sequence of uavcov.Sensor, one per UAV, got {type(sensors).__name__}")
    if not all(isinstance(s, Sensor) for s in sensors):
        raise InvalidTypeError("every sensor must be a uavcov.Sensor")
    array = as_float_array(poses, "poses")
    if array.ndim != 2 or array.shape[1] not in (3, 5):
        raise InvalidInputError(f"poses must have shape (N, 3) or (N, 5) (x, y, z, yaw, pitch), got {array.shape}")
    if len(sensors) != array.shape[0]:
        raise InvalidInputError(f"{len(sensors)} sensors for {array.shape[0]} UAVs: give one per UAV")
    cameras = [i for i, s in enumerate(sensors) if s.camera is not None]
    packed = np.full((array.shape[0], _COLUMNS), np.nan)
    packed[:, 0] = [s.d_min for s in sensors]
    packed[:, 1] = [s.reach_m for s in sensors]
    if cameras:
        if array.shape[1] != 5:
            raise InvalidInputError("a camera needs its pose's yaw and pitch: poses must have shape (N, 5)")
        forward, right, up = camera_axes(array[cameras, 3], array[cameras, 4])
        packed[cameras, 2:5] = forward
        packed[cameras, 5:8] = right
        packed[cameras, 8:11] = up
        packed[cameras, 11:13] = [sensors[i].camera.tan_half_fov for i in cameras]  # type: ignore[union-attr]
    for i, s in enumerate(sensors):
        if s.max_incidence_deg is not None:
            packed[i, 13] = math.cos(math.radians(s.max_incidence_deg))
        if s.good_gsd_m is not None and s.camera is not None:
            packed[i, 14:16] = (s.camera.gsd_m(1.0), s.good_gsd_m)
    return np.ascontiguousarray(array[:, :3]), packed
