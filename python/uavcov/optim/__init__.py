"""On-line optimisers: CAO (centralised and per robot) and the random draws it makes."""

from __future__ import annotations

from ._cao import MARGINAL_OPTIMIZERS, OPTIMIZERS, CAOSettings, Optimizer, OptimizerTrace, cao, per_robot_cao
from ._draws import redraw_monomials, standard_normal
from ._presets import CAO_PRESETS, PRESET_RANGE, cao_preset

__all__ = [
    "CAOSettings",
    "OptimizerTrace",
    "Optimizer",
    "cao",
    "per_robot_cao",
    "OPTIMIZERS",
    "MARGINAL_OPTIMIZERS",
    "standard_normal",
    "redraw_monomials",
    "CAO_PRESETS",
    "PRESET_RANGE",
    "cao_preset",
]
