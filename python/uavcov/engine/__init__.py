"""The exact geometry over the Rust core: surfaces, targets, sensors, visibility and the tracker."""

from __future__ import annotations

from ._sensors import Camera, Gimbal, Sensor, camera_axes, gimbal_pitch_limits, pack_sensors
from ._surface import GridInfo, Terrain, as_mesh_surface, degenerate_faces
from ._targets import Targets
from ._visibility import CoverageTracker, UavCounts, Visibility, coverage

__all__ = [
    "Camera",
    "Sensor",
    "Gimbal",
    "camera_axes",
    "gimbal_pitch_limits",
    "pack_sensors",
    "Terrain",
    "GridInfo",
    "as_mesh_surface",
    "degenerate_faces",
    "Targets",
    "Visibility",
    "CoverageTracker",
    "UavCounts",
    "coverage",
]
