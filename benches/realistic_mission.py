"""A flown 4-UAV mission on the buildings scene: simulated seconds per wall second, one core.

Flies :data:`uavcov.experiments.BUILDINGS`' CVT mission (seed 1000, a development scene) with
:func:`uavcov.sim.fly_mission` once per integrator (``FlightSettings.integrator``: ``rk45`` is
RotorPy's default configuration, ``rk23`` uavcov's default), the integrators interleaved over
``--repeats`` rounds so that both see the same load, and reports the medians: the mission's
flight time, its wall time and their ratio (the issue's target: 20x real time), where the wall
time goes (RotorPy's dynamics ``Multirotor.step`` and controller ``SE3Control.update``, timed by
wrapping them, and the rest: CAO, the references, the depth images, the fusion, the exact
coverage), the speed-up over the first integrator, and how far the flown states part from the
first integrator's (metres, the whole mission).

    RAYON_NUM_THREADS=1 python benches/realistic_mission.py [--iterations 200] [--integrators rk45,rk23] [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import time
from typing import Any

import numpy as np
from rotorpy.controllers.quadrotor_control import SE3Control
from rotorpy.vehicles.multirotor import Multirotor

from uavcov.paper import BUILDINGS
from uavcov.sim import FlightSettings, FlownMission, SimSettings, fly_mission

_SPENT = {"dynamics": 0.0, "controller": 0.0}


def _timed(cls: Any, name: str, bucket: str) -> None:
    original = getattr(cls, name)

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        began = time.perf_counter()
        try:
            return original(*args, **kwargs)
        finally:
            _SPENT[bucket] += time.perf_counter() - began

    setattr(cls, name, wrapper)


def _fly(integrator: str, iterations: int, seed: int) -> tuple[FlownMission, dict[str, float]]:
    terrain, known = BUILDINGS.terrain.make(seed), BUILDINGS.known(seed)
    spec = BUILDINGS.mission_settings(4, "cvt").with_changes(iterations=iterations)
    _SPENT.update(dynamics=0.0, controller=0.0)
    began = time.perf_counter()
    flown = fly_mission(terrain, spec, SimSettings(flight=FlightSettings(integrator=integrator)), known=known, rng=seed)
    wall = time.perf_counter() - began
    return flown, {"wall": wall, "dynamics": _SPENT["dynamics"], "controller": _SPENT["controller"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=200)
    parser.add_argument("--integrators", default="rk45,rk23", help="FlightSettings.integrator values, comma separated")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seed", type=int, default=1000)
    args = parser.parse_args()
    _timed(Multirotor, "step", "dynamics")
    _timed(SE3Control, "update", "controller")
    integrators = args.integrators.split(",")
    times: dict[str, list[dict[str, float]]] = {name: [] for name in integrators}
    flown: dict[str, FlownMission] = {}
    for _ in range(args.repeats):
        for name in integrators:
            flown[name], spent = _fly(name, args.iterations, args.seed)
            times[name].append(spent)
    print(
        "| integrator | iterations | flight time (s) | wall (s, median) | x real time | dynamics (s) | controller (s) "
        "| rest (s) | speed-up | best coverage | states apart from the first (m) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    first = integrators[0]
    base_wall = statistics.median(r["wall"] for r in times[first])
    for name in integrators:
        run = flown[name]
        med = {key: statistics.median(r[key] for r in times[name]) for key in ("wall", "dynamics", "controller")}
        common = min(len(run.states), len(flown[first].states))
        apart = float(np.abs(run.states[:common] - flown[first].states[:common]).max()) if common else float("nan")
        print(
            f"| {name} | {len(run.exact) - 1} | {run.flight_time_s:.1f} | {med['wall']:.1f} | {run.flight_time_s / med['wall']:.2f} | "
            f"{med['dynamics']:.1f} | {med['controller']:.1f} | {med['wall'] - med['dynamics'] - med['controller']:.1f} | "
            f"{base_wall / med['wall']:.2f} | {run.best_coverage:.3f} | {apart:.2g} |"
        )


if __name__ == "__main__":
    main()
