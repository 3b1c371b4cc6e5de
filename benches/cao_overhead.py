"""How much time CAO itself takes per iteration, beside the coverage measurement.

Two runs per team size N (5, 12, 20):

* "own work": a free measure (a quadratic) and no constraints, so the trace's ``time_optimizer_s``
  divided by the iterations is the optimiser's own cost: the ridge fit on the window and the
  surrogate over the M candidates (one matrix product), the candidate draw and the bookkeeping.
* "paper terrain": the real thing on a paper-like terrain (100 m x 100 m Gaussian hills, 1 m
  targets, d_max = 25 m, default constraints), split into coverage measurement, feasibility
  (clearance of the M x N candidate points on the real surface) and own work.

Run: ``python benches/cao_overhead.py [--iterations 200] [--repeats 3]``.
Prints one line per (N, optimiser, case) with milliseconds per iteration (median over repeats).
"""

from __future__ import annotations

import argparse
import functools
import statistics
import time

import numpy as np

from uavcov.optim import CAOSettings, cao, per_robot_cao


def own_work(n_uavs: int, optimizer: str, iterations: int, seed: int) -> dict[str, float]:
    target = np.random.default_rng(seed).uniform(0.0, 100.0, size=(n_uavs, 3))
    x0 = target + 10.0
    if optimizer == "cao":
        trace = cao(lambda x: -float(np.sum((x - target) ** 2)), x0, feasible=None, iterations=iterations, rng=seed)
    else:

        def measure(x):
            parts = -np.sum((x - target) ** 2, axis=1)
            return float(parts.sum()), parts

        trace = per_robot_cao(measure, x0, feasible=None, iterations=iterations, rng=seed)
    return {"own": trace.time_optimizer_s, "measure": trace.time_measure_s, "feasible": trace.time_feasibility_s}


def paper_terrain(n_uavs: int, optimizer: str, iterations: int, seed: int, world: dict) -> dict[str, float]:
    from uavcov.limits import closest_admissible, feasibility

    terrain, vis, constraints = world["terrain"], world["vis"], world["constraints"]
    rng = np.random.default_rng(seed)
    xy = rng.uniform(5.0, 95.0, size=(n_uavs, 2))
    start = closest_admissible(constraints, terrain, np.column_stack([xy, np.full(n_uavs, -1.0)]))
    start[:, 2] += 3.0
    feasible = feasibility(constraints, terrain)
    if optimizer == "cao":
        trace = cao(vis.coverage, start, feasible=feasible, iterations=iterations, rng=seed)
    else:

        def measure(x):
            return vis.coverage(x), vis.per_uav(x).exclusive_share

        trace = per_robot_cao(measure, start, feasible=feasible, iterations=iterations, rng=seed)
    return {"own": trace.time_optimizer_s, "measure": trace.time_measure_s, "feasible": trace.time_feasibility_s}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--no-terrain", action="store_true", help="skip the paper-terrain runs")
    args = parser.parse_args()

    world = None
    if not args.no_terrain:
        from uavcov import Constraints, Visibility, gaussian_hills

        terrain = gaussian_hills(size=100.0, spacing=1.0, rng=1000)
        world = {
            "terrain": terrain,
            "vis": Visibility(terrain, 25.0),
            "constraints": Constraints.for_world(terrain, h_min=2.0, z_max=50.0, d_safe=2.0),
        }

    s = CAOSettings()
    print(
        f"M = {s.n_candidates} candidates, T_h = {s.history}, {args.iterations} iterations, median of {args.repeats} runs; ms per iteration"
    )
    print(f"{'N':>3} {'optimiser':>10} {'case':>14} {'L':>4} {'own':>8} {'measure':>8} {'feasible':>9}")
    for n_uavs in (5, 12, 20):
        for optimizer in ("cao", "per_robot"):
            # partial binds this iteration's n_uavs and optimizer; each case is called with a seed
            cases = [("own work", functools.partial(own_work, n_uavs, optimizer, args.iterations))]
            if world is not None:
                cases.append(("paper terrain", functools.partial(paper_terrain, n_uavs, optimizer, args.iterations, world=world)))
            for name, run in cases:
                results = [run(seed) for seed in range(args.repeats)]
                med = {key: statistics.median(r[key] for r in results) * 1e3 / args.iterations for key in results[0]}
                n_reg = s.regressors_for(n_uavs) if optimizer == "cao" else s.robot_regressors_value()
                print(
                    f"{n_uavs:>3} {optimizer:>10} {name:>14} {n_reg:>4} {med['own']:>8.3f} {med['measure']:>8.3f} {med['feasible']:>9.3f}"
                )


if __name__ == "__main__":
    start = time.perf_counter()
    main()
    print(f"total {time.perf_counter() - start:.1f} s")
