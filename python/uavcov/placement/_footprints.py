"""A camera start: each UAV's height (and free angles) chosen so its footprint is its Voronoi cell.

The paper's start places generators on the approximating surface S' and flies them there; with
an omnidirectional sensor of range ``d_max`` the height hardly matters. A camera sees a footprint
that grows with height and tilts with pitch, so the same generators cover their cells well only at
the right height: too low and the footprint leaves most of the cell unseen, too high and it spills
over the neighbours' cells while the frustum's slant range runs out. The paper names this next
step itself ("new metrics ... for the Voronoi tessellation").

:func:`fit_footprints` keeps each generator's cell (the S' targets nearest to it in x-y) and picks,
for each UAV on its own, the pose whose view of S' (range, frustum and occlusion, by
:class:`~uavcov.engine.Visibility` on S') best matches the cell: the largest weighted Jaccard
index ``w(seen & cell) / w(seen | cell)``. It searches heights within the flight band above S',
the gimbal's pitch range where the pitch is free, and, where the heading is free, the cell's two
principal axes (both ways for an oblique camera). An oblique UAV is moved back along its heading
so that its optical axis meets S' near its generator. Only S' is used: the real surface is not
known before the flight, and the mission then lifts each UAV to its closest admissible position.

Examples
--------
>>> import numpy as np, uavcov
>>> flat = uavcov.Terrain.from_grid(np.zeros((121, 121)), spacing=1.0)
>>> camera = uavcov.Sensor(100.0, camera=uavcov.Camera.from_fov(60.0, 60.0))
>>> starts = np.array([[30.0, 30.0, 2.0], [90.0, 30.0, 2.0], [30.0, 90.0, 2.0], [90.0, 90.0, 2.0]])
>>> fit = fit_footprints(flat, starts, camera, [[0.0, -90.0]] * 4, heights=(10.0, 80.0), n_heights=15)
>>> fit.positions[:, 2].tolist()  # 60 m cells; a 60 deg footprint is 1.15 h wide: 63 m at 55 m up
[55.0, 55.0, 55.0, 55.0]
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from .._validate import as_bounds, as_float_array, as_points, as_positive_int
from ..engine import Gimbal, Sensor, Terrain, Visibility
from ..errors import InvalidInputError, InvalidTypeError

_MAX_HEIGHT = 1e6
"""The highest height above S' :func:`fit_footprints` searches, metres (far beyond any camera's use)."""
_MAX_POSES_PER_UAV = 10_000
"""Most heights x pitches :func:`fit_footprints` tries per UAV (each heading counts once more)."""


@dataclass(frozen=True, eq=False)
class FootprintFit:
    """The poses :func:`fit_footprints` chose.

    Attributes
    ----------
    positions : (N, 3) float64
        Metres; x-y is the generator's, or behind it along the heading for an oblique camera.
    attitudes : (N, 2) float64
        ``(yaw, pitch)`` in degrees.
    match : (N,) float64
        Each UAV's weighted Jaccard index between what it sees of S' and its cell, in [0, 1]
        (NaN for a UAV without a camera, left where it was).
    """

    positions: np.ndarray
    attitudes: np.ndarray
    match: np.ndarray


def _principal_yaw(points: np.ndarray, weights: np.ndarray) -> float:
    """Compass heading (degrees) of the cell's long axis in x-y (0 when the cell is round or empty)."""
    if points.shape[0] < 2 or weights.sum() <= 0.0:
        return 0.0
    centre = np.average(points, axis=0, weights=weights)
    d = points - centre
    cov = (d * weights[:, None]).T @ d
    values, vectors = np.linalg.eigh(cov)
    east, north = vectors[:, int(np.argmax(values))]
    return math.degrees(math.atan2(east, north)) % 360.0  # compass: clockwise from north (+y)


def _pose_facing(
    surface: Terrain,
    generator: np.ndarray,
    height: float,
    yaw: float,
    pitch: float,
    d_max: float,
    bounds: tuple[float, float, float, float],
    n_threads: int | None,
) -> np.ndarray | None:
    """``(1, 5)`` pose ``height`` above S' whose camera axis meets ``generator``, or ``None`` over nodata."""
    xy = generator[:2].copy()
    if pitch > -89.9:  # an oblique camera looks ahead: stand back so its axis meets the cell's generator
        back = height / math.tan(math.radians(-pitch)) if pitch < 0.0 else 0.0
        back = min(back, d_max)
        heading = math.radians(yaw)
        xy -= back * np.array([math.sin(heading), math.cos(heading)])
        xy = np.clip(xy, [bounds[0], bounds[1]], [bounds[2], bounds[3]])
    ground = surface.ground_height(xy[None], n_threads=n_threads)[0]
    if not np.isfinite(ground):
        return None
    return np.array([[xy[0], xy[1], ground + height, yaw, pitch]])


def fit_footprints(
    surface: Terrain,
    generators: Any,
    sensor: Sensor | Sequence[Sensor],
    attitudes: Any,
    *,
    heights: tuple[float, float],
    gimbal: Gimbal | None = None,
    bounds: tuple[float, float, float, float] | None = None,
    n_heights: int = 12,
    n_pitches: int = 7,
    n_threads: int | None = None,
) -> FootprintFit:
    """Pick each UAV's height above S' (and its free angles) so its camera sees its Voronoi cell.

    Parameters
    ----------
    surface : Terrain
        S', the surface known before the flight; its default targets define the cells.
    generators : (N, 3) array_like
        The start's positions (CVT generators or any start), metres; their x-y define the cells.
    sensor : Sensor or sequence of Sensor
        Every UAV's sensor, or one per UAV; a UAV without a camera keeps its position and
        angles (its ``match`` is NaN), and at least one must have a camera.
    attitudes : (N, 2) array_like
        ``(yaw, pitch)`` degrees: the angles a fixed gimbal keeps, and where a free angle starts.
    heights : (float, float)
        Lowest and highest height above S', metres (the flight band; ``0 < lowest <= highest``).
    gimbal : Gimbal, optional
        Which angles are free: a free pitch is searched over its ``pitch_range``, a free heading
        over the cell's principal axes. ``None``: both fixed.
    bounds : (xmin, ymin, xmax, ymax), optional
        Where a UAV moved back along its heading may stand; default S''s x-y bounds.
    n_heights, n_pitches : int
        Heights (evenly spaced over the band) and pitches (over ``pitch_range``) tried.
    n_threads : int, optional
        Threads of each visibility query.

    Returns
    -------
    FootprintFit

    Raises
    ------
    InvalidInputError, InvalidTypeError
        A sensor without a camera, bad shapes or bands.
    """
    if not isinstance(surface, Terrain):
        raise InvalidTypeError(f"surface must be a uavcov.Terrain, got {type(surface).__name__}")
    team = [sensor] if isinstance(sensor, Sensor) else list(sensor) if isinstance(sensor, (list, tuple)) else None
    if team is None or not all(isinstance(s, Sensor) for s in team):
        raise InvalidTypeError(f"sensor must be a uavcov.Sensor or a sequence of them, got {type(sensor).__name__}")
    if all(s.camera is None for s in team):
        raise InvalidInputError("fitting footprints needs a sensor with a camera (an omnidirectional sensor has none)")
    if gimbal is not None and not isinstance(gimbal, Gimbal):
        raise InvalidTypeError(f"gimbal must be a uavcov.Gimbal or None, got {type(gimbal).__name__}")
    points = as_points(generators, "generators")
    n = points.shape[0]
    if len(team) == 1:
        team = team * n
    if len(team) != n:
        raise InvalidInputError(f"{len(team)} sensors for {n} generators: give one per UAV, or one for all")
    angles = as_float_array(attitudes, "attitudes")
    if angles.shape != (n, 2):
        raise InvalidInputError(f"attitudes must have shape ({n}, 2) (yaw, pitch per UAV), got {angles.shape}")
    band = as_float_array(heights, "heights")
    if band.shape != (2,) or not 0.0 < band[0] <= band[1]:
        raise InvalidInputError(f"heights must be (lowest, highest) with 0 < lowest <= highest, got {heights!r}")
    if band[1] > _MAX_HEIGHT:
        raise InvalidInputError(f"heights above S' of {band[1]:g} m are beyond the {_MAX_HEIGHT:g} m a camera start considers")
    n_heights = as_positive_int(n_heights, "n_heights")
    n_pitches = as_positive_int(n_pitches, "n_pitches")
    if n_heights * n_pitches > _MAX_POSES_PER_UAV:  # each is a visibility query: refuse a search that would not end
        raise InvalidInputError(f"n_heights x n_pitches = {n_heights * n_pitches:,} poses per UAV; at most {_MAX_POSES_PER_UAV:,}")
    if bounds is None:
        b = surface.bounds
        bounds = (float(b[0, 0]), float(b[0, 1]), float(b[1, 0]), float(b[1, 1]))
    else:  # checked even when no camera is oblique (only an oblique one stands back within them)
        bounds = as_bounds(bounds)

    vis = Visibility(surface, max(s.d_max for s in team), n_threads=n_threads)
    targets = vis.targets
    target_xy = np.asarray(targets.points)[:, :2]
    weights = np.asarray(targets.weights)
    cell_of = cKDTree(points[:, :2]).query(target_xy)[1]
    free_yaw = gimbal is not None and gimbal.free_yaw
    pitch_range = None if gimbal is None else gimbal.pitch_range
    height_options = np.linspace(band[0], band[1], n_heights)
    positions = points.copy()
    chosen = angles.copy()
    match = np.full(n, np.nan)
    for i in range(n):
        if team[i].camera is None:
            continue
        sensors: Sequence[Sensor] = [team[i]]
        cell = cell_of == i
        cell_weight = float(weights[cell].sum())
        pitches = np.linspace(pitch_range[0], pitch_range[1], n_pitches) if pitch_range is not None else angles[i, 1:2]
        axis = _principal_yaw(target_xy[cell], weights[cell])
        best = (-1.0, points[i].copy(), angles[i].copy())
        for pitch in np.unique(pitches):
            if free_yaw:
                turns = (0.0, 90.0, 180.0, 270.0) if pitch > -90.0 else (0.0, 90.0)
                yaws = [(axis + t) % 360.0 for t in turns]
            else:
                yaws = [float(angles[i, 0])]
            for yaw in yaws:
                for height in height_options:
                    pose = _pose_facing(surface, points[i], height, yaw, pitch, team[i].d_max, bounds, n_threads)
                    if pose is None:
                        continue
                    seen = vis.seen(pose, sensors=sensors)
                    union = cell_weight + float(weights[seen & ~cell].sum())
                    score = float(weights[seen & cell].sum()) / union if union > 0.0 else 0.0
                    if score > best[0] + 1e-12:
                        best = (score, pose[0, :3].copy(), np.array([yaw, pitch]))
        match[i], positions[i], chosen[i] = max(best[0], 0.0), best[1], best[2]
    return FootprintFit(positions=positions, attitudes=chosen, match=match)
