"""Small structure meshes for the tests: a box on a ground plane, a deck on two piers.

Every solid is a closed box wound counter-clockwise seen from outside (right-hand normals point
out); the ground is a square facing up. Components touch but do not interpenetrate.
"""

from __future__ import annotations

import numpy as np

import uavcov

# A unit cube's corners and its twelve outward triangles (counter-clockwise seen from outside).
_CORNERS = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=np.float64)
_CUBE_FACES = np.array(
    [
        [0, 2, 1], [1, 2, 3],  # bottom (z = 0), facing -z
        [4, 5, 6], [5, 7, 6],  # top (z = 1), facing +z
        [0, 1, 4], [1, 5, 4],  # y = 0, facing -y
        [2, 6, 3], [3, 6, 7],  # y = 1, facing +y
        [0, 4, 2], [2, 4, 6],  # x = 0, facing -x
        [1, 3, 5], [3, 7, 5],  # x = 1, facing +x
    ],
    dtype=np.int64,
)  # fmt: skip


def box(lo, hi) -> tuple[np.ndarray, np.ndarray]:
    """A closed axis-aligned box from ``lo`` to ``hi``: (8, 3) vertices, (12, 3) faces."""
    lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    return lo + _CORNERS * (hi - lo), _CUBE_FACES.copy()


def ground(half: float, z: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """A square ``[-half, half]^2`` at height ``z``, facing up."""
    v = np.array([[-half, -half, z], [half, -half, z], [half, half, z], [-half, half, z]])
    return v, np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)


def join(*parts: tuple[np.ndarray, np.ndarray]) -> uavcov.Terrain:
    vertices, faces, offset = [], [], 0
    for v, f in parts:
        vertices.append(v)
        faces.append(f + offset)
        offset += v.shape[0]
    return uavcov.Terrain(np.vstack(vertices), np.vstack(faces))


def box_on_ground() -> uavcov.Terrain:
    """A 10 m x 6 m x 8 m box standing on a 40 m square of ground (the box's floor on z = 0)."""
    return join(ground(20.0), box([-5.0, -3.0, 0.0], [5.0, 3.0, 8.0]))


def bridge() -> uavcov.Terrain:
    """A 30 m x 6 m deck, 10 m to 11 m up, on two 2 m x 6 m piers, over a 40 m square of ground."""
    return join(
        ground(20.0),
        box([-15.0, -3.0, 10.0], [15.0, 3.0, 11.0]),
        box([-11.0, -3.0, 0.0], [-9.0, 3.0, 10.0]),
        box([9.0, -3.0, 0.0], [11.0, 3.0, 10.0]),
    )


def face_targets(surface: uavcov.Terrain) -> uavcov.Targets:
    """One target per face: its centroid, area and right-hand unit normal."""
    v, f = surface.vertices, surface.faces
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    cross = np.cross(b - a, c - a)
    return uavcov.Targets((a + b + c) / 3.0, 0.5 * np.linalg.norm(cross, axis=1), cross / np.linalg.norm(cross, axis=1)[:, None])
