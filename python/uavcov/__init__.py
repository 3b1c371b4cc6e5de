"""uavcov: multi-UAV visual coverage of partially known 3D surfaces.

The geometry (visibility, surface CVT) runs in Rust; the optimiser, scenarios and experiments
are thin Python on top. The names a user meets first are here; everything else lives in its
layer, from the bottom up:

- :mod:`uavcov.engine`: surfaces, targets, sensors, exact visibility and the tracker;
- :mod:`uavcov.terrain`: what a surface is made from (hills, buildings, mesh files, DEMs) and
  the prior S';
- :mod:`uavcov.structures`: structures that are not height fields (bridges, towers, mesh files)
  and their S';
- :mod:`uavcov.limits`: where a team may fly (flight limits, feasibility, the closest admissible
  configuration);
- :mod:`uavcov.cover`: candidate viewpoints, the greedy placement with its certified bound, the
  exact placement;
- :mod:`uavcov.placement`: the constrained CVT, starts, camera footprints;
- :mod:`uavcov.optim`: CAO, CAO with escapes from local optima, and CAO's random draws;
- :func:`run_mission` and :func:`save_mission` (one mission, one file);
- :mod:`uavcov.experiments`: specs x seeds on an executor into a results folder, sweep files;
- :mod:`uavcov.field`: areas of interest, flight plans on real DEMs and their files;
- :mod:`uavcov.paper`: the paper's experiments as data, their reproduction, reports and claims;
- :mod:`uavcov.plotting`: figures (needs ``uavcov[plot]``; imported on use).

Getting started (install, the README's two commands, a first mission in ten lines): the
documentation site's getting-started page, ``docs/getting-started.md``.
"""

from __future__ import annotations

from . import cover, engine, errors, experiments, field, limits, optim, paper, placement, structures, terrain
from ._core import __version__
from .engine import Camera, Gimbal, Sensor, Targets, Terrain, Visibility
from .field import FlightPlan, PlanSettings, plan, write_plan
from .limits import Constraints
from .mission import MissionResult, mission_time, run_mission
from .optim import CAOSettings, EscapeSettings
from .placement import CVTSettings, StartSettings
from .records import load_mission, save_mission
from .settings import MissionSettings
from .terrain import GeoDem, gaussian_hills, read_dem, sample_dem

__all__ = [
    "__version__",
    "errors",
    # the layers
    "engine",
    "terrain",
    "structures",
    "limits",
    "cover",
    "placement",
    "optim",
    "experiments",
    "field",
    "paper",
    # the exact geometry
    "Terrain",
    "Targets",
    "Visibility",
    "Sensor",
    "Camera",
    "Gimbal",
    # surfaces
    "gaussian_hills",
    "GeoDem",
    "read_dem",
    "sample_dem",
    # one mission: its settings, its run, its record
    "Constraints",
    "CVTSettings",
    "CAOSettings",
    "EscapeSettings",
    "StartSettings",
    "MissionSettings",
    "run_mission",
    "MissionResult",
    "mission_time",
    "save_mission",
    "load_mission",
    # a flight plan on a real site
    "PlanSettings",
    "FlightPlan",
    "plan",
    "write_plan",
]
