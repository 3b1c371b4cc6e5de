"""A depth camera rendered with the project's exact ray engine, and the camera pose a vehicle gives it.

Each pixel is one ray cast against the true surface by the Rust core
(:meth:`uavcov._core.Surface.first_hits`, the BVH the visibility engine uses): its depth is the
distance to the first triangle, or nothing beyond ``range_m``. Pixels are spread evenly in angle
(an equiangular projection), so one model covers a narrow camera and the paper's omnidirectional
sensor (``fov_deg = (360, 180)``: every direction within ``range_m``, the sensor of the paper's
simulations).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from .._validate import as_bool, as_finite_float, as_float_array, as_generator, as_n_threads, as_positive_float, is_int
from ..engine import Terrain
from ..errors import InvalidInputError, InvalidTypeError

__all__ = ["DepthCamera", "camera_rotation"]

_MAX_PIXELS = 4_000_000


@dataclass(frozen=True)
class DepthCamera:
    """A depth camera: resolution, field of view, range and depth noise.

    Attributes
    ----------
    width, height : int
        Pixels across the horizontal and the vertical field of view.
    fov_deg : (float, float)
        Horizontal and vertical field of view, degrees (at most 360 and 180).
    range_m : float
        Farthest depth returned, metres; farther surfaces give no pixel.
    noise_sd : float, default 0.0
        Standard deviation of the depth noise, metres (Gaussian, along each ray).
    pitch_deg : float, default -90.0
        The gimbal's pitch of the optical axis, degrees (-90: straight down; 0: level).
    stabilised : bool, default True
        Whether the gimbal cancels the vehicle's roll and pitch (the axis then follows only its
        heading); ``False`` fixes the camera to the body, which tilts with it.
    """

    width: int
    height: int
    fov_deg: tuple[float, float]
    range_m: float
    noise_sd: float = 0.0
    pitch_deg: float = -90.0
    stabilised: bool = True

    def __post_init__(self) -> None:
        for name in ("width", "height"):
            value = getattr(self, name)
            if not is_int(value) or not 1 <= int(value) <= 100_000:
                raise InvalidInputError(f"{name} must be a whole number of pixels in [1, 100000], got {value!r}")
            object.__setattr__(self, name, int(value))
        if self.width * self.height > _MAX_PIXELS:
            raise InvalidInputError(f"{self.width} x {self.height} pixels: at most {_MAX_PIXELS:,} a camera")
        fov = None if isinstance(self.fov_deg, (str, bytes)) else as_float_array(self.fov_deg, "fov_deg")
        if fov is None or fov.shape != (2,) or not np.isfinite(fov).all() or not (0 < fov[0] <= 360 and 0 < fov[1] <= 180):
            raise InvalidInputError(f"fov_deg must be (horizontal in (0, 360], vertical in (0, 180]) degrees, got {self.fov_deg!r}")
        object.__setattr__(self, "fov_deg", (float(fov[0]), float(fov[1])))
        object.__setattr__(self, "range_m", as_positive_float(self.range_m, "range_m"))
        if self.range_m > 1e6:
            raise InvalidInputError(f"range_m = {self.range_m} m is beyond a camera's (at most 1e6 m)")
        noise = as_finite_float(self.noise_sd, "noise_sd")
        if not 0.0 <= noise <= self.range_m:
            raise InvalidInputError(f"noise_sd must lie in [0, range_m], got {noise}")
        object.__setattr__(self, "noise_sd", noise)
        pitch = as_finite_float(self.pitch_deg, "pitch_deg")
        if not -90.0 <= pitch <= 90.0:
            raise InvalidInputError(f"pitch_deg must lie in [-90, 90], got {pitch}")
        object.__setattr__(self, "pitch_deg", pitch)
        as_bool(self.stabilised, "stabilised")

    @classmethod
    def omnidirectional(cls, range_m: float, resolution: int = 128, noise_sd: float = 0.0) -> DepthCamera:
        """The paper's sensor as a depth camera: every direction within ``range_m``, ``2r x r`` pixels."""
        if not is_int(resolution):  # 2 * resolution of a float or None would fail before the camera's own checks
            raise InvalidTypeError(f"resolution must be a whole number of pixels, got {resolution!r}")
        return cls(width=2 * resolution, height=resolution, fov_deg=(360.0, 180.0), range_m=range_m, noise_sd=noise_sd)

    @property
    def footprint_m(self) -> float:
        """A pixel's width at full range, metres: ``range_m`` times its largest angular size.

        The sensed coverage counts a target observed when a depth point lies this close
        (:func:`uavcov.sim.sensed_coverage`): with it the sensed share tends to the exact one as
        the resolution rises (``docs/realistic.md``), where a fixed radius over-counts.
        """
        return float(self.range_m * max(np.radians(self.fov_deg[0]) / self.width, np.radians(self.fov_deg[1]) / self.height))

    def directions(self) -> np.ndarray:
        """``(height * width, 3)`` unit rays in the camera frame (x forward, y left, z up), row by row."""
        h_fov, v_fov = np.radians(self.fov_deg)
        # Pixel centres: a full circle closes on itself, so its pixels split it without repeating an edge.
        az = (np.arange(self.width) + 0.5) / self.width * h_fov - h_fov / 2.0
        el = v_fov / 2.0 - (np.arange(self.height) + 0.5) / self.height * v_fov
        el_grid, az_grid = np.meshgrid(el, az, indexing="ij")
        cos_el = np.cos(el_grid)
        rays = np.stack([cos_el * np.cos(az_grid), cos_el * np.sin(az_grid), np.sin(el_grid)], axis=-1)
        return rays.reshape(-1, 3)

    def render(
        self, terrain: Terrain, position: Any, rotation: Any, *, rng: Any = None, n_threads: int | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """The depth image from ``position`` with the camera's ``rotation`` (camera to world).

        Parameters
        ----------
        terrain : Terrain
            The true surface.
        position : (3,) array_like
            The camera's centre, metres.
        rotation : (3, 3) array_like
            Camera frame to world frame (:func:`camera_rotation`).
        rng : None, int or numpy.random.Generator
            Source of the depth noise.
        n_threads : int, optional

        Returns
        -------
        depth : (height, width) ndarray
            Metres along each ray (noise included), NaN where nothing lies within range.
        points : (n, 3) ndarray
            The world points of the valid pixels, metres.
        """
        if not isinstance(terrain, Terrain):
            raise InvalidTypeError(f"terrain must be a uavcov.Terrain, got {type(terrain).__name__}")
        generator = as_generator(rng)  # checked with or without noise to draw
        origin = as_float_array(position, "position")
        turn = as_float_array(rotation, "rotation")
        if origin.shape != (3,) or turn.shape != (3, 3) or not (np.isfinite(origin).all() and np.isfinite(turn).all()):
            raise InvalidInputError("position must be 3 finite metres and rotation a finite 3 x 3 matrix")
        rays = self.directions() @ turn.T
        hits = terrain.core.first_hits(np.broadcast_to(origin, rays.shape).copy(), rays, self.range_m, as_n_threads(n_threads))
        valid = np.isfinite(hits)
        depth = np.where(valid, hits, np.nan)
        if self.noise_sd > 0.0:
            depth = depth + generator.normal(0.0, self.noise_sd, size=depth.shape)
        points = origin + rays[valid] * depth[valid, None]
        return depth.reshape(self.height, self.width), points


def camera_rotation(quaternion: Any, camera: DepthCamera) -> np.ndarray:
    """Camera-to-world rotation of ``camera`` on a vehicle of attitude ``quaternion`` ``[x, y, z, w]``.

    The gimbal pitches the optical axis by ``camera.pitch_deg`` about the body's y axis; a
    stabilised gimbal keeps only the vehicle's heading (yaw), a fixed camera the whole attitude.
    """
    if not isinstance(camera, DepthCamera):
        raise InvalidTypeError(f"camera must be a DepthCamera, got {type(camera).__name__}")
    q = as_float_array(quaternion, "quaternion", ndim=1)
    if q.shape != (4,) or not np.linalg.norm(q) > 0.0:
        raise InvalidInputError(f"quaternion must be 4 numbers [x, y, z, w], not all zero, got {q.tolist()}")
    body = Rotation.from_quat(q)
    if camera.stabilised:
        yaw = body.as_euler("ZYX")[0]
        body = Rotation.from_euler("Z", yaw)
    # Pitch down is a positive turn about the body's y axis (x forward, y left, z up).
    gimbal = Rotation.from_euler("y", -camera.pitch_deg, degrees=True)
    return np.asarray((body * gimbal).as_matrix())
