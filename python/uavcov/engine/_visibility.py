"""Who sees what: the coverage objective (paper eq. 1, discretised on targets).

A target ``q`` is seen by a UAV at ``p`` when ``|p - q| <= d_max`` (3D) and the segment from
``p`` towards ``q``, stopped 0.1 % of its length short of ``q``, crosses no triangle. Coverage is
the weighted share of targets seen by at least one UAV.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _core
from .._validate import as_n_threads, as_points, as_positive_float, not_a_terrain
from ..errors import InvalidTypeError
from ._sensors import Sensor, pack_sensors
from ._surface import Terrain
from ._targets import Targets


@dataclass(frozen=True, eq=False)
class UavCounts:
    """What each UAV contributes.

    Attributes
    ----------
    seen : (N,) int64
        Number of targets each UAV sees.
    exclusive : (N,) int64
        Number of targets only that UAV sees: its marginal contribution.
    seen_share, exclusive_share : (N,) float64
        The same as weighted shares of all targets, in [0, 1].
    coverage : float
        The weighted share of targets seen by at least one UAV: the value
        :meth:`Visibility.coverage` returns for the same UAVs, to the last bit.
    """

    seen: np.ndarray
    exclusive: np.ndarray
    seen_share: np.ndarray
    exclusive_share: np.ndarray
    coverage: float


class Visibility:
    """The coverage objective for one terrain, one target set and one sensing range.

    Build it once and call it many times: targets and their spatial index live in Rust.

    Parameters
    ----------
    terrain : Terrain
        The surface that both holds the targets and blocks the lines of sight.
    d_max : float
        Sensing range, metres (> 0, finite). From 4e15 m up it is an unlimited range: every two
        points a surface may hold (coordinates at most 1e15 m) are closer than that.
    targets : Targets, optional
        Defaults to ``terrain.default_targets()``.
    n_threads : int, optional
        Threads for each evaluation, 1 to 1024; ``None`` (the default) is rayon's default:
        ``RAYON_NUM_THREADS`` if set, else every core. Results do not depend on it.
    method : {"auto", "grid", "mesh"}, default "auto"
        How lines of sight are tested. The *grid method* ("grid") walks the elevation grid of a
        terrain built with :meth:`Terrain.from_grid`; the *mesh method* ("mesh") uses the triangle
        mesh and its BVH; "auto" takes the grid method whenever the terrain is a grid. Both give
        the same answer for every target; the grid method is faster and needs no triangle list (a
        grid of many millions of nodes fits), and with the default targets of a grid terrain the
        targets are generated in Rust, not stored.

    Examples
    --------
    >>> import numpy as np, uavcov
    >>> t = uavcov.Terrain.from_grid(np.zeros((21, 21)), spacing=1.0)
    >>> vis = uavcov.Visibility(t, d_max=50.0)
    >>> vis.coverage([[10.0, 10.0, 5.0]])
    1.0
    >>> vis
    Visibility(d_max=50 m, 441 targets, grid path, on Terrain(grid 21x21, 441 vertices, 800 faces, area 400.0 m^2))
    """

    __slots__ = ("_core", "_d_max", "_method", "_n_threads", "_targets", "_terrain")

    def __init__(
        self,
        terrain: Terrain,
        d_max: float,
        targets: Targets | None = None,
        *,
        n_threads: int | None = None,
        method: str = "auto",
    ) -> None:
        if not isinstance(terrain, Terrain):
            raise not_a_terrain(terrain, "terrain")
        if targets is not None and not isinstance(targets, Targets):
            raise InvalidTypeError(f"targets must be a uavcov.Targets, got {type(targets).__name__}")
        if not isinstance(method, str):
            raise InvalidTypeError(f"method must be a string, got {type(method).__name__}")
        if targets is None and terrain.grid is None:
            targets = terrain.default_targets()
        self._terrain = terrain
        self._targets = targets  # None: the grid's vertices, generated in Rust, made on request
        self._d_max = as_positive_float(d_max, "d_max")
        self._n_threads = as_n_threads(n_threads)
        self._method = method
        points, weights = (None, None) if targets is None else (targets.points, targets.weights)
        normals = None if targets is None else targets.normals
        self._core = _core.Visibility(terrain.core, points, weights, self._d_max, method, normals)

    def __reduce__(self) -> tuple[Any, ...]:
        n_threads = self._n_threads or None
        return (_rebuild, (self._terrain, self._d_max, self._targets, n_threads, self._method))

    def __repr__(self) -> str:
        return f"Visibility(d_max={self._d_max:g} m, {self._core.n_targets} targets, {self._core.path} path, on {self._terrain!r})"

    @property
    def terrain(self) -> Terrain:
        """The terrain."""
        return self._terrain

    @property
    def targets(self) -> Targets:
        """The targets (for a grid terrain's default targets, built on first access)."""
        if self._targets is None:
            self._targets = self._terrain.default_targets()
        return self._targets

    @property
    def d_max(self) -> float:
        """The sensing range, metres."""
        return self._d_max

    def _uavs(self, uavs: Any, sensors: Sequence[Sensor] | None) -> tuple[np.ndarray, np.ndarray | None]:
        if sensors is None:
            return as_points(uavs, "uavs"), None
        return pack_sensors(sensors, uavs)

    def coverage(self, uavs: Any, *, sensors: Sequence[Sensor] | None = None) -> float:
        """Weighted share of targets seen by at least one UAV.

        Parameters
        ----------
        uavs : (N, 3) or (N, 5) array_like of float
            UAV positions, metres; with ``sensors`` that hold a camera, poses ``(x, y, z, yaw,
            pitch)`` (degrees, see :mod:`uavcov.engine`).
        sensors : sequence of Sensor, optional
            One per UAV. ``None``: every UAV omnidirectional up to :attr:`d_max` (the paper's).

        Returns
        -------
        float
            In [0, 1].
        """
        points, packed = self._uavs(uavs, sensors)
        return float(self._core.coverage(points, self._n_threads, packed))

    def seen(self, uavs: Any, *, sensors: Sequence[Sensor] | None = None) -> np.ndarray:
        """``(T,)`` bool: whether at least one UAV sees each target (arguments as :meth:`coverage`)."""
        points, packed = self._uavs(uavs, sensors)
        return self._core.seen(points, self._n_threads, packed)

    def quality(self, uavs: Any, *, sensors: Sequence[Sensor] | None = None) -> np.ndarray:
        """``(T,)`` float in [0, 1]: each target's best view quality over the UAVs that see it, 0
        where none does (:attr:`Sensor.good_gsd_m` rates resolution, the targets' normals the
        incidence; without ``sensors`` every seen target has quality 1). Arguments as
        :meth:`coverage`."""
        points, packed = self._uavs(uavs, sensors)
        return self._core.quality(points, self._n_threads, packed)

    def quality_coverage(self, uavs: Any, *, sensors: Sequence[Sensor] | None = None) -> float:
        """Quality-weighted coverage: the weighted mean of :meth:`quality` over the targets, in
        [0, 1] (:meth:`coverage` when every view has quality 1)."""
        points, packed = self._uavs(uavs, sensors)
        return float(self._core.quality_coverage(points, self._n_threads, packed))

    def tracker(self, margin: float | None = None) -> CoverageTracker:
        """A :class:`CoverageTracker` of this objective: :meth:`coverage` of one team measured
        again and again as it moves, each measurement reusing what the last ones proved.

        Parameters
        ----------
        margin : float or None, default None
            Metres each UAV may move (height change plus the terrain's steepest slope times the
            horizontal move) before its certificates are made anew. ``None``: each UAV's own,
            2.5 times its recent steps, within 1-4 m and at most 0.3 of its height above the
            ground. It changes the work only, never an answer.
        """
        return CoverageTracker(self, margin)

    def per_uav(self, uavs: Any, *, sensors: Sequence[Sensor] | None = None) -> UavCounts:
        """How many targets each UAV sees and how many only it sees, and the team's coverage, in
        one pass (see :class:`UavCounts`; arguments as :meth:`coverage`)."""
        points, packed = self._uavs(uavs, sensors)
        seen, exclusive, seen_w, exclusive_w, total, coverage = self._core.per_uav(points, self._n_threads, packed)
        return UavCounts(
            seen.astype(np.int64),
            exclusive.astype(np.int64),
            seen_w / total,
            exclusive_w / total,
            float(coverage),
        )


class CoverageTracker:
    """:meth:`Visibility.coverage` and :meth:`Visibility.seen` of one team, measured again and
    again as it moves (an optimiser's loop): the same answers to the last bit, with most sight
    lines settled by what earlier measurements proved.

    For each target it keeps a certificate: a UAV that sees it with room to spare (the line from
    the target to the UAV's *anchor* lowered by ``margin`` is clear), or UAVs that cannot see it
    with room to spare (the line to the anchor raised by ``margin`` is blocked). While a UAV has
    moved less than ``margin`` from its anchor (height change plus the terrain's steepest slope
    times the horizontal move), its certificates hold; beyond it the anchor moves to the UAV.
    With ``margin=None`` each anchor takes its own, from its UAV's recent steps and height.
    Only targets without a certificate that holds are tested. Certificates need the grid
    method on a terrain without nodata and the objective's one range; elsewhere a tracker
    measures like its :class:`Visibility`. Build it with :meth:`Visibility.tracker`; it is one
    team's (not thread-safe, not picklable); a different team size starts afresh.

    Examples
    --------
    >>> import numpy as np, uavcov
    >>> t = uavcov.Terrain.from_grid(np.add.outer(np.arange(41.0), np.arange(41.0)) % 7, spacing=1.0)
    >>> vis = uavcov.Visibility(t, d_max=20.0)
    >>> tracker = vis.tracker()
    >>> team = np.array([[10.0, 10.0, 9.0], [30.0, 25.0, 8.0]])
    >>> all(tracker.coverage(team + 0.01 * k) == vis.coverage(team + 0.01 * k) for k in range(20))
    True
    >>> tracker.settled > 0  # targets the last measurement took from a certificate
    True
    """

    __slots__ = ("_core", "_visibility")

    def __init__(self, visibility: Visibility, margin: float | None = None) -> None:
        if not isinstance(visibility, Visibility):
            raise InvalidTypeError(f"visibility must be a uavcov.Visibility, got {type(visibility).__name__}")
        self._visibility = visibility
        fixed = None if margin is None else as_positive_float(margin, "margin")
        self._core = _core.CoverageTracker(visibility._core, fixed)

    def __reduce__(self) -> Any:
        raise TypeError("a CoverageTracker belongs to one team's run and is not pickled; make one with Visibility.tracker()")

    @property
    def visibility(self) -> Visibility:
        """The objective it measures."""
        return self._visibility

    @property
    def margin(self) -> float | None:
        """How far (metres) a UAV moves before its certificates are made anew (``None``: each
        anchor's own, see :meth:`Visibility.tracker`)."""
        margin = self._core.margin
        return None if margin is None else float(margin)

    @property
    def certifies(self) -> bool:
        """Whether certificates are in use (grid method, no nodata)."""
        return bool(self._core.certifies)

    @property
    def settled(self) -> int:
        """Targets the last measurement found seen from a certificate, without a sight line."""
        return int(self._core.settled)

    def coverage(self, uavs: Any) -> float:
        """:meth:`Visibility.coverage` of the team at ``uavs`` ((N, 3) metres), to the last bit."""
        return float(self._core.coverage(as_points(uavs, "uavs"), self._visibility._n_threads))

    def seen(self, uavs: Any) -> np.ndarray:
        """:meth:`Visibility.seen` of the team at ``uavs`` ((N, 3) metres): ``(T,)`` bool."""
        return self._core.seen(as_points(uavs, "uavs"), self._visibility._n_threads)


def _rebuild(terrain: Terrain, d_max: float, targets: Targets | None, n_threads: int | None, method: str = "auto") -> Visibility:
    return Visibility(terrain, d_max, targets, n_threads=n_threads, method=method)


def coverage(
    terrain: Terrain,
    uavs: Any,
    d_max: float,
    targets: Targets | None = None,
    *,
    n_threads: int | None = None,
    method: str = "auto",
) -> float:
    """Coverage of one configuration: a one-off :meth:`Visibility.coverage`.

    Prefer a :class:`Visibility` object when evaluating many configurations; the arguments are
    those of :class:`Visibility` (``n_threads=None`` is rayon's default: ``RAYON_NUM_THREADS`` if
    set, else every core), and ``uavs`` those of :meth:`Visibility.coverage`.

    Examples
    --------
    >>> import numpy as np, uavcov
    >>> flat = uavcov.Terrain.from_grid(np.zeros((11, 11)), spacing=1.0)
    >>> round(uavcov.engine.coverage(flat, [[5.0, 5.0, 3.0]], d_max=4.0), 2)  # nodes within 4 m of the UAV
    0.21
    """
    return Visibility(terrain, d_max, targets, n_threads=n_threads, method=method).coverage(uavs)
