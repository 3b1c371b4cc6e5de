"""Structures, not height fields: bridges, a wind turbine, a facade, a lattice pylon, randomised
families of them, mesh files read as structures, and the surface S' made from partial knowledge.

One layer above :mod:`uavcov.terrain` (a structure file is read with its mesh loader).
"""

from __future__ import annotations

from ._families import STRUCTURE_FAMILIES
from ._height_field import height_field_violation
from ._structure_prior import (
    ReconstructionError,
    StructurePrior,
    coarse_structure_prior,
    reconstruct_structure,
    reconstruction_error,
    sample_structure_prior,
)
from ._structures import STRUCTURE_SCENES, Structure, StructureTargets, facade, girder_bridge, load_structure

__all__ = [
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
