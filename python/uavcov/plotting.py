"""Figures of a mission, after the paper's: surfaces, CVT, coverage map, curves, Table 1, point cloud.

Every function takes library objects (a :class:`~uavcov.mission.MissionResult`, or a path to a
run saved by :func:`uavcov.records.save_mission`, a :class:`~uavcov.surface.Terrain`, a
:class:`~uavcov.cvt.CVTResult`, rows of a ``runs.csv``), draws into a new figure or into the
``ax`` it is given, saves to ``out`` when asked, and returns the matplotlib ``Figure``.
:func:`plot_directory` redraws every figure of a results directory without rerunning anything.

matplotlib is the optional extra ``uavcov[plot]`` and is imported only when a figure is drawn.
Figures are built as ``matplotlib.figure.Figure`` objects, not through ``pyplot``: they need no
display and no GUI backend (they render with Agg when saved), and nothing is kept in pyplot's
global figure list, so a long loop of figures does not leak memory.

Large surfaces are drawn decimated, never target by target: an elevation grid becomes at most
``max_polygons`` quads (each coloured by the share of its grid targets that is seen), a mesh is
clustered down to that many triangles, and top views are rasters.
"""

from __future__ import annotations

import csv
import math
import os
import shutil
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .cvt import CVTResult
from .errors import InvalidInputError, InvalidTypeError, ResultsFormatError
from .records import load_mission
from .surface import Terrain
from .targets import Targets
from .visibility import Visibility

__all__ = [
    "animate_mission",
    "plot_approximation",
    "plot_coverage_curves",
    "plot_coverage_map",
    "plot_cvt",
    "plot_directory",
    "plot_point_cloud",
    "plot_table1",
    "published_values",
    "seen_points",
    "write_ply",
]

# The paper's colours where it has them: covered surface red, start black, end green.
SEEN_COLOUR = (0.84, 0.15, 0.16)
UNSEEN_COLOUR = (0.72, 0.77, 0.84)
TRUE_SURFACE_COLOUR = (0.86, 0.33, 0.28)
START_COLOUR = "black"
END_COLOUR = (0.10, 0.65, 0.15)
INIT_COLOURS = {"cvt": "#2ca02c", "random": "#1f77b4", "corner": "#d62728", "pairs": "#9467bd"}
DEFAULT_MAX_POLYGONS = 20_000
LIGHT = np.array([-1.0, 1.0, 1.4142135623730951]) / 2.0  # from the north-west, 45 degrees up



# ---------------------------------------------------------------------------------------------
# matplotlib, loaded on demand


def _matplotlib() -> Any:
    """Import matplotlib, or say which extra provides it."""
    try:
        import matplotlib
        from matplotlib.figure import Figure  # noqa: F401
    except ImportError as exc:
        raise ImportError(
            "uavcov's figures need matplotlib, the optional extra: pip install 'uavcov[plot]'"
        ) from exc
    return matplotlib


def _new_axes(ax: Any, *, three_d: bool, figsize: tuple[float, float]) -> tuple[Any, Any]:
    """``(figure, axes)``: the caller's axes, checked, or a new figure with one axes."""
    _matplotlib()
    from matplotlib.axes import Axes

    if ax is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=figsize)
        ax = fig.add_subplot(projection="3d" if three_d else None)
        return fig, ax
    if not isinstance(ax, Axes):
        raise InvalidTypeError(f"ax must be a matplotlib Axes, got {type(ax).__name__}")
    if three_d and getattr(ax, "name", "") != "3d":
        raise InvalidInputError("this figure is 3D: pass axes made with projection='3d'")
    if not three_d and getattr(ax, "name", "") == "3d":
        raise InvalidInputError("this figure is 2D: pass ordinary (not 3D) axes")
    return ax.figure, ax


def _finish(fig: Any, out: Any, dpi: float) -> Any:
    if out is not None:
        path = Path(out)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=dpi, bbox_inches="tight", pad_inches=0.15)
    return fig


# ---------------------------------------------------------------------------------------------
# Checking what we are given


def _as_result(result: Any, needs: Sequence[str]) -> Any:
    """A mission result with the fields ``needs``; a path is read with :func:`load_mission`."""
    if isinstance(result, (str, os.PathLike)):
        result = load_mission(result)
    if result is None:
        raise ResultsFormatError("no result given (None)")
    missing = [name for name in needs if not hasattr(result, name)]
    if missing:
        raise ResultsFormatError(
            f"{type(result).__name__} is not a complete mission result: missing {', '.join(missing)}"
        )
    for name in needs:
        if name in ("terrain", "approximation") and not isinstance(getattr(result, name), Terrain):
            raise ResultsFormatError(f"the result's {name} is not a Terrain")
    if "trajectory" in needs:
        _trajectory(result.trajectory)
    if "coverage" in needs:
        _curve(result.coverage)
    return result


def _trajectory(value: Any) -> np.ndarray:
    try:
        traj = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ResultsFormatError(f"the trajectory is not numeric: {exc}") from exc
    if traj.ndim != 3 or traj.shape[2] != 3:
        raise ResultsFormatError(f"the trajectory must have shape (K + 1, N, 3), got {traj.shape}")
    if traj.shape[0] == 0 or traj.shape[1] == 0:
        raise ResultsFormatError(f"the trajectory is empty (shape {traj.shape})")
    if not np.isfinite(traj).all():
        raise ResultsFormatError("the trajectory holds NaN or infinite positions")
    return traj


def _curve(value: Any) -> np.ndarray:
    try:
        curve = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ResultsFormatError(f"the coverage curve is not numeric: {exc}") from exc
    if curve.ndim != 1 or curve.shape[0] == 0:
        raise ResultsFormatError(f"the coverage curve must be a non-empty (K + 1,) array, got shape {curve.shape}")
    if not np.isfinite(curve).all():
        raise ResultsFormatError("the coverage curve holds NaN or infinite values")
    return curve


def _d_max(result: Any) -> float:
    settings = getattr(result, "settings", None)
    value = getattr(settings, "d_max", None)
    if value is None:
        raise ResultsFormatError("the result's settings are missing d_max (the sensing range)")
    d = float(value)
    if not (math.isfinite(d) and d > 0):
        raise ResultsFormatError(f"the result's d_max must be a positive number, got {value!r}")
    return d


def _points(value: Any, name: str, *, allow_empty: bool = True) -> np.ndarray:
    try:
        pts = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"{name} is not a numeric array: {exc}") from exc
    if pts.size == 0 and allow_empty:
        return np.empty((0, 3))
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise InvalidInputError(f"{name} must have shape (n, 3), got {pts.shape}")
    if pts.shape[0] == 0 and not allow_empty:
        raise InvalidInputError(f"{name} is empty")
    if not np.isfinite(pts).all():
        raise InvalidInputError(f"{name} holds NaN or infinite values")
    return pts


def _terrain(value: Any, name: str) -> Terrain:
    if not isinstance(value, Terrain):
        raise InvalidTypeError(f"{name} must be a uavcov.Terrain, got {type(value).__name__}")
    return value


def _configuration(result: Any, configuration: Any) -> tuple[np.ndarray, str, int | None]:
    """The positions to show, how to call them, and their iteration (None when unknown)."""
    traj = _trajectory(result.trajectory)
    if isinstance(configuration, (int, np.integer)) and not isinstance(configuration, bool):
        k = int(configuration)
        if not -traj.shape[0] <= k < traj.shape[0]:
            raise InvalidInputError(f"configuration {k} is outside the trajectory (0..{traj.shape[0] - 1})")
        k %= traj.shape[0]
        return traj[k], f"positions at iteration {k}", k
    if not isinstance(configuration, str):
        raise InvalidInputError(f"configuration must be 'final', 'best', 'initial' or an iteration, got {configuration!r}")
    if configuration == "final":
        return traj[-1], f"final positions (iteration {traj.shape[0] - 1})", traj.shape[0] - 1
    if configuration == "initial":
        return traj[0], "start positions (iteration 0)", 0
    if configuration == "best":
        best = _points(getattr(result, "best_positions", None), "best_positions", allow_empty=False)
        it = getattr(result, "best_iteration", None)
        if isinstance(it, (int, np.integer)) and 0 <= int(it) < traj.shape[0]:
            return best, f"best positions (iteration {int(it)})", int(it)
        return best, "best positions", None
    raise InvalidInputError(f"configuration must be 'final', 'best', 'initial' or an iteration, got {configuration!r}")


def _as_positive_int(value: Any, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InvalidInputError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


# ---------------------------------------------------------------------------------------------
# Surfaces as polygons: decimated grids, subdivided or clustered meshes


class _Polygons:
    """Polygons to draw and where to evaluate a value for each.

    ``polys`` is ``(P, k, 3)``; ``probes`` ``(P, 3)`` are points on the true surface, one per
    polygon. For a grid, ``blocks`` gives each quad's inclusive node ranges ``(r0, r1, c0, c1)``
    so per-node values (the grid targets) can be averaged over it.
    """

    def __init__(self, polys: np.ndarray, probes: np.ndarray, blocks: np.ndarray | None = None) -> None:
        self.polys = polys
        self.probes = probes
        self.blocks = blocks

    def __len__(self) -> int:
        return int(self.polys.shape[0])


def _node_index(n: int, stride: int) -> np.ndarray:
    idx = np.arange(0, n, stride)
    return idx if idx[-1] == n - 1 else np.r_[idx, n - 1]


def _grid_polygons(terrain: Terrain, max_polygons: int) -> _Polygons:
    grid = terrain.grid
    assert grid is not None
    ny, nx = grid.shape
    stride = max(1, math.ceil(math.sqrt((ny - 1) * (nx - 1) / max_polygons)))
    rows, cols = _node_index(ny, stride), _node_index(nx, stride)
    xs, ys = grid.node_xy()
    z = np.asarray(grid.z)
    r0, c0 = np.meshgrid(rows[:-1], cols[:-1], indexing="ij")
    r1, c1 = np.meshgrid(rows[1:], cols[1:], indexing="ij")
    r0, r1, c0, c1 = (a.ravel() for a in (r0, r1, c0, c1))
    corners_r = np.stack([r0, r0, r1, r1], axis=1)
    corners_c = np.stack([c0, c1, c1, c0], axis=1)
    polys = np.stack([xs[corners_c], ys[corners_r], z[corners_r, corners_c]], axis=2)
    keep = np.isfinite(polys[:, :, 2]).all(axis=1)
    polys = polys[keep]
    return _Polygons(polys, polys.mean(axis=1), np.stack([r0, r1, c0, c1], axis=1)[keep])


def _subdivision_template(m: int) -> np.ndarray:
    """``(m^2, 3, 3)`` barycentric weights of the sub-triangles of a triangle cut ``m`` ways."""
    tris = []
    for i in range(m):
        for j in range(m - i):
            tris.append([(i, j), (i + 1, j), (i, j + 1)])
            if i + j <= m - 2:
                tris.append([(i + 1, j), (i + 1, j + 1), (i, j + 1)])
    lattice = np.array(tris, dtype=np.float64) / m  # (m^2, 3, 2): weights of B and C
    return np.concatenate([1.0 - lattice.sum(axis=2, keepdims=True), lattice], axis=2)


def _cluster(vertices: np.ndarray, faces: np.ndarray, cell: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertex clustering: merge vertices sharing a ``cell``-sized voxel, drop collapsed faces."""
    keys = np.floor((vertices - vertices.min(axis=0)) / cell).astype(np.int64)
    _, cluster, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    cluster = cluster.ravel()
    merged = np.zeros((counts.shape[0], 3))
    np.add.at(merged, cluster, vertices)
    merged /= counts[:, None]
    f = cluster[faces]
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
    f = np.unique(np.sort(f, axis=1), axis=0) if f.shape[0] else f
    return merged, f


def _mesh_polygons(terrain: Terrain, max_polygons: int) -> _Polygons:
    vertices = np.asarray(terrain.vertices)
    faces = np.asarray(terrain.faces)
    if faces.shape[0] > max_polygons:
        # Too many to draw: cluster vertices until few enough triangles remain, then put each
        # triangle's probe back on the true surface.
        extent = float(np.ptp(vertices, axis=0).max())
        cell = max(math.sqrt(2.0 * terrain.area / max_polygons), 1e-9 * extent)
        while True:
            merged, merged_faces = _cluster(vertices, faces, cell)
            if 0 < merged_faces.shape[0] <= max_polygons or merged_faces.shape[0] == 0:
                break
            cell *= 1.3
        if merged_faces.shape[0] == 0:
            raise InvalidInputError("the mesh could not be decimated for drawing; raise max_polygons")
        polys = merged[merged_faces]
        return _Polygons(polys, terrain.closest_point(polys.mean(axis=1)))
    # Few, possibly large triangles (an approximating surface S'): cut them so colours that
    # change inside a triangle (Voronoi regions, visibility) show.
    areas = np.asarray(terrain.face_areas)
    piece = terrain.area / max_polygons
    cuts = np.clip(np.floor(np.sqrt(areas / piece)), 1, 64).astype(np.int64)
    while int((cuts**2).sum()) > max_polygons and cuts.max() > 1:
        cuts = np.maximum(1, cuts - 1)
    tri = vertices[faces]
    pieces = []
    for m in np.unique(cuts):
        weights = _subdivision_template(int(m))
        pieces.append(np.einsum("tkv,fvd->ftkd", weights, tri[cuts == m]).reshape(-1, 3, 3))
    polys = np.concatenate(pieces)
    return _Polygons(polys, polys.mean(axis=1))


def _surface_polygons(terrain: Terrain, max_polygons: int) -> _Polygons:
    max_polygons = _as_positive_int(max_polygons, "max_polygons")
    if terrain.grid is not None:
        return _grid_polygons(terrain, max_polygons)
    return _mesh_polygons(terrain, max_polygons)


def _block_means(node_values: np.ndarray, blocks: np.ndarray) -> np.ndarray:
    """Mean of the finite node values over each inclusive block ``(r0, r1, c0, c1)``."""
    valid = np.isfinite(node_values)
    sums = np.zeros((node_values.shape[0] + 1, node_values.shape[1] + 1))
    counts = np.zeros_like(sums)
    sums[1:, 1:] = np.where(valid, node_values, 0.0).cumsum(0).cumsum(1)
    counts[1:, 1:] = valid.cumsum(0).cumsum(1)
    r0, r1, c0, c1 = blocks.T

    def box(table: np.ndarray) -> np.ndarray:
        return table[r1 + 1, c1 + 1] - table[r0, c1 + 1] - table[r1 + 1, c0] + table[r0, c0]

    n = box(counts)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, box(sums) / np.maximum(n, 1), np.nan)


def _normals(polys: np.ndarray) -> np.ndarray:
    if polys.shape[1] == 4:
        n = np.cross(polys[:, 2] - polys[:, 0], polys[:, 3] - polys[:, 1])
    else:
        n = np.cross(polys[:, 1] - polys[:, 0], polys[:, 2] - polys[:, 0])
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return n / np.where(length > 0, length, 1.0)


def _shade(rgb: np.ndarray, polys: np.ndarray) -> np.ndarray:
    """Two-sided diffuse light from the north-west: relief shows, hue stays readable."""
    intensity = np.abs(_normals(polys) @ LIGHT)
    return np.clip(rgb[:, :3] * (0.45 + 0.55 * intensity)[:, None], 0.0, 1.0)


def _blend(fraction: np.ndarray, low: Sequence[float], high: Sequence[float]) -> np.ndarray:
    f = np.clip(np.nan_to_num(fraction, nan=0.0), 0.0, 1.0)[:, None]
    return (1.0 - f) * np.asarray(low)[None, :] + f * np.asarray(high)[None, :]


def _draw_polygons(ax: Any, polys: np.ndarray, rgb: np.ndarray, *, shade: bool, alpha: float = 1.0,
                   zorder: float = 1.0) -> Any:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # type: ignore[import-untyped]

    colours = _shade(rgb, polys) if shade else np.asarray(rgb)[:, :3]
    rgba = np.concatenate([colours, np.full((colours.shape[0], 1), alpha)], axis=1)
    # Edges the colour of the faces close the hairline seams antialiasing leaves between them.
    coll = Poly3DCollection(list(polys), facecolors=rgba, edgecolors=rgba, linewidths=0.25, zorder=zorder)
    ax.add_collection3d(coll)
    return coll


def _style_3d(ax: Any, bounds: np.ndarray, *, elev: float, azim: float, title: str | None) -> None:
    lo, hi = np.asarray(bounds[0], dtype=float), np.asarray(bounds[1], dtype=float)
    span = np.maximum(hi - lo, 1e-6)
    pad = 0.02 * span
    ax.set_xlim(lo[0] - pad[0], hi[0] + pad[0])
    ax.set_ylim(lo[1] - pad[1], hi[1] + pad[1])
    ax.set_zlim(lo[2], hi[2] + pad[2])
    flat = 0.3 * max(span[0], span[1])
    exaggeration = flat / span[2] if span[2] < flat else 1.0
    ax.set_box_aspect((span[0], span[1], span[2] * exaggeration))
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)" if exaggeration < 1.05 else f"z (m, vertical x{exaggeration:.1f})")
    ax.view_init(elev=elev, azim=azim)
    from matplotlib.ticker import MaxNLocator

    # The vertical axis is short on screen: few ticks keep its labels apart.
    ax.zaxis.set_major_locator(MaxNLocator(nbins=4))
    ax.tick_params(labelsize=8, pad=1)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.pane.set_facecolor((0.97, 0.97, 0.97, 1.0))
    if title:
        ax.set_title(title, fontsize=10)


def _scene_bounds(*parts: np.ndarray) -> np.ndarray:
    stacked = np.concatenate([np.asarray(p, dtype=float).reshape(-1, 3) for p in parts if np.size(p)])
    return np.stack([stacked.min(axis=0), stacked.max(axis=0)])


def _legend(ax: Any, handles: list[Any]) -> None:
    """Under a 3D axes, where it hides nothing of the scene."""
    ax.legend(handles=handles, fontsize=8, framealpha=0.9, loc="upper center", bbox_to_anchor=(0.5, -0.04),
              ncol=min(len(handles), 2))


def _patch(colour: Any, label: str) -> Any:
    from matplotlib.patches import Patch

    return Patch(facecolor=colour, edgecolor="0.3", linewidth=0.5, label=label)


def _marker(label: str, **style: Any) -> Any:
    from matplotlib.lines import Line2D

    return Line2D([], [], linestyle="none", label=label, **style)


def _line(label: str, **style: Any) -> Any:
    from matplotlib.lines import Line2D

    return Line2D([], [], label=label, **style)


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
    from mpl_toolkits.mplot3d.art3d import Line3DCollection  # type: ignore[import-untyped]

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
    _style_3d(ax, _scene_bounds(truth.bounds, approximation.bounds), elev=elev, azim=azim,
              title=f"True surface S and its approximation S'{source_text}")
    _legend(ax, handles)
    return _finish(fig, out, dpi)


def _outline_edges(surface: Terrain, max_all: int = 600) -> tuple[np.ndarray, str]:
    """Edges that show a surface as lines: every edge of a coarse mesh (S' from a few points),
    only creases (faces meeting at more than 20 degrees) and borders of a fine one (a map of
    buildings), where every edge would be a grey smear."""
    faces = np.asarray(surface.faces)
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, inverse, counts = np.unique(edges, axis=0, return_inverse=True, return_counts=True)
    if faces.shape[0] <= max_all:
        return unique, "its triangles"
    inverse = inverse.ravel()
    owner = np.tile(np.arange(faces.shape[0]), 3)
    order = np.argsort(inverse, kind="stable")
    first = np.searchsorted(inverse[order], np.arange(unique.shape[0]))
    normals = _normals(np.asarray(surface.vertices)[faces])
    pair = counts == 2
    a = owner[order[first[pair]]]
    b = owner[order[first[pair] + 1]]
    crease = np.zeros(unique.shape[0], dtype=bool)
    crease[pair] = np.abs(np.einsum("ij,ij->i", normals[a], normals[b])) < math.cos(math.radians(20.0))
    return unique[crease | (counts != 2)], "its creases and borders"


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
                start = getattr(getattr(result, "settings", None), "start", "?")
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
    ax.scatter(generators[:, 0], generators[:, 1], generators[:, 2], s=60, marker="*", c="black",
               edgecolors="white", linewidths=0.6, depthshade=False, zorder=3)
    for i, g in enumerate(generators):
        ax.text(g[0], g[1], g[2], f" {i}", fontsize=7, zorder=4)
    handles = [
        _marker(f"generators ({generators.shape[0]}, the UAVs' start)", marker="*", color="black", markersize=9),
        _patch(palette[0], "Voronoi region of one generator (one colour each)"),
    ]
    iters = f", {cvt.iterations} iterations" + ("" if cvt.converged else ", not converged")
    _style_3d(ax, _scene_bounds(surface.bounds, generators), elev=elev, azim=azim,
              title=f"Constrained CVT on the approximating surface{iters}")
    _legend(ax, handles)
    return _finish(fig, out, dpi)


# ---------------------------------------------------------------------------------------------
# Fig. 5c / 7: the coverage map


def _grid_node_mask(terrain: Terrain, seen: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Per grid node: 1.0 seen, 0.0 not seen, NaN where no target stands (nodata)."""
    grid = terrain.grid
    assert grid is not None
    (ox, oy), (dx, dy) = grid.origin, grid.spacing
    j = np.rint((points[:, 0] - ox) / dx).astype(np.int64)
    i = np.rint((points[:, 1] - oy) / dy).astype(np.int64)
    nodes = np.full(grid.shape, np.nan)
    nodes[i, j] = seen.astype(np.float64)
    return nodes


def _coverage_fraction(terrain: Terrain, polys: _Polygons, positions: np.ndarray, d_max: float) -> np.ndarray:
    """Share of each drawn polygon that is seen, from the engine's mask.

    Grid: the polygon's grid targets (nodes), averaged. Mesh: the polygon's probe point.
    """
    if terrain.grid is not None:
        assert polys.blocks is not None
        targets = terrain.default_targets()
        seen = Visibility(terrain, d_max, targets).seen(positions)
        return _block_means(_grid_node_mask(terrain, seen, targets.points), polys.blocks)
    seen = Visibility(terrain, d_max, Targets(polys.probes)).seen(positions)
    return seen.astype(np.float64)


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
    start: np.ndarray | None = None
    label = "UAV positions"
    coverage_value: float | None = None
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
    d = float(d_max)
    if not (math.isfinite(d) and d > 0):
        raise InvalidInputError(f"d_max must be a positive number of metres, got {d_max!r}")
    if path is not None:
        start = path[0]
    coverage_value = Visibility(terrain, d).coverage(pts)
    if view == "3d":
        fig, ax = _new_axes(ax, three_d=True, figsize=(7.2, 5.8))
        _coverage_3d(ax, terrain, pts, d, path, max_polygons=max_polygons, shade=shade)
        _style_3d(ax, _scene_bounds(terrain.bounds, pts, path if path is not None else pts), elev=elev, azim=azim,
                  title=f"Coverage {coverage_value:.3f} (d_max = {d:g} m)")
    elif view == "top":
        fig, ax = _new_axes(ax, three_d=False, figsize=(6.6, 6.0))
        image, extent = _top_view(terrain, pts, d, _as_positive_int(raster, "raster"), shade=shade)
        ax.imshow(image, extent=extent, origin="lower", interpolation="nearest")
        if path is not None:
            for i in range(path.shape[1]):
                ax.plot(path[:, i, 0], path[:, i, 1], color="0.1", linewidth=0.8, alpha=0.8)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_aspect("equal")
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


def _scatter(ax: Any, pts: np.ndarray, three_d: bool, **style: Any) -> None:
    if three_d:
        ax.scatter(pts[:, 0], pts[:, 1], pts[:, 2], depthshade=False, **style)
    else:
        ax.scatter(pts[:, 0], pts[:, 1], **style)


def _coverage_3d(ax: Any, terrain: Terrain, pts: np.ndarray, d_max: float, path: np.ndarray | None, *,
                 max_polygons: int, shade: bool) -> Any:
    ax.computed_zorder = False  # paths and UAVs stay in front of the surface
    polys = _surface_polygons(terrain, max_polygons)
    fraction = _coverage_fraction(terrain, polys, pts, d_max)
    coll = _draw_polygons(ax, polys.polys, _blend(fraction, UNSEEN_COLOUR, SEEN_COLOUR), shade=shade, zorder=1)
    # Kept on the artist so a test (or a curious user) can compare colours with the engine.
    coll.uavcov_seen_fraction = fraction
    coll.uavcov_probes = polys.probes
    if path is not None:
        width = 0.9 if path.shape[0] <= 150 else 0.6  # long random-looking paths: lighter
        for i in range(path.shape[1]):
            ax.plot(path[:, i, 0], path[:, i, 1], path[:, i, 2], color="0.1", linewidth=width, alpha=0.8, zorder=4)
    # Dotted drops to the ground place each UAV over the map.
    ground = terrain.ground_height(pts[:, :2])
    for p, g in zip(pts, ground):
        if np.isfinite(g):
            ax.plot([p[0], p[0]], [p[1], p[1]], [g, p[2]], color="0.25", linewidth=0.6, linestyle=":", zorder=4)
    return coll


# ---------------------------------------------------------------------------------------------
# Top views (rasters)


def _raster_points(terrain: Terrain, raster: int) -> tuple[np.ndarray, np.ndarray, tuple[float, float, float, float]]:
    """Top-surface points on a regular raster: ``(points (H, W, 3) with NaN z off the surface,
    z (H, W), extent)``."""
    lo, hi = terrain.bounds[0], terrain.bounds[1]
    span = max(hi[0] - lo[0], hi[1] - lo[1])
    step = span / raster
    w = max(2, round((hi[0] - lo[0]) / step))
    h = max(2, round((hi[1] - lo[1]) / step))
    dx, dy = (hi[0] - lo[0]) / w, (hi[1] - lo[1]) / h
    xs = lo[0] + (np.arange(w) + 0.5) * dx
    ys = lo[1] + (np.arange(h) + 0.5) * dy
    gx, gy = np.meshgrid(xs, ys)
    z = terrain.ground_height(np.column_stack([gx.ravel(), gy.ravel()])).reshape(h, w)
    return np.stack([gx, gy, z], axis=2), z, (lo[0], hi[0], lo[1], hi[1])


def _hillshade(z: np.ndarray, dx: float, dy: float) -> np.ndarray:
    filled = np.where(np.isfinite(z), z, np.nanmean(z) if np.isfinite(z).any() else 0.0)
    gy, gx = np.gradient(filled, dy, dx)
    n = np.stack([-gx, -gy, np.ones_like(gx)], axis=2)
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    return np.abs(n @ LIGHT)


class _TopView:
    """A top view of a terrain that recolours quickly for any configuration (animations).

    Grids use their own targets, block-averaged to at most ``raster`` pixels a side; meshes
    use the highest surface point under each pixel centre as a target.
    """

    def __init__(self, terrain: Terrain, d_max: float, raster: int) -> None:
        self.terrain = terrain
        grid = terrain.grid
        if grid is not None:
            ny, nx = grid.shape
            stride = max(1, math.ceil(max(ny, nx) / raster))
            rows, cols = np.arange(0, ny, stride), np.arange(0, nx, stride)
            r0, c0 = np.meshgrid(rows, cols, indexing="ij")
            self.blocks = np.stack([r0, np.minimum(r0 + stride - 1, ny - 1), c0,
                                    np.minimum(c0 + stride - 1, nx - 1)], axis=2).reshape(-1, 4)
            self.shape = (rows.size, cols.size)
            z = _block_means(np.asarray(grid.z, dtype=float), self.blocks).reshape(self.shape)
            (ox, oy), (dx, dy) = grid.origin, grid.spacing
            self.extent = (ox - dx / 2, ox + (nx - 0.5) * dx, oy - dy / 2, oy + (ny - 0.5) * dy)
            self.targets = terrain.default_targets()
            pixel = (stride * dx, stride * dy)
        else:
            points, z, self.extent = _raster_points(terrain, raster)
            self.shape = z.shape
            self.valid = np.isfinite(z).ravel()
            if not self.valid.any():
                raise InvalidInputError("the terrain has no surface under its own bounds")
            self.targets = Targets(points.reshape(-1, 3)[self.valid])
            pixel = ((self.extent[1] - self.extent[0]) / z.shape[1], (self.extent[3] - self.extent[2]) / z.shape[0])
        self.z = z
        self.light = 0.45 + 0.55 * _hillshade(z, *pixel)
        self.nodata = ~np.isfinite(z)
        self.visibility = Visibility(terrain, d_max, self.targets)

    def fraction(self, positions: np.ndarray) -> np.ndarray:
        seen = self.visibility.seen(positions)
        if self.terrain.grid is not None:
            nodes = _grid_node_mask(self.terrain, seen, self.targets.points)
            return _block_means(nodes, self.blocks).reshape(self.shape)
        out = np.full(self.valid.shape, np.nan)
        out[self.valid] = seen
        return out.reshape(self.shape)

    def image(self, positions: np.ndarray, *, shade: bool = True) -> np.ndarray:
        f = self.fraction(positions)
        rgb = _blend(f.ravel(), UNSEEN_COLOUR, SEEN_COLOUR).reshape(*self.shape, 3)
        if shade:
            rgb = rgb * self.light[:, :, None]
        rgba = np.concatenate([np.clip(rgb, 0, 1), np.ones((*self.shape, 1))], axis=2)
        rgba[self.nodata] = (1.0, 1.0, 1.0, 0.0)
        return rgba


def _top_view(terrain: Terrain, pts: np.ndarray, d_max: float, raster: int, *, shade: bool) -> tuple[np.ndarray, tuple[float, ...]]:
    view = _TopView(terrain, d_max, raster)
    return view.image(pts, shade=shade), view.extent


# ---------------------------------------------------------------------------------------------
# Fig. 5d / 6 / 8: coverage per iteration


def _group_results(results: Any, group_by: str) -> dict[str, list[Any]]:
    if isinstance(results, Mapping):
        groups = {str(k): list(v) if isinstance(v, (list, tuple)) else [v] for k, v in results.items()}
    else:
        if isinstance(results, (str, os.PathLike)) or not isinstance(results, Iterable):
            results = [results]
        groups = {}
        for r in results:
            r = _as_result(r, ("coverage",))
            if group_by == "none":
                key = "runs"
            else:
                key = str(getattr(getattr(r, "settings", None), group_by, None))
                if key == "None":
                    raise ResultsFormatError(f"a result's settings have no {group_by!r} to group by")
            groups.setdefault(key, []).append(r)
    if not groups or not any(groups.values()):
        raise ResultsFormatError("no results to plot (empty)")
    return {k: [_as_result(r, ("coverage",)) for r in v] for k, v in groups.items() if v}


def _curve_stats(curves: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean and sample sigma (``ddof=1``, as the tables) per iteration over the runs that
    reached it, and how many did."""
    length = max(c.shape[0] for c in curves)
    stack = np.full((len(curves), length), np.nan)
    for i, c in enumerate(curves):
        stack[i, : c.shape[0]] = c
    count = np.isfinite(stack).sum(axis=0)
    mean = np.nanmean(stack, axis=0)
    squares = np.nansum((stack - mean) ** 2, axis=0)
    sigma = np.where(count > 1, np.sqrt(squares / np.maximum(count - 1, 1)), 0.0)
    return mean, sigma, count


def plot_coverage_curves(
    results: Any,
    *,
    group_by: str = "start",
    running_max: bool = False,
    show_runs: bool | None = None,
    reference: Mapping[str, float] | None = None,
    ax: Any = None,
    out: Any = None,
    title: str | None = None,
    dpi: float = 110.0,
) -> Any:
    """Coverage per iteration, one colour per group: the mean with a band of one sigma.

    Paper Fig. 5d (one run), Fig. 6 (three starts on one terrain) and Fig. 8 (buildings).

    Parameters
    ----------
    results : MissionResult, path, sequence of them, or mapping label -> sequence
        The runs. A mapping gives the groups and their legend labels directly.
    group_by : str
        Setting that splits a sequence into groups (default "start": cvt / random / corner);
        "none" puts every run in one group.
    running_max : bool
        Plot the best coverage so far instead of the coverage at each iteration.
    show_runs : bool, optional
        Draw each run thinly under the mean; default when a group has at most 10 runs.
    reference : mapping label -> float, optional
        A published value per group (e.g. the paper's Fig. 6 maxima), drawn as a dashed line.
    ax : matplotlib Axes, optional
    out : path, optional
    title : str, optional
    dpi : float

    Returns
    -------
    matplotlib.figure.Figure
    """
    groups = _group_results(results, group_by)
    fig, ax = _new_axes(ax, three_d=False, figsize=(6.6, 4.2))
    handles = []
    fallback = iter(["#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"] * 10)
    order = sorted(groups, key=lambda k: (list(INIT_COLOURS).index(k) if k in INIT_COLOURS else 99, k))
    for key in order:
        runs = groups[key]
        curves = [_curve(r.coverage) for r in runs]
        if running_max:
            curves = [np.maximum.accumulate(c) for c in curves]
        colour = INIT_COLOURS.get(key) or next(fallback)
        mean, sigma, count = _curve_stats(curves)
        k = np.arange(mean.shape[0])
        if show_runs if show_runs is not None else len(curves) <= 10:
            for c in curves if len(curves) > 1 else []:
                ax.plot(np.arange(c.shape[0]), c, color=colour, linewidth=0.5, alpha=0.35)
        if len(curves) > 1:
            ax.fill_between(k, mean - sigma, mean + sigma, color=colour, alpha=0.18, linewidth=0)
        best = max(float(c.max()) for c in curves)
        what = f"{len(curves)} runs, mean and one sigma" if len(curves) > 1 else "1 run"
        ax.plot(k, mean, color=colour, linewidth=1.8)
        handles.append(_line(f"{key} ({what}; max {best:.3f})", color=colour, linewidth=1.8))
        if (count < len(curves)).any():
            ax.axvline(int(np.argmax(count < len(curves))), color=colour, linewidth=0.6, linestyle=":")
        if reference is not None and key in reference:
            value = float(reference[key])
            ax.axhline(value, color=colour, linewidth=1.0, linestyle="--")
            handles.append(_line(f"{key}: the paper's max ({value:.2f})", color=colour, linewidth=1.0, linestyle="--"))
    ax.set_xlabel("iteration")
    ax.set_ylabel("best coverage so far" if running_max else "coverage (share of the surface seen)")
    ax.grid(True, linewidth=0.4, alpha=0.5)
    ax.set_title(title or "Coverage during the optimisation", fontsize=10)
    ax.legend(handles=handles, fontsize=8, loc="lower right", framealpha=0.9)
    if fig.get_layout_engine() is None and ax is fig.axes[0] and len(fig.axes) == 1:
        fig.set_layout_engine("constrained")
    return _finish(fig, out, dpi)


# ---------------------------------------------------------------------------------------------
# Table 1 beside the paper


def _read_runs(path: Any) -> list[dict[str, str]]:
    """Rows of a ``runs.csv`` as dicts of strings (the ``csv`` module's), header checked.

    Raises
    ------
    ResultsFormatError
        No such file, no header, or a required column missing (named).
    """
    path = Path(path)
    if not path.is_file():
        raise ResultsFormatError(f"no runs file at {path}")
    with path.open(newline="") as handle:
        reader = csv.DictReader(handle)
        if reader.fieldnames is None:
            raise ResultsFormatError(f"{path} is empty (no header line)")
        missing = [c for c in ("experiment", "init", "n_uavs", "max_coverage") if c not in reader.fieldnames]
        if missing:
            raise ResultsFormatError(f"{path} lacks the column(s) {', '.join(missing)}")
        return list(reader)


def _number(row: Mapping[str, Any], column: str, index: int) -> float | None:
    """The row's value, or None when the run failed (empty, "nan")."""
    if column not in row:
        raise ResultsFormatError(f"row {index} of the runs has no {column!r} column")
    raw = row[column]
    if raw is None or (isinstance(raw, str) and raw.strip().lower() in ("", "nan", "none")):
        return None
    try:
        value = float(raw)
    except (TypeError, ValueError) as exc:
        raise ResultsFormatError(f"row {index}: {column} = {raw!r} is not a number") from exc
    return value if math.isfinite(value) else None


def plot_table1(
    rows: Any,
    *,
    metric: str = "max_coverage",
    paper: bool = True,
    ax: Any = None,
    out: Any = None,
    dpi: float = 110.0,
) -> Any:
    """Grouped bars: mean ``metric`` (with one sigma) per start and team size, ours beside the paper's.

    Parameters
    ----------
    rows : iterable of mappings, or a path to runs.csv
        Rows with at least ``experiment``, ``init``, ``n_uavs`` and ``metric`` (strings as the
        ``csv`` module gives them, or numbers). Rows whose value is empty or NaN (failed runs)
        are left out and counted in the title.
    metric : str
        Column to compare: "max_coverage" (paper Table 1's "Max.") or "initial_coverage".
    paper : bool
        Draw the paper's value (hatched) beside ours where it publishes one for the row's
        experiment ("table1", "pyramid"), start and N.
    ax, out, dpi
        As elsewhere.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if isinstance(rows, (str, os.PathLike)):
        rows = _read_runs(rows)
    if isinstance(rows, Mapping) or not isinstance(rows, Iterable):
        raise InvalidTypeError("rows must be an iterable of mappings (csv.DictReader rows) or a runs.csv path")
    rows = list(rows)
    if not rows:
        raise ResultsFormatError("no runs to plot (empty)")
    values: dict[tuple[str, str, int], list[float]] = {}
    failed = 0
    for index, row in enumerate(rows):
        if not isinstance(row, Mapping):
            raise InvalidTypeError(f"row {index} is a {type(row).__name__}, not a mapping")
        for column in ("experiment", "init", "n_uavs"):
            if column not in row:
                raise ResultsFormatError(f"row {index} of the runs has no {column!r} column")
        n = _number(row, "n_uavs", index)
        value = _number(row, metric, index)
        if value is None or n is None:
            failed += 1
            continue
        values.setdefault((str(row["experiment"]), str(row["init"]), int(n)), []).append(value)
    if not values:
        raise ResultsFormatError(f"no run has a value for {metric!r} ({failed} failed)")
    experiments = sorted({e for e, _, _ in values})
    series = sorted({(e, i) for e, i, _ in values},
                    key=lambda s: (s[0], list(INIT_COLOURS).index(s[1]) if s[1] in INIT_COLOURS else 99, s[1]))
    sizes = sorted({n for _, _, n in values})
    published = published_values() if paper else {}

    fig, ax = _new_axes(ax, three_d=False, figsize=(max(6.0, 1.6 + 1.5 * len(sizes) * max(1, len(series)) / 3), 4.4))
    bars_per_series = 2 if any((e, metric, i, n) in published for e, i in series for n in sizes) else 1
    width = 0.8 / (len(series) * bars_per_series)
    fallback = iter(["#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"] * 10)
    handles = []
    for s_index, (experiment, init) in enumerate(series):
        colour = INIT_COLOURS.get(init) or next(fallback)
        name = init if len(experiments) == 1 else f"{experiment}/{init}"
        for n_index, n in enumerate(sizes):
            base = n_index - 0.4 + s_index * bars_per_series * width + width / 2
            ours = values.get((experiment, init, n))
            if ours:
                mean = float(np.mean(ours))
                sigma = float(np.std(ours, ddof=1)) if len(ours) > 1 else 0.0
                ax.bar(base, mean, width, yerr=sigma, color=colour, edgecolor="black", linewidth=0.4,
                       error_kw={"elinewidth": 0.8, "capsize": 2})
                ax.text(base, 0.01, f"{len(ours)}", ha="center", va="bottom", fontsize=6, color="white")
            ref = published.get((experiment, metric, init, n))
            if ref is not None and bars_per_series == 2:
                ax.bar(base + width, ref[0], width, yerr=ref[1], color=colour, alpha=0.35, hatch="///",
                       edgecolor="black", linewidth=0.4, error_kw={"elinewidth": 0.8, "capsize": 2})
        handles.append(_patch(colour, f"{name}: ours"))
        if bars_per_series == 2 and any((experiment, metric, init, n) in published for n in sizes):
            from matplotlib.patches import Patch

            handles.append(Patch(facecolor=colour, alpha=0.35, hatch="///", edgecolor="black", linewidth=0.4,
                                 label=f"{name}: paper"))
    ax.set_xticks(range(len(sizes)), [f"N = {n}" for n in sizes])
    ax.set_xlim(-0.6, len(sizes) - 0.4)
    ax.set_ylim(0.0, 1.08)
    ax.set_ylabel(f"mean {metric.replace('_', ' ')} (error bar: one sigma)")
    ax.set_xlabel("team size (white digits: our runs per bar)")
    ax.grid(True, axis="y", linewidth=0.4, alpha=0.5)
    note = f"; {failed} failed run(s) left out" if failed else ""
    ax.set_title(f"{', '.join(experiments)}: {metric.replace('_', ' ')} by start and team size{note}", fontsize=10)
    # Below the axes: bars may reach the top anywhere.
    ax.legend(handles=handles, fontsize=7, ncol=max(1, min(len(handles), 6)), loc="upper center",
              bbox_to_anchor=(0.5, -0.14), framealpha=0.9)
    if fig.get_layout_engine() is None and len(fig.axes) == 1:
        fig.set_layout_engine("constrained")
    return _finish(fig, out, dpi)


def published_values() -> dict[tuple[str, str, str, int], tuple[float, float]]:
    """The paper's numbers the bars can stand beside: ``(experiment, metric, init, N) -> (mean, sigma)``.

    From :mod:`uavcov.paper`: Table 1 (experiment "table1", d_max = 25 m, 40 terrains) and the
    pyramid prior of section V-D (experiment "pyramid", N = 12, CVT start). ``metric`` is a
    ``runs.csv`` column: "initial_coverage" or "max_coverage".
    """
    from . import paper

    metrics = {"initial": "initial_coverage", "max": "max_coverage"}
    values = {("table1", metrics[kind], init, int(n)): (v.mean, v.sigma)
              for (n, init, kind), v in paper.PUBLISHED_TABLE1.items()}
    for kind, v in paper.PUBLISHED_PYRAMID.items():
        values[("pyramid", metrics[kind], "cvt", 12)] = (v.mean, v.sigma)
    return values


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
    count = _as_positive_int(max_configurations, "max_configurations")
    picks = np.unique(np.rint(np.linspace(0, traj.shape[0] - 1, min(count, traj.shape[0]))).astype(np.int64))
    vis = Visibility(result.terrain, _d_max(result), targets)
    seen = np.zeros(len(vis.targets), dtype=bool)
    for k in picks:
        seen |= vis.seen(traj[k])
    return np.array(vis.targets.points[seen])


def write_ply(points: Any, path: Any, colors: Any = None) -> Path:
    """Write points (and optional 8-bit RGB colours) as an ASCII PLY file.

    Parameters
    ----------
    points : (n, 3) array_like of float
        Metres.
    path : path
        The file to write.
    colors : (n, 3) array_like, optional
        RGB as integers 0-255, or floats in [0, 1].

    Returns
    -------
    Path
    """
    pts = _points(points, "points")
    rgb = None
    if colors is not None:
        rgb = np.asarray(colors)
        if rgb.shape != (pts.shape[0], 3):
            raise InvalidInputError(f"colors must have shape ({pts.shape[0]}, 3), got {rgb.shape}")
        if np.issubdtype(rgb.dtype, np.floating):
            if not np.isfinite(rgb).all() or rgb.min() < 0 or rgb.max() > 1:
                raise InvalidInputError("float colors must lie in [0, 1]")
            rgb = np.rint(rgb * 255)
        elif not np.issubdtype(rgb.dtype, np.integer) or rgb.min(initial=0) < 0 or rgb.max(initial=0) > 255:
            raise InvalidInputError("integer colors must lie in 0..255")
        rgb = rgb.astype(np.int64)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    header = ["ply", "format ascii 1.0", "comment uavcov: surface points seen by the team, metres",
              f"element vertex {pts.shape[0]}", "property double x", "property double y", "property double z"]
    if rgb is not None:
        header += ["property uchar red", "property uchar green", "property uchar blue"]
    header.append("end_header")
    with path.open("w", encoding="ascii", newline="\n") as handle:
        handle.write("\n".join(header) + "\n")
        if pts.shape[0]:
            if rgb is None:
                np.savetxt(handle, pts, fmt="%.6f")
            else:
                table = np.concatenate([pts, rgb.astype(np.float64)], axis=1)
                np.savetxt(handle, table, fmt=["%.6f"] * 3 + ["%d"] * 3)
    return path


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
        A mission (points from :func:`seen_points`; its final positions drawn too), or the
        points themselves.
    positions : (N, 3) array_like, optional
        UAV positions to draw.
    max_points : int
        Most points drawn (evenly thinned); the PLY file gets them all.
    max_configurations : int
        See :func:`seen_points`.
    ax, out, elev, azim, dpi
        As elsewhere.
    ply : path, optional
        Also write every seen point there as ASCII PLY (see :func:`write_ply`).

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
        write_ply(pts, ply)
    fig, ax = _new_axes(ax, three_d=True, figsize=(7.0, 5.6))
    ax.computed_zorder = False
    limit = _as_positive_int(max_points, "max_points")
    shown = pts[:: math.ceil(pts.shape[0] / limit)] if pts.shape[0] > limit else pts
    handles = []
    if shown.shape[0]:
        cloud = ax.scatter(shown[:, 0], shown[:, 1], shown[:, 2], c=shown[:, 2], cmap="viridis",
                           s=max(1.0, min(8.0, 40_000.0 / shown.shape[0])), marker="o", linewidths=0,
                           depthshade=False, zorder=1)
        bar = fig.colorbar(cloud, ax=ax, shrink=0.55, pad=0.14)
        bar.set_label("height of the seen point (m)")
    parts = [shown] if shown.shape[0] else []
    if positions is not None:
        uav = _points(positions, "positions")
        if uav.shape[0]:
            ax.scatter(uav[:, 0], uav[:, 1], uav[:, 2], s=46, c=[END_COLOUR], edgecolors="black",
                       linewidths=0.6, depthshade=False, zorder=3)
            handles.append(_marker("final UAV positions", marker="o", markerfacecolor=END_COLOUR,
                                   markeredgecolor="black", markersize=6))
            parts.append(uav)
    if not parts:
        raise InvalidInputError("nothing to draw: no point was seen and no position was given")
    drawn = f"{shown.shape[0]} of {pts.shape[0]} points drawn" if shown.shape[0] < pts.shape[0] else f"{pts.shape[0]} points"
    of = f" of {total_targets} targets" if total_targets else ""
    handles.insert(0, _marker(f"surface point seen during the mission ({drawn}{of})", marker=".",
                              color=(0.2, 0.5, 0.55), markersize=8))
    _style_3d(ax, _scene_bounds(*parts), elev=elev, azim=azim, title="Point cloud of what the team saw")
    _legend(ax, handles)
    return _finish(fig, out, dpi)


# ---------------------------------------------------------------------------------------------
# The animation


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
    UAVs (green) and their paths so far; right: coverage per iteration up to that point.

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
    out = Path(out)
    suffix = out.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise InvalidInputError(f"the animation is written as .gif or .mp4, got {out.name!r}")
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise InvalidInputError("writing .mp4 needs ffmpeg on the PATH; write a .gif instead")
    if not (isinstance(fps, (int, float)) and math.isfinite(fps) and fps > 0):
        raise InvalidInputError(f"fps must be a positive number, got {fps!r}")
    traj = _trajectory(result.trajectory)
    curve = _curve(result.coverage)
    frames = np.unique(np.rint(np.linspace(0, traj.shape[0] - 1,
                                           min(_as_positive_int(max_frames, "max_frames"), traj.shape[0]))).astype(int))
    d = _d_max(result)
    view = _TopView(result.terrain, d, _as_positive_int(raster, "raster"))

    _matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 4.6), dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    grid = fig.add_gridspec(1, 2, width_ratios=(1.15, 1.0), left=0.07, right=0.98, bottom=0.24, top=0.9, wspace=0.28)
    ax_map = fig.add_subplot(grid[0])
    ax_curve = fig.add_subplot(grid[1])
    picture = ax_map.imshow(view.image(traj[0]), extent=view.extent, origin="lower", interpolation="nearest")
    ax_map.set_xlabel("x (m)")
    ax_map.set_ylabel("y (m)")
    ax_map.set_aspect("equal")
    ax_map.scatter(traj[0, :, 0], traj[0, :, 1], s=14, c=START_COLOUR, zorder=3)
    paths = [ax_map.plot([], [], color="0.1", linewidth=0.8)[0] for _ in range(traj.shape[1])]
    uavs = ax_map.scatter(traj[0, :, 0], traj[0, :, 1], s=36, c=[END_COLOUR], edgecolors="black", linewidths=0.6, zorder=4)
    ax_map.legend(handles=[_patch(SEEN_COLOUR, "seen"), _patch(UNSEEN_COLOUR, "not seen"),
                           _marker("start", marker="o", color=START_COLOUR, markersize=4),
                           _marker("UAV", marker="o", markerfacecolor=END_COLOUR, markeredgecolor="black", markersize=6)],
                  fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.17), ncol=4, framealpha=0.9)
    ax_curve.set_xlim(0, max(1, curve.shape[0] - 1))
    low = float(curve.min())
    ax_curve.set_ylim(max(0.0, low - 0.05), min(1.0, float(curve.max()) + 0.03) + 1e-3)
    ax_curve.set_xlabel("iteration")
    ax_curve.set_ylabel("coverage")
    ax_curve.grid(True, linewidth=0.4, alpha=0.5)
    line = ax_curve.plot([], [], color=INIT_COLOURS.get(getattr(result.settings, "start", ""), "#1f77b4"), linewidth=1.5)[0]
    dot = ax_curve.plot([], [], "o", color="black", markersize=4)[0]
    title = fig.suptitle("", fontsize=10)

    images = []
    for k in frames:
        picture.set_data(view.image(traj[k]))
        for i, p in enumerate(paths):
            p.set_data(traj[: k + 1, i, 0], traj[: k + 1, i, 1])
        uavs.set_offsets(traj[k, :, :2])
        line.set_data(np.arange(k + 1), curve[: k + 1])
        dot.set_data([k], [curve[k]])
        title.set_text(f"iteration {k} of {traj.shape[0] - 1}: coverage {curve[k]:.3f} (d_max = {d:g} m)")
        canvas.draw()
        images.append(np.asarray(canvas.buffer_rgba())[:, :, :3].copy())
    out.parent.mkdir(parents=True, exist_ok=True)
    if suffix == ".gif":
        _write_gif(images, out, fps)
    else:
        _write_mp4(images, out, fps)
    return out


def _write_gif(images: list[np.ndarray], out: Path, fps: float) -> None:
    try:
        from PIL import Image
    except ImportError as exc:
        raise ImportError("GIF animations need Pillow, part of the extra: pip install 'uavcov[plot]'") from exc
    # One palette for all frames keeps colours steady and the file small.
    first = Image.fromarray(images[0]).quantize(colors=128, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    frames = [first] + [Image.fromarray(a).quantize(palette=first, dither=Image.Dither.NONE) for a in images[1:]]
    duration = round(1000.0 / fps)
    durations = [duration] * (len(frames) - 1) + [max(duration, 1500)]  # linger on the result
    frames[0].save(out, save_all=True, append_images=frames[1:], duration=durations, loop=0, optimize=True)


def _write_mp4(images: list[np.ndarray], out: Path, fps: float) -> None:
    import subprocess

    h, w = images[0].shape[:2]
    # yuv420p wants even sizes; pad by one pixel where needed.
    command = ["ffmpeg", "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{w}x{h}",
               "-r", f"{fps:g}", "-i", "-", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p",
               "-vcodec", "libx264", str(out)]
    with subprocess.Popen(command, stdin=subprocess.PIPE, stderr=subprocess.PIPE) as proc:
        assert proc.stdin is not None
        try:
            for a in images:
                proc.stdin.write(np.ascontiguousarray(a).tobytes())
        except BrokenPipeError:
            pass
        proc.stdin.close()
        err = proc.stderr.read().decode(errors="replace") if proc.stderr else ""
        if proc.wait() != 0:
            raise InvalidInputError(f"ffmpeg could not write {out}: {err.strip()}")


# ---------------------------------------------------------------------------------------------
# Every figure of a results directory


def _safe(text: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in text)


def plot_directory(directory: Any, out: Any = None, *, max_runs: int = 6, animation: bool = True,
                   dpi: float = 110.0) -> list[Path]:
    """Redraw every figure of a results directory from what is stored, without rerunning anything.

    Reads ``DIR/runs.csv`` (one row per run) and ``DIR/runs/*.npz`` (runs saved by
    :func:`uavcov.records.save_mission`, named ``<run_id>.npz``; the row with that ``run_id``
    gives the run's experiment and start) and writes, into ``out`` (default ``DIR/figures``):

    - ``<experiment>_max_coverage.png`` and ``<experiment>_initial_coverage.png``: the bars of
      :func:`plot_table1`, beside the paper where it has numbers (only for experiments with
      several runs per start and team size);
    - ``<experiment>_coverage_N<n>_d<d_max>.png``: :func:`plot_coverage_curves` of every stored
      run of that experiment, team size and range, one colour per start (the paper's Fig. 6
      maxima drawn for the "comparison" experiment);
    - for up to ``max_runs`` stored runs (the first of each experiment, start and team size,
      then in name order): ``<run>_approximation.png``, ``<run>_cvt.png`` (CVT starts),
      ``<run>_coverage_map.png``, ``<run>_coverage_top.png``, ``<run>_point_cloud.png`` and
      ``<run>_seen.ply``;
    - ``<run>_animation.gif`` for the first of them when ``animation`` is true.

    ``dpi`` is the resolution of the PNG files.

    Returns
    -------
    list of Path
        The files written, in that order.

    Raises
    ------
    ResultsFormatError
        No such directory, nothing to plot in it, a ``runs.csv`` without a required column, or
        a stored run that cannot be read (the message names the file and what is missing).
    ImportError
        matplotlib is not installed (the ``uavcov[plot]`` extra).
    """
    directory = Path(directory)
    if not directory.is_dir():
        raise ResultsFormatError(f"no results directory at {directory}")
    limit = max(0, int(max_runs))
    target = directory / "figures" if out is None else Path(out)
    runs_csv = directory / "runs.csv"
    run_files = sorted((directory / "runs").glob("*.npz")) if (directory / "runs").is_dir() else []
    if not runs_csv.is_file() and not run_files:
        raise ResultsFormatError(f"{directory} holds neither runs.csv nor runs/*.npz: nothing to plot")
    _matplotlib()
    from . import paper

    written: list[Path] = []
    rows = _read_runs(runs_csv) if runs_csv.is_file() else []
    by_experiment: dict[str, list[dict[str, str]]] = {}
    for row in rows:
        by_experiment.setdefault(str(row.get("experiment") or "runs"), []).append(row)
    for experiment, group in sorted(by_experiment.items()):
        cells: dict[tuple[str, str], int] = {}
        for index, row in enumerate(group):
            if _number(row, "max_coverage", index) is not None:
                key = (str(row["init"]), str(row["n_uavs"]))
                cells[key] = cells.get(key, 0) + 1
        if not cells or max(cells.values()) < 2:
            continue  # one run per bar is a number, not a distribution: the curves show it
        for metric in ("max_coverage", "initial_coverage"):
            if metric not in group[0] or all(_number(r, metric, i) is None for i, r in enumerate(group)):
                continue
            path = target / f"{_safe(experiment)}_{metric}.png"
            _close(plot_table1(group, metric=metric, out=path, dpi=dpi))
            written.append(path)

    # Curves of every stored run; whole results are kept only for the runs drawn one by one.
    row_of = {str(r.get("run_id")): r for r in rows if r.get("run_id")}
    curves: dict[tuple[str, int, float], dict[str, list[Any]]] = {}
    chosen: list[tuple[Path, Any]] = []
    kinds: set[tuple[str, str, int]] = set()
    for f in run_files:
        result = load_mission(f)
        row = row_of.get(f.stem, {})
        experiment = str(row.get("experiment") or "runs")
        init = str(row.get("init") or result.settings.start)
        n, d = int(result.settings.n_uavs), float(result.settings.d_max)
        curves.setdefault((experiment, n, d), {}).setdefault(init, []).append(_Curve(result.coverage))
        if (experiment, init, n) not in kinds and len(chosen) < limit:
            kinds.add((experiment, init, n))
            chosen.append((f, result))
    for f in run_files:
        if len(chosen) >= limit:
            break
        if all(f != c for c, _ in chosen):
            chosen.append((f, load_mission(f)))
    for (experiment, n, d), groups in sorted(curves.items()):
        path = target / f"{_safe(experiment)}_coverage_N{n}_d{d:g}.png"
        reference = dict(paper.PUBLISHED_FIG6_MAX) if experiment == "comparison" else None
        _close(plot_coverage_curves(groups, reference=reference, out=path, dpi=dpi,
                                    title=f"{experiment}: coverage during the optimisation, N = {n}, d_max = {d:g} m"))
        written.append(path)

    for index, (f, r) in enumerate(chosen):
        stem = _safe(f.stem)
        figures: list[tuple[str, Any, dict[str, Any]]] = [("approximation", plot_approximation, {})]
        if r.cvt is not None:
            figures.append(("cvt", plot_cvt, {}))
        figures += [("coverage_map", plot_coverage_map, {}), ("coverage_top", plot_coverage_map, {"view": "top"})]
        for suffix, draw, options in figures:
            path = target / f"{stem}_{suffix}.png"
            _close(draw(r, out=path, dpi=dpi, **options))
            written.append(path)
        ply = target / f"{stem}_seen.ply"
        path = target / f"{stem}_point_cloud.png"
        _close(plot_point_cloud(r, out=path, ply=ply, dpi=dpi))
        written += [path, ply]
        if animation and index == 0:
            written.append(animate_mission(r, target / f"{stem}_animation.gif"))
    return written


class _Curve:
    """Just the coverage curve of a stored run (what the curves figure needs)."""

    def __init__(self, coverage: np.ndarray) -> None:
        self.coverage = np.asarray(coverage)


def _close(fig: Any) -> None:
    """Drop the figure's drawing state at once (figures here are not registered with pyplot)."""
    fig.clear()
