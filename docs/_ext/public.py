"""The public names of uavcov: every name of the ``__all__`` of the package and of each layer.

Shared by the site (``crossrefs``: each must be documented) and ``tests/test_docs.py`` (each
must be listed in ``docs/api``).
"""

from __future__ import annotations

import importlib
from typing import Any

# Bottom-up, as docs/design.md lists the layers: a name re-exported upwards (``uavcov.Terrain``)
# is documented once, at the lowest module that lists it (``uavcov.engine.Terrain``).
MODULES = (
    "uavcov.errors",
    "uavcov.engine",
    "uavcov.terrain",
    "uavcov.structures",
    "uavcov.limits",
    "uavcov.cover",
    "uavcov.placement",
    "uavcov.optim",
    "uavcov.settings",
    "uavcov.mission",
    "uavcov.records",
    "uavcov.experiments",
    "uavcov.field",
    "uavcov.paper",
    "uavcov.sim",
    "uavcov.plotting",
)
TOP = "uavcov"


def public_names(module: str) -> list[str]:
    """The ``__all__`` of ``module``, in its order."""
    return list(importlib.import_module(module).__all__)


def canonical_names() -> dict[int, str]:
    """``id(obj) -> "module.name"`` for every public class, function and module, at the lowest
    layer that lists it. Constants are left out: equal small values share an id."""
    found: dict[int, str] = {}
    for module in (*MODULES, TOP):
        mod = importlib.import_module(module)
        found.setdefault(id(mod), module)
        for name in mod.__all__:
            obj: Any = getattr(mod, name)
            if callable(obj) or isinstance(obj, type(mod)):
                found.setdefault(id(obj), obj.__name__ if isinstance(obj, type(mod)) else f"{module}.{name}")
    return found
