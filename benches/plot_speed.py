"""How long the figures take on large surfaces: a 447 x 447 grid (about 200k targets), the
buildings mesh and a fine buildings mesh (more triangles than are drawn), drawn and saved to PNG.

Run: ``python benches/plot_speed.py`` (needs the ``plot`` extra). Prints one line
per figure: seconds to build the figure and seconds to render and save it. The coverage map of
the grid computes visibility for all 200k targets and draws at most ``max_polygons`` quads, so
its cost does not grow with the number of targets beyond the visibility pass.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

import uavcov
from uavcov import plotting


def _timed(label: str, build, out: Path) -> None:
    t0 = time.perf_counter()
    fig = build()
    t1 = time.perf_counter()
    fig.savefig(out, dpi=110)
    t2 = time.perf_counter()
    print(f"{label:<44} build {t1 - t0:6.2f} s   render+save {t2 - t1:6.2f} s   total {t2 - t0:6.2f} s")


def main() -> None:
    # Importing matplotlib takes a second or two once per process: not what is measured here.
    from matplotlib.figure import Figure

    Figure().add_subplot(projection="3d")
    rng = np.random.default_rng(0)
    hills = uavcov.gaussian_hills(size=100.0, spacing=100.0 / 446, rng=0)
    targets = len(hills.default_targets())
    uavs = np.column_stack([rng.uniform(5, 95, (12, 2)), np.zeros(12)])
    uavs[:, 2] = hills.ground_height(uavs[:, :2]) + 12.0
    trajectory = uavs[None] + np.cumsum(rng.normal(scale=0.5, size=(200, 12, 3)), axis=0) * [1, 1, 0.2]
    scene = uavcov.terrain.buildings_scene(rng=0)
    scene_uavs = np.array([[6.0, 6.0, 12.0], [18.0, 6.0, 12.0], [6.0, 18.0, 12.0], [18.0, 18.0, 12.0]])
    print(f"grid: {hills!r}, {targets} targets; scene: {scene!r}")
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        t0 = time.perf_counter()
        uavcov.Visibility(hills, 25.0).seen(uavs)
        print(f"{'(visibility of every grid target, once)':<44} {time.perf_counter() - t0:6.2f} s")
        _timed(
            "coverage map 3D, 200k-target grid", lambda: plotting.plot_coverage_map(hills, uavs, 25.0, trajectory=trajectory), out / "a.png"
        )
        _timed(
            "coverage map top view, 200k-target grid",
            lambda: plotting.plot_coverage_map(hills, uavs, 25.0, trajectory=trajectory, view="top"),
            out / "b.png",
        )
        _timed("coverage map 3D, buildings mesh", lambda: plotting.plot_coverage_map(scene, scene_uavs, 8.0), out / "c.png")
        _timed(
            "coverage map top view, buildings mesh", lambda: plotting.plot_coverage_map(scene, scene_uavs, 8.0, view="top"), out / "d.png"
        )
        fine = uavcov.terrain.buildings_scene(spacing=0.125, rng=0)
        print(f"fine scene: {fine!r}")
        _timed("coverage map 3D, fine mesh (clustered)", lambda: plotting.plot_coverage_map(fine, scene_uavs, 8.0), out / "f.png")
        points = hills.default_targets().points
        _timed("point cloud, 200k points (30k drawn)", lambda: plotting.plot_point_cloud(points), out / "e.png")


if __name__ == "__main__":
    main()
