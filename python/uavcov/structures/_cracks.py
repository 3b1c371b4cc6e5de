"""Whether a mesh's open edges are only the zero-width cracks that dropped slivers leave.

A closed solid exported with slivers of (numerically) zero area (a vertex a hair off an edge, as
a CAD exporter leaves where it mends a T-junction) loses them in the mesh repair (the engine
refuses zero-area faces), and the edges around each sliver open. Those edges form loops that
enclose no area: the solid is still closed, up to cracks no ray or UAV can pass. A real hole
(a missing face) encloses its face's area.
"""

from __future__ import annotations

import numpy as np

# A loop's vector area, over the squared bounding-box diagonal, below which it is a crack: ten
# times the repair's zero-area rule (``uavcov.engine.degenerate_faces``, 1e-13) per edge of the
# loop, so the slivers a loop lost always pass, and any face the engine keeps does not.
_CRACK_AREA = 1e-12


def zero_width_cracks(vertices: np.ndarray, faces: np.ndarray) -> bool:
    """True when the mesh has open edges and every loop of them encloses no area.

    Parameters
    ----------
    vertices : (V, 3) float64 ndarray
    faces : (F, 3) int64 ndarray
        Wound consistently (each open edge is met once, in the direction of its face).

    Returns
    -------
    bool
        False without open edges, with an open edge met twice in one direction, or with a loop
        that encloses an area (a hole).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    undirected = np.sort(directed, axis=1)
    _, inverse, counts = np.unique(undirected, axis=0, return_inverse=True, return_counts=True)
    open_edges = directed[counts[inverse.reshape(-1)] == 1]
    if not open_edges.shape[0] or np.unique(open_edges, axis=0).shape[0] != open_edges.shape[0]:
        return False
    n = vertices.shape[0]
    local = vertices - vertices.min(axis=0)  # small coordinates: the loops' sums cancel to their areas, not to rounding
    graph = coo_matrix((np.ones(open_edges.shape[0]), (open_edges[:, 0], open_edges[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    loop = label[open_edges[:, 0]]
    # Twice each loop's vector area: the sum of p_i x p_j over its directed edges (each loop is
    # closed, so the origin drops out).
    cross = np.cross(local[open_edges[:, 0]], local[open_edges[:, 1]])
    areas = np.zeros((label.max() + 1, 3))
    np.add.at(areas, loop, cross)
    edges = np.bincount(loop, minlength=label.max() + 1)
    diagonal2 = float(np.sum(local.max(axis=0) ** 2))
    enclosed = 0.5 * np.linalg.norm(areas, axis=1)
    return bool((enclosed[edges > 0] <= _CRACK_AREA * diagonal2 * edges[edges > 0]).all())
