"""The outer surface of a structure from known points: what a team flying outside it can see.

Three pieces, shared by every reconstruction method of :func:`reconstruct_structure`:

:func:`check_prior_points`
    What goes into a reconstruction (scipy's Delaunay, Open3D's Poisson and ball pivoting) is
    checked first: finite, within the coordinate bound, enough *distinct* points, spanning a
    volume (not all on a line or a plane). A foreign library given a degenerate cloud crashes
    (Open3D's Poisson segfaults on 50 equal points) or invents a surface (3,632 faces from 50
    collinear points), so nothing degenerate reaches it.
:func:`alpha_solid`
    The alpha shape's solid with its cavities filled: the Delaunay tetrahedra of circumradius
    at most alpha, plus every other tetrahedron that the outside cannot reach (a flood from the
    convex hull through the tetrahedra not kept). Points sampled on a solid's surface leave its
    interior to large tetrahedra, which the plain alpha shape drops: its boundary then has an
    inner shell facing into the structure (40-45 % of its area on a box, issue 42). The filled
    solid's boundary is the outer surface only, each face wound away from its solid tetrahedron.
:func:`outer_shells`
    For a surface made elsewhere (Open3D): its connected pieces, each kept only if no other
    piece encloses it (ray parity), turned outward by its signed volume when closed, else by the
    known points' normals.

:func:`separate_groups`
    Known points in groups far apart (buildings 200 m apart on a campus) are separate
    structures: each is reconstructed alone, so S' does not span the air between them.
"""

from __future__ import annotations

import numpy as np

from .._validate import within_coordinate_bound
from ..errors import InvalidInputError
from ._solids import face_normals, signed_volume

# A cloud whose thinnest extent (smallest singular value of its centred points) is below this
# share of its largest spans no volume: a plane or a line up to rounding.
FLAT_SHARE = 1e-6


def check_prior_points(points: np.ndarray, normals: np.ndarray | None, min_points: int) -> None:
    """Refuse a point cloud no reconstruction can make a solid from.

    Raises
    ------
    InvalidInputError
        Non-finite or huge coordinates, fewer than ``min_points`` distinct points, points on a
        line or a plane, or normals that are not finite non-zero vectors.
    """
    if not np.isfinite(points).all():
        raise InvalidInputError("the known points contain NaN or infinite coordinates")
    within_coordinate_bound(points, "the known points")  # as the engine's meshes
    distinct = np.unique(points, axis=0).shape[0]
    if distinct < min_points:
        raise InvalidInputError(
            f"{distinct} distinct known points (of {points.shape[0]}) are too sparse to reconstruct a structure (at least {min_points})"
        )
    centred = points - points.mean(axis=0)
    spread = np.linalg.svd(centred, compute_uv=False)
    if not spread[2] > FLAT_SHARE * spread[0]:
        shape = "a line" if not spread[1] > FLAT_SHARE * spread[0] else "a plane"
        raise InvalidInputError(f"the known points lie on {shape} (they span no volume): no solid can be made from them")
    if normals is not None:
        length = np.linalg.norm(normals, axis=1)
        if not (np.isfinite(length).all() and (length > 0).all()):
            raise InvalidInputError("the known points' normals must be finite, non-zero vectors")


def _circumradii(points: np.ndarray, tetra: np.ndarray) -> np.ndarray:
    p = points[tetra]
    a = p[:, 1:] - p[:, :1]  # (T, 3, 3)
    rhs = 0.5 * np.einsum("tij,tij->ti", a, a)
    det = np.linalg.det(a)
    flat = np.abs(det) <= 1e-12 * np.abs(a).max() ** 3
    centre = np.zeros((tetra.shape[0], 3))
    centre[~flat] = np.linalg.solve(a[~flat], rhs[~flat][..., None])[..., 0]
    radius: np.ndarray = np.where(flat, np.inf, np.linalg.norm(centre, axis=1))
    return radius


def _flat(points: np.ndarray, tetra: np.ndarray) -> np.ndarray:
    """Tetrahedra whose volume is nil up to rounding, relative to their longest edge cubed."""
    p = points[tetra]
    edges = p[:, [1, 2, 3, 2, 3, 3]] - p[:, [0, 0, 0, 1, 1, 2]]
    longest = np.linalg.norm(edges, axis=2).max(axis=1)
    volume = np.abs(np.linalg.det(p[:, 1:] - p[:, :1]))
    flat: np.ndarray = volume <= 1e-9 * longest**3
    return flat


def _reachable_from_outside(open_tetra: np.ndarray, neighbours: np.ndarray) -> np.ndarray:
    """The tetrahedra not kept that a path through tetrahedra not kept joins to the convex hull."""
    outside = np.zeros(open_tetra.shape[0], dtype=bool)
    frontier = np.flatnonzero(open_tetra & (neighbours < 0).any(axis=1))
    outside[frontier] = True
    while frontier.size:
        nxt = neighbours[frontier].reshape(-1)
        nxt = np.unique(nxt[nxt >= 0])
        nxt = nxt[open_tetra[nxt] & ~outside[nxt]]
        outside[nxt] = True
        frontier = nxt
    return outside


def alpha_solid(points: np.ndarray, alpha: float | None) -> tuple[np.ndarray, np.ndarray]:
    """Outer boundary of the alpha shape with its cavities filled, wound outward.

    The default alpha is the least that leaves no point outside the shape (every point a corner
    of a kept tetrahedron), so the result is never empty.

    Returns
    -------
    vertices : (n, 3) float64 ndarray
        The distinct points (some unused: inside the solid).
    faces : (F, 3) int64 ndarray
        The faces between the solid and the outside, right-hand normal outward.
    """
    from scipy.spatial import Delaunay, QhullError

    points = np.unique(points, axis=0)  # qhull leaves a repeated point out of every tetrahedron
    try:
        triangulation = Delaunay(points)
    except (QhullError, ValueError) as exc:
        raise InvalidInputError(f"the known points span no volume (all on a plane or a line?): {exc}") from None
    tetra, neighbours = triangulation.simplices, triangulation.neighbors
    radius = _circumradii(points, tetra)
    if alpha is None:
        least = np.full(points.shape[0], np.inf)
        for k in range(4):
            np.minimum.at(least, tetra[:, k], radius)
        alpha = float(least.max())
        if not np.isfinite(alpha):
            raise InvalidInputError("some known points are in no tetrahedron of positive volume")
    kept = radius <= alpha
    if not kept.any():
        raise InvalidInputError(f"alpha={alpha} keeps no tetrahedron; use a larger alpha")
    solid = ~_reachable_from_outside(~kept, neighbours)
    return points, _boundary(points, tetra, neighbours, solid)


# Known points whose normals vote on each tetrahedron's side: a few, so one noisy or misplaced
# normal does not flip a tetrahedron, and all near, so a far part does not vote.
_VOTERS = 6


def normal_vote(points: np.ndarray, normals: np.ndarray, queries: np.ndarray) -> np.ndarray:
    """Where the known points put each query: negative behind their tangent planes (inside).

    The mean over the query's six nearest known points of ``n_i . (q - p_i) / |q - p_i|^2``
    (closer points weigh more; ``normals`` unit).
    """
    from scipy.spatial import cKDTree

    k = min(_VOTERS, points.shape[0])
    _, nearest = cKDTree(points).query(queries, k=k)
    nearest = nearest.reshape(queries.shape[0], k)
    offset = queries[:, None, :] - points[nearest]
    squared = np.maximum(np.einsum("tki,tki->tk", offset, offset), 1e-300)
    vote: np.ndarray = (np.einsum("tki,tki->tk", offset, normals[nearest]) / squared).mean(axis=1)
    return vote


def oriented_solid(points: np.ndarray, normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The Delaunay tetrahedra the known normals put inside, and their boundary, wound outward.

    Each tetrahedron's centroid is inside when its nearest known points (six, closer ones
    weighing more) see it behind their tangent planes: the mean of ``n_i . (c - p_i) / |c -
    p_i|^2`` is negative. Points sampled on a solid's surface leave its interior and the space
    between its parts to large tetrahedra; an alpha radius cannot tell them apart when the
    points are sparse (the shell it keeps has holes, and the interior leaks out through them),
    the normals can. The boundary between inside and outside tetrahedra (and the convex hull)
    is closed by construction and has no inner shell.
    """
    from scipy.spatial import Delaunay, QhullError

    points, first = np.unique(points, axis=0, return_index=True)
    normals = normals[first] / np.linalg.norm(normals[first], axis=1)[:, None]
    try:
        triangulation = Delaunay(points)
    except (QhullError, ValueError) as exc:
        raise InvalidInputError(f"the known points span no volume (all on a plane or a line?): {exc}") from None
    tetra, neighbours = triangulation.simplices, triangulation.neighbors
    solid = oriented_labels(points, normals, tetra, neighbours)
    if not solid.any():
        raise InvalidInputError("the known points' normals put no tetrahedron inside: are they outward?")
    return points, _boundary(points, tetra, neighbours, solid)


def oriented_labels(
    points: np.ndarray, normals: np.ndarray, tetra: np.ndarray, neighbours: np.ndarray, free: np.ndarray | None = None
) -> np.ndarray:
    """Which Delaunay tetrahedra :func:`oriented_solid` puts inside (unit ``normals``).

    ``free`` (optional, per tetrahedron) marks tetrahedra known to be outside: they are never
    inside, and the fill does not grow into them (benches/structure_free_space.py measures
    free-space carving with it).
    """
    solid = normal_vote(points, normals, points[tetra].mean(axis=1)) < 0.0
    # A flat tetrahedron (four points of one wall) has no side of its own: the flat ones joined
    # to the hull through flat ones are outside, the rest inside, so no face lies between two
    # flat tetrahedra (where no corner would tell its orientation).
    flat = _flat(points, tetra)
    solid[flat] = ~_reachable_from_outside(flat, neighbours)[flat]
    if free is None:
        free = np.zeros(tetra.shape[0], dtype=bool)
    solid[free] = False
    _fill_against_normals(points, normals, tetra, neighbours, solid, free)
    return solid


# How far a corner's known normal must point against a face of S' for _fill_against_normals to
# fill behind it: any amount (n_i . n_f < -0). Stricter margins were measured and not kept
# (benches/structure_fill_margin.py: more of S' faces inward, as much of it is air).
_CONTRADICTION_MARGIN = 0.0

# Rounds of _fill_against_normals: each fills the tetrahedra behind the faces the known normals
# contradict; the pockets they open close in a few (at most 20 on the families' development seeds).
_FILL_ROUNDS = 20


def _fill_against_normals(
    points: np.ndarray, normals: np.ndarray, tetra: np.ndarray, neighbours: np.ndarray, solid: np.ndarray, free: np.ndarray
) -> None:
    """Fill (in place) every tetrahedron outside S' behind a face of S' whose corners' known
    normals contradict it.

    A face of S' between a solid tetrahedron and one left outside faces away from the solid one;
    its three corners are known points whose normals say which way the real surface faces
    there. Where one of them points against the face, the tetrahedron left outside is inside
    the structure: the vote at a centroid errs there, as under a roof's overhang or a deck,
    whose downward normals put the building or the girders below them outside (a face of S'
    then lies on a wall with its normal into the building: 21 % of S''s area on the building
    family, 30 % on the tower's blades and bridges, issue 42). Filling it moves the face
    outwards, where the next round judges it again. Tetrahedra marked ``free`` are not filled.
    """
    opposite = ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1))
    for _ in range(_FILL_ROUNDS):
        filled = False
        for k, corners in enumerate(opposite):
            other = neighbours[:, k]
            face = np.flatnonzero(solid & (other >= 0) & ~solid[np.maximum(other, 0)] & ~free[np.maximum(other, 0)])
            if not face.size:
                continue
            triangle = tetra[face][:, list(corners)]
            a = points[triangle[:, 0]]
            normal, _ = face_normals(points, triangle)
            # Outward: away from the solid tetrahedron's own corner off the face.
            normal[np.einsum("ij,ij->i", normal, points[tetra[face, k]] - a) > 0] *= -1.0
            contradicted = (np.einsum("ij,itj->it", normal, normals[triangle]) < -_CONTRADICTION_MARGIN).any(axis=1)
            if contradicted.any():
                solid[other[face[contradicted]]] = True
                filled = True
        if not filled:
            return


def _boundary(points: np.ndarray, tetra: np.ndarray, neighbours: np.ndarray, solid: np.ndarray) -> np.ndarray:
    """The faces between solid tetrahedra and the rest (or the hull), wound away from the solid.

    Each face is turned by whichever point off its plane is farther from it: the solid
    tetrahedron's fourth corner, the outside neighbour's (on the other side), or for a face of
    the convex hull the points' mean (inside the hull). Points sampled on one wall are
    coplanar, so a tetrahedron of four of them is flat and its own corner says nothing.
    """
    # Face k of a tetrahedron is the one opposite its corner k (scipy's neighbour convention).
    opposite = ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1))
    tri, inner, outer = [], [], []
    middle = points.mean(axis=0)
    for k, corners in enumerate(opposite):
        other = neighbours[:, k]
        boundary = solid & ((other < 0) | ~solid[np.maximum(other, 0)])
        tri.append(tetra[boundary][:, list(corners)])
        inner.append(points[tetra[boundary, k]])
        across = other[boundary]
        # The neighbour's corner off this face: the one of its four not on the face.
        far = np.where(across[:, None] >= 0, tetra[np.maximum(across, 0)], -1)
        on_face = (far[:, :, None] == tetra[boundary][:, list(corners)][:, None, :]).any(axis=2)
        pick = far[np.arange(far.shape[0]), np.argmin(on_face, axis=1)]
        outer.append(np.where((across >= 0)[:, None], points[np.maximum(pick, 0)], np.nan))
        inner[-1] = np.where((across >= 0)[:, None], inner[-1], middle)
    faces = np.concatenate(tri)
    a = points[faces[:, 0]]
    normal, _ = face_normals(points, faces)
    towards_solid = np.einsum("ij,ij->i", normal, np.concatenate(inner) - a)
    towards_outside = np.einsum("ij,ij->i", normal, np.nan_to_num(np.concatenate(outer) - a))
    inward = np.where(np.abs(towards_solid) >= np.abs(towards_outside), towards_solid > 0, towards_outside < 0)
    faces[inward] = faces[inward][:, ::-1]
    return faces.astype(np.int64)


def _components(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """A label per face: faces sharing a vertex are in one piece."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    rows = np.repeat(np.arange(faces.shape[0]), 3)
    graph = coo_matrix((np.ones(rows.size), (rows, faces.reshape(-1) + faces.shape[0])), shape=(faces.shape[0] + n_vertices,) * 2)
    _, label = connected_components(graph, directed=False)
    return np.asarray(label[: faces.shape[0]])


def is_closed(faces: np.ndarray) -> bool:
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    _, counts = np.unique(np.sort(edges, axis=1), axis=0, return_counts=True)
    return bool((counts % 2 == 0).all())


def outer_shells(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray, normals: np.ndarray | None) -> np.ndarray:
    """The faces of the pieces no other piece encloses, each piece turned outward.

    A closed piece is turned by its signed volume; an open one (ball pivoting's sheets) by the
    known points' normals (the nearest point to each face votes, weighted by area) when there
    are normals, and refused otherwise (there is no outside to tell).
    """
    from scipy.spatial import cKDTree

    from ..engine import Terrain

    label = _components(faces, vertices.shape[0])
    pieces = [faces[label == q] for q in np.unique(label)]
    closed = [is_closed(piece) for piece in pieces]
    kept = []
    for q, piece in enumerate(pieces):
        probe = vertices[piece[0, 0]][None, :]
        enclosed = any(closed[r] and bool(Terrain(vertices, pieces[r]).inside(probe, n_threads=1)[0]) for r in range(len(pieces)) if r != q)
        if enclosed:
            continue
        if closed[q]:
            outward = signed_volume(vertices, piece) > 0
        elif normals is not None:
            unit, area = face_normals(vertices, piece)
            _, nearest = cKDTree(points).query(vertices[piece].mean(axis=1))
            outward = float((area * np.einsum("ij,ij->i", unit, normals[nearest])).sum()) >= 0
        else:
            raise InvalidInputError("the reconstruction left an open sheet and the prior has no normals to tell its outside")
        kept.append(piece if outward else piece[:, ::-1])
    return np.concatenate(kept) if kept else np.empty((0, 3), dtype=np.int64)


# Known points more than this many of their spacings apart may belong to separate structures:
# groups of occupied cells this size, joined through their 26 neighbours, are reconstructed
# alone. Every connected structure measured stays one group (the families' widest gap in
# their known points is 9 spacings over report and development seeds, tests/shape_zoo.py's
# guyed mast 27 along its wires); buildings 200 m apart are 67-99 (tests/shape_zoo2.py's campus).
SEPARATE_CELL_SPACINGS = 15.0


# The fewest distinct known points a separate group is reconstructed from (a box's corners).
MIN_GROUP_POINTS = 8


def separate_groups(points: np.ndarray, spacing: float) -> list[np.ndarray]:
    """Indices of the known points in each group far from the others (a single group when any
    group would be too small to reconstruct: fewer than :data:`MIN_GROUP_POINTS` distinct
    points, or no volume)."""
    everything = [np.arange(points.shape[0])]
    cell = SEPARATE_CELL_SPACINGS * spacing
    # Cells finer than 2^-40 of the extent say nothing (and their integer keys would overflow).
    if not (spacing > 0.0 and float(np.ptp(points, axis=0).max()) < 2.0**40 * cell):
        return everything
    label = _cell_components(points, cell)
    groups = [np.flatnonzero(label == g) for g in range(int(label.max()) + 1)]
    if len(groups) < 2 or not all(_reconstructable(points[group]) for group in groups):
        return everything
    return groups


def _cell_components(points: np.ndarray, cell: float) -> np.ndarray:
    """Per point, the label of its group of occupied ``cell``-sized cells joined through their
    26 neighbours."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    key = np.floor((points - points.min(axis=0)) / cell).astype(np.int64)
    occupied, point_cell = np.unique(key, axis=0, return_inverse=True)
    lookup = {tuple(k): i for i, k in enumerate(occupied.tolist())}
    rows, cols = [], []
    for i, k in enumerate(occupied.tolist()):
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    j = lookup.get((k[0] + dx, k[1] + dy, k[2] + dz))
                    if j is not None:
                        rows.append(i)
                        cols.append(j)
    graph = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(occupied.shape[0],) * 2)
    _, label = connected_components(graph, directed=False)
    return np.asarray(label[point_cell.reshape(-1)])


def _reconstructable(points: np.ndarray) -> bool:
    distinct = np.unique(points, axis=0)
    if distinct.shape[0] < MIN_GROUP_POINTS:
        return False
    spread = np.linalg.svd(distinct - distinct.mean(axis=0), compute_uv=False)
    return bool(spread[2] > FLAT_SHARE * spread[0])
