"""uavcov.sim's flight (RotorPy, the ``sim`` extra): its dynamics as RotorPy's own, the closed loop,
safety against an independent distance, determinism, failures that end cleanly."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

pytest.importorskip("rotorpy")

from rotorpy.controllers.quadrotor_control import SE3Control
from rotorpy.trajectories.minsnap import MinSnap
from rotorpy.vehicles.hummingbird_params import quad_params
from rotorpy.vehicles.multirotor import Multirotor

import uavcov
from reference import closest_point_on_mesh, ground_height_mesh
from uavcov.errors import FlightError, InvalidInputError, InvalidTypeError
from uavcov.paper import BUILDINGS
from uavcov.sim import FlightSettings, SimSettings, Team, fly_mission, hover_rotor_speed


def test_hover_holds_still_at_rotorpy_hover_speed() -> None:
    team = Team.hovering([[1.0, 2.0, 3.0]], FlightSettings(dwell_s=2.0))
    leg = team.fly([[1.0, 2.0, 3.0]])
    assert np.abs(leg.positions - [1.0, 2.0, 3.0]).max() < 1e-6
    hover = math.sqrt(quad_params["mass"] * 9.81 / (4 * quad_params["k_eta"]))
    assert hover_rotor_speed(quad_params) == pytest.approx(hover)
    assert np.abs(leg.rotor_speeds - hover).max() < 0.5  # rad/s
    # Rotor power at hover: 4 k_m w^3.
    assert leg.power[-1, 0] == pytest.approx(4 * quad_params["k_m"] * hover**3, rel=1e-3)
    assert leg.duration_s == pytest.approx(2.0 + 0.01, abs=0.011)


def _rotorpy_step(start: np.ndarray, goal: np.ndarray, n: int, integrator_kwargs: dict | None) -> np.ndarray:
    """RotorPy's own loop (its example's: SE3Control on a MinSnap reference), ``n`` control periods."""
    hover = hover_rotor_speed(quad_params)
    state = {
        "x": start.copy(),
        "v": np.zeros(3),
        "q": np.array([0.0, 0.0, 0.0, 1.0]),
        "w": np.zeros(3),
        "wind": np.zeros(3),
        "rotor_speeds": np.full(4, hover),
    }
    vehicle = Multirotor(quad_params, initial_state=state, integrator_kwargs=integrator_kwargs)
    controller = SE3Control(quad_params)
    reference = MinSnap(np.stack([start, goal]), v_avg=1.0, v_max=2.2, verbose=False)
    t, rows = 0.0, []
    for _ in range(n):
        state = vehicle.step(state, controller.update(t, state, reference.update(t)), 0.01)
        t += 0.01
        rows.append(np.concatenate([state["x"], state["rotor_speeds"]]))
    return np.array(rows)


@pytest.mark.parametrize("integrator", ["rk23", "rk45"])
def test_a_step_to_a_waypoint_is_rotorpys_own_flight(integrator: str) -> None:
    """The team's leg is, state for state and bit for bit, RotorPy's own loop with the same
    integrator settings."""
    start, goal = np.array([0.0, 0.0, 2.0]), np.array([3.0, -1.0, 2.5])
    settings = FlightSettings(speed=1.0, max_acceleration=5.0, integrator=integrator)
    leg = Team.hovering([start], settings).fly([goal])
    own = _rotorpy_step(start, goal, len(leg.time), settings.integrator_kwargs)
    assert np.array_equal(own[:, :3], leg.positions[:, 0])
    assert np.array_equal(own[:, 3:], leg.rotor_speeds[:, 0])
    assert np.linalg.norm(leg.positions[-1, 0] - goal) <= settings.settle_position
    assert leg.settled_s >= float(np.linalg.norm(goal - start))  # no earlier than the reference ends


def test_the_default_integrator_flies_rotorpys_default_configuration() -> None:
    """The default (RK23 from one step of dt) against RotorPy's default Multirotor (adaptive RK45)
    and a tight DOP853 reference: the 3 m step and the hover after it within 1e-4 m, rotor speeds
    within 2 rad/s (0.4 % of hover). docs/realistic.md states the measured differences."""
    start, goal = np.array([0.0, 0.0, 2.0]), np.array([3.0, -1.0, 2.5])
    fast = _rotorpy_step(start, goal, 600, FlightSettings().integrator_kwargs)
    default = _rotorpy_step(start, goal, 600, None)
    tight = _rotorpy_step(start, goal, 600, {"method": "DOP853", "rtol": 1e-10, "atol": 1e-12})
    assert np.abs(fast[:, :3] - default[:, :3]).max() < 1e-4
    assert np.abs(fast[:, :3] - tight[:, :3]).max() < 1e-4
    assert np.abs(fast[:, 3:] - default[:, 3:]).max() < 2.0
    assert np.abs(fast[-100:, :3] - goal).max() < 1e-3  # the hover after the step holds the waypoint
    assert np.abs(fast[:, :3] - default[:, :3]).max() > 0.0  # a different integrator, not the same one


def _scene(seed: int = 1000) -> tuple[uavcov.Terrain, uavcov.Terrain]:
    return BUILDINGS.terrain.make(seed), BUILDINGS.known(seed)


def test_a_flown_mission_keeps_the_limits_against_an_independent_distance_and_repeats() -> None:
    terrain, known = _scene()
    spec = BUILDINGS.mission_settings(4, "cvt").with_changes(iterations=4)
    flown = fly_mission(terrain, spec, SimSettings(), known=known, rng=1000)
    assert flown.failure is None and flown.exact.shape == (5,)
    states = flown.states.reshape(-1, 3)
    vertices, faces = np.asarray(terrain.vertices), np.asarray(terrain.faces)
    distance, _ = closest_point_on_mesh(states, vertices, faces)  # brute force over every triangle
    assert flown.safety is not None and flown.safety.violations == 0
    assert flown.safety.min_distance == pytest.approx(distance.min(), abs=1e-6)
    assert distance.min() > 0.0
    below = states[:, 2] - ground_height_mesh(states[:, :2], vertices, faces, below=states[:, 2])
    assert below.min() >= spec.constraints.h_min
    assert flown.safety.min_clearance == pytest.approx(below.min(), abs=1e-6)
    again = fly_mission(terrain, spec, SimSettings(), known=known, rng=1000)
    assert np.array_equal(flown.states, again.states) and np.array_equal(flown.exact, again.exact)
    assert np.array_equal(flown.sensed, again.sensed)
    copy = pickle.loads(pickle.dumps(flown))
    assert np.array_equal(copy.states, flown.states) and copy.safety == flown.safety
    # The start and CAO's first waypoints are the kinematic mission's: the same streams.
    kinematic = uavcov.run_mission(terrain, spec, known=known, n_threads=1, rng=1000)
    assert np.array_equal(flown.start, kinematic.trajectory[0])
    assert flown.energy_j.min() > 0 and np.all(flown.distance_m > 0)


def test_settled_flight_measures_what_the_kinematic_mission_measures() -> None:
    """Settled within 1 cm, each measurement is the kinematic one at the commanded waypoints to
    within 0.02 (coverage is discontinuous: 1 cm can flip a target on an edge). The best coverage
    of whole missions is compared in docs/realistic.md: CAO's paths part once one value differs."""
    terrain, known = _scene()
    spec = BUILDINGS.mission_settings(4, "pairs").with_changes(iterations=4)
    tight = SimSettings(flight=FlightSettings(settle_position=0.01, settle_speed=0.01), render=False)
    flown = fly_mission(terrain, spec, tight, known=known, rng=1000)
    assert np.abs(flown.reached - flown.commanded).max() <= 0.011
    vis = uavcov.Visibility(terrain, spec.d_max, n_threads=1)
    at_waypoints = np.array([vis.coverage(x) for x in flown.commanded])
    assert np.abs(flown.exact - at_waypoints).max() <= 0.02
    kinematic = uavcov.run_mission(terrain, spec, known=known, n_threads=1, rng=1000)
    assert flown.exact[0] == pytest.approx(kinematic.coverage[0], abs=0.02)  # the same start


def test_wind_beyond_thrust_is_a_recorded_failure_not_a_hang() -> None:
    terrain, known = _scene()
    spec = BUILDINGS.mission_settings(4, "cvt").with_changes(iterations=3)
    gale = SimSettings(flight=FlightSettings(wind=(40.0, 0.0, 0.0), max_leg_s=2.0), render=False)
    flown = fly_mission(terrain, spec, gale, known=known, rng=1000)
    assert flown.failure is not None and ("settle" in flown.failure or "hit" in flown.failure)
    assert flown.states.shape[0] > 0 and flown.safety is not None  # what flew is kept


def test_a_waypoint_inside_a_building_is_a_clear_error() -> None:
    terrain, _ = _scene()
    roof = terrain.vertices[np.argmax(terrain.vertices[:, 2])]
    above = roof + [0.0, 0.0, 2.0]
    team = Team.hovering([above], FlightSettings(max_leg_s=3.0), terrain)
    with pytest.raises(FlightError, match="hit the surface") as caught:
        team.fly([roof - [0.0, 0.0, 1.5]])  # inside the building under its roof
    assert caught.value.leg.positions.shape[1] == 1  # the states flown until the hit


@pytest.mark.parametrize(
    "changes",
    [
        {"speed": 0.0},
        {"speed": float("nan")},
        {"speed": 1e300},
        {"dt": 0.5},
        {"wind": (1.0, 2.0)},
        {"wind": (1e3, 0, 0)},
        {"vehicle": "ardrone"},
        {"dwell_s": -1.0},
        {"max_leg_s": 1e9},
        {"gusts": (-1.0, 0.0, 0.0)},
        {"gusts": (float("nan"), 0.0, 0.0)},
        {"gusts": (1e300, 0.0, 0.0)},
        {"gusts": "strong"},
        {"integrator": "euler"},
    ],
)
def test_flight_settings_refuse_hostile_values(changes: dict[str, object]) -> None:
    with pytest.raises(InvalidInputError):
        FlightSettings(**changes)  # type: ignore[arg-type]


def test_fly_mission_refuses_what_it_cannot_fly() -> None:
    terrain, known = _scene()
    spec = BUILDINGS.mission_settings(4, "cvt").with_changes(iterations=1)
    with pytest.raises(InvalidInputError):
        fly_mission(terrain, spec.with_changes(optimizer="per_robot"), SimSettings(), known=known, rng=0)
    with pytest.raises(InvalidTypeError):
        fly_mission(terrain, spec, "fast", known=known, rng=0)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError):
        SimSettings(measurement="guessed")
    with pytest.raises(InvalidInputError):
        SimSettings(measurement="sensed", render=False)
    with pytest.raises(InvalidInputError):
        Team.hovering([[0.0, 0.0, np.nan]], FlightSettings())
    team = Team.hovering([[0.0, 0.0, 5.0]], FlightSettings())
    with pytest.raises(InvalidInputError):
        team.fly([[0.0, 0.0, 5.0], [1.0, 1.0, 5.0]])


def test_cao_can_maximise_the_sensed_coverage() -> None:
    terrain, known = _scene()
    spec = BUILDINGS.mission_settings(4, "cvt").with_changes(iterations=2)
    flown = fly_mission(terrain, spec, SimSettings(measurement="sensed"), known=known, rng=1000)
    assert flown.failure is None and np.isfinite(flown.sensed).all()
    assert np.array_equal(flown.measured, flown.sensed)
    assert np.abs(flown.sensed - flown.exact).max() < 0.1  # 64 x 128 pixels: within a few hundredths
    assert len(flown.map_points) > 1000


def test_synchronous_legs_move_the_team_in_step() -> None:
    """Legs of 1 m and 4 m: in step, each vehicle is at the same fraction of its move at every
    instant (within the tracking error over the short move's length), as Constraints(move_step=)
    judges the moves; without it the short leg ends first."""
    start = np.array([[0.0, 0.0, 5.0], [0.0, 5.0, 5.0]])
    goal = start + [[1.0, 0.0, 0.0], [4.0, 0.0, 0.0]]

    def fractions(settings: FlightSettings) -> np.ndarray:
        leg = Team.hovering(start, settings).fly(goal)
        return np.asarray((leg.positions[..., 0] - start[:, 0]) / (goal[:, 0] - start[:, 0]))

    in_step = fractions(FlightSettings(synchronous=True))
    apart = fractions(FlightSettings())
    assert np.abs(in_step[:, 0] - in_step[:, 1]).max() < 0.05  # 5 cm on the 1 m leg
    assert np.abs(apart[:, 0] - apart[:, 1]).max() > 0.2
    with pytest.raises(InvalidTypeError):
        FlightSettings(synchronous="yes")  # type: ignore[arg-type]
