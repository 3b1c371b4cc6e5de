"""What made a plan, for its record: the library versions, settings as strict JSON."""

from __future__ import annotations

import math
import platform
from importlib import metadata
from typing import Any

from .._core import __version__
from .._validate import as_non_negative_float, as_optional_str

_LIBRARIES = ("numpy", "scipy", "pyproj", "rasterio", "trimesh")


def versions() -> dict[str, str]:
    """uavcov's version, Python's and those of the libraries a plan goes through (installed ones only)."""
    found = {"uavcov": str(__version__), "python": platform.python_version()}
    for name in _LIBRARIES:
        try:
            found[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue
    return found


def versions_line(found: dict[str, str]) -> str:
    """``uavcov 0.1.0, python 3.11.2, numpy 2.1.0, ...``."""
    return ", ".join(f"{name} {version}" for name, version in found.items())


def check_provenance(command: Any, runtime_s: Any) -> tuple[str | None, float | None]:
    """A plan record's ``command`` (None or a string) and ``runtime_s`` (None or finite seconds >= 0)."""
    return as_optional_str(command, "command"), None if runtime_s is None else as_non_negative_float(runtime_s, "runtime_s")


def json_safe(value: Any) -> Any:
    """``value`` (dicts, lists, tuples, numbers) with every non-finite float as None: JSON has no
    infinity, and an unbounded setting (``z_max = inf``) is written as ``null``."""
    if isinstance(value, dict):
        return {str(k): json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
