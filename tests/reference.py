"""A brute-force numpy reference for the coverage engine, written without looking at it.

Everything here is plain geometry over *all* triangles, with no acceleration structure, so that
the engine (a BVH in Rust) is checked against something that shares none of its code paths:

* segment-triangle intersection by a vectorised Moller-Trumbore test,
* a *grazing* flag for every segment that passes within ``eps`` of a triangle's boundary (an
  edge, or one of the segment's own end points close to a triangle). Outside those flagged
  pairs, the answer "does this segment cross a triangle?" is stable under perturbations smaller
  than ``eps``, so any two correct implementations must agree on it exactly,
* exact point-triangle distances and closest points,
* the highest surface point below a point (a vertical ray), and the piecewise-linear height of
  an elevation grid computed straight from the grid (not from a mesh).

Why the grazing flag is sufficient: if a segment and a (closed, convex) triangle do not
intersect, the distance between them is attained at a boundary point of one of them, i.e. at a
segment end point or on a triangle edge. So when no edge and no end point is within ``eps``,
either the distance is >= ``eps`` (a clear miss) or the segment pierces the triangle's interior
at least ``eps`` away from every edge (a clear hit).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "SHORTEN",
    "GRAZING_EPS",
    "segment_triangle_hits",
    "segments_hit_mesh",
    "VisibilityReference",
    "visibility_reference",
    "point_segment_distance",
    "segment_segment_distance",
    "closest_points_on_triangles",
    "closest_point_on_mesh",
    "mesh_area",
    "triangle_areas",
    "ground_height_mesh",
    "grid_height",
    "grid_mesh",
]

SHORTEN = 0.999
"""The sight segment runs from p to p + SHORTEN * (q - p) (stopped 0.1 % short of the target)."""

GRAZING_EPS = 1e-6
"""Segments closer than this to a triangle's boundary are flagged as grazing (metres)."""

# Cap on segments x triangles per vectorised block, to bound memory (~ a few tens of MB).
_BLOCK = 200_000


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("...k,...k->...", a, b)


def _triangles(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    return vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]


def triangle_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area of each face, ``(F,)`` in m^2."""
    a, b, c = _triangles(vertices, faces)
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)


def mesh_area(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Total surface area in m^2."""
    return float(triangle_areas(vertices, faces).sum())


# --------------------------------------------------------------------------------------------
# distances


def point_segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance from points ``p`` to segments ``[a, b]`` (broadcast over leading axes).

    Returns ``(distance, closest_point)``. A zero-length segment is treated as a point.
    """
    d = b - a
    dd = _dot(d, d)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(dd > 0.0, _dot(p - a, d) / np.where(dd > 0.0, dd, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    closest = a + t[..., None] * d
    return np.linalg.norm(p - closest, axis=-1), closest


def segment_segment_distance(p1: np.ndarray, q1: np.ndarray, p2: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Distance between segments ``[p1, q1]`` and ``[p2, q2]`` (broadcast over leading axes).

    Minimises over the parameter square [0, 1]^2: the unconstrained minimum when it lies inside
    and the segments are not parallel, otherwise the best of the four edges of the square (each a
    point-segment distance). Written this way it handles parallel and zero-length segments
    without special cases.
    """
    d1 = q1 - p1
    d2 = q2 - p2
    r = p1 - p2
    a = _dot(d1, d1)
    e = _dot(d2, d2)
    b = _dot(d1, d2)
    c = _dot(d1, r)
    f = _dot(d2, r)
    denom = a * e - b * b
    candidates = [
        point_segment_distance(p1, p2, q2)[0],
        point_segment_distance(q1, p2, q2)[0],
        point_segment_distance(p2, p1, q1)[0],
        point_segment_distance(q2, p1, q1)[0],
    ]
    best = np.minimum.reduce(candidates)
    # Only trust the interior stationary point when the segments are clearly not parallel.
    scale = np.maximum(a * e, np.finfo(float).tiny)
    ok = denom > 1e-12 * scale
    safe = np.where(ok, denom, 1.0)
    s = (b * f - c * e) / safe
    t = (a * f - b * c) / safe
    inside = ok & (s >= 0.0) & (s <= 1.0) & (t >= 0.0) & (t <= 1.0)
    x1 = p1 + s[..., None] * d1
    x2 = p2 + t[..., None] * d2
    interior = np.linalg.norm(x1 - x2, axis=-1)
    return np.where(inside, np.minimum(best, interior), best)


def closest_points_on_triangles(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Closest point of each triangle ``(a, b, c)`` to ``p`` (broadcast over leading axes).

    The closest point is either the orthogonal projection onto the plane (when it falls inside
    the triangle) or the closest point of one of the three edges; taking the best of these four
    candidates is exact and needs no case analysis. Degenerate triangles use the edges only.
    Returns ``(distance, closest_point)``.
    """
    p, a, b, c = np.broadcast_arrays(p, a, b, c)
    best_d, best_x = point_segment_distance(p, a, b)
    for u, v in ((b, c), (c, a)):
        d, x = point_segment_distance(p, u, v)
        better = d < best_d
        best_d = np.where(better, d, best_d)
        best_x = np.where(better[..., None], x, best_x)
    n = np.cross(b - a, c - a)
    nn = _dot(n, n)
    nondegenerate = nn > 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        proj = p - (_dot(p - a, n) / np.where(nondegenerate, nn, 1.0))[..., None] * n
    inside = nondegenerate.copy()
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= _dot(np.cross(v - u, proj - u), n) >= 0.0
    d = np.linalg.norm(p - proj, axis=-1)
    better = inside & (d < best_d)
    best_d = np.where(better, d, best_d)
    best_x = np.where(better[..., None], proj, best_x)
    return best_d, best_x


def closest_point_on_mesh(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Brute force over all triangles: ``(distance (n,), closest point (n, 3))``."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    a, b, c = _triangles(vertices, faces)
    n_faces = a.shape[0]
    out_d = np.empty(points.shape[0])
    out_x = np.empty_like(points)
    step = max(1, _BLOCK // max(n_faces, 1))
    for start in range(0, points.shape[0], step):
        block = points[start : start + step, None, :]
        d, x = closest_points_on_triangles(block, a[None], b[None], c[None])
        k = np.argmin(d, axis=1)
        rows = np.arange(d.shape[0])
        out_d[start : start + step] = d[rows, k]
        out_x[start : start + step] = x[rows, k]
    return out_d, out_x


# --------------------------------------------------------------------------------------------
# segment against triangles


def segment_triangle_hits(origin: np.ndarray, end: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Moller-Trumbore: does the closed segment ``[origin, end]`` meet triangle ``(a, b, c)``?

    Broadcast over leading axes. Segments parallel to the triangle's plane count as a miss here;
    any such segment that touches the triangle is within ``eps`` of its boundary and is flagged
    by :func:`segments_hit_mesh` as grazing.
    """
    direction = end - origin
    e1 = b - a
    e2 = c - a
    pvec = np.cross(direction, e2)
    det = _dot(e1, pvec)
    scale = np.linalg.norm(direction, axis=-1) * np.linalg.norm(e1, axis=-1) * np.linalg.norm(e2, axis=-1)
    usable = np.abs(det) > 1e-14 * np.maximum(scale, np.finfo(float).tiny)
    inv = 1.0 / np.where(usable, det, 1.0)
    tvec = origin - a
    u = _dot(tvec, pvec) * inv
    qvec = np.cross(tvec, e1)
    v = _dot(direction, qvec) * inv
    t = _dot(e2, qvec) * inv
    return usable & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t >= 0.0) & (t <= 1.0)


def segments_hit_mesh(
    starts: np.ndarray, ends: np.ndarray, vertices: np.ndarray, faces: np.ndarray, *, eps: float = GRAZING_EPS
) -> tuple[np.ndarray, np.ndarray]:
    """For paired closed segments ``[starts[k], ends[k]]``: ``(hit (n,), grazing (n,))``.

    ``hit[k]`` is True when segment k meets any triangle. ``grazing[k]`` is True when segment k
    passes within ``eps`` of a triangle edge, or one of its end points lies within ``eps`` of a
    triangle; only then may a correct implementation answer differently.
    """
    starts = np.asarray(starts, dtype=np.float64).reshape(-1, 3)
    ends = np.asarray(ends, dtype=np.float64).reshape(-1, 3)
    a, b, c = _triangles(vertices, faces)
    n_faces = a.shape[0]
    n = starts.shape[0]
    hit = np.zeros(n, dtype=bool)
    grazing = np.zeros(n, dtype=bool)
    if n == 0 or n_faces == 0:
        return hit, grazing
    # Bounding spheres of the triangles: a cheap filter before the exact boundary distances.
    centre = (a + b + c) / 3.0
    radius = np.max(np.stack([np.linalg.norm(v - centre, axis=1) for v in (a, b, c)]), axis=0)
    step = max(1, _BLOCK // n_faces)
    for start in range(0, n, step):
        s = starts[start : start + step, None, :]
        e = ends[start : start + step, None, :]
        hit[start : start + step] = segment_triangle_hits(s, e, a[None], b[None], c[None]).any(axis=1)
        near = point_segment_distance(centre[None], s, e)[0] <= radius[None] + eps
        rows, cols = np.nonzero(near)
        if rows.size == 0:
            continue
        s0 = starts[start + rows]
        s1 = ends[start + rows]
        ta, tb, tc = a[cols], b[cols], c[cols]
        close = np.zeros(rows.size, dtype=bool)
        for u, v in ((ta, tb), (tb, tc), (tc, ta)):
            close |= segment_segment_distance(s0, s1, u, v) < eps
        for point in (s0, s1):
            close |= closest_points_on_triangles(point, ta, tb, tc)[0] < eps
        flagged = np.zeros(s.shape[0], dtype=bool)
        np.logical_or.at(flagged, rows, close)
        grazing[start : start + step] = flagged
    return hit, grazing


@dataclass(frozen=True)
class VisibilityReference:
    """Brute-force visibility of every UAV-target pair.

    visible : (N, T) bool -- in range and the shortened segment crosses no triangle.
    uncertain : (N, T) bool -- grazing within ``eps`` of a triangle boundary, or at the range
        limit to a relative 1e-9: a correct engine may answer either way for these pairs.
    """

    visible: np.ndarray
    uncertain: np.ndarray

    @property
    def seen(self) -> np.ndarray:
        """(T,) bool: seen by at least one UAV, using certain pairs only."""
        return (self.visible & ~self.uncertain).any(axis=0)

    @property
    def seen_uncertain(self) -> np.ndarray:
        """(T,) bool: targets whose 'seen by any UAV' status depends on an uncertain pair."""
        return ~self.seen & self.uncertain.any(axis=0)

    @property
    def target_uncertain(self) -> np.ndarray:
        """(T,) bool: targets with any uncertain pair (their per-UAV status may differ)."""
        return self.uncertain.any(axis=0)

    def per_uav_seen(self) -> np.ndarray:
        """(N,) int: targets each UAV sees (uncertain pairs counted as seen by the reference)."""
        return self.visible.sum(axis=1)

    def exclusive(self) -> np.ndarray:
        """(N,) int: targets seen by that UAV and by no other."""
        only = self.visible & (self.visible.sum(axis=0) == 1)[None, :]
        return only.sum(axis=1)


def visibility_reference(
    vertices: np.ndarray,
    faces: np.ndarray,
    uavs: np.ndarray,
    targets: np.ndarray,
    d_max: float,
    *,
    shorten: float = SHORTEN,
    eps: float = GRAZING_EPS,
) -> VisibilityReference:
    """Which UAV sees which target: ``|p - q| <= d_max`` and ``[p, p + shorten (q - p)]`` is clear."""
    uavs = np.asarray(uavs, dtype=np.float64).reshape(-1, 3)
    targets = np.asarray(targets, dtype=np.float64).reshape(-1, 3)
    n, t = uavs.shape[0], targets.shape[0]
    dist = np.linalg.norm(uavs[:, None, :] - targets[None, :, :], axis=2)
    in_range = dist <= d_max
    at_limit = np.abs(dist - d_max) <= 1e-9 * d_max
    ui, ti = np.nonzero(in_range | at_limit)
    p = uavs[ui]
    q = targets[ti]
    hit, grazing = segments_hit_mesh(p, p + shorten * (q - p), vertices, faces, eps=eps)
    visible = np.zeros((n, t), dtype=bool)
    uncertain = at_limit.copy()
    visible[ui, ti] = in_range[ui, ti] & ~hit
    uncertain[ui, ti] |= grazing
    return VisibilityReference(visible=visible, uncertain=uncertain)


# --------------------------------------------------------------------------------------------
# heights


def ground_height_mesh(xy: np.ndarray, vertices: np.ndarray, faces: np.ndarray, *, below: np.ndarray | None = None) -> np.ndarray:
    """Highest surface z on the vertical line through each ``(x, y)``; NaN where there is none.

    With ``below`` (n,), only surface points at or under ``below[k]`` count (the first surface
    a vertical ray going down from ``(x, y, below[k])`` meets). Vertical triangles (zero area in
    projection) are skipped: a vertical ray only grazes them.
    """
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    limit = None if below is None else np.asarray(below, dtype=np.float64).reshape(-1)
    a, b, c = _triangles(vertices, faces)
    out = np.full(xy.shape[0], np.nan)
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    keep = np.abs(det) > 1e-12
    a, b, c, det = a[keep], b[keep], c[keep], det[keep]
    step = max(1, _BLOCK // max(a.shape[0], 1))
    tol = 1e-12
    for start in range(0, xy.shape[0], step):
        x = xy[start : start + step, 0:1]
        y = xy[start : start + step, 1:2]
        l1 = ((b[:, 0] - x) * (c[:, 1] - y) - (c[:, 0] - x) * (b[:, 1] - y)) / det
        l2 = ((c[:, 0] - x) * (a[:, 1] - y) - (a[:, 0] - x) * (c[:, 1] - y)) / det
        l3 = 1.0 - l1 - l2
        inside = (l1 >= -tol) & (l2 >= -tol) & (l3 >= -tol)
        z = l1 * a[:, 2] + l2 * b[:, 2] + l3 * c[:, 2]
        if limit is not None:
            inside &= z <= limit[start : start + step, None]
        z = np.where(inside, z, -np.inf)
        best = z.max(axis=1) if z.shape[1] else np.full(z.shape[0], -np.inf)
        out[start : start + step] = np.where(np.isfinite(best), best, np.nan)
    return out


def grid_height(xy: np.ndarray, z: np.ndarray, spacing: tuple[float, float], origin: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """Piecewise-linear height of an elevation grid, straight from the grid values.

    Vertex (i, j) is at ``x = ox + j dx, y = oy + i dy``; each cell is split along the diagonal
    (i, j)-(i+1, j+1). NaN outside the grid and on triangles touching a NaN vertex.
    """
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    z = np.asarray(z, dtype=np.float64)
    dx, dy = spacing
    ox, oy = origin
    ny, nx = z.shape
    gx = (xy[:, 0] - ox) / dx
    gy = (xy[:, 1] - oy) / dy
    outside = (gx < 0) | (gy < 0) | (gx > nx - 1) | (gy > ny - 1)
    j = np.clip(np.floor(gx).astype(np.int64), 0, nx - 2)
    i = np.clip(np.floor(gy).astype(np.int64), 0, ny - 2)
    fx = gx - j
    fy = gy - i
    z00 = z[i, j]
    z01 = z[i, j + 1]
    z10 = z[i + 1, j]
    z11 = z[i + 1, j + 1]
    lower = fx >= fy  # triangle (i,j), (i,j+1), (i+1,j+1)
    h_lower = z00 + fx * (z01 - z00) + fy * (z11 - z01)
    h_upper = z00 + fy * (z10 - z00) + fx * (z11 - z10)
    valid_lower = np.isfinite(z00) & np.isfinite(z01) & np.isfinite(z11)
    valid_upper = np.isfinite(z00) & np.isfinite(z10) & np.isfinite(z11)
    h = np.where(lower, np.where(valid_lower, h_lower, np.nan), np.where(valid_upper, h_upper, np.nan))
    return np.where(outside, np.nan, h)


def grid_mesh(z: np.ndarray, spacing: tuple[float, float], origin: tuple[float, float] = (0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """The grid's triangulation built independently: ``(vertices (ny*nx, 3), faces (F, 3))``.

    All vertices are kept (NaN ones included, with their NaN z); triangles touching a NaN vertex
    are dropped. Vertex (i, j) has index ``i * nx + j``.
    """
    z = np.asarray(z, dtype=np.float64)
    dx, dy = spacing
    ox, oy = origin
    ny, nx = z.shape
    jj, ii = np.meshgrid(np.arange(nx), np.arange(ny))
    vertices = np.column_stack([ox + jj.ravel() * dx, oy + ii.ravel() * dy, z.ravel()])
    i, j = np.meshgrid(np.arange(ny - 1), np.arange(nx - 1), indexing="ij")
    i = i.ravel()
    j = j.ravel()
    v00 = i * nx + j
    v01 = i * nx + j + 1
    v10 = (i + 1) * nx + j
    v11 = (i + 1) * nx + j + 1
    faces = np.concatenate([np.column_stack([v00, v01, v11]), np.column_stack([v00, v11, v10])])
    finite = np.isfinite(vertices[:, 2])
    faces = faces[finite[faces].all(axis=1)]
    return vertices, faces
