"""Flying a real site: areas of interest, flight plans on a GeoDem or around a geo-referenced
structure, the files a ground station reads, and a structure's seen point cloud."""

from __future__ import annotations

from ._area import AreaOfInterest, bbox_area, read_area
from ._geodesy import GeoAnchor
from ._outputs import write_plan
from ._plan import FlightPlan, PlanSettings, plan
from ._ply import write_seen_ply
from ._qgc import MAV_CMD_DO_MOUNT_CONTROL, MAV_FRAME_GLOBAL_RELATIVE_ALT
from ._results_folder import check_plan_folder
from ._structure_flight import StructureFlight
from ._structure_plan import StructurePlan, plan_structure, write_structure_plan

__all__ = [
    "AreaOfInterest",
    "bbox_area",
    "read_area",
    "write_plan",
    "check_plan_folder",
    "MAV_CMD_DO_MOUNT_CONTROL",
    "MAV_FRAME_GLOBAL_RELATIVE_ALT",
    "PlanSettings",
    "FlightPlan",
    "plan",
    "GeoAnchor",
    "StructurePlan",
    "StructureFlight",
    "plan_structure",
    "write_structure_plan",
    "write_seen_ply",
]
