"""What a surface is made from: Gaussian hills, buildings, mesh files, geo-referenced DEMs, 3D structures, and the prior S'."""

from __future__ import annotations

from ._buildings import Building, buildings_scene, buildings_terrain, perturb_buildings, random_buildings
from ._dem import SAMPLE_VERTICAL_DATUM, WGS84, GeoDem, RasterGrid, dem_from_array, read_dem, read_mesh_dem, sample_dem
from ._families import (
    STRUCTURE_FAMILIES,
    arch_bridge_family,
    building_family,
    girder_bridge_family,
    pylon_family,
    tower_family,
)
from ._frame import LocalFrame, metres_per_degree
from ._generators import BuildingsGenerator, HillsGenerator, TerrainGenerator
from ._hills import GaussianMixture, gaussian_hills, random_gaussian_mixture
from ._meshes import LoadedMesh, MeshReport, clean_mesh, load_mesh, mesh_terrain
from ._prior import (
    ApproximationError,
    Prior,
    approximate_surface,
    approximation_error,
    building_corner_prior,
    buildings_prior,
    sample_node_prior,
    sample_prior,
)
from ._structure_prior import (
    ReconstructionError,
    StructurePrior,
    coarse_structure_prior,
    reconstruct_structure,
    reconstruction_error,
    sample_structure_prior,
)
from ._structures import (
    STRUCTURE_SCENES,
    Structure,
    StructureTargets,
    arch_bridge,
    facade,
    girder_bridge,
    height_field_violation,
    lattice_pylon,
    load_structure,
    wind_turbine,
)

__all__ = [
    "Building",
    "random_buildings",
    "buildings_terrain",
    "buildings_scene",
    "perturb_buildings",
    "RasterGrid",
    "GeoDem",
    "dem_from_array",
    "read_dem",
    "read_mesh_dem",
    "sample_dem",
    "WGS84",
    "SAMPLE_VERTICAL_DATUM",
    "LocalFrame",
    "metres_per_degree",
    "HillsGenerator",
    "BuildingsGenerator",
    "TerrainGenerator",
    "GaussianMixture",
    "random_gaussian_mixture",
    "gaussian_hills",
    "MeshReport",
    "LoadedMesh",
    "mesh_terrain",
    "clean_mesh",
    "load_mesh",
    "Prior",
    "sample_prior",
    "sample_node_prior",
    "approximate_surface",
    "ApproximationError",
    "approximation_error",
    "building_corner_prior",
    "buildings_prior",
    "Structure",
    "StructureTargets",
    "STRUCTURE_SCENES",
    "girder_bridge",
    "arch_bridge",
    "wind_turbine",
    "facade",
    "lattice_pylon",
    "load_structure",
    "height_field_violation",
    "STRUCTURE_FAMILIES",
    "building_family",
    "girder_bridge_family",
    "arch_bridge_family",
    "tower_family",
    "pylon_family",
    "StructurePrior",
    "sample_structure_prior",
    "coarse_structure_prior",
    "reconstruct_structure",
    "ReconstructionError",
    "reconstruction_error",
]
