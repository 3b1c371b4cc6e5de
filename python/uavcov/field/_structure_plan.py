"""A structure's plan: its mission made into what a crew flies and inspects, the seen cloud, the parts.

:func:`plan_structure` runs :func:`uavcov.run_mission` on a :class:`~uavcov.structures.Structure`
(standoff limits), finds for each UAV a route from the take-off pad that crosses no face of the
structure, and geo-references it from a WGS84 anchor (``structure_flight``);
:func:`write_structure_plan` writes the plan's files, the seen point cloud (PLY) and the
coverage of each part.

Routes: a UAV climbs over the pad to its position's height and flies straight to it when that
crosses nothing; else it climbs to a safe height (over the structure's top, under ``z_max``),
flies over its position and comes down; else (a position under a deck) it comes down beside the
structure, at the first of a ring of points round the position from which the way down and the
last level leg are clear. None clear: :class:`~uavcov.errors.InfeasibleError` naming the UAV.
"""

from __future__ import annotations

import csv
import io
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import as_float_array, read_only
from ..engine import Terrain, Visibility
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError
from ..mission import MissionResult, run_mission
from ..settings import MissionSettings
from ..structures import Structure, StructureTargets
from ._geodesy import GeoAnchor
from ._ply import seen_cloud_bytes
from ._provenance import check_provenance
from ._results_folder import write_files
from ._strict_json import json_bytes
from ._structure_flight import StructureFlight, render_structure_flight, structure_flight
from ._structure_report import structure_record, structure_report_md

# Ring of detours round a position, metres out and directions: enough to leave a deck's
# underside sideways on the scenes' bridges (decks 8-12 m wide) without searching a graph.
_DETOUR_RADII = (4.0, 8.0, 12.0, 16.0, 24.0)
_DETOUR_DIRECTIONS = 16
_LIFT_OFF_M = 0.01  # as structure_flight: the pad itself lies on the ground


@dataclass(frozen=True, eq=False)
class StructurePlan:
    """A structure's plan: the mission, what it sees, and the team's flight in WGS84 (:func:`plan_structure`).

    Attributes
    ----------
    result : MissionResult
        The mission (``result.coverage_by_part``: each part's share seen).
    targets : StructureTargets
        The targets coverage was measured on.
    seen_count : (T,) int64 ndarray
        How many UAVs of the best configuration see each target.
    flight : StructureFlight
        The best configuration in WGS84, with a clear route for each UAV.
    """

    result: MissionResult
    targets: StructureTargets
    seen_count: np.ndarray
    flight: StructureFlight


def _clear(surface: Terrain, path: np.ndarray) -> bool:
    return bool(surface.segments_clear(np.ascontiguousarray(path[:-1]), np.ascontiguousarray(path[1:])).all())


def structure_routes(surface: Terrain, pad: Any, positions: Any, safe_z: float) -> list[np.ndarray]:
    """For each position, waypoints from the pad (not included) that cross no face of ``surface``.

    Parameters
    ----------
    surface : Terrain
        The structure, ground included.
    pad : (3,) array_like
        The take-off pad, metres.
    positions : (N, 3) array_like
        Where each UAV goes, metres.
    safe_z : float
        A height above every face of the structure, metres.

    Returns
    -------
    list of (k, 3) float64 ndarray
        The waypoints before each position (see the module for the rule).

    Raises
    ------
    InfeasibleError
        No route of the rule is clear for some UAV.
    """
    start = np.asarray(pad, dtype=np.float64) + [0.0, 0.0, _LIFT_OFF_M]
    points = np.asarray(positions, dtype=np.float64)
    angles = 2.0 * np.pi * np.arange(_DETOUR_DIRECTIONS) / _DETOUR_DIRECTIONS
    ring = np.array([[r * np.cos(a), r * np.sin(a)] for r in _DETOUR_RADII for a in angles])
    routes = []
    for k, p in enumerate(points):
        high_pad = [start[0], start[1], max(safe_z, p[2])]
        options = [np.array([[start[0], start[1], p[2]]]), np.array([high_pad, [p[0], p[1], max(safe_z, p[2])]])]
        options += [np.array([high_pad, [p[0] + dx, p[1] + dy, safe_z], [p[0] + dx, p[1] + dy, p[2]]]) for dx, dy in ring]
        for option in options:
            if _clear(surface, np.vstack([start, option, p])):
                routes.append(option)
                break
        else:
            raise InfeasibleError(f"UAV {k + 1} at {p.round(2).tolist()}: no clear route from the pad found (tried {len(options)})")
    return routes


def plan_structure(
    structure: Structure,
    settings: MissionSettings,
    anchor: GeoAnchor,
    *,
    takeoff: Any = None,
    targets: StructureTargets | None = None,
    known: Any = None,
    hold_s: float = 30.0,
    rng: Any = None,
    n_threads: int | None = None,
) -> StructurePlan:
    """Run a structure's mission and make its best configuration a geo-referenced plan.

    Parameters
    ----------
    structure : Structure
        In a local east-north-up frame whose origin is ``anchor``.
    settings : MissionSettings
        With ``constraints.clearance == "standoff"`` (:func:`uavcov.run_mission`).
    anchor : GeoAnchor
        WGS84 longitude, latitude and ellipsoidal height of the local origin.
    takeoff : (3,) array_like, optional
        The pad, local metres; by default on the ground 2 m inside the flight box's south-west
        corner.
    targets : StructureTargets, optional
        Default ``structure.targets()``.
    known : optional
        As :func:`uavcov.run_mission`'s.
    hold_s : float, default 30
        Seconds each UAV holds its position.
    rng, n_threads
        As :func:`uavcov.run_mission`'s.

    Returns
    -------
    StructurePlan

    Raises
    ------
    InvalidInputError, InvalidTypeError
        Bad settings or arguments (a vertical clearance, a pad over no ground).
    InfeasibleError
        The team cannot be placed, or a UAV has no clear route.
    """
    if not isinstance(structure, Structure):
        raise InvalidTypeError(f"structure must be a uavcov Structure, got {type(structure).__name__}")
    if not isinstance(anchor, GeoAnchor):
        raise InvalidTypeError(f"anchor must be a uavcov.field.GeoAnchor, got {type(anchor).__name__}")
    chosen = structure.targets() if targets is None else targets
    result = run_mission(structure, settings, known=known, targets=chosen, rng=rng, n_threads=n_threads)
    surface = structure.surface
    limits = result.settings.constraints
    if takeoff is None:
        xmin, ymin, _, _ = limits.flight_box
        xy = np.array([[xmin + 2.0, ymin + 2.0]])
        pad = np.array([xy[0, 0], xy[0, 1], float(surface.ground_height(xy)[0])])
    else:
        pad = as_float_array(takeoff, "takeoff")
        if pad.shape != (3,) or not np.isfinite(pad).all():
            raise InvalidInputError(f"takeoff must be a finite local (x, y, z), got {takeoff!r}")
    if not np.isfinite(pad).all():
        raise InvalidInputError(f"the take-off pad at {pad[:2].tolist()} stands over no ground")
    best = np.asarray(result.best_positions)
    safe_z = min(float(surface.bounds[1, 2]) + max(limits.h_min, 1.0), limits.z_max)
    routes = structure_routes(surface, pad, best, safe_z)
    # How many UAVs see each target: one seen mask per UAV of the best configuration.
    vis = Visibility(surface, result.settings.d_max, chosen, n_threads=n_threads)
    sensors = result.settings.team_sensors()
    attitudes = result.best_attitudes
    poses = best if attitudes is None else np.column_stack([best, attitudes])
    count = np.zeros(len(chosen), dtype=np.int64)
    for k in range(best.shape[0]):
        count += vis.seen(poses[k : k + 1], sensors=None if sensors is None else sensors[k : k + 1])
    flight = structure_flight(best, anchor, takeoff=pad, attitudes=attitudes, routes=routes, surface=surface, hold_s=hold_s)
    return StructurePlan(result=result, targets=chosen, seen_count=read_only(count), flight=flight)


def write_structure_plan(plan: StructurePlan, out: Any, *, command: str | None = None, runtime_s: float | None = None) -> list[Path]:
    """Write the plan's files (``write_structure_flight``), ``seen.ply``, ``parts.csv`` and
    ``report.md`` into ``out``; ``plan.json`` adds the command, the seed, every setting, the
    versions and the coverage of the whole and of each part. A plan replaces its folder as a whole.

    Raises
    ------
    ResultsInUseError
        ``out`` holds files that are not a plan's.
    ResultsFolderError
        ``out`` is a file, or cannot be created or written.
    """
    if not isinstance(plan, StructurePlan):
        raise InvalidTypeError(f"plan must be a StructurePlan, got {type(plan).__name__}")
    command, runtime_s = check_provenance(command, runtime_s)
    files = render_structure_flight(plan.flight)
    document = {**json.loads(files["plan.json"]), **structure_record(plan, command, runtime_s)}
    files["plan.json"] = json_bytes(document, indent=2, what="plan.json")
    files["report.md"] = structure_report_md(plan, document)
    files["seen.ply"] = seen_cloud_bytes(plan.targets, plan.seen_count)
    table = io.StringIO()
    writer = csv.writer(table, lineterminator="\n")
    writer.writerow(["part", "seen_share"])
    for part, share in (plan.result.coverage_by_part or {}).items():
        writer.writerow([part, f"{share:.6f}"])
    writer.writerow(["all", f"{plan.result.best_coverage:.6f}"])
    files["parts.csv"] = table.getvalue().encode("utf-8")
    return write_files(files, out)
