#!/usr/bin/env python
"""The cameras page's figure and table: one team of 6, the same positions, five sensors.

On a paper terrain (``uavcov.paper.TABLE1.terrain``, seed 0) six UAVs fly 25 m above the ground
at fixed positions; each row of the table is one sensor for all six (the paper's omnidirectional
one, and cameras nadir and oblique, with and without view-quality limits): coverage and
quality-weighted coverage. The figure is :func:`uavcov.plotting.plot_camera_views` for the
oblique survey camera.

    python scripts/camera_views.py OUT_DIR

writes ``OUT_DIR/camera_views.png`` and prints the table (Markdown) that docs/cameras.md quotes,
then flies one camera mission on the same terrain (8 UAVs, the 45 deg oblique 60 x 45 deg camera,
10-40 m above the ground, the footprint start, heading free, 150 CAO iterations, seed 0) and
writes its animation, ``OUT_DIR/camera_mission.gif``: footprints and headings at every frame.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from camera_experiment import CAMERA_CAO  # this folder's, as the script runs from it

import uavcov
from uavcov import paper
from uavcov.plotting import animate_mission, plot_camera_views

SURVEY = uavcov.Camera(sensor_width_mm=13.2, sensor_height_mm=8.8, focal_length_mm=8.8, image_width_px=5472, image_height_px=3648)
WIDE = uavcov.Camera.from_fov(84.0, 62.0)
NARROW = uavcov.Camera.from_fov(60.0, 45.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path)
    args = parser.parse_args()
    terrain = paper.TABLE1.terrain.make(0)
    xy = np.array([[20.0, 20.0], [50.0, 20.0], [80.0, 20.0], [20.0, 70.0], [50.0, 70.0], [80.0, 70.0]])
    positions = np.column_stack([xy, terrain.ground_height(xy) + 25.0])
    headings = np.array([0.0, 60.0, 120.0, 180.0, 240.0, 300.0])
    cases = [
        ("omnidirectional, 40 m (the paper's)", uavcov.Sensor(40.0), -90.0),
        ("nadir 84 x 62 deg, 40 m", uavcov.Sensor(40.0, camera=WIDE), -90.0),
        ("nadir 60 x 45 deg, 40 m", uavcov.Sensor(40.0, camera=NARROW), -90.0),
        ("1-inch survey camera, 45 deg oblique, 40 m", uavcov.Sensor(40.0, camera=SURVEY), -45.0),
        (
            "the same, at most 70 deg off the surface normal, full quality at 8 mm/px",
            uavcov.Sensor(40.0, camera=SURVEY, max_incidence_deg=70.0, good_gsd_m=0.008),
            -45.0,
        ),
    ]
    vis = uavcov.Visibility(terrain, 40.0)
    print("| sensor (all six UAVs) | coverage | quality-weighted coverage |")
    print("|---|---|---|")
    for name, sensor, pitch in cases:
        poses = np.column_stack([positions, headings, np.full(6, pitch)])
        sensors = [sensor] * 6
        print(f"| {name} | {vis.coverage(poses, sensors=sensors):.3f} | {vis.quality_coverage(poses, sensors=sensors):.3f} |")
    _, sensor, pitch = cases[-1]
    poses = np.column_stack([positions, headings, np.full(6, pitch)])
    args.out.mkdir(parents=True, exist_ok=True)
    plot_camera_views(terrain, poses, [sensor] * 6, out=args.out / "camera_views.png")
    print(f"\nwrote {args.out / 'camera_views.png'}")
    mission = uavcov.MissionSettings(
        n_uavs=8,
        d_max=40.0,
        iterations=150,
        sensor=uavcov.Sensor(40.0, camera=NARROW),
        attitude=(0.0, -45.0),
        gimbal=uavcov.Gimbal(free_yaw=True),
        footprint_start=True,
        start=uavcov.StartSettings(altitude=20.0, altitude_reference="prior", climb=1.0),
        constraints=uavcov.Constraints(h_min=10.0, h_max=40.0, z_max=80.0, d_safe=1.0),
        cao=CAMERA_CAO,  # the step docs/cameras.md's GIF was made with
    )
    result = uavcov.run_mission(terrain, mission, rng=0)
    animate_mission(result, args.out / "camera_mission.gif", max_frames=30, raster=120, dpi=70)
    print(f"camera mission: coverage {result.initial_coverage:.3f} -> {result.best_coverage:.3f}; wrote {args.out / 'camera_mission.gif'}")


if __name__ == "__main__":
    main()
