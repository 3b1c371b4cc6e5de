"""A flown 4-UAV mission on the buildings scene: simulated seconds per wall second, one core.

Flies :data:`uavcov.experiments.BUILDINGS`' CVT mission (seed 1000, a development scene) with
:func:`uavcov.sim.fly_mission` and reports the mission's flight time, its wall time and their
ratio (the issue's target: 20x real time), then where the wall time goes: RotorPy's dynamics
(``Multirotor.step``) and controller (``SE3Control.update``), timed by wrapping them, and the
rest (CAO, the depth images, the fusion, the exact coverage). With ``--dt`` several control
periods run side by side in one process (the lever RotorPy offers without its torch backend).

    RAYON_NUM_THREADS=1 python benches/realistic_mission.py [--iterations 200] [--dt 0.01,0.02]
"""

from __future__ import annotations

import argparse
import time
from typing import Any

from rotorpy.controllers.quadrotor_control import SE3Control
from rotorpy.vehicles.multirotor import Multirotor

from uavcov.paper import BUILDINGS
from uavcov.sim import FlightSettings, SimSettings, fly_mission

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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=200)
    parser.add_argument("--dt", default="0.01", help="control periods, seconds, comma separated")
    parser.add_argument("--seed", type=int, default=1000)
    args = parser.parse_args()
    _timed(Multirotor, "step", "dynamics")
    _timed(SE3Control, "update", "controller")
    terrain = BUILDINGS.terrain.make(args.seed)
    known = BUILDINGS.known(args.seed)
    spec = BUILDINGS.mission_settings(4, "cvt").with_changes(iterations=args.iterations)
    print("| dt (s) | iterations | flight time (s) | wall (s) | x real time | dynamics (s) | controller (s) | rest (s) | best coverage |")
    print("|---|---|---|---|---|---|---|---|---|")
    for dt in (float(v) for v in args.dt.split(",")):
        _SPENT.update(dynamics=0.0, controller=0.0)
        began = time.perf_counter()
        flown = fly_mission(terrain, spec, SimSettings(flight=FlightSettings(dt=dt)), known=known, rng=args.seed)
        wall = time.perf_counter() - began
        rest = wall - _SPENT["dynamics"] - _SPENT["controller"]
        print(
            f"| {dt:g} | {len(flown.exact) - 1} | {flown.flight_time_s:.1f} | {wall:.1f} | {flown.flight_time_s / wall:.2f} | "
            f"{_SPENT['dynamics']:.1f} | {_SPENT['controller']:.1f} | {rest:.1f} | {flown.best_coverage:.3f} |"
        )


if __name__ == "__main__":
    main()
