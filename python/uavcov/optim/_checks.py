"""What CAO checks of its inputs and of what the user's callables return."""

from __future__ import annotations

import math
import numbers
import time
from typing import Any

import numpy as np

from .._validate import MAX_ITERATIONS, as_count, as_float_array, as_points
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError
from ._protocol import FeasibleFn
from ._settings import CAOSettings


def _check_common(x0: Any, feasible: Any, iterations: Any, settings: Any, *, positions_only: bool = True) -> tuple[np.ndarray, int]:
    if not isinstance(settings, CAOSettings):
        raise InvalidTypeError(f"settings must be a CAOSettings, got {type(settings).__name__}")
    if positions_only:
        x0 = as_points(x0, "x0")
    else:
        x0 = as_float_array(x0, "x0")
        if x0.ndim != 2 or x0.shape[0] == 0 or x0.shape[1] < 3:
            raise InvalidInputError(f"x0 must have shape (N, d) with N >= 1 and d >= 3 (a position, then any angles), got {x0.shape}")
    iterations = as_count(iterations, "iterations", MAX_ITERATIONS, minimum=0)
    if feasible is not None and not callable(feasible):
        raise InvalidTypeError(f"feasible must be callable or None, got {type(feasible).__name__}")
    return x0, iterations


def _as_value(raw: Any, what: str, k: int) -> float:
    if isinstance(raw, bool) or not isinstance(raw, (numbers.Real, np.floating, np.integer)):
        if isinstance(raw, np.ndarray) and raw.ndim == 0:
            raw = raw.item()
        else:
            raise InvalidTypeError(f"{what} must return a real number, got {type(raw).__name__} at iteration {k}")
    value = float(raw)
    if not math.isfinite(value):
        raise InvalidInputError(f"{what} returned {value} at iteration {k}")
    return value


def _as_team_and_marginals(raw: Any, n_uavs: int, k: int) -> tuple[float, np.ndarray]:
    if not isinstance(raw, tuple) or len(raw) != 2:
        raise InvalidTypeError(
            f"per-robot measure must return (team value, marginals of shape ({n_uavs},)), got {type(raw).__name__} at iteration {k}"
        )
    team = _as_value(raw[0], "measure (team value)", k)
    marginals = np.asarray(raw[1], dtype=np.float64) if not isinstance(raw[1], (str, bytes)) else None
    if marginals is None or marginals.shape != (n_uavs,) or not np.isfinite(marginals).all():
        raise InvalidInputError(f"per-robot measure must return finite marginals of shape ({n_uavs},) at iteration {k}")
    return team, marginals


class _Feasibility:
    """Calls the user's feasibility test, checks what it returns and times it."""

    def __init__(self, feasible: FeasibleFn | None) -> None:
        self.feasible = feasible
        self.seconds = 0.0

    def __call__(self, current: np.ndarray, candidates: np.ndarray) -> np.ndarray:
        if self.feasible is None:
            return np.ones(candidates.shape[0], dtype=bool)
        start = time.perf_counter()
        mask = self.feasible(current.copy(), candidates.copy())
        self.seconds += time.perf_counter() - start
        mask = np.asarray(mask)
        if mask.shape != (candidates.shape[0],) or mask.dtype != np.bool_:
            raise InvalidInputError(
                f"feasible must return a ({candidates.shape[0]},) bool array, got shape {mask.shape} dtype {mask.dtype}"
            )
        return mask


def _check_start(check: _Feasibility, x0: np.ndarray) -> None:
    if not check(x0, x0[None])[0]:
        raise InfeasibleError("the start configuration is infeasible; move it first with uavcov.limits.closest_admissible")
