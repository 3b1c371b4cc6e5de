"""The team's fused map: every depth point in voxels, and the surface targets it has observed.

Voxel hashing in numpy: a point's voxel is ``floor(p / size)``, its three integers packed into
one 64-bit key; the map keeps one point per voxel (the mean of the points that fell in it), so
its size is bounded by the surface's area over ``size**2``, not by the images' pixels. A target
is observed when a sensed point lies within ``radius`` of it (scipy's k-d tree, exact).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from .._validate import as_float_array, as_positive_float
from ..engine import Targets
from ..errors import InvalidInputError, InvalidTypeError

__all__ = ["VoxelMap", "observed_targets", "sensed_coverage"]

_BITS = 21  # per axis: 2 million voxels a side
_OFFSET = 1 << (_BITS - 1)


def _keys(cells: np.ndarray) -> np.ndarray:
    if cells.size and (np.abs(cells).max() >= _OFFSET):
        raise InvalidInputError(f"a point lies beyond {_OFFSET:,} voxels from the origin: use larger voxels")
    shifted = (cells + _OFFSET).astype(np.int64)
    return np.asarray((shifted[:, 0] << (2 * _BITS)) | (shifted[:, 1] << _BITS) | shifted[:, 2])


@dataclass
class VoxelMap:
    """Points fused into voxels of ``size`` metres: one point (the mean) per occupied voxel.

    Mutable: :meth:`add` fuses more points.
    """

    size: float
    _keys: np.ndarray = field(default_factory=lambda: np.empty(0, np.int64), repr=False)
    _sums: np.ndarray = field(default_factory=lambda: np.empty((0, 3)), repr=False)
    _counts: np.ndarray = field(default_factory=lambda: np.empty(0, np.int64), repr=False)

    def __post_init__(self) -> None:
        self.size = as_positive_float(self.size, "size")

    def add(self, points: Any) -> None:
        """Fuse ``(n, 3)`` points (metres) into the map."""
        pts = as_float_array(points, "points")
        if pts.ndim != 2 or pts.shape[1] != 3 or not np.isfinite(pts).all():
            raise InvalidInputError(f"points must be finite, of shape (n, 3), got shape {pts.shape}")
        if not len(pts):
            return
        keys = _keys(np.floor(pts / self.size))
        all_keys = np.concatenate([self._keys, keys])
        unique, inverse = np.unique(all_keys, return_inverse=True)
        sums = np.zeros((len(unique), 3))
        np.add.at(sums, inverse[: len(self._keys)], self._sums)
        np.add.at(sums, inverse[len(self._keys) :], pts)
        counts = np.zeros(len(unique), np.int64)
        np.add.at(counts, inverse[: len(self._keys)], self._counts)
        np.add.at(counts, inverse[len(self._keys) :], 1)
        self._keys, self._sums, self._counts = unique, sums, counts

    def __len__(self) -> int:
        return int(self._keys.size)

    @property
    def points(self) -> np.ndarray:
        """``(V, 3)`` the mean point of each occupied voxel, metres."""
        return np.asarray(self._sums / self._counts[:, None])

    @property
    def counts(self) -> np.ndarray:
        """``(V,)`` points fused into each voxel."""
        return self._counts.copy()


def observed_targets(targets: Targets, points: Any, radius: float) -> np.ndarray:
    """``(T,)`` bool: which targets have a sensed point within ``radius`` metres."""
    if not isinstance(targets, Targets):
        raise InvalidTypeError(f"targets must be a uavcov.Targets, got {type(targets).__name__}")
    radius = as_positive_float(radius, "radius")
    pts = as_float_array(points, "points")
    if pts.size == 0:  # nothing sensed yet, whatever the empty shape
        pts = pts.reshape(0, 3)
    elif pts.shape == (3,):
        pts = pts.reshape(1, 3)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise InvalidInputError(f"points must have shape (n, 3), got {pts.shape}")
    if not len(pts):
        return np.zeros(len(targets), dtype=bool)
    distance, _ = cKDTree(pts).query(targets.points, k=1, distance_upper_bound=radius)
    return np.asarray(np.isfinite(distance))


def sensed_coverage(targets: Targets, points: Any, radius: float) -> float:
    """Weighted share of ``targets`` observed by ``points`` (:func:`observed_targets`), in [0, 1]."""
    seen = observed_targets(targets, points, radius)
    weights = np.asarray(targets.weights, dtype=np.float64)
    return float(weights[seen].sum() / weights.sum())
