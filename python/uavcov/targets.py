"""The points whose visibility defines coverage, each weighted by the surface area it stands for."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ._validate import as_float_array, as_points
from .errors import InvalidInputError

__all__ = ["Targets"]


@dataclass(frozen=True, eq=False)
class Targets:
    """Target points and their weights.

    Parameters
    ----------
    points : (T, 3) array_like of float
        Points on (or near) the surface, metres.
    weights : (T,) array_like of float, optional
        The area each point stands for (m^2) or any non-negative importance; 1 each by default.
        Coverage is the weighted share of targets seen, so only ratios matter.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, negative weights or weights that are all zero.

    Examples
    --------
    >>> from uavcov import Targets
    >>> targets = Targets([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], weights=[1.0, 3.0])
    >>> len(targets), targets.total_weight
    (2, 4.0)
    """

    points: np.ndarray
    weights: np.ndarray

    def __init__(self, points: Any, weights: Any = None) -> None:
        p = as_points(points, "targets")
        if weights is None:
            w = np.ones(p.shape[0])
        else:
            w = as_float_array(weights, "weights", ndim=1)
            if w.shape[0] != p.shape[0]:
                raise InvalidInputError(f"{w.shape[0]} weights for {p.shape[0]} targets")
            if (w < 0).any():
                raise InvalidInputError("target weights must be >= 0")
            if not w.sum() > 0:
                raise InvalidInputError("target weights are all zero")
        p = p.copy()  # our own read-only copy: later edits to the caller's array change nothing
        w = w.copy()
        p.setflags(write=False)
        w.setflags(write=False)
        object.__setattr__(self, "points", p)
        object.__setattr__(self, "weights", w)

    @classmethod
    def from_points(cls, points: Any, weights: Any = None) -> Targets:
        """Same as the constructor; reads better at call sites."""
        return cls(points, weights)

    def __len__(self) -> int:
        return int(self.points.shape[0])

    def __reduce__(self) -> tuple[Any, ...]:
        return (Targets, (np.array(self.points), np.array(self.weights)))

    @property
    def total_weight(self) -> float:
        """Sum of the weights (the surface area for a terrain's default targets)."""
        return float(self.weights.sum())
