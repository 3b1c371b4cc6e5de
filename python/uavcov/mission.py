"""The paper's two-step mission: an off-line start from the prior, then on-line CAO.

:func:`run_mission` takes the true surface, what is known of it beforehand (the prior), the team
and its sensor, and runs

1. the start: the constrained CVT of the approximating surface S' (or a random or corner start,
   the paper's baselines), lifted to flying height and moved to the closest admissible positions
   above the real surface (the UAVs sense the ground, paper section V-B);
2. the optimiser (CAO, centralised or per robot) on the real surface, which it sees only through
   coverage measurements and the constraint checks.

It returns a :class:`MissionResult`: a frozen, picklable record of everything that happened.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ._validate import as_generator, as_non_negative_float, as_non_negative_int, as_points, as_positive_float, as_positive_int
from .cao import CAOSettings, OptimizerTrace, cao, per_robot_cao
from .constraints import Constraints, closest_admissible, feasibility
from .cvt import CVTResult, cvt
from .errors import InvalidInputError, InvalidTypeError
from .prior import Prior, approximate_surface, sample_prior
from .starts import START_KINDS, initial_positions
from .surface import Terrain
from .targets import Targets
from .visibility import Visibility

__all__ = ["MissionSettings", "MissionResult", "run_mission", "iterations_to_fraction"]

OPTIMIZERS = ("cao", "per_robot")


@dataclass(frozen=True)
class MissionSettings:
    """Every setting of one mission, resolved (what :func:`run_mission` actually used).

    Attributes
    ----------
    n_uavs : int
        Team size ``N``.
    d_max : float
        Sensing range, metres.
    start : {"cvt", "random", "corner", "given"}
        How the team starts ("given": positions passed by the caller).
    optimizer : {"cao", "per_robot"}
        Centralised CAO or one estimator per UAV.
    iterations : int
        Optimiser iterations (measurements minus one).
    start_altitude : float
        Height of the start above the real ground, metres, before the closest admissible
        position is taken.
    h_min, z_max, d_safe : float
        The constraints of eq. 2, metres (see :class:`uavcov.constraints.Constraints`).
    check_moves : bool
        Whether moves must not cross the surface (scenes with buildings).
    cao : CAOSettings
        The optimiser's constants.
    prior_kind : str
        How the prior was obtained ("random", "pyramid", "points", "surface", ...).
    n_prior : int
        Number of known points (0 when an approximating surface was given).
    seed : int or None
        The integer seed, when ``rng`` was one.
    """

    n_uavs: int
    d_max: float
    start: str
    optimizer: str
    iterations: int
    start_altitude: float
    h_min: float
    z_max: float
    d_safe: float
    check_moves: bool
    cao: CAOSettings
    prior_kind: str
    n_prior: int
    seed: int | None = None

    def as_dict(self) -> dict[str, Any]:
        """Plain ``dict`` (nested settings included), ready for JSON."""
        return asdict(self)


@dataclass(frozen=True, eq=False)
class MissionResult:
    """What one mission did. Frozen and picklable.

    Attributes
    ----------
    settings : MissionSettings
    terrain : Terrain
        The true surface.
    prior_points : (n, 3) ndarray
        The known points (empty when S' was given directly).
    approximation : Terrain
        S', the surface the start was computed on.
    start_positions : (N, 3) ndarray
        The start as computed on S' (CVT generators, random or corner lattice), metres.
    cvt : CVTResult or None
        The CVT run, for the "cvt" start.
    trajectory : (K + 1, N, 3) ndarray
        Positions at every iteration; ``trajectory[0]`` is the admissible start.
    coverage : (K + 1,) ndarray
        True coverage at every iteration, in [0, 1].
    best_positions : (N, 3) ndarray
        The configuration with the highest coverage.
    best_coverage, initial_coverage, final_coverage : float
    best_iteration : int
    iterations_to_95 : int
        First iteration whose coverage reaches 95 % of ``best_coverage``.
    evaluations : int
        Coverage measurements made by the optimiser.
    wall_time_s : float
        Seconds for the whole mission (prior, start, optimisation).
    time_measure_s, time_optimizer_s : float
        Seconds in coverage measurements and in the optimiser's own work.
    trace : OptimizerTrace
        The optimiser's full record.
    """

    settings: MissionSettings
    terrain: Terrain
    prior_points: np.ndarray
    approximation: Terrain
    start_positions: np.ndarray
    cvt: CVTResult | None
    trajectory: np.ndarray
    coverage: np.ndarray
    best_positions: np.ndarray
    best_coverage: float
    initial_coverage: float
    final_coverage: float
    best_iteration: int
    iterations_to_95: int
    evaluations: int
    wall_time_s: float
    time_measure_s: float
    time_optimizer_s: float
    trace: OptimizerTrace = field(repr=False)

    @property
    def initial_positions(self) -> np.ndarray:
        """``(N, 3)`` admissible start the optimiser began from."""
        return self.trajectory[0]

    @property
    def final_positions(self) -> np.ndarray:
        """``(N, 3)`` positions after the last iteration."""
        return self.trajectory[-1]


def iterations_to_fraction(values: np.ndarray, fraction: float = 0.95) -> int:
    """First index at which ``values`` reaches ``fraction`` of its maximum."""
    values = np.asarray(values, dtype=float)
    return int(np.argmax(values >= fraction * values.max()))


def _seed_of(rng: Any) -> int | None:
    return int(rng) if isinstance(rng, (int, np.integer)) and not isinstance(rng, bool) else None


def _approximation(terrain: Terrain, prior: Any, n_prior: int, rng: np.random.Generator) -> tuple[Terrain, np.ndarray, str]:
    """S', the known points behind it, and how they were chosen."""
    if isinstance(prior, Terrain):
        return prior, np.empty((0, 3)), "surface"
    if isinstance(prior, Prior):
        known = prior
    elif isinstance(prior, str) and prior in ("random", "pyramid"):
        known = sample_prior(terrain, n_prior, kind=prior, rng=rng)
    elif isinstance(prior, str):
        raise InvalidInputError(f"prior must be 'random', 'pyramid', a Prior, points or a Terrain, got {prior!r}")
    else:
        known = sample_prior(terrain, kind="points", points=prior, rng=rng)
    return approximate_surface(known), np.array(known.points), known.kind


def run_mission(
    terrain: Terrain,
    *,
    n_uavs: int,
    d_max: float,
    prior: Any = "random",
    n_prior: int = 30,
    start: Any = "cvt",
    optimizer: str = "cao",
    iterations: int = 500,
    settings: CAOSettings | None = None,
    start_altitude: float = 5.0,
    climb: float = 0.0,
    h_min: float = 2.0,
    z_max: float = 50.0,
    d_safe: float = 2.0,
    check_moves: bool | None = None,
    targets: Targets | None = None,
    cvt_options: dict[str, Any] | None = None,
    n_threads: int | None = None,
    rng: Any = None,
) -> MissionResult:
    """Run the paper's two-step mission on a true surface.

    Parameters
    ----------
    terrain : Terrain
        The true surface S. The optimiser sees it only through coverage measurements and the
        constraint checks (clearance below each UAV, and moves crossing no surface).
    n_uavs : int
        Team size ``N`` (> 0).
    d_max : float
        Sensing range, metres (> 0).
    prior : "random", "pyramid", Prior, (n, 2 or 3) array_like, or Terrain
        What is known beforehand: ``n_prior`` random points plus the 4 corners, the paper's
        pyramid (4 corners and the centre), a :class:`~uavcov.prior.Prior`, known positions or
        points, or an approximating surface S' given directly (e.g. a buildings map).
    n_prior : int, default 30
        Random known points for ``prior="random"``.
    start : {"cvt", "random", "corner"} or (N, 3) array_like, default "cvt"
        The start: constrained CVT on S', uniform over the region, a compact lattice in one
        corner, or positions of your own (metres, used as given: no ``start_altitude`` lift).
        Every start is moved to the closest admissible positions before the optimiser begins.
    optimizer : {"cao", "per_robot"}, default "cao"
    iterations : int, default 500
    settings : CAOSettings, optional
        The optimiser's constants (defaults: :class:`~uavcov.cao.CAOSettings`).
    start_altitude : float, default 5.0
        The start flies this high above the real ground (metres) before it is moved to the
        closest admissible positions.
    climb : float, default 0.0
        Metres above ``h_min`` at which a start UAV that had to be lifted is put (see
        :func:`uavcov.constraints.closest_admissible`).
    h_min, z_max, d_safe : float
        Least clearance above the real surface, highest altitude, least UAV-UAV distance, metres.
    check_moves : bool, optional
        Refuse moves that cross the surface. Default: on for general meshes (buildings), off for
        elevation grids, where an admissible-to-admissible move cannot cross the ground within
        one step of a few metres.
    targets : Targets, optional
        Coverage targets; the true terrain's default targets by default.
    cvt_options : dict, optional
        Keyword arguments for :func:`uavcov.cvt.cvt` (the "cvt" start), e.g. ``{"preset": "lloyd"}``.
    n_threads : int, optional
        Threads for each coverage measurement; all cores by default.
    rng : None, int or numpy.random.Generator
        Source of every random draw (prior, start, optimiser); the same seed gives the same run.

    Returns
    -------
    MissionResult
    """
    started = time.perf_counter()
    if not isinstance(terrain, Terrain):
        raise InvalidTypeError(f"terrain must be a uavcov.Terrain, got {type(terrain).__name__}")
    n_uavs = as_positive_int(n_uavs, "n_uavs")
    d_max = as_positive_float(d_max, "d_max")
    iterations = as_non_negative_int(iterations, "iterations")
    n_prior = as_non_negative_int(n_prior, "n_prior")
    start_altitude = as_non_negative_float(start_altitude, "start_altitude")
    given_start = None
    if not isinstance(start, str):
        given_start = as_points(start, "start")
        if given_start.shape[0] != n_uavs:
            raise InvalidInputError(f"start has {given_start.shape[0]} positions for {n_uavs} UAVs")
        start = "given"
    elif start not in START_KINDS:
        raise InvalidInputError(f"start must be one of {START_KINDS} or an (N, 3) array, got {start!r}")
    if optimizer not in OPTIMIZERS:
        raise InvalidInputError(f"optimizer must be one of {OPTIMIZERS}, got {optimizer!r}")
    settings = CAOSettings() if settings is None else settings
    if not isinstance(settings, CAOSettings):
        raise InvalidTypeError(f"settings must be a CAOSettings, got {type(settings).__name__}")
    if check_moves is None:
        check_moves = terrain.grid is None
    constraints = Constraints.for_world(terrain, h_min=h_min, z_max=z_max, d_safe=d_safe, check_moves=check_moves)
    constraints.check_team(n_uavs, terrain)
    vis = Visibility(terrain, d_max, targets, n_threads=n_threads)

    generator = as_generator(rng)
    prior_rng, start_rng, optimizer_rng = generator.spawn(3)
    approximation, prior_points, prior_kind = _approximation(terrain, prior, n_prior, prior_rng)
    cvt_result: CVTResult | None = None
    if given_start is not None:
        start_positions = given_start
    elif start == "cvt":
        # Called directly rather than through initial_positions, to keep the whole CVT run.
        cvt_result = cvt(approximation, n_uavs, rng=start_rng, n_threads=n_threads, **dict(cvt_options or {}))
        start_positions = np.array(cvt_result.generators)
    else:
        start_positions = initial_positions(start, approximation, n_uavs, rng=start_rng, n_threads=n_threads)
    flying = start_positions.copy()
    if given_start is None:
        ground = terrain.ground_height(flying[:, :2])
        # Over a nodata hole of the real surface there is no ground to measure from: keep S' height.
        flying[:, 2] = np.where(np.isnan(ground), flying[:, 2], ground) + start_altitude
    x0 = closest_admissible(constraints, terrain, flying, climb=climb)

    feasible = feasibility(constraints, terrain)
    if optimizer == "cao":
        trace = cao(vis.coverage, x0, feasible=feasible, iterations=iterations, settings=settings, rng=optimizer_rng)
    else:

        def measure(x: np.ndarray) -> tuple[float, np.ndarray]:
            counts = vis.per_uav(x)  # the coverage and the marginals in one pass
            return counts.coverage, counts.exclusive_share

        trace = per_robot_cao(measure, x0, feasible=feasible, iterations=iterations, settings=settings, rng=optimizer_rng)

    values = np.asarray(trace.values, dtype=float)
    resolved = MissionSettings(
        n_uavs=n_uavs,
        d_max=d_max,
        start=start,
        optimizer=optimizer,
        iterations=iterations,
        start_altitude=start_altitude,
        h_min=constraints.h_min,
        z_max=constraints.z_max,
        d_safe=constraints.d_safe,
        check_moves=constraints.check_moves,
        cao=trace.settings,
        prior_kind=prior_kind,
        n_prior=int(prior_points.shape[0]),
        seed=_seed_of(rng),
    )
    return MissionResult(
        settings=resolved,
        terrain=terrain,
        prior_points=prior_points,
        approximation=approximation,
        start_positions=start_positions,
        cvt=cvt_result,
        trajectory=trace.trajectory,
        coverage=values,
        best_positions=trace.best_positions,
        best_coverage=float(trace.best_value),
        initial_coverage=float(values[0]),
        final_coverage=float(values[-1]),
        best_iteration=int(trace.best_iteration),
        iterations_to_95=iterations_to_fraction(values, 0.95),
        evaluations=int(trace.evaluations),
        wall_time_s=time.perf_counter() - started,
        time_measure_s=float(trace.time_measure),
        time_optimizer_s=float(trace.time_own),
        trace=trace,
    )
