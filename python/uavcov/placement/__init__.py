"""Where a team starts: the constrained CVT, the start configurations (the greedy start on
:mod:`uavcov.cover`'s lattice among them), a structure's standoff start with cameras facing it,
and camera footprints."""

from __future__ import annotations

from ._cvt import PRESETS, CVTResult, CVTSettings, cvt
from ._footprints import FootprintFit, fit_footprints
from ._starts import ALTITUDE_REFERENCES, CORNERS, START_KINDS, StartSettings, start_configuration
from ._starts3d import StandoffStart, facing_attitudes, standoff_start

__all__ = [
    "cvt",
    "CVTSettings",
    "CVTResult",
    "PRESETS",
    "FootprintFit",
    "fit_footprints",
    "start_configuration",
    "StartSettings",
    "START_KINDS",
    "CORNERS",
    "ALTITUDE_REFERENCES",
    "standoff_start",
    "StandoffStart",
    "facing_attitudes",
]
