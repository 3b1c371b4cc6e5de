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
``--phases`` also splits the measurements by phase of the run (the start, iterations 1-49, 50-99,
100-199, 200 on), beside how far a UAV moves per iteration there (the median over the UAVs that
move): the tracker's certificates hold while a UAV stays within 1-4 m of where they were made.
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import replace

import numpy as np

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


PHASES = ((0, 1), (1, 50), (50, 100), (100, 200), (200, None))
"""Iterations ``[start, stop)`` of each phase of ``--phases`` (``None``: to the end)."""


class _Timed:
    """A measurer whose calls are timed, one entry of ``seconds`` per configuration measured."""

    def __init__(self, inner: object, seconds: list[float]) -> None:
        self.inner, self.seconds = inner, seconds

    def coverage(self, uavs: object) -> float:
        start = time.perf_counter()
        value: float = self.inner.coverage(uavs)  # type: ignore[attr-defined]
        self.seconds.append(time.perf_counter() - start)
        return value


def _phases(seconds: list[float], trajectory: np.ndarray) -> list[tuple[float, float, float]]:
    """Per phase: the measurements' seconds, seconds per measurement, median move (metres).

    A configuration equal to the one before is not measured again (``run_mission`` repeats the
    last value), so ``seconds`` has one entry per configuration that differs from its predecessor.
    """
    moves = np.linalg.norm(np.diff(trajectory, axis=0), axis=2)  # (K, N): the move into k + 1
    measured = np.flatnonzero(np.concatenate([[True], moves.max(axis=1) > 0]))
    if measured.size != len(seconds):
        raise RuntimeError(f"{len(seconds)} measurements timed for {measured.size} configurations measured")
    per_iteration = np.zeros(trajectory.shape[0])
    per_iteration[measured] = seconds
    out = []
    for start, stop in PHASES:
        n_measured = int(np.count_nonzero((measured >= start) & (measured < (stop or trajectory.shape[0]))))
        spent = float(per_iteration[start:stop].sum())
        moved = moves[max(start - 1, 0) : None if stop is None else stop - 1]
        moved = moved[moved > 0]
        out.append((spent, spent / max(n_measured, 1), float(np.median(moved)) if moved.size else float("nan")))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--n-threads", type=int, default=1)
    parser.add_argument("--optimizer", default="cao", choices=["cao", "per_robot"])
    parser.add_argument("--paper", action="store_true", help="the paper's Table 1 mission (uavcov.paper.TABLE1), N = 12")
    parser.add_argument("--plain", action="store_true", help="measure without the CoverageTracker")
    parser.add_argument("--phases", action="store_true", help="split the measurements by phase of the run (optimizer cao)")
    args = parser.parse_args()
    if args.phases and args.optimizer != "cao":
        parser.error("--phases times the measurements of optimizer cao")
    if args.plain:
        uavcov.Visibility.tracker = _plain_tracker  # type: ignore[method-assign]
    seconds: list[float] = []
    if args.phases:
        make = uavcov.Visibility.tracker
        uavcov.Visibility.tracker = lambda vis, margin=None: _Timed(make(vis, margin), seconds)  # type: ignore[method-assign, assignment, return-value]
    rows = []
    phases = []
    for seed in range(1000, 1000 + args.seeds):
        if args.paper:
            terrain = paper.TABLE1.terrain.make(seed)
            spec = replace(paper.TABLE1.mission, n_uavs=12, optimizer=args.optimizer)
        else:
            terrain = uavcov.gaussian_hills(spacing=1.0, rng=seed)
            spec = uavcov.MissionSettings(n_uavs=12, d_max=25.0, iterations=500, optimizer=args.optimizer)
        seconds.clear()
        r = uavcov.run_mission(terrain, spec, rng=seed, n_threads=args.n_threads)
        if args.phases:
            phases.append(_phases(seconds, np.asarray(r.trajectory)))
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
        print(f"| {name} | {value:.3f} | {value / total:.0%} |")
    print(f"| rest (prior, S', CVT, start) | {total - sum(med[1:]):.3f} | {(total - sum(med[1:])) / total:.0%} |")
    if phases:
        print()
        print("| iterations | measurements, s | per measurement, ms | median move of a UAV, m |")
        print("|---|---|---|---|")
        for (start, stop), runs in zip(PHASES, zip(*phases, strict=True), strict=True):
            spent, each, move = (statistics.median(col) for col in zip(*runs, strict=True))
            name = "the start" if stop == 1 else f"{start}-{stop - 1}" if stop else f"{start} on"
            print(f"| {name} | {spent:.3f} | {1e3 * each:.2f} | {'-' if np.isnan(move) else f'{move:.2f}'} |")


if __name__ == "__main__":
    main()
