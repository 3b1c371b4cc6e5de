"""Where a team may fly: the flight limits (bounds, heights above the surface or a standoff from
it, separation, moves clear of the surface), the feasibility check the optimisers take, and the
closest admissible configuration."""

from __future__ import annotations

from ._constraints import Constraints, World, closest_admissible, feasibility

__all__ = [
    "World",
    "Constraints",
    "feasibility",
    "closest_admissible",
]
