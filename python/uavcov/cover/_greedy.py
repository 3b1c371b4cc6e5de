"""Greedy placement on candidate viewpoints, and a certified bound on the best placement.

With a finite set of candidate viewpoints (:class:`uavcov.cover.Viewpoints`), coverage is a
weighted maximum-coverage problem, monotone and submodular. :class:`CoverageProblem` builds, in
Rust, which candidate sees which target (a bitset per candidate, ``uavcov._core.SeenMatrix``:
the answers of :meth:`uavcov.Visibility.seen` for each candidate alone), then

* :meth:`CoverageProblem.greedy`: lazy greedy (Minoux 1978; CELF, Leskovec et al. 2007), each
  pick the candidate of the largest marginal gain at least ``d_safe`` from the earlier picks;
  within ``1 - 1/e`` of the optimum without the separation (Nemhauser, Wolsey, Fisher 1978);
* :meth:`CoverageProblem.bound`: for ANY placement ``A`` of ``k`` UAVs (greedy's, or positions
  off the candidates such as CAO's final ones, whose true seen set is measured), the online
  bound of Leskovec et al. (2007): no ``k`` candidates see more than ``f(A)`` plus the ``k``
  largest marginal gains of the candidates given ``A``; nor more than the ceiling, the weight
  of the targets any candidate sees;
* :meth:`CoverageProblem.dual_bound`: the LP relaxation's bound, certified by a dual-feasible
  point evaluated on the full matrix (:mod:`uavcov.cover._dual_bound`); informative where
  the online bound reaches the ceiling (larger teams). :meth:`CoverageProblem.certified_bound`
  keeps the smaller of the two.

What the bound holds for, precisely: the largest weighted share of *these targets* that any
``k`` of *these candidates* see together (with or without the separation, which only removes
sets). A placement off the candidates may do better than this optimum; a finer lattice raises
the optimum it bounds (benches/README.md measures how the bound moves with the spacing).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _core
from .._validate import MAX_UAVS, as_count, as_n_threads, as_non_negative_float, as_points, as_positive_float, is_int, read_only
from ..engine import Sensor, Visibility, pack_sensors
from ..errors import InvalidInputError, InvalidTypeError
from ._dual_bound import DualCertificate, dual_bound
from ._viewpoints import Viewpoints, as_viewpoints


@dataclass(frozen=True)
class CoverageBound:
    """A placement's coverage and the certified bound on the best ``k`` candidates.

    Attributes
    ----------
    coverage : float
        The placement's weighted share of the targets seen (its own positions, exactly).
    bound : float
        No ``k`` of the candidates see more than this share together (see :attr:`holds_for`).
        Below ``coverage`` when the placement, off the candidates, beats all of them.
    ceiling : float
        The share of the targets at least one candidate sees.
    k : int
        Team size the bound is for.
    holds_for : str
        What the bound bounds, in words.
    """

    coverage: float
    bound: float
    ceiling: float
    k: int
    holds_for: str

    @property
    def gap(self) -> float:
        """``bound - coverage``: how much a placement on the candidates could still gain, at most."""
        return self.bound - self.coverage


@dataclass(frozen=True)
class GreedyResult:
    """Greedy's placement and its certificate.

    Attributes
    ----------
    positions : (n, 3) float64 ndarray
        The picks, metres, in the order picked (``n < k`` only when the separation leaves no
        candidate).
    poses : (n, 5) float64 ndarray or None
        Their ``(x, y, z, yaw, pitch)`` for camera candidates.
    picks : (n,) int64 ndarray
        The candidates' indices.
    gains : (n,) float64 ndarray
        The share of the targets each pick added.
    coverage : float
        The picks' weighted share of the targets seen.
    bound : float
        No ``k`` candidates see more than this share (the smallest online bound given each
        prefix of the picks: none, the first, ..., all; at most the ceiling).
    ceiling : float
        The share of the targets at least one candidate sees.
    k : int
        Picks asked for.
    holds_for : str
        What the bound bounds, in words.
    n_candidates : int
    matrix_bytes : int
        Memory of the seen-matrix.
    matrix_time_s, greedy_time_s : float
        Wall time of the seen-matrix and of the greedy with its bound, seconds.
    offline_time_s : float
        Wall time of the whole placement: the matrix and the greedy, and the lattice when
        ``uavcov.placement._starts.greedy_start`` made it, seconds.
    """

    positions: np.ndarray
    poses: np.ndarray | None
    picks: np.ndarray
    gains: np.ndarray
    coverage: float
    bound: float
    ceiling: float
    k: int
    holds_for: str
    n_candidates: int
    matrix_bytes: int
    matrix_time_s: float
    greedy_time_s: float
    offline_time_s: float


class CoverageProblem:
    """Which candidate viewpoint sees which target on ``visibility``'s surface and targets.

    Parameters
    ----------
    visibility : Visibility
        The surface, targets and range (the true surface for an oracle, S' for a start on S').
    candidates : Viewpoints or (C, 3) / (C, 5) array_like
        Candidate viewpoints (poses for camera sensors).
    sensor : Sensor, optional
        Every candidate's sensor; ``None``: omnidirectional up to ``visibility.d_max``. A camera
        needs poses.
    n_threads : int, optional
        Threads for the Rust side (``None``: rayon's default); results do not depend on it.

    Raises
    ------
    InvalidInputError
        Bad candidates (NaN, beyond 1e15 m, wrong shape).
    SurfaceTooLargeError
        The seen-matrix would exceed 1 GiB.
    """

    def __init__(self, visibility: Visibility, candidates: Any, sensor: Sensor | None = None, *, n_threads: int | None = None) -> None:
        if not isinstance(visibility, Visibility):
            raise InvalidTypeError(f"visibility must be a uavcov.Visibility, got {type(visibility).__name__}")
        if sensor is not None and not isinstance(sensor, Sensor):
            raise InvalidTypeError(f"sensor must be a uavcov.Sensor or None, got {type(sensor).__name__}")
        self._visibility = visibility
        self._viewpoints = as_viewpoints(candidates)
        self._sensor = sensor
        self._n_threads = as_n_threads(n_threads)
        packed = None
        points = self._viewpoints.positions
        if sensor is not None:
            poses = self._viewpoints.poses if self._viewpoints.poses is not None else points
            points, packed = pack_sensors([sensor] * self._viewpoints.n, poses)
        started = time.perf_counter()
        self._matrix = _core.SeenMatrix(visibility._core, np.ascontiguousarray(points), packed, self._n_threads)
        self.matrix_time_s = time.perf_counter() - started
        self._dense: np.ndarray | None = None
        """Wall time of the seen-matrix, seconds."""

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (self._visibility, self._viewpoints, self._sensor, self._n_threads or None))

    @property
    def viewpoints(self) -> Viewpoints:
        """The candidates."""
        return self._viewpoints

    @property
    def nbytes(self) -> int:
        """Memory of the seen-matrix's bits."""
        return int(self._matrix.nbytes)

    def ceiling(self) -> float:
        """The weighted share of the targets at least one candidate sees: what no team on the candidates exceeds."""
        return float(self._matrix.ceiling())

    def seen(self, c: int) -> np.ndarray:
        """``(T,)`` bool: the targets candidate ``c`` sees."""
        if not is_int(c):
            raise InvalidTypeError(f"c must be an int, got {type(c).__name__}")
        if not 0 <= int(c) < self._viewpoints.n:
            raise InvalidInputError(f"candidate {c} of {self._viewpoints.n}")
        return self._matrix.column(int(c))

    def dense(self) -> np.ndarray:
        """``(C, T)`` bool: the whole seen-matrix, one row per candidate (made once, then kept)."""
        if self._dense is None:
            rows = [self._matrix.column(c) for c in range(self._viewpoints.n)]
            self._dense = read_only(np.stack(rows) if rows else np.zeros((0, self._matrix.n_targets), dtype=bool))
        return self._dense

    def dual_bound(self, k: int, *, cell: float | None = 3.0) -> DualCertificate:
        """The LP relaxation's certified bound on the best ``k`` candidates, with or without separation.

        Parameters
        ----------
        k : int
            Team size.
        cell : float or None, optional
            The LP is solved on ``cell``-metre clusters of targets (faster, a little looser,
            still certified); ``None``: the full LP, one row per target.

        Returns
        -------
        DualCertificate
            ``bound`` (a share), the certificate ``u`` (a share per target), the LP's value.
        """
        k = as_count(k, "k", MAX_UAVS)
        if cell is not None:
            cell = as_positive_float(cell, "cell")
        targets = self._visibility.targets
        return dual_bound(self.dense(), targets.weights, k, targets.points, cell)

    def certified_bound(self, k: int, d_safe: float = 0.0) -> float:
        """The smaller of greedy's online bound and the LP dual bound for ``k`` candidates."""
        return min(self.greedy(k, d_safe).bound, self.dual_bound(k).bound)

    def _holds_for(self, k: int) -> str:
        t = self._matrix.n_targets
        return f"the best {k} of these candidates ({self._viewpoints.description}), on these {t} targets, with or without separation"

    def greedy(self, k: int, d_safe: float = 0.0) -> GreedyResult:
        """Lazy greedy of ``k`` candidates kept ``d_safe`` metres apart, and its bound.

        Picks the candidate of the largest marginal gain (the lowest index among equal gains),
        exactly as plain greedy does.
        """
        k = as_count(k, "k", MAX_UAVS)
        separation = as_non_negative_float(d_safe, "d_safe")
        started = time.perf_counter()
        picks, gains, coverage, bound = self._matrix.greedy(k, separation, self._n_threads)
        elapsed = time.perf_counter() - started
        poses = self._viewpoints.poses
        return GreedyResult(
            positions=read_only(self._viewpoints.positions[picks].copy()),
            poses=None if poses is None else read_only(poses[picks].copy()),
            picks=read_only(np.asarray(picks, dtype=np.int64)),
            gains=read_only(np.asarray(gains, dtype=np.float64)),
            coverage=float(coverage),
            bound=float(bound),
            ceiling=self.ceiling(),
            k=k,
            holds_for=self._holds_for(k),
            n_candidates=self._viewpoints.n,
            matrix_bytes=self.nbytes,
            matrix_time_s=self.matrix_time_s,
            greedy_time_s=elapsed,
            offline_time_s=self.matrix_time_s + elapsed,
        )

    def bound(self, positions: Any, *, sensors: Sequence[Sensor] | None = None, k: int | None = None) -> CoverageBound:
        """The certified bound for the placement ``positions`` (any positions: its true seen set is measured).

        Parameters
        ----------
        positions : (N, 3) or (N, 5) array_like
            The placement (poses with camera ``sensors``).
        sensors : sequence of Sensor, optional
            The placement's own sensors, one per UAV (as :meth:`uavcov.Visibility.seen`).
        k : int, optional
            Team size of the bound; default ``N``.
        """
        if sensors is None:
            as_points(positions, "positions")
        seen = self._visibility.seen(positions, sensors=sensors)
        n = int(np.asarray(positions).shape[0])
        k = n if k is None else as_count(k, "k", MAX_UAVS)
        coverage, bound = self._matrix.bound(np.ascontiguousarray(seen, dtype=bool), k, self._n_threads)
        return CoverageBound(coverage=float(coverage), bound=float(bound), ceiling=self.ceiling(), k=k, holds_for=self._holds_for(k))


def _rebuild(visibility: Visibility, viewpoints: Viewpoints, sensor: Sensor | None, n_threads: int | None) -> CoverageProblem:
    return CoverageProblem(visibility, viewpoints, sensor, n_threads=n_threads)


def greedy_placement(
    visibility: Visibility,
    candidates: Any,
    k: int,
    *,
    d_safe: float = 0.0,
    sensor: Sensor | None = None,
    n_threads: int | None = None,
) -> GreedyResult:
    """Greedy placement of ``k`` UAVs on ``candidates``, with its certified bound (see :class:`CoverageProblem`).

    Examples
    --------
    >>> import uavcov
    >>> from uavcov.cover import GreedySettings, greedy_placement, viewpoint_lattice
    >>> from uavcov.limits import Constraints
    >>> hills = uavcov.gaussian_hills(size=40.0, spacing=1.0, n_hills=3, rng=1)
    >>> limits = Constraints(h_min=2.0, h_max=10.0, z_max=60.0, d_safe=1.0)
    >>> lattice = viewpoint_lattice(hills, limits, GreedySettings(spacing=5.0))
    >>> result = greedy_placement(uavcov.Visibility(hills, 12.0), lattice, 3, d_safe=1.0)
    >>> result.coverage <= result.bound <= result.ceiling
    True
    """
    if not isinstance(visibility, Visibility):
        raise InvalidTypeError(f"visibility must be a uavcov.Visibility, got {type(visibility).__name__}")
    return CoverageProblem(visibility, candidates, sensor, n_threads=n_threads).greedy(k, d_safe)


def coverage_bound(
    visibility: Visibility,
    positions: Any,
    candidates: Any,
    *,
    sensors: Sequence[Sensor] | None = None,
    sensor: Sensor | None = None,
    k: int | None = None,
    n_threads: int | None = None,
) -> CoverageBound:
    """How far any placement of your own is from the best ``k`` of ``candidates``, with a certificate.

    The placement's coverage is measured exactly (off the candidates too); the bound is what no
    ``k`` of the candidates see together (:meth:`CoverageProblem.bound`). For several placements on
    one set of candidates, build one :class:`CoverageProblem` and call its ``bound``: the
    seen-matrix is computed once.

    Parameters
    ----------
    visibility : Visibility
        The surface, its targets and the sensing range.
    positions : (N, 3) or (N, 5) array_like
        The placement, metres (poses ``x, y, z, yaw, pitch`` with camera ``sensors``).
    candidates : Viewpoints or (C, 3) / (C, 5) array_like
        The candidate viewpoints the bound is over, e.g. :func:`viewpoint_lattice` over the
        flight band.
    sensors : sequence of Sensor, optional
        The placement's own sensors, one per UAV; ``None``: omnidirectional up to ``d_max``.
    sensor : Sensor, optional
        Every candidate's sensor (as :class:`CoverageProblem`).
    k : int, optional
        Team size the bound is for; default ``N``.
    n_threads : int, optional
        Rust threads; results do not depend on it.

    Returns
    -------
    CoverageBound
        ``coverage`` (the placement's), ``bound``, ``ceiling`` and ``gap = bound - coverage``.

    Examples
    --------
    Three UAVs placed by hand on 40 m hills, against the best 3 of a 5 m lattice over the band:

    >>> import numpy as np, uavcov
    >>> from uavcov.cover import GreedySettings, coverage_bound, viewpoint_lattice
    >>> hills = uavcov.gaussian_hills(size=40.0, spacing=1.0, n_hills=3, rng=1)
    >>> limits = uavcov.Constraints(h_min=2.0, h_max=10.0, z_max=60.0)
    >>> lattice = viewpoint_lattice(hills, limits, GreedySettings(spacing=5.0))
    >>> xy = np.array([[10.0, 10.0], [30.0, 10.0], [20.0, 30.0]])
    >>> mine = np.column_stack([xy, hills.ground_height(xy) + 6.0])  # 6 m above the ground
    >>> b = coverage_bound(uavcov.Visibility(hills, 12.0), mine, lattice)
    >>> bool(b.coverage <= b.bound <= b.ceiling <= 1.0), b.k
    (True, 3)
    """
    if sensors is None:
        as_points(positions, "positions")
    problem = CoverageProblem(visibility, candidates, sensor, n_threads=n_threads)
    return problem.bound(positions, sensors=sensors, k=k)
