"""uavcov.sim's sensing (no simulator needed): the batch ray query, depth cameras, the voxel map."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import uavcov
from uavcov.errors import InvalidInputError, InvalidTypeError
from uavcov.sim import DepthCamera, VoxelMap, camera_rotation, check_flight, observed_targets, sensed_coverage
from uavcov.terrain import buildings_scene


def _flat(z: float = 0.0) -> uavcov.Terrain:
    return uavcov.Terrain.from_grid(np.full((21, 21), z), 1.0)


def test_first_hits_matches_the_analytic_depth_of_a_plane() -> None:
    plane = _flat(1.5)
    origins = np.array([[5.0, 5.0, 10.0], [5.0, 5.0, 10.0], [5.0, 5.0, 10.0], [5.0, 5.0, 10.0]])
    # Straight down, 60 degrees off the vertical, up (never), and down but too short a range.
    down60 = [math.sin(math.radians(60)), 0.0, -math.cos(math.radians(60))]
    directions = np.array([[0.0, 0.0, -2.0], down60, [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])
    hits = plane.core.first_hits(origins[:3], directions[:3], 100.0)
    assert hits[0] == pytest.approx(8.5, abs=1e-9)  # unnormalised direction: still metres
    assert hits[1] == pytest.approx(8.5 / math.cos(math.radians(60)), abs=1e-9)
    assert math.isinf(hits[2])
    assert math.isinf(plane.core.first_hits(origins[3:], directions[3:], 8.0)[0])


@pytest.mark.parametrize(
    "origins, directions, t_max",
    [
        (np.zeros((2, 3)), np.ones((3, 3)), 1.0),  # lengths differ
        (np.zeros((1, 3)), np.zeros((1, 3)), 1.0),  # no direction
        (np.full((1, 3), np.nan), np.ones((1, 3)), 1.0),
        (np.zeros((1, 3)), np.ones((1, 3)), float("nan")),
        (np.zeros((1, 3)), np.ones((1, 3)), 0.0),
        (np.zeros((1, 3)), np.ones((1, 3)), 1e300),
        (np.zeros((1, 2)), np.ones((1, 2)), 1.0),
        (np.full((1, 3), 1e300), np.ones((1, 3)), 1.0),
    ],
)
def test_first_hits_refuses_hostile_input(origins: np.ndarray, directions: np.ndarray, t_max: float) -> None:
    with pytest.raises(InvalidInputError):
        _flat().core.first_hits(origins, directions, t_max)


def test_a_nadir_camera_sees_its_footprint_at_the_plane() -> None:
    camera = DepthCamera(width=9, height=9, fov_deg=(60.0, 60.0), range_m=50.0)
    rotation = camera_rotation([0.0, 0.0, 0.0, 1.0], camera)
    assert rotation @ np.array([1.0, 0.0, 0.0]) == pytest.approx([0.0, 0.0, -1.0], abs=1e-12)
    depth, points = camera.render(_flat(), [10.0, 10.0, 5.0], rotation)
    assert depth.shape == (9, 9) and points.shape == (81, 3)
    assert np.abs(points[:, 2]).max() < 1e-9  # every pixel lands on the plane z = 0
    assert depth[4, 4] == pytest.approx(5.0, abs=1e-9)  # the centre pixel looks straight down
    half = math.tan(math.radians(30.0)) * 5.0
    assert np.abs(points[:, :2] - 10.0).max() <= half + 1e-9


def test_a_stabilised_gimbal_ignores_tilt_and_a_fixed_camera_follows_it() -> None:
    tilted = [math.sin(math.radians(10)), 0.0, 0.0, math.cos(math.radians(10))]  # 20 degrees of roll
    stabilised = DepthCamera(width=1, height=1, fov_deg=(10.0, 10.0), range_m=10.0)
    fixed = DepthCamera(width=1, height=1, fov_deg=(10.0, 10.0), range_m=10.0, stabilised=False)
    axis = np.array([1.0, 0.0, 0.0])
    assert camera_rotation(tilted, stabilised) @ axis == pytest.approx([0.0, 0.0, -1.0], abs=1e-12)
    assert (camera_rotation(tilted, fixed) @ axis)[2] == pytest.approx(-math.cos(math.radians(20)), abs=1e-12)


def test_depth_noise_follows_rng() -> None:
    camera = DepthCamera(width=8, height=8, fov_deg=(90.0, 90.0), range_m=20.0, noise_sd=0.05)
    rotation = camera_rotation([0.0, 0.0, 0.0, 1.0], camera)
    a = camera.render(_flat(), [10.0, 10.0, 5.0], rotation, rng=3)[0]
    b = camera.render(_flat(), [10.0, 10.0, 5.0], rotation, rng=3)[0]
    c = camera.render(_flat(), [10.0, 10.0, 5.0], rotation, rng=4)[0]
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    exact = DepthCamera(width=8, height=8, fov_deg=(90.0, 90.0), range_m=20.0).render(_flat(), [10.0, 10.0, 5.0], rotation)[0]
    assert 0.02 < np.std(a - exact) < 0.08


@pytest.mark.parametrize(
    "changes",
    [
        {"width": 0},
        {"width": 2.5},
        {"height": 10**6},
        {"width": 5000, "height": 5000},
        {"fov_deg": (400.0, 90.0)},
        {"fov_deg": (90.0, float("nan"))},
        {"fov_deg": "wide"},
        {"range_m": -1.0},
        {"range_m": 1e300},
        {"noise_sd": -0.1},
        {"pitch_deg": 120.0},
    ],
)
def test_depth_camera_refuses_hostile_settings(changes: dict[str, object]) -> None:
    settings: dict[str, object] = {"width": 8, "height": 8, "fov_deg": (90.0, 90.0), "range_m": 10.0, **changes}
    with pytest.raises(InvalidInputError):
        DepthCamera(**settings)  # type: ignore[arg-type]


def test_render_refuses_what_is_not_a_pose() -> None:
    camera = DepthCamera(width=2, height=2, fov_deg=(90.0, 90.0), range_m=10.0)
    with pytest.raises(InvalidTypeError):
        camera.render("terrain", [0.0, 0.0, 1.0], np.eye(3))  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError):
        camera.render(_flat(), [0.0, np.nan, 1.0], np.eye(3))
    with pytest.raises(InvalidInputError):
        camera.render(_flat(), [0.0, 0.0, 1.0], np.eye(2))


def test_voxel_map_keeps_one_mean_point_per_voxel() -> None:
    fused = VoxelMap(1.0)
    fused.add([[0.1, 0.1, 0.1], [0.3, 0.5, 0.9]])
    fused.add([[0.2, 0.3, 0.2], [5.5, -2.5, 0.5]])
    assert len(fused) == 2
    order = np.argsort(fused.points[:, 0])
    assert fused.points[order[0]] == pytest.approx([0.2, 0.3, 0.4])
    assert fused.counts[order].tolist() == [3, 1]
    fused.add(np.empty((0, 3)))
    assert len(fused) == 2
    for bad in ([[np.nan, 0.0, 0.0]], [[0.0, 0.0]], [[1e30, 0.0, 0.0]]):
        with pytest.raises(InvalidInputError):
            fused.add(bad)
    with pytest.raises(InvalidInputError):
        VoxelMap(0.0)


def test_observed_targets_against_brute_force() -> None:
    rng = np.random.default_rng(0)
    targets = uavcov.Targets(rng.uniform(0, 10, (200, 3)), weights=rng.uniform(0.5, 2.0, 200))
    points = rng.uniform(0, 10, (300, 3))
    brute = (np.linalg.norm(targets.points[:, None, :] - points[None, :, :], axis=2) <= 0.7).any(axis=1)
    assert np.array_equal(observed_targets(targets, points, 0.7), brute)
    assert sensed_coverage(targets, points, 0.7) == pytest.approx(targets.weights[brute].sum() / targets.weights.sum())
    assert sensed_coverage(targets, np.empty((0, 3)), 0.7) == 0.0


@pytest.mark.parametrize("seed", [0, 1])
def test_sensed_coverage_approaches_the_exact_one_as_the_resolution_rises(seed: int) -> None:
    terrain = buildings_scene(n_buildings=4, footprint=(2.0, 5.0), heights=(3.0, 8.0), rng=seed)
    vis = uavcov.Visibility(terrain, 8.0, n_threads=1)
    uavs = np.array([[6.0, 6.0, 9.0], [18.0, 6.0, 9.5], [6.0, 18.0, 10.0], [18.0, 18.0, 9.0]])
    exact = vis.coverage(uavs)
    gaps = []
    for resolution in (8, 32, 128):
        camera = DepthCamera.omnidirectional(8.0, resolution=resolution)
        cloud = np.concatenate([camera.render(terrain, p, np.eye(3), n_threads=1)[1] for p in uavs])
        gaps.append(abs(sensed_coverage(vis.targets, cloud, camera.footprint_m) - exact))
    # Measured: 0.139, 0.044, 0.002 (seed 0); 0.126, 0.031, 0.005 (seed 1).
    assert gaps[0] > gaps[1] > gaps[2], gaps
    assert gaps[2] < 0.015, gaps


def test_check_flight_counts_each_limit_on_a_plane() -> None:
    plane = _flat(0.0)
    limits = uavcov.limits.Constraints(h_min=1.0, h_max=5.0, z_max=6.0, d_safe=1.0).resolve(plane)
    starts = np.array([[[2.0, 2.0, 2.0], [8.0, 8.0, 2.0]]])
    goals = np.array([[[6.0, 2.0, 2.0], [8.0, 8.0, 2.0]]])
    states = np.array(
        [
            [[3.0, 2.5, 2.0], [8.0, 8.0, 2.0]],  # 0.5 m off the move, fine
            [[6.5, 2.0, 0.5], [8.0, 8.0, 2.0]],  # past the goal by 0.5 m, under h_min
            [[6.0, 2.0, 5.5], [8.0, 8.0, 2.0]],  # over h_max
            [[7.8, 7.9, 2.0], [8.0, 8.0, 2.0]],  # crowding the other vehicle
        ]
    )
    report = check_flight(plane, limits, states, np.zeros(4, dtype=int), starts, goals)
    assert (report.below_h_min, report.above_h_max, report.above_z_max, report.straight_above_h_max) == (1, 1, 0, 0)
    assert report.too_close == 2  # both vehicles of the crowded state
    assert report.violations == 4 and not report.safe
    assert report.min_clearance == pytest.approx(0.5) and report.max_clearance == pytest.approx(5.5)
    # The crowding state is farthest from its move (foot at the goal (6, 2, 2)) and past it by 1.8 m.
    assert report.max_deviation == pytest.approx(math.hypot(1.8, 5.9), abs=1e-9)
    assert report.max_overshoot == pytest.approx(1.8, abs=1e-9)
    assert report.min_separation == pytest.approx(math.hypot(0.2, 0.1))
    # The straight moves (feet of the states on them) stay 2 m over the plane: none under h_min.
    assert report.straight_below_h_min == 0 and report.straight_min_distance == pytest.approx(2.0)


def _box_on_ground() -> uavcov.Terrain:
    """A 4 m x 4 m x 6 m box at (8-12, 8-12) on a 20 m square ground sheet."""
    box = np.array([[8, 8, 0], [12, 8, 0], [12, 12, 0], [8, 12, 0], [8, 8, 6], [12, 8, 6], [12, 12, 6], [8, 12, 6]], float)
    walls = [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4]]
    walls += [[1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]
    ground = np.array([[0, 0, 0], [20, 0, 0], [20, 20, 0], [0, 20, 0]], float)
    return uavcov.Terrain(np.vstack([ground, box]), np.vstack([[[0, 1, 2], [0, 2, 3]], np.array(walls) + 4]))


def test_check_flight_bounds_the_3d_standoff_beside_a_wall_when_the_limits_say_so() -> None:
    """Beside a wall, 3 m over the ground: eq. 2 (straight down) admits a state 0.3 m from the
    wall, a 1 m standoff does not (nor one 0.5 m beside the other wall, 5.5 m up)."""
    world = _box_on_ground()
    states = np.array([[[7.7, 10.0, 3.0]], [[6.0, 10.0, 3.0]], [[12.5, 10.0, 5.5]]])  # 0.3 m, 2 m, 0.5 m from the box
    legs, starts, goals = np.zeros(3, dtype=int), states[:1], states[:1]
    vertical = uavcov.limits.Constraints(h_min=1.0, h_max=6.0, z_max=20.0).resolve(world)
    standoff = uavcov.limits.Constraints(h_min=1.0, h_max=6.0, z_max=20.0, clearance="standoff").resolve(world)
    by_eq2 = check_flight(world, vertical, states, legs, starts, goals)
    by_standoff = check_flight(world, standoff, states, legs, starts, goals)
    assert by_eq2.below_h_min == 0 and by_eq2.violations == 0  # 3 m, 3 m and 5.5 m straight down
    assert by_standoff.below_h_min == 2 and by_standoff.violations == 2
    assert by_standoff.min_distance == pytest.approx(0.3) and by_eq2.min_distance == pytest.approx(0.3)
    # The straight move (a single point here) is judged by the same measure.
    assert by_eq2.straight_below_h_min == 0 and by_standoff.straight_below_h_min == 3


@pytest.mark.parametrize(
    "bad",
    [
        ["realistic", "--starts", "corner"],
        ["realistic", "--seeds", "x-y"],
        ["realistic", "--starts", "cvt,random"],
        ["realistic", "--measurements", "guessed"],
        ["realistic", "--measurements", "exact,psychic"],
        ["flown-table1", "--starts", "pairs"],
        ["flown-table1", "--measurements", "sensed"],
        ["flown-table1", "--standoff", "1"],
        ["table1", "--standoff", "1"],
        ["structures", "--measurements", "exact"],
        ["realistic", "--standoff", "0"],
        ["realistic", "--standoff", "nan"],
        ["realistic", "--standoff", "6"],
        ["realistic", "--standoff", "1e300"],
    ],
)
def test_reproduce_realistic_refuses_bad_choices_in_one_line(tmp_path: object, capsys: pytest.CaptureFixture[str], bad: list[str]) -> None:
    from uavcov.cli import EXIT_BAD_INPUT, main

    try:
        code = main(["reproduce", *bad, "--out", str(tmp_path)])
    except SystemExit as exit_:  # argparse's own refusals (a flag's type) exit from the parser
        code = exit_.code
    assert code == EXIT_BAD_INPUT
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "error" in err[0]


def test_a_flown_run_file_is_told_apart_and_hostile_files_are_refused(tmp_path: Path) -> None:
    """``is_flown_file`` says False for anything but a flown run; ``load_flown`` refuses each
    hostile file with ResultsFormatError (a mission's run, bytes, an empty file, a bare array,
    a header of another format, a missing file)."""
    import json

    from uavcov.errors import ResultsFormatError
    from uavcov.records import save_mission
    from uavcov.sim import FLOWN_FORMAT, is_flown_file, load_flown

    hills = uavcov.gaussian_hills(size=20.0, spacing=2.0, n_hills=2, rng=0)
    mission = save_mission(uavcov.run_mission(hills, uavcov.MissionSettings(n_uavs=2, d_max=10.0, iterations=2), rng=0), tmp_path / "m.npz")
    garbage = tmp_path / "g.npz"
    garbage.write_bytes(b"\x00\x01not a zip" * 10)
    empty = tmp_path / "e.npz"
    empty.write_bytes(b"")
    bare = tmp_path / "a.npy"
    np.save(bare, np.arange(3))
    other = tmp_path / "o.npz"
    np.savez(other, header=np.array(json.dumps({"format": "uavcov-flown-0"})))
    wrong = tmp_path / "w.npz"
    np.savez(wrong, header=np.array(json.dumps({"format": FLOWN_FORMAT})), reached=np.zeros((2, 2, 3)))
    for path in (mission, garbage, empty, bare, other, tmp_path / "missing.npz"):
        assert not is_flown_file(path)
    assert is_flown_file(wrong)  # its header says so; its arrays do not
    for path in (mission, garbage, empty, bare, other, wrong, tmp_path / "missing.npz"):
        with pytest.raises(ResultsFormatError):
            load_flown(path)
