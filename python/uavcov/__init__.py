"""uavcov: multi-UAV visual coverage of partially known 3D surfaces.

The geometry (visibility, surface CVT) runs in Rust; the optimiser, scenarios and experiments
are thin Python on top. See the README for a quick start.
"""

from __future__ import annotations

from . import errors
from ._core import __version__
from .area import AreaOfInterest, bbox_area, read_area
from .buildings import (
    Building,
    buildings_scene,
    buildings_terrain,
    perturb_buildings,
    random_buildings,
)
from .cao import CAOSettings, OptimizerTrace, cao, per_robot_cao
from .constraints import Constraints, closest_admissible, feasibility, feasible_mask, trajectory_feasible
from .cvt import CVTResult, CVTSettings, cvt
from .geo import GeoDem, dem_from_array, read_dem, sample_geo_dem
from .hills import (
    GaussianMixture,
    gaussian_hills,
    random_gaussian_mixture,
)
from .loaders import (
    LoadedTerrain,
    LocalFrame,
    MeshReport,
    clean_mesh,
    load_dem,
    load_geotiff,
    load_mesh,
    mesh_terrain,
    metres_per_degree,
    sample_dem,
)
from .mission import MissionResult, MissionSpec, run_mission
from .plan import FlightPlan, PlanSettings
from .plan_outputs import write_plan
from .prior import (
    ApproximationError,
    Prior,
    approximate_surface,
    approximation_error,
    building_corner_prior,
    buildings_prior,
    sample_prior,
)
from .records import load_mission, save_mission
from .sensors import Camera, Gimbal, Sensor, camera_axes
from .starts import StartSpec, initial_positions, start_configuration
from .surface import GridInfo, Terrain
from .targets import Targets
from .visibility import CoverageTracker, UavCounts, Visibility, coverage

__all__ = [
    "__version__",
    "errors",
    "GridInfo",
    "Terrain",
    "Targets",
    "CoverageTracker",
    "UavCounts",
    "Visibility",
    "coverage",
    # sensors
    "Camera",
    "Sensor",
    "Gimbal",
    "camera_axes",
    # surfaces
    "Building",
    "GaussianMixture",
    "LoadedTerrain",
    "LocalFrame",
    "MeshReport",
    "buildings_scene",
    "buildings_terrain",
    "clean_mesh",
    "gaussian_hills",
    "load_dem",
    "load_geotiff",
    "load_mesh",
    "mesh_terrain",
    "metres_per_degree",
    "perturb_buildings",
    "random_buildings",
    "random_gaussian_mixture",
    "sample_dem",
    # partial knowledge
    "ApproximationError",
    "Prior",
    "approximate_surface",
    "approximation_error",
    "building_corner_prior",
    "buildings_prior",
    "sample_prior",
    # the constrained CVT and the starts
    "CVTResult",
    "CVTSettings",
    "cvt",
    "StartSpec",
    "initial_positions",
    "start_configuration",
    # on-line optimisation
    "CAOSettings",
    "OptimizerTrace",
    "cao",
    "per_robot_cao",
    "Constraints",
    "closest_admissible",
    "feasibility",
    "feasible_mask",
    "trajectory_feasible",
    # the mission and its records
    "MissionResult",
    "MissionSpec",
    "run_mission",
    "load_mission",
    "save_mission",
    # real ground: geo-referenced DEMs, areas of interest, flight plans (uavcov.plan.plan)
    "GeoDem",
    "dem_from_array",
    "read_dem",
    "sample_geo_dem",
    "AreaOfInterest",
    "bbox_area",
    "read_area",
    "FlightPlan",
    "PlanSettings",
    "write_plan",
]


def __getattr__(name: str) -> object:
    if name == "MissionSettings":
        import warnings

        warnings.warn("uavcov.MissionSettings is deprecated; use uavcov.MissionSpec", DeprecationWarning, stacklevel=2)
        return MissionSpec
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
