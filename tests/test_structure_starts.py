"""Starts and cameras for structures (issue 35, point 4) on small meshes: a box on the ground, a bridge."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from structure_meshes import box_on_ground, bridge, face_targets
from uavcov import Camera, Gimbal, MissionSettings, Sensor, Targets, Terrain, Visibility
from uavcov.cover._faces import surface_normals
from uavcov.engine import camera_axes
from uavcov.engine._sensors import GIMBAL_PITCH_LIMITS
from uavcov.errors import InfeasibleError, InvalidInputError, InvalidTypeError
from uavcov.placement import facing_attitudes, standoff_start
from uavcov.placement._starts3d import check_reachable, launch_pad_start, random_volume_start


def _trimesh(surface: Terrain) -> trimesh.Trimesh:
    return trimesh.Trimesh(surface.vertices, surface.faces, process=False)


def _brute_closest(surface: Terrain, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Closest points and faces by trimesh's point-triangle routine, over every face (no index)."""
    triangles = surface.vertices[surface.faces]
    n, f = len(points), len(triangles)
    near = trimesh.triangles.closest_point(np.repeat(triangles[None], n, axis=0).reshape(-1, 3, 3), np.repeat(points, f, axis=0))
    distance = np.linalg.norm(near - np.repeat(points, f, axis=0), axis=1).reshape(n, f)
    face = distance.argmin(axis=1)
    return near.reshape(n, f, 3)[np.arange(n), face], face


def _inside_boxes(points: np.ndarray, boxes: list[tuple[list[float], list[float]]]) -> np.ndarray:
    return np.any([((points > lo) & (points < hi)).all(axis=1) for lo, hi in boxes], axis=0)


# ------------------------------------------------------------------------------------------------
# Normals and standoff starts


def test_surface_normals_are_the_face_normals_and_the_bisector_on_an_edge():
    surface = box_on_ground()
    points = [[0.0, 0.0, 8.0], [5.0, 0.0, 4.0], [0.0, -3.0, 4.0], [15.0, 15.0, 0.0], [0.0, 0.0, 9.5], [5.0, 0.0, 8.0]]
    closest, normals = surface_normals(surface, points)
    expected = [[0, 0, 1], [1, 0, 0], [0, -1, 0], [0, 0, 1], [0, 0, 1], [math.sqrt(0.5), 0, math.sqrt(0.5)]]
    np.testing.assert_allclose(normals, expected, atol=1e-12)
    np.testing.assert_allclose(closest[4], [0.0, 0.0, 8.0], atol=1e-12)
    # Against trimesh's closest faces: each normal is the normal of a face holding the point.
    rng = np.random.default_rng(3)
    probes = rng.uniform([-20, -20, 0.5], [20, 20, 15], size=(200, 3))
    near, normal = surface_normals(surface, probes)
    ref_points, ref_faces = _brute_closest(surface, probes)
    np.testing.assert_allclose(near, ref_points, atol=1e-9)
    interior = np.abs(np.abs(normal).max(axis=1) - 1.0) < 1e-12  # off the box's edges
    assert interior.sum() > 120
    np.testing.assert_allclose(normal[interior], _trimesh(surface).face_normals[ref_faces[interior]], atol=1e-12)


def test_a_standoff_start_flies_out_along_the_normal_and_faces_its_generator():
    surface = bridge()
    start = standoff_start(surface, 12, 3.0, rng=5)
    # Along the normal, 3 m out or farther where 3 m is nearer than 3 m to another part (the
    # ground beside a pier's foot: fly_out's steps of 1, 1.5, 2, 3, 4 standoffs).
    out = np.einsum("ij,ij->i", start.positions - start.anchors, start.normals)
    np.testing.assert_allclose(start.positions, start.anchors + out[:, None] * start.normals, atol=1e-12)
    assert set(np.round(out, 9).tolist()) <= {3.0, 4.5, 6.0, 9.0, 12.0} and not start.lifted.any()
    np.testing.assert_allclose(np.linalg.norm(start.normals, axis=1), 1.0, atol=1e-12)
    # Each camera's optical axis points along the inward normal, at its anchor.
    forward, _, _ = camera_axes(start.attitudes[:, 0], start.attitudes[:, 1])
    np.testing.assert_allclose(forward, -start.normals, atol=1e-12)
    # Positions are outside every solid and above the ground, and the reported distance is
    # trimesh's point-triangle distance (brute force over the faces: an independent reference).
    solids = [([-15, -3, 10], [15, 3, 11]), ([-11, -3, 0], [-9, 3, 10]), ([9, -3, 0], [11, 3, 10])]
    assert not _inside_boxes(start.positions, solids).any() and (start.positions[:, 2] > 0).all()
    ref, _ = _brute_closest(surface, start.positions)
    np.testing.assert_allclose(start.distance, np.linalg.norm(start.positions - ref, axis=1), atol=1e-9)
    # At the standoff, but in a concave corner no step frees (a pier's foot): there the first.
    assert ((start.distance >= 3.0 - 1e-9) | np.isclose(out, 3.0)).all()
    # Deterministic.
    again = standoff_start(surface, 12, 3.0, rng=5)
    np.testing.assert_array_equal(again.positions, start.positions)
    np.testing.assert_array_equal(again.attitudes, start.attitudes)


def test_the_deck_underside_needs_an_upward_gimbal():
    surface = bridge()
    # With enough generators some lie on the deck's underside: their cameras look straight up.
    start = standoff_start(surface, 40, 2.0, rng=1)
    under = np.isclose(start.normals[:, 2], -1.0) & np.isclose(start.anchors[:, 2], 10.0)
    assert under.any()
    np.testing.assert_allclose(start.attitudes[under, 1], 90.0)
    with pytest.raises(InfeasibleError, match="upward"):
        standoff_start(surface, 40, 2.0, gimbal="three_axis", rng=1)
    with pytest.raises(InfeasibleError, match="no given gimbal"):
        standoff_start(surface, 40, 2.0, gimbal=["nadir", Gimbal(pitch_range=(-90.0, 30.0))], rng=1)
    clipped = standoff_start(surface, 40, 2.0, gimbal="nadir", clip_pitch=True, rng=1)
    assert (clipped.attitudes[:, 1] <= 0.0).all()
    np.testing.assert_array_equal(clipped.positions, start.positions)


def test_check_reachable_picks_the_first_gimbal_and_refuses_what_none_reaches():
    np.testing.assert_array_equal(check_reachable([-90.0, -10.0, 20.0, 80.0], ["nadir", "three_axis", "upward"]), [0, 0, 1, 2])
    assert check_reachable([-45.0], Gimbal.preset("nadir")).tolist() == [0]
    with pytest.raises(InfeasibleError, match=r"UAV 1 at 45\.0"):
        check_reachable([-30.0, 45.0], "three_axis")
    with pytest.raises(InvalidInputError, match="pitch_range"):
        check_reachable([0.0], Gimbal())
    with pytest.raises(InvalidInputError, match="unknown gimbal capability"):
        check_reachable([0.0], "gimbal-of-dreams")
    with pytest.raises(InvalidTypeError):
        check_reachable([0.0], [])
    with pytest.raises(InvalidInputError):
        check_reachable([math.nan], "upward")


def test_bad_standoff_inputs_are_clear_errors():
    surface = box_on_ground()
    with pytest.raises(InvalidInputError):
        standoff_start(surface, 4, 0.0, rng=0)
    with pytest.raises(InvalidInputError):
        standoff_start(surface, 4, math.nan, rng=0)
    with pytest.raises(InvalidInputError):
        standoff_start(surface, 0, 2.0, rng=0)
    with pytest.raises(InvalidTypeError):
        standoff_start("box", 4, 2.0)  # type: ignore[arg-type]
    # An empty or flat-to-nothing mesh: refused by the Terrain or by the start, never a crash.
    with pytest.raises(InvalidInputError):
        standoff_start(Terrain(np.zeros((3, 3)), np.zeros((0, 3), dtype=np.int64)), 4, 2.0)
    with pytest.raises(InvalidInputError):
        standoff_start(Terrain([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], [[0, 1, 2]]), 4, 2.0)
    with pytest.raises(InvalidInputError):
        surface_normals(surface, [[math.nan, 0.0, 0.0]])
    with pytest.raises(InvalidTypeError):
        standoff_start(surface, 4, 2.0, gimbal=5, clip_pitch=True)


def test_facing_attitudes_invert_camera_axes():
    rng = np.random.default_rng(0)
    directions = rng.normal(size=(500, 3))
    attitudes = facing_attitudes(directions)
    assert ((attitudes[:, 0] >= 0) & (attitudes[:, 0] < 360) & (np.abs(attitudes[:, 1]) <= 90)).all()
    forward, _, _ = camera_axes(attitudes[:, 0], attitudes[:, 1])
    np.testing.assert_allclose(forward, directions / np.linalg.norm(directions, axis=1)[:, None], atol=1e-12)
    with pytest.raises(InvalidInputError):
        facing_attitudes([[0.0, 0.0, 0.0]])


# ------------------------------------------------------------------------------------------------
# Random and launch-pad starts


def test_random_volume_start_is_uniform_in_the_admissible_volume_and_deterministic():
    surface = box_on_ground()
    box = [[-20.0, -20.0, 0.0], [20.0, 20.0, 15.0]]

    def admissible(points: np.ndarray) -> np.ndarray:
        # 2 m from every surface (trimesh's point-triangle distance), outside the box.
        near, _ = _brute_closest(surface, points)
        return (np.linalg.norm(points - near, axis=1) >= 2.0) & ~_inside_boxes(points, [([-5, -3, 0], [5, 3, 8])])

    points = random_volume_start(box, 10, admissible, separation=3.0, rng=7)
    assert points.shape == (10, 3)
    assert admissible(points).all()
    gaps = np.linalg.norm(points[:, None] - points[None], axis=2) + np.eye(10) * 1e9
    assert gaps.min() >= 3.0
    np.testing.assert_array_equal(points, random_volume_start(box, 10, admissible, separation=3.0, rng=7))
    # Uniform: with an always-true predicate the draws are the generator's own uniforms.
    free = random_volume_start(box, 5, lambda p: np.ones(len(p), dtype=bool), rng=11)
    np.testing.assert_array_equal(free, np.random.default_rng(11).uniform(box[0], box[1], size=(256, 3))[:5])


def test_random_volume_start_refuses_bad_input():
    yes = lambda p: np.ones(len(p), dtype=bool)  # noqa: E731
    with pytest.raises(InfeasibleError, match="admissible"):
        random_volume_start([[0, 0, 0], [1, 1, 1]], 3, lambda p: np.zeros(len(p), dtype=bool), rng=0)
    with pytest.raises(InfeasibleError):
        random_volume_start([[0, 0, 0], [1, 1, 1]], 3, yes, separation=5.0, rng=0)  # no room for three
    with pytest.raises(InvalidInputError, match="bool"):
        random_volume_start([[0, 0, 0], [1, 1, 1]], 3, lambda p: np.ones(3), rng=0)
    for bad in ([[0, 0, 0], [1, 1, math.nan]], [[0, 0, 0], [0, 1, 1]], [[0, 0, 0]]):
        with pytest.raises(InvalidInputError):
            random_volume_start(bad, 3, yes)
    with pytest.raises(InvalidTypeError):
        random_volume_start([[0, 0, 0], [1, 1, 1]], 3, "yes")  # type: ignore[arg-type]


def test_launch_pad_start_is_a_compact_lattice_on_the_pad():
    pad = np.array([12.0, -4.0, 0.5])
    points = launch_pad_start(pad, 7, spacing=2.5, altitude=1.5)
    assert points.shape == (7, 3)
    np.testing.assert_allclose(points[:, 2], 2.0)
    # 3 columns x 3 rows centred on the pad: the full lattice's mean is the pad.
    full = launch_pad_start(pad, 9, spacing=2.5)
    np.testing.assert_allclose(full[:, :2].mean(axis=0), pad[:2])
    gaps = np.linalg.norm(full[:, None] - full[None], axis=2) + np.eye(9) * 1e9
    assert gaps.min() == pytest.approx(2.5)
    np.testing.assert_array_equal(points, full[:7] + [0, 0, 1.5])
    for bad in ([math.nan, 0, 0], [0, 0], [1e400, 0, 0]):
        with pytest.raises(InvalidInputError):
            launch_pad_start(bad, 3)
    with pytest.raises(InvalidInputError):
        launch_pad_start(pad, 3, spacing=-1.0)


# ------------------------------------------------------------------------------------------------
# Cameras above the horizon, incidence limits


def test_a_camera_looking_straight_up_sees_a_plate_above_it_and_not_below():
    plate = Terrain([[-5.0, -5.0, 10.0], [5.0, -5.0, 10.0], [5.0, 5.0, 10.0], [-5.0, 5.0, 10.0]], [[0, 1, 2], [0, 2, 3]])
    targets = Targets([[0.0, 0.0, 10.0], [4.0, 0.0, 10.0], [0.0, 4.5, 10.0]], normals=[[0, 0, 1]] * 3)
    vis = Visibility(plate, d_max=50.0, targets=targets)
    camera = Camera.from_fov(60.0, 60.0)  # tan(30 deg) = 0.577: at 5 m below, 2.89 m off the axis
    sensors = [Sensor(50.0, camera=camera)]
    up = vis.seen([[0.0, 0.0, 5.0, 0.0, 90.0]], sensors=sensors)
    assert up.tolist() == [True, False, False]
    wide = vis.seen([[0.0, 0.0, 1.0, 0.0, 90.0]], sensors=sensors)  # 9 m below: 5.2 m off the axis
    assert wide.tolist() == [True, True, True]
    assert vis.seen([[0.0, 0.0, 5.0, 0.0, -90.0]], sensors=sensors).tolist() == [False, False, False]
    assert vis.seen([[0.0, 0.0, 5.0, 0.0, 0.0]], sensors=sensors).tolist() == [False, False, False]
    # Tilted 60 degrees up towards +x: the axis meets the plate at x = 5 / tan(60) = 2.89 m.
    tilted = vis.seen([[0.0, 0.0, 5.0, 90.0, 60.0]], sensors=[Sensor(50.0, camera=Camera.from_fov(20.0, 20.0))])
    assert tilted.tolist() == [False, True, False]


def test_an_incidence_limit_on_the_structure_normals_keeps_only_steep_views():
    surface = box_on_ground()
    targets = face_targets(surface)
    wall = np.flatnonzero(np.isclose(targets.normals[:, 0], 1.0))  # the east wall's two faces
    vis = Visibility(surface, d_max=100.0, targets=targets)
    head_on = [[15.0, 0.0, 4.0]]
    grazing = [[20.0, 60.0, 4.0]]  # 74 to 77 degrees off the east wall's normal
    limited = [Sensor(100.0, max_incidence_deg=60.0)]
    assert vis.seen(head_on, sensors=limited)[wall].all()
    assert vis.seen(grazing, sensors=[Sensor(100.0)])[wall].all()
    assert vis.seen(grazing, sensors=[Sensor(100.0, max_incidence_deg=80.0)])[wall].all()
    assert not vis.seen(grazing, sensors=limited)[wall].any()


def test_gimbal_pitch_ranges_reach_above_the_horizon_and_missions_refuse_an_unreachable_pitch():
    assert GIMBAL_PITCH_LIMITS["nadir"] == (-90.0, 0.0)
    assert GIMBAL_PITCH_LIMITS["upward"] == (-90.0, 90.0)
    assert Gimbal.preset("three_axis", free_yaw=True).free_angles == ("yaw", "pitch")
    assert Gimbal(pitch_range=(-30.0, 60.0)).pitch_range == (-30.0, 60.0)
    with pytest.raises(InvalidInputError):
        Gimbal(pitch_range=(0.0, 95.0))
    with pytest.raises(InvalidInputError):
        Gimbal.preset("gimbal-of-dreams")
    camera = Sensor(20.0, camera=Camera.from_fov(60.0, 45.0))
    with pytest.raises(InvalidInputError, match="point up"):
        MissionSettings(n_uavs=2, d_max=20.0, sensor=camera, attitude=(0.0, 45.0))
    with pytest.raises(InvalidInputError, match="pitch_range"):
        MissionSettings(n_uavs=2, d_max=20.0, sensor=camera, attitude=(0.0, 45.0), gimbal=Gimbal.preset("three_axis"))
    ok = MissionSettings(n_uavs=2, d_max=20.0, sensor=camera, attitude=(0.0, 45.0), gimbal=Gimbal.preset("upward"))
    assert ok.attitude == (0.0, 45.0)
    with pytest.raises(InvalidInputError, match="zenith"):
        camera_axes([0.0], [90.5])


def test_a_mission_optimises_a_pitch_above_the_horizon_within_its_gimbal():
    from uavcov import CAOSettings, Constraints, StartSettings, gaussian_hills, run_mission

    terrain = gaussian_hills(size=60.0, spacing=2.0, n_hills=3, rng=4)
    spec = MissionSettings(
        n_uavs=3,
        d_max=40.0,
        iterations=30,
        sensor=Sensor(40.0, camera=Camera.from_fov(70.0, 50.0)),
        attitude=(10.0, 10.0),
        gimbal=Gimbal(pitch_range=(-20.0, 40.0), alpha0_deg=40.0),
        start=StartSettings(altitude=10.0),
        constraints=Constraints(h_min=4.0, h_max=25.0, z_max=200.0, d_safe=1.0),
        cao=CAOSettings(alpha0=2.0, stability=5.0, decay=1.0),
    )
    result = run_mission(terrain, spec, rng=3)
    pitch = result.attitudes[..., 1]
    assert (pitch >= -20.0).all() and (pitch <= 40.0).all() and (pitch > 0.0).any()
    assert np.ptp(pitch) > 1.0


def test_closest_faces_on_a_fine_mesh_with_a_large_face_match_brute_force():
    from uavcov import gaussian_hills
    from uavcov.cover import closest_faces

    hills = gaussian_hills(size=30.0, spacing=1.0, rng=2)
    # A fine mesh (1800 faces) and one large floating triangle above it, far bigger than the rest.
    vertices = np.vstack([hills.vertices, [[-10.0, -10.0, 40.0], [50.0, -10.0, 40.0], [-10.0, 50.0, 40.0]]])
    faces = np.vstack([hills.faces, [[len(hills.vertices), len(hills.vertices) + 1, len(hills.vertices) + 2]]])
    surface = Terrain(vertices, faces)
    probes = np.random.default_rng(4).uniform([-5.0, -5.0, -5.0], [35.0, 35.0, 50.0], size=(400, 3))
    found = closest_faces(surface, probes)
    _, reference = _brute_closest(surface, probes)
    ours = np.linalg.norm(probes - _brute_closest_on(surface, probes, found), axis=1)
    best = np.linalg.norm(probes - _brute_closest_on(surface, probes, reference), axis=1)
    np.testing.assert_allclose(ours, best, atol=1e-9)  # equally close (ties may pick another face)
    assert (found == surface.n_faces - 1).any() and (found < surface.n_faces - 1).any()


def _brute_closest_on(surface: Terrain, points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    return trimesh.triangles.closest_point(surface.vertices[surface.faces[faces]], points)
