"""Two or more builds of uavcov side by side: the reference case's evaluation, alternating builds.

Each build is a copy of the ``uavcov`` package (its Python files and its ``_core`` extension) in a
folder of its own, for example made from a commit with::

    git worktree add /tmp/old COMMIT && (cd /tmp/old && cargo build --release --features python)
    mkdir -p /tmp/pkg-old && cp -r /tmp/old/python/uavcov /tmp/pkg-old/
    cp /tmp/old/target/release/libuavcov.so /tmp/pkg-old/uavcov/_core.abi3.so

Every round runs each build in turn, each in a fresh process with its folder first on
``PYTHONPATH``: that process times ``--calls`` evaluations of ``coverage_vs_open3d.py``'s
reference case (after two untimed ones) and reports their 10th percentile, which a burst of load
on a shared machine moves least. Alternating builds round by round gives them the same machine.

    python benches/alternate_builds.py /tmp/pkg-old /tmp/pkg-new [--rounds 4] [--threads 1]
        [--seed 0] [--spacing 0.5] [--calls 300]
"""

from __future__ import annotations

import argparse
import os
import pathlib
import statistics
import subprocess
import sys

_ONE_BUILD = """
import sys, time
sys.path.insert(0, {benches!r})
from coverage_vs_open3d import reference_case
import uavcov
terrain, uavs = reference_case({spacing}, {seed})
vis = uavcov.Visibility(terrain, 25.0, n_threads={threads})
vis.coverage(uavs)
vis.coverage(uavs)
times = []
for _ in range({calls}):
    start = time.perf_counter()
    vis.coverage(uavs)
    times.append(time.perf_counter() - start)
times.sort()
print(uavcov.__file__, 1e3 * times[len(times) // 10])
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("builds", nargs="+", type=pathlib.Path, help="folders, each holding a uavcov package")
    parser.add_argument("--rounds", type=int, default=4)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--seed", type=int, default=0, help="terrain seed (0: the reference case)")
    parser.add_argument("--spacing", type=float, default=0.5)
    parser.add_argument("--calls", type=int, default=300)
    args = parser.parse_args()
    for build in args.builds:
        if not (build / "uavcov" / "__init__.py").is_file():
            sys.exit(f"{build} holds no uavcov package")
    code = _ONE_BUILD.format(
        benches=str(pathlib.Path(__file__).resolve().parent), spacing=args.spacing, seed=args.seed, threads=args.threads, calls=args.calls
    )
    times: dict[pathlib.Path, list[float]] = {build: [] for build in args.builds}
    for _ in range(args.rounds):
        for build in args.builds:
            env = {**os.environ, "PYTHONPATH": str(build.resolve()), "OPENBLAS_NUM_THREADS": "1"}
            out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True).stdout.split()
            if not pathlib.Path(out[0]).resolve().is_relative_to(build.resolve()):
                sys.exit(f"{build}: the process imported uavcov from {out[0]}")
            times[build].append(float(out[1]))
    first = statistics.median(times[args.builds[0]])
    print(f"reference case, terrain seed {args.seed}, {args.spacing} m, {args.threads} thread(s): p10 of {args.calls} evaluations, ms")
    for build, values in times.items():
        median = statistics.median(values)
        rounds = " / ".join(f"{v:.3f}" for v in values)
        print(f"{build}: {rounds}; median {median:.3f} ({median / first:.2f}x the first build)")


if __name__ == "__main__":
    main()
