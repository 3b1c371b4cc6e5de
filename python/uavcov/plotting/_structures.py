"""A structure coloured by what the team sees, from several sides at once.

A height field shows everything from above; a bridge hides its deck's underside from every view
above the deck. :func:`plot_structure_seen` therefore draws the same coloured mesh in several 3D
axes, by default from the four quarters above and once from below. Each face is coloured by
the (weighted) share of its targets that is seen, from the unseen colour to the seen colour, and
shaded by the figures' north-west light so the faces' orientation reads. Faces turned away from
a view are not drawn (the meshes are wound outward). Views from below leave the
ground out (by default the upward faces at the scene's lowest height), which would hide the rest.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .._validate import as_bool_array, as_float_array, as_optional_str, as_points, as_positive_int
from ..cover import closest_faces
from ..engine import Targets, Terrain
from ..errors import InvalidInputError, InvalidTypeError
from ..structures import Structure
from ._canvas import END_COLOUR, SEEN_COLOUR, UNSEEN_COLOUR, _finish, _marker, _matplotlib, _patch
from ._views import DEFAULT_MAX_POLYGONS, _blend, _draw_polygons, _mesh_polygons, _scene_bounds, _style_3d

STRUCTURE_VIEWS: tuple[tuple[float, float], ...] = ((30.0, -60.0), (30.0, 120.0), (8.0, 30.0), (-30.0, -60.0))
"""Default ``(elevation, azimuth)`` of the views, degrees: two opposite quarters from above, one
low from the side, one from below (without the ground, which would hide everything)."""


def _numbers(seen: Any) -> np.ndarray:
    """Seen flags, counts or shares as floats (a bool array is welcome here)."""
    return as_float_array(seen, "seen", ndim=1, allow_bool=True)


def face_seen_share(surface: Terrain, targets: Targets, seen: Any) -> np.ndarray:
    """Per face of ``surface``, the weighted share of the targets on it that are seen (NaN where none lies).

    Each target belongs to its closest face (:func:`uavcov.cover.closest_faces`; between
    faces that touch, the one facing as the target's normal says).
    """
    if not isinstance(targets, Targets):
        raise InvalidTypeError(f"targets must be a uavcov.Targets, got {type(targets).__name__}")
    flags = _numbers(seen)
    if flags.shape[0] != len(targets):
        raise InvalidInputError(f"seen has {flags.shape[0]} flags for {len(targets)} targets")
    face = closest_faces(surface, targets.points, targets.normals)
    weight = np.bincount(face, weights=targets.weights, minlength=surface.n_faces)
    hit = np.bincount(face, weights=targets.weights * (flags > 0), minlength=surface.n_faces)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(weight > 0, hit / np.where(weight > 0, weight, 1.0), np.nan)


def _mesh_and_ground(surface: Any, ground: Any) -> tuple[Terrain, Any]:
    """A :class:`Structure`'s mesh and ground faces (``ground`` when given), or a Terrain as it is."""
    if isinstance(surface, Structure):
        if ground is None and surface.ground_part is not None:
            ground = surface.face_parts == surface.ground_part
        return surface.surface, ground
    if not isinstance(surface, Terrain):
        raise InvalidTypeError(f"surface must be a uavcov Terrain or Structure, got {type(surface).__name__}")
    return surface, ground


def plot_structure_seen(
    surface: Terrain | Structure,
    seen: Any,
    *,
    targets: Targets | None = None,
    positions: Any = None,
    views: Sequence[tuple[float, float]] = STRUCTURE_VIEWS,
    ground: Any = None,
    max_polygons: int = DEFAULT_MAX_POLYGONS,
    title: str | None = None,
    out: Any = None,
    dpi: float = 110.0,
) -> Any:
    """The structure coloured by seen, from several sides (one 3D axes per view).

    Parameters
    ----------
    surface : Terrain or Structure
        The structure's mesh (ground included or not), or the :class:`~uavcov.structures.Structure`
        itself (its ground part is then the default ``ground``).
    seen : (F,) or (T,) array_like
        Per face, the share seen in ``[0, 1]`` (or a bool), NaN where unknown; or, with
        ``targets``, per target whether it is seen (a bool or a count of UAVs).
    targets : Targets, optional
        The targets ``seen`` is about; each face then shows the share of its targets seen
        (``face_seen_share``).
    positions : (N, 3) array_like, optional
        UAVs to draw.
    views : sequence of (elevation, azimuth)
        Degrees, one axes each, 1 to 12 of them; a negative elevation looks from below.
    ground : (F,) array_like of bool, optional
        The faces views from below leave out; by default those facing up (within 1 degree)
        with every vertex at the scene's lowest height.
    max_polygons : int
        A finer mesh is clustered down to about this many triangles for drawing (each drawn
        triangle takes the value of the face under its centre).
    title : str, optional
    out : path, optional
        Save the figure there.
    dpi : float

    Returns
    -------
    matplotlib.figure.Figure
    """
    surface, ground = _mesh_and_ground(surface, ground)
    if surface.n_faces == 0:
        raise InvalidInputError("the surface has no faces to draw")
    if targets is not None:
        share = face_seen_share(surface, targets, seen)
    else:
        share = _numbers(seen)
        if share.shape[0] != surface.n_faces:
            raise InvalidInputError(f"seen has {share.shape[0]} values for {surface.n_faces} faces (give targets= for per-target flags)")
        if (share[np.isfinite(share)] < 0).any() or (share[np.isfinite(share)] > 1).any():
            raise InvalidInputError("seen: per-face shares must lie in [0, 1]")
    angles = [tuple(float(v) for v in as_float_array(view, "view")) for view in views] if isinstance(views, Sequence) else []
    if not 1 <= len(angles) <= 12 or any(len(a) != 2 or not np.isfinite(a).all() for a in angles):
        raise InvalidInputError(f"views must be 1 to 12 finite (elevation, azimuth) pairs, got {views!r}")
    limit = as_positive_int(max_polygons, "max_polygons")
    uavs = None if positions is None else as_points(positions, "positions")

    triangles = surface.vertices[surface.faces]
    if ground is None:
        up = surface.face_normals[:, 2] >= np.cos(np.radians(1.0))
        low = float(surface.bounds[0][2])
        floor = np.isclose(triangles[:, :, 2], low, rtol=0.0, atol=1e-9 * (1.0 + abs(low))).all(axis=1)
        ground_mask = up & floor
    else:
        ground_mask = as_bool_array(ground, "ground", surface.n_faces)
    if surface.n_faces > limit:
        drawn = _mesh_polygons(surface, limit)
        polys = drawn.polys
        face = closest_faces(surface, drawn.probes)
    else:
        polys = triangles
        face = np.arange(surface.n_faces)
    colours = _blend(share[face], UNSEEN_COLOUR, SEEN_COLOUR)
    above_ground = ~ground_mask[face]
    facing = surface.face_normals[face]  # each drawn polygon's face, the engine's normal

    _matplotlib()
    from matplotlib.figure import Figure

    columns = 2 if len(angles) == 4 else min(len(angles), 3)
    rows = -(-len(angles) // columns)
    # Rows as tall as the views' flat boxes need (a structure is long and low), and room between
    # columns for the z labels of two neighbouring views, which face each other.
    height = 2.9 * rows + 1.05
    fig = Figure(figsize=(5.0 * columns, height))
    fig.subplots_adjust(left=0.02, right=0.96, bottom=0.3 / height, top=1.0 - 0.75 / height, wspace=0.22, hspace=0.1)
    bounds = _scene_bounds(surface.vertices, *([uavs] if uavs is not None else []))
    for k, (elev, azim) in enumerate(angles):
        ax = fig.add_subplot(rows, columns, k + 1, projection="3d")
        ax.computed_zorder = False
        keep = above_ground if elev < 0 else np.ones(len(polys), dtype=bool)
        # Back faces culled: a closed solid hides them anyway, and matplotlib's painter's sort
        # (by each polygon's centre) would draw some of them over the front ones.
        e, a = np.radians(elev), np.radians(azim)
        keep &= facing @ np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)]) > 0.0
        _draw_polygons(ax, polys[keep], colours[keep], shade=True, zorder=1)
        if uavs is not None and uavs.shape[0]:
            ax.scatter(
                uavs[:, 0], uavs[:, 1], uavs[:, 2], s=30, c=[END_COLOUR], edgecolors="black", linewidths=0.5, depthshade=False, zorder=3
            )
        side = "below, without the ground" if elev < 0 else "above"
        _style_3d(ax, bounds, elev=elev, azim=azim, title=f"from {side} (elevation {elev:g}, azimuth {azim:g} deg)")
        ax.set_box_aspect(ax.get_box_aspect(), zoom=1.15)  # the scene fills its panel, not its ticks' margin
    seen_area = float(np.nansum(np.nan_to_num(share) * surface.face_areas))
    known_area = float(surface.face_areas[np.isfinite(share)].sum())
    handles = [_patch(SEEN_COLOUR, "seen"), _patch(UNSEEN_COLOUR, "not seen")]
    if uavs is not None:
        handles.append(_marker("UAVs", marker="o", markerfacecolor=END_COLOUR, markeredgecolor="black", markersize=6))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=9, bbox_to_anchor=(0.5, 0.0))
    share_text = f"{100.0 * seen_area / known_area:.1f} % of the area seen" if known_area > 0 else "no target"
    fig.suptitle(as_optional_str(title, "title") or f"structure coloured by seen: {share_text}", fontsize=11)
    return _finish(fig, out, dpi)
