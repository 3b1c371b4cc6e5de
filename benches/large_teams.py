"""Large teams on a large map: what one mission costs as the team grows, for both optimisers.

The map of ``benches/large_map.py`` (``maps.heights``: 2 km x 2 km, rolling hills with steep
small ones on top) at ``--spacing`` (default 1 m: 4 million nodes, every node a target), d_max =
50 m, the paper's model scaled to that range (h_min 1 m, h_max 12 m above the ground, d_safe
1 m, every move checked), 30 known points, a CVT start, ``--iterations`` CAO iterations, for N in
``--sizes``. Each mission runs in a fresh Python process, so its peak resident memory
(``ru_maxrss``) is that of one map and one mission; the time is split as the optimiser's trace
records it (coverage measurements, feasibility, the optimiser's own work).

    python benches/large_teams.py [--sizes 12,25,50,100] [--iterations 500] [--optimizers cao,per_robot]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

CHILD = r"""
import json, resource, sys, time
import numpy as np
import uavcov

size, spacing, n_uavs, d_max, iterations, optimizer, threads, here = json.loads(sys.argv[1])
sys.path.insert(0, here)
from maps import heights

t0 = time.perf_counter()
terrain = uavcov.Terrain.from_grid(heights(size, spacing), spacing)
top = float(terrain.bounds[1, 2])
spec = uavcov.MissionSettings(
    n_uavs=n_uavs, d_max=d_max, iterations=iterations, optimizer=optimizer,
    start=uavcov.StartSettings(kind="cvt", altitude=2.0, altitude_reference="prior", climb=1.0),
    constraints=uavcov.Constraints(h_min=1.0, h_max=12.0, z_max=top + 50.0, d_safe=1.0, check_moves=True),
    cao=uavcov.CAOSettings(alpha0=10.0, stability=5.0, decay=1.0),
)
t1 = time.perf_counter()
r = uavcov.run_mission(terrain, spec, rng=0, n_threads=threads)
t2 = time.perf_counter()
t = r.trace
print(json.dumps({
    "map_s": t1 - t0, "mission_s": t2 - t1, "measure_s": t.time_measure_s, "feasibility_s": t.time_feasibility_s,
    "optimizer_s": t.time_optimizer_s, "initial": r.initial_coverage, "best": r.best_coverage,
    "regressors": int(t.settings.robot_regressors if optimizer == "per_robot" else t.settings.n_regressors),
    "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
}))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=float, default=2000.0, help="side of the square map, m")
    parser.add_argument("--spacing", type=float, default=1.0, help="grid spacing, m")
    parser.add_argument("--sizes", default="12,25,50,100", help="team sizes")
    parser.add_argument("--d-max", type=float, default=50.0)
    parser.add_argument("--iterations", type=int, default=500)
    parser.add_argument("--optimizers", default="cao,per_robot")
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    here = os.path.dirname(os.path.abspath(__file__))
    print(f"load average before: {os.getloadavg()[0]:.2f}", flush=True)
    columns = ["optimizer", "N", "regressors L (per estimator)", "mission", "measurements", "feasibility", "optimiser's own"]
    print("| " + " | ".join([*columns, "initial", "best", "peak RSS"]) + " |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for optimizer in args.optimizers.split(","):
        for n in (int(v) for v in args.sizes.split(",")):
            config = json.dumps([args.size, args.spacing, n, args.d_max, args.iterations, optimizer, args.threads, here])
            out = subprocess.run([sys.executable, "-c", CHILD, config], capture_output=True, text=True, check=False)
            if out.returncode != 0:
                sys.exit(out.stderr)
            r = json.loads(out.stdout)
            print(
                f"| {optimizer} | {n} | {r['regressors']} | {r['mission_s']:.1f} s | {r['measure_s']:.1f} s | {r['feasibility_s']:.1f} s "
                f"| {r['optimizer_s']:.1f} s | {r['initial']:.3f} | {r['best']:.3f} | {r['peak_mib']:.0f} MiB |",
                flush=True,
            )
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
