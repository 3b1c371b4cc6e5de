"""The faces of a triangle mesh a point lies on, and the outward normal there.

A structure is made of flat faces meeting at sharp edges: the normal at a point is the *face*
normal of the triangle the point lies on (on an edge or vertex shared by several, the mean of
their distinct planes' normals), not an interpolated vertex normal, which on a coarse mesh
smears an edge over the whole face. The candidate viewpoints of a structure
(:func:`~uavcov.cover.viewpoint_offsets`) and its starts (:func:`uavcov.placement.standoff_start`)
are flown out along these normals.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import as_points
from ..engine import Terrain
from ..errors import InvalidInputError, InvalidTypeError

# (point, face) pairs tested at once by the closest-face search, about: bounds its memory (a few
# hundred MB of temporaries), with a point's nearby small faces counted as 32.
_PAIRS_PER_CHUNK = 500_000


def _check_surface(surface: Any) -> Terrain:
    if not isinstance(surface, Terrain):
        raise InvalidTypeError(f"surface must be a uavcov Terrain, got {type(surface).__name__}")
    if surface.n_faces == 0 or surface.area <= 0.0:
        raise InvalidInputError("surface has no area: its faces and normals need a mesh with faces")
    return surface


class _Faces:
    """A mesh's triangles with what the closest-face queries need, computed once."""

    def __init__(self, surface: Terrain) -> None:
        v, f = surface.vertices, surface.faces
        self.a, self.b, self.c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
        self.unit = surface.face_normals  # the engine's; zero for a degenerate face
        self.lo = np.minimum(np.minimum(self.a, self.b), self.c)
        self.hi = np.maximum(np.maximum(self.a, self.b), self.c)
        scale = float(np.abs(surface.bounds).max()) + float(np.ptp(surface.bounds, axis=0).max())
        self.tol = 1e-9 * max(scale, 1.0)

    def holding(self, closest: np.ndarray) -> list[np.ndarray]:
        """For each point on the surface, the faces it lies on (its closest, and any tied)."""
        from scipy.spatial import cKDTree

        # A point inside a face's bounding box lies within half its diagonal of the box's centre:
        # small faces are found by a k-d tree over the centres with the largest such radius, the
        # few large ones (a ground plane's two triangles) by testing each, so that neither a
        # fine mesh nor one huge face makes the search quadratic.
        centre = 0.5 * (self.lo + self.hi)
        half = 0.5 * np.linalg.norm(self.hi - self.lo, axis=1)
        # At most about 1 % of the faces count as large, so the brute-force part stays small.
        large = half > max(4.0 * float(np.median(half)), float(np.quantile(half, 0.99))) + self.tol
        big, small = np.flatnonzero(large), np.flatnonzero(~large)
        tree = cKDTree(centre[small]) if small.size else None
        radius = float(half[small].max()) + self.tol if small.size else 0.0
        out: list[np.ndarray] = []
        step = max(1, _PAIRS_PER_CHUNK // (big.size + 32))
        for start in range(0, closest.shape[0], step):
            chunk = closest[start : start + step]
            n = chunk.shape[0]
            point_parts, face_parts = [np.repeat(np.arange(n), big.size)], [np.tile(big, n)]
            if tree is not None:
                nearby = tree.query_ball_point(chunk, r=radius)
                counts = np.fromiter((len(found) for found in nearby), dtype=np.int64, count=n)
                point_parts.append(np.repeat(np.arange(n), counts))
                flat = np.fromiter((f for found in nearby for f in found), dtype=np.int64, count=int(counts.sum()))
                face_parts.append(small[flat])
            # Every (point, candidate face) pair at once: the box test, then the exact distance.
            point, face = np.concatenate(point_parts), np.concatenate(face_parts)
            q = chunk[point]
            inside = ((q >= self.lo[face] - self.tol) & (q <= self.hi[face] + self.tol)).all(axis=1)
            point, face, q = point[inside], face[inside], q[inside]
            distance = _triangle_distance(q, self.a[face], self.b[face], self.c[face])
            least = np.full(n, np.inf)
            np.minimum.at(least, point, distance)
            tied = distance <= least[point] + self.tol
            point, face = point[tied], face[tied]
            order = np.lexsort((face, point))
            point, face = point[order], face[order]
            out.extend(np.split(face, np.searchsorted(point, np.arange(1, n))))
        return out


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
    surface = _check_surface(surface)
    p = as_points(points, "points", allow_empty=True)
    direction = None if normals is None else as_points(normals, "normals", allow_empty=True)
    if direction is not None and direction.shape != p.shape:
        raise InvalidInputError(f"{direction.shape[0]} normals for {p.shape[0]} points")
    if not p.shape[0]:
        return np.empty(0, dtype=np.int64)
    faces = _Faces(surface)
    out = np.empty(p.shape[0], dtype=np.int64)
    for k, tied in enumerate(faces.holding(surface.closest_point(p))):
        best = tied
        if direction is not None and tied.size > 1:
            agreement = faces.unit[tied] @ direction[k]
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
    surface = _check_surface(surface)
    p = as_points(points, "points")
    closest = surface.closest_point(p)
    faces = _Faces(surface)
    normals = np.empty_like(closest)
    for k, holding in enumerate(faces.holding(closest)):
        # Each plane once: the two triangles of one flat face must not outvote the other side.
        planes = np.unique(np.round(faces.unit[holding], 9), axis=0) if holding.size else np.zeros((1, 3))
        total = planes.sum(axis=0)
        length = float(np.linalg.norm(total))
        if length < 1e-6 and holding.size:
            # Faces back to back (two solids touching, a fin of zero thickness) cancel: there
            # is no outside there; take the lowest-numbered face's side, deterministically,
            # and leave the flight limits to push the UAV out of the solid it lands in.
            total, length = faces.unit[holding[0]], float(np.linalg.norm(faces.unit[holding[0]]))
        if not length > 0.0:
            raise InvalidInputError(f"no outward normal at surface point {closest[k].tolist()}: its faces are degenerate")
        normals[k] = total / length
    return closest, normals


def _triangle_distance(q: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Distance from each ``q`` (one point, or one per triangle) to each triangle ``(a, b, c)``
    (the closest point by Ericson's regions)."""
    ab, ac, ap = b - a, c - a, q - a
    d1, d2 = (ab * ap).sum(1), (ac * ap).sum(1)
    bp = q - b
    d3, d4 = (ab * bp).sum(1), (ac * bp).sum(1)
    cp = q - c
    d5, d6 = (ab * cp).sum(1), (ac * cp).sum(1)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denominator = va + vb + vc
        v = np.where(denominator != 0, vb / denominator, 0.0)
        w = np.where(denominator != 0, vc / denominator, 0.0)
        closest = a + ab * v[:, None] + ac * w[:, None]  # inside the face
        # The vertex and edge regions, most specific last so that they win.
        t_bc = np.clip(np.where((d4 - d3) + (d5 - d6) != 0, (d4 - d3) / ((d4 - d3) + (d5 - d6)), 0.0), 0.0, 1.0)
        closest = np.where(((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0))[:, None], b + (c - b) * t_bc[:, None], closest)
        t_ac = np.clip(np.where(d2 - d6 != 0, d2 / (d2 - d6), 0.0), 0.0, 1.0)
        closest = np.where(((vb <= 0) & (d2 >= 0) & (d6 <= 0))[:, None], a + ac * t_ac[:, None], closest)
        t_ab = np.clip(np.where(d1 - d3 != 0, d1 / (d1 - d3), 0.0), 0.0, 1.0)
        closest = np.where(((vc <= 0) & (d1 >= 0) & (d3 <= 0))[:, None], a + ab * t_ab[:, None], closest)
    closest = np.where(((d6 >= 0) & (d5 <= d6))[:, None], c, closest)
    closest = np.where(((d3 >= 0) & (d4 <= d3))[:, None], b, closest)
    closest = np.where(((d1 <= 0) & (d2 <= 0))[:, None], a, closest)
    distance: np.ndarray = np.linalg.norm(q - closest, axis=1)
    return distance
