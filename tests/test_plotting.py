"""Figures: each renders and is not blank, colours agree with the engine, bad input is refused.

Everything runs on small terrains and short missions. Figures are rendered with Agg into
arrays; the colour checks compare what is drawn with masks recomputed here from
``Visibility.seen``, not with anything the plotting module computed.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import shutil
import sys
import types

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import uavcov
from uavcov import Targets, Visibility, plotting
from uavcov.errors import InvalidInputError, InvalidTypeError, ResultsFormatError
from uavcov.plotting import _curves as curve_figures
from uavcov.plotting import _directory as directory
from uavcov.plotting import _figures as figures
from uavcov.plotting import _runs
from uavcov.plotting import _views as views
from uavcov.records import save_mission


def _render(fig) -> np.ndarray:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[:, :, :3].astype(np.float64)


def _set_colours(coll) -> np.ndarray:
    """The face colours as set, in polygon order (``get_facecolor`` of a 3D collection returns
    them depth-sorted for the current view)."""
    return np.asarray(coll._facecolor3d)[:, :3]


def _assert_not_blank(image: np.ndarray) -> None:
    assert image.std() > 20.0, f"image looks blank (std {image.std():.1f})"
    non_white = (image < 245).any(axis=2).mean()
    assert non_white > 0.03, f"only {non_white:.1%} of the pixels are drawn on"
    colours = np.unique((image[::3, ::3] // 8).reshape(-1, 3), axis=0).shape[0]
    assert colours > 30, f"only {colours} distinct colours"


@pytest.fixture(scope="module")
def hills():
    return uavcov.gaussian_hills(size=40.0, spacing=2.0, rng=1)


@pytest.fixture(scope="module")
def hills_runs(hills):
    """Three starts x two seeds on the same hills."""
    return [
        uavcov.run_mission(
            hills, uavcov.MissionSettings(n_uavs=4, d_max=15.0, iterations=12, start=uavcov.StartSettings(kind=start)), rng=seed
        )
        for start in ("cvt", "random", "corner")
        for seed in (1, 2)
    ]


@pytest.fixture(scope="module")
def hills_run(hills_runs):
    return hills_runs[0]


@pytest.fixture(scope="module")
def scene_run():
    scene = uavcov.terrain.buildings_scene(size=12.0, n_buildings=2, footprint=(2.0, 4.0), heights=(2.0, 5.0), spacing=1.0, rng=0)
    spec = uavcov.MissionSettings(
        n_uavs=3, d_max=6.0, iterations=8, constraints=uavcov.Constraints(h_min=1.0, z_max=12.0, d_safe=1.0, check_moves=None)
    )
    return uavcov.run_mission(scene, spec, rng=1)


def _both_kinds(fraction: np.ndarray) -> None:
    """A colour check means little unless the case has seen and unseen parts."""
    assert (fraction > 0.99).any() and (fraction < 0.01).any()


# ---------------------------------------------------------------------------------------------
# Every figure renders and is not blank


def test_approximation_renders(hills_run):
    fig = plotting.plot_approximation(hills_run)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "x (m)" and ax.get_ylabel() == "y (m)" and ax.get_zlabel().startswith("z (m")
    assert ax.get_legend() is not None
    _assert_not_blank(_render(fig))


def test_approximation_of_a_terrain_needs_the_approximation(hills_run):
    fig = plotting.plot_approximation(hills_run.terrain, approximation=hills_run.approximation, prior_points=hills_run.prior_points)
    _assert_not_blank(_render(fig))
    with pytest.raises(InvalidInputError, match="approximation"):
        plotting.plot_approximation(hills_run.terrain)


def test_outline_of_a_fine_surface_is_its_creases_and_border():
    x = np.arange(31.0)
    flat = uavcov.Terrain.from_grid(np.zeros((31, 31)), spacing=1.0)
    flat_mesh = uavcov.Terrain(flat.vertices, flat.faces)
    edges, which = views._outline_edges(flat_mesh)
    assert which == "its creases and borders" and len(edges) == 4 * 30
    ends = flat_mesh.vertices[edges]

    def on_border(p):
        return np.isin(p[:, 0], (0, 30)) | np.isin(p[:, 1], (0, 30))

    assert on_border(ends[:, 0]).all() and on_border(ends[:, 1]).all()
    # A roof ridge along x = 15 (slopes of 45 degrees either side) adds its 30 edges.
    roof = uavcov.Terrain.from_grid(np.tile(15.0 - np.abs(x - 15.0), (31, 1)), spacing=1.0)
    edges, _ = views._outline_edges(uavcov.Terrain(roof.vertices, roof.faces))
    assert len(edges) == 4 * 30 + 30
    coarse, which = views._outline_edges(uavcov.Terrain.from_grid(np.zeros((3, 3)), spacing=1.0))
    assert which == "its triangles" and len(coarse) == 16


def test_cvt_renders_and_colours_follow_the_regions(hills_run):
    fig = plotting.plot_cvt(hills_run)
    _assert_not_blank(_render(fig))
    # Each polygon has the palette colour of the region (nearest generator, by the engine) of a
    # point of the surface inside it; shading only scales a colour, so its direction tells.
    fig = plotting.plot_cvt(hills_run.approximation, cvt=hills_run.cvt, max_polygons=3000)
    coll = fig.axes[0].collections[0]
    colours = _set_colours(coll)
    probes = coll.uavcov_probes
    surface = hills_run.approximation
    np.testing.assert_allclose(surface.closest_point(probes), probes, atol=1e-7)
    region = hills_run.cvt.regions(probes)
    assert len(np.unique(region)) == hills_run.cvt.n_generators
    palette = figures._region_colours(hills_run.cvt.n_generators)
    unit = colours / np.linalg.norm(colours, axis=1, keepdims=True)
    expected = palette[region] / np.linalg.norm(palette[region], axis=1, keepdims=True)
    np.testing.assert_allclose(unit, expected, atol=1e-9)


def test_coverage_map_renders_grid_and_mesh(hills_run, scene_run):
    for run in (hills_run, scene_run):
        for view in ("3d", "top"):
            fig = plotting.plot_coverage_map(run, view=view)
            ax = fig.axes[0]
            assert ax.get_xlabel() == "x (m)" and ax.get_ylabel() == "y (m)"
            labels = [t.get_text() for t in ax.get_legend().get_texts()]
            assert "seen by at least one UAV" in labels and "not seen" in labels
            assert "start positions" in labels
            _assert_not_blank(_render(fig))


def test_coverage_curves_mean_and_band(hills_runs):
    fig = plotting.plot_coverage_curves(hills_runs)
    _assert_not_blank(_render(fig))
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert [label.split(" ")[0] for label in labels] == ["cvt", "random", "corner"]
    # The thick line of each group is the mean of its runs' curves.
    cvt_curves = np.array([r.coverage for r in hills_runs if r.settings.start.kind == "cvt"])
    thick = [line for line in ax.lines if line.get_linewidth() > 1.5]
    assert len(thick) == 3
    np.testing.assert_allclose(thick[0].get_ydata(), cvt_curves.mean(axis=0))
    # The band spans one sigma either side.
    band = ax.collections[0].get_paths()[0].vertices
    sigma = cvt_curves.std(axis=0, ddof=1)
    assert np.isclose(band[:, 1].max(), (cvt_curves.mean(axis=0) + sigma).max())
    assert np.isclose(band[:, 1].min(), (cvt_curves.mean(axis=0) - sigma).min())


def test_curves_of_different_lengths_average_the_runs_that_reached_each_iteration():
    curves = [np.array([0.1, 0.2, 0.3, 0.4]), np.array([0.3, 0.2]), np.array([0.5, 0.5, 0.6])]
    mean, sigma, count = curve_figures._curve_stats(curves)
    for k in range(4):
        here = [c[k] for c in curves if k < len(c)]
        assert count[k] == len(here)
        assert np.isclose(mean[k], np.mean(here))
        assert np.isclose(sigma[k], np.std(here, ddof=1) if len(here) > 1 else 0.0)


def test_coverage_curves_running_max_and_mapping(hills_runs):
    fig = plotting.plot_coverage_curves({"first": hills_runs[:2], "second": hills_runs[2]}, running_max=True)
    ax = fig.axes[0]
    thick = [line for line in ax.lines if line.get_linewidth() > 1.5]
    np.testing.assert_allclose(thick[1].get_ydata(), np.maximum.accumulate(hills_runs[2].coverage))
    assert np.all(np.diff(thick[0].get_ydata()) >= 0)


def _rows(results, experiment="table1"):
    return [
        {
            "run_id": f"{experiment}-{i}",
            "experiment": experiment,
            "init": r.settings.start.kind,
            "n_uavs": str(r.settings.n_uavs),
            "seed": str(i),
            "sensing_range": str(r.settings.d_max),
            "initial_coverage": repr(r.initial_coverage),
            "max_coverage": repr(r.best_coverage),
            "final_coverage": repr(r.final_coverage),
            "iterations_to_95": str(r.iterations_to_95),
            "wall_time_s": repr(r.wall_time_s),
        }
        for i, r in enumerate(results)
    ]


def test_table1_bars_are_the_means_beside_the_paper():
    rng = np.random.default_rng(0)
    rows = [
        {
            "experiment": "table1",
            "init": init,
            "n_uavs": str(n),
            "seed": str(seed),
            "max_coverage": f"{rng.uniform(0.4, 0.9):.6f}",
            "initial_coverage": "0.5",
        }
        for init in ("cvt", "random", "corner")
        for n in (5, 8)
        for seed in range(4)
    ]
    rows.append(
        {"experiment": "table1", "init": "cvt", "n_uavs": "5", "seed": "9", "max_coverage": "", "initial_coverage": ""}
    )  # a failed run
    fig = plotting.plot_table1(rows)
    _assert_not_blank(_render(fig))
    ax = fig.axes[0]
    assert "1 failed" in ax.get_title()
    heights = sorted(round(p.get_height(), 6) for p in ax.patches)
    for init in ("cvt", "random", "corner"):
        for n in (5, 8):
            ours = [float(r["max_coverage"]) for r in rows if r["init"] == init and r["n_uavs"] == str(n) and r["max_coverage"]]
            assert round(float(np.mean(ours)), 6) in heights
            assert round(uavcov.paper._data.PUBLISHED_TABLE1[(n, init, "max")].mean, 6) in heights
    assert len(ax.patches) == 12  # 3 starts x 2 sizes x (ours, paper)


def test_table1_takes_typed_rows_with_failed_runs_as_none():
    rows = [
        {"experiment": "pyramid", "init": "cvt", "n_uavs": 12, "seed": s, "max_coverage": v, "error": ""}
        for s, v in enumerate([0.9, 0.94, 0.91])
    ]
    rows.append({"experiment": "pyramid", "init": "cvt", "n_uavs": 12, "seed": 9, "max_coverage": None, "error": "InfeasibleError: ..."})
    ax = plotting.plot_table1(rows).axes[0]
    assert "1 failed" in ax.get_title()
    heights = sorted(p.get_height() for p in ax.patches)
    assert np.allclose(heights, sorted([np.mean([0.9, 0.94, 0.91]), uavcov.paper._data.PUBLISHED_PYRAMID["max"].mean]))


def test_table1_from_real_rows_without_paper_values(hills_runs, tmp_path):
    path = tmp_path / "runs.csv"
    rows = _rows(hills_runs, experiment="sweep")
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    fig = plotting.plot_table1(path)
    assert len(fig.axes[0].patches) == 3  # no paper bars for an experiment the paper does not have
    _assert_not_blank(_render(fig))


def test_point_cloud_renders_and_is_the_union_of_seen_targets(hills_run, tmp_path):
    ply = tmp_path / "seen.ply"
    fig = plotting.plot_point_cloud(hills_run, ply=ply, max_configurations=1000)
    _assert_not_blank(_render(fig))
    vis = Visibility(hills_run.terrain, hills_run.settings.d_max)
    union = np.zeros(len(vis.targets), dtype=bool)
    for x in hills_run.trajectory:
        union |= vis.seen(x)
    expected = vis.targets.points[union]
    np.testing.assert_array_equal(plotting._figures.seen_points(hills_run, max_configurations=1000), expected)
    trimesh = pytest.importorskip("trimesh")
    cloud = trimesh.load(ply)
    np.testing.assert_allclose(np.asarray(cloud.vertices), expected, atol=1e-6)


def test_write_ply_with_colours_reads_back(tmp_path):
    pts = np.array([[0.0, 1.5, -2.25], [3.0, 4.0, 5.0]])
    path = plotting._writers.write_ply(pts, tmp_path / "c.ply", colors=np.array([[1.0, 0.0, 0.5], [0.0, 1.0, 0.0]]))
    lines = path.read_text().splitlines()
    assert lines[0] == "ply" and "element vertex 2" in lines and lines.index("end_header") == len(lines) - 3
    body = np.array([line.split() for line in lines[-2:]], dtype=float)
    np.testing.assert_allclose(body[:, :3], pts)
    np.testing.assert_array_equal(body[:, 3:], [[255, 0, 128], [0, 255, 0]])
    empty = plotting._writers.write_ply(np.empty((0, 3)), tmp_path / "e.ply")
    assert "element vertex 0" in empty.read_text()
    assert "element vertex 0" in plotting._writers.write_ply([], tmp_path / "none.ply").read_text()  # [] is no points too
    with pytest.raises(InvalidInputError):
        plotting._writers.write_ply(pts, tmp_path / "x.ply", colors=[[300, 0, 0], [0, 0, 0]])
    with pytest.raises(InvalidInputError):
        plotting._writers.write_ply([[0.0, np.nan, 0.0]], tmp_path / "x.ply")


def test_animation_gif(hills_run, tmp_path):
    from PIL import Image

    path = plotting.animate_mission(hills_run, tmp_path / "run.gif", max_frames=5, raster=40, dpi=50)
    with Image.open(path) as im:
        assert im.n_frames == 5
        im.seek(2)
        _assert_not_blank(np.asarray(im.convert("RGB"), dtype=float))


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="ffmpeg is not on the PATH")
def test_animation_mp4(hills_run, tmp_path):
    import subprocess

    path = plotting.animate_mission(hills_run, tmp_path / "run.mp4", max_frames=4, raster=40, dpi=50)
    # Decode it back: 4 frames of real pictures.
    raw = subprocess.run(
        ["ffmpeg", "-loglevel", "error", "-i", str(path), "-f", "rawvideo", "-pix_fmt", "rgb24", "-vf", "scale=100:50", "-"],
        capture_output=True,
        check=True,
    ).stdout
    frames = np.frombuffer(raw, dtype=np.uint8).reshape(-1, 50, 100, 3)
    assert frames.shape[0] == 4
    _assert_not_blank(frames[-1].astype(float))


def test_animation_mp4_without_ffmpeg_is_refused(hills_run, tmp_path, monkeypatch):
    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(InvalidInputError, match="ffmpeg"):
        plotting.animate_mission(hills_run, tmp_path / "run.mp4")


def test_paths_end_at_the_configuration_shown(hills_run):
    best = hills_run.best_iteration
    fig = plotting.plot_coverage_map(hills_run, configuration="best")
    ax = fig.axes[0]
    paths = [line for line in ax.lines if line.get_linestyle() == "-"]
    assert len(paths) == hills_run.trajectory.shape[1]
    for i, line in enumerate(paths):
        x, y, z = line.get_data_3d()
        np.testing.assert_allclose(np.column_stack([x, y, z]), hills_run.trajectory[: best + 1, i])
    np.testing.assert_allclose(hills_run.trajectory[best], hills_run.best_positions)
    assert f"best positions (iteration {best})" in [t.get_text() for t in ax.get_legend().get_texts()]


def test_into_given_axes(hills_run):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 4))
    left = fig.add_subplot(1, 2, 1, projection="3d")
    right = fig.add_subplot(1, 2, 2)
    assert plotting.plot_coverage_map(hills_run, ax=left) is fig
    assert plotting.plot_coverage_curves(hills_run, ax=right) is fig
    _assert_not_blank(_render(fig))


# ---------------------------------------------------------------------------------------------
# Colours agree with the engine's mask


def test_grid_coverage_colours_match_the_engine(hills_run):
    terrain = hills_run.terrain
    grid = terrain.grid
    final = hills_run.trajectory[-1]
    vis = Visibility(terrain, hills_run.settings.d_max)
    np.testing.assert_array_equal(vis.targets.points, terrain.vertices)  # grid targets: the nodes, in order
    nodes = vis.seen(final).reshape(grid.shape).astype(float)
    fig = plotting.plot_coverage_map(hills_run, shade=False, max_polygons=10**6)
    coll = fig.axes[0].collections[0]
    colours = _set_colours(coll)
    centres = coll.uavcov_probes
    assert len(colours) == (grid.shape[0] - 1) * (grid.shape[1] - 1)
    j = np.floor((centres[:, 0] - grid.origin[0]) / grid.spacing[0]).astype(int)
    i = np.floor((centres[:, 1] - grid.origin[1]) / grid.spacing[1]).astype(int)
    fraction = (nodes[i, j] + nodes[i + 1, j] + nodes[i, j + 1] + nodes[i + 1, j + 1]) / 4.0
    _both_kinds(fraction)
    expected = (1 - fraction)[:, None] * plotting.UNSEEN_COLOUR + fraction[:, None] * np.array(plotting.SEEN_COLOUR)
    np.testing.assert_allclose(colours, expected, atol=1e-9)


def test_grid_top_view_pixels_match_the_engine(hills_run):
    terrain = hills_run.terrain
    final = hills_run.trajectory[-1]
    nodes = Visibility(terrain, hills_run.settings.d_max).seen(final).reshape(terrain.grid.shape)
    fig = plotting.plot_coverage_map(hills_run, view="top", shade=False)
    image = np.asarray(fig.axes[0].images[0].get_array())
    assert image.shape[:2] == nodes.shape  # one pixel per node: no decimation on a small grid
    _both_kinds(nodes.astype(float))
    np.testing.assert_allclose(image[nodes][:, :3], np.broadcast_to(plotting.SEEN_COLOUR, (nodes.sum(), 3)))
    np.testing.assert_allclose(image[~nodes][:, :3], np.broadcast_to(plotting.UNSEEN_COLOUR, ((~nodes).sum(), 3)))


@pytest.mark.parametrize("cut", [False, True], ids=["one-polygon-per-face", "faces-subdivided"])
def test_mesh_coverage_colours_match_the_engine(scene_run, cut):
    terrain = scene_run.terrain
    final = scene_run.trajectory[-1]
    budget = 8 * terrain.n_faces if cut else terrain.n_faces
    fig = plotting.plot_coverage_map(scene_run, shade=False, max_polygons=budget)
    coll = fig.axes[0].collections[0]
    colours = _set_colours(coll)
    probes = coll.uavcov_probes
    if cut:
        assert terrain.n_faces < len(probes) <= budget
        np.testing.assert_allclose(terrain.closest_point(probes), probes, atol=1e-9)
    else:
        centroids = terrain.vertices[terrain.faces].mean(axis=1)

        def order(p):
            return p[np.lexsort(np.round(p, 9).T)]

        np.testing.assert_allclose(order(probes), order(centroids))  # one polygon per face, at its centre
    seen = Visibility(terrain, scene_run.settings.d_max, Targets(probes)).seen(final)
    _both_kinds(seen.astype(float))
    expected = np.where(seen[:, None], plotting.SEEN_COLOUR, plotting.UNSEEN_COLOUR)
    np.testing.assert_allclose(colours, expected, atol=1e-9)


def test_decimated_grid_blocks_are_brute_force_means(hills):
    rng = np.random.default_rng(3)
    polys = views._surface_polygons(hills, 60)
    assert len(polys) <= 60
    values = rng.uniform(size=hills.grid.shape)
    values[0, 5] = np.nan
    means = views._block_means(values, polys.blocks)
    for (r0, r1, c0, c1), mean in zip(polys.blocks, means, strict=False):
        assert np.isclose(mean, np.nanmean(values[r0 : r1 + 1, c0 : c1 + 1]))


def test_decimated_mesh_stays_under_budget_and_on_the_surface(scene_run):
    terrain = scene_run.terrain
    polys = views._surface_polygons(terrain, 200)
    assert 0 < len(polys) <= 200
    np.testing.assert_allclose(terrain.closest_point(polys.probes), polys.probes, atol=1e-9)
    fig = plotting.plot_coverage_map(scene_run, max_polygons=200)
    _assert_not_blank(_render(fig))


# ---------------------------------------------------------------------------------------------
# Redrawing a results directory


def test_plot_directory_redraws_everything(hills_runs, tmp_path, monkeypatch):
    (tmp_path / "runs").mkdir()
    rows = _rows(hills_runs)
    random_index = next(i for i, r in enumerate(hills_runs) if r.settings.start.kind == "random")
    corner_index = next(i for i, r in enumerate(hills_runs) if r.settings.start.kind == "corner")
    given = hills_runs[corner_index]
    save_mission(hills_runs[random_index], tmp_path / "runs" / f"{rows[random_index]['run_id']}.npz")
    save_mission(given, tmp_path / "runs" / f"{rows[corner_index]['run_id']}.npz")
    with (tmp_path / "runs.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    drawn_groups = []
    original = plotting.plot_coverage_curves

    def spy(results, **kwargs):
        drawn_groups.append({k: [np.asarray(r.coverage) for r in v] for k, v in results.items()})
        return original(results, **kwargs)

    monkeypatch.setattr(directory, "plot_coverage_curves", spy)  # where plot_directory looks it up
    written = plotting.plot_directory(tmp_path, max_runs=1, dpi=60)
    names = {p.name for p in written}
    first = rows[random_index]["run_id"]
    assert names == {
        "table1_max_coverage.png",
        "table1_initial_coverage.png",
        "table1_coverage_N4_d15.png",
        f"{first}_approximation.png",
        f"{first}_coverage_map.png",
        f"{first}_coverage_top.png",
        f"{first}_point_cloud.png",
        f"{first}_seen.ply",
        f"{first}_animation.gif",
    }  # no CVT: random
    assert len(drawn_groups) == 1 and set(drawn_groups[0]) == {"random", "corner"}
    np.testing.assert_array_equal(drawn_groups[0]["corner"][0], hills_runs[corner_index].coverage)
    assert all(p.parent == tmp_path / "figures" and p.stat().st_size > 0 for p in written)
    from PIL import Image

    for p in written:
        if p.suffix == ".png":
            with Image.open(p) as im:
                _assert_not_blank(np.asarray(im.convert("RGB"), dtype=float))


def test_plot_directory_draws_the_same_from_text_rows(hills_runs, tmp_path, monkeypatch):
    """Rows with parsed cells (uavcov.experiments._results.read_runs) and rows of strings (the csv module's)
    give the same files, byte for byte."""
    results = tmp_path / "results"
    (results / "runs").mkdir(parents=True)
    rows = _rows(hills_runs)
    failed = dict.fromkeys(rows[0], "")
    failed.update(run_id="table1-failed", experiment="table1", init="cvt", n_uavs="4", seed="9")
    rows.append(failed)
    save_mission(hills_runs[0], results / "runs" / f"{rows[0]['run_id']}.npz")
    with (results / "runs.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    parsed = _runs._read_runs(results / "runs.csv")
    assert isinstance(parsed[0]["n_uavs"], int) and parsed[-1]["max_coverage"] is None
    as_numbers = plotting.plot_directory(results, out=tmp_path / "numbers", max_runs=0, animation=False, dpi=40)

    def text_reader(path):
        with open(path, newline="") as handle:
            return list(csv.DictReader(handle))

    monkeypatch.setattr(_runs, "_read_runs", text_reader)
    as_text = plotting.plot_directory(results, out=tmp_path / "text", max_runs=0, animation=False, dpi=40)
    assert (
        [p.name for p in as_text]
        == [p.name for p in as_numbers]
        == ["table1_max_coverage.png", "table1_initial_coverage.png", "table1_coverage_N4_d15.png"]
    )
    for text, numbers in zip(as_text, as_numbers, strict=False):
        assert text.read_bytes() == numbers.read_bytes(), text.name


def test_plot_directory_of_single_runs_draws_no_bars(hills_run, tmp_path):
    (tmp_path / "runs").mkdir()
    rows = _rows([hills_run], experiment="example")
    save_mission(hills_run, tmp_path / "runs" / f"{rows[0]['run_id']}.npz")
    with (tmp_path / "runs.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    written = plotting.plot_directory(tmp_path, out=tmp_path / "elsewhere", max_runs=0, dpi=50)
    assert [p.name for p in written] == ["example_coverage_N4_d15.png"]
    assert written[0].parent == tmp_path / "elsewhere"


# ---------------------------------------------------------------------------------------------
# Bad input: clear messages, never a traceback from inside matplotlib


def test_empty_results_are_refused():
    with pytest.raises(ResultsFormatError, match="empty"):
        plotting.plot_coverage_curves([])
    with pytest.raises(ResultsFormatError, match="empty"):
        plotting.plot_table1([])
    with pytest.raises(ResultsFormatError, match="no result"):
        plotting.plot_coverage_map(None)


def test_missing_fields_are_named(hills_run):
    partial = types.SimpleNamespace(terrain=hills_run.terrain, settings=hills_run.settings)
    with pytest.raises(ResultsFormatError, match="missing trajectory"):
        plotting.plot_coverage_map(partial)
    with pytest.raises(ResultsFormatError, match="approximation"):
        plotting.plot_approximation(types.SimpleNamespace(terrain=hills_run.terrain, prior_points=np.zeros((0, 3))))
    no_range = dataclasses.replace(hills_run, settings=types.SimpleNamespace(start=types.SimpleNamespace(kind="cvt")))
    with pytest.raises(ResultsFormatError, match="d_max"):
        plotting.plot_coverage_map(no_range)
    with pytest.raises(ResultsFormatError, match="missing d_max"):
        plotting._figures.seen_points(no_range)
    with pytest.raises(ResultsFormatError, match="start"):
        plotting.plot_coverage_curves([hills_run, types.SimpleNamespace(coverage=np.ones(3), settings=None)])


def _with_trace(result, **changes):
    """``result`` whose optimiser's record has ``changes`` (the result reads its trajectory and coverage there)."""
    return dataclasses.replace(result, trace=dataclasses.replace(result.trace, **changes))


def test_empty_or_broken_arrays_are_refused(hills_run):
    with pytest.raises(ResultsFormatError, match="empty"):
        plotting.plot_coverage_map(_with_trace(hills_run, trajectory=np.empty((0, 4, 3))))
    bad = hills_run.trajectory.copy()
    bad[3, 1, 2] = np.nan
    with pytest.raises(ResultsFormatError, match="NaN"):
        plotting.animate_mission(_with_trace(hills_run, trajectory=bad), "x.gif")
    with pytest.raises(ResultsFormatError, match="coverage curve"):
        plotting.plot_coverage_curves(_with_trace(hills_run, values=np.array([])))


def test_run_without_cvt_is_refused(hills_runs):
    random_start = next(r for r in hills_runs if r.settings.start.kind == "random")
    with pytest.raises(ResultsFormatError, match=r"no CVT.*random"):
        plotting.plot_cvt(random_start)


def test_older_or_broken_run_files_are_refused(hills_run, tmp_path):
    path = save_mission(hills_run, tmp_path / "old.npz")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["header"] = np.array(str(arrays["header"]).replace("uavcov.mission/2", "uavcov.mission/0"))
    np.savez(tmp_path / "old.npz", **arrays)
    with pytest.raises(ResultsFormatError, match="format"):
        plotting.plot_coverage_map(tmp_path / "old.npz")
    del arrays["coverage"]
    arrays["header"] = np.array(str(arrays["header"]).replace("uavcov.mission/0", "uavcov.mission/2"))
    np.savez(tmp_path / "partial.npz", **arrays)
    with pytest.raises(ResultsFormatError, match="coverage"):
        plotting.plot_coverage_curves([tmp_path / "partial.npz"])
    (tmp_path / "runs").mkdir()
    shutil.copy(tmp_path / "partial.npz", tmp_path / "runs" / "partial.npz")
    with pytest.raises(ResultsFormatError, match=r"partial.npz is missing coverage"):
        plotting.plot_directory(tmp_path)


def test_bad_runs_csv_is_refused(tmp_path):
    with pytest.raises(ResultsFormatError, match="no results directory"):
        plotting.plot_directory(tmp_path / "nowhere")
    with pytest.raises(ResultsFormatError, match=r"neither runs.csv nor"):
        plotting.plot_directory(tmp_path)
    (tmp_path / "runs.csv").write_text("experiment,init,seed\ntable1,cvt,0\n")
    with pytest.raises(ResultsFormatError, match="n_uavs, max_coverage"):
        plotting.plot_directory(tmp_path)
    (tmp_path / "runs.csv").write_text("")
    with pytest.raises(ResultsFormatError, match=r"empty runs.csv"):
        plotting.plot_directory(tmp_path)
    (tmp_path / "runs.csv").write_bytes(b"\x89PNG\r\n\x1a\n\x00\xff\n")
    with pytest.raises(ResultsFormatError, match="not UTF-8"):
        plotting.plot_directory(tmp_path)
    rows = [{"experiment": "t", "init": "cvt", "n_uavs": "5", "max_coverage": "lots"}]
    with pytest.raises(ResultsFormatError, match="'lots' is not a number"):
        plotting.plot_table1(rows)
    with pytest.raises(ResultsFormatError, match="'init'"):
        plotting.plot_table1([{"experiment": "t", "n_uavs": "5", "max_coverage": "0.5"}])
    with pytest.raises(ResultsFormatError, match="no run has a value"):
        plotting.plot_table1([{"experiment": "t", "init": "cvt", "n_uavs": "5", "max_coverage": ""}])


def test_bad_arguments_are_refused(hills_run, tmp_path):
    from matplotlib.figure import Figure

    flat = Figure().add_subplot()
    with pytest.raises(InvalidInputError, match="3D"):
        plotting.plot_coverage_map(hills_run, ax=flat)
    with pytest.raises(InvalidTypeError, match="Axes"):
        plotting.plot_coverage_map(hills_run, ax="axes")
    with pytest.raises(InvalidInputError, match="configuration"):
        plotting.plot_coverage_map(hills_run, configuration="middle")
    with pytest.raises(InvalidInputError, match="configuration"):
        plotting.plot_coverage_map(hills_run, configuration=np.zeros(3))
    with pytest.raises(InvalidInputError, match="outside"):
        plotting.plot_coverage_map(hills_run, configuration=10**6)
    with pytest.raises(InvalidInputError, match="view"):
        plotting.plot_coverage_map(hills_run, view="side")
    with pytest.raises(InvalidInputError, match="max_polygons"):
        plotting.plot_coverage_map(hills_run, max_polygons=0)
    with pytest.raises(InvalidTypeError, match="max_polygons"):  # a count, not rounded
        plotting.plot_coverage_map(hills_run, max_polygons=2.5)
    with pytest.raises(InvalidInputError, match="fps"):
        plotting.animate_mission(hills_run, tmp_path / "run.gif", fps=0)
    with pytest.raises(InvalidInputError, match="d_max"):
        plotting.plot_coverage_map(hills_run.terrain, hills_run.trajectory[-1], -1.0)
    with pytest.raises(InvalidInputError, match="positions"):
        plotting.plot_coverage_map(hills_run.terrain, [[1.0, 2.0]], 10.0)
    with pytest.raises(InvalidInputError, match=r".gif or .mp4"):
        plotting.animate_mission(hills_run, tmp_path / "run.avi")
    with pytest.raises(InvalidTypeError, match="CVTResult"):
        plotting.plot_cvt(hills_run.approximation, cvt="generators")


def test_missing_matplotlib_names_the_extra(hills_run, monkeypatch):
    for name in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(ImportError, match=r"uavcov\[plot\]"):
        plotting.plot_coverage_curves(hills_run)


def test_saving_to_a_path(hills_run, tmp_path):
    out = tmp_path / "sub" / "curve.png"
    plotting.plot_coverage_curves(hills_run, out=out)
    from PIL import Image

    with Image.open(out) as im:
        _assert_not_blank(np.asarray(im.convert("RGB"), dtype=float))
    buffer = io.BytesIO()
    plotting.plot_coverage_curves(hills_run).savefig(buffer, format="png")
    assert buffer.getvalue()[:8] == b"\x89PNG\r\n\x1a\n"


def test_camera_views_draw_each_footprint_and_the_quality_map(tmp_path):
    terrain = uavcov.gaussian_hills(spacing=2.0, rng=3)
    xy = np.array([[25.0, 25.0], [70.0, 30.0], [50.0, 75.0]])
    poses = np.column_stack([xy, terrain.ground_height(xy) + 25.0, [0.0, 45.0, 200.0], [-90.0, -60.0, -40.0]])
    camera = uavcov.Camera(13.2, 8.8, 8.8, 5472, 3648)
    sensors = [uavcov.Sensor(60.0, camera=camera, good_gsd_m=0.006, max_incidence_deg=75.0)] * 3
    fig = plotting.plot_camera_views(terrain, poses, sensors, out=tmp_path / "cameras.png")
    assert (tmp_path / "cameras.png").stat().st_size > 10_000
    left, right = fig.axes[:2]
    # each footprint's outline is the hull of what that camera sees on its own
    outlines = plotting.footprints(terrain, poses, sensors)
    vis = uavcov.Visibility(terrain, 60.0)
    for i, outline in enumerate(outlines):
        seen = vis.targets.points[vis.seen(poses[i : i + 1], sensors=[sensors[i]]), :2]
        assert outline.shape[0] >= 3 and seen.shape[0] > 10
        assert np.isin(outline, seen).all()  # hull corners are seen points
    drawn = [line for line in left.lines if len(line.get_xdata()) > 2]
    assert len(drawn) == 3
    # the quality panel shows vis.quality where seen, nothing elsewhere
    image = right.images[0].get_array()
    quality = vis.quality(poses, sensors=sensors)
    assert np.nanmax(np.ma.filled(image.astype(float), np.nan)) == pytest.approx(quality.max())
    assert right.get_title().endswith(f"{vis.quality_coverage(poses, sensors=sensors):.3f}")
    mesh = uavcov.Terrain(terrain.vertices, terrain.faces)
    with pytest.raises(InvalidInputError, match="grid"):
        plotting.plot_camera_views(mesh, poses, sensors)


def _camera_run(terrain, sensor, n_uavs, attitude, iterations, altitude, rng):
    """A short mission of a camera team whose heading CAO moves (5-30 m above the ground)."""
    spec = uavcov.MissionSettings(
        n_uavs=n_uavs,
        d_max=sensor.d_max,
        iterations=iterations,
        sensor=sensor,
        attitude=attitude,
        gimbal=uavcov.Gimbal(free_yaw=True),
        start=uavcov.StartSettings(altitude=altitude),
        constraints=uavcov.Constraints(h_min=5.0, h_max=30.0, z_max=200.0),
    )
    return uavcov.run_mission(terrain, spec, rng=rng)


def test_a_camera_run_animates_what_its_cameras_see(tmp_path, monkeypatch):
    from uavcov.plotting import _animation as animation

    terrain = uavcov.gaussian_hills(size=60.0, spacing=2.0, n_hills=3, rng=5)
    sensor = uavcov.Sensor(40.0, camera=uavcov.Camera.from_fov(60.0, 45.0))
    run = _camera_run(terrain, sensor, 3, (0.0, -60.0), iterations=6, altitude=15.0, rng=1)
    path = save_mission(run, tmp_path / "camera.npz")
    shown = []  # the coverage fractions each frame draws, and the footprints outlined
    fraction, outline = views._TopView.fraction, animation.footprints
    monkeypatch.setattr(views._TopView, "fraction", lambda self, p, s=None: shown.append((p, s)) or fraction(self, p, s))
    drawn = []
    monkeypatch.setattr(animation, "footprints", lambda *a: drawn.append(outline(*a)) or drawn[-1])
    gif = plotting.animate_mission(path, tmp_path / "camera.gif", max_frames=7, raster=40, dpi=50)
    assert gif.stat().st_size > 0 and len(drawn) == 7
    poses, sensors = shown[-1]  # the last frame: the final poses, cameras posed as the run left them
    np.testing.assert_array_equal(poses, np.column_stack([run.trajectory[-1], run.attitudes[-1]]))
    assert sensors == [sensor] * 3
    vis = Visibility(terrain, 40.0)
    assert vis.coverage(poses, sensors=sensors) == run.final_coverage  # what the frame shows is what the run measured
    assert all(shape.shape[0] >= 3 for shape in drawn[-1])


def test_coverage_maps_and_seen_points_of_a_camera_run_are_what_its_cameras_see():
    terrain = uavcov.gaussian_hills(size=40.0, spacing=1.0, n_hills=3, rng=2)
    sensor = uavcov.Sensor(30.0, camera=uavcov.Camera.from_fov(50.0, 40.0))
    run = _camera_run(terrain, sensor, 2, (30.0, -50.0), iterations=4, altitude=12.0, rng=4)
    poses = np.column_stack([run.trajectory[-1], run.attitudes[-1]])
    vis = Visibility(terrain, 30.0)
    nodes = vis.seen(poses, sensors=[sensor] * 2).reshape(terrain.grid.shape)
    assert 0 < nodes.sum() < 0.9 * nodes.size and not np.array_equal(nodes, vis.seen(run.trajectory[-1]).reshape(nodes.shape))
    fig = plotting.plot_coverage_map(run, view="top", shade=False)
    image = np.asarray(fig.axes[0].images[0].get_array())
    np.testing.assert_allclose(image[nodes][:, :3], np.broadcast_to(plotting.SEEN_COLOUR, (nodes.sum(), 3)))
    np.testing.assert_allclose(image[~nodes][:, :3], np.broadcast_to(plotting.UNSEEN_COLOUR, ((~nodes).sum(), 3)))
    assert fig.axes[0].get_title().startswith(f"Coverage {run.final_coverage:.3f}")
    fig3d = plotting.plot_coverage_map(run, view="3d", max_polygons=100_000)
    surface = next(c for c in fig3d.axes[0].collections if hasattr(c, "uavcov_seen_fraction"))
    assert surface.uavcov_seen_fraction.mean() == pytest.approx(nodes.mean(), abs=0.05)
    union = np.zeros(len(vis.targets), dtype=bool)
    for k in range(run.trajectory.shape[0]):
        union |= vis.seen(np.column_stack([run.trajectory[k], run.attitudes[k]]), sensors=[sensor] * 2)
    np.testing.assert_array_equal(plotting._figures.seen_points(run), vis.targets.points[union])


def test_a_quality_run_animates_and_plots_its_objective(tmp_path, monkeypatch):
    terrain = uavcov.gaussian_hills(size=40.0, spacing=1.0, n_hills=3, rng=6)
    sensor = uavcov.Sensor(30.0, camera=uavcov.Camera.from_fov(60.0, 45.0), good_gsd_m=0.005)
    spec = uavcov.MissionSettings(
        n_uavs=2,
        d_max=30.0,
        iterations=3,
        sensor=sensor,
        objective="quality",
        start=uavcov.StartSettings(altitude=12.0),
        constraints=uavcov.Constraints(h_min=5.0, h_max=30.0, z_max=200.0),
    )
    run = uavcov.run_mission(terrain, spec, rng=0)
    poses = np.column_stack([run.trajectory[-1], run.attitudes[-1]])
    view = views._TopView(terrain, 30.0, 400)  # one pixel per node: no decimation
    image = view.quality_image(poses, [sensor] * 2, shade=False)
    vis = Visibility(terrain, 30.0)
    seen = vis.seen(poses, sensors=[sensor] * 2).reshape(terrain.grid.shape)
    quality = vis.quality(poses, sensors=[sensor] * 2).reshape(terrain.grid.shape)
    import matplotlib as mpl

    np.testing.assert_allclose(image[seen][:, :3], mpl.colormaps["viridis"](quality[seen])[:, :3])
    np.testing.assert_allclose(image[~seen][:, :3], np.broadcast_to(plotting.UNSEEN_COLOUR, ((~seen).sum(), 3)))
    drawn = []
    monkeypatch.setattr(views._TopView, "quality_image", lambda self, p, s, shade=True: drawn.append(p) or image)
    plotting.animate_mission(run, tmp_path / "quality.gif", max_frames=2, raster=40, dpi=50)
    assert len(drawn) == 1 + 2  # the first picture, then every frame: quality maps
    assert plotting.plot_coverage_curves(run).axes[0].get_ylabel() == "quality-weighted coverage"


def test_coverage_against_distance_marks_each_start_and_team_size_at_its_means():
    rows = [
        {"init": init, "n_uavs": str(n), "max_coverage": str(0.5 + 0.1 * k + 0.01 * s), "distance_mean_m": str(30.0 * k + n + s)}
        for k, init in enumerate(("cvt", "greedy"))
        for n in (5, 8)
        for s in range(3)
    ]
    rows.append({"init": "cvt", "n_uavs": "5", "max_coverage": "", "distance_mean_m": ""})  # a failed run
    fig = plotting._distance.plot_coverage_distance(rows)
    _assert_not_blank(_render(fig))
    ax = fig.axes[0]
    means = sorted((round(x, 6), round(y, 6)) for line in ax.lines for x, y in zip(line.get_xdata(), line.get_ydata(), strict=True))
    expected = sorted((round(30.0 * k + n + 1, 6), round(0.51 + 0.1 * k, 6)) for k in range(2) for n in (5, 8))
    assert [m for m in means if m in expected] == expected
    with pytest.raises(uavcov.errors.ResultsFormatError):
        plotting._distance.plot_coverage_distance([{"init": "cvt", "n_uavs": "5", "max_coverage": "0.5"}])


def test_the_structure_figures_views_keep_their_labels_apart_and_fill_the_figure():
    """Side by side, each view's labels (its z label included) end before the next view's begin,
    and the views fill the height: no empty strip above the legend."""
    from uavcov.structures import girder_bridge

    surface = girder_bridge(rng=0).surface
    seen = np.random.default_rng(0).random(surface.n_faces) < 0.6
    fig = plotting.plot_structure_seen(surface, seen.astype(float))
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    axes = [ax for ax in fig.axes if ax.name == "3d"]
    boxes = [ax.get_tightbbox(renderer) for ax in axes]
    height = fig.bbox.height
    for row in (boxes[:2], boxes[2:]):
        left, right = row
        assert left.x1 <= right.x0, (left, right)
    legend = fig.legends[0].get_window_extent(renderer)
    lowest = min(box.y0 for box in boxes[2:])
    assert lowest - legend.y1 < 0.08 * height, "an empty strip between the views and the legend"
    assert all(box.y1 <= fig._suptitle.get_window_extent(renderer).y0 + 1 for box in boxes[:2])


def test_the_3d_view_has_a_key_for_seen_and_not_seen(hills_run):
    """The surface's two colours are named in the legend, after the traces the frames update."""
    pytest.importorskip("plotly")
    from uavcov.plotting._canvas import SEEN_COLOUR, UNSEEN_COLOUR

    fig = plotting.view(hills_run, max_frames=3)
    names = [trace.name for trace in fig.data]
    assert names[-2:] == ["surface: seen", "surface: not seen"]
    colours = [trace.marker.color for trace in fig.data[-2:]]
    assert colours == ["rgb({},{},{})".format(*(round(255 * c) for c in colour)) for colour in (SEEN_COLOUR, UNSEEN_COLOUR)]
    scale = fig.data[0].colorscale
    assert scale[0][1] == colours[1] and scale[-1][1] == colours[0]  # the key is the surface's own colours
    # The whole scene sits above the slider, seen from farther than plotly's default eye.
    assert fig.layout.scene.domain.y[0] > 0.05
    eye = fig.layout.scene.camera.eye
    assert np.linalg.norm([eye.x, eye.y, eye.z]) > np.linalg.norm([1.25, 1.25, 1.25])
