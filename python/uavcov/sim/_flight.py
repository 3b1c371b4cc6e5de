"""A team of quadrotors flying legs between waypoints with RotorPy's dynamics and controller.

RotorPy (the ``uavcov[sim]`` extra, ``docs/realistic.md`` says why this simulator) provides
everything that flies: the vehicle's parameter set, its rigid-body dynamics with rotor drag and
motor lag (``Multirotor``), the SE(3) geometric controller (``SE3Control``), the minimum-snap
reference between two waypoints (``MinSnap``) and the constant wind (``ConstantWind``); the gusts
are :class:`~uavcov.sim.DrydenGusts` (``_wind.py`` says why not RotorPy's). This module only steps
them together for the team, stops a leg once every vehicle has settled, and records every state.
Without gusts nothing here is stochastic; with them the team's generator draws them: the same
waypoints and seed give the same flight, to the last bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validate import as_bool, as_finite_float, as_float_array, as_generator, as_positive_float, read_only, within_coordinate_bound
from ..engine import Terrain
from ..errors import FlightError, InvalidInputError, InvalidTypeError, MissingExtraError
from ._wind import DrydenGusts

__all__ = ["FlightSettings", "INTEGRATORS", "Leg", "Team", "VEHICLES", "hover_rotor_speed", "vehicle_parameters"]

VEHICLES = ("hummingbird",)
"""RotorPy parameter sets a team can fly: the AscTec Hummingbird (0.50 kg, 0.17 m arms), the
closest of RotorPy's sets to the paper's Parrot AR.Drone 2.0 (0.42 kg with the indoor hull,
about 0.18 m arms); ``docs/realistic.md`` compares them."""

INTEGRATORS = ("rk23", "rk45")
"""How each control period is integrated (:attr:`FlightSettings.integrator`); ``"rk45"`` is RotorPy's default."""

_GRAVITY = 9.81  # m/s^2, RotorPy's value
# A rest-to-rest leg's 7th-degree polynomial peaks at 35/16 of its average speed mid-leg; RotorPy's
# cap on the mid-leg speed must allow it, or its QP has no solution.
_PEAK_OVER_AVERAGE = 2.2
_PEAK_ACCELERATION = 7.5132  # the polynomial's peak acceleration in units of L / T^2


def _rotorpy() -> Any:
    """RotorPy's modules, or a clear error naming the extra."""
    try:
        from rotorpy.controllers.quadrotor_control import SE3Control
        from rotorpy.trajectories.hover_traj import HoverTraj
        from rotorpy.trajectories.minsnap import MinSnap
        from rotorpy.vehicles.hummingbird_params import quad_params
        from rotorpy.vehicles.multirotor import Multirotor
        from rotorpy.wind.default_winds import ConstantWind
    except ImportError as exc:
        raise MissingExtraError(f"flying a mission needs RotorPy: pip install 'uavcov[sim]' ({exc})") from exc
    return {
        "SE3Control": SE3Control,
        "HoverTraj": HoverTraj,
        "MinSnap": MinSnap,
        "Multirotor": Multirotor,
        "ConstantWind": ConstantWind,
        "params": {"hummingbird": quad_params},
    }


def vehicle_parameters(name: str) -> dict[str, Any]:
    """RotorPy's parameter dictionary of vehicle ``name`` (one of :data:`VEHICLES`)."""
    if not isinstance(name, str) or name not in VEHICLES:
        raise InvalidInputError(f"vehicle must be one of {VEHICLES}, got {name!r}")
    params: dict[str, Any] = _rotorpy()["params"][name]
    return params


def hover_rotor_speed(params: dict[str, Any]) -> float:
    """Rotor speed that holds the vehicle's weight, rad/s: ``sqrt(m g / (n k_eta))``."""
    if not isinstance(params, dict) or not {"mass", "num_rotors", "k_eta"} <= params.keys():
        raise InvalidInputError("params must be a vehicle's parameter dictionary (vehicle_parameters), with mass, num_rotors and k_eta")
    return math.sqrt(params["mass"] * _GRAVITY / (params["num_rotors"] * params["k_eta"]))


@dataclass(frozen=True)
class FlightSettings:
    """How the team flies between two configurations.

    Attributes
    ----------
    vehicle : str, default "hummingbird"
        RotorPy parameter set (:data:`VEHICLES`).
    speed : float, default 1.5
        Average speed of a leg's minimum-snap reference, m/s (RotorPy's time allocation: a leg
        of length ``L`` lasts ``L / speed``). A leg from rest to rest is one 7th-degree
        polynomial, whose peak speed is ``35/16 = 2.19`` times the average (3.3 m/s at 1.5 m/s).
    max_acceleration : float, default 2.0
        Most acceleration of the reference, m/s^2: a leg of length ``L`` averages at most
        ``sqrt(max_acceleration L / 7.51)`` (the polynomial's peak acceleration is ``7.51 L / T^2``).
        Short legs at full speed ask for accelerations the attitude loop cannot follow (the
        motors saturate at zero speed and the vehicle falls: measured at 11 m/s^2).
    dt : float, default 0.01
        Control period, seconds: the controller runs and the dynamics integrate (RotorPy's
        RK45) once per period.
    settle_position, settle_speed : float, default 0.1, 0.1
        A vehicle has settled at its waypoint within this distance (m) and below this speed (m/s).
    dwell_s : float, default 0.0
        Seconds every vehicle hovers after the whole team has settled, before the measurement.
    max_leg_s : float, default 30.0
        Seconds allowed beyond the reference's end for the team to settle; past them the leg
        fails (:class:`~uavcov.errors.FlightError`): a waypoint it cannot reach, wind beyond its
        thrust.
    wind : (float, float, float), default (0, 0, 0)
        Constant wind, m/s, world frame (RotorPy's ``ConstantWind``; its aerodynamic model turns
        it into drag on the frame and the rotors).
    collision_distance : float, default 0.02
        A state closer than this to the surface (3D distance, m) is a collision: the leg fails.
    gusts : (float, float, float), default (0, 0, 0)
        Standard deviation of Dryden gusts on top of ``wind``, m/s per axis (:class:`DrydenGusts`,
        one independent process per vehicle, drawn from the mission's ``rng``).
    integrator : {"rk23", "rk45"}, default "rk23"
        How RotorPy's ``Multirotor`` integrates each control period (its ``integrator_kwargs``,
        scipy's ``solve_ivp``): ``"rk45"`` is RotorPy's default (adaptive RK45 from scipy's
        initial step); ``"rk23"`` is adaptive RK23 at RotorPy's tolerances starting from one
        step of ``dt``, 1.7 times as fast, within 6e-5 m of ``"rk45"`` on a 3 m step and
        within 1e-4 m of a tight DOP853 reference (``benches/realistic_mission.py``, ``docs/realistic.md``).
    synchronous : bool, default False
        Every vehicle's leg lasts as long as the slowest one's (each slowed to it), so the team
        moves in step: each vehicle at the same fraction of its straight move at every instant
        (one rest-to-rest polynomial per leg, the same in normalised time), which is how
        ``Constraints(move_step=...)`` judges the moves. Without it each leg ends when its own
        length allows, and two vehicles whose straight moves keep ``d_safe`` in step can pass
        closer (docs/realistic.md). Legs under 0.1 m stay steps.
    """

    vehicle: str = "hummingbird"
    speed: float = 1.5
    max_acceleration: float = 2.0
    dt: float = 0.01
    settle_position: float = 0.1
    settle_speed: float = 0.1
    dwell_s: float = 0.0
    max_leg_s: float = 30.0
    wind: tuple[float, float, float] = (0.0, 0.0, 0.0)
    collision_distance: float = 0.02
    gusts: tuple[float, float, float] = (0.0, 0.0, 0.0)
    integrator: str = "rk23"
    synchronous: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.vehicle, str) or self.vehicle not in VEHICLES:
            raise InvalidInputError(f"vehicle must be one of {VEHICLES}, got {self.vehicle!r}")
        for name in ("speed", "max_acceleration", "dt", "settle_position", "settle_speed", "max_leg_s", "collision_distance"):
            object.__setattr__(self, name, as_positive_float(getattr(self, name), name))
        if self.speed > 20.0 or self.max_acceleration > 20.0:
            raise InvalidInputError(f"speed {self.speed} m/s, max_acceleration {self.max_acceleration} m/s^2: at most 20 each")
        if self.dt > 0.05:
            raise InvalidInputError(f"dt = {self.dt} s is too coarse for the attitude loop (at most 0.05 s)")
        if self.max_leg_s > 3600.0:
            raise InvalidInputError(f"max_leg_s = {self.max_leg_s} s: at most an hour per leg")
        dwell = as_finite_float(self.dwell_s, "dwell_s")
        if not 0.0 <= dwell <= 600.0:
            raise InvalidInputError(f"dwell_s must lie in [0, 600] s, got {dwell}")
        object.__setattr__(self, "dwell_s", dwell)
        wind = None if isinstance(self.wind, (str, bytes)) else as_float_array(self.wind, "wind")
        if wind is None or wind.shape != (3,) or not np.isfinite(wind).all() or np.abs(wind).max() > 100.0:
            raise InvalidInputError(f"wind must be 3 finite speeds of at most 100 m/s, got {self.wind!r}")
        object.__setattr__(self, "wind", (float(wind[0]), float(wind[1]), float(wind[2])))
        gusts = None if isinstance(self.gusts, (str, bytes)) else as_float_array(self.gusts, "gusts")
        if gusts is None or gusts.shape != (3,) or not np.isfinite(gusts).all() or gusts.min() < 0.0 or gusts.max() > 50.0:
            raise InvalidInputError(f"gusts must be 3 standard deviations in [0, 50] m/s, got {self.gusts!r}")
        object.__setattr__(self, "gusts", (float(gusts[0]), float(gusts[1]), float(gusts[2])))
        if not isinstance(self.integrator, str) or self.integrator not in INTEGRATORS:
            raise InvalidInputError(f"integrator must be one of {INTEGRATORS}, got {self.integrator!r}")
        object.__setattr__(self, "synchronous", as_bool(self.synchronous, "synchronous"))

    @property
    def integrator_kwargs(self) -> dict[str, Any] | None:
        """What RotorPy's ``Multirotor`` passes to scipy's ``solve_ivp`` (None: its default)."""
        return None if self.integrator == "rk45" else {"method": "RK23", "first_step": self.dt}


@dataclass(frozen=True)
class Leg:
    """Every state of one leg, at every control period (the leg's first state excluded).

    Attributes
    ----------
    time : (n,) ndarray
        Seconds since the leg began.
    positions, velocities : (n, N, 3) ndarray
        Metres, m/s.
    quaternions : (n, N, 4) ndarray
        Attitudes ``[x, y, z, w]`` (body to world).
    rotor_speeds : (n, N, 4) ndarray
        rad/s.
    power : (n, N) ndarray
        Rotor shaft power, W: ``sum k_m w^3`` (each rotor's drag torque ``k_m w^2`` times its speed).
    settled_s : float
        Seconds until every vehicle had settled (the leg then dwelt ``dwell_s`` more).
    """

    time: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    quaternions: np.ndarray
    rotor_speeds: np.ndarray
    power: np.ndarray
    settled_s: float

    @property
    def duration_s(self) -> float:
        """Seconds the leg lasted."""
        return float(self.time[-1]) if self.time.size else 0.0

    @property
    def energy_j(self) -> np.ndarray:
        """``(N,)`` rotor energy of each vehicle over the leg, joules."""
        dt = np.diff(np.concatenate([[0.0], self.time]))
        return np.asarray((self.power * dt[:, None]).sum(axis=0))

    @property
    def distance_m(self) -> np.ndarray:
        """``(N,)`` distance each vehicle flew over the leg, metres (its sampled path)."""
        if self.positions.shape[0] < 2:
            return np.zeros(self.positions.shape[1])
        return np.asarray(np.linalg.norm(np.diff(self.positions, axis=0), axis=2).sum(axis=0))


class _HeldAtEnd:
    """A reference whose flat output past its end is computed once: ``MinSnap.update`` clips the
    time to its last keyframe, so every later call returns the same values (bit for bit)."""

    def __init__(self, reference: Any, end: float) -> None:
        self.reference, self.end, self.held = reference, end, None

    def update(self, t: float) -> Any:
        if t < self.end:
            return self.reference.update(t)
        if self.held is None:
            self.held = self.reference.update(self.end)
        return self.held


_CHECK_EVERY = 100  # control periods between two checks of the team against the mesh (one Rust call)


@dataclass
class Team:
    """N vehicles at rest or in flight: their RotorPy models, controllers and current states.

    Create it hovering at ``positions`` (:meth:`hovering`), then :meth:`fly` it to each
    configuration in turn. Mutable (it is the simulation); what it flew is returned as
    frozen :class:`Leg` records.
    """

    settings: FlightSettings
    terrain: Terrain | None
    states: list[dict[str, np.ndarray]]
    _vehicle: Any = field(repr=False)
    _controller: Any = field(repr=False)
    _winds: list[Any] = field(repr=False)
    _params: dict[str, Any] = field(repr=False)

    @classmethod
    def hovering(cls, positions: Any, settings: FlightSettings, terrain: Terrain | None = None, *, rng: Any = None) -> Team:
        """A team hovering at ``positions`` ``(N, 3)`` (level, at rest, rotors at hover speed).

        ``rng`` (None, an int or a Generator, SPEC 7) draws the gusts, one independent stream per
        vehicle; without gusts nothing is drawn.
        """
        rp = _rotorpy()
        if not isinstance(settings, FlightSettings):
            raise InvalidTypeError(f"settings must be a FlightSettings, got {type(settings).__name__}")
        if terrain is not None and not isinstance(terrain, Terrain):
            raise InvalidTypeError(f"terrain must be a uavcov.Terrain or None, got {type(terrain).__name__}")
        generator = as_generator(rng)  # checked with or without gusts to draw
        params = vehicle_parameters(settings.vehicle)
        x0 = as_float_array(positions, "positions")
        if x0.ndim != 2 or x0.shape[1] != 3 or x0.shape[0] == 0:
            raise InvalidInputError(f"positions must have shape (N, 3) with N >= 1, got shape {x0.shape}")
        within_coordinate_bound(x0, "positions")  # the engine's bound: beyond, a step of the dynamics is lost in rounding
        hover = hover_rotor_speed(params)
        states = [
            {
                "x": p.copy(),
                "v": np.zeros(3),
                "q": np.array([0.0, 0.0, 0.0, 1.0]),
                "w": np.zeros(3),
                "wind": np.array(settings.wind),
                "rotor_speeds": np.full(params["num_rotors"], hover),
            }
            for p in x0
        ]
        vehicle = rp["Multirotor"](
            params,
            initial_state=states[0],
            control_abstraction="cmd_motor_speeds",
            aero=True,
            integrator_kwargs=settings.integrator_kwargs,
        )
        winds: list[Any]
        if any(settings.gusts):
            streams = generator.spawn(len(x0))
            winds = [DrydenGusts(settings.wind, settings.gusts, settings.dt, float(p[2]), g) for p, g in zip(x0, streams, strict=True)]
        else:
            winds = [rp["ConstantWind"](*settings.wind)] * len(x0)
        return cls(settings, terrain, states, vehicle, rp["SE3Control"](params), winds, params)

    @property
    def positions(self) -> np.ndarray:
        """``(N, 3)`` current positions, metres."""
        return np.array([s["x"] for s in self.states])

    def _references(self, waypoints: np.ndarray) -> tuple[list[Any], float]:
        """Each vehicle's reference to its waypoint, and the time the longest one ends."""
        rp = _rotorpy()
        references, end = [], 0.0
        lengths = [float(np.linalg.norm(goal - state["x"])) for state, goal in zip(self.states, waypoints, strict=True)]
        speeds = [min(self.settings.speed, math.sqrt(self.settings.max_acceleration * length / _PEAK_ACCELERATION)) for length in lengths]
        # In step: every leg lasts the slowest one's time (RotorPy allocates length / v_avg).
        longest = max((length / speed for length, speed in zip(lengths, speeds, strict=True) if length >= 0.1), default=0.0)
        for state, goal, length, own_speed in zip(self.states, waypoints, lengths, speeds, strict=True):
            if length < 0.1:  # MinSnap drops legs under 0.1 m: a step instead
                references.append(rp["HoverTraj"](x0=goal.copy()))
                continue
            speed = length / longest if self.settings.synchronous else own_speed
            ms = rp["MinSnap"](np.stack([state["x"], goal]), v_avg=speed, v_max=_PEAK_OVER_AVERAGE * speed, verbose=False)
            references.append(_HeldAtEnd(ms, float(ms.t_keyframes[-1])))
            end = max(end, float(ms.t_keyframes[-1]))
        return references, end

    def fly(self, waypoints: Any) -> Leg:
        """Fly every vehicle to its waypoint ``(N, 3)`` until the team settles, then dwell.

        Raises
        ------
        FlightError
            The team did not settle within ``max_leg_s`` after its references ended, a vehicle
            came within ``collision_distance`` of the surface, or the flight diverged; its
            ``leg`` attribute holds the states flown until then.
        """
        goals = as_float_array(waypoints, "waypoints")
        if goals.shape != (len(self.states), 3):
            raise InvalidInputError(f"waypoints must be finite, of shape ({len(self.states)}, 3), got {goals.shape}")
        within_coordinate_bound(goals, "waypoints")
        cfg = self.settings
        references, end = self._references(goals)
        deadline = end + cfg.max_leg_s
        times: list[float] = []
        rows: list[list[dict[str, np.ndarray]]] = []  # RotorPy returns a new state each step: kept as is
        t, settled_at, checked = 0.0, math.nan, 0
        while True:
            for k, ref in enumerate(references):
                state = self.states[k]
                state["wind"] = np.asarray(self._winds[k].update(t, state["x"]), dtype=np.float64)
                control = self._controller.update(t, state, ref.update(t))
                self.states[k] = self._vehicle.step(state, control, cfg.dt)
            t += cfg.dt
            times.append(t)
            rows.append(list(self.states))
            x = np.array([s["x"] for s in self.states])
            v = np.array([s["v"] for s in self.states])
            problem = self._problem(x, v, goals, t, deadline)
            done = False
            if problem is None:
                if math.isnan(settled_at) and t >= end and self._settled(x, v, goals):
                    settled_at = t
                done = not math.isnan(settled_at) and t >= settled_at + cfg.dwell_s - 1e-9
            if problem is not None or done or len(rows) - checked >= _CHECK_EVERY:
                hit = self._collision(rows, times, checked)
                checked = len(rows)
                if hit is not None:
                    problem, rows, times = hit[0], rows[: hit[1] + 1], times[: hit[1] + 1]
            if problem is not None:
                error = FlightError(problem)
                error.leg = self._leg(times, rows, math.nan)  # what flew, for the mission's record
                raise error
            if done:
                return self._leg(times, rows, settled_at)

    def _collision(self, rows: list[list[dict[str, np.ndarray]]], times: list[float], since: int) -> tuple[str, int] | None:
        """The first state since row ``since`` within ``collision_distance`` of the surface (one
        call for the whole stretch), as the reason and its row, or None."""
        if self.terrain is None or since >= len(rows):
            return None
        x = np.array([[s["x"] for s in row] for row in rows[since:]])
        gap = self.terrain.distance(x.reshape(-1, 3), n_threads=1).reshape(x.shape[:2])
        hits = np.flatnonzero((gap < self.settings.collision_distance).any(axis=1))
        if not hits.size:
            return None
        row = since + int(hits[0])
        k = int(np.argmin(gap[hits[0]]))
        where = np.round(x[hits[0], k], 2).tolist()
        return f"vehicle {k} hit the surface at t = {times[row]:.2f} s of the leg (at {where})", row

    def _problem(self, x: np.ndarray, v: np.ndarray, goals: np.ndarray, t: float, deadline: float) -> str | None:
        """Why the leg must stop now (diverged, out of time), or None; collisions are checked in
        stretches by :meth:`_collision`."""
        if not (np.isfinite(x).all() and np.isfinite(v).all()):
            return f"the flight diverged at t = {t:.2f} s of the leg (non-finite state)"
        if t > deadline:
            worst = float(np.linalg.norm(x - goals, axis=1).max())
            return (
                f"the team did not settle within {self.settings.max_leg_s:g} s after its references ended "
                f"(worst vehicle {worst:.2f} m from its waypoint; wind {self.settings.wind} m/s, "
                f"gusts {self.settings.gusts} m/s): waypoint out of reach"
            )
        return None

    def _leg(self, times: list[float], rows: list[list[dict[str, np.ndarray]]], settled_at: float) -> Leg:
        def stacked(key: str) -> np.ndarray:
            return read_only(np.array([[s[key] for s in row] for row in rows]))

        rotor_speeds = stacked("rotor_speeds")
        return Leg(
            time=read_only(np.array(times)),
            positions=stacked("x"),
            velocities=stacked("v"),
            quaternions=stacked("q"),
            rotor_speeds=rotor_speeds,
            power=read_only(self._params["k_m"] * (rotor_speeds**3).sum(axis=2)),
            settled_s=float(settled_at),
        )

    def _settled(self, x: np.ndarray, v: np.ndarray, goals: np.ndarray) -> bool:
        cfg = self.settings
        return bool(
            (np.linalg.norm(x - goals, axis=1) <= cfg.settle_position).all() and (np.linalg.norm(v, axis=1) <= cfg.settle_speed).all()
        )
