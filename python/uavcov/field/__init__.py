"""Flying a real site: areas of interest, flight plans on a GeoDem or around a geo-referenced
structure, the files a ground station reads, and a structure's seen point cloud."""

from __future__ import annotations

from ._area import AREA_FRAMES, AreaOfInterest, bbox_area, points_in_rings, read_area
from ._geodesy import GeoAnchor, enu_to_wgs84, local_to_true_heading
from ._gis_files import COVERAGE_NODATA, read_coverage_geotiff, read_plan_geojson, read_plan_kml
from ._outputs import render_plan, write_plan
from ._plan import TAKEOFF_FRAMES, FlightPlan, PlanSettings, plan
from ._plan_tables import read_positions_csv
from ._ply import read_seen_ply, seen_cloud_bytes, write_seen_ply
from ._qgc import (
    MAV_CMD_DO_MOUNT_CONTROL,
    MAV_CMD_NAV_LOITER_TIME,
    MAV_CMD_NAV_TAKEOFF,
    MAV_CMD_NAV_WAYPOINT,
    MAV_FRAME_GLOBAL_RELATIVE_ALT,
    qgc_plan,
    read_qgc_plan,
)
from ._results_folder import check_plan_folder
from ._structure_mission import StructureMission, plan_structure, structure_routes, write_structure_mission
from ._structure_plan import StructurePlan, render_structure_plan, structure_plan, structure_qgc_plan, write_structure_plan

__all__ = [
    "AreaOfInterest",
    "bbox_area",
    "read_area",
    "points_in_rings",
    "AREA_FRAMES",
    "write_plan",
    "check_plan_folder",
    "render_plan",
    "qgc_plan",
    "read_qgc_plan",
    "read_positions_csv",
    "read_plan_geojson",
    "read_plan_kml",
    "read_coverage_geotiff",
    "COVERAGE_NODATA",
    "MAV_CMD_NAV_TAKEOFF",
    "MAV_CMD_NAV_WAYPOINT",
    "MAV_CMD_NAV_LOITER_TIME",
    "MAV_CMD_DO_MOUNT_CONTROL",
    "MAV_FRAME_GLOBAL_RELATIVE_ALT",
    "PlanSettings",
    "FlightPlan",
    "plan",
    "TAKEOFF_FRAMES",
    "GeoAnchor",
    "enu_to_wgs84",
    "local_to_true_heading",
    "write_seen_ply",
    "read_seen_ply",
    "seen_cloud_bytes",
    "StructurePlan",
    "structure_plan",
    "structure_qgc_plan",
    "render_structure_plan",
    "write_structure_plan",
    "StructureMission",
    "plan_structure",
    "structure_routes",
    "write_structure_mission",
]
