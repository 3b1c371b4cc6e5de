"""The paper's mission flown: CAO's next configuration is each vehicle's waypoint, and the
measurement is taken where the vehicles actually are.

:func:`fly_mission` runs the mission's off-line part with :func:`uavcov.mission.run_mission`
(the prior, the start on S', the admissible start: the same streams as the kinematic mission),
then CAO (:func:`uavcov.optim.cao`, untouched) with a measurement that wraps the flight: each
configuration CAO asks for is flown by the team (:class:`~uavcov.sim.Team`) until it settles,
and the coverage is measured at the states reached (exactly, or from the fused depth images).
CAO's ``trajectory`` is then the commanded waypoints; the flown states are the record's.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .._validate import as_bool, as_finite_float, as_generator, as_positive_float, read_only
from ..engine import Terrain, Visibility
from ..errors import FlightError, InvalidInputError, InvalidTypeError
from ..limits import Constraints, feasibility
from ..mission import MissionSettings, run_mission
from ..optim import cao
from ._depth import DepthCamera, camera_rotation
from ._flight import FlightSettings, Leg, Team
from ._safety import SafetyReport, check_flight
from ._voxels import VoxelMap, sensed_coverage

__all__ = ["SimSettings", "FlownMission", "fly_mission", "MEASUREMENTS"]

MEASUREMENTS = ("exact", "sensed")
"""What CAO maximises in a flown mission: the exact coverage at the reached states, or the share of
targets observed in that configuration's depth images."""


@dataclass(frozen=True)
class SimSettings:
    """How a mission is flown and sensed.

    Attributes
    ----------
    flight : FlightSettings
        Vehicles, speeds, settling, dwell, wind.
    measurement : {"exact", "sensed"}, default "exact"
        CAO's measurement (:data:`MEASUREMENTS`); the other is recorded beside it when a camera
        renders.
    camera : DepthCamera or None, default None
        Every vehicle's depth camera. ``None``: the paper's omnidirectional sensor of the
        mission's ``d_max`` at 64 x 128 pixels; ``render=False`` renders nothing.
    render : bool, default True
        Whether the cameras render (needed by ``measurement="sensed"``, the fused map and the gap).
    observe_radius : float, optional
        A target counts as sensed when a depth point lies this close, metres; ``None`` (the
        default) is the camera's pixel width at full range (:attr:`DepthCamera.footprint_m`),
        with which the sensed coverage tends to the exact one as the resolution rises.
    voxel_size : float, default 0.25
        The fused map's voxels, metres.
    limits_margin : float, default 0.0
        Metres between the limits the mission plans with (its ``constraints``, which CAO keeps
        at every waypoint, and along every move with ``move_step``) and the flight limits the
        flown states are judged against (:func:`check_flight`): ``h_min`` and ``d_safe`` lower
        by it, ``h_max`` and ``z_max`` higher, the x-y bounds wider. A flown path strays from its straight move by a
        few centimetres (the report's max deviation): planning that far inside the limits is
        what keeps every state within them.
    """

    flight: FlightSettings = field(default_factory=FlightSettings)
    measurement: str = "exact"
    camera: DepthCamera | None = None
    render: bool = True
    observe_radius: float | None = None
    voxel_size: float = 0.25
    limits_margin: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.flight, FlightSettings):
            raise InvalidTypeError(f"flight must be a FlightSettings, got {type(self.flight).__name__}")
        if not isinstance(self.measurement, str) or self.measurement not in MEASUREMENTS:
            raise InvalidInputError(f"measurement must be one of {MEASUREMENTS}, got {self.measurement!r}")
        if self.camera is not None and not isinstance(self.camera, DepthCamera):
            raise InvalidTypeError(f"camera must be a DepthCamera or None, got {type(self.camera).__name__}")
        object.__setattr__(self, "render", as_bool(self.render, "render"))
        if self.measurement == "sensed" and not self.render:
            raise InvalidInputError("the sensed measurement needs the cameras to render (render=True)")
        if self.observe_radius is not None:
            object.__setattr__(self, "observe_radius", as_positive_float(self.observe_radius, "observe_radius"))
        object.__setattr__(self, "voxel_size", as_positive_float(self.voxel_size, "voxel_size"))
        margin = as_finite_float(self.limits_margin, "limits_margin")
        if not 0.0 <= margin <= 1.0:
            raise InvalidInputError(f"limits_margin must lie in [0, 1] m, got {margin}")
        object.__setattr__(self, "limits_margin", margin)

    def flight_limits(self, planned: Constraints) -> Constraints:
        """The limits the flown states are judged against: ``planned`` widened by ``limits_margin``."""
        if not isinstance(planned, Constraints):
            raise InvalidTypeError(f"planned must be a Constraints, got {type(planned).__name__}")
        m = self.limits_margin
        if m == 0.0:
            return planned
        box = planned.bounds
        return replace(
            planned,
            bounds=None if box is None else (box[0] - m, box[1] - m, box[2] + m, box[3] + m),
            h_min=max(planned.h_min - m, 0.0),
            d_safe=max(planned.d_safe - m, 0.0),
            h_max=None if planned.h_max is None else planned.h_max + m,
            z_max=planned.z_max + m,
        )

    def camera_for(self, d_max: float) -> DepthCamera:
        """The camera every vehicle carries (the default: the omnidirectional one of range ``d_max``)."""
        return self.camera if self.camera is not None else DepthCamera.omnidirectional(d_max, resolution=64)


@dataclass(frozen=True)
class FlownMission:
    """What one flown mission did. Frozen and picklable. Times in seconds, distances in metres.

    Attributes
    ----------
    settings : MissionSettings
        The mission (constraints resolved).
    sim : SimSettings
    seed : int or None
    start : (N, 3) ndarray
        The admissible start the team hovers at before the first measurement.
    commanded : (K + 1, N, 3) ndarray
        The configurations CAO asked for (its waypoints), one per measurement.
    reached : (K + 1, N, 3) ndarray
        Where the vehicles were when each measurement was taken.
    exact : (K + 1,) ndarray
        Exact coverage of the true surface at the reached states.
    sensed : (K + 1,) ndarray
        Share of targets observed in that configuration's depth images (NaN without rendering).
    clock : (K + 1,) ndarray
        Mission time of each measurement, seconds since the first.
    states_time : (M,) ndarray
        Mission time of every recorded state.
    states : (M, N, 3) ndarray
        Every recorded position (each control period).
    leg_ends_s : (L,) ndarray
        Mission time at the end of each leg flown (leg ``k`` ends at measurement ``k``; a failed
        last leg has none).
    distance_m, energy_j : (N,) ndarray
        Each vehicle's distance flown and rotor energy (joules) over the mission.
    leg_energy_j : (L, N) ndarray
        Each vehicle's rotor energy over each leg (leg ``k`` ends at measurement ``k``), joules.
    safety : SafetyReport or None
        Every state against the limits (None when nothing flew).
    map_points : (V, 3) ndarray
        The team's fused map: one point per occupied voxel.
    failure : str or None
        Why the mission stopped early (a :class:`~uavcov.errors.FlightError`), else None.
    wall_time_s : float
        Seconds the whole run took.
    """

    settings: MissionSettings
    sim: SimSettings
    seed: int | None
    start: np.ndarray
    commanded: np.ndarray
    reached: np.ndarray
    exact: np.ndarray
    sensed: np.ndarray
    clock: np.ndarray
    states_time: np.ndarray
    states: np.ndarray
    leg_ends_s: np.ndarray
    distance_m: np.ndarray
    energy_j: np.ndarray
    leg_energy_j: np.ndarray
    safety: SafetyReport | None
    map_points: np.ndarray
    failure: str | None
    wall_time_s: float

    @property
    def measured(self) -> np.ndarray:
        """What CAO saw at each measurement (``exact`` or ``sensed``)."""
        return self.exact if self.sim.measurement == "exact" else self.sensed

    @property
    def best_coverage(self) -> float:
        """Highest exact coverage at a reached configuration."""
        return float(self.exact.max()) if self.exact.size else math.nan

    @property
    def flight_time_s(self) -> float:
        """Mission time at the last measurement, seconds."""
        return float(self.clock[-1]) if self.clock.size else 0.0

    def time_to_fraction(self, fraction: float = 0.95) -> float:
        """Mission seconds until the exact coverage first reaches ``fraction`` (in [0, 1]) of its best."""
        fraction = as_finite_float(fraction, "fraction")
        if not 0.0 <= fraction <= 1.0:  # above 1 no measurement reaches it: argmax would answer the start
            raise InvalidInputError(f"fraction must be in [0, 1], got {fraction}")
        if not self.exact.size:
            return math.nan
        return float(self.clock[int(np.argmax(self.exact >= fraction * self.exact.max()))])


class _FlownMeasure:
    """The measurement CAO calls: fly to ``x``, sense where the team is, answer the chosen value."""

    def __init__(
        self, team: Team, vis: Visibility, terrain: Terrain, sim: SimSettings, camera: DepthCamera, rng: np.random.Generator
    ) -> None:
        self.team, self.vis, self.terrain, self.sim, self.camera, self.rng = team, vis, terrain, sim, camera, rng
        self.map = VoxelMap(sim.voxel_size)
        self.legs: list[Leg] = []
        self.starts: list[np.ndarray] = []
        self.goals: list[np.ndarray] = []
        self.reached: list[np.ndarray] = []
        self.exact: list[float] = []
        self.sensed: list[float] = []

    def _sense(self) -> float:
        points = [
            self.camera.render(self.terrain, s["x"], camera_rotation(s["q"], self.camera), rng=self.rng, n_threads=1)[1]
            for s in self.team.states
        ]
        cloud = np.concatenate(points) if points else np.empty((0, 3))
        self.map.add(cloud)
        radius = self.sim.observe_radius if self.sim.observe_radius is not None else self.camera.footprint_m
        return sensed_coverage(self.vis.targets, cloud, radius)

    def __call__(self, x: np.ndarray) -> float:
        goals = np.array(x[:, :3], dtype=np.float64)
        self.starts.append(self.team.positions)
        self.goals.append(goals)
        try:
            leg = self.team.fly(goals)
        except FlightError as exc:
            if isinstance(exc.leg, Leg):
                self.legs.append(exc.leg)
            raise
        self.legs.append(leg)
        reached = self.team.positions
        self.reached.append(reached)
        self.exact.append(float(self.vis.coverage(reached)))
        self.sensed.append(self._sense() if self.sim.render else math.nan)
        return self.exact[-1] if self.sim.measurement == "exact" else self.sensed[-1]


def _optimizer_stream(seq: np.random.SeedSequence, first_child: int, bit_generator: Any) -> np.random.Generator:
    """The stream :func:`run_mission` gives its optimiser (the third of the three children it spawns)."""
    child = np.random.SeedSequence(seq.entropy, spawn_key=(*seq.spawn_key, first_child + 2), pool_size=seq.pool_size)
    return np.random.Generator(type(bit_generator)(child))


def fly_mission(
    terrain: Terrain,
    settings: MissionSettings,
    sim: SimSettings = SimSettings(),
    *,
    known: Any = None,
    start_positions: Any = None,
    rng: Any = None,
) -> FlownMission:
    """Fly the paper's mission on ``terrain``: RotorPy's vehicles in the loop of CAO.

    Parameters
    ----------
    terrain : Terrain
        The true surface.
    settings : MissionSettings
        The mission: the centralised optimiser ``"cao"``, the paper's omnidirectional sensor.
    sim : SimSettings
        How it is flown and sensed.
    known, start_positions
        As :func:`uavcov.mission.run_mission`'s.
    rng : None, int or numpy.random.Generator
        Seeds the prior, the start and the optimiser exactly as ``run_mission(..., rng=rng)``
        does (so a flown mission and its kinematic twin share them), then the depth noise and
        the gusts (:attr:`FlightSettings.gusts`): the same seed flies the same states twice.

    Returns
    -------
    FlownMission
        A :class:`~uavcov.errors.FlightError` during the flight (a waypoint out of reach, wind
        beyond the vehicles' thrust, a collision) ends the mission: the record holds what flew
        and says why in ``failure``.
    """
    started = time.perf_counter()
    if not isinstance(settings, MissionSettings):
        raise InvalidTypeError(f"settings must be a MissionSettings, got {type(settings).__name__}")
    if not isinstance(sim, SimSettings):
        raise InvalidTypeError(f"sim must be a SimSettings, got {type(sim).__name__}")
    if settings.optimizer != "cao" or settings.sensor is not None or settings.gimbal is not None or settings.objective != "coverage":
        raise InvalidInputError(
            "a flown mission runs centralised CAO on the coverage of the paper's sensor (optimizer='cao', no sensor or gimbal)"
        )
    generator = as_generator(rng)
    seq = generator.bit_generator.seed_seq
    if not isinstance(seq, np.random.SeedSequence):
        raise InvalidTypeError("rng must be None, an int, a SeedSequence or a Generator seeded by a SeedSequence")
    first_child = seq.n_children_spawned
    offline = run_mission(
        terrain, settings.with_changes(iterations=0), known=known, start_positions=start_positions, n_threads=1, rng=generator
    )
    optimizer_rng = _optimizer_stream(seq, first_child, generator.bit_generator)
    noise_rng, wind_rng = generator.spawn(2)  # the depth noise's stream is spawn(1)'s: unchanged by the gusts
    spec = offline.settings
    x0 = np.array(offline.trajectory[0])
    vis = Visibility(terrain, spec.d_max, n_threads=1)
    team = Team.hovering(x0, sim.flight, terrain, rng=wind_rng)
    measure = _FlownMeasure(team, vis, terrain, sim, sim.camera_for(spec.d_max), noise_rng)
    failure = None
    try:
        cao(
            measure,
            x0,
            feasible=feasibility(spec.constraints, terrain, n_threads=1),
            iterations=settings.iterations,
            settings=spec.cao,
            rng=optimizer_rng,
        )
    except FlightError as exc:
        failure = str(exc)
    return _record(replace(spec, iterations=settings.iterations), sim, rng, x0, measure, terrain, started, failure)


def _record(
    spec: MissionSettings,
    sim: SimSettings,
    rng: Any,
    x0: np.ndarray,
    measure: _FlownMeasure,
    terrain: Terrain,
    started: float,
    failure: str | None,
) -> FlownMission:
    legs, n = measure.legs, spec.n_uavs
    n_done = len(measure.exact)  # legs whose measurement was taken (a failed leg has none)
    ends = np.cumsum([leg.duration_s for leg in legs])
    clock = ends[:n_done] - ends[0] if n_done else np.empty(0)
    starts_of_legs = np.concatenate([[0.0], ends[:-1]])
    states = np.concatenate([leg.positions for leg in legs]) if legs else np.empty((0, n, 3))
    states_time = np.concatenate([leg.time + t0 for leg, t0 in zip(legs, starts_of_legs, strict=True)]) if legs else np.empty(0)
    leg_of_state = np.concatenate([np.full(leg.time.size, k) for k, leg in enumerate(legs)]) if legs else np.empty(0, int)
    safety = (
        check_flight(terrain, sim.flight_limits(spec.constraints), states, leg_of_state, np.array(measure.starts), np.array(measure.goals))
        if len(states)
        else None
    )

    def stack(rows: list[np.ndarray]) -> np.ndarray:
        return read_only(np.array(rows).reshape(-1, n, 3))

    return FlownMission(
        settings=spec,
        sim=sim,
        seed=int(rng) if isinstance(rng, (int, np.integer)) and not isinstance(rng, bool) else None,
        start=read_only(x0),
        commanded=stack(measure.goals[:n_done]),
        reached=stack(measure.reached),
        exact=read_only(np.array(measure.exact)),
        sensed=read_only(np.array(measure.sensed)),
        clock=read_only(clock),
        states_time=read_only(states_time),
        states=read_only(states),
        leg_ends_s=read_only(np.asarray(ends, dtype=np.float64)),
        distance_m=read_only(np.sum([leg.distance_m for leg in legs], axis=0) if legs else np.zeros(n)),
        energy_j=read_only(np.sum([leg.energy_j for leg in legs], axis=0) if legs else np.zeros(n)),
        leg_energy_j=read_only(np.array([leg.energy_j for leg in legs]).reshape(-1, n)),
        safety=safety,
        map_points=read_only(measure.map.points if len(measure.map) else np.empty((0, 3))),
        failure=failure,
        wall_time_s=time.perf_counter() - started,
    )
