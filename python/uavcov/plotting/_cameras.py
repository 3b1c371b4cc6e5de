"""What a team of cameras sees, from above: coverage with each camera's footprint, and view quality.

:func:`plot_camera_views` draws two top views of a grid terrain side by side: the surface seen /
not seen with the outline of each UAV's footprint (what its camera sees, occlusion included) and
its heading, and the best view quality of every seen point (:meth:`uavcov.Visibility.quality`:
resolution against the sensor's GSD of full quality, times the cosine of the incidence).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..engine import Sensor, Terrain, Visibility, camera_axes, pack_sensors
from ..errors import InvalidInputError, InvalidTypeError
from ._canvas import SEEN_COLOUR, UNSEEN_COLOUR, _finish, _line, _matplotlib, _patch, check_output
from ._views import _grid_node_mask


def footprints(terrain: Terrain, poses: Any, sensors: Sequence[Sensor]) -> list[np.ndarray]:
    """Each UAV's footprint: the ``(K, 2)`` x-y outline (convex hull, metres) of the grid points
    its own sensor sees, occlusion included; ``(0, 2)`` when it sees fewer than three."""
    positions, _ = pack_sensors(sensors, poses)
    poses_array = np.asarray(poses, dtype=np.float64)
    vis = Visibility(terrain, max(s.reach_m for s in sensors))
    points = vis.targets.points
    return [_outline(points[vis.seen(poses_array[i : i + 1], sensors=[sensors[i]]), :2]) for i in range(positions.shape[0])]


def _outline(xy: np.ndarray) -> np.ndarray:
    """The convex hull ``(K, 2)`` of points ``(n, 2)``; ``(0, 2)`` when they span no area."""
    from scipy.spatial import ConvexHull

    if xy.shape[0] < 3 or np.linalg.matrix_rank(xy - xy.mean(axis=0)) < 2:
        return np.empty((0, 2))
    hull: np.ndarray = xy[ConvexHull(xy).vertices]
    return hull


def plot_camera_views(
    terrain: Terrain,
    poses: Any,
    sensors: Sequence[Sensor],
    *,
    out: Any = None,
    dpi: float = 110.0,
) -> Any:
    """Coverage with the cameras' footprints, and view quality, from above.

    Parameters
    ----------
    terrain : Terrain
        A grid terrain (:meth:`Terrain.from_grid`); its grid nodes are the targets.
    poses : (N, 5) array_like of float
        ``(x, y, z, yaw, pitch)`` per UAV (metres, degrees; see :mod:`uavcov.engine`); ``(N, 3)``
        when no sensor is a camera.
    sensors : sequence of Sensor
        One per UAV.
    out : path, optional
        Save the figure there.
    dpi : float
        Resolution of the saved file.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InvalidInputError
        A terrain that is not a grid, or poses and sensors that :func:`uavcov.engine.pack_sensors`
        refuses.
    """
    if not isinstance(terrain, Terrain):
        raise InvalidTypeError(f"terrain must be a uavcov.Terrain, got {type(terrain).__name__}")
    if terrain.grid is None:
        raise InvalidInputError("plot_camera_views draws grid terrains (Terrain.from_grid)")
    positions, _ = pack_sensors(sensors, poses)
    _, dpi = check_output(out, dpi)  # before the drawing: a dpi matplotlib cannot draw text at fails late
    poses_array = np.asarray(poses, dtype=np.float64)
    vis = Visibility(terrain, max(s.reach_m for s in sensors))
    points = vis.targets.points
    seen = vis.seen(poses_array, sensors=sensors)
    quality = vis.quality(poses_array, sensors=sensors)
    seen_grid = _grid_node_mask(terrain, seen, points)
    quality_grid = _grid_node_mask(terrain, np.where(seen, quality, np.nan), points)
    grid = terrain.grid
    (ox, oy), (dx, dy) = grid.origin, grid.spacing
    ny, nx = grid.shape
    extent = (ox - dx / 2, ox + (nx - 0.5) * dx, oy - dy / 2, oy + (ny - 0.5) * dy)

    mpl = _matplotlib()
    from matplotlib.figure import Figure

    fig = Figure(figsize=(12.5, 5.4), layout="constrained")
    left, right = fig.subplots(1, 2)
    rgb = np.where(np.isnan(seen_grid)[..., None], 1.0, np.where(seen_grid[..., None] > 0, SEEN_COLOUR, UNSEEN_COLOUR))
    left.imshow(rgb, extent=extent, origin="lower", interpolation="nearest")
    cmap = mpl.colormaps["viridis"].with_extremes(bad="0.85")
    image = right.imshow(
        np.ma.masked_invalid(quality_grid), extent=extent, origin="lower", interpolation="nearest", cmap=cmap, vmin=0.0, vmax=1.0
    )
    fig.colorbar(image, ax=right, shrink=0.85, label="best view quality (grey: not seen)")
    colours = mpl.colormaps["tab10"]
    outlines = footprints(terrain, poses_array, sensors)
    forward = np.zeros((positions.shape[0], 3))
    cameras = [i for i, s in enumerate(sensors) if s.camera is not None]
    if cameras:
        forward[cameras] = camera_axes(poses_array[cameras, 3], poses_array[cameras, 4])[0]
    arrow = 0.04 * max(extent[1] - extent[0], extent[3] - extent[2])
    for ax in (left, right):
        for i, outline in enumerate(outlines):
            colour = colours(i % 10)
            if outline.shape[0]:
                closed = np.vstack([outline, outline[:1]])
                ax.plot(closed[:, 0], closed[:, 1], color=colour, linewidth=1.2)
            ax.plot(positions[i, 0], positions[i, 1], marker="o", color=colour, markeredgecolor="black", markersize=6)
            horizontal = np.hypot(forward[i, 0], forward[i, 1])
            if horizontal > 1e-6:  # a heading to show (a nadir camera has none)
                ax.annotate(
                    "",
                    xy=(positions[i, 0] + arrow * forward[i, 0] / horizontal, positions[i, 1] + arrow * forward[i, 1] / horizontal),
                    xytext=(positions[i, 0], positions[i, 1]),
                    arrowprops={"arrowstyle": "->", "color": colour, "linewidth": 1.2},
                )
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_aspect("equal")
        ax.set_xlim(extent[0], extent[1])
        ax.set_ylim(extent[2], extent[3])
    left.set_title(f"Coverage {vis.coverage(poses_array, sensors=sensors):.3f} with {len(sensors)} sensor(s)", fontsize=10)
    right.set_title(f"Quality-weighted coverage {vis.quality_coverage(poses_array, sensors=sensors):.3f}", fontsize=10)
    handles = [_patch(SEEN_COLOUR, "seen"), _patch(UNSEEN_COLOUR, "not seen"), _line("footprint (what the camera sees)", color="0.2")]
    left.legend(handles=handles, fontsize=8, framealpha=0.9, loc="upper left")
    return _finish(fig, out, dpi)
