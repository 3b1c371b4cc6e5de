"""The faces of a triangle mesh a point lies on, and the outward normal there.

A structure is made of flat faces meeting at sharp edges: the normal at a point is the *face*
normal of the triangle the point lies on (on an edge or vertex shared by several, the mean of
their distinct planes' normals), not an interpolated vertex normal, which on a coarse mesh
smears an edge over the whole face. The candidate viewpoints of a structure
(:func:`~uavcov.cover.viewpoint_offsets`) and its starts (:func:`uavcov.placement.standoff_start`)
are flown out along these normals. The geometry (closest point, the triangles holding it, their
normals) is the engine's (:meth:`uavcov.Terrain.faces_at_closest`, parry in Rust); this module
only chooses among the triangles.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import as_points
from ..engine import Terrain, as_mesh_surface
from ..errors import InvalidInputError


def closest_faces(surface: Terrain, points: Any, normals: Any = None) -> np.ndarray:
    """The index of the triangle of ``surface`` closest to each point.

    Where several are equally close (an edge, a vertex, or two solids touching face to face, as
    a pier's top under a deck), the one whose normal agrees best with the point's ``normal``
    when given, then the lowest-numbered.

    Parameters
    ----------
    surface : Terrain
    points : (n, 3) array_like of float
    normals : (n, 3) array_like of float, optional
        Each point's surface normal (a target's).

    Returns
    -------
    (n,) int64 ndarray
    """
    surface = as_mesh_surface(surface, "a face normal")
    p = as_points(points, "points", allow_empty=True)
    direction = None if normals is None else as_points(normals, "normals", allow_empty=True)
    if direction is not None and direction.shape != p.shape:
        raise InvalidInputError(f"{direction.shape[0]} normals for {p.shape[0]} points")
    if not p.shape[0]:
        return np.empty(0, dtype=np.int64)
    unit = surface.face_normals
    _, holding = surface.faces_at_closest(p)
    out = np.empty(p.shape[0], dtype=np.int64)
    for k, tied in enumerate(holding):
        best = tied
        if direction is not None and tied.size > 1:
            agreement = unit[tied] @ direction[k]
            best = tied[agreement >= agreement.max() - 1e-9]
        out[k] = best[0]
    return out


def surface_normals(surface: Terrain, points: Any) -> tuple[np.ndarray, np.ndarray]:
    """The closest point of ``surface`` to each point, and the outward face normal there.

    The normal is the right-hand normal of the triangle holding the closest point (faces wound
    counter-clockwise seen from outside); where that point lies on an edge or a vertex shared
    by several triangles, the mean of their distinct unit normals, each plane once (the bisector
    at a box's edge, whatever the triangulation).

    Parameters
    ----------
    surface : Terrain
    points : (n, 3) array_like of float
        Metres.

    Returns
    -------
    closest : (n, 3) float64 ndarray
        The closest points on the surface, metres.
    normals : (n, 3) float64 ndarray
        Unit normals.
    """
    surface = as_mesh_surface(surface, "a face normal")
    p = as_points(points, "points")
    unit = surface.face_normals  # zero for a degenerate face
    closest, holding = surface.faces_at_closest(p)
    normals = np.empty_like(closest)
    for k, faces in enumerate(holding):
        # Each plane once: the two triangles of one flat face must not outvote the other side.
        planes = np.unique(np.round(unit[faces], 9), axis=0) if faces.size else np.zeros((1, 3))
        total = planes.sum(axis=0)
        length = float(np.linalg.norm(total))
        if length < 1e-6 and faces.size:
            # Faces back to back (two solids touching, a fin of zero thickness) cancel: there
            # is no outside there; take the lowest-numbered face's side, deterministically,
            # and leave the flight limits to push the UAV out of the solid it lands in.
            total, length = unit[faces[0]], float(np.linalg.norm(unit[faces[0]]))
        if not length > 0.0:
            raise InvalidInputError(f"no outward normal at surface point {closest[k].tolist()}: its faces are degenerate")
        normals[k] = total / length
    return closest, normals
