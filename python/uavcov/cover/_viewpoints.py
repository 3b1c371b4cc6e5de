"""Candidate viewpoints: where a UAV may be placed, as a finite set a greedy can choose from.

A coverage problem over a finite set of candidate viewpoints is a weighted maximum-coverage
problem (see :mod:`uavcov.cover._greedy`). For terrain the candidates are a lattice over the
flight band: an x-y lattice ``spacing`` metres apart over the flight box (from its lower-left
corner, so that halving the spacing keeps every earlier column), times ``n_heights`` heights
per column evenly spaced from ``ground + h_min`` to ``min(ground + h_max, z_max)`` (so that
``2 n - 1`` heights keep the ``n`` earlier ones), kept where eq. 2's limits accept them
(``uavcov.limits.feasibility``, one UAV at a time). Where the sensors are cameras,
each position is repeated for every orientation ``(yaw, pitch)`` of the settings.

:class:`Viewpoints` is what every generator returns. For a structure, ``viewpoint_offsets``
flies points of the surface out along their outward normals (under a deck, beside a pier), with
``source="normal offsets"``; nothing downstream changes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .._validate import as_bool, as_count, as_finite_float, as_float_array, as_positive_float, as_positive_int, read_only
from ..engine import Terrain
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError
from ..limits import Constraints, feasibility
from ._faces import surface_normals

MAX_CANDIDATES = 1_000_000
"""Most candidate viewpoints one problem may hold (10^6 x 10^4 targets is 1.25 GB of bits: the
Rust side refuses over 1 GiB with :class:`uavcov.errors.SurfaceTooLargeError`)."""
# The flight band's ends are moved in by this much, so that the limits' exact checks never
# refuse a lattice point on round-off (the same metre fraction closest_admissible aims inside by).
_BAND_INSET = 1e-6


@dataclass(frozen=True)
class GreedySettings:
    """The candidate viewpoints of a greedy placement and how the greedy runs.

    Attributes
    ----------
    spacing : float, default 5.0
        Distance between neighbouring x-y lattice columns, metres (> 0).
    n_heights : int, default 3
        Heights per column, evenly spaced over the flight band (1: its floor, ``ground + h_min``).
    yaws : tuple of float, default (0.0, 90.0, 180.0, 270.0)
        Camera headings tried at every position, degrees (camera sensors only).
    pitches : tuple of float, default (-90.0,)
        Camera gimbal pitches tried at every position, degrees (-90: straight down; cameras only).
    separation : bool, default True
        Keep the picks at least the constraints' ``d_safe`` apart.
    """

    spacing: float = 5.0
    n_heights: int = 3
    yaws: tuple[float, ...] = (0.0, 90.0, 180.0, 270.0)
    pitches: tuple[float, ...] = (-90.0,)
    separation: bool = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "spacing", as_positive_float(self.spacing, "spacing"))
        object.__setattr__(self, "n_heights", as_count(self.n_heights, "n_heights", 1000))
        for name in ("yaws", "pitches"):
            value = getattr(self, name)
            if isinstance(value, (str, bytes)) or not isinstance(value, (tuple, list)) or not value:
                raise InvalidInputError(f"{name} must be a non-empty tuple of angles in degrees, got {value!r}")
            object.__setattr__(self, name, tuple(as_finite_float(v, name) for v in value))
        as_bool(self.separation, "separation")


@dataclass(frozen=True)
class Viewpoints:
    """A finite set of candidate viewpoints.

    Attributes
    ----------
    positions : (C, 3) float64 ndarray
        Metres.
    poses : (C, 5) float64 ndarray or None
        ``(x, y, z, yaw, pitch)`` (degrees) for camera sensors, else None.
    source : str
        How they were made: ``"lattice"`` (:func:`viewpoint_lattice`).
    description : str
        The lattice in words (what a bound over these candidates holds for).
    """

    positions: np.ndarray
    poses: np.ndarray | None
    source: str
    description: str = field(default="")

    @property
    def n(self) -> int:
        """Number of candidates."""
        return int(self.positions.shape[0])


def _admissible_alone(limits: Constraints, world: Terrain, points: np.ndarray, n_threads: int | None) -> np.ndarray:
    """The ``(n, 3)`` points the limits accept, each as a lone UAV where it is (no move to check)."""
    alone = replace(limits, check_moves=False)
    kept: np.ndarray = points[np.asarray(feasibility(alone, world, n_threads=n_threads)(points[:1], points[:, None, :]), dtype=bool)]
    return kept


def viewpoint_lattice(
    world: Terrain,
    constraints: Constraints,
    settings: GreedySettings | None = None,
    *,
    cameras: bool = False,
    n_threads: int | None = None,
) -> Viewpoints:
    """The admissible lattice of candidate viewpoints over ``world``'s flight band.

    Parameters
    ----------
    world : Terrain
        The surface the limits are judged on (the true surface, or S' for a start on S').
    constraints : Constraints
        Eq. 2's limits; their x-y bounds default to ``world``'s.
    settings : GreedySettings, optional
        Lattice spacing, heights and camera orientations.
    cameras : bool, default False
        Repeat every position for each ``(yaw, pitch)`` of ``settings``.
    n_threads : int, optional
        Threads for the admissibility check.

    Returns
    -------
    Viewpoints

    Raises
    ------
    InvalidInputError
        More than ``MAX_CANDIDATES`` candidates.
    InfeasibleError
        No admissible candidate.
    """
    if not isinstance(world, Terrain):
        raise InvalidTypeError(f"world must be a uavcov Terrain, got {type(world).__name__}")
    if not isinstance(constraints, Constraints):
        raise InvalidTypeError(f"constraints must be a Constraints, got {type(constraints).__name__}")
    settings = GreedySettings() if settings is None else settings
    if not isinstance(settings, GreedySettings):
        raise InvalidTypeError(f"settings must be a GreedySettings, got {type(settings).__name__}")
    if n_threads is not None:
        as_positive_int(n_threads, "n_threads")
    limits = constraints.resolve(world)
    xmin, ymin, xmax, ymax = limits.flight_box
    s = settings.spacing
    columns = [math.floor((hi - lo) / s + 1e-9) + 1 for lo, hi in ((xmin, xmax), (ymin, ymax))]
    orientations = len(settings.yaws) * len(settings.pitches) if as_bool(cameras, "cameras") else 1
    total = columns[0] * columns[1] * settings.n_heights * orientations
    if total > MAX_CANDIDATES:
        raise InvalidInputError(
            f"{columns[0]} x {columns[1]} columns x {settings.n_heights} heights x {orientations} orientations = {total:,} "
            f"candidates, more than {MAX_CANDIDATES:,}: use a larger spacing"
        )
    gx, gy = np.meshgrid(xmin + s * np.arange(columns[0]), ymin + s * np.arange(columns[1]))
    xy = np.column_stack([gx.ravel(), gy.ravel()])
    ground = world.ground_height(xy, n_threads=n_threads)
    keep = np.isfinite(ground)
    xy, ground = xy[keep], ground[keep]
    # the band's ends moved in by _BAND_INSET, so the exact checks never refuse them on round-off
    low = ground + limits.h_min + _BAND_INSET
    top = np.minimum(ground + limits.h_max, limits.z_max) if limits.h_max is not None else np.full_like(ground, limits.z_max)
    high = top - _BAND_INSET
    fraction = np.linspace(0.0, 1.0, settings.n_heights) if settings.n_heights > 1 else np.zeros(1)
    z = low[:, None] + fraction[None, :] * (high - low)[:, None]
    points = np.column_stack([np.repeat(xy, settings.n_heights, axis=0), z.ravel()])
    points = points[np.repeat(high >= low, settings.n_heights)]
    if points.shape[0]:
        points = _admissible_alone(limits, world, points, n_threads)
    if points.shape[0] == 0:
        raise InfeasibleError("no lattice point is admissible: the flight band is empty, or the spacing misses it")
    heights = f"{settings.n_heights} height{'s' if settings.n_heights > 1 else ''}"
    description = f"{points.shape[0]} admissible points of a {s:g} m x-y lattice x {heights} over the flight band"
    poses = None
    if cameras:
        angles = np.array([(yaw, pitch) for yaw in settings.yaws for pitch in settings.pitches], dtype=np.float64)
        poses = np.column_stack([np.repeat(points, len(angles), axis=0), np.tile(angles, (points.shape[0], 1))])
        points = poses[:, :3].copy()
        description += f", each with {len(angles)} camera orientation{'s' if len(angles) > 1 else ''}"
    return Viewpoints(
        positions=read_only(np.ascontiguousarray(points)),
        poses=None if poses is None else read_only(poses),
        source="lattice",
        description=description,
    )


def viewpoint_offsets(
    world: Terrain,
    constraints: Constraints,
    distances: Any,
    *,
    spacing: float = 5.0,
    n_threads: int | None = None,
) -> Viewpoints:
    """Candidate viewpoints around a structure: points of ``world`` about ``spacing`` apart, each
    flown out along the outward normal there by every one of ``distances``.

    The structures' counterpart of :func:`viewpoint_lattice`: under a bridge deck the normal
    points down, beside a pier sideways, so the candidates reach where no lattice over a height
    band goes. Only the admissible ones are kept, each judged alone where it is
    (``uavcov.limits.feasibility``; with ``Constraints(clearance="standoff")`` the
    distances should be at least ``h_min``).

    Parameters
    ----------
    world : Terrain
        The surface (a structure's mesh, faces wound counter-clockwise seen from outside).
    constraints : Constraints
    distances : sequence of float
        Offsets along the normal, metres (> 0).
    spacing : float, default 5.0
        About how far apart the surface points are, metres (one per ``spacing**2`` m^2).
    n_threads : int, optional

    Returns
    -------
    Viewpoints
        ``source="normal offsets"``.

    Raises
    ------
    InvalidInputError
        No distance, a distance not finite or <= 0, or more than ``MAX_CANDIDATES``.
    InfeasibleError
        No candidate is admissible.
    """
    if not isinstance(world, Terrain):
        raise InvalidTypeError(f"world must be a uavcov.Terrain, got {type(world).__name__}")
    if not isinstance(constraints, Constraints):
        raise InvalidTypeError(f"constraints must be a Constraints, got {type(constraints).__name__}")
    offsets = as_float_array(distances, "distances", ndim=1) if not isinstance(distances, (str, bytes)) else None
    if offsets is None or offsets.size == 0 or not np.all(np.isfinite(offsets)) or np.any(offsets <= 0.0):
        raise InvalidInputError(f"distances must be a non-empty sequence of finite offsets > 0 m, got {distances!r}")
    spacing = as_positive_float(spacing, "spacing")
    if not 0.0 < spacing * spacing < math.inf:  # the surface points' density is 1 / spacing**2
        raise InvalidInputError(f"spacing must have a finite, non-zero square, got {spacing}")
    if world.area / spacing**2 * offsets.size > MAX_CANDIDATES:
        raise InvalidInputError(
            f"about {world.area / spacing**2 * offsets.size:,.0f} candidates, more than {MAX_CANDIDATES:,}: use a larger spacing"
        )
    limits = constraints.resolve(world)
    on_surface, normals = surface_normals(world, world.default_targets(density=1.0 / spacing**2).points)
    points = (on_surface[None, :, :] + offsets[:, None, None] * normals[None, :, :]).reshape(-1, 3)
    points = _admissible_alone(limits, world, points, n_threads)
    if points.shape[0] == 0:
        raise InfeasibleError("no normal offset is admissible: the distances miss the flight limits")
    return Viewpoints(
        positions=read_only(np.ascontiguousarray(points)),
        poses=None,
        source="normal offsets",
        description=f"{points.shape[0]} admissible normal offsets ({', '.join(f'{d:g}' for d in offsets)} m) of points {spacing:g} m apart",
    )


def as_viewpoints(value: Any) -> Viewpoints:
    """``value`` as :class:`Viewpoints`: itself, or an ``(C, 3)`` / ``(C, 5)`` array of given candidates."""
    if isinstance(value, Viewpoints):
        return value
    if isinstance(value, (str, bytes)):
        raise InvalidInputError(f"candidates must be Viewpoints or an (C, 3) or (C, 5) array, got {value!r}")
    array = as_float_array(value, "candidates", ndim=2)
    if array.shape[1] not in (3, 5) or array.shape[0] == 0:
        raise InvalidInputError(f"candidates must be Viewpoints or an (C, 3) or (C, 5) array, got shape {array.shape}")
    if array.shape[0] > MAX_CANDIDATES:
        raise InvalidInputError(f"{array.shape[0]:,} candidates, more than {MAX_CANDIDATES:,}")
    poses = read_only(array.copy()) if array.shape[1] == 5 else None
    return Viewpoints(read_only(np.ascontiguousarray(array[:, :3])), poses, "given", f"{array.shape[0]} given candidates")
