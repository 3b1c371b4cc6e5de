"""Make the example figures of docs/figures.md (and the README) from real runs.

Run from the repository root: ``python docs/figures/make_figures.py`` (needs ``uavcov[plot]``;
about a minute on two cores). Every mission is one of the paper's experiments as
``uavcov reproduce`` runs it (settings from :mod:`uavcov.paper`); the Table 1 preview is a
short sweep (5 terrains, 150 iterations), not the published table, which
``uavcov reproduce table1`` makes. PNGs are written at a modest resolution and stored with a
256-colour palette to stay small.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from PIL import Image

from uavcov import paper, plotting
from uavcov.experiments import RunSpec, experiments_hash

HERE = Path(__file__).resolve().parent
DPI = 100


def _small(path: Path) -> Path:
    """Store a PNG with an adaptive 256-colour palette (a third of the size, same look)."""
    with Image.open(path) as im:
        im.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(path, optimize=True)
    return path


SETTINGS = f"uavcov.paper {experiments_hash(paper.EXPERIMENTS)}"


def _save(fig, name: str) -> None:
    path = HERE / name
    fig.text(0.998, 0.998, SETTINGS, ha="right", va="top", fontsize=7, color="0.45")  # the settings it was made with
    fig.savefig(path, dpi=DPI, bbox_inches="tight", pad_inches=0.1)
    _small(path)
    print(f"{name:<32} {path.stat().st_size / 1e3:6.0f} kB", flush=True)


def _run(experiment, seed: int, n: int, start: str, iterations: int | None = None):
    if iterations is not None:
        experiment = experiment.with_changes(iterations=iterations)
    return RunSpec(experiment, seed, n, start).run(n_threads=None)


def main() -> int:
    started = time.perf_counter()

    # Fig. 5: the illustrative example (9 UAVs, d_max = 35 m, 30 known points, CVT start).
    example = _run(paper.EXAMPLE, 0, 9, "cvt")
    _save(plotting.plot_approximation(example), "example_approximation.png")
    _save(plotting.plot_cvt(example), "example_cvt.png")
    _save(plotting.plot_coverage_map(example, configuration="best"), "example_coverage_map.png")
    _save(plotting.plot_coverage_curves(example, title="Fig. 5d: coverage during the optimisation"), "example_coverage_curve.png")
    _save(plotting.plot_point_cloud(example), "example_point_cloud.png")

    # Fig. 6: the three starts on one terrain (10 UAVs, d_max = 25 m), the paper's maxima dashed.
    comparison = {start: [_run(paper.COMPARISON, 0, 10, start)] for start in ("cvt", "random", "corner")}
    _save(plotting.plot_coverage_map(comparison["corner"][0], configuration="best"), "comparison_corner_coverage_map.png")
    gif = plotting.animate_mission(comparison["corner"][0], HERE / "comparison_corner_animation.gif", max_frames=40, raster=100, dpi=70)
    print(f"{gif.name:<32} {gif.stat().st_size / 1e3:6.0f} kB", flush=True)
    _save(
        plotting.plot_coverage_curves(
            comparison, reference=dict(paper.PUBLISHED_FIG6_MAX), title="Fig. 6: 10 UAVs, one terrain, three starts"
        ),
        "comparison_curves.png",
    )
    # The same over five terrains: mean and one sigma.
    five = {start: [_run(paper.COMPARISON, seed, 10, start, iterations=300) for seed in range(5)] for start in ("cvt", "random", "corner")}
    _save(
        plotting.plot_coverage_curves(five, title="10 UAVs, 5 terrains (seeds 0-4), 300 iterations: mean and one sigma"),
        "comparison_band.png",
    )

    # Figs. 7-8: the buildings scene (4 UAVs, d_max = 8 m), CVT on the simplified map vs two pairs.
    buildings = {start: [_run(paper.BUILDINGS, 0, 4, start)] for start in ("cvt", "pairs")}
    cvt_run = buildings["cvt"][0]
    _save(plotting.plot_approximation(cvt_run), "buildings_map.png")
    _save(plotting.plot_coverage_map(cvt_run, configuration="best"), "buildings_coverage_map.png")
    _save(plotting.plot_coverage_map(cvt_run, configuration="best", view="top"), "buildings_coverage_top.png")
    _save(plotting.plot_point_cloud(cvt_run), "buildings_point_cloud.png")
    _save(plotting.plot_coverage_curves(buildings, title="Fig. 8: buildings scene, CVT start against two pairs"), "buildings_curves.png")

    # Table 1 preview: 5 terrains x N x 3 starts, 150 iterations, beside the paper's values.
    rows = []
    for seed in range(5):
        for n in paper.TABLE1.team_sizes:
            for start in paper.TABLE1.starts:
                r = _run(paper.TABLE1, seed, n, start, iterations=150)
                rows.append(
                    {
                        "experiment": "table1",
                        "init": start,
                        "n_uavs": str(n),
                        "seed": str(seed),
                        "initial_coverage": repr(r.initial_coverage),
                        "max_coverage": repr(r.best_coverage),
                    }
                )
    fig = plotting.plot_table1(rows)
    fig.axes[0].set_title("Table 1 preview (5 terrains, 150 iterations) beside the paper (40 terrains, 500)", fontsize=10)
    _save(fig, "table1_preview.png")

    print(f"done in {time.perf_counter() - started:.0f} s, settings {SETTINGS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
