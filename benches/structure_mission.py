"""Where a 500-iteration mission on a structure spends its time (issue 35).

The mission: the girder bridge (``uavcov.structures.girder_bridge``, seed 0, 7 404 triangles, 6 108
targets 1 m apart on the structure), 12 UAVs, d_max = 15 m, the 3D prior (100 points, alpha
shape), the CVT start flown 6 m out along S''s normals, standoff limits (h_min 2 m, d_safe 1 m,
z_max 10 m over the top, every move checked), 500 CAO iterations, one Rust thread. Prints, per
seed and as the median over the seeds, the wall time and its parts as the optimiser's trace
records them: coverage measurements, feasibility (the standoff checks of every candidate batch)
and the optimiser's own work; and the ratio of the mission's time to its coverage evaluations'.

    nice python benches/structure_mission.py [--seeds 3] [--iterations 500] [--n-threads 1]
"""

from __future__ import annotations

import argparse
import statistics
import time

from uavcov import MissionSettings, run_mission
from uavcov.limits import Constraints
from uavcov.placement import StartSettings
from uavcov.structures import girder_bridge


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--iterations", type=int, default=500)
    parser.add_argument("--n-threads", type=int, default=1)
    args = parser.parse_args()
    bridge = girder_bridge(rng=0)
    targets = bridge.targets(spacing=1.0)
    top = float(bridge.surface.bounds[1, 2])
    settings = MissionSettings(
        n_uavs=12,
        d_max=15.0,
        n_prior=100,
        iterations=args.iterations,
        start=StartSettings(kind="cvt", altitude=6.0, altitude_reference="normal", climb=0.5),
        constraints=Constraints(clearance="standoff", h_min=2.0, d_safe=1.0, z_max=top + 10.0, check_moves=True),
    )
    print(f"girder bridge: {bridge.surface.n_faces} triangles, {len(targets)} targets; 12 UAVs, {args.iterations} iterations")
    rows = []
    for seed in range(args.seeds):
        began = time.perf_counter()
        result = run_mission(bridge, settings, targets=targets, rng=seed, n_threads=args.n_threads)
        wall = time.perf_counter() - began
        trace = result.trace
        row = {
            "wall": wall,
            "measure": trace.time_measure_s,
            "feasibility": trace.time_feasibility_s,
            "optimizer": trace.time_optimizer_s,
            "evaluations": result.evaluations,
            "best": result.best_coverage,
            "underside": (result.coverage_by_part or {}).get("deck_underside", float("nan")),
        }
        rows.append(row)
        print(
            f"seed {seed}: wall {wall:.2f} s, coverage measurements {row['measure']:.2f} s ({row['evaluations']} evaluations), "
            f"feasibility {row['feasibility']:.2f} s, optimiser {row['optimizer']:.2f} s; mission / measurements "
            f"{wall / row['measure']:.2f}; best coverage {row['best']:.3f}, deck underside {row['underside']:.3f}"
        )
    median = {k: statistics.median(r[k] for r in rows) for k in ("wall", "measure", "feasibility", "optimizer")}
    ratio = statistics.median(r["wall"] / r["measure"] for r in rows)
    print(
        f"median: wall {median['wall']:.2f} s, measurements {median['measure']:.2f} s, feasibility {median['feasibility']:.2f} s, "
        f"optimiser {median['optimizer']:.2f} s; mission / coverage evaluations {ratio:.2f}"
    )


if __name__ == "__main__":
    main()
