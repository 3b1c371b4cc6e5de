"""The interactive 3D view (``uavcov.plotting.view``, ``write_view``, ``uavcov view``), and the
page it writes opened in headless Chromium (``browser.py``)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("plotly")

import uavcov
from browser import open_page
from uavcov import plotting
from uavcov.cli import EXIT_BAD_INPUT, EXIT_OK, main
from uavcov.engine import Camera, Sensor, Visibility
from uavcov.errors import InvalidInputError, ResultsFormatError


@pytest.fixture(scope="module")
def hills() -> uavcov.Terrain:
    return uavcov.gaussian_hills(size=40.0, spacing=2.0, n_hills=4, heights=(4.0, 12.0), sigma=6.0, rng=3)


@pytest.fixture(scope="module")
def result(hills: uavcov.Terrain) -> uavcov.MissionResult:
    settings = uavcov.MissionSettings(n_uavs=3, d_max=15.0, iterations=24)
    return uavcov.run_mission(hills, settings, rng=0)


@pytest.fixture(scope="module")
def camera_result(hills: uavcov.Terrain) -> uavcov.MissionResult:
    settings = uavcov.MissionSettings(
        n_uavs=2, d_max=25.0, iterations=8, sensor=Sensor(25.0, camera=Camera.from_fov(70.0, 50.0)), attitude=(0.0, -70.0)
    )
    return uavcov.run_mission(hills, settings, rng=1)


@pytest.fixture(scope="module")
def page(result: uavcov.MissionResult, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return plotting.write_view(result, tmp_path_factory.mktemp("view") / "view.html")


def test_colours_are_the_engines_counts_and_match_the_runs_coverage(result: uavcov.MissionResult, hills: uavcov.Terrain) -> None:
    fig = plotting.view(result)
    surface = fig.data[0]
    points = np.column_stack([surface.x, surface.y, surface.z])
    # A 21 x 21 grid is drawn node for node: the view's vertices are the run's own targets.
    targets = hills.default_targets()
    assert points.shape == targets.points.shape
    np.testing.assert_array_equal(points, targets.points)
    frames = {int(f.name): f for f in fig.frames}
    assert {0, result.best_iteration, result.trajectory.shape[0] - 1} <= set(frames)
    vis = Visibility(hills, result.settings.d_max)
    for k, frame in frames.items():
        counts = np.asarray(frame.data[0].intensity)
        uavs = result.trajectory[k]
        # Independently: each UAV alone, summed; and the team's weighted coverage is the run's.
        expected = sum(vis.seen(uavs[i : i + 1]).astype(int) for i in range(uavs.shape[0]))
        np.testing.assert_array_equal(counts, expected)
        share = float(targets.weights[counts > 0].sum() / targets.weights.sum())
        assert share == pytest.approx(result.coverage[k], abs=1e-12)
        assert f"coverage {result.coverage[k]:.3f}" in frame.layout.title.text
        np.testing.assert_allclose(np.asarray(frame.data[2].x), uavs[:, 0], rtol=1e-6)
    # The figure opens at the best iteration.
    np.testing.assert_array_equal(np.asarray(surface.intensity), np.asarray(frames[result.best_iteration].data[0].intensity))
    assert fig.layout.sliders[0].steps[fig.layout.sliders[0].active].label == str(result.best_iteration)


def test_large_surfaces_are_decimated_for_the_view_only(result: uavcov.MissionResult) -> None:
    fig = plotting.view(result, max_vertices=100, max_frames=5)
    assert len(fig.data[0].x) <= 100
    assert len(fig.frames) <= 6  # five evenly spaced, and the best
    best = next(f for f in fig.frames if int(f.name) == result.best_iteration)
    assert f"coverage {result.coverage[result.best_iteration]:.3f}" in best.layout.title.text


def test_a_mesh_is_clustered_onto_the_surface(hills: uavcov.Terrain) -> None:
    mesh = uavcov.Terrain(np.asarray(hills.vertices), np.asarray(hills.faces))  # the same surface, as a mesh
    run = uavcov.run_mission(mesh, uavcov.MissionSettings(n_uavs=2, d_max=15.0, iterations=4), rng=0)
    fig = plotting.view(run, max_vertices=120)
    points = np.column_stack([fig.data[0].x, fig.data[0].y, fig.data[0].z])
    assert len(points) <= 120
    np.testing.assert_allclose(mesh.clearance(points + [0.0, 0.0, 1e-6]), 1e-6, atol=1e-6)  # on the surface


def test_cameras_show_their_footprints(camera_result: uavcov.MissionResult) -> None:
    fig = plotting.view(camera_result)
    names = [trace.name for trace in fig.data]
    assert "camera footprints" in names
    footprint = np.asarray(fig.data[names.index("camera footprints")].x, dtype=float)
    assert np.isfinite(footprint).sum() >= 4  # at least one closed outline


def test_write_view_is_one_offline_file(page: Path) -> None:
    html = page.read_text()
    assert "plotly.js" in html.lower() or "Plotly" in html
    # No script or stylesheet is fetched from anywhere.
    assert not re.search(r"<script[^>]+src=", html)
    assert not re.search(r"<link[^>]+href=\"?https?:", html)
    assert page.stat().st_size < 20e6


def test_find_run_in_files_and_folders(result: uavcov.MissionResult, tmp_path: Path) -> None:
    (tmp_path / "results" / "runs").mkdir(parents=True)
    uavcov.save_mission(result, tmp_path / "results" / "runs" / "b.npz")
    uavcov.save_mission(result, tmp_path / "results" / "runs" / "a.npz")
    (tmp_path / "results" / "runs" / ".tmp-x.npz").write_bytes(b"half")
    assert plotting.find_run(tmp_path / "results") == tmp_path / "results" / "runs" / "a.npz"
    assert plotting.find_run(tmp_path / "results", "b").name == "b.npz"
    assert plotting.find_run(tmp_path / "results" / "runs") == tmp_path / "results" / "runs" / "a.npz"
    assert plotting.find_run(tmp_path / "results" / "runs" / "b.npz").name == "b.npz"
    with pytest.raises(ResultsFormatError, match="no run named"):
        plotting.find_run(tmp_path / "results", "c")
    with pytest.raises(ResultsFormatError, match="no runs"):
        plotting.find_run(tmp_path)
    with pytest.raises(ResultsFormatError, match="no run or folder"):
        plotting.find_run(tmp_path / "nothing")
    (tmp_path / "plan").mkdir()
    (tmp_path / "plan" / "plan.json").write_text("{}")  # what `uavcov plan` writes keeps no run: say where to look
    with pytest.raises(ResultsFormatError, match=r"flight plan's folder.*report\.png.*save_mission\(flight_plan\.mission"):
        plotting.find_run(tmp_path / "plan")


def test_bad_arguments(result: uavcov.MissionResult) -> None:
    for bad in (0, 15, 2.5, True, "many"):
        with pytest.raises(InvalidInputError, match="max_vertices"):
            plotting.view(result, max_vertices=bad)
    with pytest.raises(InvalidInputError, match="max_frames"):
        plotting.view(result, max_frames=1)
    with pytest.raises(ResultsFormatError):
        plotting.view(None)


def test_cli_writes_the_view_and_refuses_bad_input_in_one_line(
    result: uavcov.MissionResult, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "runs").mkdir()
    uavcov.save_mission(result, tmp_path / "runs" / "r1.npz")
    out = tmp_path / "view.html"
    assert main(["view", str(tmp_path), "--out", str(out), "--max-frames", "4"]) == EXIT_OK
    assert out.stat().st_size > 1e6  # plotly.js is inlined
    capsys.readouterr()
    (tmp_path / "broken.npz").write_bytes(b"not a run")
    for argv in (
        ["view", str(tmp_path / "missing")],
        ["view", str(tmp_path), "--run", "r2"],
        ["view", str(tmp_path / "broken.npz"), "--out", str(tmp_path / "x.html")],
        ["view", str(tmp_path / "runs" / "r1.npz"), "--out", str(tmp_path / "no" / "such" / "dir.html")],
    ):
        assert main(argv) == EXIT_BAD_INPUT
        err = capsys.readouterr().err
        assert err.startswith("uavcov view: error:") and err.count("\n") == 1, err
    assert not (tmp_path / "x.html").exists()


def test_the_view_renders_in_chromium_without_a_console_error(page: Path) -> None:
    report = open_page(page)
    assert report.rendered
    assert report.errors == ()
    assert report.colours > 50  # a drawn surface, not a blank canvas


def test_the_browser_check_catches_a_planted_javascript_error(page: Path, tmp_path: Path) -> None:
    planted = tmp_path / "planted.html"
    planted.write_text(page.read_text().replace("</body>", "<script>null.planted_by_the_test();</script></body>"))
    report = open_page(planted)
    assert report.rendered  # the plot drew, but the page is broken
    assert any("planted_by_the_test" in error for error in report.errors), report.errors


def test_the_browser_check_catches_a_blank_canvas_and_a_network_fetch(tmp_path: Path) -> None:
    blank = tmp_path / "blank.html"
    blank.write_text('<html><body style="margin:0;background:#fff"><div style="width:400px;height:300px"></div></body></html>')
    report = open_page(blank, timeout_s=2.0, settle_s=0.0)
    assert not report.rendered and report.colours == 1
    fetching = tmp_path / "fetching.html"
    fetching.write_text('<html><body><script src="http://example.invalid/plotly.js"></script></body></html>')
    assert open_page(fetching, timeout_s=2.0, settle_s=0.0).errors  # offline: the fetch fails loudly


def test_a_flown_run_shows_the_states_flown_not_only_the_waypoints(tmp_path: Path) -> None:
    """A realistic run's view (uavcov.sim's saved states): each frame's paths are the simulated
    states up to that measurement, ending where the UAVs measured; the CLI finds it in states/."""
    pytest.importorskip("rotorpy")
    from uavcov.paper import BUILDINGS
    from uavcov.sim import SimSettings, fly_mission, load_flown, save_flown

    terrain, known = BUILDINGS.terrain.make(1000), BUILDINGS.known(1000)
    spec = BUILDINGS.mission_settings(4, "cvt").with_changes(iterations=3)
    flown = fly_mission(terrain, spec, SimSettings(render=False), known=known, rng=1000)
    path = save_flown(flown, tmp_path / "states" / "s1000_cvt_exact.npz", terrain)
    run = load_flown(path)
    assert np.array_equal(run.flown_states, flown.states) and np.array_equal(run.trajectory, flown.reached)
    fig = plotting.view(path, max_frames=4)
    assert "flown" in fig.data[1].name
    last = fig.frames[-1].data[1]
    xyz = np.column_stack([last.x, last.y, last.z]).astype(np.float64)
    paths = np.split(xyz, np.flatnonzero(np.isnan(xyz[:, 0])))
    paths = [p[~np.isnan(p[:, 0])] for p in paths]
    assert len(paths) == 4
    for i, p in enumerate(paths):
        assert p.shape[0] > flown.reached.shape[0] + 10  # the states, not K + 1 waypoints
        assert np.allclose(p[-1], flown.reached[-1, i], atol=1e-4)  # ends where the UAV measured
        assert np.allclose(p[0], flown.start[i], atol=1e-4)
    # The states stray from the straight moves between waypoints: the drawn path is the flight.
    assert flown.safety is not None and flown.safety.max_deviation > 0.0
    assert main(["view", str(tmp_path), "--out", str(tmp_path / "flown.html"), "--max-frames", "3"]) == EXIT_OK
    assert (tmp_path / "flown.html").stat().st_size > 10_000
    broken = tmp_path / "broken" / "s.npz"
    broken.parent.mkdir()
    broken.write_bytes(path.read_bytes()[:200])
    with pytest.raises(ResultsFormatError):
        plotting.view(broken)
    with pytest.raises(ResultsFormatError):
        load_flown(broken)
