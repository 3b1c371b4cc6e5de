"""Camera missions: angles as decision variables (``MissionSettings.gimbal``), the footprint start,
and cameras in sweep files.

References: a closed form for the optimiser (a concave quadratic over positions and angles), a
flat plane whose best heading is known (it extends on one side only), and the area of a nadir
camera's square footprint against a square Voronoi cell, computed by hand.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from uavcov import (
    Camera,
    CAOSettings,
    Constraints,
    Gimbal,
    MissionSettings,
    Sensor,
    StartSettings,
    Terrain,
    Visibility,
    gaussian_hills,
    load_mission,
    run_mission,
    save_mission,
)
from uavcov.errors import ConfigError, InvalidInputError, InvalidTypeError
from uavcov.experiments import parse_sweep_config
from uavcov.experiments._sweep import settings_hash
from uavcov.optim import cao
from uavcov.paper import EXPERIMENTS as PAPER_EXPERIMENTS
from uavcov.placement import fit_footprints


def test_cao_optimises_any_number_of_variables_per_uav():
    top = np.array([[10.0, 20.0, 30.0, 4.0, -2.0]])  # a position and two angles
    start = top + np.array([[3.0, -3.0, 3.0, -3.0, 3.0]])
    trace = cao(lambda x: -float(np.sum((x - top) ** 2)), start, feasible=None, iterations=400, rng=0)
    assert trace.trajectory.shape == (401, 1, 5)
    assert np.abs(trace.best_positions - top).max() < 0.4  # from 3 off on every variable
    assert trace.settings.n_regressors == 1 + 5 + 10  # 1 + dN + max(10, N)
    with pytest.raises(InvalidInputError, match="d >= 3"):
        cao(lambda x: 0.0, np.zeros((2, 2)), feasible=None, iterations=1)


def _one_side_plane() -> Terrain:
    """Flat ground 0 <= y <= 40 m only: a UAV on the northern edge looking north sees little."""
    return Terrain.from_grid(np.zeros((41, 81)), spacing=1.0)  # 81 columns of x, 41 rows of y


def test_a_free_heading_turns_the_camera_to_where_the_surface_is():
    plane = _one_side_plane()
    sensor = Sensor(60.0, camera=Camera.from_fov(50.0, 40.0))
    spec = MissionSettings(
        n_uavs=1,
        d_max=60.0,
        iterations=150,
        sensor=sensor,
        attitude=(0.0, -30.0),  # facing north, off the plane's edge
        gimbal=Gimbal(free_yaw=True, alpha0_deg=45.0),
        # the position is all but pinned (a 1 m box, 9-11 m up): what moves the view is the heading
        constraints=Constraints(bounds=(39.5, 39.5, 40.5, 40.5), h_min=9.0, h_max=11.0, z_max=50.0, d_safe=0.0),
    )
    start = np.array([[40.0, 40.0, 10.0]])
    result = run_mission(plane, spec, start_positions=start, rng=1)
    attitudes = result.attitudes
    assert attitudes is not None and attitudes.shape == (151, 1, 2)
    assert ((attitudes[..., 0] >= 0.0) & (attitudes[..., 0] < 360.0)).all()
    assert (attitudes[..., 1] == -30.0).all()  # the pitch is not free
    # the reference: every heading 2 degrees apart, from the start's position
    vis = Visibility(plane, 60.0)
    sweep = [vis.coverage([[40.0, 40.0, 10.0, yaw, -30.0]], sensors=[sensor]) for yaw in range(0, 360, 2)]
    assert result.best_coverage >= 0.97 * max(sweep)
    assert result.best_coverage > 2.0 * result.initial_coverage  # it turned away from the edge
    # every value is the coverage of the pose the trajectory and the attitudes say
    for k in (0, 50, 150):
        pose = np.column_stack([result.trajectory[k], attitudes[k]])
        assert result.coverage[k] == vis.coverage(pose, sensors=[sensor])


def test_a_free_pitch_stays_in_its_range_at_every_iteration(tmp_path):
    terrain = gaussian_hills(size=60.0, spacing=2.0, n_hills=3, rng=4)
    gimbal = Gimbal(free_yaw=True, pitch_range=(-80.0, -40.0), alpha0_deg=40.0)
    spec = MissionSettings(
        n_uavs=3,
        d_max=40.0,
        iterations=60,
        sensor=Sensor(40.0, camera=Camera.from_fov(70.0, 50.0)),
        attitude=(10.0, -60.0),
        gimbal=gimbal,
        start=StartSettings(altitude=10.0),
        constraints=Constraints(h_min=4.0, h_max=25.0, z_max=200.0, d_safe=1.0),
        cao=CAOSettings(alpha0=2.0, stability=5.0, decay=1.0),
    )
    result = run_mission(terrain, spec, rng=3)
    state = result.trace.trajectory
    assert state.shape == (61, 3, 5)
    pitch = result.attitudes[..., 1]
    assert (pitch >= -80.0).all() and (pitch <= -40.0).all()
    assert np.ptp(pitch) > 1.0 and np.ptp(state[..., 3]) > 0.0  # both angles moved
    np.testing.assert_allclose(result.attitudes[..., 0], (state[..., 3] * 20.0) % 360.0)  # 40 deg over alpha0 2 m
    assert result.trajectory.shape == (61, 3, 3) and not result.trajectory.flags.writeable
    path = save_mission(result, tmp_path / "gimbal.npz")
    again = load_mission(path)
    assert again.settings == result.settings
    np.testing.assert_array_equal(again.attitudes, result.attitudes)
    np.testing.assert_array_equal(again.trajectory, result.trajectory)
    assert MissionSettings.from_dict(json.loads(json.dumps(spec.as_dict()))) == spec
    assert run_mission(terrain, spec, rng=3).coverage.tolist() == result.coverage.tolist()  # same rng, same run


def test_bad_gimbal_settings_are_clear_errors():
    camera = Sensor(20.0, camera=Camera.from_fov(60.0, 45.0))
    with pytest.raises(InvalidInputError, match="pitch_range"):
        Gimbal(pitch_range=(-30.0, -60.0))
    with pytest.raises(InvalidInputError, match="pitch_range"):
        Gimbal(pitch_range=(-100.0, 0.0))
    with pytest.raises(InvalidInputError, match="pitch_range"):
        Gimbal(pitch_range=(-60.0,))  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError):
        Gimbal(alpha0_deg=0.0)
    with pytest.raises(InvalidTypeError):
        Gimbal(free_yaw="yes")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="camera"):
        MissionSettings(n_uavs=2, d_max=20.0, gimbal=Gimbal(free_yaw=True))
    with pytest.raises(InvalidInputError, match="centralised"):
        MissionSettings(n_uavs=2, d_max=20.0, sensor=camera, gimbal=Gimbal(free_yaw=True), optimizer="per_robot")
    with pytest.raises(InvalidInputError, match="outside"):
        MissionSettings(n_uavs=2, d_max=20.0, sensor=camera, attitude=(0.0, -90.0), gimbal=Gimbal(pitch_range=(-60.0, -30.0)))
    with pytest.raises(InvalidTypeError):
        MissionSettings(n_uavs=2, d_max=20.0, sensor=camera, gimbal="free")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="camera"):
        MissionSettings(n_uavs=2, d_max=20.0, footprint_start=True)
    MissionSettings(n_uavs=2, d_max=20.0, gimbal=Gimbal())  # nothing free: fine without a camera


def _jaccard_of_nadir_square(height: float, half_fov_deg: float) -> float:
    """A nadir square footprint over the cell [0, 60]^2 of the plane [0, 120]^2, centred on (30, 30)."""
    half = height * math.tan(math.radians(half_fov_deg))
    lo, hi = max(0.0, 30.0 - half), 30.0 + half
    seen = (hi - lo) ** 2
    inside = (min(60.0, hi) - lo) ** 2
    return inside / (3600.0 + seen - inside)


def test_the_footprint_start_picks_the_height_of_the_hand_computed_best_match():
    flat = Terrain.from_grid(np.zeros((121, 121)), spacing=1.0)
    sensor = Sensor(200.0, camera=Camera.from_fov(60.0, 60.0))
    starts = np.array([[30.0, 30.0, 2.0], [90.0, 30.0, 2.0], [30.0, 90.0, 2.0], [90.0, 90.0, 2.0]])
    fit = fit_footprints(flat, starts, sensor, [[0.0, -90.0]] * 4, heights=(10.0, 100.0), n_heights=19)
    heights = np.linspace(10.0, 100.0, 19)
    expected = heights[int(np.argmax([_jaccard_of_nadir_square(h, 30.0) for h in heights]))]
    assert fit.positions[:, 2].tolist() == [expected] * 4
    np.testing.assert_allclose(fit.match, _jaccard_of_nadir_square(expected, 30.0), atol=0.03)  # targets are a 1 m grid
    np.testing.assert_array_equal(fit.positions[:, :2], starts[:, :2])
    with pytest.raises(InvalidInputError, match="camera"):
        fit_footprints(flat, starts, Sensor(50.0), [[0.0, -90.0]] * 4, heights=(10.0, 100.0))
    with pytest.raises(InvalidInputError, match="attitudes"):
        fit_footprints(flat, starts, sensor, [[0.0, -90.0]] * 3, heights=(10.0, 100.0))
    with pytest.raises(InvalidInputError, match="heights"):
        fit_footprints(flat, starts, sensor, [[0.0, -90.0]] * 4, heights=(50.0, 10.0))
    with pytest.raises(InvalidInputError, match="poses per UAV"):
        fit_footprints(flat, starts, sensor, [[0.0, -90.0]] * 4, heights=(10.0, 100.0), n_heights=10**9)
    with pytest.raises(InvalidInputError, match="beyond"):
        fit_footprints(flat, starts, sensor, [[0.0, -90.0]] * 4, heights=(1e300, 1e300))


def test_a_footprint_start_sees_more_of_the_hills_than_the_papers_low_start():
    terrain = gaussian_hills(size=80.0, spacing=1.0, n_hills=5, rng=7)
    spec = MissionSettings(
        n_uavs=6,
        d_max=50.0,
        iterations=0,
        sensor=Sensor(50.0, camera=Camera.from_fov(60.0, 45.0)),
        constraints=Constraints(h_min=3.0, h_max=40.0, z_max=200.0, d_safe=1.0),
    )
    low = run_mission(terrain, spec, rng=0)
    fitted = run_mission(terrain, spec.with_changes(footprint_start=True), rng=0)
    np.testing.assert_array_equal(fitted.start_positions[:, :2], low.start_positions[:, :2])  # the same cells
    assert fitted.initial_coverage > 2.0 * low.initial_coverage
    assert (fitted.start_positions[:, 2] > low.start_positions[:, 2]).all()


CAMERA_SWEEP = {
    "seeds": [1000],
    "team_sizes": [3],
    "starts": ["cvt"],
    "iterations": 2,
    "terrain": {"spacing": 5.0},
    "objective": "quality",
    "attitude": [10.0, -60.0],
    "footprint_start": True,
    "constraints": {"h_max": 30.0},
    "sensor": {"good_gsd_m": 0.02, "camera": {"hfov_deg": 84.0, "vfov_deg": 62.0}},
    "gimbal": {"free_yaw": True, "pitch_range": [-90.0, -30.0]},
    "sweep": {"sensor.camera.hfov_deg": [60.0, 84.0], "d_max": [25.0, 40.0]},
}


def test_a_sweep_file_sets_and_sweeps_cameras():
    config = parse_sweep_config(CAMERA_SWEEP, bases=PAPER_EXPERIMENTS)
    assert len(config.variants) == 4 and len(config.specs()) == 4
    hashes = set()
    for experiment, extra in config.variants:
        swept = dict(extra)
        mission = experiment.mission
        assert mission.objective == "quality" and mission.attitude == (10.0, -60.0) and mission.footprint_start
        assert mission.gimbal == Gimbal(free_yaw=True, pitch_range=(-90.0, -30.0))
        assert mission.sensor is not None and mission.sensor.camera is not None
        assert mission.sensor.d_max == swept["d_max"] == mission.d_max  # the sensor's range follows d_max
        assert mission.sensor.good_gsd_m == 0.02
        assert mission.sensor.camera == Camera.from_fov(swept["sensor.camera.hfov_deg"], 62.0)
        hashes.add(settings_hash(experiment))
    assert len(hashes) == 4
    names = ("sensor_width_mm", "sensor_height_mm", "focal_length_mm", "image_width_px", "image_height_px")
    camera = dict(zip(names, (13.2, 8.8, 8.8, 5472, 3648), strict=True))
    lens = {**CAMERA_SWEEP, "sweep": {}, "sensor": {"d_max": 30.0, "camera": camera}}
    ((experiment, _),) = parse_sweep_config(lens, bases=PAPER_EXPERIMENTS).variants
    assert experiment.mission.sensor == Sensor(30.0, camera=Camera(13.2, 8.8, 8.8, 5472, 3648))


@pytest.mark.parametrize(
    "change, message",
    [
        ({"sensor": {"rnage": 3.0}}, "sensor.rnage"),
        ({"sensor": {"camera": {"hfov": 60.0}}}, "hfov_deg"),
        ({"sensor": {"camera": {"hfov_deg": 200.0, "vfov_deg": 60.0}}}, "sensor.camera"),
        ({"sensor": {"camera": {"hfov_deg": 60.0, "vfov_deg": 60.0, "focal_length_mm": 8.0}}}, "not both"),
        ({"sensor": {"d_min": 90.0}}, "sensor"),
        ({"gimbal": {"pitch_range": [-10.0, -60.0]}}, "gimbal"),
        ({"gimbal": {"free_yaw": "yes"}}, "gimbal.free_yaw"),
        ({"objective": "area"}, "objective"),
        ({"attitude": [0.0]}, "attitude"),
        ({"sensor": 3}, "sensor"),
    ],
)
def test_bad_camera_tables_are_config_errors_naming_the_key(change, message):
    with pytest.raises(ConfigError, match=message):
        parse_sweep_config({**CAMERA_SWEEP, "sweep": {}, **change}, bases=PAPER_EXPERIMENTS)


def test_sweeping_a_camera_field_needs_its_table():
    plain = {k: v for k, v in CAMERA_SWEEP.items() if k not in ("sensor", "gimbal", "objective", "footprint_start")}
    with pytest.raises(ConfigError, match="give that table first"):
        parse_sweep_config({**plain, "sweep": {"sensor.camera.hfov_deg": [60.0]}}, bases=PAPER_EXPERIMENTS)


def test_the_example_camera_sweep_parses():
    from pathlib import Path

    from uavcov.experiments import load_sweep_config

    config = load_sweep_config(Path(__file__).parents[1] / "examples" / "camera_sweep.toml", bases=PAPER_EXPERIMENTS)
    assert config.axes == ("sensor.camera.hfov_deg",) and len(config.specs()) == 2 * 5 * 2
    assert all(e.mission.footprint_start and e.mission.gimbal == Gimbal(free_yaw=True) for e, _ in config.variants)


def test_a_mixed_team_flies_each_uavs_own_sensor(tmp_path):
    terrain = gaussian_hills(size=60.0, spacing=2.0, n_hills=3, rng=8)
    team = (
        Sensor(40.0, camera=Camera.from_fov(84.0, 62.0)),
        Sensor(25.0),  # an omnidirectional UAV of shorter range
        Sensor(35.0, camera=Camera.from_fov(50.0, 40.0), d_min=2.0),
    )
    spec = MissionSettings(
        n_uavs=3,
        d_max=40.0,
        iterations=25,
        sensor=team,
        attitude=(20.0, -70.0),
        gimbal=Gimbal(free_yaw=True),
        footprint_start=True,
        start=StartSettings(altitude=8.0),
        constraints=Constraints(h_min=4.0, h_max=30.0, z_max=200.0, d_safe=1.0),
    )
    assert spec.team_sensors() == list(team) and spec.has_camera
    result = run_mission(terrain, spec, rng=2)
    vis = Visibility(terrain, 40.0)
    for k in (0, 12, 25):
        poses = np.column_stack([result.trajectory[k], result.attitudes[k]])
        assert result.coverage[k] == vis.coverage(poses, sensors=list(team))
    plain = run_mission(terrain, spec.with_changes(footprint_start=False), rng=2)
    np.testing.assert_array_equal(result.start_positions[1], plain.start_positions[1])  # the omnidirectional UAV is not lifted
    assert (result.start_positions[[0, 2], 2] > plain.start_positions[[0, 2], 2]).all()
    path = save_mission(result, tmp_path / "mixed.npz")
    assert load_mission(path).settings == result.settings
    assert MissionSettings.from_dict(json.loads(json.dumps(spec.as_dict()))) == spec
    with pytest.raises(InvalidInputError, match="one per UAV"):
        spec.with_changes(n_uavs=4)
    with pytest.raises(InvalidTypeError):
        MissionSettings(n_uavs=2, d_max=10.0, sensor=(Sensor(10.0), "camera"))  # type: ignore[arg-type]
