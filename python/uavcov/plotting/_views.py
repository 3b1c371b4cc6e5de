"""How surfaces are drawn: 3D views made of few polygons, and top views made of rasters.

Large surfaces are never drawn target by target. An elevation grid becomes at most
``max_polygons`` quads (each can carry the mean of its grid nodes' values), a fine mesh is
clustered down to that many triangles, a coarse one (an approximating surface S') is cut into
that many so colours can change inside a triangle. Each polygon keeps a probe point on the true
surface where a value (a Voronoi region, seen or not) is evaluated. Polygons are shaded by a
light from the north-west; top views are rasters with a hillshade. The 3D axes styling (limits,
vertical exaggeration, labels, legend under the scene) lives here too.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .._validate import MAX_POLYGONS, as_count, as_finite_float, within_coordinate_bound
from ..engine import Sensor, Targets, Terrain, Visibility
from ..errors import InvalidInputError
from ._canvas import SEEN_COLOUR, UNSEEN_COLOUR

DEFAULT_MAX_POLYGONS = 20_000
"""Most polygons a 3D view draws of one surface: enough for relief, few enough to render in seconds."""
LIGHT = np.array([-1.0, 1.0, 1.4142135623730951]) / 2.0  # from the north-west, 45 degrees up
"""Unit vector towards the light of the shading and the hillshade (x east, y north, z up)."""


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
    """Every ``stride``-th of ``n`` grid lines, and always the last, so the border is kept."""
    idx = np.arange(0, n, stride)
    return idx if idx[-1] == n - 1 else np.r_[idx, n - 1]


def _grid_polygons(terrain: Terrain, max_polygons: int) -> _Polygons:
    """A grid as at most ``max_polygons`` quads over every ``stride``-th node; quads touching a
    nodata node are left out."""
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
    """A mesh as at most ``max_polygons`` triangles: clustered when it has more, subdivided
    when it has fewer (each large triangle cut into up to 64^2 pieces)."""
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
    """The polygons that draw ``terrain``: :func:`_grid_polygons` or :func:`_mesh_polygons`."""
    max_polygons = as_count(max_polygons, "max_polygons", MAX_POLYGONS)
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
        sums: np.ndarray = table[r1 + 1, c1 + 1] - table[r0, c1 + 1] - table[r1 + 1, c0] + table[r0, c0]
        return sums

    n = box(counts)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, box(sums) / np.maximum(n, 1), np.nan)


# ---------------------------------------------------------------------------------------------
# Shading and drawing polygons


def _normals(polys: np.ndarray) -> np.ndarray:
    """Unit normals ``(P, 3)`` of ``(P, 3 or 4, 3)`` polygons (zero for a degenerate one)."""
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
    """``(P, 3)`` colours from ``low`` (fraction 0, and NaN) to ``high`` (fraction 1)."""
    f = np.clip(np.nan_to_num(fraction, nan=0.0), 0.0, 1.0)[:, None]
    colours: np.ndarray = (1.0 - f) * np.asarray(low)[None, :] + f * np.asarray(high)[None, :]
    return colours


def _draw_polygons(ax: Any, polys: np.ndarray, rgb: np.ndarray, *, shade: bool, alpha: float = 1.0, zorder: float = 1.0) -> Any:
    """Add ``(P, k, 3)`` polygons in colours ``rgb`` ``(P, 3 or 4)`` to 3D axes; returns the collection."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    colours = _shade(rgb, polys) if shade else np.asarray(rgb)[:, :3]
    rgba = np.concatenate([colours, np.full((colours.shape[0], 1), alpha)], axis=1)
    # Edges the colour of the faces close the hairline seams antialiasing leaves between them.
    coll = Poly3DCollection(list(polys), facecolors=rgba, edgecolors=rgba, linewidths=0.25, zorder=zorder)
    ax.add_collection3d(coll)
    return coll


# ---------------------------------------------------------------------------------------------
# 3D axes


def _style_3d(ax: Any, bounds: np.ndarray, *, elev: float, azim: float, title: str | None) -> None:
    """Limits from ``bounds`` ``(2, 3)`` (low, high corners, metres), labels, view and title.

    A flat scene is stretched vertically (and the z label says by how much) so relief shows.
    """
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
    ax.set_zlabel("z (m)" if exaggeration < 1.05 else f"z (m, x{exaggeration:.1f})")
    ax.view_init(elev=as_finite_float(elev, "elev"), azim=as_finite_float(azim, "azim"))
    from matplotlib.ticker import MaxNLocator

    # The vertical axis is short on screen: few ticks keep its labels apart.
    ax.zaxis.set_major_locator(MaxNLocator(nbins=4))
    ax.tick_params(labelsize=8, pad=1)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.pane.set_facecolor((0.97, 0.97, 0.97, 1.0))
    if title:
        ax.set_title(title, fontsize=10)


def _scene_bounds(*parts: np.ndarray) -> np.ndarray:
    """``(2, 3)`` low and high corners of every point of ``parts`` (any arrays of 3D points)."""
    stacked = np.concatenate([np.asarray(p, dtype=float).reshape(-1, 3) for p in parts if np.size(p)])
    within_coordinate_bound(stacked, "a figure's points")  # matplotlib's projection turns singular far before 1e300
    return np.stack([stacked.min(axis=0), stacked.max(axis=0)])


def _legend(ax: Any, handles: list[Any]) -> None:
    """Under a 3D axes, where it hides nothing of the scene."""
    ax.legend(handles=handles, fontsize=8, framealpha=0.9, loc="upper center", bbox_to_anchor=(0.5, -0.04), ncol=min(len(handles), 2))


# ---------------------------------------------------------------------------------------------
# A surface as lines


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
    normals = np.asarray(surface.face_normals)
    pair = counts == 2
    a = owner[order[first[pair]]]
    b = owner[order[first[pair] + 1]]
    crease = np.zeros(unique.shape[0], dtype=bool)
    crease[pair] = np.abs(np.einsum("ij,ij->i", normals[a], normals[b])) < math.cos(math.radians(20.0))
    return unique[crease | (counts != 2)], "its creases and borders"


# ---------------------------------------------------------------------------------------------
# Coverage in 3D: the share of each polygon that is seen, and the view that shows it


def _grid_node_mask(terrain: Terrain, seen: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Per grid node the value of the target on it (``seen``: bool gives 1.0 seen, 0.0 not seen,
    or any float per target), NaN where no target stands (nodata)."""
    grid = terrain.grid
    assert grid is not None
    (ox, oy), (dx, dy) = grid.origin, grid.spacing
    j = np.rint((points[:, 0] - ox) / dx).astype(np.int64)
    i = np.rint((points[:, 1] - oy) / dy).astype(np.int64)
    nodes = np.full(grid.shape, np.nan)
    nodes[i, j] = seen.astype(np.float64)
    return nodes


def _coverage_fraction(
    terrain: Terrain, polys: _Polygons, positions: np.ndarray, d_max: float, sensors: Sequence[Sensor] | None = None
) -> np.ndarray:
    """Share of each drawn polygon that is seen, from the engine's mask.

    Grid: the polygon's grid targets (nodes), averaged. Mesh: the polygon's probe point.
    """
    if terrain.grid is not None:
        assert polys.blocks is not None
        targets = terrain.default_targets()
        seen = Visibility(terrain, d_max, targets).seen(positions, sensors=sensors)
        return _block_means(_grid_node_mask(terrain, seen, targets.points), polys.blocks)
    seen = Visibility(terrain, d_max, Targets(polys.probes)).seen(positions, sensors=sensors)
    return seen.astype(np.float64)


def _coverage_3d(
    ax: Any,
    terrain: Terrain,
    pts: np.ndarray,
    d_max: float,
    path: np.ndarray | None,
    *,
    max_polygons: int,
    shade: bool,
    sensors: Sequence[Sensor] | None = None,
) -> Any:
    """Draw the coverage of positions ``pts`` ``(N, 3)`` (poses ``(N, 5)`` with cameras among
    ``sensors``) on 3D axes: the surface blended from not seen to seen, the paths
    ``(K + 1, N, 3)`` (metres) when given, a drop line under each UAV. Returns the surface's
    collection."""
    ax.computed_zorder = False  # paths and UAVs stay in front of the surface
    polys = _surface_polygons(terrain, max_polygons)
    fraction = _coverage_fraction(terrain, polys, pts, d_max, sensors)
    pts = pts[:, :3]
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
    for p, g in zip(pts, ground, strict=True):
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
    """Diffuse light in [0, 1] per cell of heights ``z`` ``(H, W)`` with cell size ``dx``, ``dy`` (m)."""
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
            self.blocks = np.stack([r0, np.minimum(r0 + stride - 1, ny - 1), c0, np.minimum(c0 + stride - 1, nx - 1)], axis=2).reshape(
                -1, 4
            )
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
        # a grid's own targets (None) carry the node normals a camera's view quality needs
        self.visibility = Visibility(terrain, d_max, None if grid is not None else self.targets)

    def fraction(self, positions: np.ndarray, sensors: Sequence[Sensor] | None = None) -> np.ndarray:
        """``self.shape`` shares seen from ``positions`` ``(N, 3)`` (poses ``(N, 5)`` with cameras
        among ``sensors``); NaN off the surface."""
        seen = self.visibility.seen(positions, sensors=sensors)
        if self.terrain.grid is not None:
            nodes = _grid_node_mask(self.terrain, seen, self.targets.points)
            return _block_means(nodes, self.blocks).reshape(self.shape)
        out = np.full(self.valid.shape, np.nan)
        out[self.valid] = seen
        return out.reshape(self.shape)

    def quality_image(self, poses: np.ndarray, sensors: Sequence[Sensor], *, shade: bool = True) -> np.ndarray:
        """``(*self.shape, 4)`` RGBA of the best view quality (viridis, 0-1) where something is seen,
        the not-seen colour elsewhere (:meth:`uavcov.Visibility.quality`)."""
        import matplotlib as mpl

        seen = self.visibility.seen(poses, sensors=sensors)
        value = np.where(seen, self.visibility.quality(poses, sensors=sensors), np.nan)
        if self.terrain.grid is not None:
            per_pixel = _block_means(_grid_node_mask(self.terrain, value, self.targets.points), self.blocks).reshape(self.shape)
        else:
            per_pixel = np.full(self.valid.shape, np.nan)
            per_pixel[self.valid] = value
            per_pixel = per_pixel.reshape(self.shape)
        rgb = np.where(
            np.isnan(per_pixel)[..., None], np.asarray(UNSEEN_COLOUR), mpl.colormaps["viridis"](np.nan_to_num(per_pixel))[..., :3]
        )
        if shade:
            rgb = rgb * self.light[:, :, None]
        rgba = np.concatenate([np.clip(rgb, 0, 1), np.ones((*self.shape, 1))], axis=2)
        rgba[self.nodata] = (1.0, 1.0, 1.0, 0.0)
        return rgba

    def image(self, positions: np.ndarray, *, shade: bool = True, sensors: Sequence[Sensor] | None = None) -> np.ndarray:
        """``(*self.shape, 4)`` RGBA, transparent off the surface, row 0 at the south (``origin="lower"``)."""
        f = self.fraction(positions, sensors)
        rgb = _blend(f.ravel(), UNSEEN_COLOUR, SEEN_COLOUR).reshape(*self.shape, 3)
        if shade:
            rgb = rgb * self.light[:, :, None]
        rgba = np.concatenate([np.clip(rgb, 0, 1), np.ones((*self.shape, 1))], axis=2)
        rgba[self.nodata] = (1.0, 1.0, 1.0, 0.0)
        return rgba


def _top_view(
    terrain: Terrain, pts: np.ndarray, d_max: float, raster: int, *, shade: bool, sensors: Sequence[Sensor] | None = None
) -> tuple[np.ndarray, tuple[float, ...]]:
    """An ``(H, W, 4)`` RGBA image of what positions ``pts`` see, and its ``imshow`` extent (m)."""
    view = _TopView(terrain, d_max, raster)
    return view.image(pts, shade=shade, sensors=sensors), view.extent
