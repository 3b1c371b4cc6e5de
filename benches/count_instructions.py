"""A fixed workload of the coverage engine, to be counted in instructions under valgrind.

This machine's timings move by 10-30 % from run to run; the instructions a workload executes do
not, so a change to the engine can be weighed exactly, function by function:

    valgrind --tool=callgrind --callgrind-out-file=OUT python benches/count_instructions.py paper DIR/table1
    valgrind --tool=callgrind --callgrind-out-file=OUT python benches/count_instructions.py reference
    valgrind --tool=callgrind --callgrind-out-file=OUT python benches/count_instructions.py along DIR/table1
    valgrind --tool=callgrind --callgrind-out-file=OUT python benches/count_instructions.py mission
    valgrind --tool=callgrind --callgrind-out-file=OUT python benches/count_instructions.py high
    callgrind_annotate --inclusive=yes OUT | grep -E "Engine::line_of_sight|Stencil::skyline|walk_hits_from"
    callgrind_annotate --inclusive=yes OUT | grep -E "__pymethod_coverage__ \\["

``paper``: the first ``--evaluations`` configurations (default 50) of one stored Table 1 run with
N = 12 and the CVT start (``--run``: its index among those of ``DIR/runs``, sorted by name; ``DIR``
from ``uavcov reproduce table1 --seeds 0 --out DIR/table1 --no-plots``), measured with the plain
objective on one thread: the first one without skylines, the second building them, the others
as CAO's first iterations see them (UAVs 1-8 m above the ground). ``reference``: the reference
case of ``coverage_vs_open3d.py`` on its terrains 0, 7001 and 7002 at ``--spacing`` (default
0.5 m), each evaluated ``--evaluations`` times (default 6) on one thread (``--terrain-seeds`` for
fewer or others). ``high``: the reference terrain with 12 UAVs 45-60 m up and ``d_max`` = 60 m,
above every node, evaluated ``--evaluations`` times (default 20). ``along``: every
``--every``-th stored run of ``DIR/runs`` (default 96: 5 of Table 1's 480) measured along its
whole path through ``Visibility.tracker()`` (``--margin`` for a fixed one), as ``run_mission``
measures it. ``mission``: ``benches/mission_split.py``'s reference mission (seed 1000), CAO
included; its measurements are the calls of ``CoverageTracker.coverage``.
"""

from __future__ import annotations

import argparse
import pathlib
import sys

import numpy as np

import uavcov


def paper(folder: pathlib.Path, run: int, evaluations: int) -> None:
    files = sorted((folder / "runs").glob("*cvt-n12*.npz"))
    if not files:
        sys.exit(f"no Table 1 run with N = 12 and the CVT start in {folder / 'runs'}")
    with np.load(files[run]) as stored:
        z, spacing, origin = stored["terrain_grid_z"], stored["terrain_grid_spacing"], stored["terrain_grid_origin"]
        trajectory = stored["trace_trajectory"]
    vis = uavcov.Visibility(uavcov.Terrain.from_grid(z, spacing, origin), 25.0, n_threads=1)
    for uavs in trajectory[:evaluations]:
        vis.coverage(uavs)


def along(folder: pathlib.Path, every: int, margin: float | None) -> None:
    files = sorted((folder / "runs").glob("*.npz"))[::every]
    if not files:
        sys.exit(f"no stored runs in {folder / 'runs'}")
    for f in files:
        with np.load(f) as stored:
            z, spacing, origin = stored["terrain_grid_z"], stored["terrain_grid_spacing"], stored["terrain_grid_origin"]
            trajectory = stored["trace_trajectory"]
        tracker = uavcov.Visibility(uavcov.Terrain.from_grid(z, spacing, origin), 25.0, n_threads=1).tracker(margin)
        for uavs in trajectory:
            tracker.coverage(uavs)


def mission() -> None:
    terrain = uavcov.gaussian_hills(spacing=1.0, rng=1000)
    spec = uavcov.MissionSettings(n_uavs=12, d_max=25.0, iterations=500)
    uavcov.run_mission(terrain, spec, rng=1000, n_threads=1)


def reference(spacing: float, evaluations: int, seeds: list[int]) -> None:
    sys.path.insert(0, str(pathlib.Path(__file__).parent))
    from coverage_vs_open3d import reference_case

    for seed in seeds:
        terrain, uavs = reference_case(spacing, seed)
        vis = uavcov.Visibility(terrain, 25.0, n_threads=1)
        for _ in range(evaluations):
            vis.coverage(uavs)


def high(spacing: float, evaluations: int) -> None:
    sys.path.insert(0, str(pathlib.Path(__file__).parent))
    from coverage_vs_open3d import gaussian_hills_grid

    terrain = uavcov.Terrain.from_grid(gaussian_hills_grid(spacing, 0), spacing)
    rng = np.random.default_rng(5)
    uavs = np.c_[rng.uniform(0.0, 100.0, (12, 2)), rng.uniform(45.0, 60.0, 12)]
    vis = uavcov.Visibility(terrain, 60.0, n_threads=1)
    for _ in range(evaluations):
        vis.coverage(uavs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("workload", choices=["paper", "reference", "along", "mission", "high"])
    parser.add_argument("folder", nargs="?", type=pathlib.Path, help="a Table 1 results folder (paper, along)")
    parser.add_argument("--run", type=int, default=0)
    parser.add_argument("--evaluations", type=int, default=None)
    parser.add_argument("--spacing", type=float, default=0.5)
    parser.add_argument("--every", type=int, default=96)
    parser.add_argument("--margin", type=float, default=None)
    parser.add_argument("--terrain-seeds", type=int, nargs="+", default=[0, 7001, 7002])
    args = parser.parse_args()
    if args.workload in ("paper", "along") and args.folder is None:
        parser.error(f"{args.workload} needs the Table 1 results folder")
    if args.workload == "paper":
        paper(args.folder, args.run, args.evaluations or 50)
    elif args.workload == "along":
        along(args.folder, args.every, args.margin)
    elif args.workload == "mission":
        mission()
    elif args.workload == "high":
        high(args.spacing, args.evaluations or 20)
    else:
        reference(args.spacing, args.evaluations or 6, args.terrain_seeds)


if __name__ == "__main__":
    main()
