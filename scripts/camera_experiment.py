#!/usr/bin/env python
"""Does the CVT start keep its advantage with real cameras? A sweep over field of view and pitch.

The paper's terrains (``uavcov.paper.TABLE1.terrain``), N = 8 and 12, CVT and random starts, the
same scenarios for every sensor: the paper's omnidirectional sensor and three cameras (nadir
84 x 62 deg, nadir 60 x 45 deg, 45 deg oblique 60 x 45 deg, heading north), all with a 40 m range.
A camera sees a footprint only a few metres wide from the paper's 1-8 m band, so every sensor
flies the same camera envelope instead: 10-40 m above the ground, the start 20 m above S', CAO's
first step 5 m with A = 5 (``CAMERA_CAO``: ``uavcov.paper``'s step when the tables of
docs/cameras.md were made, kept so that they stay reproducible), 300 iterations. Nothing here
was tuned: the envelope is a round choice for a camera survey, made once, and the scenarios
are 0-9.

    python scripts/camera_experiment.py [--seeds 0-9] [--workers 2] [--starts fixed,footprint,gimbal]

``--starts`` picks the rules compared (each applied to the CVT and the random start alike):
``fixed``, every camera flown as set, 20 m above S'; ``footprint``, each start position lifted to
the height above S' whose view of S' best matches its Voronoi cell (``footprint_start``);
``heading``, the footprint start with the heading free, searched by the start and moved by CAO
beside the positions; ``gimbal``, the same with the pitch free too (-90 to -30 deg)
(``uavcov.Gimbal``: the angles' first CAO step ``--angle-step`` degrees, 10 by default).
Prints, per rule, sensor and N, the mean initial and best coverage of each start and the paired
CVT-over-random gain in best coverage with its 95 % interval (docs/cameras.md quotes the tables).
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import multiprocessing
from collections import defaultdict
from dataclasses import replace

import numpy as np

import uavcov
from uavcov import paper
from uavcov.experiments import Experiment, RunSpec

SENSORS: dict[str, tuple[uavcov.Sensor, tuple[float, float]]] = {
    "omnidirectional": (uavcov.Sensor(40.0), (0.0, -90.0)),
    "nadir 84 x 62 deg": (uavcov.Sensor(40.0, camera=uavcov.Camera.from_fov(84.0, 62.0)), (0.0, -90.0)),
    "nadir 60 x 45 deg": (uavcov.Sensor(40.0, camera=uavcov.Camera.from_fov(60.0, 45.0)), (0.0, -90.0)),
    "45 deg oblique, 60 x 45 deg": (uavcov.Sensor(40.0, camera=uavcov.Camera.from_fov(60.0, 45.0)), (0.0, -45.0)),
}


RULES: dict[str, dict[str, object]] = {
    "fixed": {},
    "footprint": {"footprint_start": True},
    "heading": {"footprint_start": True, "gimbal": uavcov.Gimbal(free_yaw=True)},
    "gimbal": {"footprint_start": True, "gimbal": uavcov.Gimbal(free_yaw=True, pitch_range=(-90.0, -30.0))},
}


CAMERA_CAO = paper.TABLE1.with_changes(**paper.ABLATIONS_BY_NAME["plateau-step"].changes).mission.cao
"""CAO's constants of this experiment: Table 1's with the plateau step (first step 5 m, A = 5)."""


def _rules(alpha0_deg: float) -> dict[str, dict[str, object]]:
    """:data:`RULES` with every gimbal's first angle step set to ``alpha0_deg``."""
    return {
        name: {k: replace(v, alpha0_deg=alpha0_deg) if isinstance(v, uavcov.Gimbal) else v for k, v in rule.items()}
        for name, rule in RULES.items()
    }


def experiment(
    sensor: uavcov.Sensor, attitude: tuple[float, float], iterations: int, rule: str = "fixed", alpha0_deg: float = 10.0
) -> Experiment:
    """The camera envelope on Table 1's terrains, for one sensor and start rule."""
    changes = _rules(alpha0_deg)[rule] if sensor.camera is not None else {}
    mission = replace(
        paper.TABLE1.mission,
        d_max=40.0,
        start=replace(paper.TABLE1.mission.start, altitude=20.0),
        constraints=replace(paper.TABLE1.mission.constraints, h_min=10.0, h_max=40.0),
        cao=CAMERA_CAO,
        sensor=sensor,
        attitude=attitude,
        iterations=iterations,
        **changes,  # type: ignore[arg-type]
    )
    return replace(paper.TABLE1, name="cameras", mission=mission, team_sizes=(8, 12), starts=("cvt", "random"))


def run_one(
    rule: str, name: str, seed: int, n: int, start: str, iterations: int, alpha0_deg: float
) -> tuple[tuple[str, str, int, str], int, float, float]:
    sensor, attitude = SENSORS[name]
    result = RunSpec(experiment(sensor, attitude, iterations, rule, alpha0_deg), seed, n, start).run(n_threads=1)
    return (rule, name, n, start), seed, result.initial_coverage, result.best_coverage


def _seeds(text: str) -> list[int]:
    a, _, b = text.partition("-")
    return list(range(int(a), int(b or a) + 1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", default="0-9")
    parser.add_argument("--iterations", type=int, default=300)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--starts", default="fixed", help="comma-separated start rules: " + ", ".join(RULES))
    parser.add_argument(
        "--angle-step", dest="alpha0_deg", type=float, default=10.0, help="the angles' first CAO step, degrees (uavcov.Gimbal.alpha0_deg)"
    )
    args = parser.parse_args()
    rules = args.starts.split(",")
    unknown = sorted(set(rules) - set(RULES))
    if unknown:
        parser.error(f"unknown start rule(s) {unknown}; the rules are {list(RULES)}")
    jobs = [
        (rule, name, seed, n, start)
        for rule in rules
        for name in SENSORS
        if rule == "fixed" or SENSORS[name][0].camera is not None
        for seed in _seeds(args.seeds)
        for n in (8, 12)
        for start in ("cvt", "random")
    ]
    initial: dict[tuple[str, str, int, str], dict[int, float]] = defaultdict(dict)
    best: dict[tuple[str, str, int, str], dict[int, float]] = defaultdict(dict)
    context = multiprocessing.get_context("spawn")
    with cf.ProcessPoolExecutor(args.workers, mp_context=context) as pool:
        futures = [pool.submit(run_one, *job, args.iterations, args.alpha0_deg) for job in jobs]
        for future in cf.as_completed(futures):
            key, seed, first, top = future.result()
            initial[key][seed], best[key][seed] = first, top
    print(f"seeds {args.seeds}, {args.iterations} iterations, 10-40 m above the ground, 40 m range, angle step {args.alpha0_deg:g} deg")
    for rule in rules:
        print(f"\nstart rule: {rule}\n")
        print("| sensor | N | CVT initial / max | random initial / max | CVT over random, max (95 % interval of the paired difference) |")
        print("|---|---|---|---|---|")
        for name in SENSORS:
            if (rule, name, 8, "cvt") not in best:
                continue
            for n in (8, 12):
                cvt, rnd = best[(rule, name, n, "cvt")], best[(rule, name, n, "random")]
                seeds = sorted(set(cvt) & set(rnd))
                a, b = np.array([cvt[s] for s in seeds]), np.array([rnd[s] for s in seeds])
                a0 = np.mean([initial[(rule, name, n, "cvt")][s] for s in seeds])
                b0 = np.mean([initial[(rule, name, n, "random")][s] for s in seeds])
                diff = a - b
                half = 1.96 * diff.std(ddof=1) / np.sqrt(diff.size) if diff.size > 1 else float("nan")
                gain = 100 * (a.mean() / b.mean() - 1)
                rel = 100 * half / b.mean()
                print(
                    f"| {name} | {n} | {a0:.3f} / {a.mean():.3f} | {b0:.3f} / {b.mean():.3f} "
                    f"| {gain:+.1f} % [{gain - rel:+.1f}, {gain + rel:+.1f}] |"
                )


if __name__ == "__main__":
    main()
