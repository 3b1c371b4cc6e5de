"""The ``uavcov`` command line: parses arguments, then calls one library function."""

from __future__ import annotations

import argparse
import sys
import time
from typing import Sequence

import numpy as np

__all__ = ["main"]


def _demo(args: argparse.Namespace) -> int:
    from .terrains import gaussian_hills
    from .visibility import Visibility

    t0 = time.perf_counter()
    terrain = gaussian_hills(spacing=args.spacing, rng=args.seed)
    built = time.perf_counter() - t0
    rng = np.random.default_rng(args.seed)
    xy = rng.uniform(0.0, 100.0, (args.uavs, 2))
    uavs = np.c_[xy, terrain.ground_height(xy) + rng.uniform(5.0, 30.0, args.uavs)]
    vis = Visibility(terrain, d_max=args.d_max)
    vis.coverage(uavs)  # warm the thread pool
    times = []
    for _ in range(20):
        t0 = time.perf_counter()
        value = vis.coverage(uavs)
        times.append(time.perf_counter() - t0)
    print(f"terrain: {terrain!r} (built in {1e3 * built:.0f} ms)")
    print(f"{args.uavs} UAVs at random 5-30 m above ground, d_max = {args.d_max} m, {len(vis.targets)} targets")
    print(f"coverage: {value:.4f}   one evaluation: median {1e3 * float(np.median(times)):.2f} ms over 20")
    return 0


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="uavcov", description="Multi-UAV visual coverage of 3D surfaces.")
    commands = parser.add_subparsers(dest="command", required=True)
    demo = commands.add_parser("demo", help="the main example: a terrain, a team, its coverage")
    demo.add_argument("--spacing", type=float, default=0.5, help="terrain grid spacing, m (default 0.5)")
    demo.add_argument("--uavs", type=int, default=12, help="team size (default 12)")
    demo.add_argument("--d-max", type=float, default=25.0, help="sensing range, m (default 25)")
    demo.add_argument("--seed", type=int, default=0, help="terrain and team seed (default 0)")
    demo.set_defaults(run=_demo)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    args = _parser().parse_args(argv)
    return int(args.run(args))


if __name__ == "__main__":
    sys.exit(main())
