"""The points whose visibility defines coverage, each weighted by the surface area it stands for."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import as_float_array, as_points, within_coordinate_bound
from ..errors import InvalidInputError


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
    normals : (T, 3) array_like of float, optional
        Unit surface normals at the points, for sensors that limit the incidence angle or rate
        view quality (:mod:`uavcov.engine`). A grid terrain's own grid-node targets (the default
        of :class:`~uavcov.Visibility`) need none: the engine computes theirs.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, points beyond 1e15 m, negative weights or weights that
        are all zero.

    Examples
    --------
    >>> from uavcov import Targets
    >>> targets = Targets([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], weights=[1.0, 3.0])
    >>> len(targets), targets.total_weight
    (2, 4.0)
    """

    points: np.ndarray
    weights: np.ndarray
    normals: np.ndarray | None

    def __init__(self, points: Any, weights: Any = None, normals: Any = None) -> None:
        p = within_coordinate_bound(as_points(points, "targets"), "targets")  # as the surfaces they stand on
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
        n = None
        if normals is not None:
            n = as_points(normals, "normals").copy()
            if n.shape != p.shape:
                raise InvalidInputError(f"{n.shape[0]} normals for {p.shape[0]} targets")
            if (np.abs(np.einsum("ij,ij->i", n, n) - 1.0) > 1e-6).any():
                raise InvalidInputError("target normals must be unit vectors")
            n.setflags(write=False)
        object.__setattr__(self, "points", p)
        object.__setattr__(self, "weights", w)
        object.__setattr__(self, "normals", n)

    @classmethod
    def from_points(cls, points: Any, weights: Any = None, normals: Any = None) -> Targets:
        """Same as the constructor; reads better at call sites."""
        return cls(points, weights, normals)

    def __len__(self) -> int:
        return int(self.points.shape[0])

    def __reduce__(self) -> tuple[Any, ...]:
        normals = None if self.normals is None else np.array(self.normals)
        return (Targets, (np.array(self.points), np.array(self.weights), normals))

    @property
    def total_weight(self) -> float:
        """Sum of the weights (the surface area for a terrain's default targets)."""
        return float(self.weights.sum())
