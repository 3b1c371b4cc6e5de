"""Escaping CAO's local optima by relocating the UAV that contributes least.

CAO (:func:`uavcov.optim.cao`) climbs the coverage it measures and settles on a local optimum:
after a while no configuration it measures beats the best one. ``escape_cao`` runs CAO and,
each time it stalls, flies one UAV elsewhere, then resumes CAO. It uses only what the team has
measured, as CAO does: the team's coverage at every configuration it visited, each UAV's
exclusive share there (the targets only that UAV sees: what the team loses without it,
``Visibility.per_uav(...).exclusive_share``), and the flight-limit checks of ``feasible``. It
never sees the surface.

The algorithm
-------------
1. Run CAO (the same iterations, draws and surrogate as :func:`cao`) from the current
   configuration. It *stalls* when ``patience`` measurements in a row have not beaten the best
   coverage measured so far (measured as the optimiser sees it, noise included).
2. On a stall, plan a relocation from the configuration reached ``c`` and its exclusive shares
   ``m``. The UAVs with the smallest share are tried first (``movers`` of them). For UAV ``i``
   the candidate destinations are the positions ``p`` some UAV ``j`` occupied at a measured
   configuration ``h``; the gain predicted there is the exclusive share ``m[h, j]`` measured
   then. That share was measured with the nearest teammate of ``j`` at a distance ``r_then``;
   it still holds as a prediction only if the team without ``i`` is now no closer to ``p``
   (``r_now >= r_then``): a teammate that came closer could now see part of what was ``j``'s
   alone. Eligible destinations predict more than ``i`` gives now (``m[h, j] > m_i +
   min_gain``), lie at least ``hop`` away from ``i``, and are tried best prediction first
   (``destinations`` of them, each at least ``hop`` from the ones tried before).
3. Fly there. The team measures as it flies (so the flight is recorded, and counted in the
   iterations, like any other move): UAV ``i`` goes in legs of at most ``hop`` metres
   horizontally towards ``p``, its height interpolated between the two ends and, where that is
   not admissible, the nearest admissible height within ``climb_search`` metres above or below
   (in steps of ``climb_step``), every leg a move checked by ``feasible`` (flight band, ceiling,
   separation, and the ground crossing where the mission checks moves). A destination whose
   flight cannot be completed, or that needs more legs than the iterations left, is not
   flown; the next one is tried. When none can be flown, CAO goes on and the stall count
   starts again.
4. Resume CAO from where the UAV landed: a fresh surrogate (the old window's measurements
   describe another neighbourhood) with the step size schedule continuing where it was
   (``alpha_k`` of the mission's iteration ``k``), or restarted at ``alpha_0`` with
   ``restart_step``.

The best configuration is the best one measured over the whole run, flights included, so an
escape that does not pay off loses nothing but the distance and the iterations it cost. Every
configuration visited passed ``feasible`` from the one before. The trace's ``relocations``
lists every flight (UAV, first and last iteration); its distance is the UAV's path between
them (:attr:`uavcov.MissionResult.distance_flown` counts every move).

The step sizes of a flight's legs are recorded as 0 (they are not CAO's perturbations);
``n_checked`` and ``n_feasible`` of the leg count the configurations its planning checked.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .._validate import as_bool, as_non_negative_float, as_positive_float, as_positive_int, read_only
from ..errors import InvalidInputError, InvalidTypeError
from ._cao import _cao_run
from ._checks import _as_team_and_marginals, _check_common, _check_start, _Feasibility
from ._protocol import FeasibleFn
from ._settings import CAOSettings
from ._trace import OptimizerTrace, _finish


@dataclass(frozen=True)
class EscapeSettings:
    """Constants of ``escape_cao`` (CAO's own are the mission's :class:`CAOSettings`).

    Parameters
    ----------
    patience : int, default 40
        Measurements in a row without a new best coverage after which CAO has stalled.
    hop : float, default 5.0
        Longest horizontal leg of a relocation flight, metres: the team measures once per leg.
    climb_search : float, default 8.0
        How far above or below the straight line between the flight's ends a leg may look for
        an admissible height, metres.
    climb_step : float, default 1.0
        Spacing of the heights a leg tries, metres (nearest to the straight line first).
    max_relocations : int or None, default 10
        Most relocations in one run; ``None``: no limit.
    movers : int, default 2
        UAVs considered for a relocation, smallest exclusive share first.
    destinations : int, default 5
        Destinations tried per UAV, best predicted gain first.
    min_gain : float, default 0.0
        A destination must predict an exclusive share above the mover's current one by more than
        this (a share of the targets' weight).
    restart_step : bool, default False
        After a relocation, restart CAO's step at ``alpha_0`` instead of continuing its schedule.
    """

    patience: int = 40
    hop: float = 5.0
    climb_search: float = 8.0
    climb_step: float = 1.0
    max_relocations: int | None = 10
    movers: int = 2
    destinations: int = 5
    min_gain: float = 0.0
    restart_step: bool = False

    def __post_init__(self) -> None:
        def put(name: str, value: Any) -> None:
            object.__setattr__(self, name, value)

        put("patience", as_positive_int(self.patience, "patience"))
        put("hop", as_positive_float(self.hop, "hop"))
        put("climb_search", as_non_negative_float(self.climb_search, "climb_search"))
        put("climb_step", as_positive_float(self.climb_step, "climb_step"))
        if self.climb_search / self.climb_step > 1000:
            raise InvalidInputError(f"climb_search / climb_step = {self.climb_search / self.climb_step:g} heights per leg; at most 1000")
        if self.max_relocations is not None:
            put("max_relocations", as_positive_int(self.max_relocations, "max_relocations"))
        put("movers", as_positive_int(self.movers, "movers"))
        put("destinations", as_positive_int(self.destinations, "destinations"))
        put("min_gain", as_non_negative_float(self.min_gain, "min_gain"))
        put("restart_step", as_bool(self.restart_step, "restart_step"))

    def heights(self) -> np.ndarray:
        """Offsets a leg tries from the straight line, metres, nearest first: 0, +s, -s, +2s, ..."""
        n = math.floor(self.climb_search / self.climb_step + 1e-9)
        steps = np.arange(1, n + 1, dtype=np.float64) * self.climb_step
        offsets = np.empty(2 * n + 1)
        offsets[0] = 0.0
        offsets[1::2] = steps
        offsets[2::2] = -steps
        return offsets


class _Log:
    """What the team measured: every configuration, each UAV's exclusive share there, and the
    distance from each UAV to its nearest teammate then."""

    def __init__(self, n_max: int, n_uavs: int) -> None:
        self.positions = np.empty((n_max, n_uavs, 3))
        self.shares = np.empty((n_max, n_uavs))
        self.nearest = np.empty((n_max, n_uavs))
        self.size = 0

    def add(self, x: np.ndarray, shares: np.ndarray) -> None:
        self.positions[self.size] = x[:, :3]
        self.shares[self.size] = shares
        self.nearest[self.size] = _nearest_distance(x[:, :3], x[:, :3], exclude_self=True)
        self.size += 1


_CHUNK = 4096


def _nearest_distance(points: np.ndarray, team: np.ndarray, *, exclude_self: bool = False) -> np.ndarray:
    """``(P,)`` distance from each of ``points`` to the nearest of ``team`` (inf when it is empty),
    skipping ``team[p]`` for point ``p`` with ``exclude_self``; in chunks, so memory stays small."""
    out = np.full(points.shape[0], np.inf)
    if team.shape[0] == 0:
        return out
    for lo in range(0, points.shape[0], _CHUNK):
        gaps = np.linalg.norm(points[lo : lo + _CHUNK, None, :] - team[None, :, :], axis=-1)
        if exclude_self:
            rows = np.arange(gaps.shape[0])
            gaps[rows, rows + lo] = np.inf
        out[lo : lo + _CHUNK] = gaps.min(axis=1)
    return out


def _destinations(log: _Log, mover: int, current: np.ndarray, share: float, settings: EscapeSettings) -> list[np.ndarray]:
    """Positions where ``mover`` is predicted to add most, best first (step 2 of the module's algorithm)."""
    positions = log.positions[: log.size].reshape(-1, 3)
    predicted = log.shares[: log.size].reshape(-1)
    then = log.nearest[: log.size].reshape(-1)
    away = np.linalg.norm(positions - current[mover], axis=1) >= settings.hop
    candidate = np.flatnonzero((predicted > share + settings.min_gain) & away)
    now = _nearest_distance(positions[candidate], np.delete(current, mover, axis=0))
    eligible = candidate[now >= then[candidate]]
    chosen: list[np.ndarray] = []
    for index in eligible[np.argsort(-predicted[eligible], kind="stable")]:
        p = positions[index]
        if all(np.linalg.norm(p - q) >= settings.hop for q in chosen):
            chosen.append(p)
            if len(chosen) == settings.destinations:
                break
    return chosen


def _flight(
    current: np.ndarray, mover: int, goal: np.ndarray, legs_left: int, check: _Feasibility, settings: EscapeSettings
) -> tuple[list[np.ndarray], int, int] | None:
    """Configurations of ``mover``'s flight to ``goal`` (the last one there), each a checked move
    from the one before, with the configurations checked and found admissible; ``None`` when it
    cannot be flown within ``legs_left`` legs (step 3 of the module's algorithm)."""
    start = current[mover, :3].copy()
    span = float(np.linalg.norm(goal[:2] - start[:2]))
    n_legs = max(1, math.ceil(span / settings.hop - 1e-9))
    if n_legs > legs_left:
        return None
    offsets = settings.heights()
    here = current.copy()
    path: list[np.ndarray] = []
    checked = found = 0
    for leg in range(1, n_legs + 1):
        along = start + (goal - start) * (leg / n_legs)
        # the last leg lands on the destination itself, where it was admissible
        heights = np.array([goal[2]]) if leg == n_legs else along[2] + offsets
        candidates = np.broadcast_to(here, (heights.size, *here.shape)).copy()
        candidates[:, mover, :2] = along[:2]
        candidates[:, mover, 2] = heights
        ok = check(here, candidates)
        checked += int(ok.size)
        found += int(ok.sum())
        if not ok.any():
            return None
        here = candidates[int(np.argmax(ok))]
        path.append(here)
    return path, checked, found


_DEFAULT_CAO = CAOSettings()


def _escape_flight(log: _Log, legs_left: int, check: _Feasibility, settings: EscapeSettings) -> list[Any]:
    """The flight of a stalled team: ``[mover, configurations, checked, found]`` of the first of its
    least useful UAVs that has a clear way to a destination, or ``[]`` when none has."""
    current = log.positions[log.size - 1]
    shares = log.shares[log.size - 1]
    for mover in np.argsort(shares, kind="stable")[: settings.movers]:
        for goal in _destinations(log, int(mover), current, float(shares[mover]), settings):
            flight = _flight(current, int(mover), goal, legs_left, check, settings)
            if flight is not None:
                return [int(mover), *flight]
    return []


class _Pieces:
    """The trace's arrays, gathered from CAO's runs and the escape flights between them."""

    def __init__(self) -> None:
        self.traj: list[np.ndarray] = []
        self.values: list[np.ndarray] = []
        self.measured: list[np.ndarray] = []
        self.steps: list[np.ndarray] = []
        self.n_checked: list[np.ndarray] = []
        self.n_feasible: list[np.ndarray] = []

    def add_run(self, part: OptimizerTrace) -> None:
        self.traj.append(part.trajectory)
        self.values.append(part.values)
        self.measured.append(part.measured)
        self.steps.append(part.step_sizes)
        self.n_checked.append(part.n_checked)
        self.n_feasible.append(part.n_feasible)

    def add_leg(self, leg: np.ndarray, value: float, seen: float) -> None:
        """A configuration the flight passes through, and what was measured there."""
        self.traj.append(leg[None])
        self.values.append(np.array([value]))
        self.measured.append(np.array([seen]))

    def add_flight(self, n_configurations: int, checked: int, found: int) -> None:
        """A flight's steps (none: it is not CAO's) and the configurations its planning checked."""
        self.steps.append(np.zeros(n_configurations))
        self.n_checked.append(np.array([checked] + [0] * (n_configurations - 1), dtype=np.int64))
        self.n_feasible.append(np.array([found] + [0] * (n_configurations - 1), dtype=np.int64))

    def trace(self, settings: CAOSettings, t_measure: float, t_feasible: float, t_total: float) -> OptimizerTrace:
        return _finish(
            "escape",
            np.concatenate(self.traj),
            np.concatenate(self.values),
            np.concatenate(self.measured),
            np.concatenate(self.steps),
            np.concatenate(self.n_checked),
            np.concatenate(self.n_feasible),
            settings,
            t_measure,
            t_feasible,
            t_total,
        )


def escape_cao(
    measure: Callable[[np.ndarray], tuple[float, np.ndarray]],
    x0: Any,
    *,
    feasible: FeasibleFn | None,
    iterations: int,
    settings: CAOSettings = _DEFAULT_CAO,
    rng: Any = None,
    escape: EscapeSettings = EscapeSettings(),
) -> OptimizerTrace:
    """Centralised CAO that relocates its least useful UAV whenever it stalls (module docstring).

    Parameters
    ----------
    measure : callable
        ``measure(x)`` with ``x`` ``(N, 3)`` returns ``(team_value, exclusive_shares)``: the
        coverage and each UAV's exclusive share ``(N,)`` (what the team loses without it), as
        :func:`per_robot_cao` takes. One call per visited configuration.
    x0, feasible, iterations, settings, rng
        As in :func:`cao`; ``x0`` holds positions only ``(N, 3)``.
    escape : EscapeSettings
        When to relocate and how to fly there.

    Returns
    -------
    OptimizerTrace
        ``kind == "escape"``, ``relocations`` the flights; ``K + 1`` configurations measured in
        all, CAO's and the flights'.

    Raises
    ------
    InvalidInputError, InvalidTypeError
        As :func:`cao`, and ``escape`` not an :class:`EscapeSettings`.
    InfeasibleError
        The start is not feasible.

    Examples
    --------
    Two UAVs on a measured objective with two peaks; UAV 1 starts on the lesser one:

    >>> import numpy as np
    >>> peaks = np.array([[0.0, 0.0, 0.0], [30.0, 0.0, 0.0]])
    >>> def measure(x):
    ...     own = np.exp(-(np.linalg.norm(x[:, None] - peaks[None], axis=2) ** 2) / 50.0) * [1.0, 0.5]
    ...     return float(own.max(axis=0).sum()), own.max(axis=1)
    >>> trace = escape_cao(measure, [[1.0, 0.0, 0.0], [29.0, 0.0, 0.0]], feasible=None, iterations=100, rng=0)
    >>> trace.kind, trace.evaluations
    ('escape', 101)
    """
    x0, n_iter = _check_common(x0, feasible, iterations, settings)
    if not callable(measure):
        raise InvalidTypeError(f"measure must be callable, got {type(measure).__name__}")
    if not isinstance(escape, EscapeSettings):
        raise InvalidTypeError(f"escape must be an EscapeSettings, got {type(escape).__name__}")
    n_uavs = x0.shape[0]
    base = settings.resolved(n_uavs)
    rng = np.random.default_rng(rng)
    check = _Feasibility(feasible)
    t_start = time.perf_counter()
    _check_start(check, x0)

    log = _Log(n_iter + 1, n_uavs)
    clock = {"measure": 0.0}

    def team_value(x: np.ndarray) -> float:
        t0 = time.perf_counter()
        team, shares = _as_team_and_marginals(measure(x.copy()), n_uavs, log.size)
        clock["measure"] += time.perf_counter() - t0
        log.add(x, shares)
        return team

    pieces = _Pieces()
    relocations: list[tuple[int, int, int]] = []
    best = -math.inf
    waited = 0
    plan: list[Any] = []  # the flight decided by the last stall: (mover, configurations, checked, found)
    offset = 0  # the mission's iteration at which the current CAO run started
    x = x0

    def stalled(seen: np.ndarray) -> bool:
        nonlocal best, waited
        if seen[-1] > best:
            best, waited = float(seen[-1]), 0
            return False
        waited += 1
        here = offset + seen.size - 1
        full = escape.max_relocations is not None and len(relocations) >= escape.max_relocations
        if waited < escape.patience or full or here >= n_iter:
            return False
        waited = 0
        plan[:] = _escape_flight(log, n_iter - here, check, escape)
        return bool(plan)

    while True:
        run_settings = base
        if offset and not escape.restart_step:  # alpha_{offset + j} = alpha0' ((1 + A') / (j + 1 + A')) ** decay
            run_settings = replace(base, alpha0=float(base.step_size(offset)), stability=base.stability + offset)
        plan.clear()
        part = _cao_run(team_value, x, feasible=check, iterations=n_iter - offset, settings=run_settings, rng=rng, stop=stalled)
        pieces.add_run(part)
        here = offset + part.n_iterations
        if not plan:
            break
        mover, path, checked, found = plan
        # the flight's legs: measured on the way, the last one is where CAO resumes (and measures)
        for leg in path[:-1]:
            value = team_value(leg)
            seen = value + base.measurement_noise * rng.standard_normal() if base.measurement_noise else value
            pieces.add_leg(leg, value, seen)
            best = max(best, seen)
        pieces.add_flight(len(path), checked, found)
        relocations.append((mover, here, here + len(path)))
        offset = here + len(path)
        x = path[-1]

    trace = pieces.trace(base, clock["measure"], check.seconds, time.perf_counter() - t_start)
    return replace(trace, relocations=read_only(np.array(relocations, dtype=np.int64).reshape(-1, 3)))
