"""The admissible UAV configurations of the paper (eq. 2), and how to reach one.

A configuration ``x`` of shape ``(N, 3)`` is admissible when every UAV

* lies inside the region's x-y bounds (closed),
* has at least ``h_min`` of clearance straight down to the real surface (and a surface below it
  at all: a UAV under a heightfield or over a nodata hole has none, and is refused),
* has at most ``h_max`` of that clearance, when ``h_max`` is set: the paper's maximum height of
  flight, measured, like the minimum, above the ground the UAV is over (the height its
  altimeter reads, and the one flight rules cap),
* flies at most at the absolute altitude ``z_max``,
* stays at least ``d_safe`` away from every other UAV,

and, when ``check_moves`` is set (scenes with buildings), the straight move from the current
position to the new one crosses no surface. The checks read the world only through what a UAV
team could sense or has been told: :class:`World` (``clearance``, ``segments_clear``,
``ground_height``, ``bounds``), which :class:`uavcov.engine.Terrain` provides.

That is the ``clearance="vertical"`` meaning, the paper's, made for height fields. Structures
(a bridge deck a UAV flies under, a tower it circles) take ``clearance="standoff"``: ``h_min``
and ``h_max`` then bound the least 3D distance from the UAV to any surface
(``Terrain.distance``), the UAV must have some surface straight below it (not under the ground
nor off its edge) and be inside no closed solid (``Terrain.inside``), and ``z_max`` stays an
absolute ceiling. :func:`closest_admissible` then pushes a UAV out along the line from its
nearest surface point (out of a solid, away from a surface closer than ``h_min``, back within
``h_max``) instead of lifting it above the highest surface.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, Protocol

import numpy as np

from .._validate import (
    MAX_ITERATIONS,
    MAX_UAVS,
    as_bounds,
    as_count,
    as_finite_float,
    as_float_array,
    as_non_negative_float,
    as_points,
    as_positive_float,
)
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError

# closest_admissible aims this far inside every bound, so the exact checks of feasible_mask
# (which use the true h_min and d_safe) never fail on round-off. Metres.
_MARGIN = 1e-6


class World(Protocol):
    """What the constraints need to know about the real surface (``Terrain`` provides it)."""

    @property
    def bounds(self) -> np.ndarray:
        """``(2, 3)``: ``[[xmin, ymin, zmin], [xmax, ymax, zmax]]`` of the surface."""
        ...

    def ground_height(self, xy: np.ndarray) -> np.ndarray:
        """``(n, 2) -> (n,)`` highest surface z above each point, NaN where none."""
        ...

    def clearance(self, points: np.ndarray) -> np.ndarray:
        """``(n, 3) -> (n,)`` distance straight down to the surface, inf where none."""
        ...

    def segments_clear(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """``(n, 3), (n, 3) -> (n,)`` bool: the closed segment crosses no surface."""
        ...


class StandoffWorld(World, Protocol):
    """What ``clearance="standoff"`` needs besides :class:`World` (``Terrain`` provides it)."""

    def distance(self, points: np.ndarray) -> np.ndarray:
        """``(n, 3) -> (n,)`` least 3D distance to the surface."""
        ...

    def inside(self, points: np.ndarray) -> np.ndarray:
        """``(n, 3) -> (n,)`` bool: inside a closed solid."""
        ...

    def closest_point(self, points: np.ndarray) -> np.ndarray:
        """``(n, 3) -> (n, 3)`` the closest surface point."""
        ...


_CLEARANCES = ("vertical", "standoff")


@dataclass(frozen=True)
class Constraints:
    """The constraint set of the paper's eq. 2. Defaults follow ``paper-setup.md``.

    One object holds every flight limit of a mission; :meth:`resolve` fills what depends on the
    surface (its x-y bounds, and whether moves are checked), and every check here resolves the
    constraints against the world it is given.

    Parameters
    ----------
    bounds : (xmin, ymin, xmax, ymax), optional
        Closed x-y region the UAVs must stay in, metres. A ``(2, k)`` array
        ``[[xmin, ymin, ...], [xmax, ymax, ...]]`` (such as ``Terrain.bounds``) is accepted.
        ``None``: the x-y bounds of the surface the constraints are applied to.
    h_min : float, default 2.0
        Least clearance straight down to the real surface, metres (>= 0).
    z_max : float, default 50.0
        Highest absolute altitude, metres, in the surface's frame. With the vertical clearance
        ``h_min > z_max`` is refused: height fields stand on z >= 0, so it would leave no room
        anywhere; a structure (standoff) may stand below z = 0, and is judged against its own
        lowest point when a team is placed (:meth:`check_team`).
    h_max : float or None, default None
        Most clearance straight down to the real surface, metres: the maximum height of flight
        above the ground below the UAV (``None``: no such ceiling, only ``z_max``). Must be at
        least ``h_min``. Above ground rather than absolute because eq. 2's constraints "depend
        on the surface" (the paper, section III), because it is what a UAV's altimeter senses
        and what flight rules cap, and because an absolute ceiling over hills binds over the
        peaks only and leaves the valleys free.
    d_safe : float, default 2.0
        Least distance between two UAVs, metres (>= 0).
    check_moves : bool or None, default False
        Also require the straight move from the current to the new position to cross no surface
        (scenes with buildings: two admissible positions on either side of a wall or a roof edge
        can be joined by a move through it, and in a mesh with ground under its buildings a
        point inside one passes the clearance test). ``None`` decides by the surface: on for
        general meshes, off for elevation grids, where a move between two admissible positions a few metres apart
        cannot cross the ground.
    clearance : {"vertical", "standoff"}, default "vertical"
        What ``h_min`` and ``h_max`` bound. ``"vertical"``: the distance straight down to the
        surface, as above (height fields; today's runs). ``"standoff"`` (structures): the least
        3D distance to any surface; the UAV must also have surface straight below it and be
        inside no closed solid, and ``z_max`` stays an absolute ceiling. Use ``check_moves``
        with it (``None`` turns it on for meshes): a move is then checked against the mesh, and
        a UAV that reached its position by a clear move from outside every solid needs no
        inside test.
    move_step : float or None, default None
        Metres. When set, every move is also checked between its ends, as a team flies it: the
        UAVs in step along their straight lines (each at the same fraction of its move), sampled
        every ``move_step`` metres of the longest move; at every sample each UAV keeps ``h_min``
        (by ``clearance``'s measure) and every pair ``d_safe``. The waypoints alone (``None``, the
        paper's eq. 2) admit a move that cuts past a roof's edge nearer than ``h_min``, or two UAVs
        whose straight paths cross (docs/realistic.md). A sampled check: between two samples a
        move can come nearer by up to ``move_step / 2``.

    Raises
    ------
    InvalidInputError
        Non-finite or out-of-range values, an unknown ``clearance``.
    InfeasibleError
        ``h_min > z_max`` or ``h_min > h_max``.
    """

    bounds: tuple[float, float, float, float] | None = None
    h_min: float = 2.0
    z_max: float = 50.0
    d_safe: float = 2.0
    check_moves: bool | None = False
    h_max: float | None = None
    clearance: str = "vertical"
    move_step: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.clearance, str):
            raise InvalidTypeError(f"clearance must be a string, got {type(self.clearance).__name__}")
        if self.clearance not in _CLEARANCES:
            raise InvalidInputError(f'clearance must be "vertical" or "standoff", got {self.clearance!r}')
        if self.bounds is not None:
            object.__setattr__(self, "bounds", as_bounds(self.bounds))
        object.__setattr__(self, "h_min", as_non_negative_float(self.h_min, "h_min"))
        object.__setattr__(self, "z_max", as_finite_float(self.z_max, "z_max"))
        object.__setattr__(self, "d_safe", as_non_negative_float(self.d_safe, "d_safe"))
        if self.check_moves is not None:
            if not isinstance(self.check_moves, (bool, np.bool_)):
                raise InvalidTypeError(f"check_moves must be a bool or None, got {type(self.check_moves).__name__}")
            object.__setattr__(self, "check_moves", bool(self.check_moves))
        if self.move_step is not None:
            object.__setattr__(self, "move_step", as_positive_float(self.move_step, "move_step"))
        if self.h_min > self.z_max and self.clearance == "vertical":
            # A height field stands on z >= 0; a structure may stand anywhere in its site's frame
            # (below a datum: z < 0), and check_team judges it against its own lowest point.
            raise InfeasibleError(f"h_min = {self.h_min} m above the surface cannot be met below z_max = {self.z_max} m")
        if self.h_max is not None:
            object.__setattr__(self, "h_max", as_finite_float(self.h_max, "h_max"))
            if self.h_min > self.h_max:
                raise InfeasibleError(f"h_min = {self.h_min} m above the surface is more than h_max = {self.h_max} m")

    @classmethod
    def for_world(cls, world: World, **kwargs: Any) -> Constraints:
        """Constraints whose x-y bounds are those of ``world`` (e.g. a ``Terrain``)."""
        _check_world(world)
        return cls(bounds=as_bounds(world.bounds), **kwargs).resolve(world)

    def resolve(self, world: World) -> Constraints:
        """These constraints with ``bounds`` and ``check_moves`` decided for ``world``.

        ``bounds=None`` becomes the x-y bounds of ``world``; ``check_moves=None`` becomes True
        unless ``world`` is an elevation grid (``world.grid`` set).
        """
        _check_world(world)
        if self.bounds is not None and self.check_moves is not None:
            return self
        bounds = as_bounds(world.bounds) if self.bounds is None else self.bounds
        check_moves = getattr(world, "grid", None) is None if self.check_moves is None else self.check_moves
        return replace(self, bounds=bounds, check_moves=check_moves)

    @property
    def flight_box(self) -> tuple[float, float, float, float]:
        """The x-y bounds; raises :class:`InvalidInputError` while they are unresolved."""
        if self.bounds is None:
            raise InvalidInputError("these constraints have no bounds yet: resolve them against a surface first")
        return self.bounds

    def check_team(self, n_uavs: int, world: World) -> None:
        """Raise :class:`InfeasibleError` if ``n_uavs`` UAVs surely cannot all be admissible.

        Three necessary conditions: some altitude satisfies ``h_min`` and ``z_max`` above the
        lowest point of ``world`` (with either clearance: a standoff needs surface below too),
        two UAVs can be ``d_safe`` apart inside the flight box, and the
        balls of radius ``d_safe / 2`` around the UAVs fit, by volume, in the flight box grown by
        that radius. Passing them does not prove a
        packing exists; :func:`closest_admissible` reports when it finds none.
        """
        n_uavs = as_count(n_uavs, "number of UAVs", MAX_UAVS)  # a team, and a count the volume check can multiply
        resolved = self.resolve(world)
        zmin, ztop = (float(z) for z in np.asarray(world.bounds, dtype=np.float64)[:, 2])
        floor = zmin + self.h_min
        if floor > self.z_max:
            raise InfeasibleError(
                f"the lowest surface point (z = {zmin:g} m) plus h_min = {self.h_min} m is above "
                f"z_max = {self.z_max} m: no altitude is admissible. z_max is an absolute altitude in the "
                f"surface's frame (the default 50 m suits the paper's hills at z >= 0): raise it, e.g. "
                f"Constraints(z_max={math.ceil(ztop) + 50}) for 50 m above the highest point (z_max = "
                f"{math.ceil(ztop) + 50} under [constraints] in a sweep file), or give heights above a local datum"
            )
        if n_uavs == 1 or self.d_safe == 0.0:
            return
        r = self.d_safe / 2.0
        xmin, ymin, xmax, ymax = resolved.flight_box
        # over any x-y point the admissible altitudes span at most z_max - floor, and at most
        # h_max - h_min when the ceiling above ground is set (a standoff's h_max bounds a shell
        # around a structure, which can be as tall as the structure: no such bound)
        height = self.z_max - floor
        if self.h_max is not None and self.clearance == "vertical":
            height = min(height, self.h_max - self.h_min)
        diagonal = math.hypot(xmax - xmin, ymax - ymin, height)
        if self.d_safe > diagonal:
            raise InfeasibleError(
                f"d_safe = {self.d_safe} m exceeds the flight box's diagonal ({diagonal:.4g} m): no two UAVs can be that far apart"
            )
        box = (xmax - xmin + 2 * r) * (ymax - ymin + 2 * r) * (height + 2 * r)
        need = n_uavs * 4.0 / 3.0 * math.pi * r * r * r  # inf, not OverflowError, for a huge d_safe
        if need > box:
            raise InfeasibleError(
                f"{n_uavs} UAVs kept d_safe = {self.d_safe} m apart cannot fit in the flight "
                f"volume (their safety balls need {need:.4g} m^3, the region offers {box:.4g} m^3)"
            )


def _check_world(world: Any, constraints: Constraints | None = None) -> None:
    names = ["bounds", "ground_height", "clearance", "segments_clear"]
    if constraints is not None and constraints.clearance == "standoff":
        names += ["distance", "inside", "closest_point"]
    for name in names:
        if not hasattr(world, name):
            raise InvalidTypeError(f"world must provide {name} (a Terrain does), got {type(world).__name__}")


def _as_candidates(candidates: Any, n_uavs: int) -> np.ndarray:
    array = as_float_array(candidates, "candidates")
    if array.ndim == 2 and array.shape == (n_uavs, 3):
        array = array[None]
    if array.ndim != 3 or array.shape[1:] != (n_uavs, 3):
        raise InvalidInputError(f"candidates must have shape (M, {n_uavs}, 3), got {array.shape}")
    return array


def _static_ok(constraints: Constraints, cand: np.ndarray) -> np.ndarray:
    """Bounds, altitude and pairwise distance for ``(M, N, 3)`` candidates: ``(M,)`` bool."""
    xmin, ymin, xmax, ymax = constraints.flight_box
    x, y, z = cand[..., 0], cand[..., 1], cand[..., 2]
    inside = (x >= xmin) & (x <= xmax) & (y >= ymin) & (y <= ymax) & (z <= constraints.z_max)
    ok: np.ndarray = np.asarray(inside.all(axis=1), dtype=bool)
    n_uavs = cand.shape[1]
    if n_uavs > 1 and constraints.d_safe > 0.0:
        i, j = _pairs(n_uavs)
        idx = np.flatnonzero(ok)
        inside_cand = cand[idx]
        diff = inside_cand[:, i] - inside_cand[:, j]
        far = (np.einsum("mpk,mpk->mp", diff, diff) >= constraints.d_safe**2).all(axis=1)
        ok[idx] = far
    return ok


@functools.lru_cache(maxsize=32)
def _pairs(n_uavs: int) -> tuple[np.ndarray, np.ndarray]:
    """Every pair ``i < j`` of ``n_uavs`` UAVs (read-only; an optimiser asks for them every iteration)."""
    i, j = np.triu_indices(n_uavs, 1)
    i.setflags(write=False)
    j.setflags(write=False)
    return i, j


def feasible_mask(constraints: Constraints, world: World, current: Any, candidates: Any, *, n_threads: int | None = None) -> np.ndarray:
    """Which candidate configurations are admissible.

    Parameters
    ----------
    constraints : Constraints
    world : World
        The real surface. A ``Terrain`` judges the whole batch in one Rust pass
        (``Terrain.admissible_check``); any other world is queried once for the clearance of the
        candidates that pass the bounds and separation, and once for their moves when
        ``check_moves`` is set, with the same answers.
    current : (N, 3) array_like
        Positions now, metres (the start of each move).
    candidates : (M, N, 3) array_like
        Candidate configurations, metres.
    n_threads : int, optional
        Passed to the world's queries (``Terrain.clearance(..., n_threads=)``); ``None`` leaves
        them their default. A sweep worker gives its own count, so that a few hundred small
        queries per mission do not each wake a pool of every core.

    Returns
    -------
    (M,) bool ndarray
    """
    if not isinstance(constraints, Constraints):
        raise InvalidTypeError(f"constraints must be a Constraints, got {type(constraints).__name__}")
    _check_world(world, constraints)
    constraints = constraints.resolve(world)
    cur = as_points(current, "current")
    cand = _as_candidates(candidates, cur.shape[0])
    n_uavs = cur.shape[0]
    fused = _fused_check(constraints, world, n_threads)
    if fused is not None:  # a Terrain: every check below in one Rust pass, with the same answers
        ok = np.asarray(fused(cur, cand), dtype=bool)
        return _moves_ok(constraints, world, cur, cand, ok, n_threads)
    threads: dict[str, Any] = {} if n_threads is None else {"n_threads": n_threads}
    # cheap checks first, so the surface is only queried for candidates still in the running
    ok = _static_ok(constraints, cand)
    idx = np.flatnonzero(ok)
    if idx.size and constraints.clearance == "standoff":
        ok[idx] = _standoff_ok(constraints, world, cand[idx], threads)
    elif idx.size:
        clear = np.asarray(world.clearance(np.ascontiguousarray(cand[idx].reshape(-1, 3)), **threads), dtype=np.float64)
        clear = clear.reshape(idx.size, n_uavs)
        good = np.isfinite(clear) & (clear >= constraints.h_min)
        if constraints.h_max is not None:
            good &= clear <= constraints.h_max
        ok[idx] = good.all(axis=1)
    if constraints.check_moves:
        idx = np.flatnonzero(ok)
        if idx.size:
            ends = cand[idx]
            moved = (ends != cur[None]).any(axis=2)  # a UAV that stays has nothing to cross
            if moved.any():
                starts = np.broadcast_to(cur[None], ends.shape)[moved]
                clear_moves = np.asarray(
                    world.segments_clear(np.ascontiguousarray(starts), np.ascontiguousarray(ends[moved]), **threads), dtype=bool
                )
                per_uav = np.ones(moved.shape, dtype=bool)
                per_uav[moved] = clear_moves
                ok[idx] = per_uav.all(axis=1)
    return _moves_ok(constraints, world, cur, cand, ok, n_threads)


# Samples of one move at most: a move_step this fine against moves this long is a typo (and memory).
_MAX_MOVE_SAMPLES = 10_000
# Sampled positions of one batch at most (candidates x samples x UAVs): checked before allocating.
_MAX_BATCH_SAMPLES = 10_000_000


def _moves_ok(constraints: Constraints, world: Any, cur: np.ndarray, cand: np.ndarray, ok: np.ndarray, n_threads: int | None) -> np.ndarray:
    """``ok`` with the candidates whose moves break ``h_min`` or ``d_safe`` between their ends
    turned off (``move_step``; the ends themselves are the configuration checks' own)."""
    idx = np.flatnonzero(ok)
    if constraints.move_step is None or not idx.size:
        return ok
    ends = cand[idx]
    longest = float(np.linalg.norm(ends - cur[None], axis=2).max())
    ratio = longest / constraints.move_step  # inf for a subnormal move_step: checked before ceil
    n_samples = math.ceil(ratio) - 1 if ratio <= _MAX_MOVE_SAMPLES + 1 else _MAX_MOVE_SAMPLES + 1  # strictly between the ends
    if n_samples <= 0:
        return ok
    if n_samples > _MAX_MOVE_SAMPLES:
        raise InvalidInputError(
            f"a {longest:.3g} m move sampled every move_step = {constraints.move_step} m is over {_MAX_MOVE_SAMPLES} samples"
        )
    n_uavs = cur.shape[0]
    if idx.size * n_samples * n_uavs > _MAX_BATCH_SAMPLES:
        raise InvalidInputError(
            f"checking {idx.size} moves of {n_uavs} UAVs every move_step = {constraints.move_step} m needs over "
            f"{_MAX_BATCH_SAMPLES:,} sampled positions: a coarser move_step or fewer candidates per call"
        )
    fractions = np.arange(1, n_samples + 1) / (n_samples + 1)
    samples = cur[None, None] + fractions[None, :, None, None] * (ends - cur[None])[:, None]  # (m, k, n, 3)
    flat = np.ascontiguousarray(samples.reshape(-1, 3))
    threads: dict[str, Any] = {} if n_threads is None else {"n_threads": n_threads}
    if constraints.clearance == "standoff":
        near = np.asarray(world.distance(flat, **threads), dtype=np.float64)
    else:
        near = np.asarray(world.clearance(flat, **threads), dtype=np.float64)
    good = (near >= constraints.h_min).reshape(samples.shape[:3]).all(axis=(1, 2))
    if constraints.d_safe > 0.0 and n_uavs > 1:
        i, j = np.triu_indices(n_uavs, 1)
        gaps = np.linalg.norm(samples[:, :, i] - samples[:, :, j], axis=3)
        good &= (gaps >= constraints.d_safe).all(axis=(1, 2))
    out = ok.copy()
    out[idx] = good
    return out


def _standoff_ok(constraints: Constraints, world: Any, cand: np.ndarray, threads: dict[str, Any]) -> np.ndarray:
    """The standoff rules for ``(M, N, 3)`` candidates, one query of each kind: ``(M,)`` bool."""
    flat = np.ascontiguousarray(cand.reshape(-1, 3))
    dist = np.asarray(world.distance(flat, **threads), dtype=np.float64)
    good = dist >= constraints.h_min
    if constraints.h_max is not None:
        good &= dist <= constraints.h_max
    good &= np.isfinite(np.asarray(world.clearance(flat, **threads), dtype=np.float64))
    good &= ~np.asarray(world.inside(flat, **threads), dtype=bool)
    return np.asarray(good.reshape(cand.shape[:2]).all(axis=1), dtype=bool)


def feasibility(constraints: Constraints, world: World, *, n_threads: int | None = None) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """The ``feasible(current, candidates)`` callable the optimisers take, bound to ``world`` (and ``n_threads``).

    ``constraints`` with ``bounds=None`` take ``world``'s x-y bounds; ``n_threads`` (1 to 1024,
    ``None``: every core) changes no answer. The callable maps ``current`` ``(N, 3)`` positions,
    metres, and ``candidates`` ``(M, N, 3)`` to the ``(M,)`` bool mask of the candidates that keep
    every limit (:func:`uavcov.optim.cao`'s ``feasible``).

    Examples
    --------
    >>> import numpy as np, uavcov
    >>> from uavcov.limits import Constraints, feasibility
    >>> flat = uavcov.Terrain.from_grid(np.zeros((11, 11)), spacing=10.0)  # 100 m x 100 m at z = 0
    >>> feasible = feasibility(Constraints(h_min=5.0, z_max=50.0, d_safe=2.0), flat)
    >>> current = np.array([[20.0, 20.0, 10.0], [80.0, 80.0, 10.0]])
    >>> candidates = np.array([current + [0, 0, 5], current - [0, 0, 6], [[20, 20, 10], [21, 20, 10]]])
    >>> feasible(current, candidates).tolist()  # fine; too low (4 m); two UAVs 1 m apart
    [True, False, False]
    """
    if not isinstance(constraints, Constraints):
        raise InvalidTypeError(f"constraints must be a Constraints, got {type(constraints).__name__}")
    _check_world(world, constraints)
    constraints = constraints.resolve(world)
    fused = _fused_check(constraints, world, n_threads)
    if fused is not None and constraints.move_step is None:  # the limits checked once, not on each of a mission's hundreds of calls
        return fused
    if fused is not None:
        checked = fused

        def feasible_moves(current: np.ndarray, candidates: np.ndarray) -> np.ndarray:
            cur = as_points(current, "current")
            cand = _as_candidates(candidates, cur.shape[0])
            return _moves_ok(constraints, world, cur, cand, np.asarray(checked(cur, cand), dtype=bool), n_threads)

        return feasible_moves

    def feasible(current: np.ndarray, candidates: np.ndarray) -> np.ndarray:
        return feasible_mask(constraints, world, current, candidates, n_threads=n_threads)

    return feasible


def _fused_check(constraints: Constraints, world: World, n_threads: int | None) -> Callable[[Any, Any], np.ndarray] | None:
    """``world``'s one-pass check of ``constraints`` (resolved), when it has one (a Terrain)."""
    bind = getattr(world, "admissible_check", None)
    if bind is None:
        return None
    check: Callable[[Any, Any], np.ndarray] = bind(
        bounds=constraints.flight_box,
        h_min=constraints.h_min,
        h_max=constraints.h_max,
        z_max=constraints.z_max,
        d_safe=constraints.d_safe,
        check_moves=bool(constraints.check_moves),
        n_threads=n_threads,
        **({} if constraints.clearance == "vertical" else {"clearance": constraints.clearance}),
    )
    return check


def trajectory_feasible(constraints: Constraints, world: World, trajectory: Any) -> np.ndarray:
    """``(K + 1,)`` bool: configuration ``k`` is admissible, and so is the move into it.

    ``trajectory`` is ``(K + 1, N, 3)``; entry 0 is judged as a configuration only.
    """
    traj = as_float_array(trajectory, "trajectory")
    if traj.ndim != 3 or traj.shape[2] != 3 or traj.shape[0] == 0 or traj.shape[1] == 0:
        raise InvalidInputError(f"trajectory must have shape (K + 1, N, 3), got {traj.shape}")
    out = np.empty(traj.shape[0], dtype=bool)
    out[0] = feasible_mask(constraints, world, traj[0], traj[:1])[0]
    for k in range(1, traj.shape[0]):
        out[k] = feasible_mask(constraints, world, traj[k - 1], traj[k : k + 1])[0]
    return out


def _separation_direction(i: int, j: int) -> np.ndarray:
    """A fixed horizontal unit vector for two UAVs at the same point (deterministic)."""
    angle = 2.399963229728653 * (i + 1) * (j + 2)  # golden angle: pairs get spread directions
    return np.array([math.cos(angle), math.sin(angle), 0.0])


def _lift(constraints: Constraints, world: World, pos: np.ndarray, climb: float) -> None:
    """One vertical projection of every UAV in place: to ``ground + h_min``, under the ceilings."""
    ground = np.asarray(world.ground_height(np.ascontiguousarray(pos[:, :2])), dtype=np.float64)
    if np.isnan(ground).any():
        bad = int(np.flatnonzero(np.isnan(ground))[0])
        raise InfeasibleError(f"UAV {bad} at x-y ({pos[bad, 0]:g}, {pos[bad, 1]:g}) stands over no surface")
    floor = ground + constraints.h_min
    # Lifted with a margin, and judged with it: a UAV exactly at ground + h_min can measure a
    # clearance a rounding below h_min and be refused by feasible_mask.
    inset = _MARGIN if constraints.h_max is None else min(_MARGIN, 0.5 * (constraints.h_max - constraints.h_min))
    low = pos[:, 2] < floor + inset
    pos[low, 2] = floor[low] + max(climb, inset)
    if constraints.h_max is not None:
        # too high above the ground, or lifted by a climb through the ceiling: just under it
        ceiling = ground + constraints.h_max - inset
        high = pos[:, 2] > ceiling
        pos[high, 2] = ceiling[high]
    if (pos[:, 2] > constraints.z_max).any():
        if (floor > constraints.z_max).any():
            bad = int(np.flatnonzero(floor > constraints.z_max)[0])
            raise InfeasibleError(f"UAV {bad}: ground at {ground[bad]:.3f} m plus h_min exceeds z_max = {constraints.z_max} m")
        pos[:, 2] = np.minimum(pos[:, 2], constraints.z_max)


def _push_out(constraints: Constraints, world: Any, pos: np.ndarray, climb: float) -> None:
    """One standoff projection of every UAV in place, along the line from its nearest surface point.

    A UAV inside a solid or under the ground goes out through its nearest surface point (the
    point is then between the UAV and the open air) to ``h_min`` beyond it; a UAV closer than
    ``h_min`` goes straight away from its nearest point to ``h_min``; one beyond ``h_max``
    comes back towards it to just inside ``h_max``; then under ``z_max``. A UAV exactly on the
    surface, with no direction to leave along, goes up.
    """
    inset = _MARGIN if constraints.h_max is None else min(_MARGIN, 0.5 * (constraints.h_max - constraints.h_min))
    flat = np.ascontiguousarray(pos)
    nearest = np.asarray(world.closest_point(flat), dtype=np.float64)
    away = pos - nearest
    dist = np.sqrt(np.einsum("nk,nk->n", away, away))
    trapped = np.asarray(world.inside(flat), dtype=bool) | ~np.isfinite(np.asarray(world.clearance(flat), dtype=np.float64))
    unit = np.zeros_like(pos)
    unit[:, 2] = 1.0
    has_dir = dist > 0.0
    unit[has_dir] = away[has_dir] / dist[has_dir, None]
    unit[trapped & has_dir] *= -1.0  # out through the nearest surface, not deeper in
    low = trapped | (dist < constraints.h_min + inset)
    pos[low] = nearest[low] + unit[low] * (constraints.h_min + max(climb, inset))
    # Pushed from its nearest surface, a UAV can land under the ground (out of a solid standing
    # on it, through its base), within h_min of another surface (wedged between an arch and a
    # deck, among a pylon's braces, in a slot between two walls) or still inside a solid (the
    # nearest face was one of two overlapping solids', inside the other), and the next sweep
    # pushes it back: such a UAV goes up instead, over the highest surface within its standoff
    # around it (the centre and a ring of 8 points h_min out).
    moved = np.flatnonzero(low)
    if moved.size:
        here = np.ascontiguousarray(pos[moved])
        clear = np.asarray(world.clearance(here), dtype=np.float64)
        near = np.asarray(world.distance(here), dtype=np.float64)
        still_inside = np.asarray(world.inside(here), dtype=bool)
        lost = moved[~np.isfinite(clear) | (near < constraints.h_min) | still_inside]
        if lost.size:
            reach = constraints.h_min + max(climb, inset)
            angles = np.arange(9) * (np.pi / 4.0)
            ring = np.column_stack([np.cos(angles), np.sin(angles)]) * reach
            ring[8] = 0.0
            xy = (pos[lost, None, :2] + ring[None]).reshape(-1, 2)
            top = np.asarray(world.ground_height(np.ascontiguousarray(xy)), dtype=np.float64).reshape(lost.size, 9)
            highest = np.where(np.isfinite(top), top, -np.inf).max(axis=1)
            pos[lost, 2] = np.where(np.isfinite(highest), highest, pos[lost, 2]) + reach
    if constraints.h_max is not None:
        high = ~low & (dist > constraints.h_max - inset)
        pos[high] = nearest[high] + unit[high] * (constraints.h_max - inset)
    np.minimum(pos[:, 2], constraints.z_max, out=pos[:, 2])


def _off_the_edge(world: World, pos: np.ndarray, box: tuple[float, float, float, float]) -> None:
    """Move a UAV clamped onto the flight box's edge ``_MARGIN`` inside it when the ray down from it misses.

    The box is the surface's own x-y extent by default, so a UAV clamped onto it can stand on
    the mesh's boundary edge, where the ray straight down may miss by round-off (a ground sheet
    of two triangles did): no projection moves it then, and the start was refused.
    """
    xmin, ymin, xmax, ymax = box
    edge = np.flatnonzero((pos[:, 0] == xmin) | (pos[:, 0] == xmax) | (pos[:, 1] == ymin) | (pos[:, 1] == ymax))
    if not edge.size:
        return
    clear = np.asarray(world.clearance(np.ascontiguousarray(pos[edge])), dtype=np.float64)
    ground = np.asarray(world.ground_height(np.ascontiguousarray(pos[edge, :2])), dtype=np.float64)
    lost = edge[~np.isfinite(clear) & ~(pos[edge, 2] < ground)]  # not a UAV under the ground: the projections lift that one
    inset = np.minimum(_MARGIN, 0.5 * np.array([xmax - xmin, ymax - ymin]))  # a box thinner than two margins: its middle
    pos[lost, :2] = np.clip(pos[lost, :2], np.array([xmin, ymin]) + inset, np.array([xmax, ymax]) - inset)


def closest_admissible(constraints: Constraints, world: World, x: Any, *, climb: float = 0.0, max_sweeps: int = 1000) -> np.ndarray:
    """Move a start configuration to nearby admissible positions (deterministic).

    Each sweep projects every UAV onto its own constraints exactly (clamp into the x-y bounds;
    lift to ``ground + h_min`` when under the terrain, inside a building or too low; lower to
    ``ground + h_max`` and to ``z_max``), then pushes every pair closer than ``d_safe`` apart symmetrically along the line
    joining them (a fixed horizontal direction when they coincide). Sweeps repeat until nothing
    moves. A UAV already admissible and far from the others is left exactly where it is.

    With ``clearance="standoff"`` the projection instead moves a UAV along the line from its
    nearest surface point (``Terrain.closest_point``): out of a solid or from under the ground
    through that point to ``h_min`` beyond it, away from a surface closer than ``h_min``, back
    within ``h_max``; a UAV under a bridge deck with its standoff is left where it is.

    Parameters
    ----------
    constraints : Constraints
    world : World
        The real surface (a ``Terrain``).
    x : (N, 3) array_like
        Start positions, metres.
    climb : float, default 0.0
        Metres above ``ground + h_min`` at which a UAV that had to be lifted is put. A team left
        exactly on the ``h_min`` boundary has few feasible perturbations (each lifted UAV halves
        them), which can freeze an optimiser; a climb of about a metre avoids it.
    max_sweeps : int, default 1000

    Returns
    -------
    (N, 3) float64 ndarray
        Admissible positions (``feasible_mask`` accepts them).

    Raises
    ------
    InfeasibleError
        The team cannot fit (:meth:`Constraints.check_team`), a UAV stands over no surface, or
        no admissible configuration was reached.

    Examples
    --------
    >>> import numpy as np, uavcov
    >>> from uavcov.limits import Constraints, closest_admissible
    >>> flat = uavcov.Terrain.from_grid(np.zeros((11, 11)), spacing=10.0)
    >>> limits = Constraints(h_min=5.0, z_max=50.0, d_safe=2.0)
    >>> start = [[20.0, 20.0, 1.0], [150.0, 50.0, 60.0]]  # too low; off the map and too high
    >>> closest_admissible(limits, flat, start, climb=1.0).round(3).tolist()  # lifted to h_min + climb; moved in, lowered
    [[20.0, 20.0, 6.0], [100.0, 50.0, 50.0]]
    """
    if not isinstance(constraints, Constraints):
        raise InvalidTypeError(f"constraints must be a Constraints, got {type(constraints).__name__}")
    _check_world(world, constraints)
    constraints = constraints.resolve(world)
    pos = as_points(x, "x").copy()
    climb = as_non_negative_float(climb, "climb")
    max_sweeps = as_count(max_sweeps, "max_sweeps", MAX_ITERATIONS)  # 10**400 sweeps of an infeasible team never end
    n_uavs = pos.shape[0]
    constraints.check_team(n_uavs, world)
    xmin, ymin, xmax, ymax = constraints.flight_box
    target = constraints.d_safe + _MARGIN if constraints.d_safe > 0.0 else 0.0
    pairs = np.triu_indices(n_uavs, 1)

    for _ in range(max_sweeps):
        before = pos.copy()
        pos[:, 0] = np.clip(pos[:, 0], xmin, xmax)
        pos[:, 1] = np.clip(pos[:, 1], ymin, ymax)
        _off_the_edge(world, pos, (xmin, ymin, xmax, ymax))
        if constraints.clearance == "standoff":
            _push_out(constraints, world, pos, climb)
        else:
            _lift(constraints, world, pos, climb)
        if target > 0.0 and n_uavs > 1:
            i, j = pairs
            diff = pos[i] - pos[j]
            dist = np.sqrt(np.einsum("pk,pk->p", diff, diff))
            close = np.flatnonzero(dist < constraints.d_safe)
            if close.size:
                push = np.zeros_like(pos)
                for p in close:  # only the offending pairs; usually none or a few
                    a, b = int(i[p]), int(j[p])
                    unit = diff[p] / dist[p] if dist[p] > 0.0 else _separation_direction(a, b)
                    step = 0.5 * (target - dist[p]) * unit
                    push[a] += step
                    push[b] -= step
                pos += push
        if np.array_equal(pos, before):
            break
    if not feasible_mask(constraints, world, pos, pos[None])[0]:
        raise InfeasibleError(
            f"no admissible configuration found near the start after {max_sweeps} sweeps "
            "(the region may be too crowded for d_safe, or a UAV is over a hole in the surface)"
        )
    return pos
