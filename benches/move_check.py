"""What checking every move against the ground costs on an elevation grid.

The paper's Table 1 mission (``uavcov.paper.TABLE1``: 7 Gaussian hills, 1 m targets, d_max =
25 m, 500 CAO iterations, CVT start) run twice per seed, with ``constraints.check_moves`` on (the
paper's model: robot-obstacle avoidance on every move) and off, interleaved so that both see the
same load. Prints the median wall time, the median time in feasibility queries, their ratio, and
whether the two runs flew the same trajectory (on a smooth grid a move between two admissible
positions a few metres apart seldom crosses the ground, so the check mostly costs time).

    python benches/move_check.py [--seeds 5] [--sizes 5,12,20] [--n-threads 1]
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np

from uavcov import paper
from uavcov.experiments import RunSpec


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--sizes", default="5,12,20")
    parser.add_argument("--n-threads", type=int, default=1)
    args = parser.parse_args()
    print(f"median of {args.seeds} runs (seeds 1000-{999 + args.seeds}), n_threads {args.n_threads}, CVT start")
    print("| N | mission, moves checked | mission, not checked | ratio | feasibility, checked | feasibility, not | same trajectories |")
    print("|---|---|---|---|---|---|---|")
    for n in (int(v) for v in args.sizes.split(",")):
        wall: dict[bool, list[float]] = {True: [], False: []}
        feasible: dict[bool, list[float]] = {True: [], False: []}
        same = 0
        for seed in range(1000, 1000 + args.seeds):
            trajectories = {}
            for check in (True, False):
                experiment = paper.TABLE1.with_changes(**{"constraints.check_moves": check})
                result = RunSpec(experiment, seed, n, "cvt").run(n_threads=args.n_threads)
                wall[check].append(result.wall_time_s)
                feasible[check].append(result.trace.time_feasibility_s)
                trajectories[check] = result.trajectory
            same += int(np.array_equal(trajectories[True], trajectories[False]))
        on, off = statistics.median(wall[True]), statistics.median(wall[False])
        print(
            f"| {n} | {on:.2f} s | {off:.2f} s | {on / off:.2f} | {statistics.median(feasible[True]):.3f} s | "
            f"{statistics.median(feasible[False]):.3f} s | {same} of {args.seeds} |"
        )


if __name__ == "__main__":
    main()
