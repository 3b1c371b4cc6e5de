"""How far a structure is from a height field ``z = f(x, y)``."""

from __future__ import annotations

import numpy as np

from .._validate import as_positive_float, cells_along
from ..errors import InvalidTypeError
from ._solids import face_normals
from ._structures import CONTACT, Structure


def height_field_violation(structure: Structure, *, resolution: float | None = None) -> tuple[float, float]:
    """How far a structure is from a height field ``z = f(x, y)``.

    Parameters
    ----------
    structure : Structure
    resolution : float, optional
        Spacing of the vertical rays (m); default 1/200 of the larger side of the structure's
        (x, y) bounding box.

    Returns
    -------
    double_hit_share : float
        Share of the footprint (the lattice points over which a vertical ray meets the
        structure, ground left out) where the ray meets a downward-facing face above the lowest
        surface under it: free space with structure both above and below. 0 for a height field
        (a box on the ground included).
    downward_area_share : float
        Share of the structure's visible area (ground and contact faces left out) facing down
        (normal z < -1e-6). 0 for a height field.
    """
    if not isinstance(structure, Structure):
        raise InvalidTypeError(f"expected a Structure, got {type(structure).__name__}")
    vertices, faces = structure.surface.vertices, structure.surface.faces
    normals, areas = face_normals(vertices, faces)
    visible = structure.face_mask(include_ground=False)
    solid = visible | (structure.face_parts == structure.part_names.index(CONTACT) if CONTACT in structure.part_names else visible)
    down_area = float(areas[visible & (normals[:, 2] < -1e-6)].sum())
    downward_share = down_area / float(areas[visible].sum())

    lo = vertices[np.unique(faces[solid])].min(axis=0)
    hi = vertices[np.unique(faces[solid])].max(axis=0)
    side = float(max(hi[0] - lo[0], hi[1] - lo[1]))
    step = side / 200.0 if resolution is None else as_positive_float(resolution, "resolution")
    nx = max(1, int(np.ceil(cells_along(float(hi[0] - lo[0]), step, "resolution"))))
    ny = max(1, int(np.ceil(cells_along(float(hi[1] - lo[1]), step, "resolution"))))
    xs = lo[0] + (np.arange(nx) + 0.5) * (hi[0] - lo[0]) / nx
    ys = lo[1] + (np.arange(ny) + 0.5) * (hi[1] - lo[1]) / ny
    lowest = np.full((nx, ny), np.inf)
    highest_down = np.full((nx, ny), -np.inf)
    hit_solid = np.zeros((nx, ny), dtype=bool)
    down = visible & (normals[:, 2] < -1e-6)
    for f in np.nonzero(np.abs(normals[:, 2]) > 1e-9)[0]:
        a, b, c = vertices[faces[f]]
        i0, i1 = np.searchsorted(xs, min(a[0], b[0], c[0])), np.searchsorted(xs, max(a[0], b[0], c[0]), side="right")
        j0, j1 = np.searchsorted(ys, min(a[1], b[1], c[1])), np.searchsorted(ys, max(a[1], b[1], c[1]), side="right")
        if i0 >= i1 or j0 >= j1:
            continue
        px, py = np.meshgrid(xs[i0:i1], ys[j0:j1], indexing="ij")
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        s = ((px - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (py - a[1])) / det
        t = ((b[0] - a[0]) * (py - a[1]) - (px - a[0]) * (b[1] - a[1])) / det
        inside = (s >= 0) & (t >= 0) & (s + t <= 1)
        if not inside.any():
            continue
        z = a[2] + s * (b[2] - a[2]) + t * (c[2] - a[2])
        block = (slice(i0, i1), slice(j0, j1))
        lowest[block] = np.where(inside, np.minimum(lowest[block], z), lowest[block])
        if solid[f]:
            hit_solid[block] |= inside
        if down[f]:
            highest_down[block] = np.where(inside, np.maximum(highest_down[block], z), highest_down[block])
    tolerance = 1e-6 * max(side, float(hi[2] - lo[2]), 1.0)
    double = hit_solid & (highest_down > lowest + tolerance)
    footprint = int(hit_solid.sum())
    return (float(double.sum()) / footprint if footprint else 0.0, downward_share)
