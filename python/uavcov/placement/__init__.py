"""Where a team may fly and where it starts: flight limits, the constrained CVT, starts, camera footprints,
candidate viewpoints, the greedy placement with its certified bound, and the exact placement."""

from __future__ import annotations

from ._constraints import Constraints, StandoffWorld, World, closest_admissible, feasibility, feasible_mask, trajectory_feasible
from ._cvt import PRESETS, CVTResult, CVTSettings, cvt, default_samples_per_iteration, seed_from_rng
from ._dual_bound import DualCertificate
from ._exact import ExactResult, exact_placement
from ._footprints import FootprintFit, fit_footprints
from ._greedy import CoverageBound, CoverageProblem, GreedyResult, coverage_bound, greedy_placement
from ._starts import (
    ALTITUDE_REFERENCES,
    CORNERS,
    START_KINDS,
    STRUCTURE_START_KINDS,
    StartSettings,
    greedy_start,
    initial_positions,
    start_configuration,
)
from ._starts3d import (
    StandoffStart,
    check_reachable,
    closest_faces,
    facing_attitudes,
    launch_pad_start,
    random_volume_start,
    standoff_start,
    surface_normals,
)
from ._viewpoints import MAX_CANDIDATES, GreedySettings, Viewpoints, viewpoint_lattice, viewpoint_offsets

__all__ = [
    "StandoffWorld",
    "World",
    "Constraints",
    "feasible_mask",
    "feasibility",
    "trajectory_feasible",
    "closest_admissible",
    "cvt",
    "CVTSettings",
    "CVTResult",
    "PRESETS",
    "default_samples_per_iteration",
    "seed_from_rng",
    "FootprintFit",
    "fit_footprints",
    "initial_positions",
    "start_configuration",
    "StartSettings",
    "START_KINDS",
    "STRUCTURE_START_KINDS",
    "CORNERS",
    "ALTITUDE_REFERENCES",
    "standoff_start",
    "StandoffStart",
    "random_volume_start",
    "launch_pad_start",
    "surface_normals",
    "facing_attitudes",
    "check_reachable",
    "closest_faces",
    "GreedySettings",
    "Viewpoints",
    "viewpoint_lattice",
    "viewpoint_offsets",
    "MAX_CANDIDATES",
    "CoverageProblem",
    "GreedyResult",
    "CoverageBound",
    "DualCertificate",
    "greedy_placement",
    "coverage_bound",
    "ExactResult",
    "exact_placement",
    "greedy_start",
]
