"""The true surfaces: the paper's scenarios and real terrain loaded from files, in one namespace.

Three families, all returning a :class:`~uavcov.surface.Terrain` in a local metric frame
(metres, Z up), each in its own module:

* :mod:`uavcov.hills`: **Gaussian hills**, the paper's 40 test terrains (:func:`gaussian_hills`,
  :class:`GaussianMixture`).
* :mod:`uavcov.buildings`: **a buildings scene**, the paper's realistic environment
  (:func:`random_buildings`, :func:`buildings_terrain`, :func:`buildings_scene`,
  :func:`perturb_buildings`).
* :mod:`uavcov.loaders`: **real terrain** from arrays, GeoTIFF and mesh files, in a recentred
  :class:`LocalFrame` (:func:`load_dem`, :func:`load_geotiff`, :func:`load_mesh`,
  :func:`mesh_terrain`, :func:`sample_dem`).
"""

from __future__ import annotations

from .buildings import Building, buildings_scene, buildings_terrain, perturb_buildings, random_buildings
from .hills import GaussianMixture, gaussian_hills, random_gaussian_mixture
from .loaders import (
    LoadedTerrain,
    LocalFrame,
    MeshReport,
    clean_mesh,
    load_dem,
    load_geotiff,
    load_mesh,
    mesh_terrain,
    metres_per_degree,
    sample_dem,
)

__all__ = [
    "GaussianMixture",
    "random_gaussian_mixture",
    "gaussian_hills",
    "Building",
    "random_buildings",
    "buildings_terrain",
    "buildings_scene",
    "perturb_buildings",
    "LocalFrame",
    "MeshReport",
    "LoadedTerrain",
    "metres_per_degree",
    "load_dem",
    "load_geotiff",
    "mesh_terrain",
    "clean_mesh",
    "load_mesh",
    "sample_dem",
]
