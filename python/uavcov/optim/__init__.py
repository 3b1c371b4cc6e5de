"""On-line optimisers: CAO (centralised, per robot, and with escapes from local optima) and the random draws it makes."""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from ._cao import cao
from ._draws import standard_normal
from ._escape import EscapeSettings, escape_cao
from ._per_robot import per_robot_cao
from ._presets import CAO_PRESETS, cao_preset
from ._protocol import Optimizer
from ._settings import CAOSettings
from ._trace import OptimizerTrace

OPTIMIZERS: Mapping[str, Optimizer] = MappingProxyType({"cao": cao, "per_robot": per_robot_cao, "escape": escape_cao})
"""Optimisers by name, for the mission and the command line."""

MARGINAL_OPTIMIZERS: frozenset[str] = frozenset({"per_robot", "escape"})
"""Names in :data:`OPTIMIZERS` whose ``measure`` returns ``(team value, marginals)`` (each UAV's exclusive share)."""

__all__ = [
    "CAOSettings",
    "OptimizerTrace",
    "cao",
    "per_robot_cao",
    "EscapeSettings",
    "OPTIMIZERS",
    "MARGINAL_OPTIMIZERS",
    "standard_normal",
    "CAO_PRESETS",
    "cao_preset",
]
