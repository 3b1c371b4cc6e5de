"""Sensors per UAV (range, minimum range, pinhole camera) against an independent numpy reference.

The reference: the brute-force sight lines of ``reference.py`` for every UAV-target pair, kept
where a frustum test written here by dot products (and a range test) says the sensor reaches the
target. The camera's axes come from ``uavcov.engine.camera_axes``, itself checked against rotation
matrices, so that both sides test the same floating-point frustum: targets placed exactly on its
edges must get the same answer.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import random_grid_case, uavs_above
from reference import visibility_reference
from uavcov import Camera, Sensor, Targets, Terrain, Visibility
from uavcov.engine import camera_axes
from uavcov.errors import InvalidInputError, InvalidTypeError


def _rotation(yaw_deg: float, pitch_deg: float) -> np.ndarray:
    """World-from-camera rotation, columns (right, forward, up), by composing two rotations:
    pitch about the camera's right (x) axis, then the heading about z (clockwise from north)."""
    p, y = math.radians(pitch_deg), math.radians(yaw_deg)
    pitch = np.array([[1, 0, 0], [0, math.cos(p), -math.sin(p)], [0, math.sin(p), math.cos(p)]])
    heading = np.array([[math.cos(y), math.sin(y), 0], [-math.sin(y), math.cos(y), 0], [0, 0, 1]])
    return heading @ pitch


@pytest.mark.parametrize("yaw, pitch", [(0, -90), (0, 0), (90, 0), (359.9, -30), (0.1, -30), (-45, -60), (720 + 10, -5)])
def test_camera_axes_are_the_rotated_camera_frame(yaw, pitch):
    forward, right, up = camera_axes([yaw], [pitch])
    r = _rotation(yaw, pitch)
    np.testing.assert_allclose(right[0], r[:, 0], atol=1e-12)
    np.testing.assert_allclose(forward[0], r[:, 1], atol=1e-12)
    np.testing.assert_allclose(up[0], r[:, 2], atol=1e-12)
    if pitch == -90:
        np.testing.assert_allclose(forward[0], [0, 0, -1], atol=1e-15)
        np.testing.assert_allclose(up[0], [math.sin(math.radians(yaw)), math.cos(math.radians(yaw)), 0], atol=1e-12)


def _reach(uavs, packed_axes, sensors, targets, normals=None, uncertain=None):
    """(N, T) bool: range, frustum and incidence, dot products summed x, y, z (the order the
    docs state). Pairs within 1e-9 of the incidence limit are flagged in ``uncertain``."""
    out = np.zeros((len(sensors), targets.shape[0]), dtype=bool)
    for i, s in enumerate(sensors):
        d = targets - uavs[i]
        d2 = d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2]
        ok = (d2 <= s.reach_m * s.reach_m) & (d2 >= s.d_min * s.d_min)
        if s.max_incidence_deg is not None:
            cos = np.abs(np.einsum("tk,tk->t", -d, normals)) / np.sqrt(d2)
            limit = math.cos(math.radians(s.max_incidence_deg))
            ok &= cos >= limit
            if uncertain is not None:
                uncertain[i] |= np.abs(cos - limit) <= 1e-9
        if s.camera is not None:
            f, r, u = (packed_axes[k][i] for k in range(3))
            th, tv = s.camera.tan_half_fov
            depth = d[:, 0] * f[0] + d[:, 1] * f[1] + d[:, 2] * f[2]
            across = d[:, 0] * r[0] + d[:, 1] * r[1] + d[:, 2] * r[2]
            along = d[:, 0] * u[0] + d[:, 1] * u[1] + d[:, 2] * u[2]
            ok &= (depth > 0) & (np.abs(across) <= th * depth) & (np.abs(along) <= tv * depth)
        out[i] = ok
    return out


def _team(rng: np.random.Generator, n: int) -> list[Sensor]:
    kinds = [
        Sensor(6.0),
        Sensor(9.0, d_min=1.5, camera=Camera.from_fov(84.0, 62.0)),
        Sensor(12.0, camera=Camera.from_fov(60.0, 45.0)),
        Sensor(20.0, camera=Camera(13.2, 8.8, 8.8, 5472, 3648), max_gsd_m=0.002),
        Sensor(8.0, d_min=0.5, camera=Camera.from_fov(120.0, 90.0)),
    ]
    return [kinds[k] for k in rng.integers(0, len(kinds), size=n)]


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("method", ["grid", "mesh"])
def test_seen_matches_the_reference_with_mixed_sensors(seed, method):
    case = random_grid_case(seed, nx=21, ny=17)
    terrain = Terrain.from_grid(case.z, case.spacing, origin=case.origin)
    targets = terrain.default_targets()
    rng = np.random.default_rng(100 + seed)
    n = 6
    uavs = uavs_above(case, n, rng, low=1.0, high=6.0)
    yaw = rng.choice([0.0, 359.95, 0.05, 90.0, 181.0, 270.0, -30.0], size=n)
    pitch = rng.choice([-90.0, 0.0, -45.0, -89.9, -10.0], size=n)
    poses = np.column_stack([uavs, yaw, pitch])
    sensors = _team(rng, n)
    vis = Visibility(terrain, 5.0, targets=targets, method=method)
    seen = vis.seen(poses, sensors=sensors)
    ref = visibility_reference(case.vertices, case.faces, uavs, targets.points, 50.0)
    reach = _reach(uavs, camera_axes(yaw, pitch), sensors, targets.points)
    visible = ref.visible & reach
    certain_seen = (visible & ~ref.uncertain).any(axis=0)
    undecided = ~certain_seen & (ref.uncertain & reach).any(axis=0)
    np.testing.assert_array_equal(seen[~undecided], certain_seen[~undecided])
    assert 0 < seen.sum() < seen.size and (reach.any(axis=0) & ~seen).any()  # occlusion and reach both bite
    counts = vis.per_uav(poses, sensors=sensors)
    assert counts.coverage == vis.coverage(poses, sensors=sensors)
    assert np.all(np.abs(counts.seen - visible.sum(axis=1)) <= (ref.uncertain & reach).sum(axis=1))


@pytest.mark.parametrize("method", ["grid", "mesh"])
def test_targets_on_the_frustums_edges_get_the_references_answer(method):
    # nothing occludes (the ground is 50 m below): the answer is the frustum test alone
    terrain = Terrain.from_grid(np.full((11, 11), -50.0), (10.0, 10.0))
    uav = np.array([50.0, 50.0, 0.0])
    cameras = [Camera.from_fov(60.0, 45.0), Camera.from_fov(84.0, 84.0), Camera(13.2, 8.8, 8.8, 5472, 3648)]
    rng = np.random.default_rng(3)
    for camera in cameras:
        for yaw, pitch in [(0.0, -90.0), (359.99, -45.0), (0.01, 0.0), (123.4, -67.8)]:
            (f,), (r,), (u,) = camera_axes([yaw], [pitch])
            th, tv = camera.tan_half_fov
            depth = rng.uniform(1.0, 30.0, size=200)
            a = rng.choice([-1.0, 1.0], size=200) * th * rng.choice([1.0, rng.uniform(0, 1)], size=200)
            b = rng.choice([-1.0, 1.0], size=200) * tv * rng.choice([1.0, rng.uniform(0, 1)], size=200)
            points = uav + depth[:, None] * (f + a[:, None] * r + b[:, None] * u)
            targets = Targets.from_points(points, np.ones(200))
            vis = Visibility(terrain, 100.0, targets=targets, method=method)
            sensors = [Sensor(100.0, camera=camera)]
            seen = vis.seen([[*uav, yaw, pitch]], sensors=sensors)
            expected = _reach(uav[None], camera_axes([yaw], [pitch]), sensors, points)[0]
            np.testing.assert_array_equal(seen, expected)
            assert 0 < expected.sum() < expected.size  # edges fall on both sides


def test_the_papers_sensor_given_explicitly_changes_nothing(hill_terrain):
    vis = Visibility(hill_terrain, 8.0)
    rng = np.random.default_rng(0)
    lo, hi = hill_terrain.bounds
    uavs = rng.uniform(lo + [0, 0, 3.0], hi + [0, 0, 6.0], size=(5, 3))
    sensors = [Sensor(8.0)] * 5
    assert vis.coverage(uavs, sensors=sensors) == vis.coverage(uavs)
    np.testing.assert_array_equal(vis.seen(uavs, sensors=sensors), vis.seen(uavs))
    a, b = vis.per_uav(uavs, sensors=sensors), vis.per_uav(uavs)
    np.testing.assert_array_equal(a.seen, b.seen)
    # a narrower camera never sees more than the omnidirectional sensor of the same range
    narrow = [Sensor(8.0, camera=Camera.from_fov(60.0, 45.0))] * 5
    poses = np.column_stack([uavs, np.zeros(5), np.full(5, -90.0)])
    assert not (vis.seen(poses, sensors=narrow) & ~vis.seen(uavs)).any()


def test_camera_vocabulary():
    c = Camera(13.2, 8.8, 8.8, 5472, 3648)
    assert c.hfov_deg == pytest.approx(2 * math.degrees(math.atan(13.2 / 17.6)))
    assert c.gsd_m(100.0) == pytest.approx(100.0 * 13.2 / (8.8 * 5472))
    wide = Camera.from_fov(84.0, 60.0)
    assert (wide.hfov_deg, wide.vfov_deg) == (pytest.approx(84.0), pytest.approx(60.0))
    assert Sensor(500.0, camera=c, max_gsd_m=0.01).reach_m == pytest.approx(0.01 * 8.8 * 5472 / 13.2)
    assert Sensor(5.0, camera=c, max_gsd_m=0.01).reach_m == 5.0


def test_bad_sensors_and_poses_are_clear_errors(hill_terrain):
    vis = Visibility(hill_terrain, 8.0)
    cam = Camera.from_fov(60.0, 45.0)
    pose = [[5.0, 5.0, 20.0, 0.0, -90.0]]
    for fov in (0.0, 180.0, 200.0, -10.0, math.nan, math.inf):
        with pytest.raises(InvalidInputError):
            Camera.from_fov(fov, 45.0)
    with pytest.raises(InvalidInputError):
        Camera(13.2, 8.8, -8.8, 5472, 3648)  # a negative focal length
    with pytest.raises(InvalidInputError):
        Camera(13.2, 8.8, 8.8, 0, 3648)
    with pytest.raises(InvalidInputError):
        Sensor(5.0, d_min=5.0)
    with pytest.raises(InvalidInputError):
        Sensor(5.0, max_gsd_m=0.01)  # a GSD needs a camera
    with pytest.raises(InvalidInputError, match="nothing is in range"):
        Sensor(50.0, d_min=10.0, camera=Camera(13.2, 8.8, 8.8, 5472, 3648), max_gsd_m=0.001)  # fine enough only within 3.6 m
    with pytest.raises(InvalidTypeError):
        Sensor(5.0, camera="wide")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="nadir to zenith"):
        vis.coverage([[5.0, 5.0, 20.0, 0.0, 95.0]], sensors=[Sensor(8.0, camera=cam)])  # past the zenith
    for bad in (math.nan, math.inf):
        with pytest.raises(InvalidInputError):
            vis.coverage([[5.0, 5.0, 20.0, bad, -90.0]], sensors=[Sensor(8.0, camera=cam)])
    with pytest.raises(InvalidInputError, match="one per UAV"):
        vis.coverage(pose * 2, sensors=[Sensor(8.0, camera=cam)])
    with pytest.raises(InvalidInputError, match=r"\(N, 5\)"):
        vis.coverage([[5.0, 5.0, 20.0]], sensors=[Sensor(8.0, camera=cam)])
    with pytest.raises(InvalidTypeError):
        vis.coverage(pose, sensors=Sensor(8.0, camera=cam))  # type: ignore[arg-type]
    # the engine's own checks, behind the Python ones
    from uavcov import _core

    packed = np.full((1, 16), np.nan)
    packed[0, :2] = [0.0, 8.0]
    packed[0, 2:5] = [0.0, 0.0, -1.0]  # a partial camera
    with pytest.raises(InvalidInputError):
        vis._core.coverage(np.array([[5.0, 5.0, 20.0]]), 1, packed)
    packed[0, 2:] = np.nan
    packed[0, 13] = 1.5  # an incidence cosine beyond 1
    with pytest.raises(InvalidInputError):
        vis._core.coverage(np.array([[5.0, 5.0, 20.0]]), 1, packed)
    with pytest.raises(InvalidInputError):
        vis._core.coverage(np.array([[5.0, 5.0, 20.0]]), 1, np.zeros((1, 12)))
    assert isinstance(_core.available_threads(), int)


def _grid_normals(case) -> np.ndarray:
    """Unit vertex normals of a grid's triangles: the area-weighted sum of the face normals."""
    vertices, faces = case.vertices, case.faces
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    face = np.cross(b - a, c - a)
    face *= np.sign(face[:, 2:3])  # upward, whatever the winding
    normals = np.zeros_like(vertices)
    for k in range(3):
        np.add.at(normals, faces[:, k], face)
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


def _best_quality(uavs, sensors, points, normals, visible):
    """(T,) best view quality over the pairs in ``visible`` (N, T): resolution x |cos incidence|."""
    best = np.zeros(points.shape[0])
    for i, s in enumerate(sensors):
        v = uavs[i] - points
        dist = np.linalg.norm(v, axis=1)
        q = np.abs(np.einsum("tk,tk->t", v, normals)) / dist
        if s.good_gsd_m is not None:
            q = q * np.minimum(1.0, s.good_gsd_m / (s.camera.gsd_m(1.0) * dist))
        best = np.maximum(best, np.where(visible[i], q, 0.0))
    return best


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("method", ["grid", "mesh"])
def test_incidence_limits_and_view_quality_match_the_reference(seed, method):
    case = random_grid_case(seed, nx=21, ny=17)
    terrain = Terrain.from_grid(case.z, case.spacing, origin=case.origin)
    rng = np.random.default_rng(200 + seed)
    n = 5
    uavs = uavs_above(case, n, rng, low=1.0, high=6.0)
    yaw, pitch = rng.uniform(0, 360, size=n), rng.choice([-90.0, -45.0, -20.0], size=n)
    poses = np.column_stack([uavs, yaw, pitch])
    cam = Camera(13.2, 8.8, 8.8, 5472, 3648)
    sensors = [
        Sensor(9.0, max_incidence_deg=60.0),
        Sensor(12.0, camera=cam, max_incidence_deg=45.0, good_gsd_m=0.0008),
        Sensor(10.0, camera=Camera.from_fov(84.0, 62.0), good_gsd_m=0.002),
        Sensor(8.0, max_incidence_deg=80.0),
        Sensor(15.0, camera=cam, max_incidence_deg=70.0, good_gsd_m=0.0012),
    ]
    normals = _grid_normals(case)
    points = case.vertices
    # the grid's own targets (normals from the engine) and the same points with given normals
    grid_nodes = Visibility(terrain, 5.0, method=method)
    given = Visibility(terrain, 5.0, targets=Targets.from_points(points, terrain.default_targets().weights, normals), method=method)
    np.testing.assert_array_equal(grid_nodes.targets.points, points)
    ref = visibility_reference(case.vertices, case.faces, uavs, points, 50.0)
    uncertain = ref.uncertain.copy()
    reach = _reach(uavs, camera_axes(yaw, pitch), sensors, points, normals, uncertain)
    visible = ref.visible & reach
    decided = ~(uncertain & (reach | ref.visible)).any(axis=0)
    expected_seen = visible.any(axis=0)
    for vis in (grid_nodes, given):
        seen = vis.seen(poses, sensors=sensors)
        np.testing.assert_array_equal(seen[decided], expected_seen[decided])
        quality = vis.quality(poses, sensors=sensors)
        np.testing.assert_allclose(quality[decided], _best_quality(uavs, sensors, points, normals, visible)[decided], rtol=1e-9, atol=1e-12)
        assert np.all((quality > 0) == seen)
        w = vis.targets.weights
        assert vis.quality_coverage(poses, sensors=sensors) == pytest.approx(float(quality @ w / w.sum()), rel=1e-12)
    assert decided.mean() > 0.9 and 0 < expected_seen[decided].sum() < decided.sum()
    # the limit binds: without it more targets are reached
    loose = [Sensor(s.d_max, camera=s.camera) for s in sensors]
    assert grid_nodes.seen(poses, sensors=loose).sum() > grid_nodes.seen(poses, sensors=sensors).sum()


def test_vertex_normals_are_the_engines_and_carry_incidence_to_a_subset_of_targets():
    case = random_grid_case(3, nx=19, ny=15)
    z = case.z.copy()
    z[4:6, 7:9] = np.nan  # nodata: the vertices are the valid nodes only
    terrain = Terrain.from_grid(z, case.spacing, origin=case.origin)
    normals = terrain.vertex_normals()
    full = terrain.default_targets()
    assert normals.shape == full.points.shape and np.isfinite(normals).all()
    flat = Terrain.from_grid(case.z, case.spacing, origin=case.origin)
    np.testing.assert_allclose(flat.vertex_normals(), _grid_normals(case), rtol=0, atol=1e-12)  # the numpy reference
    rng = np.random.default_rng(9)
    poses = np.column_stack([uavs_above(case, 4, rng, low=2.0, high=6.0), rng.uniform(0, 360, 4), [-90.0, -60.0, -45.0, -30.0]])
    sensors = [Sensor(12.0, camera=Camera.from_fov(84.0, 62.0), max_incidence_deg=55.0, good_gsd_m=0.002)] * 4
    whole = Visibility(terrain, 12.0)  # the grid's own targets: normals made in Rust
    keep = rng.random(full.points.shape[0]) < 0.4
    part = Visibility(terrain, 12.0, targets=Targets(full.points[keep], full.weights[keep], normals[keep]))
    np.testing.assert_array_equal(part.seen(poses, sensors=sensors), whole.seen(poses, sensors=sensors)[keep])
    np.testing.assert_array_equal(part.quality(poses, sensors=sensors), whole.quality(poses, sensors=sensors)[keep])
    mesh = Terrain(terrain.vertices, terrain.faces)
    with pytest.raises(InvalidInputError, match="grid"):
        mesh.vertex_normals()


def test_incidence_needs_normals_and_bad_quality_settings_are_errors(hill_terrain):
    bare = Visibility(hill_terrain, 8.0, targets=hill_terrain.default_targets())
    with pytest.raises(InvalidInputError, match="normals"):
        bare.seen([[5.0, 5.0, 20.0]], sensors=[Sensor(8.0, max_incidence_deg=45.0)])
    assert bare.quality([[5.0, 5.0, 20.0]]).max() <= 1.0  # without sensors: 1 where seen
    for bad in (-1.0, 91.0, math.nan):
        with pytest.raises(InvalidInputError):
            Sensor(8.0, max_incidence_deg=bad)
    with pytest.raises(InvalidInputError):
        Sensor(8.0, good_gsd_m=0.01)  # needs a camera
    pts = hill_terrain.default_targets().points[:3]
    with pytest.raises(InvalidInputError):
        Targets.from_points(pts, None, np.zeros((3, 3)))  # not unit
    with pytest.raises(InvalidInputError):
        Targets.from_points(pts, None, np.tile([0.0, 0.0, 1.0], (2, 1)))  # one short
    import pickle

    t = Targets.from_points(pts, None, np.tile([0.0, 0.0, 1.0], (3, 1)))
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(t)).normals, t.normals)


def test_a_mission_flies_cameras_and_maximises_the_objective_it_is_given(tmp_path):
    import json

    from uavcov import Constraints, MissionSettings, StartSettings, gaussian_hills, load_mission, run_mission, save_mission

    terrain = gaussian_hills(spacing=2.0, rng=1)
    camera = Camera.from_fov(84.0, 62.0)
    base = MissionSettings(
        n_uavs=4,
        d_max=40.0,
        iterations=40,
        start=StartSettings(altitude=20.0),
        constraints=Constraints(h_min=5.0, z_max=80.0),
        sensor=Sensor(40.0, camera=camera, good_gsd_m=0.01),
        attitude=(30.0, -80.0),
    )
    vis = Visibility(terrain, 40.0)
    sensors = [base.sensor] * 4
    for objective in ("coverage", "quality"):
        spec = base.with_changes(objective=objective)
        result = run_mission(terrain, spec, rng=2)
        for k in (0, 17, 40):  # every value is the objective at that configuration, cameras posed
            poses = np.column_stack([result.trajectory[k], np.full(4, 30.0), np.full(4, -80.0)])
            measure = vis.quality_coverage if objective == "quality" else vis.coverage
            assert result.coverage[k] == measure(poses, sensors=sensors)
        save_mission(result, tmp_path / f"{objective}.npz")
        assert load_mission(tmp_path / f"{objective}.npz").settings == result.settings
        assert MissionSettings.from_dict(json.loads(json.dumps(spec.as_dict()))) == spec
    omni = run_mission(terrain, base.with_changes(sensor=None), rng=2)
    assert omni.initial_coverage > result.initial_coverage  # the cameras see less than the paper's sensor


def test_missions_refuse_bad_sensor_settings():
    from uavcov import MissionSettings

    with pytest.raises(InvalidInputError):
        MissionSettings(n_uavs=2, d_max=10.0, objective="area")
    with pytest.raises(InvalidInputError, match="centralised"):
        MissionSettings(n_uavs=2, d_max=10.0, objective="quality", optimizer="per_robot")
    with pytest.raises(InvalidInputError, match="point up"):
        MissionSettings(n_uavs=2, d_max=10.0, attitude=(0.0, 15.0))
    with pytest.raises(InvalidInputError):
        MissionSettings(n_uavs=2, d_max=10.0, attitude=(0.0,))
    with pytest.raises(InvalidTypeError):
        MissionSettings(n_uavs=2, d_max=10.0, sensor="camera")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError):
        MissionSettings.from_dict({"n_uavs": 2, "d_max": 10.0, "sensor": {"d_max": 5.0, "lens": 3}})


def test_the_papers_settings_hashes_do_not_see_the_new_sensor_fields():
    from uavcov.experiments._sweep import experiment_settings, settings_hash
    from uavcov.paper import _data as paper

    for experiment in paper.EXPERIMENTS.values():
        assert not {"sensor", "attitude", "objective"} & set(experiment_settings(experiment)["mission"])
    table1 = paper.TABLE1
    camera = table1.with_changes(sensor=Sensor(25.0, camera=Camera.from_fov(60.0, 45.0)))
    assert settings_hash(camera) != settings_hash(table1)
    assert settings_hash(table1.with_changes(objective="quality")) != settings_hash(table1)
    assert settings_hash(table1.with_changes(attitude=(0.0, -90.0))) == settings_hash(table1)  # the default
