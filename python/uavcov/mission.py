"""The paper's two-step mission: an off-line start from the prior, then on-line CAO.

:func:`run_mission` runs a :class:`~uavcov.settings.MissionSettings` on a true surface:

1. the prior: the known points (random samples plus the 4 corners, or the paper's pyramid), or
   an approximating surface S' given directly, and S' from them (:mod:`uavcov.terrain`, :mod:`uavcov.structures`);
2. the start on S' (:func:`uavcov.placement.start_configuration`: the constrained CVT, or a random,
   corner or pairs start), lifted to flying height and moved to the closest admissible
   positions above the real surface (the UAVs sense the ground, paper section V-B);
3. the optimiser (CAO, centralised or per robot) on the real surface, which it sees only through
   coverage measurements and the constraint checks.

It returns a :class:`MissionResult`: a frozen, picklable record of everything that happened.

Random streams
--------------
``rng`` is split into three independent children (``numpy`` ``Generator.spawn(3)``): the prior
samples, the start, the optimiser. So two missions with the same ``rng`` see the same prior
points whatever their team size or start, and a change of the optimiser's settings leaves the
start as it was.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any, TypeVar

import numpy as np

from ._validate import (
    as_generator,
    as_non_negative_float,
    as_points,
    as_positive_float,
    is_int,
    read_only,
)
from .engine import Targets, Terrain, Visibility
from .errors import InvalidInputError, InvalidTypeError
from .limits import closest_admissible, feasibility
from .optim import MARGINAL_OPTIMIZERS, OPTIMIZERS, OptimizerTrace
from .placement import CVTResult, facing_attitudes, fit_footprints, start_configuration
from .settings import MissionSettings
from .structures import Structure, StructurePrior, StructureTargets, reconstruct_structure, sample_structure_prior
from .terrain import Prior, approximate_surface, sample_prior

__all__ = ["MissionResult", "run_mission", "mission_time", "iterations_to_fraction"]


@dataclass(frozen=True, eq=False)
class MissionResult:
    """What one mission did. Frozen and picklable.

    What the optimiser did is its :attr:`trace`; the run's figures that come from it
    (:attr:`trajectory`, :attr:`coverage`, :attr:`best_positions`, :attr:`best_iteration`,
    :attr:`evaluations`, the timings, ...) are properties over it, as ``scipy.optimize``'s
    ``OptimizeResult`` reads one record.

    Attributes
    ----------
    settings : MissionSettings
        What ran, with the constraints resolved against the true surface.
    seed : int or None
        The integer seed, when ``rng`` was one.
    prior_kind : str
        How the known points were obtained: "random", "pyramid", "points" (given), "surface"
        (S' given directly), "structure_points" or "structure_boxes" / "structure_decimated" (a
        structure's 3D prior), ...
    terrain : Terrain
        The true surface.
    prior_points : (n, 3) ndarray
        The known points (empty when S' was given directly).
    approximation : Terrain
        S', the surface the start was computed on.
    start_positions : (N, 3) ndarray
        The start before it was made admissible: lifted CVT generators, random or corner
        positions, or the positions given.
    cvt : CVTResult or None
        The CVT run, for the "cvt" start.
    trace : OptimizerTrace
        The optimiser's full record (its ``values`` are the coverage measured).
    wall_time_s : float
        Seconds for the whole mission (prior, start, optimisation).
    start_time_s : float
        Seconds to compute the start on S' (its off-line time: the CVT, or the greedy start's
        lattice, seen-matrix and greedy); 0 for given start positions, NaN when not recorded.
    coverage_by_part : dict of str to float, optional
        For a mission on a :class:`~uavcov.structures.Structure` (targets with parts): the
        weighted share of each part's targets seen by :attr:`best_positions` ("deck_top",
        "deck_underside", "piers", ...); ``None`` otherwise.

    Examples
    --------
    >>> import numpy as np, uavcov
    >>> hills = uavcov.gaussian_hills(size=40.0, spacing=2.0, n_hills=3, rng=1)
    >>> result = uavcov.run_mission(hills, uavcov.MissionSettings(n_uavs=3, d_max=15.0, iterations=20), rng=0)
    >>> result.trajectory.shape, result.coverage.shape  # (K + 1, N, 3) positions, (K + 1,) coverage
    ((21, 3, 3), (21,))
    >>> bool(result.best_coverage == result.coverage[result.best_iteration] >= result.initial_coverage)
    True

    Which targets the best configuration sees (the mission keeps its coverage, not the flags):

    >>> vis = uavcov.Visibility(result.terrain, result.settings.d_max)
    >>> seen = vis.seen(result.best_positions)
    >>> bool(abs(np.average(seen, weights=vis.targets.weights) - result.best_coverage) < 1e-12)
    True

    Its repr is a summary (the fields hold whole surfaces):

    >>> result  # doctest: +ELLIPSIS
    MissionResult(3 UAVs, d_max 15 m, cvt start, cao 20 iterations: coverage 0... at the start, best 0... at iteration ...; seed 0, ... s)
    """

    settings: MissionSettings
    seed: int | None
    prior_kind: str
    terrain: Terrain
    prior_points: np.ndarray
    approximation: Terrain
    start_positions: np.ndarray
    cvt: CVTResult | None
    trace: OptimizerTrace = field(repr=False)
    wall_time_s: float
    start_time_s: float = math.nan
    coverage_by_part: dict[str, float] | None = None

    def __repr__(self) -> str:
        # A summary, as Terrain's: the fields hold whole surfaces and arrays (thousands of characters).
        spec = self.settings
        parts = f", by part { ({part: round(share, 3) for part, share in self.coverage_by_part.items()}) }" if self.coverage_by_part else ""
        return (
            f"MissionResult({spec.n_uavs} UAVs, d_max {spec.d_max:g} m, {spec.start.kind} start, {spec.optimizer} "
            f"{len(self.trace.values) - 1} iterations: coverage {self.initial_coverage:.3f} at the start, best "
            f"{self.best_coverage:.3f} at iteration {self.best_iteration}{parts}; seed {self.seed}, {self.wall_time_s:.1f} s)"
        )

    @functools.cached_property
    def trajectory(self) -> np.ndarray:
        """``(K + 1, N, 3)`` positions at every iteration; ``trajectory[0]`` is the admissible start.

        The camera angles, fixed or free, are :attr:`attitudes`; ``trace.trajectory`` holds the
        optimiser's whole state.
        """
        return read_only(np.ascontiguousarray(self.trace.trajectory[..., :3]))

    @property
    def coverage(self) -> np.ndarray:
        """``(K + 1,)`` true coverage at every iteration, in [0, 1] (the trace's ``values``)."""
        return np.asarray(self.trace.values, dtype=np.float64)

    @functools.cached_property
    def best_positions(self) -> np.ndarray:
        """``(N, 3)`` the configuration with the highest coverage."""
        return read_only(np.ascontiguousarray(self.trace.best_positions[..., :3]))

    @property
    def best_coverage(self) -> float:
        """The highest coverage measured, at :attr:`best_iteration`."""
        return float(self.trace.best_value)

    @property
    def initial_coverage(self) -> float:
        """Coverage at the admissible start."""
        return float(self.trace.values[0])

    @property
    def final_coverage(self) -> float:
        """Coverage after the last iteration."""
        return float(self.trace.values[-1])

    @property
    def best_iteration(self) -> int:
        """The iteration of :attr:`best_coverage` (the first one on ties)."""
        return int(self.trace.best_iteration)

    @property
    def iterations_to_95(self) -> int:
        """First iteration whose coverage reaches 95 % of :attr:`best_coverage`."""
        return iterations_to_fraction(self.coverage, 0.95)

    @property
    def evaluations(self) -> int:
        """Coverage measurements made by the optimiser."""
        return int(self.trace.evaluations)

    @property
    def time_measure_s(self) -> float:
        """Seconds in coverage measurements."""
        return float(self.trace.time_measure_s)

    @property
    def time_optimizer_s(self) -> float:
        """Seconds in the optimiser's own work."""
        return float(self.trace.time_optimizer_s)

    @property
    def attitudes(self) -> np.ndarray | None:
        """``(K + 1, N, 2)`` ``(yaw, pitch)`` of every camera at every iteration, degrees.

        Yaw in ``[0, 360)``. The fixed angles are the spec's ``attitude``, the free ones
        (``spec.gimbal``) the optimiser's. ``None`` for a sensor without a camera.
        """
        spec = self.settings
        if not spec.has_camera:
            return None
        state = np.asarray(self.trace.trajectory)
        angles = np.empty((*state.shape[:2], 2))
        angles[...] = spec.attitude
        scale = _degrees_per_unit(spec)
        for column, name in enumerate(spec.free_angles, start=3):
            angles[..., 0 if name == "yaw" else 1] = state[..., column] * scale
        angles[..., 0] %= 360.0
        angles.flags.writeable = False
        return angles

    @property
    def best_attitudes(self) -> np.ndarray | None:
        """``(N, 2)`` ``(yaw, pitch)`` at :attr:`best_iteration`, degrees; ``None`` without a camera."""
        angles = self.attitudes
        return None if angles is None else angles[self.best_iteration]

    @property
    def distance_flown(self) -> np.ndarray:
        """``(N,)`` metres each UAV flew during the mission.

        The sum of the straight moves between consecutive configurations of :attr:`trajectory`
        (every UAV moves in a straight line from one measured configuration to the next, as CAO
        moves it and as the ``"escape"`` optimiser's flights are made of legs). It starts at the
        admissible start ``trajectory[0]``: the flight from the take-off site to the start, and
        the move from :attr:`start_positions` to the admissible start, are not counted (the paper
        does not model a take-off site). Camera angles cost no distance.
        """
        return _path_lengths(np.asarray(self.trajectory))

    @property
    def relocations(self) -> np.ndarray:
        """``(R, 3)`` int64 ``(uav, first, last)`` of every escape flight of the ``"escape"``
        optimiser (see :class:`~uavcov.optim.OptimizerTrace`); empty for the others."""
        return np.asarray(self.trace.relocations)

    @property
    def relocation_distance(self) -> float:
        """Metres flown in the escape flights (:attr:`relocations`), summed; 0 without any."""
        path = np.asarray(self.trajectory)
        return float(sum(_path_lengths(path[first : last + 1, [uav]])[0] for uav, first, last in self.relocations))

    @property
    def initial_positions(self) -> np.ndarray:
        """``(N, 3)`` admissible start the optimiser began from."""
        return np.asarray(self.trajectory[0])

    @property
    def final_positions(self) -> np.ndarray:
        """``(N, 3)`` positions after the last iteration."""
        return np.asarray(self.trajectory[-1])


def _path_lengths(trajectory: np.ndarray) -> np.ndarray:
    """``(N,)`` length of each UAV's polyline through ``(K + 1, N, 3)`` positions, metres."""
    if trajectory.shape[0] < 2:
        return np.zeros(trajectory.shape[1])
    lengths: np.ndarray = np.linalg.norm(np.diff(trajectory, axis=0), axis=2).sum(axis=0)
    return lengths


def mission_time(result: MissionResult, speed: float, *, hover_s: float = 0.0) -> float:
    """Seconds the mission takes at cruise ``speed`` (m/s), the UAVs flying at the same time.

    The model: the team moves from one measured configuration to the next together and measures
    once all have arrived (CAO is synchronous), so a move takes its longest straight move over
    ``speed``; each of the ``K + 1`` configurations adds ``hover_s`` seconds of hovering to
    measure. Acceleration, turns and the flight to the start are not modelled. This is at
    least ``max(result.distance_flown) / speed`` (equal when one UAV is the slowest of every
    move).

    Parameters
    ----------
    result : MissionResult
    speed : float
        Cruise speed, metres per second (> 0).
    hover_s : float, default 0.0
        Seconds spent at each configuration measuring (>= 0).

    Returns
    -------
    float
        Seconds.

    Raises
    ------
    InvalidInputError
        ``speed`` not positive and finite, or ``hover_s`` negative or not finite.
    InvalidTypeError
        ``result`` not a :class:`MissionResult`.

    Examples
    --------
    >>> import uavcov
    >>> hills = uavcov.gaussian_hills(size=40.0, spacing=2.0, n_hills=3, rng=1)
    >>> result = run_mission(hills, MissionSettings(n_uavs=3, d_max=15.0, iterations=5), rng=0)
    >>> bool(mission_time(result, 5.0) >= result.distance_flown.max() / 5.0)
    True
    """
    if not isinstance(result, MissionResult):
        raise InvalidTypeError(f"result must be a MissionResult, got {type(result).__name__}")
    speed = as_positive_float(speed, "speed")
    hover_s = as_non_negative_float(hover_s, "hover_s")
    path = np.asarray(result.trajectory)
    longest = np.linalg.norm(np.diff(path, axis=0), axis=2).max(axis=1) if path.shape[0] > 1 else np.zeros(0)
    return float(longest.sum() / speed + hover_s * path.shape[0])


def iterations_to_fraction(values: np.ndarray, fraction: float = 0.95) -> int:
    """First index at which ``values`` reaches ``fraction`` of its maximum."""
    values = np.asarray(values, dtype=float)
    return int(np.argmax(values >= fraction * values.max()))


def _seed_of(rng: Any) -> int | None:
    return int(rng) if is_int(rng) else None


def _approximation(terrain: Terrain, spec: MissionSettings, known: Any, rng: np.random.Generator) -> tuple[Terrain, np.ndarray, str]:
    """S', the known points behind it, and how they were chosen."""
    if isinstance(known, Terrain):
        return known, np.empty((0, 3)), "surface"
    if isinstance(known, StructurePrior):
        return _structure_approximation(known, rng)
    if known is None:
        prior = sample_prior(terrain, spec.n_prior, kind=spec.prior, rng=rng)
    elif isinstance(known, Prior):
        prior = known
    else:
        prior = sample_prior(terrain, kind="points", points=known, rng=rng)
    return approximate_surface(prior), np.array(prior.points), prior.kind


def _structure_approximation(prior: StructurePrior, rng: np.random.Generator) -> tuple[Terrain, np.ndarray, str]:
    """S' of a structure from a 3D prior, without a ground plane.

    The CVT spreads the team over S' by area, and the targets are the structure's (the ground
    carries none by default): a ground plane in S' would draw most generators onto the ground
    around the structure, and the starts need no ground in S' (the real one is sensed: the flight
    limits keep every UAV above it).
    """
    return reconstruct_structure(prior, rng=rng), np.array(prior.points), f"structure_{prior.kind}"


def _structure_inputs(
    structure: Structure, spec: MissionSettings, known: Any, targets: Targets | None, rng: np.random.Generator
) -> tuple[Any, Targets]:
    """What a structure's mission is given by default: a 3D prior of ``n_prior`` points, its targets."""
    if spec.constraints.clearance != "standoff":
        raise InvalidInputError(
            f"a mission on the structure {structure.name!r} needs 3D flight limits: "
            'constraints=Constraints(clearance="standoff", ...) (a vertical clearance forbids flying under a deck)'
        )
    structure.check_ground()
    if known is None:
        if spec.prior != "random":
            raise InvalidInputError(f"prior={spec.prior!r} is a height field's: a structure's prior is n_prior random points on it")
        known = sample_structure_prior(structure, spec.n_prior, rng=rng)
    return known, structure.targets() if targets is None else targets


def run_mission(
    terrain: Terrain | Structure,
    settings: MissionSettings,
    *,
    known: Any = None,
    start_positions: Any = None,
    targets: Targets | None = None,
    n_threads: int | None = None,
    rng: Any = None,
) -> MissionResult:
    """Run the paper's two-step mission on a true surface.

    Parameters
    ----------
    terrain : Terrain or Structure
        The true surface S. The optimiser sees it only through coverage measurements and the
        constraint checks (clearance below each UAV, and moves crossing no surface). A
        :class:`~uavcov.structures.Structure` (a bridge, a tower: not a height field) needs
        ``settings.constraints.clearance == "standoff"``; its prior is then ``n_prior`` random
        points on it (:func:`~uavcov.structures.sample_structure_prior`) reconstructed into S' by
        :func:`~uavcov.structures.reconstruct_structure` (no ground plane), its targets
        :meth:`~uavcov.structures.Structure.targets`, and the result has :attr:`MissionResult.coverage_by_part`.
    settings : MissionSettings
        Everything the mission runs.
    known : Prior, StructurePrior, (n, 2 or 3) array_like, or Terrain, optional
        What is known beforehand, instead of what ``settings.prior`` samples: a
        :class:`~uavcov.terrain.Prior` (a height field's: S' by ``approximate_surface``), a
        :class:`~uavcov.structures.StructurePrior` (S' by ``reconstruct_structure``), known
        positions or points, or an approximating surface S' given directly (e.g. a buildings map).
    start_positions : (N, 3) array_like, optional
        Positions of your own to start from (metres, used as given: no lift), instead of
        ``settings.start``'s; they are still moved to the closest admissible positions.
    targets : Targets, optional
        Coverage targets; the true terrain's default targets by default.
    n_threads : int, optional
        Threads for each coverage measurement and for the start, 1 to 1024; ``None`` (the
        default) is rayon's default: ``RAYON_NUM_THREADS`` if set, else every core. Results do
        not depend on it.
    rng : None, int or numpy.random.Generator
        Source of every random draw (see the module's random streams); the same seed gives the
        same run.

    Returns
    -------
    MissionResult

    Raises
    ------
    InvalidInputError, InvalidTypeError
        Bad settings or argument; a structure with no ground, or whose ground stops short of it
        (no UAV could stand beside it there).
    InfeasibleError
        The team cannot be placed admissibly.

    Examples
    --------
    >>> import uavcov
    >>> hills = uavcov.gaussian_hills(size=40.0, spacing=2.0, n_hills=3, rng=1)
    >>> result = run_mission(hills, MissionSettings(n_uavs=3, d_max=15.0, iterations=5), rng=0)
    >>> result.coverage.shape, 0.0 < result.best_coverage <= 1.0
    ((6,), True)
    """
    started = time.perf_counter()
    structure = terrain if isinstance(terrain, Structure) else None
    if structure is not None:
        terrain = structure.surface
    if not isinstance(terrain, Terrain):
        raise InvalidTypeError(f"terrain must be a uavcov.Terrain or Structure, got {type(terrain).__name__}")
    if not isinstance(settings, MissionSettings):
        raise InvalidTypeError(f"settings must be a MissionSettings, got {type(settings).__name__}")
    spec = settings
    given = None
    if start_positions is not None:
        given = as_points(start_positions, "start_positions")
        if given.shape[0] != spec.n_uavs:
            raise InvalidInputError(f"start_positions has {given.shape[0]} positions for {spec.n_uavs} UAVs")
    constraints = spec.constraints.resolve(terrain)
    constraints.check_team(spec.n_uavs, terrain)
    spec = replace(spec, constraints=constraints)
    prior_rng, start_rng, optimizer_rng = as_generator(rng).spawn(3)
    if structure is not None:
        known, targets = _structure_inputs(structure, spec, known, targets, prior_rng)
    vis = Visibility(terrain, spec.d_max, targets, n_threads=n_threads)

    approximation, prior_points, prior_kind = _approximation(terrain, spec, known, prior_rng)
    if given is None:
        keep_out = _keep_out(known, spec.start.kind)
        flying, tessellation, start_time_s = _start(spec, approximation, terrain, start_rng, n_threads, keep_out)
    else:
        flying, tessellation, start_time_s = given, None, 0.0
    attitudes = np.broadcast_to(np.asarray(spec.attitude, dtype=np.float64), (spec.n_uavs, 2))
    if spec.footprint_start and given is None:
        flying, attitudes = _footprint_start(spec, approximation, flying, attitudes, n_threads)
    x0 = closest_admissible(constraints, terrain, flying, climb=spec.start.climb)
    if spec.start.altitude_reference == "normal" and spec.has_camera:
        attitudes = _facing_start(spec, approximation, x0, n_threads)
    state = _CameraState(spec, attitudes)
    trace = _optimise(spec, terrain, vis, state, x0, optimizer_rng, n_threads)
    parts = None
    if structure is not None and isinstance(vis.targets, StructureTargets):
        best = np.ascontiguousarray(trace.best_positions)
        seen = vis.seen(state.poses(best), sensors=spec.team_sensors()) if spec.has_camera else vis.seen(best)
        parts = structure.coverage_by_part(np.asarray(seen, dtype=bool), vis.targets)
    return MissionResult(
        settings=replace(spec, cao=trace.settings),
        seed=_seed_of(rng),
        prior_kind=prior_kind,
        terrain=terrain,
        prior_points=prior_points,
        approximation=approximation,
        start_positions=flying,
        cvt=tessellation,
        wall_time_s=time.perf_counter() - started,
        trace=trace,
        start_time_s=start_time_s,
        coverage_by_part=parts,
    )


# How far from the known points (in their spacings) their vote keeps a CVT start's UAV out:
# the best mean on development seeds 1000-1007 (benches/structure_keep_out.py: 0.907 with the
# vote everywhere, 0.922-0.925 within 1-4 spacings, the most at 4, 0.919 at 6; one start inside
# a building at 1). Deep inside a large solid the vote is right however far the known points
# are: 3 spacings left one start inside a building, at a step 3.0 spacings from the nearest
# known point (report seed 5, docs/structures.md).
CVT_KEEP_OUT_SPACINGS = 4.0


def _keep_out(known: Any, kind: str) -> Callable[[np.ndarray], Any] | None:
    """Where the known points' normals put the structure, as a keep-out for the start.

    They see parts S' misses (a girder, a balcony): no start there. A greedy start drops a
    candidate the vote marks, one of thousands, at no cost, so it takes the vote everywhere; a
    CVT start's generator is a UAV, flown farther or lifted over S' when marked, so it takes the
    vote only where it is evidence, near the known points.
    """
    if not (isinstance(known, StructurePrior) and known.normals is not None):
        return None
    if kind == "greedy":
        return known.behind
    return functools.partial(known.behind, reach=CVT_KEEP_OUT_SPACINGS * known.spacing)


def _start(
    spec: MissionSettings,
    approximation: Terrain,
    terrain: Terrain,
    rng: np.random.Generator,
    n_threads: int | None,
    keep_out: Callable[[np.ndarray], Any] | None = None,
) -> tuple[np.ndarray, CVTResult | None, float]:
    """``spec.start`` on S': the positions, the CVT run (for a "cvt" start) and the seconds it took."""
    began = time.perf_counter()
    flying, record = start_configuration(
        spec.start,
        approximation,
        terrain,
        spec.n_uavs,
        cvt_settings=spec.cvt,
        rng=rng,
        n_threads=n_threads,
        d_max=spec.d_max,
        constraints=spec.constraints,
        keep_out=keep_out,
    )
    return flying, record if isinstance(record, CVTResult) else None, time.perf_counter() - began


def _optimise(
    spec: MissionSettings,
    terrain: Terrain,
    vis: Visibility,
    state: _CameraState,
    x0: np.ndarray,
    rng: np.random.Generator,
    n_threads: int | None,
) -> OptimizerTrace:
    """``spec.optimizer`` from the admissible start ``x0``, measuring the true coverage."""
    feasible = feasibility(spec.constraints, terrain, n_threads=n_threads)
    sensors = spec.team_sensors()
    camera = spec.has_camera

    def poses(x: np.ndarray) -> np.ndarray:
        return state.poses(x) if camera else x

    optimizer = OPTIMIZERS[spec.optimizer]
    if spec.optimizer in MARGINAL_OPTIMIZERS:

        @_repeats_the_last
        def measure(x: np.ndarray) -> tuple[float, np.ndarray]:
            counts = vis.per_uav(poses(x), sensors=sensors)  # the coverage and the marginals in one pass
            return counts.coverage, counts.exclusive_share

        extra = {"escape": spec.escape} if spec.optimizer == "escape" else {}
        return optimizer(measure, x0, feasible=feasible, iterations=spec.iterations, settings=spec.cao, rng=rng, **extra)
    if spec.objective == "coverage" and sensors is None:
        # One team's measurements along its path: the tracker reuses what each proved.
        along = vis.tracker()

        @_repeats_the_last
        def value(x: np.ndarray) -> float:
            return along.coverage(x)

    else:
        objective = vis.quality_coverage if spec.objective == "quality" else vis.coverage

        @_repeats_the_last
        def value(x: np.ndarray) -> float:
            return objective(poses(x), sensors=sensors)

    return optimizer(value, state.initial(x0), feasible=state.feasible(feasible), iterations=spec.iterations, settings=spec.cao, rng=rng)


_Measured = TypeVar("_Measured")


def _repeats_the_last(measure: Callable[[np.ndarray], _Measured]) -> Callable[[np.ndarray], _Measured]:
    """``measure`` that answers a configuration equal to the last one measured with the same value.

    The simulated measurement is a deterministic function of the configuration, and an optimiser
    often stays put (no candidate better than staying, or none admissible: 1-10 % of the paper's
    iterations), so the answer is the same to the last bit without the engine's work. The
    optimiser still counts the call; simulated noise is drawn on top by the optimiser.
    """
    last: list[tuple[np.ndarray, _Measured]] = []

    def cached(x: np.ndarray) -> _Measured:
        if last and np.array_equal(last[0][0], x):
            return last[0][1]
        value = measure(x)
        last[:] = [(x.copy(), value)]
        return value

    return cached


def _degrees_per_unit(spec: MissionSettings) -> float:
    """Degrees of camera angle per unit of CAO's state: the angles' first step over the positions'."""
    return spec.gimbal.alpha0_deg / spec.cao.alpha0 if spec.gimbal is not None else 1.0


class _CameraState:
    """The optimiser's state for a camera team: positions, then each free angle over its scale.

    An angle enters CAO's state in units of the step (``gimbal.alpha0_deg / cao.alpha0`` degrees
    per unit), so one ``alpha_k`` perturbs positions and angles alike; yaw stays unwrapped in the
    state (the surrogate is local: a wrap would be a jump) and wraps in the poses.
    """

    def __init__(self, spec: MissionSettings, attitudes: np.ndarray) -> None:
        self.fixed = np.array(attitudes, dtype=np.float64)
        self.free = spec.free_angles
        self.columns = [0 if name == "yaw" else 1 for name in self.free]
        self.scale = _degrees_per_unit(spec)
        self.pitch_range = spec.gimbal.pitch_range if spec.gimbal is not None else None

    def initial(self, x0: np.ndarray) -> np.ndarray:
        return np.column_stack([x0, self.fixed[:, self.columns] / self.scale]) if self.free else x0

    def poses(self, x: np.ndarray) -> np.ndarray:
        angles = self.fixed.copy()
        if self.free:
            angles[:, self.columns] = x[:, 3:] * self.scale
        return np.column_stack([x[:, :3], angles])

    def feasible(self, positions_ok: Any) -> Any:
        """``positions_ok`` on the positions, and every free pitch within the gimbal's range."""
        if not self.free:
            return positions_ok
        pitch_column = 3 + self.free.index("pitch") if "pitch" in self.free else None

        def ok(current: np.ndarray, candidates: np.ndarray) -> np.ndarray:
            mask: np.ndarray = np.ones(candidates.shape[0], dtype=bool)
            if pitch_column is not None and self.pitch_range is not None:
                pitch = candidates[:, :, pitch_column] * self.scale
                mask = np.asarray(((pitch >= self.pitch_range[0]) & (pitch <= self.pitch_range[1])).all(axis=1))
            if mask.any():
                mask[mask] = positions_ok(np.ascontiguousarray(current[:, :3]), np.ascontiguousarray(candidates[mask][:, :, :3]))
            return mask

        return ok


def _facing_start(spec: MissionSettings, approximation: Terrain, positions: np.ndarray, n_threads: int | None) -> np.ndarray:
    """Each camera turned to the nearest point of S' (a structure's start), its pitch within the
    gimbal's range (a mapping gimbal's, -90 to 0, without one)."""
    nearest = approximation.closest_point(positions, n_threads=n_threads)
    away = nearest - positions
    away[np.linalg.norm(away, axis=1) == 0.0] = (0.0, 0.0, -1.0)
    attitudes = facing_attitudes(away)
    low, high = spec.gimbal.pitch_range if spec.gimbal is not None and spec.gimbal.pitch_range is not None else (-90.0, 0.0)
    attitudes[:, 1] = np.clip(attitudes[:, 1], low, high)
    return attitudes


def _footprint_start(
    spec: MissionSettings, approximation: Terrain, flying: np.ndarray, attitudes: np.ndarray, n_threads: int | None
) -> tuple[np.ndarray, np.ndarray]:
    """The start lifted (and its free angles turned) so each camera's view of S' matches its cell."""
    sensors = spec.team_sensors()
    if sensors is None:
        raise InvalidInputError("footprint_start needs a sensor with a camera")
    constraints = spec.constraints
    lowest = max(constraints.h_min, 0.5)
    highest = constraints.h_max if constraints.h_max is not None else max(s.reach_m for s in sensors)
    fit = fit_footprints(
        approximation,
        flying,
        sensors,
        attitudes,
        heights=(lowest, max(lowest, highest)),
        gimbal=spec.gimbal,
        bounds=constraints.bounds,
        n_threads=n_threads,
    )
    return fit.positions, fit.attitudes
