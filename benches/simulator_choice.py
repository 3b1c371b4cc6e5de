"""The candidate simulators side by side: a 5 s hover, a 1 m step in x, and their speed.

Each candidate flies with its own position controller: RotorPy's ``SE3Control`` on a
``HoverTraj`` at 100 Hz (with each of scipy's integrators RotorPy can use), PyFlyt's ``Aviary``
in mode 7 (position control) at its 120 Hz; one vehicle, then four for PyFlyt. A candidate that
is not installed is skipped. Run each in its own venv (``pip install --only-binary=:all: X``).

    python benches/simulator_choice.py
"""

from __future__ import annotations

import importlib.util
import time

import numpy as np


def rotorpy_case(method: str) -> None:
    from rotorpy.controllers.quadrotor_control import SE3Control
    from rotorpy.trajectories.hover_traj import HoverTraj
    from rotorpy.vehicles.hummingbird_params import quad_params
    from rotorpy.vehicles.multirotor import Multirotor

    hover = np.sqrt(quad_params["mass"] * 9.81 / 4 / quad_params["k_eta"])
    start = {
        "x": np.zeros(3),
        "v": np.zeros(3),
        "q": np.array([0, 0, 0, 1.0]),
        "w": np.zeros(3),
        "wind": np.zeros(3),
        "rotor_speeds": np.full(4, hover),
    }
    vehicle = Multirotor(quad_params, initial_state=start, integrator_kwargs={"method": method})
    controller = SE3Control(quad_params)

    def fly(goal: np.ndarray, seconds: float = 5.0, dt: float = 0.01) -> tuple[np.ndarray, float]:
        state, reference, path = {k: v.copy() for k, v in start.items()}, HoverTraj(goal), []
        began = time.perf_counter()
        for k in range(round(seconds / dt)):
            state = vehicle.step(state, controller.update(k * dt, state, reference.update(k * dt)), dt)
            path.append(state["x"].copy())
        return np.array(path), seconds / (time.perf_counter() - began)

    path, speed = fly(np.zeros(3))
    print(f"rotorpy {method}: hover drift {np.abs(path).max():.2g} m, {speed:.2f} sim s / wall s")
    path, speed = fly(np.array([1.0, 0.0, 0.0]))
    t90 = 0.01 * (np.argmax(path[:, 0] > 0.9) + 1)
    error = np.abs(path[-1] - [1, 0, 0]).max()
    print(f"rotorpy {method}: step max {path[:, 0].max():.4f} m, final error {error:.2g} m, t90 {t90:.2f} s, {speed:.2f} sim s / wall s")


def pyflyt_case() -> None:
    from PyFlyt.core import Aviary

    def run(env: Aviary, steps: int) -> tuple[np.ndarray, float]:
        path, began = [], time.perf_counter()
        for _ in range(steps):
            env.step()
            path.append(env.state(0)[3].copy())
        return np.array(path), steps / 120.0 / (time.perf_counter() - began)

    env = Aviary(start_pos=np.array([[0.0, 0.0, 1.0]]), start_orn=np.zeros((1, 3)), render=False, drone_type="quadx")
    env.set_mode(7)
    env.set_setpoint(0, np.array([0.0, 0.0, 0.0, 1.0]))
    run(env, 120)  # numba compiles on the first steps
    path, speed = run(env, 600)
    print(f"pyflyt: hover drift {np.abs(path - [0, 0, 1]).max():.2g} m, {speed:.2f} sim s / wall s")
    env.set_setpoint(0, np.array([1.0, 0.0, 0.0, 1.0]))
    path, speed = run(env, 600)
    t90 = (np.argmax(path[:, 0] > 0.9) + 1) / 120.0
    print(f"pyflyt: step max {path[:, 0].max():.4f} m, final {np.round(path[-1], 3).tolist()}, t90 {t90:.2f} s, {speed:.2f} sim s / wall s")
    four = Aviary(
        start_pos=np.array([[0, 0, 1.0], [2, 0, 1], [0, 2, 1], [2, 2, 1]]), start_orn=np.zeros((4, 3)), render=False, drone_type="quadx"
    )
    four.set_mode(7)
    _, speed = run(four, 600)
    print(f"pyflyt: four vehicles {speed:.2f} sim s / wall s")


if __name__ == "__main__":
    if importlib.util.find_spec("rotorpy"):
        for integrator in ("RK45", "RK23", "LSODA"):
            rotorpy_case(integrator)
    if importlib.util.find_spec("PyFlyt"):
        pyflyt_case()
