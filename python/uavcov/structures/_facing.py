"""Which points of S' face into the real structure: the measure behind
``reconstruction_error(...).inward_area_share``.

A face of S' *faces into the structure* when its outward normal points into a real solid: a
start flown out along it goes into the structure instead of away from it. Judged at a point
``x`` of S' with unit normal ``n``, by where ``x`` lies:

- **outside the real solids**: against the way out there, the direction ``g`` from the nearest
  point of the real surface to ``x`` (the gradient of the signed distance; the outward face
  normal in front of a face, between two faces' normals beside an edge). ``n`` faces in when it
  points against it (``n . g < 0``): towards the solid ``x`` stands in front of.
- **on the real surface** (``x`` within rounding of it): against the outward normals of the
  triangles holding ``x`` (the engine's :meth:`~uavcov.Terrain.faces_at_closest`), the one
  agreeing best with ``n``, so that where two solids touch face to face the wrong side is not
  picked at random.
- **inside a real solid** (S' bulging into a part): the nearest real face is no guide there (in
  a 0.8 m deck a point below the middle is nearer the underside whatever S' approximates), so
  the normal is judged by the way out along its own line: ``n`` faces in when the solid
  extends farther along ``n`` than against it (the ray along ``n`` leaves the solid later than
  the ray along ``-n``). A face of S' a little inside a wall with the wall's outward normal
  leaves it at once along ``n``: it does not face in.

So the measure is of orientation, not of position: the true surface itself scores 0, its
inverted copy 1, and a copy shrunk into it or grown around it 0 (tests/test_structure_outer.py).
"""

from __future__ import annotations

import numpy as np

from ..engine import Terrain


def facing_into(solid: Terrain, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Whether each point's normal points into the solids of ``solid`` (see the module).

    Parameters
    ----------
    solid : Terrain
        The real structure's closed solids, wound outward (contact faces included).
    points : (n, 3) float64 ndarray
        Points of S', metres.
    normals : (n, 3) float64 ndarray
        S''s outward unit normals there.

    Returns
    -------
    (n,) bool ndarray
    """
    unit = solid.face_normals
    closest, holding = solid.faces_at_closest(points, n_threads=1)
    agreement = np.array([float((unit[faces] @ n).max()) if faces.size else 0.0 for faces, n in zip(holding, normals, strict=True)])
    away = points - closest
    distance = np.linalg.norm(away, axis=1)
    # Off the surface the way out is the direction from the nearest point (the signed distance's
    # gradient: at an edge or a corner, between its faces' normals); on it, the faces' own.
    apart = distance > 1e-9 * max(1.0, float(np.abs(solid.bounds).max()))
    into = np.where(apart, np.einsum("ij,ij->i", away, normals) < 0.0, agreement < 0.0)
    inside = solid.inside(points, n_threads=1)
    if inside.any():
        origin, direction = points[inside], normals[inside]
        reach = float(np.ptp(solid.bounds, axis=0).max()) * 2.0 + 1.0
        ahead = solid.core.first_hits(origin, direction, reach, 1)
        behind = solid.core.first_hits(origin, -direction, reach, 1)
        into[inside] = ahead > behind
    return np.asarray(into, dtype=bool)
