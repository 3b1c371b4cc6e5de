"""What a surface is made from: Gaussian hills, buildings, mesh files, geo-referenced DEMs, 3D structures, and the prior S'."""

from __future__ import annotations

from ._buildings import buildings_scene
from ._dem import GeoDem, RasterGrid, dem_from_array, read_dem, read_mesh_dem, sample_dem, wrap_longitude
from ._families import STRUCTURE_FAMILIES
from ._frame import LocalFrame, metres_per_degree
from ._generators import BuildingsGenerator, HillsGenerator
from ._hills import gaussian_hills
from ._meshes import MeshReport
from ._prior import ApproximationError, Prior, approximate_surface, approximation_error, sample_node_prior, sample_prior
from ._structure_prior import (
    ReconstructionError,
    StructurePrior,
    coarse_structure_prior,
    reconstruct_structure,
    reconstruction_error,
    sample_structure_prior,
)
from ._structures import STRUCTURE_SCENES, Structure, StructureTargets, facade, girder_bridge, height_field_violation, load_structure

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
    "MeshReport",
    "Prior",
    "sample_prior",
    "sample_node_prior",
    "approximate_surface",
    "ApproximationError",
    "approximation_error",
    "Structure",
    "StructureTargets",
    "STRUCTURE_SCENES",
    "girder_bridge",
    "facade",
    "load_structure",
    "height_field_violation",
    "STRUCTURE_FAMILIES",
    "StructurePrior",
    "sample_structure_prior",
    "coarse_structure_prior",
    "reconstruct_structure",
    "ReconstructionError",
    "reconstruction_error",
]
