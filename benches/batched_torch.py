"""RotorPy's batched torch vehicle (``BatchedMultirotor``, fixed-step RK4, and ``BatchedSE3Control``)
against its numpy vehicle (``Multirotor`` + ``SE3Control``, uavcov's flight) on one core.

Each of B vehicles steps 1 m in x from hover (RotorPy's step-response experiment: a hover
reference at the goal) for 3 s at the 10 ms control period; reported side by side: the wall
time per vehicle and control period (median of ``--repeats``), the x real time of a 4-vehicle
team, and how far the torch vehicle's path lies from the numpy one's (RotorPy's default RK45).
Needs torch, torchdiffeq and roma (not uavcov extras: see benches/README.md for why).

    OMP_NUM_THREADS=1 python benches/batched_torch.py [--batches 4,64,512] [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import torch
from rotorpy.controllers.quadrotor_control import BatchedSE3Control, SE3Control
from rotorpy.trajectories.hover_traj import HoverTraj
from rotorpy.vehicles.hummingbird_params import quad_params
from rotorpy.vehicles.multirotor import BatchedMultirotor, BatchedMultirotorParams, Multirotor

from uavcov.sim import hover_rotor_speed

DT, SECONDS = 0.01, 3.0
GOAL = np.array([1.0, 0.0, 2.0])


def numpy_flight(integrator_kwargs: dict | None) -> tuple[np.ndarray, float]:
    """One vehicle, uavcov's loop: positions ``(n, 3)`` and seconds per control period."""
    hover = hover_rotor_speed(quad_params)
    state = {"x": np.array([0.0, 0.0, 2.0]), "v": np.zeros(3), "q": np.array([0.0, 0.0, 0.0, 1.0]), "w": np.zeros(3),
             "wind": np.zeros(3), "rotor_speeds": np.full(4, hover)}  # fmt: skip
    vehicle = Multirotor(quad_params, initial_state=state, integrator_kwargs=integrator_kwargs)
    controller, reference = SE3Control(quad_params), HoverTraj(x0=GOAL)
    n, rows, t = round(SECONDS / DT), [], 0.0
    began = time.perf_counter()
    for _ in range(n):
        state = vehicle.step(state, controller.update(t, state, reference.update(t)), DT)
        t += DT
        rows.append(state["x"].copy())
    return np.array(rows), (time.perf_counter() - began) / n


def torch_flight(batch: int) -> tuple[np.ndarray, float]:
    """``batch`` vehicles in one batched call per period: vehicle 0's positions and seconds per period."""
    device = torch.device("cpu")
    params = BatchedMultirotorParams([quad_params] * batch, batch, device)
    hover = hover_rotor_speed(quad_params)
    state = {
        "x": torch.tensor([[0.0, 0.0, 2.0]] * batch, dtype=torch.double),
        "v": torch.zeros(batch, 3, dtype=torch.double),
        "q": torch.tensor([[0.0, 0.0, 0.0, 1.0]] * batch, dtype=torch.double),
        "w": torch.zeros(batch, 3, dtype=torch.double),
        "wind": torch.zeros(batch, 3, dtype=torch.double),
        "rotor_speeds": torch.full((batch, 4), hover, dtype=torch.double),
    }
    vehicle = BatchedMultirotor(params, batch, state, device, integrator="rk4")
    controller = BatchedSE3Control(params, batch, device)
    zeros = torch.zeros(batch, 3, dtype=torch.double)
    flat = {"x": torch.tensor(np.tile(GOAL, (batch, 1))), "x_dot": zeros, "x_ddot": zeros, "x_dddot": zeros, "x_ddddot": zeros,
            "yaw": torch.zeros(batch, dtype=torch.double), "yaw_dot": torch.zeros(batch, dtype=torch.double),
            "yaw_ddot": torch.zeros(batch, dtype=torch.double)}  # fmt: skip
    n, rows, t = round(SECONDS / DT), [], 0.0
    began = time.perf_counter()
    with torch.no_grad():
        for _ in range(n):
            state = vehicle.step(state, controller.update(t, state, flat), DT)
            t += DT
            rows.append(state["x"][0].numpy().copy())
    return np.array(rows), (time.perf_counter() - began) / n


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--batches", default="4,64,512")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    torch.set_num_threads(1)
    reference, _ = numpy_flight(None)
    print(
        "| vehicle | batch | ms per period (median) | us per vehicle and period | x real time, 4 vehicles | path from RotorPy's RK45 (m) |"
    )
    print("|---|---|---|---|---|---|")
    for name, kwargs in (("numpy RK45 (RotorPy's default)", None), ("numpy RK23 (uavcov's default)", {"method": "RK23", "first_step": DT})):
        runs = [numpy_flight(kwargs) for _ in range(args.repeats)]
        per = statistics.median(r[1] for r in runs)
        print(f"| {name} | 1 | {per * 1e3:.3f} | {per * 1e6:.0f} | {DT / (4 * per):.2f} | {np.abs(runs[0][0] - reference).max():.1e} |")
    for batch in (int(b) for b in args.batches.split(",")):
        runs = [torch_flight(batch) for _ in range(args.repeats)]
        per = statistics.median(r[1] for r in runs)
        four = DT / per if batch >= 4 else float("nan")
        print(f"| torch RK4 (BatchedMultirotor) | {batch} | {per * 1e3:.3f} | {per / batch * 1e6:.0f} | {four:.2f} (the batch's time) "
              f"| {np.abs(runs[0][0] - reference).max():.1e} |")  # fmt: skip


if __name__ == "__main__":
    main()
