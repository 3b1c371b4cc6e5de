"""What a surface is made from: Gaussian hills, buildings, mesh files, geo-referenced DEMs, and the prior S'.

Structures that are not height fields (bridges, towers, facades) are :mod:`uavcov.structures`.
"""

from __future__ import annotations

from ._buildings import buildings_scene
from ._dem import GeoDem, RasterGrid, dem_from_array, read_dem, read_mesh_dem, sample_dem, wrap_longitude
from ._frame import LocalFrame, metres_per_degree
from ._generators import BuildingsGenerator, HillsGenerator
from ._hills import gaussian_hills
from ._meshes import MeshReport, load_mesh
from ._prior import ApproximationError, Prior, approximate_surface, approximation_error, sample_node_prior, sample_prior

__all__ = [
    "buildings_scene",
    "RasterGrid",
    "GeoDem",
    "dem_from_array",
    "read_dem",
    "read_mesh_dem",
    "sample_dem",
    "wrap_longitude",
    "LocalFrame",
    "metres_per_degree",
    "HillsGenerator",
    "BuildingsGenerator",
    "gaussian_hills",
    "load_mesh",
    "MeshReport",
    "Prior",
    "sample_prior",
    "sample_node_prior",
    "approximate_surface",
    "ApproximationError",
    "approximation_error",
]
