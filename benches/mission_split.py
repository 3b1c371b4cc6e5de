"""Where one 500-iteration mission spends its time: coverage measurements against the optimiser.

The reference mission: 12 UAVs, a paper terrain (7 Gaussians, 100 m x 100 m) with 1 m targets,
d_max = 25 m, CVT start, 500 CAO iterations. Prints the median over a few seeds of the wall time
and of its parts, as recorded by the optimiser's trace: coverage measurements, feasibility
(constraint queries on the real surface) and the optimiser's own work (regression, candidates).

    python benches/mission_split.py [--seeds 3] [--n-threads 1] [--paper] [--plain]

``--paper`` runs the paper's Table 1 mission instead (``uavcov.paper.TABLE1``: its terrains, 12
UAVs 1-8 m above the ground, every move checked). ``--plain`` measures every configuration with
``Visibility.coverage`` afresh instead of the ``CoverageTracker`` that ``run_mission`` uses (the
same values; the bench swaps ``Visibility.tracker`` for the plain objective), for a side-by-side.
"""

from __future__ import annotations

import argparse
import statistics
from dataclasses import replace

import uavcov
from uavcov import paper


class _Plain:
    """``Visibility.tracker``'s stand-in: every configuration measured afresh."""

    def __init__(self, vis: uavcov.Visibility) -> None:
        self.vis = vis

    def coverage(self, uavs: object) -> float:
        return self.vis.coverage(uavs)


def _plain_tracker(vis: uavcov.Visibility, margin: float | None = None) -> _Plain:
    """Takes ``Visibility.tracker``'s arguments; the margin has nothing to change here."""
    return _Plain(vis)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--n-threads", type=int, default=1)
    parser.add_argument("--optimizer", default="cao", choices=["cao", "per_robot"])
    parser.add_argument("--paper", action="store_true", help="the paper's Table 1 mission (uavcov.paper.TABLE1), N = 12")
    parser.add_argument("--plain", action="store_true", help="measure without the CoverageTracker")
    args = parser.parse_args()
    if args.plain:
        uavcov.Visibility.tracker = _plain_tracker  # type: ignore[method-assign]
    rows = []
    for seed in range(1000, 1000 + args.seeds):
        if args.paper:
            terrain = paper.TABLE1.terrain.make(seed)
            spec = replace(paper.TABLE1.mission, n_uavs=12, optimizer=args.optimizer)
        else:
            terrain = uavcov.gaussian_hills(spacing=1.0, rng=seed)
            spec = uavcov.MissionSpec(n_uavs=12, d_max=25.0, iterations=500, optimizer=args.optimizer)
        r = uavcov.run_mission(terrain, spec, rng=seed, n_threads=args.n_threads)
        t = r.trace
        rows.append((r.wall_time_s, t.time_measure_s, t.time_feasibility_s, t.time_optimizer_s))
    med = [statistics.median(col) for col in zip(*rows, strict=True)]
    total = med[0]
    what = "the paper's Table 1 mission" if args.paper else "the reference mission"
    what += ", plain measurements" if args.plain else ""
    print(f"{what}, optimizer {args.optimizer}, n_threads {args.n_threads}, median of {args.seeds} runs (seeds 1000-{999 + args.seeds})")
    print("| part | seconds | share of the run |")
    print("|---|---|---|")
    for name, value in zip(("whole mission", "coverage measurements", "feasibility queries", "optimiser's own work"), med, strict=True):
        print(f"| {name} | {value:.2f} | {value / total:.0%} |")
    print(f"| rest (prior, S', CVT, start) | {total - sum(med[1:]):.2f} | {(total - sum(med[1:])) / total:.0%} |")


if __name__ == "__main__":
    main()
