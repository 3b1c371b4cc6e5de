"""The coverage measurements of stored missions, replayed: the engine's work in the paper's runs.

Each stored run (``runs/*.npz`` of a results folder, e.g. ``uavcov reproduce table1 --out DIR``)
holds its terrain grid and its whole trajectory. This loads every ``--every``-th run, evaluates
``Visibility(terrain, d_max, n_threads=1).coverage`` at each of its configurations, checks every
value equals the one stored in the run, and prints the mean time per evaluation. Alternate it
between two builds to compare them on exactly the sight lines a sweep measures.

With ``--tracker MARGIN`` it also measures each run along its path with
``Visibility.tracker(MARGIN)`` (what ``run_mission`` does), run by run alternating with the plain
objective, checks those values too, and prints both times and their ratio. ``--from K`` times
only the measurements of iterations ``K`` on (every configuration is still measured, in order):
the late part of a mission, where the steps are small.

    uavcov reproduce table1 --seeds 0-9 --out out/table1 --no-plots
    python benches/replay.py out/table1 [--every 10] [--d-max 25] [--tracker 1.0] [--from 200]
"""

from __future__ import annotations

import argparse
import pathlib
import time

import numpy as np

import uavcov


def timed(measure, trajectory: np.ndarray, start: int) -> tuple[float, list[float]]:
    """Every configuration measured in order; the seconds spent on those from ``start`` on."""
    values = [measure(p) for p in trajectory[:start]]
    t0 = time.perf_counter()
    values += [measure(p) for p in trajectory[start:]]
    return time.perf_counter() - t0, values


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", type=pathlib.Path, help="a results folder with runs/*.npz")
    parser.add_argument("--every", type=int, default=10, help="replay every k-th run (sorted by name)")
    parser.add_argument("--d-max", type=float, default=25.0, help="sensing range of the runs, metres")
    parser.add_argument("--tracker", type=float, default=None, metavar="MARGIN", help="also measure with a CoverageTracker of this margin")
    parser.add_argument("--from", dest="start", type=int, default=0, metavar="K", help="time only the measurements of iterations K on")
    args = parser.parse_args()
    files = sorted((args.folder / "runs").glob("*.npz"))[:: args.every]
    if not files:
        raise SystemExit(f"no runs/*.npz under {args.folder}")
    seconds, tracked, evaluations, worst = 0.0, 0.0, 0, 0.0
    for f in files:
        with np.load(f, allow_pickle=False) as run:
            z, spacing, origin = run["terrain_grid_z"], run["terrain_grid_spacing"], run["terrain_grid_origin"]
            trajectory, stored = run["trace_trajectory"], run["coverage"]
        terrain = uavcov.Terrain.from_grid(z, spacing, origin)
        vis = uavcov.Visibility(terrain, args.d_max, n_threads=1)
        spent, values = timed(vis.coverage, trajectory, args.start)
        seconds += spent
        evaluations += len(values[args.start :])
        worst = max(worst, float(np.abs(np.asarray(values) - stored).max()))
        if args.tracker is not None:
            spent, along = timed(vis.tracker(args.tracker).coverage, trajectory, args.start)
            tracked += spent
            worst = max(worst, float(np.abs(np.asarray(along) - stored).max()))
    if evaluations == 0:
        raise SystemExit(f"no run has an iteration {args.start} or later to time")
    per = 1e3 * seconds / evaluations
    print(f"{len(files)} runs, {evaluations} timed evaluations, {per:.3f} ms each; largest difference from the stored coverage {worst:.1e}")
    if args.tracker is not None:
        per_tracked = 1e3 * tracked / evaluations
        print(f"tracker (margin {args.tracker} m): {per_tracked:.3f} ms each, {per_tracked / per:.2f}x the plain objective")
    if worst != 0.0:
        raise SystemExit("the replay differs from the stored runs")


if __name__ == "__main__":
    main()
