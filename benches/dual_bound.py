"""The LP dual bound against the online bound on Table 1's terrains: values and time.

For the first ``--seeds`` scenarios (5 m lattice, 3 heights, the true surface, d_max = 25 m),
per team size: greedy's coverage, its online bound (Leskovec et al. 2007), the LP relaxation's
dual bound on 3 m and 5 m clusters of targets, and (``--full``, N = 5 only: ~25-50 s each) the
full LP; means over the scenarios, solve time the median. Run as::

    OPENBLAS_NUM_THREADS=1 nice .venv/bin/python benches/dual_bound.py --seeds 5 --full
"""

from __future__ import annotations

import argparse

import numpy as np

from uavcov import Visibility
from uavcov.cover import CoverageProblem, viewpoint_lattice
from uavcov.paper import TABLE1


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--full", action="store_true", help="also the full LP (one row per target) for N = 5")
    args = parser.parse_args()
    sizes = TABLE1.team_sizes
    cells: list[float | None] = [3.0, 5.0]
    found: dict[tuple[int, str], list[tuple[float, float]]] = {}
    for seed in range(args.seeds):
        terrain = TABLE1.terrain.make(seed)
        limits = TABLE1.mission.constraints.resolve(terrain)
        lattice = viewpoint_lattice(terrain, limits, None, n_threads=args.threads)
        problem = CoverageProblem(Visibility(terrain, TABLE1.d_max, n_threads=args.threads), lattice, n_threads=args.threads)
        for n in sizes:
            greedy = problem.greedy(n, limits.d_safe)
            found.setdefault((n, "greedy"), []).append((greedy.coverage, greedy.greedy_time_s))
            found.setdefault((n, "online"), []).append((greedy.bound, greedy.greedy_time_s))
            for cell in cells + ([None] if args.full and n == sizes[0] else []):
                certificate = problem.dual_bound(n, cell=cell)
                found.setdefault((n, f"dual {cell or 'full'}"), []).append((certificate.bound, certificate.solve_time_s))
    kinds = ["greedy", "online", "dual 3.0", "dual 5.0", "dual full"]
    print("| N | " + " | ".join(f"{k} (s)" for k in kinds) + " |")
    print("|---|" + "---|" * len(kinds))
    for n in sizes:
        cells_text = []
        for kind in kinds:
            values = found.get((n, kind))
            if not values:
                cells_text.append("-")
                continue
            v = np.array(values)
            cells_text.append(f"{v[:, 0].mean():.4f} ({np.median(v[:, 1]):.2f})")
        print(f"| {n} | " + " | ".join(cells_text) + " |", flush=True)


if __name__ == "__main__":
    main()
