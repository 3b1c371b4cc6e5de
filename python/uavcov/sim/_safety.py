"""Every simulated state against the flight limits and the mesh, and how far the flown path strays.

The optimiser keeps its waypoints admissible (eq. 2: clearance above the ground in
``[h_min, h_max]``, altitude under ``z_max``, inside the bounds, ``d_safe`` apart, moves that
cross no surface); between and around them the vehicles fly a controller's path. This module
checks each recorded state, not only the waypoints, and measures the two margins that keep the
flown path inside the limits: how far a state strays from the straight move it was commanded
(tighten every limit by it) and how far it overshoots the waypoint along the move.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import as_float_array, as_index_array
from ..engine import Terrain
from ..errors import InvalidInputError, InvalidTypeError
from ..limits import Constraints

__all__ = ["SafetyReport", "check_flight"]


@dataclass(frozen=True)
class SafetyReport:
    """The flown states against the limits. Distances in metres.

    Attributes
    ----------
    n_states : int
        States checked (every control period of every vehicle).
    min_clearance : float
        Least clearance straight down to the surface (the limit: ``h_min``).
    max_clearance : float
        Most clearance straight down (the limit: ``h_max``, when set).
    min_distance : float
        Least 3D distance to the surface (a collision at 0).
    min_separation : float
        Least distance between two vehicles (the limit: ``d_safe``).
    max_altitude : float
        Highest altitude (the limit: ``z_max``).
    out_of_bounds : int
        States outside the x-y bounds.
    violations : int
        States that break some limit.
    below_h_min, above_h_max, above_z_max, too_close : int
        States under ``h_min`` (or touching the mesh), over ``h_max``, over ``z_max``, and
        closer than ``d_safe`` to another vehicle; ``h_min`` and ``h_max`` bound what the
        constraints' ``clearance`` says (straight down, or the 3D standoff to any surface). ``h_max`` binds the waypoints only (eq. 2): a
        straight move from above a roof past its edge crosses it as well, so this count is
        compared with :attr:`straight_above_h_max`.
    straight_above_h_max : int
        The same count for the straight commanded moves sampled at the same instants (each
        state's foot on its move): what the kinematic model flies through.
    straight_below_h_min : int
        States whose foot on the straight move lies under ``h_min``: eq. 2 binds the waypoints,
        and a straight move between two admissible ones can pass under ``h_min`` (over a ridge,
        a roof's edge) as the kinematic model flies it.
    straight_min_distance : float
        Least 3D distance to the surface of those feet: how close the kinematic model's moves
        come to the surface (the paper's limits bound the clearance straight down, not the
        distance to a wall beside the UAV).
    max_deviation : float
        Farthest a state strayed from its straight commanded move (the margin by which the
        limits must be tightened for the flown path to keep them).
    max_overshoot : float
        Farthest a state went past its waypoint along the move.
    """

    n_states: int
    min_clearance: float
    max_clearance: float
    min_distance: float
    min_separation: float
    max_altitude: float
    out_of_bounds: int
    violations: int
    below_h_min: int
    above_h_max: int
    above_z_max: int
    too_close: int
    straight_above_h_max: int
    max_deviation: float
    max_overshoot: float
    straight_below_h_min: int = 0
    straight_min_distance: float = float("nan")

    @property
    def safe(self) -> bool:
        """Whether no state broke a limit."""
        return self.violations == 0


def _segment_offsets(points: np.ndarray, start: np.ndarray, goal: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Distance of each point ``(M, N, 3)`` to its straight move ``start -> goal`` (same shape),
    how far past the goal it lies along the move (its distance to the goal for a move of 0), and
    its foot on the move."""
    move = goal - start
    length = np.linalg.norm(move, axis=2)
    unit = np.divide(move, length[..., None], out=np.zeros_like(move), where=length[..., None] > 0)
    along = np.einsum("mnk,mnk->mn", points - start, unit)
    foot = start + np.clip(along, 0.0, length)[..., None] * unit
    deviation = np.linalg.norm(points - foot, axis=2)
    overshoot = np.where(length > 0, np.maximum(along - length, 0.0), np.linalg.norm(points - goal, axis=2))
    return deviation, overshoot, foot


def _checked(
    terrain: Any, constraints: Any, positions: Any, leg_of_state: Any, starts: Any, goals: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """check_flight's inputs as arrays of consistent shapes, or a clear error."""
    if not isinstance(terrain, Terrain):
        raise InvalidTypeError(f"terrain must be a Terrain, got {type(terrain).__name__}")
    if not isinstance(constraints, Constraints) or constraints.bounds is None:
        raise InvalidTypeError("constraints must be a Constraints resolved against the terrain (Constraints.resolve)")
    states = as_float_array(positions, "positions", ndim=3)
    begin, end = as_float_array(starts, "starts", ndim=3), as_float_array(goals, "goals", ndim=3)
    if states.shape[0] == 0 or states.shape[1:] != begin.shape[1:] or begin.shape != end.shape or states.shape[2] != 3:
        raise InvalidInputError(f"positions (M, N, 3), starts and goals (L, N, 3) disagree: {states.shape}, {begin.shape}, {end.shape}")
    legs = as_index_array(leg_of_state, "leg_of_state", columns=None)
    if legs.shape != (states.shape[0],) or legs.min(initial=0) < 0 or legs.max(initial=0) >= begin.shape[0]:
        raise InvalidInputError(f"leg_of_state must be {states.shape[0]} leg indices in [0, {begin.shape[0]})")
    return states, legs, begin, end


def check_flight(
    terrain: Terrain,
    constraints: Constraints,
    positions: np.ndarray,
    leg_of_state: np.ndarray,
    starts: np.ndarray,
    goals: np.ndarray,
) -> SafetyReport:
    """Check every flown state against ``constraints`` (resolved) and the mesh.

    Parameters
    ----------
    terrain : Terrain
        The true surface.
    constraints : Constraints
        The mission's flight limits, resolved against ``terrain``.
    positions : (M, N, 3) ndarray
        Every state of every vehicle, metres.
    leg_of_state : (M,) ndarray of int
        The leg each state belongs to.
    starts, goals : (L, N, 3) ndarray
        Where each leg began and the waypoints it was commanded to.
    """
    positions, leg_of_state, starts, goals = _checked(terrain, constraints, positions, leg_of_state, starts, goals)
    m, n, _ = positions.shape
    flat = positions.reshape(-1, 3)
    clearance = terrain.clearance(flat).reshape(m, n)
    distance = terrain.distance(flat).reshape(m, n)
    xmin, ymin, xmax, ymax = constraints.flight_box
    outside = (flat[:, 0] < xmin) | (flat[:, 0] > xmax) | (flat[:, 1] < ymin) | (flat[:, 1] > ymax)
    # What h_min and h_max bound: the clearance straight down (eq. 2) or the 3D standoff.
    bounded = clearance if constraints.clearance == "vertical" else distance
    bad = (bounded < constraints.h_min) | (positions[..., 2] > constraints.z_max) | outside.reshape(m, n) | (distance <= 0.0)
    if constraints.h_max is not None:
        bad |= bounded > constraints.h_max
    separation = np.inf
    crowded = np.zeros((m, n), dtype=bool)
    if n > 1:
        gaps = np.linalg.norm(positions[:, :, None, :] - positions[:, None, :, :], axis=3)
        gaps[:, np.arange(n), np.arange(n)] = np.inf
        separation = float(gaps.min())
        if constraints.d_safe:
            crowded = (gaps < constraints.d_safe).any(axis=2)
            bad |= crowded
    deviation, overshoot, feet = _segment_offsets(positions, starts[leg_of_state], goals[leg_of_state])
    low = (bounded < constraints.h_min) | (distance <= 0.0)
    high = np.zeros_like(low) if constraints.h_max is None else bounded > constraints.h_max
    foot_distance = terrain.distance(feet.reshape(-1, 3))
    foot_bounded = terrain.clearance(feet.reshape(-1, 3)) if constraints.clearance == "vertical" else foot_distance
    straight_high = 0 if constraints.h_max is None else int((foot_bounded > constraints.h_max).sum())
    return SafetyReport(
        n_states=int(m * n),
        min_clearance=float(clearance.min()),
        max_clearance=float(clearance.max()),
        min_distance=float(distance.min()),
        min_separation=separation,
        max_altitude=float(positions[..., 2].max()),
        out_of_bounds=int(outside.sum()),
        violations=int(bad.sum()),
        below_h_min=int(low.sum()),
        above_h_max=int(high.sum()),
        above_z_max=int((positions[..., 2] > constraints.z_max).sum()),
        too_close=int(crowded.sum()),
        straight_above_h_max=straight_high,
        max_deviation=float(deviation.max()),
        max_overshoot=float(overshoot.max()),
        straight_below_h_min=int((foot_bounded < constraints.h_min).sum()),
        straight_min_distance=float(foot_distance.min()),
    )
