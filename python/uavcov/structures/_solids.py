"""Closed solids for the structure scenes: lofts through polygon rings (boxes, frusta, blades,
slanted braces, arches), unions of axis-aligned cells (decks, facades) and a ground sheet.

Every solid is a list of ``(vertices, faces, labels)`` pieces; faces are wound counter-clockwise
seen from outside (right-hand normal outward), each piece is closed (every edge shared by
exactly two faces, once in each direction). Nothing here is public: the scenes in
:mod:`._structures` put pieces together.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from .._validate import MAX_GRID_CELLS, as_positive_float
from ..engine import Terrain
from ..errors import InvalidInputError


@dataclass(frozen=True)
class Piece:
    """One closed solid (or the open ground sheet) with a part name per face."""

    vertices: np.ndarray  # (V, 3) float64
    faces: np.ndarray  # (F, 3) int64
    parts: tuple[str, ...]  # (F,) part name of each face


def signed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Volume enclosed by a closed mesh: positive when its normals point outward (divergence theorem)."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def wound_inward(vertices: np.ndarray, faces: np.ndarray) -> bool:
    """Whether ``faces`` close up (every edge in two faces, run both ways) and enclose a negative
    volume: a whole model exported inside out. Open or non-manifold meshes are not judged
    (their volume means nothing)."""
    if faces.shape[0] == 0:
        return False
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    forward = np.unique(directed, axis=0)
    if forward.shape[0] != directed.shape[0]:
        return False  # an edge run the same way twice: not a consistently wound closed mesh
    if not np.array_equal(forward, np.unique(directed[:, ::-1], axis=0)):
        return False  # an open edge
    return signed_volume(vertices - vertices[np.unique(faces)].mean(axis=0), faces) < 0.0  # centred: less round-off


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit right-hand normals ``(F, 3)`` and areas ``(F,)`` of the faces (none of zero area:
    the engine refuses them), from the engine (the one owner of mesh geometry)."""
    if not faces.shape[0]:
        return np.empty((0, 3)), np.empty(0)
    surface = Terrain(vertices, faces)
    return np.array(surface.face_normals), np.array(surface.face_areas)


def _outward(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    # Built with either winding depending on the ring direction; the volume sign settles it.
    return faces if signed_volume(vertices, faces) > 0 else faces[:, ::-1].copy()


def _labels_by_direction(vertices: np.ndarray, faces: np.ndarray, name: str, up: str | None, down: str | None) -> tuple[str, ...]:
    normals, _ = face_normals(vertices, faces)
    labels = np.full(faces.shape[0], name, dtype=object)
    if up is not None:
        labels[normals[:, 2] > 0.5] = up
    if down is not None:
        labels[normals[:, 2] < -0.5] = down
    return tuple(str(label) for label in labels)


def loft(
    rings: np.ndarray, name: str, *, up: str | None = None, down: str | None = None, caps: tuple[str | None, str | None] = (None, None)
) -> Piece:
    """A closed tube through ``rings`` ``(k, m, 3)`` (k >= 2 rings of m >= 3 points, each convex
    and in order around it), capped at both ends by a fan from the ring's centroid.

    Faces whose normal points up (down) more than 60 degrees from the horizontal are named
    ``up`` (``down``) when given, the rest ``name``; ``caps`` names the first and last caps
    (``"contact"`` for a cap pressed against another solid, which gets no targets).
    """
    k, m, _ = rings.shape
    centroids = rings.mean(axis=1)
    vertices = np.concatenate([rings.reshape(-1, 3), centroids[[0, -1]]])
    i = np.arange(k - 1)[:, None] * m
    j = np.arange(m)[None, :]
    a, b = i + j, i + (j + 1) % m
    c, d = a + m, b + m
    sides = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    first, last = k * m, k * m + 1
    ring = np.arange(m)
    cap0 = np.stack([np.full(m, first), (ring + 1) % m, ring], -1)
    cap1 = np.stack([np.full(m, last), (k - 1) * m + ring, (k - 1) * m + (ring + 1) % m], -1)
    faces = _outward(vertices, np.concatenate([sides, cap0, cap1]).astype(np.int64))
    labels = list(_labels_by_direction(vertices, faces, name, up, down))
    n_sides = sides.shape[0]
    for which, cap_name in enumerate(caps):
        if cap_name is not None:
            start = n_sides + which * m
            labels[start : start + m] = [cap_name] * m
    return Piece(vertices, faces, tuple(labels))


def box(
    lo: tuple[float, float, float],
    hi: tuple[float, float, float],
    name: str,
    *,
    up: str | None = None,
    down: str | None = None,
    step: float | None = None,
) -> Piece:
    """An axis-aligned box, cut along its longest axis into slices of at most ``step`` metres."""
    lo_, hi_ = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    axis = int(np.argmax(hi_ - lo_))
    others = [q for q in range(3) if q != axis]
    n = 1 if step is None else max(1, int(np.ceil((hi_[axis] - lo_[axis]) / step)))
    square = [(0, 0), (1, 0), (1, 1), (0, 1)]
    rings = np.empty((n + 1, 4, 3))
    for r, t in enumerate(np.linspace(lo_[axis], hi_[axis], n + 1)):
        for s, (u, v) in enumerate(square):
            rings[r, s, axis] = t
            rings[r, s, others[0]] = (lo_, hi_)[u][others[0]]
            rings[r, s, others[1]] = (lo_, hi_)[v][others[1]]
    return loft(rings, name, up=up, down=down)


def ellipse_ring(centre: np.ndarray, u: np.ndarray, v: np.ndarray, ru: float, rv: float, sides: int, phase: float = 0.0) -> np.ndarray:
    """``sides`` points on the ellipse ``centre + ru cos(t) u + rv sin(t) v`` ``(sides, 3)``."""
    t = phase + 2.0 * np.pi * np.arange(sides) / sides
    return centre + np.outer(ru * np.cos(t), u) + np.outer(rv * np.sin(t), v)


def frustum(
    base: np.ndarray,
    axis: np.ndarray,
    radii: tuple[float, float],
    name: str,
    *,
    sides: int,
    slices: int = 1,
    flat: tuple[float, float] = (1.0, 1.0),
    phase: float = 0.0,
    across: np.ndarray | None = None,
    caps: tuple[str | None, str | None] = (None, None),
) -> Piece:
    """A tapered tube from ``base`` along ``axis`` (its length is the tube's), radii from
    ``radii[0]`` to ``radii[1]``; ``flat`` scales the second cross-section axis at each end
    (a thin blade is a frustum with ``flat`` well below 1), ``across`` the direction of the
    first cross-section axis (perpendicular to ``axis``; any when omitted)."""
    length = float(np.linalg.norm(axis))
    w = axis / length
    if across is None:
        helper = np.array([0.0, 0.0, 1.0]) if abs(w[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
        u = np.cross(w, helper)
    else:
        u = np.asarray(across, dtype=np.float64).copy()
    u /= np.linalg.norm(u)
    v = np.cross(w, u)
    rings = []
    for t in np.linspace(0.0, 1.0, slices + 1):
        r = radii[0] + t * (radii[1] - radii[0])
        f = flat[0] + t * (flat[1] - flat[0])
        rings.append(ellipse_ring(base + t * axis, u, v, r, r * f, sides, phase))
    return loft(np.asarray(rings), name, caps=caps)


def cells(
    xs: np.ndarray,
    ys: np.ndarray,
    zs: np.ndarray,
    labels: np.ndarray,
    names: tuple[str, ...],
    *,
    up: dict[int, str] | None = None,
    down: dict[int, str] | None = None,
) -> Piece:
    """The union of the occupied cells of a rectilinear grid as one closed surface.

    ``labels`` ``(nx, ny, nz)`` holds -1 for empty cells, else an index into ``names``; the cell
    ``(i, j, k)`` is ``[xs[i], xs[i+1]] x [ys[j], ys[j+1]] x [zs[k], zs[k+1]]``. A face is kept
    where an occupied cell meets an empty one (or the grid's side), named after the occupied
    cell (``up``/``down`` rename the up- or down-facing faces of a label). Cells that meet only
    along an edge would make the surface non-manifold: the scenes never place them so.
    """
    nodes = np.stack(np.meshgrid(xs, ys, zs, indexing="ij"), -1)
    nx, ny, nz = labels.shape
    index = np.arange((nx + 1) * (ny + 1) * (nz + 1)).reshape(nx + 1, ny + 1, nz + 1)
    padded = np.full((nx + 2, ny + 2, nz + 2), -1, dtype=np.int64)
    padded[1:-1, 1:-1, 1:-1] = labels
    quads: list[np.ndarray] = []
    names_of: list[np.ndarray] = []
    directions: list[np.ndarray] = []
    for axis in range(3):
        for sign in (1, -1):
            shift = [0, 0, 0]
            shift[axis] = sign
            neighbour = np.roll(padded, -sign, axis=axis)[1:-1, 1:-1, 1:-1]
            exposed = (labels >= 0) & (neighbour < 0)
            i, j, k = np.nonzero(exposed)
            # The quad's corners on the cell side facing the neighbour, in order around it; the
            # winding is set per face below from the known outward direction.
            base = [i, j, k]
            base[axis] = base[axis] + (1 if sign > 0 else 0)
            a1, a2 = [q for q in range(3) if q != axis]
            corners = []
            for d1, d2 in ((0, 0), (1, 0), (1, 1), (0, 1)):
                c = list(base)
                c[a1] = c[a1] + d1
                c[a2] = c[a2] + d2
                corners.append(index[c[0], c[1], c[2]])
            quads.append(np.stack(corners, -1))
            names_of.append(labels[i, j, k])
            directions.append(np.full(i.shape[0], sign * (axis + 1)))
    quad = np.concatenate(quads)
    label = np.concatenate(names_of)
    direction = np.concatenate(directions)
    faces = np.concatenate([quad[:, [0, 1, 2]], quad[:, [0, 2, 3]]])
    label = np.concatenate([label, label])
    direction = np.concatenate([direction, direction])
    used, faces = np.unique(faces, return_inverse=True)
    faces = faces.reshape(-1, 3).astype(np.int64)
    vertices = nodes.reshape(-1, 3)[used]
    normals, _ = face_normals(vertices, faces)
    outward = np.zeros((faces.shape[0], 3))
    outward[np.arange(faces.shape[0]), np.abs(direction) - 1] = np.sign(direction)
    inward = np.einsum("ij,ij->i", normals, outward) < 0
    faces[inward] = faces[inward][:, ::-1]
    part = [names[int(q)] for q in label]
    for mapping, wanted in ((up, 3), (down, -3)):
        for q, new in (mapping or {}).items():
            for f in np.nonzero((label == q) & (direction == wanted))[0]:
                part[f] = new
    return Piece(vertices, faces, tuple(part))


def refine(breaks: list[float], step: float) -> np.ndarray:
    """The sorted distinct ``breaks`` with points added so no gap exceeds ``step``.

    ``step`` is the user's (a structure's ``step``): checked here, where every builder meets it,
    and before the points are made (at most ``MAX_GRID_CELLS`` along the cuts).
    """
    step = as_positive_float(step, "step")
    values = np.unique(np.asarray(breaks, dtype=np.float64))
    if (values[-1] - values[0]) / step > MAX_GRID_CELLS:
        raise InvalidInputError(
            f"step = {step} m cuts {values[-1] - values[0]:.1f} m into more than {MAX_GRID_CELLS:,} pieces (uavcov's size limit)"
        )
    out = [values[0]]
    for lo, hi in itertools.pairwise(values):
        n = max(1, int(np.ceil((hi - lo) / step - 1e-9)))
        out.extend(lo + (hi - lo) * np.arange(1, n + 1) / n)
    return np.asarray(out)


def ground(xmin: float, xmax: float, ymin: float, ymax: float, step: float, z: float = 0.0) -> Piece:
    """A flat open sheet at height ``z``, triangulated on a grid of about ``step`` metres, facing up."""
    xs = refine([xmin, xmax], step)
    ys = refine([ymin, ymax], step)
    x, y = np.meshgrid(xs, ys, indexing="ij")
    vertices = np.column_stack([x.ravel(), y.ravel(), np.full(x.size, z)])
    ny = ys.size
    i, j = np.meshgrid(np.arange(xs.size - 1), np.arange(ny - 1), indexing="ij")
    a = (i * ny + j).ravel()
    b, c, d = a + ny, a + ny + 1, a + 1
    faces = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).astype(np.int64)
    return Piece(vertices, faces, ("ground",) * faces.shape[0])


def join(pieces: list[Piece]) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Concatenate pieces (no welding: touching solids stay separate closed surfaces)."""
    vertices: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    parts: list[str] = []
    offset = 0
    for piece in pieces:
        vertices.append(piece.vertices)
        faces.append(piece.faces + offset)
        parts.extend(piece.parts)
        offset += piece.vertices.shape[0]
    return np.concatenate(vertices), np.concatenate(faces), parts
