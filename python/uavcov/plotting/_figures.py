"""One function per figure of the paper, drawn from library objects.

- :func:`plot_approximation`: the true surface, the known points and the approximating surface
  S' (Fig. 2, Fig. 5a);
- :func:`plot_cvt`: the constrained CVT on S' (Fig. 3, Fig. 5b);
- :func:`plot_coverage_map`: the surface coloured seen / not seen, with the UAVs and their paths,
  in 3D or from above (Fig. 5c, Fig. 7);
- coverage across runs, in :mod:`uavcov.plotting._curves` (:func:`plot_coverage_curves`,
  :func:`plot_table1`);
- :func:`plot_point_cloud`: what the team saw (``seen_points``) as a point cloud (Fig. 7,
  right).

Each takes a mission result, a path to a saved run or the objects themselves, draws into a new
``matplotlib.figure.Figure`` or the ``ax`` it is given, saves to ``out`` when asked and returns
the figure.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._validate import as_bool, as_finite_float, as_path, as_positive_float, as_positive_int
from ..engine import Targets, Terrain, Visibility
from ..errors import InvalidInputError, InvalidTypeError, ResultsFormatError
from ..placement import CVTResult
from ._cameras import footprints
from ._canvas import (
    END_COLOUR,
    FOOTPRINT_COLOUR,
    SEEN_COLOUR,
    START_COLOUR,
    TRUE_SURFACE_COLOUR,
    UNSEEN_COLOUR,
    _finish,
    _line,
    _marker,
    _matplotlib,
    _new_axes,
    _patch,
)
from ._inputs import _as_result, _configuration, _d_max, _points, _setting, _sight, _terrain, _trajectory
from ._views import (
    DEFAULT_MAX_POLYGONS,
    _coverage_3d,
    _draw_polygons,
    _legend,
    _outline_edges,
    _scene_bounds,
    _style_3d,
    _surface_polygons,
    _top_view,
)
from ._writers import write_ply

# ---------------------------------------------------------------------------------------------
# Fig. 2 / 5a: the true surface, the known points and the approximating surface


def plot_approximation(
    source: Any,
    approximation: Terrain | None = None,
    prior_points: Any = None,
    *,
    ax: Any = None,
    out: Any = None,
    max_polygons: int = DEFAULT_MAX_POLYGONS,
    elev: float = 30.0,
    azim: float = -60.0,
    dpi: float = 110.0,
) -> Any:
    """The true surface (red), the known points (black) and the approximating surface S' (grey).

    Paper Fig. 2 and Fig. 5a.

    Parameters
    ----------
    source : MissionResult, path to a saved run, or Terrain
        A mission (its terrain, ``prior_points`` and ``approximation`` are used), or the true
        surface, in which case ``approximation`` is required.
    approximation : Terrain, optional
        S'; overrides the mission's.
    prior_points : (n, 3) array_like, optional
        The known points, metres; overrides the mission's.
    ax : 3D matplotlib Axes, optional
        Draw here instead of in a new figure.
    out : path, optional
        Save the figure there (format from the suffix).
    max_polygons : int
        Most polygons drawn for each surface (grids are decimated, S' triangles subdivided).
    elev, azim : float
        Viewing angles, degrees.
    dpi : float
        Resolution of the saved file.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if isinstance(source, Terrain):
        truth = source
        if approximation is None:
            raise InvalidInputError("plot_approximation(terrain, ...) needs approximation= (S')")
        known = np.empty((0, 3)) if prior_points is None else _points(prior_points, "prior_points")
    else:
        result = _as_result(source, ("terrain", "approximation", "prior_points"))
        truth = result.terrain
        approximation = result.approximation if approximation is None else approximation
        known = _points(result.prior_points if prior_points is None else prior_points, "prior_points")
    approximation = _terrain(approximation, "approximation")
    fig, ax = _new_axes(ax, three_d=True, figsize=(7.0, 5.6))
    ax.computed_zorder = False

    true_polys = _surface_polygons(truth, max_polygons)
    _draw_polygons(ax, true_polys.polys, np.tile(TRUE_SURFACE_COLOUR, (len(true_polys), 1)), shade=True, zorder=1)
    # S' as its own triangles' edges: the piecewise-linear interpolant is what the eye should
    # compare with the red surface, and edges do not hide it.
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    edges, which = _outline_edges(approximation)
    segments = np.asarray(approximation.vertices)[edges]
    ax.add_collection3d(Line3DCollection(list(segments), colors="0.15", linewidths=0.6, alpha=0.8, zorder=2))
    handles = [
        _patch(TRUE_SURFACE_COLOUR, "true surface S"),
        _line(f"approximating surface S' ({which})", color="0.15", linewidth=0.8),
    ]
    if known.shape[0]:
        ax.scatter(known[:, 0], known[:, 1], known[:, 2], s=22, c="black", depthshade=False, zorder=3)
        handles.append(_marker(f"known points ({known.shape[0]})", marker="o", color="black", markersize=5))
    source_text = f" from {known.shape[0]} known points" if known.shape[0] else ""
    _style_3d(
        ax,
        _scene_bounds(truth.bounds, approximation.bounds),
        elev=elev,
        azim=azim,
        title=f"True surface S and its approximation S'{source_text}",
    )
    _legend(ax, handles)
    return _finish(fig, out, dpi)


# ---------------------------------------------------------------------------------------------
# Fig. 3 / 5b: the constrained CVT


def _region_colours(n: int) -> np.ndarray:
    _matplotlib()
    from matplotlib import colormaps

    if n <= 10:
        return np.asarray(colormaps["tab10"](np.arange(n)))[:, :3]
    if n <= 20:
        return np.asarray(colormaps["tab20"](np.arange(n)))[:, :3]
    # Many regions: spread hues, alternating lightness so neighbours in index differ.
    hsv = colormaps["hsv"](np.linspace(0.0, 1.0, n, endpoint=False))[:, :3]
    return hsv * np.where(np.arange(n) % 2 == 0, 1.0, 0.7)[:, None]


def plot_cvt(
    source: Any,
    cvt: CVTResult | None = None,
    *,
    ax: Any = None,
    out: Any = None,
    max_polygons: int = DEFAULT_MAX_POLYGONS,
    elev: float = 30.0,
    azim: float = -60.0,
    dpi: float = 110.0,
) -> Any:
    """The constrained CVT: each Voronoi region in its own colour on the surface, generators on top.

    Paper Fig. 3 and Fig. 5b. Each drawn polygon takes the region of its centre (nearest
    generator in 3D, :meth:`CVTResult.regions`).

    Parameters
    ----------
    source : MissionResult, path to a saved run, or Terrain
        A mission started from a CVT (its ``approximation`` S' and ``cvt`` are used), or the
        surface the CVT was computed on, with ``cvt`` given.
    cvt : CVTResult, optional
        Overrides the mission's.
    ax, out, max_polygons, elev, azim, dpi
        As for :func:`plot_approximation`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if isinstance(source, Terrain):
        surface = source
        if cvt is None:
            raise InvalidInputError("plot_cvt(terrain, ...) needs cvt= (a CVTResult)")
    else:
        result = _as_result(source, ("approximation", "cvt"))
        surface = result.approximation
        if cvt is None:
            cvt = result.cvt
            if cvt is None:
                start = _setting(result, "start") or "?"
                raise ResultsFormatError(f"this run has no CVT (it started from {start!r}); nothing to draw")
    if not isinstance(cvt, CVTResult):
        raise InvalidTypeError(f"cvt must be a CVTResult, got {type(cvt).__name__}")
    generators = _points(cvt.generators, "cvt.generators", allow_empty=False)
    fig, ax = _new_axes(ax, three_d=True, figsize=(7.0, 5.6))
    ax.computed_zorder = False
    polys = _surface_polygons(surface, max_polygons)
    region = cvt.regions(polys.probes)
    palette = _region_colours(generators.shape[0])
    coll = _draw_polygons(ax, polys.polys, palette[region], shade=True, zorder=1)
    coll.uavcov_probes = polys.probes
    ax.scatter(
        generators[:, 0],
        generators[:, 1],
        generators[:, 2],
        s=60,
        marker="*",
        c="black",
        edgecolors="white",
        linewidths=0.6,
        depthshade=False,
        zorder=3,
    )
    for i, g in enumerate(generators):
        ax.text(g[0], g[1], g[2], f" {i}", fontsize=7, zorder=4)
    handles = [
        _marker(f"generators ({generators.shape[0]}, the UAVs' start)", marker="*", color="black", markersize=9),
        _patch(palette[0], "Voronoi region of one generator (one colour each)"),
    ]
    iters = f", {cvt.iterations} iterations" + ("" if cvt.converged else ", not converged")
    _style_3d(
        ax, _scene_bounds(surface.bounds, generators), elev=elev, azim=azim, title=f"Constrained CVT on the approximating surface{iters}"
    )
    _legend(ax, handles)
    return _finish(fig, out, dpi)


# ---------------------------------------------------------------------------------------------
# Fig. 5c / 7: the coverage map


def plot_coverage_map(
    source: Any,
    positions: Any = None,
    d_max: float | None = None,
    *,
    configuration: Any = "final",
    trajectory: Any = None,
    view: str = "3d",
    ax: Any = None,
    out: Any = None,
    max_polygons: int = DEFAULT_MAX_POLYGONS,
    raster: int = 400,
    shade: bool = True,
    elev: float = 35.0,
    azim: float = -60.0,
    dpi: float = 110.0,
) -> Any:
    """The surface coloured by seen / not seen, with start and end positions and trajectories.

    Paper Fig. 5c (and Fig. 7 for the buildings scene). Red: seen by at least one UAV; grey-blue:
    not seen. On a grid each drawn quad shows the share of its grid targets that is seen (the
    colours blend at the border of what is seen when the grid is decimated); on a mesh each
    triangle shows whether its centre is seen.

    Parameters
    ----------
    source : MissionResult, path to a saved run, or Terrain
        A mission, or a surface (then ``positions`` and ``d_max`` are required).
    positions : (N, 3) array_like, optional
        UAV positions, metres; by default the mission's ``configuration``.
    d_max : float, optional
        Sensing range, metres; by default the mission's.
    configuration : "final", "best", "initial" or int
        Which configuration of the mission to colour by.
    trajectory : (K + 1, N, 3) array_like, optional
        Paths to draw; by default the mission's (up to the configuration shown).
    view : {"3d", "top"}
        A 3D view (paper style) or a top view (a raster; clearer for buildings).
    ax : matplotlib Axes, optional
        3D axes for ``view="3d"``, ordinary axes for ``view="top"``.
    out : path, optional
        Save the figure there.
    max_polygons : int
        Most polygons drawn in 3D.
    raster : int
        Pixels on the longer side of a top view.
    shade : bool
        Shade the relief (off gives the flat seen / not-seen colours exactly).
    elev, azim, dpi
        Viewing angles (degrees) and resolution of the saved file.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if not isinstance(view, str) or view not in ("3d", "top"):  # checked before anything is computed
        raise InvalidInputError(f"view must be '3d' or 'top', got {view!r}")
    shade = as_bool(shade, "shade")
    # The 3D view's options, checked for the top view too: a mistake is reported whichever view draws.
    elev, azim = as_finite_float(elev, "elev"), as_finite_float(azim, "azim")
    max_polygons, raster = as_positive_int(max_polygons, "max_polygons"), as_positive_int(raster, "raster")
    start: np.ndarray | None = None
    label = "UAV positions"
    coverage_value: float | None = None
    sensors = None
    if isinstance(source, Terrain):
        terrain = source
        if positions is None or d_max is None:
            raise InvalidInputError("plot_coverage_map(terrain, ...) needs positions and d_max")
        pts = _points(positions, "positions", allow_empty=False)
        path = None if trajectory is None else _trajectory(trajectory)
    else:
        result = _as_result(source, ("terrain", "trajectory", "settings"))
        terrain = result.terrain
        pts, label, iteration = _configuration(result, configuration)
        if positions is not None:
            pts, label = _points(positions, "positions", allow_empty=False), "UAV positions"
        d_max = _d_max(result) if d_max is None else d_max
        path = _trajectory(result.trajectory if trajectory is None else trajectory)
        if trajectory is None and positions is None and iteration is not None:
            path = path[: iteration + 1]  # the paths end where the configuration shown is
        sight, sensors = _sight(result, pts, iteration if positions is None else None)  # a camera run's cameras, posed
    d = as_positive_float(d_max, "d_max")
    if path is not None:
        start = path[0]
    if sensors is None:
        sight = pts
    coverage_value = Visibility(terrain, d).coverage(sight, sensors=sensors)
    if view == "3d":
        fig, ax = _new_axes(ax, three_d=True, figsize=(7.2, 5.8))
        _coverage_3d(ax, terrain, sight, d, path, max_polygons=max_polygons, shade=shade, sensors=sensors)
        _style_3d(
            ax,
            _scene_bounds(terrain.bounds, pts, path if path is not None else pts),
            elev=elev,
            azim=azim,
            title=f"Coverage {coverage_value:.3f} (d_max = {d:g} m)",
        )
    elif view == "top":
        fig, ax = _new_axes(ax, three_d=False, figsize=(6.6, 6.0))
        _draw_top(ax, terrain, sight, d, path, raster, shade=shade, sensors=sensors)
        ax.set_title(f"Coverage {coverage_value:.3f} (d_max = {d:g} m), top view", fontsize=10)
    else:
        raise InvalidInputError(f"view must be '3d' or 'top', got {view!r}")
    three_d = view == "3d"
    handles = [_patch(SEEN_COLOUR, "seen by at least one UAV"), _patch(UNSEEN_COLOUR, "not seen")]
    if path is not None:
        handles.append(_line("trajectories", color="0.1", linewidth=0.9))
    if start is not None:
        _scatter(ax, start, three_d, s=28, c=START_COLOUR, marker="o", zorder=5)
        handles.append(_marker("start positions", marker="o", color=START_COLOUR, markersize=5))
    _scatter(ax, pts, three_d, s=46, c=[END_COLOUR], marker="o", edgecolors="black", linewidths=0.6, zorder=6)
    handles.append(_marker(label, marker="o", markerfacecolor=END_COLOUR, markeredgecolor="black", markersize=6))
    if three_d:
        _legend(ax, handles)
    else:
        ax.legend(handles=handles, fontsize=8, framealpha=0.9, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return _finish(fig, out, dpi)


def _draw_top(
    ax: Any, terrain: Terrain, sight: np.ndarray, d: float, path: np.ndarray | None, raster: int, *, shade: bool, sensors: Any
) -> None:
    """The top view of what ``sight`` sees, the cameras' footprints and the paths flown."""
    image, extent = _top_view(terrain, sight, d, raster, shade=shade, sensors=sensors)
    ax.imshow(image, extent=extent, origin="lower", interpolation="nearest")
    if sensors is not None and sight.shape[1] == 5:
        for outline in footprints(terrain, sight, sensors):
            if outline.shape[0]:
                closed = np.vstack([outline, outline[:1]])
                ax.plot(closed[:, 0], closed[:, 1], color=FOOTPRINT_COLOUR, linewidth=1.0)
    if path is not None:
        for i in range(path.shape[1]):
            ax.plot(path[:, i, 0], path[:, i, 1], color="0.1", linewidth=0.8, alpha=0.8)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_aspect("equal")


def _scatter(ax: Any, pts: np.ndarray, three_d: bool, **style: Any) -> None:
    if three_d:
        ax.scatter(pts[:, 0], pts[:, 1], pts[:, 2], depthshade=False, **style)
    else:
        ax.scatter(pts[:, 0], pts[:, 1], **style)


# ---------------------------------------------------------------------------------------------
# Fig. 7 (right): what the team saw, as a point cloud


def seen_points(result: Any, *, max_configurations: int = 50, targets: Targets | None = None) -> np.ndarray:
    """Target points seen by the team at some time during the mission: the reconstruction.

    Parameters
    ----------
    result : MissionResult or path to a saved run
    max_configurations : int
        The union is taken over at most this many configurations of the trajectory, evenly
        spaced, always with the first and the last.
    targets : Targets, optional
        Points to test; the terrain's default targets by default.

    Returns
    -------
    (n, 3) float64 ndarray
        The seen points, metres, in target order.
    """
    result = _as_result(result, ("terrain", "trajectory", "settings"))
    traj = _trajectory(result.trajectory)
    count = as_positive_int(max_configurations, "max_configurations")
    picks = np.unique(np.rint(np.linspace(0, traj.shape[0] - 1, min(count, traj.shape[0]))).astype(np.int64))
    vis = Visibility(result.terrain, _d_max(result), targets)
    seen = np.zeros(len(vis.targets), dtype=bool)
    for k in picks:
        poses, sensors = _sight(result, traj[k], int(k))
        seen |= vis.seen(poses, sensors=sensors)
    return np.array(vis.targets.points[seen])


def plot_point_cloud(
    source: Any,
    *,
    positions: Any = None,
    max_points: int = 30_000,
    max_configurations: int = 50,
    ax: Any = None,
    out: Any = None,
    ply: Any = None,
    elev: float = 35.0,
    azim: float = -60.0,
    dpi: float = 110.0,
) -> Any:
    """The surface points the team saw during the mission, coloured by height (paper Fig. 7, right).

    Parameters
    ----------
    source : MissionResult, path to a saved run, or (n, 3) array_like
        A mission (points from ``seen_points``; its final positions drawn too), or the
        points themselves.
    positions : (N, 3) array_like, optional
        UAV positions to draw.
    max_points : int
        Most points drawn (evenly thinned); the PLY file gets them all.
    max_configurations : int
        See ``seen_points``.
    ax, out, elev, azim, dpi
        As for :func:`plot_approximation`.
    ply : path, optional
        Also write every seen point there as ASCII PLY (see ``write_ply``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    total_targets = None
    if isinstance(source, np.ndarray) or (isinstance(source, (list, tuple)) and not hasattr(source, "trajectory")):
        pts = _points(source, "points")
    else:
        result = _as_result(source, ("terrain", "trajectory", "settings"))
        pts = seen_points(result, max_configurations=max_configurations)
        total_targets = len(result.terrain.default_targets())
        if positions is None:
            positions = _trajectory(result.trajectory)[-1]
    if ply is not None:
        write_ply(pts, as_path(ply, "ply"))
    fig, ax = _new_axes(ax, three_d=True, figsize=(7.0, 5.6))
    ax.computed_zorder = False
    limit = as_positive_int(max_points, "max_points")
    shown = pts[:: math.ceil(pts.shape[0] / limit)] if pts.shape[0] > limit else pts
    handles = []
    if shown.shape[0]:
        cloud = ax.scatter(
            shown[:, 0],
            shown[:, 1],
            shown[:, 2],
            c=shown[:, 2],
            cmap="viridis",
            s=max(1.0, min(8.0, 40_000.0 / shown.shape[0])),
            marker="o",
            linewidths=0,
            depthshade=False,
            zorder=1,
        )
        bar = fig.colorbar(cloud, ax=ax, shrink=0.55, pad=0.14)
        bar.set_label("height of the seen point (m)")
    parts = [shown] if shown.shape[0] else []
    if positions is not None:
        uav = _points(positions, "positions")
        if uav.shape[0]:
            ax.scatter(
                uav[:, 0], uav[:, 1], uav[:, 2], s=46, c=[END_COLOUR], edgecolors="black", linewidths=0.6, depthshade=False, zorder=3
            )
            handles.append(_marker("final UAV positions", marker="o", markerfacecolor=END_COLOUR, markeredgecolor="black", markersize=6))
            parts.append(uav)
    if not parts:
        raise InvalidInputError("nothing to draw: no point was seen and no position was given")
    drawn = f"{shown.shape[0]} of {pts.shape[0]} points drawn" if shown.shape[0] < pts.shape[0] else f"{pts.shape[0]} points"
    of = f" of {total_targets} targets" if total_targets else ""
    handles.insert(0, _marker(f"surface point seen during the mission ({drawn}{of})", marker=".", color=(0.2, 0.5, 0.55), markersize=8))
    _style_3d(ax, _scene_bounds(*parts), elev=elev, azim=azim, title="Point cloud of what the team saw")
    _legend(ax, handles)
    return _finish(fig, out, dpi)
