"""How the greedy placement and its certified bound move as the candidate lattice is refined,
and the wall time of the Table 1 oracle.

On Table 1's terrains (the paper's hills, 100 m at 1 m, d_max = 25 m, h_min 1 m, h_max 8 m,
d_safe 1 m), lattices of 5, 2.5 and 1.25 m x 3 heights (each keeps every candidate of the
coarser one): candidates, seen-matrix time and memory, greedy coverage, bound and ceiling for
N = 5, 8, 12, 20, means over the first ``--seeds`` scenarios. Then (``--oracle``) the oracle over
all 40 scenarios x 4 team sizes at the default 5 m lattice, timed.

    nice .venv/bin/python benches/cover_refinement.py --seeds 5 --oracle
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np

from uavcov import Visibility
from uavcov.cover import CoverageProblem, GreedySettings, viewpoint_lattice
from uavcov.paper import TABLE1, oracle


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--spacings", type=float, nargs="+", default=[5.0, 2.5, 1.25])
    parser.add_argument("--oracle", action="store_true")
    args = parser.parse_args()
    sizes = TABLE1.team_sizes
    print("| lattice | candidates | matrix s | matrix MB | " + " | ".join(f"N={n} greedy / bound" for n in sizes) + " |")
    print("|---|---|---|---|" + "---|" * len(sizes))
    for spacing in args.spacings:
        rows = []
        for seed in range(args.seeds):
            terrain = TABLE1.terrain.make(seed)
            limits = TABLE1.mission.constraints.resolve(terrain)
            lattice = viewpoint_lattice(terrain, limits, GreedySettings(spacing=spacing, n_heights=3), n_threads=args.threads)
            problem = CoverageProblem(Visibility(terrain, TABLE1.d_max, n_threads=args.threads), lattice, n_threads=args.threads)
            results = [problem.greedy(n, limits.d_safe) for n in sizes]
            rows.append((lattice.n, problem.matrix_time_s, problem.nbytes / 1e6, [(r.coverage, r.bound) for r in results]))
        n_cand = np.mean([r[0] for r in rows])
        t = np.median([r[1] for r in rows])
        mb = np.mean([r[2] for r in rows])
        cells = []
        for j in range(len(sizes)):
            g = np.mean([r[3][j][0] for r in rows])
            b = np.mean([r[3][j][1] for r in rows])
            cells.append(f"{g:.4f} / {b:.4f}")
        print(f"| {spacing:g} m x 3 | {n_cand:.0f} | {t:.2f} | {mb:.1f} | " + " | ".join(cells) + " |", flush=True)
    if args.oracle:
        started = time.perf_counter()
        result = oracle(TABLE1, n_threads=args.threads)
        elapsed = time.perf_counter() - started
        print(f"\noracle: {len(result)} rows (40 terrains x 4 team sizes) in {elapsed:.1f} s on {args.threads} threads")
        for n in sizes:
            mine = [r for r in result if r.n_uavs == n]
            print(f"  N={n}: greedy {np.mean([r.coverage for r in mine]):.4f}, bound {np.mean([r.bound for r in mine]):.4f}")
    print(f"peak RSS {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


if __name__ == "__main__":
    main()
