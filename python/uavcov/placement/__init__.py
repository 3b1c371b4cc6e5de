"""Where a team may fly and where it starts: flight limits, the constrained CVT, starts, camera footprints,
candidate viewpoints, the greedy placement with its certified bound, and the exact placement."""

from __future__ import annotations

from ._constraints import Constraints, World, closest_admissible, feasibility
from ._cvt import PRESETS, CVTResult, CVTSettings, cvt
from ._dual_bound import DualCertificate
from ._exact import ExactResult, exact_placement
from ._footprints import FootprintFit, fit_footprints
from ._greedy import CoverageBound, CoverageProblem, GreedyResult, coverage_bound, greedy_placement
from ._starts import ALTITUDE_REFERENCES, CORNERS, START_KINDS, StartSettings, start_configuration
from ._starts3d import StandoffStart, closest_faces, facing_attitudes, standoff_start
from ._viewpoints import GreedySettings, Viewpoints, viewpoint_lattice, viewpoint_offsets

__all__ = [
    "World",
    "Constraints",
    "feasibility",
    "closest_admissible",
    "cvt",
    "CVTSettings",
    "CVTResult",
    "PRESETS",
    "FootprintFit",
    "fit_footprints",
    "start_configuration",
    "StartSettings",
    "START_KINDS",
    "CORNERS",
    "ALTITUDE_REFERENCES",
    "standoff_start",
    "viewpoint_offsets",
    "StandoffStart",
    "facing_attitudes",
    "closest_faces",
    "GreedySettings",
    "Viewpoints",
    "viewpoint_lattice",
    "CoverageProblem",
    "GreedyResult",
    "CoverageBound",
    "DualCertificate",
    "greedy_placement",
    "coverage_bound",
    "ExactResult",
    "exact_placement",
]
