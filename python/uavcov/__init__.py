"""uavcov: multi-UAV visual coverage of partially known 3D surfaces.

The geometry (visibility, surface CVT) runs in Rust; the optimiser, scenarios and experiments
are thin Python on top. See the README for a quick start.
"""

from __future__ import annotations

from . import errors
from ._core import __version__
from .surface import GridInfo, Terrain
from .targets import Targets
from .visibility import UavCounts, Visibility, coverage

__all__ = [
    "__version__",
    "errors",
    "GridInfo",
    "Terrain",
    "Targets",
    "UavCounts",
    "Visibility",
    "coverage",
]
