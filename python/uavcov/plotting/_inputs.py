"""Checks of what the figures are given: mission results (or paths to saved runs), their
trajectories and coverage curves, points, surfaces and which configuration to show.

A stored result that lacks a field or holds broken arrays raises
:class:`~uavcov.errors.ResultsFormatError` naming what is wrong; a bad argument raises
:class:`~uavcov.errors.InvalidInputError` or :class:`~uavcov.errors.InvalidTypeError`.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from typing import Any

import numpy as np

from .._validate import as_points, is_int, within_coordinate_bound
from ..engine import Terrain
from ..errors import InvalidInputError, InvalidTypeError, ResultsFormatError
from ..records import load_mission


def _as_result(result: Any, needs: Sequence[str]) -> Any:
    """A mission result with the fields ``needs``; a path is read with :func:`load_mission`.

    Arrays the figure will use (trajectory, coverage curve) are checked here, so a broken
    stored run is refused before anything is drawn.
    """
    if isinstance(result, (str, os.PathLike)):
        result = load_mission(result)
    if result is None:
        raise ResultsFormatError("no result given (None)")
    missing = [name for name in needs if not hasattr(result, name)]
    if missing:
        raise ResultsFormatError(f"{type(result).__name__} is not a complete mission result: missing {', '.join(missing)}")
    for name in needs:
        if name in ("terrain", "approximation") and not isinstance(getattr(result, name), Terrain):
            raise ResultsFormatError(f"the result's {name} is not a Terrain")
    if "trajectory" in needs:
        _trajectory(result.trajectory)
    if "coverage" in needs:
        _curve(result.coverage)
    return result


def _trajectory(value: Any) -> np.ndarray:
    """The positions of every UAV at every iteration: finite float64, ``(K + 1, N, 3)``, metres."""
    try:
        traj = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError) as exc:  # OverflowError: an int or Fraction past the largest float
        raise ResultsFormatError(f"the trajectory is not numeric: {exc}") from exc
    if traj.ndim != 3 or traj.shape[2] != 3:
        raise ResultsFormatError(f"the trajectory must have shape (K + 1, N, 3), got {traj.shape}")
    if traj.shape[0] == 0 or traj.shape[1] == 0:
        raise ResultsFormatError(f"the trajectory is empty (shape {traj.shape})")
    if not np.isfinite(traj).all():
        raise ResultsFormatError("the trajectory holds NaN or infinite positions")
    return traj


def _curve(value: Any) -> np.ndarray:
    """A coverage curve, one share of the surface per iteration: finite float64, ``(K + 1,)``."""
    try:
        curve = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ResultsFormatError(f"the coverage curve is not numeric: {exc}") from exc
    if curve.ndim != 1 or curve.shape[0] == 0:
        raise ResultsFormatError(f"the coverage curve must be a non-empty (K + 1,) array, got shape {curve.shape}")
    if not np.isfinite(curve).all():
        raise ResultsFormatError("the coverage curve holds NaN or infinite values")
    return curve


def _setting(result: Any, name: str) -> Any:
    """A setting of the mission a result ran (``result.settings``), or None; "start" is its kind."""
    spec = getattr(result, "settings", None)
    if name == "start":
        return getattr(getattr(spec, "start", None), "kind", None)
    return getattr(spec, name, None)


def _d_max(result: Any) -> float:
    """The sensing range of a result's mission, metres (> 0)."""
    value = _setting(result, "d_max")
    if value is None:
        raise ResultsFormatError("the result's spec is missing d_max (the sensing range)")
    d = float(value)
    if not (math.isfinite(d) and d > 0):
        raise ResultsFormatError(f"the result's d_max must be a positive number, got {value!r}")
    return d


def _points(value: Any, name: str, *, allow_empty: bool = True) -> np.ndarray:
    """``(n, 3)`` finite float64 points within 1e15 m of the origin, metres:
    :func:`uavcov._validate.as_points`, except that any empty input (``[]`` as well as
    ``np.empty((0, 3))``) is no points when ``allow_empty``. A point beyond the bound would be
    drawn outside the axes (or make matplotlib's projection singular): refused.

    ``as_points`` reads ``[]`` as shape ``(0,)`` and refuses it; here "nothing seen" and "no
    known points" arrive that way, and they are valid.
    """
    try:
        empty = np.size(value) == 0
    except (TypeError, ValueError):
        empty = False  # ragged and the like: as_points says what is wrong
    if empty and allow_empty:
        return np.empty((0, 3))
    return within_coordinate_bound(as_points(value, name, allow_empty=allow_empty), name)


def _terrain(value: Any, name: str) -> Terrain:
    """``value`` itself when it is a :class:`~uavcov.engine.Terrain`."""
    if not isinstance(value, Terrain):
        raise InvalidTypeError(f"{name} must be a uavcov.Terrain, got {type(value).__name__}")
    return value


def _configuration(result: Any, configuration: Any) -> tuple[np.ndarray, str, int | None]:
    """The positions to show, how to call them, and their iteration (None when unknown)."""
    traj = _trajectory(result.trajectory)
    if is_int(configuration):
        k = int(configuration)
        if not -traj.shape[0] <= k < traj.shape[0]:
            raise InvalidInputError(f"configuration {k} is outside the trajectory (0..{traj.shape[0] - 1})")
        k %= traj.shape[0]
        return traj[k], f"positions at iteration {k}", k
    if not isinstance(configuration, str):
        raise InvalidInputError(f"configuration must be 'final', 'best', 'initial' or an iteration, got {configuration!r}")
    if configuration == "final":
        return traj[-1], f"final positions (iteration {traj.shape[0] - 1})", traj.shape[0] - 1
    if configuration == "initial":
        return traj[0], "start positions (iteration 0)", 0
    if configuration == "best":
        raw = getattr(result, "best_positions", None)
        if raw is None:
            raise ResultsFormatError("the result has no best_positions to show (configuration='best')")
        best = _points(raw, "best_positions", allow_empty=False)
        it = getattr(result, "best_iteration", None)
        if isinstance(it, (int, np.integer)) and 0 <= int(it) < traj.shape[0]:
            return best, f"best positions (iteration {int(it)})", int(it)
        return best, "best positions", None
    raise InvalidInputError(f"configuration must be 'final', 'best', 'initial' or an iteration, got {configuration!r}")


def _sight(result: Any, positions: np.ndarray, iteration: int | None) -> tuple[np.ndarray, list[Any] | None]:
    """What a run's UAVs see through at ``positions``: ``(positions, None)`` for the paper's
    sensor, else the poses ``(N, 5)`` (the run's camera angles at ``iteration``, or its spec's
    when the iteration is unknown) and each UAV's sensor."""
    spec = getattr(result, "settings", None)
    sensors = spec.team_sensors() if spec is not None and getattr(spec, "sensor", None) is not None else None
    if spec is None or sensors is None or len(sensors) != positions.shape[0]:
        return positions, None
    if not spec.has_camera:
        return positions, sensors
    attitudes = getattr(result, "attitudes", None)
    if attitudes is not None and iteration is not None and attitudes.shape[1] == positions.shape[0]:
        angles = np.asarray(attitudes[iteration])
    else:
        angles = np.broadcast_to(np.asarray(spec.attitude, dtype=np.float64), (positions.shape[0], 2))
    return np.column_stack([positions, angles]), sensors
