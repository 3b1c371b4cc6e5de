"""The exceptions uavcov raises for input a user can get wrong.

Every error derives from :class:`UavcovError`, and also from the built-in class of what
happened (``ValueError``, ``TypeError``, ``OSError``, ``ImportError``, ``TimeoutError``), so
``except ValueError`` or ``except OSError`` keeps working in user code.
"""

from __future__ import annotations

__all__ = [
    "UavcovError",
    "InvalidInputError",
    "InvalidTypeError",
    "MeshError",
    "SurfaceTooLargeError",
    "ModelTooLargeError",
    "ConfigError",
    "InfeasibleError",
    "ResultsFormatError",
    "ResultsFolderError",
    "ResultsInUseError",
    "MissingExtraError",
    "SchedulerTimeoutError",
    "FlightError",
]


class UavcovError(Exception):
    """Base class of every error raised by uavcov.

    Raised as itself only for an internal error: a bug of uavcov's Rust core, caught at the
    binding instead of crossing into Python as a panic (please report it with its message).
    """


class InvalidInputError(UavcovError, ValueError):
    """A value has the wrong shape, is not finite, or is out of its documented range.

    Sizes too (team size, CVT generators and samples, iterations, seeds, runs of a sweep): each
    has a generous limit, checked before anything is allocated; the limits are listed in one
    table, in the docstring of ``uavcov._validate``.
    """


class InvalidTypeError(UavcovError, TypeError):
    """An argument has the wrong type or dtype (for example a float array for mesh faces)."""


class MeshError(InvalidInputError):
    """A surface mesh is empty, degenerate, has out-of-range indices, or cannot be read."""


class SurfaceTooLargeError(InvalidInputError):
    """A surface would need more memory than the chosen ``method`` allows; use the grid method.

    A general mesh, and the mesh method (``method="mesh"``) on a grid, keep a BVH over every
    triangle and are refused beyond 10 million triangles; the grid method of a terrain built with
    :meth:`~uavcov.engine.Terrain.from_grid` needs no triangle list (up to 2^32 nodes).
    """


class ModelTooLargeError(InvalidInputError):
    """An optimisation model would need more memory than allowed (checked before it is built).

    :func:`uavcov.cover.exact_placement` estimates its integer program from the non-zeros of
    the seen-matrix; fewer candidates or targets, or a larger ``max_model_bytes``, make it fit.
    """


class ConfigError(InvalidInputError):
    """A sweep or command-line configuration does not parse or names unknown settings."""


class InfeasibleError(InvalidInputError):
    """Settings that no configuration can satisfy (for example d_safe too large for N UAVs)."""


class ResultsFormatError(InvalidInputError):
    """Stored results are empty, from an unknown format, or miss fields a consumer needs."""


class ResultsFolderError(UavcovError, OSError):
    """A results folder cannot be created or written (a file in its place, no permission, ...)."""


class ResultsInUseError(ConfigError):
    """A results folder holds other results, or another process is writing to it."""


class MissingExtraError(UavcovError, ImportError):
    """An optional dependency is not installed; the message names the extra that provides it."""


class SchedulerTimeoutError(UavcovError, TimeoutError):
    """A Dask scheduler did not answer in time."""


class FlightError(UavcovError, RuntimeError):
    """A simulated flight failed: a vehicle did not settle at its waypoint in the time allowed
    (a waypoint it cannot reach, wind beyond its thrust), or it hit the surface.

    :mod:`uavcov.sim` raises it from a single flight, and records it as the failure of a mission
    (``FlownMission.failure``) when a whole mission flies. ``leg`` holds the states flown until
    the failure (a ``uavcov.sim.Leg``), or None.
    """

    leg: object | None = None
