"""One evaluation with cameras against the paper's omnidirectional sensor, side by side.

The reference case of benches/README.md (7-Gaussian terrain on 100 m x 100 m, heights 5-25 m,
sigma 10 m, every grid node a target, 12 UAVs 5-30 m above the ground, d_max = 25 m), evaluated
with the omnidirectional sensor and with the same range through cameras (nadir 60 deg x 45 deg,
nadir 84 deg x 62 deg, 45 deg oblique 60 deg x 45 deg), and the nadir 60 deg camera with an
incidence limit and its quality-weighted coverage, in alternating blocks so that the machine's
noise falls on all alike. Prints the median per evaluation and its ratio to the case it is set
against.

    python benches/sensors.py [--spacing 0.5] [--threads 2] [--rounds 15]
"""

from __future__ import annotations

import argparse
import functools
import statistics
import time
from collections.abc import Callable

import numpy as np

import uavcov

CAMERAS = {
    "nadir 60 x 45": (uavcov.Camera.from_fov(60.0, 45.0), -90.0),
    "nadir 84 x 62": (uavcov.Camera.from_fov(84.0, 62.0), -90.0),
    "oblique 45, 60 x 45": (uavcov.Camera.from_fov(60.0, 45.0), -45.0),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--spacing", type=float, default=0.5)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--block", type=int, default=5, help="evaluations per timed block")
    args = parser.parse_args()
    terrain = uavcov.gaussian_hills(spacing=args.spacing, heights=(5.0, 25.0), sigma=10.0, rng=0)
    rng = np.random.default_rng(1)
    xy = rng.uniform(0.0, 100.0, size=(12, 2))
    z = terrain.ground_height(xy) + rng.uniform(5.0, 30.0, size=12)
    uavs = np.column_stack([xy, z])
    yaw = rng.uniform(0.0, 360.0, size=12)
    vis = uavcov.Visibility(terrain, 25.0, n_threads=args.threads)
    cases: dict[str, tuple[np.ndarray, list[uavcov.Sensor] | None]] = {"omnidirectional": (uavs, None)}
    for name, (camera, pitch) in CAMERAS.items():
        poses = np.column_stack([uavs, yaw, np.full(12, pitch)])
        cases[name] = (poses, [uavcov.Sensor(25.0, camera=camera)] * 12)
    # the nadir 60 deg camera rating its views: full quality at 1 cm per pixel, at most 60 deg off
    # the surface normal; its quality-weighted coverage against the same camera's plain coverage
    rated = [uavcov.Sensor(25.0, camera=CAMERAS["nadir 60 x 45"][0], good_gsd_m=0.01, max_incidence_deg=60.0)] * 12
    nadir_poses = cases["nadir 60 x 45"][0]
    calls: dict[str, tuple[Callable[[], float], str]] = {
        name: (functools.partial(vis.coverage, poses, sensors=sensors), "omnidirectional") for name, (poses, sensors) in cases.items()
    }
    calls["nadir 60 x 45, limited to 60 deg incidence"] = (functools.partial(vis.coverage, nadir_poses, sensors=rated), "nadir 60 x 45")
    calls["nadir 60 x 45, quality-weighted coverage"] = (
        functools.partial(vis.quality_coverage, nadir_poses, sensors=rated),
        "nadir 60 x 45",
    )
    times: dict[str, list[float]] = {name: [] for name in calls}
    value = {}
    for name, (call, _) in calls.items():  # untimed: builds the skylines, wakes the threads
        value[name] = call()
        call()
    for _ in range(args.rounds):
        for name, (call, _) in calls.items():
            t0 = time.perf_counter()
            for _ in range(args.block):
                call()
            times[name].append((time.perf_counter() - t0) / args.block)
    print(f"spacing {args.spacing} m, {args.threads} threads, median of {args.rounds} blocks of {args.block}")
    print("| sensor | value | ms per evaluation | ratio | against |")
    print("|---|---|---|---|---|")
    for name, samples in times.items():
        med = statistics.median(samples)
        against = calls[name][1]
        base = statistics.median(times[against])
        print(f"| {name} | {value[name]:.4f} | {1e3 * med:.3f} | {med / base:.2f} | {against} |")


if __name__ == "__main__":
    main()
