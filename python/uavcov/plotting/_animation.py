"""The animation of a mission: the top-view coverage map and the coverage curve, frame by frame.

A camera team's frames also outline each camera's footprint (what it sees, occlusion included)
and its heading, at every shown iteration: the footprints move as CAO moves the UAVs and turns
their gimbals.

Frames are drawn on one Agg canvas and handed as RGB arrays to the GIF or MP4 writer of
:mod:`uavcov.plotting._writers`.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

import numpy as np

from .._io import make_parent, refuse_what_is_no_file
from .._validate import as_positive_float, as_positive_int
from ..errors import InvalidInputError
from ._cameras import footprints
from ._canvas import (
    END_COLOUR,
    FOOTPRINT_COLOUR,
    INIT_COLOURS,
    SEEN_COLOUR,
    START_COLOUR,
    UNSEEN_COLOUR,
    _line,
    _marker,
    _matplotlib,
    _patch,
    check_output,
)
from ._inputs import _as_result, _curve, _d_max, _setting, _trajectory
from ._views import _TopView
from ._writers import _write_gif, _write_mp4

_MIN_FPS = 0.001  # frames a second: one frame every 1000 s is already a slide show


def _map_legend(ax: Any, quality: bool, *, footprint: bool) -> None:
    """The top view's legend, under it: seen (or the view quality), not seen, start, UAV, footprint."""
    ax.legend(
        handles=[
            _patch("#fde725" if quality else SEEN_COLOUR, "view quality 1 (viridis)" if quality else "seen"),
            _patch(UNSEEN_COLOUR, "not seen"),
            _marker("start", marker="o", color=START_COLOUR, markersize=4),
            _marker("UAV", marker="o", markerfacecolor=END_COLOUR, markeredgecolor="black", markersize=6),
            *([_line("footprint", color=FOOTPRINT_COLOUR)] if footprint else []),
        ],
        fontsize=7,
        loc="upper center",
        bbox_to_anchor=(0.5, -0.17),
        ncol=5 if footprint else 4,
        framealpha=0.9,
    )


def _curve_axes(ax: Any, curve: np.ndarray, quality: bool, colour: str) -> tuple[Any, Any]:
    """The coverage axes, sized for the whole ``curve``; returns its line and its current-iteration dot."""
    ax.set_xlim(0, max(1, curve.shape[0] - 1))
    low = float(curve.min())
    ax.set_ylim(max(0.0, low - 0.05), min(1.0, float(curve.max()) + 0.03) + 1e-3)
    ax.set_xlabel("iteration")
    ax.set_ylabel("quality-weighted coverage" if quality else "coverage")
    ax.grid(True, linewidth=0.4, alpha=0.5)
    line = ax.plot([], [], color=colour, linewidth=1.5)[0]
    dot = ax.plot([], [], "o", color="black", markersize=4)[0]
    return line, dot


def animate_mission(
    source: Any,
    out: Any,
    *,
    fps: float = 8.0,
    max_frames: int = 60,
    raster: int = 160,
    dpi: float = 80.0,
) -> Path:
    """An animation of a run: the top-view coverage map, the UAVs and their paths, the curve.

    Left: the surface from above coloured by what the team sees at each shown iteration, the
    UAVs (green) and their paths so far, and for cameras each one's footprint and heading (a
    run that maximised the quality-weighted coverage colours the map by the best view quality);
    right: the objective per iteration up to that point.

    Parameters
    ----------
    source : MissionResult or path to a saved run
    out : path
        ``.gif`` (written with Pillow) or ``.mp4`` (needs ``ffmpeg`` on the PATH).
    fps : float
        Frames per second.
    max_frames : int
        Most frames: iterations are evenly spaced, first and last always shown.
    raster : int
        Pixels on the longer side of the map.
    dpi : float
        Resolution of each frame.

    Returns
    -------
    Path
        The file written.
    """
    result = _as_result(source, ("terrain", "trajectory", "coverage", "settings"))
    out, dpi = check_output(out, dpi, required=True)
    assert out is not None  # required=True
    suffix = out.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise InvalidInputError(f"the animation is written as .gif or .mp4, got {out.name!r}")
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise InvalidInputError("writing .mp4 needs ffmpeg on the PATH; write a .gif instead")
    fps = as_positive_float(fps, "fps")
    if fps < _MIN_FPS:  # a subnormal fps made each frame last forever (an OverflowError in the GIF writer)
        raise InvalidInputError(f"fps must be at least {_MIN_FPS:g} (a frame every {1 / _MIN_FPS:g} s), got {fps:g}")
    traj = _trajectory(result.trajectory)
    curve = _curve(result.coverage)
    frames = np.unique(
        np.rint(np.linspace(0, traj.shape[0] - 1, min(as_positive_int(max_frames, "max_frames"), traj.shape[0]))).astype(int)
    )
    d = _d_max(result)
    view = _TopView(result.terrain, d, as_positive_int(raster, "raster"))
    spec = result.settings
    sensors = spec.team_sensors() if getattr(spec, "sensor", None) is not None else None
    attitudes = getattr(result, "attitudes", None) if sensors is not None and spec.has_camera else None

    def poses(k: int) -> np.ndarray:
        return traj[k] if attitudes is None else np.column_stack([traj[k], attitudes[k]])

    quality = _setting(result, "objective") == "quality" and sensors is not None  # colour by what the run maximised

    def picture_of(k: int) -> np.ndarray:
        if quality and sensors is not None:
            return view.quality_image(poses(k), sensors)
        return view.image(poses(k), sensors=sensors)

    _matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 4.6), dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    grid = fig.add_gridspec(1, 2, width_ratios=(1.15, 1.0), left=0.07, right=0.98, bottom=0.24, top=0.9, wspace=0.28)
    ax_map = fig.add_subplot(grid[0])
    ax_curve = fig.add_subplot(grid[1])
    picture = ax_map.imshow(picture_of(0), extent=view.extent, origin="lower", interpolation="nearest")
    ax_map.set_xlabel("x (m)")
    ax_map.set_ylabel("y (m)")
    ax_map.set_aspect("equal")
    ax_map.scatter(traj[0, :, 0], traj[0, :, 1], s=14, c=START_COLOUR, zorder=3)
    paths = [ax_map.plot([], [], color="0.1", linewidth=0.8)[0] for _ in range(traj.shape[1])]
    uavs = ax_map.scatter(traj[0, :, 0], traj[0, :, 1], s=36, c=[END_COLOUR], edgecolors="black", linewidths=0.6, zorder=4)
    outlines = (
        [ax_map.plot([], [], color=FOOTPRINT_COLOUR, linewidth=1.0, zorder=3)[0] for _ in range(traj.shape[1])]
        if attitudes is not None
        else []
    )
    headings = [ax_map.plot([], [], color="black", linewidth=1.0, zorder=4)[0] for _ in outlines]
    arrow = 0.05 * max(view.extent[1] - view.extent[0], view.extent[3] - view.extent[2])
    _map_legend(ax_map, quality, footprint=bool(outlines))
    line, dot = _curve_axes(ax_curve, curve, quality, INIT_COLOURS.get(_setting(result, "start") or "", "#1f77b4"))
    title = fig.suptitle("", fontsize=10)

    images = []
    for k in frames:
        picture.set_data(picture_of(k))
        if attitudes is not None and sensors is not None:
            for outline, heading, shape, (yaw, _), position in zip(
                outlines, headings, footprints(result.terrain, poses(k), sensors), attitudes[k], traj[k], strict=True
            ):
                closed = np.vstack([shape, shape[:1]]) if shape.shape[0] else shape
                outline.set_data(closed[:, 0], closed[:, 1])
                ahead = arrow * np.array([np.sin(np.radians(yaw)), np.cos(np.radians(yaw))])
                heading.set_data([position[0], position[0] + ahead[0]], [position[1], position[1] + ahead[1]])
        for i, p in enumerate(paths):
            p.set_data(traj[: k + 1, i, 0], traj[: k + 1, i, 1])
        uavs.set_offsets(traj[k, :, :2])
        line.set_data(np.arange(k + 1), curve[: k + 1])
        dot.set_data([k], [curve[k]])
        what = "quality-weighted coverage" if quality else "coverage"
        title.set_text(f"iteration {k} of {traj.shape[0] - 1}: {what} {curve[k]:.3f} (d_max = {d:g} m)")
        canvas.draw()
        images.append(np.asarray(canvas.buffer_rgba())[:, :, :3].copy())
    refuse_what_is_no_file(make_parent(out))
    if suffix == ".gif":
        _write_gif(images, out, fps)
    else:
        _write_mp4(images, out, fps)
    return Path(out)
