"""Hostile input, round three: what ``scripts/fuzz_public_api.py`` found getting through.

Each class is tried with several hostile values, each asserting the precise error of
:mod:`uavcov.errors` and a message naming the argument: sizes refused before anything is
allocated, numbers whose square or clock overflows, complex and string arrays that numpy would
have cast silently, a word given where a choice of words is meant, a world that is not one, far
points, a plan's record, a structures experiment's settings and a figure's output.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

import uavcov
from refusals import refused
from uavcov.errors import ConfigError, InvalidInputError, InvalidTypeError

HILLS = uavcov.gaussian_hills(size=30, spacing=1, n_hills=2, rng=0)
POINTS = np.array([[5.0, 5.0, 30.0], [15.0, 12.0, 25.0]])


# ---------------------------------------------------------------------------------------------
# Sizes refused before allocating (they raised MemoryError or numpy's "array is too big")


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"size": 1e15}, "size .*uavcov's size limit"),
        ({"size": 1e300}, "size .*uavcov's size limit"),
        ({"size": 100.0, "spacing": 1e-9}, "size .*uavcov's size limit"),
        ({"n_hills": 10**12}, "n_hills must be at most"),
        ({"sigma": 1e300}, "sigma must have a finite, non-zero square"),
        ({"sigma": 1e-200}, "sigma must have a finite, non-zero square"),
    ],
)
def test_gaussian_hills_refuses_sizes_before_allocating(kwargs: dict[str, Any], words: str) -> None:
    refused(InvalidInputError, words, uavcov.gaussian_hills, rng=0, **kwargs)


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"size": 1e15}, "size .*uavcov's size limit"),
        ({"size": 24.0, "spacing": 1e-12}, "size .*uavcov's size limit"),
        ({"heights": 1e15}, "height .*uavcov's size limit"),
        ({"heights": (3.0, 1e12)}, "height .*uavcov's size limit"),
    ],
)
def test_buildings_scene_refuses_sizes_before_allocating(kwargs: dict[str, Any], words: str) -> None:
    refused(InvalidInputError, words, uavcov.terrain.buildings_scene, rng=0, **kwargs)


@pytest.mark.parametrize("n", [10**12, 2**63, 10**7 + 1])
def test_a_random_prior_refuses_a_huge_n(n: int) -> None:
    refused(InvalidInputError, "n must be at most", uavcov.terrain.sample_prior, HILLS, n, rng=0)


@pytest.mark.parametrize("optimizer", ["cao", "per_robot_cao"])
@pytest.mark.parametrize("iterations", [10**12, 10**6 + 1, 2**63])
def test_cao_refuses_huge_iterations_before_allocating(optimizer: str, iterations: int) -> None:
    from uavcov import optim

    def measure(x: np.ndarray) -> Any:
        return (0.0, np.zeros(x.shape[0])) if optimizer == "per_robot_cao" else 0.0

    refused(
        InvalidInputError,
        "iterations must be at most",
        getattr(optim, optimizer),
        measure,
        np.ones((2, 3)),
        feasible=None,
        iterations=iterations,
    )


@pytest.mark.parametrize("builder", ["girder_bridge", "facade"])
@pytest.mark.parametrize(
    "step, error, words",
    [
        (float("inf"), InvalidInputError, "step must be finite"),
        (float("nan"), InvalidInputError, "step must be finite"),
        (-1.0, InvalidInputError, r"step must be > 0"),
        (0.0, InvalidInputError, r"step must be > 0"),
        (1e-300, InvalidInputError, "step = .*uavcov's size limit"),
        (None, InvalidTypeError, "step must be a real number"),
        ("1", InvalidTypeError, "step must be a real number"),
    ],
)
def test_a_structure_step_is_checked_before_the_mesh_is_made(builder: str, step: Any, error: type[Exception], words: str) -> None:
    refused(error, words, getattr(uavcov.structures, builder), rng=0, step=step)


@pytest.mark.parametrize("time_limit", [1e300, 1e10, 2.0**64])
def test_exact_placement_refuses_a_time_limit_past_the_clock(time_limit: float) -> None:
    from uavcov.cover import CoverageProblem, exact_placement

    problem = CoverageProblem(uavcov.Visibility(HILLS, 10.0, n_threads=1), POINTS, n_threads=1)
    refused(InvalidInputError, "time_limit must be at most", exact_placement, problem, 1, time_limit=time_limit)


@pytest.mark.parametrize("spacing", [1e300, 1e200, 1e-300])
def test_viewpoint_offsets_refuses_a_spacing_whose_square_overflows(spacing: float) -> None:
    from uavcov.cover import viewpoint_offsets

    surface = uavcov.structures.girder_bridge(rng=0).surface
    constraints = uavcov.Constraints(h_min=1.0, clearance="standoff")
    refused(
        InvalidInputError, "spacing must have a finite, non-zero square", viewpoint_offsets, surface, constraints, (3.0,), spacing=spacing
    )


# ---------------------------------------------------------------------------------------------
# Arrays numpy would cast silently (complex lost its imaginary part) or with its own errors


HOSTILE_ARRAYS = [
    pytest.param(np.ones((2, 3), complex), InvalidTypeError, "must hold real numbers", id="complex"),
    pytest.param(np.array([["a", "b", "c"]]), InvalidTypeError, "must hold real numbers", id="strings"),
    pytest.param(np.array([[1.0, None, 2.0]], dtype=object), InvalidTypeError, "must hold real numbers", id="objects"),
    pytest.param({}, InvalidTypeError, "must hold real numbers", id="dict"),
    pytest.param("abc", InvalidTypeError, "must be a numeric array", id="str"),
    pytest.param(np.full((2, 3), np.nan), InvalidInputError, "contains NaN or infinite", id="nan"),
]


@pytest.mark.parametrize("value, error, words", HOSTILE_ARRAYS)
def test_sensed_points_are_read_as_real_arrays(value: Any, error: type[Exception], words: str) -> None:
    from uavcov.sim import VoxelMap, observed_targets, sensed_coverage

    targets = HILLS.default_targets()
    refused(error, "points " + words, observed_targets, targets, value, 1.0)
    refused(error, "points " + words, sensed_coverage, targets, value, 1.0)
    refused(error, "points " + words, VoxelMap(0.5).add, value)


@pytest.mark.parametrize("value", [np.ones((2, 5)), np.ones((3, 2)), np.ones(7)])
def test_sensed_points_of_the_wrong_shape_are_refused_not_reshaped(value: np.ndarray) -> None:
    from uavcov.sim import observed_targets

    refused(InvalidInputError, r"points must have shape \(n, 3\)", observed_targets, HILLS.default_targets(), value, 1.0)


def test_sensed_points_still_take_an_empty_cloud_and_a_single_point() -> None:
    from uavcov.sim import observed_targets

    targets = HILLS.default_targets()
    assert not observed_targets(targets, np.empty((0, 3)), 1.0).any()
    assert not observed_targets(targets, [], 1.0).any()
    near = targets.points[0]
    assert observed_targets(targets, near, 0.5)[0]


@pytest.mark.parametrize("value, error, words", HOSTILE_ARRAYS)
def test_a_depth_camera_reads_its_pose_and_field_of_view_as_real_arrays(value: Any, error: type[Exception], words: str) -> None:
    from uavcov.sim import DepthCamera

    camera = DepthCamera(8, 6, (60.0, 45.0), 10.0)
    refused(error, "position " + words, camera.render, HILLS, value, np.eye(3))
    refused(error, "rotation " + words, camera.render, HILLS, np.array([10.0, 10.0, 30.0]), value)
    if not isinstance(value, str):  # a string keeps its range message (tests/test_sim_sensing.py)
        refused(error, "fov_deg " + words, DepthCamera, 8, 6, value, 10.0)


@pytest.mark.parametrize("value, error, words", HOSTILE_ARRAYS)
def test_flight_settings_and_a_team_read_their_vectors_as_real_arrays(value: Any, error: type[Exception], words: str) -> None:
    pytest.importorskip("rotorpy")
    from uavcov.sim import FlightSettings, Team

    if not isinstance(value, str):  # a string keeps its range message (tests/test_sim_flight.py)
        refused(error, "wind " + words, FlightSettings, wind=value)
        refused(error, "gusts " + words, FlightSettings, gusts=value)
    settings = FlightSettings(dt=0.05, max_leg_s=2.0)
    refused(error, "positions " + words, Team.hovering, value, settings, HILLS, rng=0)
    team = Team.hovering(POINTS, settings, HILLS, rng=0)
    refused(error, "waypoints " + words, team.fly, value)


# ---------------------------------------------------------------------------------------------
# A choice of words given something else (numpy's "truth value of an array is ambiguous")

NOT_WORDS = [np.array(["cvt"]), np.zeros(0), ["cvt"], 3, None]


@pytest.mark.parametrize("value", NOT_WORDS, ids=["str-array", "empty-array", "list", "int", "None"])
@pytest.mark.parametrize(
    "make, words",
    [
        (lambda v: uavcov.MissionSettings(n_uavs=2, d_max=10.0, prior=v), "prior must be one of"),
        (lambda v: uavcov.MissionSettings(n_uavs=2, d_max=10.0, optimizer=v), "optimizer must be one of"),
        (lambda v: uavcov.MissionSettings(n_uavs=2, d_max=10.0, objective=v), "objective must be one of"),
        (lambda v: uavcov.CAOSettings(infeasible=v), "infeasible must be one of"),
        (lambda v: uavcov.StartSettings(corner=v), "corner must be one of"),
        (lambda v: uavcov.StartSettings(altitude_reference=v), "altitude_reference must be one of"),
        (lambda v: uavcov.PlanSettings(n_uavs=2, d_max=10.0, takeoff_frame=v), "takeoff_frame must be one of"),
        (lambda v: uavcov.sim.SimSettings(measurement=v), "measurement must be one of"),
        (lambda v: uavcov.sim.FlightSettings(vehicle=v), "vehicle must be one of"),
        (lambda v: uavcov.sim.FlightSettings(integrator=v), "integrator must be one of"),
        (uavcov.optim.cao_preset, "CAO preset must be one of"),
        (lambda v: uavcov.field.bbox_area(0.0, 0.0, 1.0, 1.0, frame=v), "frame must be one of"),
        (lambda v: uavcov.structures.reconstruct_structure(_structure_prior(), method=v), "method must be one of"),
        (lambda v: uavcov.structures.coarse_structure_prior(uavcov.structures.girder_bridge(rng=0), kind=v), "kind must be 'boxes'"),
        (lambda v: uavcov.paper.TABLE1.mission_settings(2, v), "start must be one of"),
    ],
)
def test_a_choice_of_words_refuses_anything_but_a_word(make: Any, words: str, value: Any) -> None:
    refused(InvalidInputError, words, make, value)


def _structure_prior() -> Any:
    return uavcov.structures.sample_structure_prior(uavcov.structures.girder_bridge(rng=0), 100, rng=0)


@pytest.mark.parametrize("value", [np.array(["full"]), ["full"], None, 2.5])
def test_plan_settings_prior_is_full_or_a_count(value: Any) -> None:
    refused(InvalidInputError, "prior must be 'full' or a number", uavcov.PlanSettings, n_uavs=2, d_max=10.0, prior=value)


@pytest.mark.parametrize(
    "argument, value", [("vertical_datum", np.zeros(0)), ("vertical_datum", 3), ("source", None), ("source", np.zeros(3))]
)
def test_dem_from_array_refuses_non_strings_for_its_labels(argument: str, value: Any) -> None:
    transform = (30.0, 0.0, 500000.0, 0.0, -30.0, 4000000.0)
    refused(
        InvalidTypeError,
        f"{argument} must be",
        uavcov.terrain.dem_from_array,
        np.zeros((4, 5)),
        transform,
        "EPSG:32617",
        **{argument: value},
    )


# ---------------------------------------------------------------------------------------------
# A world that is not one; far points; a flown mission's fraction


@pytest.mark.parametrize("world", [None, 3.0, "terrain", np.zeros((2, 3)), uavcov.Targets(POINTS)])
def test_constraints_refuse_a_world_that_is_not_one(world: Any) -> None:
    constraints = uavcov.Constraints()
    refused(InvalidTypeError, "world must provide bounds", constraints.resolve, world)
    refused(InvalidTypeError, "world must provide bounds", constraints.check_team, 2, world)
    refused(InvalidTypeError, "world must provide bounds", uavcov.Constraints.for_world, world)


@pytest.mark.parametrize("value", [1e300, -1e300, 1e16])
def test_a_structure_prior_refuses_points_beyond_the_engines_bound(value: float) -> None:
    prior = _structure_prior()
    refused(InvalidInputError, "points must lie within 1e15 m", prior.behind, np.full((3, 3), value))


@pytest.mark.parametrize("value", [1e300, -1e300, 1e16])
def test_known_points_beyond_the_engines_bound_are_refused(value: float) -> None:
    known = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 1.0], [0.0, 10.0, value]])
    refused(InvalidInputError, "samples must lie within", uavcov.terrain.approximate_surface, known)
    settings = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=1)
    refused(InvalidInputError, "points must lie within 1e15 m", uavcov.run_mission, HILLS, settings, known=known, rng=0, n_threads=1)


@pytest.fixture(scope="module")
def flown() -> Any:
    pytest.importorskip("rotorpy")
    from uavcov.sim import FlightSettings, SimSettings, fly_mission

    settings = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=1, cao=uavcov.CAOSettings(n_candidates=10))
    return fly_mission(HILLS, settings, SimSettings(flight=FlightSettings(dt=0.05, max_leg_s=2.0), render=False), rng=0)


@pytest.mark.parametrize(
    "fraction, error, words",
    [
        (float("nan"), InvalidInputError, "fraction must be finite"),
        (float("inf"), InvalidInputError, "fraction must be finite"),
        (1.5, InvalidInputError, r"fraction must be in \[0, 1\]"),
        (-0.1, InvalidInputError, r"fraction must be in \[0, 1\]"),
        (None, InvalidTypeError, "fraction must be a real number"),
        (np.zeros(3), InvalidTypeError, "fraction must be a real number"),
    ],
)
def test_time_to_fraction_refuses_a_fraction_no_run_reaches(flown: Any, fraction: Any, error: type[Exception], words: str) -> None:
    refused(error, words, flown.time_to_fraction, fraction)
    assert flown.time_to_fraction(1.0) >= flown.time_to_fraction(0.0) >= 0.0


# ---------------------------------------------------------------------------------------------
# A plan's record: the command and the run time


@pytest.fixture(scope="module")
def flight_plan() -> Any:
    pytest.importorskip("rasterio")
    pytest.importorskip("matplotlib")
    settings = uavcov.PlanSettings(n_uavs=2, d_max=200.0, iterations=1, cao=uavcov.CAOSettings(n_candidates=10))
    return uavcov.plan(uavcov.sample_dem(window=(0, 10, 0, 10)), settings, rng=0, n_threads=1)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"command": np.zeros(2)}, InvalidTypeError, "command must be None or a string"),
        ({"command": 3}, InvalidTypeError, "command must be None or a string"),
        ({"runtime_s": "1"}, InvalidTypeError, "runtime_s must be a real number"),
        ({"runtime_s": np.zeros(2)}, InvalidTypeError, "runtime_s must be a real number"),
        ({"runtime_s": float("nan")}, InvalidInputError, "runtime_s must be finite"),
        ({"runtime_s": -1.0}, InvalidInputError, "runtime_s must be >= 0"),
    ],
)
def test_write_plan_checks_its_record_before_writing(
    flight_plan: Any, tmp_path: Path, kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    refused(error, words, uavcov.write_plan, flight_plan, tmp_path / "plan", **kwargs)
    assert not (tmp_path / "plan").exists()


# ---------------------------------------------------------------------------------------------
# The structures experiment's settings (accepted as NaN, None or text, failing hours later)


@pytest.mark.parametrize(
    "change, error, words",
    [
        ({"d_max": float("nan")}, ConfigError, "d_max must be finite"),
        ({"d_max": None}, InvalidTypeError, "d_max must be a real number"),
        ({"n_uavs": 0}, ConfigError, "n_uavs must be >= 1"),
        ({"n_uavs": 2.5}, InvalidTypeError, "n_uavs must be an integer"),
        ({"iterations": 10**12}, ConfigError, "iterations must be at most"),
        ({"h_min": -1.0}, ConfigError, "h_min must be >= 0"),
        ({"reference_distances": (3.0, float("inf"))}, ConfigError, "reference_distances must be finite"),
        ({"report_seeds": None}, InvalidTypeError, "report_seeds must be a tuple"),
        ({"offsets": "2.5"}, InvalidTypeError, "offsets must be a tuple"),
        ({"families": (3,)}, InvalidTypeError, "families must be names"),
        ({"dev_seeds": (-1,)}, ConfigError, "seeds must be >= 0"),
    ],
)
def test_the_structures_experiment_checks_every_setting(change: dict[str, Any], error: type[Exception], words: str) -> None:
    from uavcov.paper import StructuresExperiment

    refused(error, words, StructuresExperiment, **change)


# ---------------------------------------------------------------------------------------------
# A figure's output, resolution and view


@pytest.fixture(scope="module")
def mission() -> Any:
    settings = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=2, cao=uavcov.CAOSettings(n_candidates=10))
    return uavcov.run_mission(HILLS, settings, rng=0, n_threads=1)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"dpi": 1e300}, InvalidInputError, "dpi must be at most"),
        ({"dpi": float("nan")}, InvalidInputError, "dpi must be finite"),
        ({"dpi": 0.0}, InvalidInputError, "dpi must be > 0"),
        ({"dpi": "110"}, InvalidTypeError, "dpi must be a real number"),
        ({"out": True}, InvalidTypeError, "out must be None, a path"),
        ({"out": 3}, InvalidTypeError, "out must be None, a path"),
        ({"elev": float("nan")}, InvalidInputError, "elev must be finite"),
        ({"azim": float("inf")}, InvalidInputError, "azim must be finite"),
    ],
)
def test_a_figure_checks_its_output_and_view(
    mission: Any, tmp_path: Path, kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_approximation

    options = {"out": tmp_path / "a.png", **kwargs}
    refused(error, words, plot_approximation, mission, **options)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"out": None}, InvalidTypeError, "out must be a path"),
        ({"out": True}, InvalidTypeError, "out must be a path"),
        ({"dpi": 1e300}, InvalidInputError, "dpi must be at most"),
        ({"dpi": np.zeros(2)}, InvalidTypeError, "dpi must be a real number"),
    ],
)
def test_an_animation_checks_its_output_before_drawing(
    mission: Any, tmp_path: Path, kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import animate_mission

    options = {"out": tmp_path / "a.gif", **kwargs}
    refused(error, words, animate_mission, mission, **options)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"directory": None}, InvalidTypeError, "directory must be a path"),
        ({"directory": 3}, InvalidTypeError, "directory must be a path"),
        ({"max_runs": 1e300}, InvalidTypeError, "max_runs must be an integer"),
        ({"max_runs": -1}, InvalidInputError, "max_runs must be >= 0"),
        ({"max_runs": 10**12}, InvalidInputError, "max_runs must be at most"),
        ({"out": True}, InvalidTypeError, "out must be None, a path"),
    ],
)
def test_plot_directory_checks_its_arguments(tmp_path: Path, kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_directory

    options = {"directory": tmp_path, **kwargs}
    refused(error, words, plot_directory, **options)


# ---------------------------------------------------------------------------------------------
# A flag given an array or a number (numpy's "truth value of an array is ambiguous")

NOT_FLAGS = [np.zeros(0), np.ones(3, bool), 1, None, "yes"]
TRIANGLE = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])


def _bridge() -> Any:
    return uavcov.structures.girder_bridge(rng=0)


@pytest.mark.parametrize("value", NOT_FLAGS, ids=["empty-array", "bool-array", "int", "None", "str"])
@pytest.mark.parametrize(
    "make, name",
    [
        (lambda v: uavcov.structures.girder_bridge(rng=0).face_mask(include_ground=v), "include_ground"),
        (lambda v: uavcov.structures.girder_bridge(rng=0).targets(2.0, include_ground=v), "include_ground"),
        (lambda v: uavcov.structures.sample_structure_prior(_bridge(), 10, normals=v, rng=0), "normals"),
        (
            lambda v: uavcov.structures.sample_structure_prior(_bridge(), 10, include_ground=v, rng=0),
            "include_ground",
        ),
        (
            lambda v: uavcov.Terrain(TRIANGLE, [[0, 1, 2]], drop_degenerate=v),
            "drop_degenerate",
        ),
        (
            lambda v: uavcov.cover.viewpoint_lattice(HILLS, uavcov.Constraints(), uavcov.cover.GreedySettings(10.0), cameras=v),
            "cameras",
        ),
        (
            lambda v: HILLS.admissible_mask(
                POINTS, POINTS[None] + 1.0, bounds=(0.0, 0.0, 30.0, 30.0), h_min=2.0, h_max=None, z_max=50.0, d_safe=1.0, check_moves=v
            ),
            "check_moves",
        ),
    ],
)
def test_a_flag_is_true_or_false_only(make: Any, name: str, value: Any) -> None:
    refused(InvalidTypeError, f"{name} must be True or False", make, value)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"closed": np.zeros(0)}, InvalidTypeError, "closed must be True or False"),
        ({"add_ground": None}, InvalidTypeError, "add_ground must be True or False"),
        ({"max_faces": float("nan")}, InvalidTypeError, "max_faces must be an integer"),
        ({"max_faces": 0}, InvalidInputError, "max_faces must be >= 1"),
        ({"max_extent": float("inf")}, InvalidInputError, "max_extent must be finite"),
        ({"max_extent": "big"}, InvalidTypeError, "max_extent must be a real number"),
    ],
)
def test_load_structure_checks_its_options(tmp_path: Path, kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    pytest.importorskip("trimesh")
    path = tmp_path / "tetra.obj"
    path.write_text("v 0 0 0\nv 4 0 0\nv 0 4 0\nv 0 0 4\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")
    refused(error, words, uavcov.structures.load_structure, path, **kwargs)


# ---------------------------------------------------------------------------------------------
# A path given something else; a seed that is not one; an attitude that is not a pair


@pytest.mark.parametrize("value", [None, 3, np.zeros(2), True])
def test_paths_are_strings_or_pathlike(value: Any) -> None:
    from uavcov.experiments import ResultsFolder, load_sweep_config
    from uavcov.sim import load_flown

    refused(InvalidTypeError, "path must be a path string", ResultsFolder, value)
    refused(InvalidTypeError, "path must be a path string", load_sweep_config, value, bases={})
    refused(InvalidTypeError, "path must be a path string", load_flown, value)


@pytest.mark.parametrize("optimizer", ["cao", "per_robot_cao"])
@pytest.mark.parametrize("rng", ["abc", -1, 1.5, [1.0, "x"]])
def test_cao_refuses_a_seed_that_is_not_one(optimizer: str, rng: Any) -> None:
    from uavcov import optim

    def measure(x: np.ndarray) -> Any:
        return (0.0, np.zeros(x.shape[0])) if optimizer == "per_robot_cao" else 0.0

    refused(
        InvalidTypeError,
        "rng must be None, an int",
        getattr(optim, optimizer),
        measure,
        np.ones((2, 3)),
        feasible=None,
        iterations=2,
        rng=rng,
    )


@pytest.mark.parametrize(
    "attitude, error", [([[1.0, 2.0], [3.0]], InvalidInputError), ({}, InvalidTypeError), (np.ones(2, complex), InvalidTypeError)]
)
def test_an_attitude_that_is_not_a_pair_of_angles_is_refused(attitude: Any, error: type[Exception]) -> None:
    refused(error, "attitude", uavcov.MissionSettings, n_uavs=2, d_max=10.0, attitude=attitude)
    refused(error, "attitude", uavcov.PlanSettings, n_uavs=2, d_max=10.0, attitude=attitude)


# ---------------------------------------------------------------------------------------------
# A structure's part labels: floats were truncated, huge numbers overflowed int32


@pytest.mark.parametrize(
    "change, error, words",
    [
        ({"face_parts": "float"}, InvalidTypeError, "face_parts must hold integers"),
        ({"face_parts": "huge"}, InvalidInputError, "face_parts must be"),
        ({"face_parts": None}, InvalidTypeError, "face_parts must hold integers"),
        ({"face_parts": "ragged"}, InvalidInputError, "face_parts cannot be read"),
        ({"part_names": None}, InvalidTypeError, "part_names must be a tuple of strings"),
        ({"part_names": (1, 2)}, InvalidTypeError, "part_names must be a tuple of strings"),
        ({"ground_part": 7}, InvalidInputError, "ground_part must be None or an index"),
        ({"ground_part": float("nan")}, InvalidInputError, "ground_part must be None or an index"),
        ({"name": None}, InvalidTypeError, "name must be a string"),
    ],
)
def test_a_structure_checks_its_parts(change: dict[str, Any], error: type[Exception], words: str) -> None:
    from uavcov.structures import Structure

    n = HILLS.n_faces
    values = {"float": np.full(n, 0.7), "huge": np.full(n, 10**15), "ragged": [[0], [0, 0]]}
    fields = {"name": "s", "surface": HILLS, "face_parts": np.zeros(n, np.int64), "part_names": ("ground",), "ground_part": 0}
    fields.update({key: values.get(value, value) if isinstance(value, str) else value for key, value in change.items()})
    refused(error, words, Structure, **fields)


@pytest.mark.parametrize(
    "parts, error, words",
    [
        (np.array([0.0, 1.0]), InvalidTypeError, "parts must hold integers"),
        (np.array([0, 10**15]), InvalidInputError, "parts must be 2 indices"),
        (np.array(["a", "b"]), InvalidTypeError, "parts must hold integers"),
        (None, InvalidTypeError, "parts must hold integers"),
    ],
)
def test_structure_targets_check_their_parts(parts: Any, error: type[Exception], words: str) -> None:
    from uavcov.structures import StructureTargets

    normals = np.array([[0.0, 0, 1], [0, 0, 1]])
    refused(error, words, StructureTargets, POINTS, np.ones(2), normals, parts, ("a", "b"))


# ---------------------------------------------------------------------------------------------
# The realistic report of a folder that is not a realistic run's (a KeyError before)


@pytest.mark.parametrize(
    "config, rows, words",
    [
        ('{"name": "sweep", "runs": {}}', "", "is not a realistic run's config"),
        ("{not json", "", "is not JSON"),
        ("[1, 2]", "", "is not a realistic run's config"),
        ('{"seeds": 3, "starts": [], "measurements": []}', "", "is not a realistic run's config"),
        ('{"seeds": [0], "starts": ["cvt"], "measurements": ["exact"]}', "[1, 2]\n", "holds a row that is not"),
        ('{"seeds": [0], "starts": ["cvt"], "measurements": ["exact"]}', '{"seed": 0}\n', "holds a row that is not"),
    ],
)
def test_the_realistic_report_refuses_a_folder_of_another_kind(tmp_path: Path, config: str, rows: str, words: str) -> None:
    from uavcov.errors import ResultsFormatError
    from uavcov.paper import write_realistic_report
    from uavcov.paper._realistic import CONFIG, ROWS

    (tmp_path / CONFIG).write_text(config)
    (tmp_path / ROWS).write_text(rows)
    refused(ResultsFormatError, words, write_realistic_report, tmp_path)


@pytest.mark.parametrize("folder", [None, 3, np.zeros(2)])
def test_the_realistic_report_needs_a_path(folder: Any) -> None:
    from uavcov.paper import write_realistic_report

    refused(InvalidTypeError, "folder must be a path string", write_realistic_report, folder)


# ---------------------------------------------------------------------------------------------
# An experiment's lists given something else (TypeError: 'bool' object is not iterable, ...)


@pytest.mark.parametrize("value", [True, None, 3, "cvt", {"a": 1}])
@pytest.mark.parametrize("argument", ["seeds", "team_sizes", "starts"])
def test_experiment_lists_are_sequences(argument: str, value: Any) -> None:
    from uavcov.experiments import Experiment, experiment_specs
    from uavcov.paper import TABLE1, reproduce

    fields = {"name": "e", "terrain": TABLE1.terrain, "mission": TABLE1.mission, "team_sizes": (2,), "starts": ("cvt",)}
    if value is not None:  # None is the experiment's own list in experiment_specs and reproduce
        refused(InvalidTypeError, f"{argument} must be a sequence", experiment_specs, TABLE1, **{argument: value})
    if argument != "seeds" and value is not None:  # reproduce reads its seeds as text (parse_seeds)
        refused(InvalidTypeError, f"{argument} must be a sequence", reproduce, "table1", "out", **{argument: value})
    refused(InvalidTypeError, f"{argument} must be a sequence", Experiment, **{**fields, argument: value})


@pytest.mark.parametrize("starts", [[np.array(["cvt"])], [["cvt"]], [None]])
def test_a_start_that_is_not_a_word_is_refused(starts: Any) -> None:
    from uavcov.errors import ConfigError
    from uavcov.experiments import experiment_specs
    from uavcov.paper import TABLE1, reproduce

    refused(InvalidInputError, "are not starts of", experiment_specs, TABLE1, starts=starts)
    refused(ConfigError, "compares the starts", reproduce, "table1", "out", starts=starts)


@pytest.mark.parametrize("value", [None, 3, [1], {"table1": 3}])
def test_experiments_hash_needs_a_mapping_of_experiments(value: Any) -> None:
    from uavcov.experiments import experiments_hash

    refused(InvalidTypeError, "experiments must be a mapping", experiments_hash, value)


@pytest.mark.parametrize("name", [["table1"], np.array(["table1"]), None])
def test_reproduce_refuses_a_name_that_is_not_one(name: Any) -> None:
    from uavcov.errors import ConfigError
    from uavcov.paper import reproduce

    refused(ConfigError, "unknown experiment", reproduce, name, "out")


@pytest.mark.parametrize("cores", [0, -1, "abc", float("nan"), 2.5, np.zeros(2)])
def test_plan_execution_refuses_a_core_count_that_is_not_one(cores: Any) -> None:
    from uavcov.errors import ConfigError
    from uavcov.experiments import plan_execution

    refused(ConfigError, "cores must be an integer >= 1", plan_execution, 1, 1, cores)


# ---------------------------------------------------------------------------------------------
# A team hovering nowhere; a figure's flags, titles and far points


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"positions": np.zeros((0, 3))}, InvalidInputError, r"positions must have shape \(N, 3\) with N >= 1"),
        ({"positions": np.full((2, 3), 1e300)}, InvalidInputError, "positions must lie within 1e15 m"),
        ({"settings": None}, InvalidTypeError, "settings must be a FlightSettings"),
        ({"settings": {"dt": 0.05}}, InvalidTypeError, "settings must be a FlightSettings"),
    ],
)
def test_a_team_hovers_somewhere(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    pytest.importorskip("rotorpy")
    from uavcov.sim import FlightSettings, Team

    arguments = {"positions": POINTS, "settings": FlightSettings(dt=0.05, max_leg_s=2.0), **kwargs}
    refused(error, words, Team.hovering, arguments.pop("positions"), arguments.pop("settings"), HILLS, rng=0)


@pytest.mark.parametrize("waypoints", [np.full((2, 3), 1e300), np.full((2, 3), -1e16)])
def test_a_team_refuses_waypoints_beyond_the_engines_bound(waypoints: np.ndarray) -> None:
    pytest.importorskip("rotorpy")
    from uavcov.sim import FlightSettings, Team

    team = Team.hovering(POINTS, FlightSettings(dt=0.05, max_leg_s=2.0), HILLS, rng=0)
    refused(InvalidInputError, "waypoints must lie within", team.fly, waypoints)


@pytest.mark.parametrize(
    "draw, error, words",
    [
        (lambda m, out: uavcov.plotting.plot_coverage_curves([m], group_by=None, out=out), InvalidTypeError, "group_by must be a string"),
        (
            lambda m, out: uavcov.plotting.plot_coverage_curves([m], running_max=np.zeros(0), out=out),
            InvalidTypeError,
            "running_max must be",
        ),
        (lambda m, out: uavcov.plotting.plot_coverage_curves([m], show_runs=1, out=out), InvalidTypeError, "show_runs must be True"),
        (lambda m, out: uavcov.plotting.plot_coverage_curves([m], reference=True, out=out), InvalidTypeError, "reference must be None"),
        (lambda m, out: uavcov.plotting.plot_coverage_curves([m], title=3.0, out=out), InvalidTypeError, "title must be None or a string"),
        (lambda m, out: uavcov.plotting.plot_coverage_map(m, view=np.zeros(0), out=out), InvalidInputError, "view must be '3d' or 'top'"),
        (lambda m, out: uavcov.plotting.plot_coverage_map(m, view="top", shade=None, out=out), InvalidTypeError, "shade must be True"),
        (lambda m, out: uavcov.plotting.plot_point_cloud(m, ply=True, out=out), InvalidTypeError, "ply must be a path string"),
        (lambda m, out: uavcov.plotting.plot_point_cloud(m, positions=np.full((2, 3), 1e300), out=out), InvalidInputError, "within 1e15 m"),
    ],
)
def test_a_figure_checks_its_flags_titles_and_points(mission: Any, tmp_path: Path, draw: Any, error: type[Exception], words: str) -> None:
    pytest.importorskip("matplotlib")
    refused(error, words, draw, mission, tmp_path / "f.png")


# ---------------------------------------------------------------------------------------------
# Indices and counts of small methods: a route's UAV, a CVT's generators, a camera's resolution


@pytest.mark.parametrize(
    "uav, error", [(-1, InvalidInputError), (99, InvalidInputError), (None, InvalidTypeError), (1.0, InvalidTypeError)]
)
def test_a_structure_flight_route_needs_the_index_of_one_of_its_uavs(uav: Any, error: type[Exception]) -> None:
    from uavcov.field import GeoAnchor, plan_structure

    settings = uavcov.MissionSettings(
        n_uavs=2,
        d_max=10.0,
        n_prior=50,
        iterations=1,
        cao=uavcov.CAOSettings(n_candidates=10),
        constraints=uavcov.Constraints(h_min=1.0, z_max=20.0, clearance="standoff"),
    )
    flight = plan_structure(_bridge(), settings, GeoAnchor(5.0, 45.0), rng=0, n_threads=1).flight
    refused(error, "uav must be", flight.route_wgs84, uav)
    assert flight.route_wgs84(1).shape[1] == 3


@pytest.mark.parametrize(
    "n, error", [(None, InvalidTypeError), (float("inf"), InvalidTypeError), (0, InvalidInputError), (10**9, InvalidInputError)]
)
def test_cvt_samples_for_needs_a_generator_count(n: Any, error: type[Exception]) -> None:
    refused(error, "n must be", uavcov.CVTSettings().samples_for, n)


@pytest.mark.parametrize("resolution", [None, 2.5, "128", np.zeros(2)])
def test_an_omnidirectional_camera_needs_a_whole_resolution(resolution: Any) -> None:
    from uavcov.sim import DepthCamera

    refused(InvalidTypeError, "resolution must be a whole number", DepthCamera.omnidirectional, 10.0, resolution)


@pytest.mark.parametrize("path", [None, 3, np.zeros(2)])
def test_read_runs_needs_a_path(path: Any) -> None:
    from uavcov.experiments import read_runs

    refused(InvalidTypeError, "path must be a path string", read_runs, path)
