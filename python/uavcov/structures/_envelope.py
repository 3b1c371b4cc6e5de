"""S' grown outward into an envelope of the structure: the level set of its signed distance.

Known points lie on the structure, so a surface through them lies inside it wherever the
structure bulges between them: a pier's foot below the lowest known point, a balcony's edge, a
girder between two points of the deck. There S''s faces have a real part in front of them and
face into the structure (``reconstruction_error(...).inward_area_share``; 2-18 % of S' for 100
known points on the families of :data:`STRUCTURE_FAMILIES`). The envelope is the set of points
within ``margin`` of S''s solid, {x : signed distance to S' <= margin}; its boundary is sampled
on a regular grid and triangulated by marching tetrahedra (each grid cube split into the six
tetrahedra of its Kuhn triangulation, which neighbouring cubes share face for face, so the
surface is closed and every edge is held by two triangles). The margin is a multiple of the
mean gap between the known points on S' (``sqrt(area / n)``): the scale on which the structure
can leave S' between them (docs/structures.md, "S' as an envelope").
"""

from __future__ import annotations

import numpy as np

from .._validate import MAX_COORDINATE_M
from ..engine import Terrain, degenerate_faces
from ..errors import InvalidInputError
from ._outer_surface import is_closed, outer_shells

ENVELOPE_GAPS = 0.75
"""Default margin of the envelope, in mean gaps between known points on S' (``sqrt(area / n)``).

The least of 0.5, 0.6, 0.75, 0.9 and 1 that keeps the share of S' facing into the structure
under 1 % on every family (development seeds 1000-1007; at 0.6 the girder bridge's is 1.4 %);
the missions the structures experiment flies from S' move by 0.01 across them (mean best
0.911-0.927 against 0.923-0.925 without an envelope): ``nice python benches/structure_envelope.py``
(benches/README.md)."""

MAX_ENVELOPE_NODES = 1 << 20
"""Most grid nodes the envelope samples (about a million, some 40 MB of work arrays and an
envelope of up to some 200,000 triangles): past it the grid is coarsened, and the margin raised
to two grid steps. The families' envelopes at 100 known points take about 10,000."""

# The unit cube's corners, corner k at (k & 1, k >> 1 & 1, k >> 2 & 1), and the six tetrahedra
# of its Kuhn triangulation (all around the diagonal from corner 0 to corner 7).
_CORNERS = np.array([[k & 1, (k >> 1) & 1, (k >> 2) & 1] for k in range(8)])
_KUHN = np.array([[0, 1, 3, 7], [0, 1, 5, 7], [0, 2, 3, 7], [0, 2, 6, 7], [0, 4, 5, 7], [0, 4, 6, 7]])


def isosurface(values: np.ndarray, origin: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """The zero level of ``values`` sampled on a regular grid, wound towards the positive side.

    Parameters
    ----------
    values : (nx, ny, nz) float64 ndarray
        Negative inside. The grid's outer nodes must be positive (the surface is then closed).
    origin : (3,) float64 ndarray
        Position of node (0, 0, 0), metres.
    step : float
        Grid spacing, metres.

    Returns
    -------
    vertices : (v, 3) float64 ndarray
    faces : (f, 3) int64 ndarray
        Each triangle's normal points from the negative corners of its tetrahedron to the
        positive ones; none has zero area.
    """
    shape = values.shape
    # A value at or near zero would put a vertex on (or a round-off from) a node, and the
    # triangles around it would have zero area: values are kept a thousandth of a step off it.
    least = 1e-3 * step
    field = np.where(values < 0.0, np.minimum(values, -least), np.maximum(values, least)).ravel()
    negative = (field < 0.0).reshape(shape)
    # The cubes the level crosses: some corners negative, not all.
    views = [negative[i : shape[0] - 1 + i, j : shape[1] - 1 + j, k : shape[2] - 1 + k] for i, j, k in _CORNERS]
    some, every = np.logical_or.reduce(views), np.logical_and.reduce(views)
    cubes = np.argwhere(some & ~every)
    corner_nodes = np.ravel_multi_index(tuple((cubes[:, None, :] + _CORNERS[None]).transpose(2, 0, 1)), shape)
    tetra = corner_nodes[:, _KUHN].reshape(-1, 4)
    inside = field[tetra] < 0.0
    count = inside.sum(axis=1)
    tetra, inside, count = tetra[(count > 0) & (count < 4)], inside[(count > 0) & (count < 4)], count[(count > 0) & (count < 4)]
    # Corners ordered inside first: one inside (a) cuts edges a-b, a-c, a-d; three inside (a, b,
    # c) cut d-a, d-b, d-c; two (a, b) cut the quadrilateral a-c, a-d, b-d, b-c.
    tetra = np.take_along_axis(tetra, np.argsort(~inside, axis=1, kind="stable"), axis=1)
    cuts = {1: [[(0, 1), (0, 2), (0, 3)]], 3: [[(3, 0), (3, 1), (3, 2)]], 2: [[(0, 2), (0, 3), (1, 3)], [(0, 2), (1, 3), (1, 2)]]}
    edges, owners = [], []
    for inside_count, triangles in cuts.items():
        chosen = tetra[count == inside_count]
        for triangle in triangles:
            edges.append(np.stack([np.sort(chosen[:, list(pair)], axis=1) for pair in triangle], axis=1))
            owners.append(chosen)
    all_edges = np.concatenate(edges).reshape(-1, 2)
    unique, faces = np.unique(all_edges, axis=0, return_inverse=True)
    faces = faces.reshape(-1, 3)
    low, high = field[unique[:, 0]], field[unique[:, 1]]
    weight = low / (low - high)
    ends = origin + step * np.stack(np.unravel_index(unique.ravel(), shape), axis=-1).reshape(-1, 2, 3)
    vertices = ends[:, 0] + weight[:, None] * (ends[:, 1] - ends[:, 0])
    # Wind each triangle from its tetrahedron's inside corners to its outside ones.
    owner = np.concatenate(owners)
    position = origin + step * np.stack(np.unravel_index(owner, shape), axis=-1)
    is_in = field[owner] < 0.0
    towards_out = (position * ~is_in[..., None]).sum(axis=1) / (~is_in).sum(axis=1, keepdims=True) - (position * is_in[..., None]).sum(
        axis=1
    ) / is_in.sum(axis=1, keepdims=True)
    # Normals from the engine (the one owner of mesh geometry); the values kept off zero leave no
    # triangle of zero area, but one would be refused there, so any such is dropped first.
    faces = faces.astype(np.int64)
    kept = ~degenerate_faces(vertices, faces)
    faces, towards_out = faces[kept], towards_out[kept]
    backwards = np.einsum("ij,ij->i", Terrain(vertices, faces).face_normals, towards_out) < 0.0
    faces[backwards] = faces[backwards][:, ::-1]
    return vertices, faces


def _grid_nodes(extent: np.ndarray, margin: float, step: float) -> float:
    # The margin and two more steps on every side: the outer nodes are outside, the level closed.
    # In logarithms: a step of 1e-300 m would overflow the product.
    per_axis = np.ceil((extent + 2.0 * margin + 4.0 * step) / step) + 1.0
    return float(np.exp(np.log(per_axis).sum()))


def envelope(surface: Terrain, margin: float, *, max_nodes: int = MAX_ENVELOPE_NODES, n_threads: int | None = 1) -> Terrain:
    """The boundary of the points within ``margin`` of ``surface``'s solid (its signed distance
    at most ``margin``), on a grid of step ``margin / 2`` (coarser, with the margin raised to two
    steps, where that grid would pass ``max_nodes``). Only its outer pieces are kept, wound
    outward (:func:`outer_shells`): no cavity inside the envelope.

    Parameters
    ----------
    surface : Terrain
        S', closed and wound outward (an open sheet has no inside to grow from: thickened on
        both sides, its inner face would look into the structure).
    margin : float
        Metres (> 0).
    max_nodes : int
    n_threads : int, optional

    Returns
    -------
    Terrain
        Closed and wound outward; it holds ``surface``.
    """
    if not is_closed(surface.faces):
        raise InvalidInputError("the envelope grows a closed surface; this one has open edges")
    extent = np.ptp(surface.bounds, axis=0)
    # Half the margin, or the step that spreads the budget over the extent if that is coarser
    # (then raised until the padded grid fits): checked before any node is allocated.
    step = max(margin / 2.0, float(np.cbrt(np.prod(extent) / max_nodes)))
    while _grid_nodes(extent, max(margin, 2.0 * step), step) > max_nodes:
        step *= 1.25
    margin = max(margin, 2.0 * step)
    if float(np.abs(surface.bounds).max()) + margin + 3.0 * step > MAX_COORDINATE_M:
        raise InvalidInputError(f"a margin of {margin:g} m grows S' past {MAX_COORDINATE_M:g} m from the origin, the engine's bound")
    low = surface.bounds[0] - margin - 2.0 * step
    shape = tuple(int(n) for n in np.ceil((extent + 2.0 * margin + 4.0 * step) / step) + 1)
    nodes = np.stack(np.meshgrid(*[low[k] + step * np.arange(shape[k]) for k in range(3)], indexing="ij"), axis=-1).reshape(-1, 3)
    distance = surface.distance(nodes, n_threads=n_threads)
    distance[surface.inside(nodes, n_threads=n_threads)] *= -1.0
    vertices, faces = isosurface((distance - margin).reshape(shape), low, step)
    return Terrain(vertices, outer_shells(vertices, faces, vertices, None), drop_degenerate=True)
