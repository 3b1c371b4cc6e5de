"""An interactive 3D view of a mission (plotly): turn the surface around, step through iterations.

:func:`view` returns a ``plotly.graph_objects.Figure`` (shown as is in a notebook):

- the true surface, coloured by what the team sees at the shown iteration: seen / not seen, or
  (a button) how many UAVs see each point;
- the UAVs at that iteration, their paths up to it, their start and best positions, the known
  points (the prior S' is built from) and, for cameras, each camera's footprint;
- a slider over iterations (at most ``max_frames`` of them, the best one always among them)
  and a play button.

:func:`write_view` writes it as one self-contained HTML file (plotly.js inlined: it opens with
no network); :func:`find_run` picks the run to show in a results or mission folder.

The surface is decimated for the view only (at most ``max_vertices`` vertices: every k-th grid
node, or a mesh clustered and put back on the surface); the colours are the engine's exact
visibility of the view's vertices, and every number shown (the coverage in the title) is the
run's own, measured on all its targets. plotly is the optional extra ``uavcov[view]``, imported
on use.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_write
from .._validate import as_optional_str, as_path, is_int
from ..engine import Sensor, Targets, Terrain, Visibility
from ..errors import InvalidInputError, MissingExtraError, ResultsFormatError
from ..sim import is_flown_file, load_flown
from ._cameras import _outline
from ._canvas import END_COLOUR, FOOTPRINT_COLOUR, SEEN_COLOUR, UNSEEN_COLOUR
from ._directory import _stored_runs
from ._inputs import _as_result, _d_max, _sight, _trajectory
from ._views import _cluster, _node_index

DEFAULT_MAX_VERTICES = 40_000
"""Vertices of the drawn surface, at most (a 200 x 200 grid): enough to read a 1 m terrain of
100 m x 100 m node by node, and an HTML file of a few MB."""
DEFAULT_MAX_FRAMES = 60
"""Iterations the slider offers, at most (evenly spaced, the first, the last and the best)."""

_NEEDS = ("terrain", "trajectory", "coverage", "settings", "start_positions", "best_positions", "best_iteration")


def _plotly() -> Any:
    """Import plotly's graph objects, or say which extra provides them."""
    try:
        import plotly.graph_objects as go
    except ImportError as exc:
        raise MissingExtraError("uavcov's interactive view needs plotly, the optional extra: pip install 'uavcov[view]'") from exc
    return go


def _rgb(colour: Sequence[float]) -> str:
    return "rgb({},{},{})".format(*(round(255 * c) for c in colour))


def _view_surface(terrain: Terrain, max_vertices: int) -> tuple[np.ndarray, np.ndarray]:
    """At most ``max_vertices`` points of the surface, ``(V, 3)`` metres, and triangles ``(F, 3)``.

    A grid keeps every ``stride``-th node (and the border) and is cut along the terrain's own
    diagonal; nodata nodes and the triangles touching them are left out. A mesh with more
    vertices is clustered until few enough remain, and each vertex is put back on the surface.
    """
    grid = terrain.grid
    if grid is not None:
        ny, nx = grid.shape
        stride = max(1, math.ceil(math.sqrt(ny * nx / max_vertices)))
        rows, cols = _node_index(ny, stride), _node_index(nx, stride)
        while rows.size * cols.size > max_vertices:  # the border lines kept may add one too many
            stride += 1
            rows, cols = _node_index(ny, stride), _node_index(nx, stride)
        xs, ys = grid.node_xy()
        gx, gy = np.meshgrid(xs[cols], ys[rows])
        z = np.asarray(grid.z)[np.ix_(rows, cols)]
        vertices = np.column_stack([gx.ravel(), gy.ravel(), z.ravel()])
        index = np.arange(vertices.shape[0]).reshape(rows.size, cols.size)
        a, b, c, d = index[:-1, :-1], index[:-1, 1:], index[1:, 1:], index[1:, :-1]
        faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
        valid = np.isfinite(vertices[:, 2])
        faces = faces[valid[faces].all(axis=1)]
        renumber = np.cumsum(valid) - 1
        return vertices[valid], renumber[faces]
    vertices, faces = np.asarray(terrain.vertices), np.asarray(terrain.faces)
    if vertices.shape[0] <= max_vertices:
        return vertices, faces
    extent = float(np.ptp(vertices, axis=0).max())
    cell = max(extent / math.sqrt(max_vertices), 1e-9 * extent)
    while True:
        merged, merged_faces = _cluster(vertices, faces, cell)
        if merged.shape[0] <= max_vertices and merged_faces.shape[0] > 0:
            return terrain.closest_point(merged), merged_faces
        if merged_faces.shape[0] == 0:
            raise InvalidInputError("the mesh could not be decimated for the view; raise max_vertices")
        cell *= 1.3


def _frames(n_iterations: int, best: int, max_frames: int) -> np.ndarray:
    """The iterations the slider offers: evenly spaced, with the first, the last and the best."""
    count = min(max_frames, n_iterations)
    chosen = np.rint(np.linspace(0, n_iterations - 1, count)).astype(np.int64)
    return np.unique(np.r_[chosen, min(max(best, 0), n_iterations - 1)])


def _seen_by_each(vis: Visibility, poses: np.ndarray, sensors: Sequence[Sensor] | None) -> np.ndarray:
    """``(N, V)`` bool: which of the view's points each UAV sees (its own sensor, occlusion included)."""
    return np.stack([vis.seen(poses[i : i + 1], sensors=None if sensors is None else [sensors[i]]) for i in range(poses.shape[0])])


def _lines(paths: Sequence[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Polylines ``(k, 3)`` as one x, y, z series with a NaN gap between them (one plotly trace).

    float32: frames repeat the paths, and a millimetre is finer than any view shows."""
    if not paths:
        return np.empty(0, np.float32), np.empty(0, np.float32), np.empty(0, np.float32)
    gap = np.full((1, 3), np.nan)
    joined = np.concatenate([part for p in paths for part in (p, gap)][:-1]).astype(np.float32)
    return joined[:, 0], joined[:, 1], joined[:, 2]


def _footprint_lines(terrain: Terrain, points: np.ndarray, seen: np.ndarray, lift: float) -> list[np.ndarray]:
    """Each camera's footprint as a closed outline ``(k, 3)`` just above the ground."""
    outlines = []
    for mask in seen:
        xy = _outline(points[mask, :2])
        if xy.shape[0] == 0:
            continue
        xy = np.vstack([xy, xy[:1]])
        outlines.append(np.column_stack([xy, terrain.ground_height(xy) + lift]))
    return outlines


def _count_scale(n_uavs: int) -> list[list[Any]]:
    """A stepped colour scale over 0..n_uavs: 0 is the unseen colour, then one band per count."""
    from plotly.colors import sample_colorscale

    colours = [_rgb(UNSEEN_COLOUR), *sample_colorscale("Plasma", [0.15 + 0.8 * k / max(1, n_uavs - 1) for k in range(n_uavs)])]
    scale: list[list[Any]] = []
    for k, colour in enumerate(colours):
        scale += [[k / (n_uavs + 1), colour], [(k + 1) / (n_uavs + 1), colour]]
    return scale


def view(result: Any, *, max_vertices: int = DEFAULT_MAX_VERTICES, max_frames: int = DEFAULT_MAX_FRAMES) -> Any:
    """An interactive 3D view of a mission, as a plotly figure.

    Parameters
    ----------
    result : MissionResult, FlownRun or path
        A mission's result, or the ``.npz`` of one saved by :func:`uavcov.records.save_mission`;
        or a flown mission (:class:`uavcov.sim.FlownRun`, the ``.npz`` of
        :func:`uavcov.sim.save_flown`: what ``uavcov reproduce realistic`` writes in ``states/``),
        whose paths are the simulated states flown, the UAVs where they measured.
    max_vertices : int, optional
        Vertices of the drawn surface, at most (default 40 000); a larger surface is decimated
        for the view only.
    max_frames : int, optional
        Iterations offered by the slider, at most (default 60; at least 2).

    Returns
    -------
    plotly.graph_objects.Figure
        Traces, in this order: the surface (``intensity``: how many UAVs see each vertex at the
        shown iteration), the paths so far, the UAVs, the starts, the best positions, the known
        points, and with cameras their footprints. It opens at the best iteration; one frame per
        offered iteration (named by it) updates the surface, paths, UAVs and footprints.

    Raises
    ------
    ResultsFormatError
        The result (or the file) is not a complete mission result.
    InvalidInputError
        ``max_vertices`` below 16 or ``max_frames`` below 2.
    MissingExtraError
        plotly is not installed (the ``uavcov[view]`` extra).
    """
    result, traj, curve = _checked(result, max_vertices, max_frames)
    go = _plotly()
    flown = _flown_paths(result)
    paths_name = "paths so far" if flown is None else "flown paths so far (the simulated states)"
    terrain: Terrain = result.terrain
    n_uavs = traj.shape[1]
    best_iteration = int(result.best_iteration)
    points, faces = _view_surface(terrain, int(max_vertices))
    _, sensors = _sight(result, traj[0], 0)
    reach = max(s.reach_m for s in sensors) if sensors is not None else _d_max(result)
    vis = Visibility(terrain, reach, Targets.from_points(points))
    cameras = bool(getattr(result.settings, "has_camera", False))
    bounds = np.asarray(terrain.bounds)
    lift = 0.005 * float(np.ptp(bounds[:, :2], axis=0).max())  # footprints float just above the ground

    def frame_traces(k: int) -> tuple[list[Any], str]:
        poses, frame_sensors = _sight(result, traj[k], k)
        seen = _seen_by_each(vis, poses, frame_sensors)
        best = f"best {float(result.best_coverage):.3f} at iteration {best_iteration}"
        title = f"iteration {k} of {traj.shape[0] - 1}: coverage {curve[k]:.3f} ({best})"
        x, y, z = _lines(_paths_until(traj, flown, k))
        traces = [
            # Counts as the smallest integers that hold them: each frame stores one per vertex.
            go.Mesh3d(intensity=seen.sum(axis=0).astype(np.uint8 if n_uavs < 256 else np.uint16)),
            go.Scatter3d(x=x, y=y, z=z),
            go.Scatter3d(x=traj[k, :, 0], y=traj[k, :, 1], z=traj[k, :, 2]),
        ]
        if cameras:
            fx, fy, fz = _lines(_footprint_lines(terrain, points, seen, lift))
            traces.append(go.Scatter3d(x=fx, y=fy, z=fz))
        return traces, title

    shown = _frames(traj.shape[0], best_iteration, int(max_frames))
    frames, titles = [], {}
    for k in shown:
        traces, titles[int(k)] = frame_traces(int(k))
        frames.append(
            go.Frame(
                data=traces, traces=[0, 1, 2, 6] if cameras else [0, 1, 2], name=str(int(k)), layout={"title": {"text": titles[int(k)]}}
            )
        )
    first = frames[int(np.searchsorted(shown, best_iteration))]
    seen_scale = [[0.0, _rgb(UNSEEN_COLOUR)], [0.5, _rgb(UNSEEN_COLOUR)], [0.5, _rgb(SEEN_COLOUR)], [1.0, _rgb(SEEN_COLOUR)]]
    surface = _surface_mesh(go, points, faces, first.data[0].intensity, seen_scale)
    start, best = np.asarray(result.start_positions), np.asarray(result.best_positions)
    known = np.asarray(getattr(result, "prior_points", np.empty((0, 3))), dtype=np.float64).reshape(-1, 3)
    data = [
        surface,
        go.Scatter3d(first.data[1], mode="lines", line={"color": "rgb(25,25,25)", "width": 3}, name=paths_name, hoverinfo="skip"),
        go.Scatter3d(
            first.data[2],
            mode="markers+text",
            text=[f"UAV {i + 1}" for i in range(n_uavs)],
            textposition="top center",
            marker={"size": 5, "color": "rgb(20,20,20)", "symbol": "circle"},
            name="UAVs at the shown iteration",
        ),
    ]

    def markers(points: np.ndarray, name: str, **style: Any) -> Any:
        return go.Scatter3d(x=points[:, 0], y=points[:, 1], z=points[:, 2], mode="markers", name=name, **style)

    data += [
        markers(start, "start", marker={"size": 4, "color": "rgb(0,0,0)", "symbol": "square-open"}),
        markers(best, f"best (iteration {best_iteration})", marker={"size": 5, "color": _rgb(END_COLOUR), "symbol": "diamond"}),
        markers(known, "known points", marker={"size": 2.5, "color": "rgb(31,119,180)"}, visible="legendonly"),
    ]
    if cameras:
        data.append(
            go.Scatter3d(
                first.data[3], mode="lines", line={"color": FOOTPRINT_COLOUR, "width": 4}, name="camera footprints", hoverinfo="skip"
            )
        )
    # Last, so the traces the frames update keep their places.
    data += _surface_key(go)
    fig = go.Figure(data=data, frames=frames)
    fig.update_layout(
        title={"text": titles[best_iteration], "x": 0.01, "font": {"size": 14}},
        margin={"l": 0, "r": 0, "t": 40, "b": 0},
        legend={"x": 0.01, "y": 0.92, "bgcolor": "rgba(255,255,255,0.7)"},
        scene=_scene(bounds),
        **_controls(shown, best_iteration, seen_scale, n_uavs),
    )
    return fig


def _checked(result: Any, max_vertices: Any, max_frames: Any) -> tuple[Any, np.ndarray, np.ndarray]:
    """The view's arguments checked: the result (read from its file: a mission's, or a flown
    mission's whose states are drawn), its trajectory and its coverage curve."""
    if not is_int(max_vertices) or max_vertices < 16:
        raise InvalidInputError(f"max_vertices must be an integer >= 16, got {max_vertices!r}")
    if not is_int(max_frames) or max_frames < 2:
        raise InvalidInputError(f"max_frames must be an integer >= 2, got {max_frames!r}")
    if isinstance(result, (str, os.PathLike)) and is_flown_file(result):
        result = load_flown(result)
    result = _as_result(result, _NEEDS)
    traj = _trajectory(result.trajectory)
    curve = np.asarray(result.coverage, dtype=np.float64)
    if curve.shape[0] != traj.shape[0]:
        raise ResultsFormatError(f"the coverage curve has {curve.shape[0]} values for {traj.shape[0]} positions of the trajectory")
    return result, traj, curve


def _paths_until(traj: np.ndarray, flown: tuple[tuple[np.ndarray, np.ndarray], np.ndarray] | None, k: int) -> list[np.ndarray]:
    """Each UAV's path up to iteration ``k``: its waypoints, or for a flown run the states flown
    until the measurement at iteration ``k``."""
    if flown is None:
        return [traj[: k + 1, i] for i in range(traj.shape[1])]
    (times, states), measured_at = flown
    upto = int(np.searchsorted(times, measured_at[k], side="right"))
    return [np.vstack([traj[0, i], states[:upto, i]]) for i in range(traj.shape[1])]


_FLOWN_POINTS_PER_UAV = 1500  # states drawn per UAV, at most: a 200-iteration run's page is about 10 MB


def _flown_paths(result: Any) -> tuple[tuple[np.ndarray, np.ndarray], np.ndarray] | None:
    """For a flown run (:class:`uavcov.sim.FlownRun`): ``((times, states), measured_at_s)``, the
    states thinned evenly to at most :data:`_FLOWN_POINTS_PER_UAV` (every measurement's own state
    kept, so each frame's path ends where the UAVs are); None for a kinematic run."""
    states = getattr(result, "flown_states", None)
    if states is None:
        return None
    times = np.asarray(result.flown_time, dtype=np.float64)
    measured_at = np.asarray(result.measured_at_s, dtype=np.float64)
    states = np.asarray(states, dtype=np.float64)
    if states.ndim != 3 or times.shape != (states.shape[0],) or measured_at.shape != (np.asarray(result.coverage).shape[0],):
        raise ResultsFormatError("the flown run's states, their times and its measurements do not match")
    keep = np.unique(np.r_[np.linspace(0, max(len(times) - 1, 0), min(len(times), _FLOWN_POINTS_PER_UAV)).astype(np.int64),
                           np.clip(np.searchsorted(times, measured_at) , 0, max(len(times) - 1, 0))])  # fmt: skip
    if not len(times):
        keep = np.empty(0, np.int64)
    return (times[keep], states[keep]), measured_at


def _surface_mesh(go: Any, points: np.ndarray, faces: np.ndarray, intensity: np.ndarray, seen_scale: list[list[Any]]) -> Any:
    """The surface, its vertices coloured by ``intensity`` on ``seen_scale``."""
    return go.Mesh3d(
        x=points[:, 0],
        y=points[:, 1],
        z=points[:, 2],
        i=faces[:, 0],
        j=faces[:, 1],
        k=faces[:, 2],
        intensity=intensity,
        intensitymode="vertex",
        colorscale=seen_scale,
        cmin=0.0,
        cmax=1.0,
        showscale=False,
        flatshading=False,
        lighting={"ambient": 0.55, "diffuse": 0.7, "specular": 0.05, "roughness": 0.9},
        lightposition={"x": -5e4, "y": -5e4, "z": 1e5},
        name="surface",
        hoverinfo="x+y+z",
    )


def _surface_key(go: Any) -> list[Any]:
    """The key to the surface's colours: two legend entries that draw nothing (plotly's legend
    has no entry for a mesh's colours)."""
    return [
        go.Scatter3d(
            x=[None], y=[None], z=[None], mode="markers", name=label, hoverinfo="skip",
            marker={"size": 10, "color": _rgb(colour), "symbol": "square", "line": {"color": "rgb(80,80,80)", "width": 1}},
        )
        for colour, label in ((SEEN_COLOUR, "surface: seen"), (UNSEEN_COLOUR, "surface: not seen"))
    ]  # fmt: skip


def _scene(bounds: np.ndarray) -> dict[str, Any]:
    """The 3D axes: metres, true to scale unless the site is too flat to read."""
    span = np.ptp(bounds, axis=0)
    relief = float(span[2]) / max(float(span[:2].max()), 1e-9)
    scene: dict[str, Any] = {
        # Above the slider, and seen from far enough that the near corner stays in the frame.
        "domain": {"x": [0.0, 1.0], "y": [0.12, 0.94]},
        "camera": {"eye": {"x": 1.45, "y": 1.45, "z": 1.05}, "center": {"x": 0.0, "y": 0.0, "z": -0.12}},
        "xaxis": {"title": {"text": "x (m)"}},
        "yaxis": {"title": {"text": "y (m)"}},
        "zaxis": {"title": {"text": "z (m)"}},
        # Flat sites (a DEM km wide, 100 m of relief) keep some height to read.
        **(
            {"aspectmode": "data"}
            if relief >= 0.15
            else {"aspectmode": "manual", "aspectratio": {"x": span[0] / span[:2].max(), "y": span[1] / span[:2].max(), "z": 0.3}}
        ),
    }
    return scene


def _controls(shown: np.ndarray, best_iteration: int, seen_scale: list[list[Any]], n_uavs: int) -> dict[str, Any]:
    """The iteration slider, play and pause, and the switch between seen and how many UAVs see it."""
    step = {"mode": "immediate", "frame": {"duration": 0, "redraw": True}, "transition": {"duration": 0}}
    return {
        "sliders": [
            {
                "active": int(np.searchsorted(shown, best_iteration)),
                "currentvalue": {"prefix": "iteration "},
                "pad": {"t": 30},
                "steps": [{"label": str(int(k)), "method": "animate", "args": [[str(int(k))], step]} for k in shown],
            }
        ],
        "updatemenus": [
            {
                "type": "buttons",
                "direction": "left",
                "x": 0.01,
                "y": 0.02,
                "xanchor": "left",
                "buttons": [
                    {
                        "label": "play",
                        "method": "animate",
                        "args": [None, {**step, "frame": {"duration": 150, "redraw": True}, "fromcurrent": True}],
                    },
                    {"label": "pause", "method": "animate", "args": [[None], step]},
                ],
            },
            {
                "type": "buttons",
                "direction": "left",
                "x": 0.99,
                "y": 0.98,
                "xanchor": "right",
                "buttons": [
                    {
                        "label": "seen",
                        "method": "restyle",
                        "args": [{"colorscale": [seen_scale], "cmin": [0.0], "cmax": [1.0], "showscale": [False]}, [0]],
                    },
                    {
                        "label": "how many UAVs see it",
                        "method": "restyle",
                        "args": [
                            {
                                "colorscale": [_count_scale(n_uavs)],
                                "cmin": [-0.5],
                                "cmax": [n_uavs + 0.5],
                                "showscale": [True],
                                "colorbar.title.text": ["UAVs"],
                            },
                            [0],
                        ],
                    },
                ],
            },
        ],
    }


def write_view(result: Any, out: str | os.PathLike[str], **options: Any) -> Path:
    """Write :func:`view` of ``result`` as one self-contained HTML file (plotly.js inlined).

    The file opens in a browser with no network. ``options`` go to :func:`view`. The file is
    written atomically (a reader never sees half of it).

    Returns
    -------
    Path
        ``out``.

    Raises
    ------
    ResultsFormatError, InvalidInputError, MissingExtraError
        As :func:`view`.
    OSError
        ``out`` cannot be written.
    """
    fig = view(result, **options)
    html = fig.to_html(include_plotlyjs=True, full_html=True, auto_play=False, config={"displaylogo": False, "responsive": True})
    path = as_path(out, "out")
    atomic_write(path, html)
    return path


def find_run(path: str | os.PathLike[str], run: str | None = None) -> Path:
    """The run to show: ``path`` itself (a ``.npz`` saved by :func:`uavcov.records.save_mission`),
    or in a folder (a results folder's ``runs/*.npz``, or a folder of ``.npz`` runs) the run
    named ``run`` (its file name without ``.npz``), by default the first in name order.

    Raises
    ------
    ResultsFormatError
        Nothing at ``path``, no run in the folder, or no run named ``run``.
    """
    where = as_path(path, "path")
    if where.is_file():
        if run is not None:
            raise ResultsFormatError(f"{where} is one run: a run name is for folders")
        return where
    if not where.is_dir():
        raise ResultsFormatError(f"no run or folder at {where}")
    runs = _stored_runs(where) or _stored_runs(where, folder=where) or _stored_runs(where, folder=where / "states")
    if not runs and (where / "plan.json").is_file():  # `uavcov plan` writes its files, not its mission
        raise ResultsFormatError(
            f"{where} is a flight plan's folder, which keeps no run: its map is report.png; to turn the plan's mission "
            "around in 3D, save it from Python (uavcov.save_mission(flight_plan.mission, 'plan.npz')) and view that file"
        )
    if not runs:
        raise ResultsFormatError(f"{where} holds no runs (neither runs/*.npz, *.npz nor a flown experiment's states/*.npz)")
    if run is None:
        return runs[0]
    run = as_optional_str(run, "run")
    for candidate in runs:
        if candidate.stem == run:
            return candidate
    names = ", ".join(r.stem for r in runs[:5]) + (" ..." if len(runs) > 5 else "")
    raise ResultsFormatError(f"no run named {run!r} in {where} (it has {names})")
