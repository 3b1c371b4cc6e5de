"""The paper's realistic environment: quadrotors with real dynamics fly the mission, and the team
measures what its depth cameras return (the ``uavcov[sim]`` extra: RotorPy).

Above the mission and the optimiser, below the experiments and the paper (whose realistic
scenario, :func:`uavcov.paper.reproduce_realistic`, it flies): :func:`fly_mission` runs CAO with a
measurement that flies each configuration (:class:`Team`, RotorPy's dynamics and SE(3)
controller) and senses at the states reached (:class:`DepthCamera` through the exact ray engine,
fused in a :class:`VoxelMap`); :func:`check_flight` checks every state against the limits.
"""

from __future__ import annotations

from ._closed_loop import MEASUREMENTS, FlownMission, SimSettings, fly_mission
from ._depth import DepthCamera, camera_rotation
from ._flight import INTEGRATORS, VEHICLES, FlightSettings, Leg, Team, hover_rotor_speed, vehicle_parameters
from ._record import FLOWN_FORMAT, FlownRun, is_flown_file, load_flown, save_flown
from ._safety import SafetyReport, check_flight
from ._voxels import VoxelMap, observed_targets, sensed_coverage
from ._wind import DrydenGusts, dryden_scales

__all__ = [
    "fly_mission",
    "FlownMission",
    "SimSettings",
    "MEASUREMENTS",
    "FlightSettings",
    "Team",
    "Leg",
    "VEHICLES",
    "INTEGRATORS",
    "DrydenGusts",
    "dryden_scales",
    "hover_rotor_speed",
    "vehicle_parameters",
    "DepthCamera",
    "camera_rotation",
    "VoxelMap",
    "observed_targets",
    "sensed_coverage",
    "SafetyReport",
    "FlownRun",
    "save_flown",
    "load_flown",
    "is_flown_file",
    "FLOWN_FORMAT",
    "check_flight",
]
