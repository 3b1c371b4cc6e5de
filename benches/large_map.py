"""A large map with the grid method (``method="grid"``): load time, one evaluation and peak memory.

The map: 2 km x 2 km at 0.5 m (4001 x 4001 nodes, 16 million cells, 32 million triangles), rolling
hills with steep small ones on top; 50 UAVs at random 5-30 m above the ground; d_max = 50 m; the
default targets (all 16 million nodes). Each measurement runs in a fresh Python process, so the
peak resident memory (``ru_maxrss``) is that of loading and evaluating this one map, heights
included; the baseline of an interpreter that has imported numpy and uavcov is printed beside it.

The mesh method (``method="mesh"``) is not run on this map: it refuses anything over ``MAX_TRIANGLES`` (10 million) with
``SurfaceTooLargeError`` instead of swapping, which the script checks too.

    python benches/large_map.py [--size 2000] [--spacing 0.5] [--uavs 50] [--d-max 50]
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
from uavcov.errors import SurfaceTooLargeError

size, spacing, n_uavs, d_max, threads, here = json.loads(sys.argv[1])
sys.path.insert(0, here)
from maps import heights
baseline_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss

t0 = time.perf_counter()
z = heights(size, spacing)
t1 = time.perf_counter()
terrain = uavcov.Terrain.from_grid(z, spacing)
t2 = time.perf_counter()
vis = uavcov.Visibility(terrain, d_max, n_threads=threads)
t3 = time.perf_counter()
rng = np.random.default_rng(1)
xy = rng.uniform(0.0, size, (n_uavs, 2))
uavs = np.column_stack([xy, terrain.ground_height(xy) + rng.uniform(5.0, 30.0, n_uavs)])
t4 = time.perf_counter()
coverage = vis.coverage(uavs)
t5 = time.perf_counter()
# The second evaluation builds the skylines of the targets it reaches; the third uses them.
second = [time.perf_counter()]
vis.coverage(uavs)
second.append(time.perf_counter())
vis.coverage(uavs)
second.append(time.perf_counter())
try:
    uavcov.Visibility(terrain, d_max, uavcov.Targets(uavs[:1, :] * [1, 1, 0]), method="mesh")
    refused = False
except SurfaceTooLargeError:
    refused = True
peak_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({
    "nodes": int(z.size), "triangles": int(terrain.n_faces), "targets": int(vis._core.n_targets),
    "heights_s": t1 - t0, "terrain_s": t2 - t1, "visibility_s": t3 - t2,
    "evaluation_s": t5 - t4, "second_evaluation_s": second[1] - second[0],
    "third_evaluation_s": second[2] - second[1],
    "coverage": coverage, "mesh_path_refused": refused,
    "baseline_mib": baseline_kib / 1024, "peak_mib": peak_kib / 1024,
}))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=float, default=2000.0, help="side of the square map, m")
    parser.add_argument("--spacing", type=float, default=0.5, help="grid spacing, m")
    parser.add_argument("--uavs", type=int, default=50)
    parser.add_argument("--d-max", type=float, default=50.0)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    config = json.dumps([args.size, args.spacing, args.uavs, args.d_max, args.threads, os.path.dirname(os.path.abspath(__file__))])
    print(f"load average before: {os.getloadavg()[0]:.2f}", flush=True)
    out = subprocess.run([sys.executable, "-c", CHILD, config], capture_output=True, text=True, check=False)
    if out.returncode != 0:
        sys.exit(out.stderr)
    r = json.loads(out.stdout)
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    print(
        f"| map | nodes | triangles | targets | UAVs, d_max | heights (numpy) | Terrain.from_grid "
        f"| Visibility() | one evaluation, {args.threads} thr | again (builds skylines) | third | coverage | peak RSS "
        f"| interpreter alone | mesh path |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    print(
        f"| {args.size / 1000:g} km x {args.size / 1000:g} km at {args.spacing:g} m | {r['nodes']:,} | {r['triangles']:,} "
        f"| {r['targets']:,} | {args.uavs}, {args.d_max:g} m | {r['heights_s']:.1f} s | {r['terrain_s']:.2f} s "
        f"| {r['visibility_s']:.2f} s | {r['evaluation_s']:.2f} s | {r['second_evaluation_s']:.2f} s "
        f"| {r['third_evaluation_s']:.2f} s "
        f"| {r['coverage']:.4f} | {r['peak_mib']:.0f} MiB | {r['baseline_mib']:.0f} MiB "
        f"| {'refused (SurfaceTooLargeError)' if r['mesh_path_refused'] else 'ran'} |"
    )


if __name__ == "__main__":
    main()
