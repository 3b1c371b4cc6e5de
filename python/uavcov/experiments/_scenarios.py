"""The true surface of each run: a generator's scenario, or a surface of the user's own.

An experiment's terrain is a scenario generator (seed -> surface) or a :class:`~uavcov.Terrain`
given as it is, the same for every seed. The settings hash of an experiment (its run ids, its
results folder's identity) must change with the true surface: a generator is its parameters, a
surface its size and a SHA-256 digest of its geometry.
"""

from __future__ import annotations

import functools
import hashlib
from typing import Any

import numpy as np

from ..engine import Terrain
from ..terrain import BuildingsGenerator, HillsGenerator


def scenario_surface(terrain: HillsGenerator | BuildingsGenerator | Terrain, seed: int) -> Terrain:
    """``terrain.make(seed)``, the last one kept for a worker's next runs; a Terrain is itself.

    Runs are listed seed by seed, so a worker's next run is most often on the same surface (other
    team sizes and starts). A Terrain is immutable, and the objectives of one surface share its
    grid nodes' skylines (``uavcov.Visibility``), which those runs then compute once. Only the
    last terrain is kept, so a worker of a sweep over large maps holds one map at a time.
    """
    if isinstance(terrain, Terrain):
        return terrain
    try:
        hash(terrain)
    except TypeError:  # a generator given lists instead of tuples: made anew each time
        return terrain.make(seed)
    return _kept_scenario(terrain, seed)


@functools.lru_cache(maxsize=1)
def _kept_scenario(terrain: HillsGenerator | BuildingsGenerator, seed: int) -> Terrain:
    return terrain.make(seed)


def surface_settings(terrain: Terrain) -> dict[str, Any]:
    """A surface given as an experiment's terrain, as plain data: its size and a digest of its geometry.

    The digest (SHA-256 of the grid's heights, spacing and origin, or of a mesh's vertices and
    faces) changes with any node.
    """
    return dict(_surface_settings(terrain))


@functools.lru_cache(maxsize=4)
def _surface_settings(terrain: Terrain) -> dict[str, Any]:
    """:func:`surface_settings`, kept for the last few surfaces: every run id asks for it."""
    digest = hashlib.sha256()
    if terrain.grid is not None:
        grid = terrain.grid
        digest.update(np.ascontiguousarray(grid.z, dtype="<f8").tobytes())
        digest.update(np.asarray([*grid.spacing, *grid.origin], dtype="<f8").tobytes())
        size: dict[str, Any] = {"grid": list(grid.shape)}
    else:
        digest.update(np.ascontiguousarray(terrain.vertices, dtype="<f8").tobytes())
        digest.update(np.ascontiguousarray(terrain.faces, dtype="<i8").tobytes())
        size = {"vertices": terrain.n_vertices, "faces": terrain.n_faces}
    return {"kind": "surface", **size, "area_m2": float(terrain.area), "sha256": digest.hexdigest()}
