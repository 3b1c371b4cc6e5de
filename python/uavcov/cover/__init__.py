"""Candidate viewpoints and how good a placement can be: the admissible viewpoint lattice, a
structure's points flown out along its face normals, the greedy placement with its certified
bound, the LP dual certificate, and the exact placement."""

from __future__ import annotations

from ._dual_bound import DualCertificate
from ._exact import ExactResult, exact_placement
from ._faces import closest_faces, surface_normals
from ._greedy import CoverageBound, CoverageProblem, GreedyResult, coverage_bound, greedy_placement
from ._viewpoints import GreedySettings, Viewpoints, viewpoint_lattice, viewpoint_offsets

__all__ = [
    "GreedySettings",
    "Viewpoints",
    "viewpoint_lattice",
    "viewpoint_offsets",
    "closest_faces",
    "surface_normals",
    "CoverageProblem",
    "GreedyResult",
    "CoverageBound",
    "DualCertificate",
    "greedy_placement",
    "coverage_bound",
    "ExactResult",
    "exact_placement",
]
