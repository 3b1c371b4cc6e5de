"""Hostile input, round five: what ``scripts/fuzz_public_api.py`` accepted for review after round four.

Records and options that checked nothing they were given (a report of NaN faces, a frame with a
latitude of "yes", a published sigma of -1), options checked only on the path that uses them (a
NaN ``alpha`` ignored by the default method, a NaN elevation of a top view), coordinates beyond
the engine's 1e15 m bound mapped to numbers that had lost their metres, and corrupt files read
by the library (a run whose trace arrays disagree, a realistic run's rows without their fields).
Each class is tried with several hostile values, each asserting the precise error of
:mod:`uavcov.errors` and a message naming the argument.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import uavcov
from refusals import refused
from uavcov.errors import InvalidInputError, InvalidTypeError, ResultsFormatError

HILLS = uavcov.gaussian_hills(size=30, spacing=1, n_hills=2, rng=0)
NAN = float("nan")

# ---------------------------------------------------------------------------------------------
# Records that checked nothing


@pytest.mark.parametrize(
    "value, error, words",
    [
        (NAN, InvalidTypeError, "must be an integer"),
        (1.5, InvalidTypeError, "must be an integer"),
        ("3", InvalidTypeError, "must be an integer"),
        (True, InvalidTypeError, "must be an integer"),
        (-1, InvalidInputError, "must be >= 0"),
    ],
)
@pytest.mark.parametrize("field", ["merged_vertices", "degenerate_faces", "nonmanifold_edges"])
def test_a_mesh_report_holds_counts(field: str, value: Any, error: type[Exception], words: str) -> None:
    refused(error, f"{field} {words}", uavcov.terrain.MeshReport, **{field: value})


def test_a_mesh_report_keeps_its_counts() -> None:
    report = uavcov.terrain.MeshReport(merged_vertices=np.int64(3), duplicate_faces=2)
    assert report.merged_vertices == 3 and type(report.merged_vertices) is int and report.repaired
    from uavcov.terrain._meshes import clean_mesh

    # a welded corner (vertex 3 is vertex 0) and the same triangle twice: one merge, one duplicate
    _, _, cleaned = clean_mesh(np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0]]), np.array([[0, 1, 2], [3, 1, 2]]))
    assert cleaned.merged_vertices == 1 and cleaned.duplicate_faces == 1


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"geographic": "yes", "reference_latitude": 45.0}, InvalidTypeError, "geographic must be True or False"),
        ({"geographic": NAN}, InvalidTypeError, "geographic must be True or False"),
        ({"geographic": True, "reference_latitude": NAN}, InvalidInputError, "reference_latitude must be finite"),
        ({"geographic": True, "reference_latitude": 91.0}, InvalidInputError, r"reference_latitude must be in \[-90, 90\]"),
        ({"geographic": True, "reference_latitude": "45"}, InvalidTypeError, "reference_latitude must be a real number"),
        ({"geographic": True}, InvalidInputError, "a geographic frame needs its reference_latitude"),
        ({"reference_latitude": 45.0}, InvalidInputError, "only a geographic one has one"),
        ({"origin": np.full(3, 1e300)}, InvalidInputError, "origin must lie within 1e15 m"),
        ({"origin": [0.0, 0.0, -2e15]}, InvalidInputError, "origin must lie within 1e15 m"),
    ],
)
def test_a_local_frame_checks_what_it_is_given(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    arguments = {"origin": np.zeros(3), "factors": np.ones(3), **kwargs}
    refused(error, words, uavcov.terrain.LocalFrame, **arguments)


@pytest.mark.parametrize(
    "factors, points, method, words",
    [
        (np.ones(3), np.full((2, 3), 1e300), "to_local", "points in the local frame must lie within 1e15 m"),
        (np.full(3, 1e5), np.full((1, 3), 1e12), "to_local", "points in the local frame must lie within 1e15 m"),
        (np.full(3, 1e300), np.ones((1, 3)), "to_local", "points in the local frame must lie within 1e15 m"),
        (np.ones(3), np.full((2, 3), -1e300), "to_source", "points must lie within 1e15 m"),
        (np.ones(3), np.full((1, 3), 2e15), "to_source", "points must lie within 1e15 m"),
    ],
)
def test_a_local_frame_refuses_points_beyond_the_engines_bound(factors: Any, points: Any, method: str, words: str) -> None:
    frame = uavcov.terrain.LocalFrame(np.zeros(3), factors)
    refused(InvalidInputError, words, getattr(frame, method), points)


def test_a_local_frame_keeps_its_answers() -> None:
    frame = uavcov.terrain.LocalFrame(
        np.array([1.0, 2.0, 3.0]), np.array([2.0, 2.0, 1.0]), geographic=np.bool_(True), reference_latitude=45
    )
    assert frame.geographic is True and frame.reference_latitude == 45.0
    points = np.array([[2.0, 4.0, 6.0], [1e14, 0.0, 0.0]])
    np.testing.assert_array_equal(frame.to_source(frame.to_local(points)), points)
    assert frame.to_local([[1e15 / 2 + 1.0, 2.0, 3.0]])[0, 0] == 1e15  # the bound itself is inside
    identity = uavcov.terrain.LocalFrame.identity()
    assert identity.geographic is False and identity.reference_latitude is None


@pytest.fixture(scope="module")
def sample_dem() -> Any:
    return uavcov.sample_dem(window=(0, 10, 0, 10))


@pytest.mark.parametrize("value", [1e300, -1e300, 1e16])
def test_a_dem_maps_no_point_beyond_the_engines_bound(sample_dem: Any, value: float) -> None:
    points = np.full((3, 3), value)
    refused(InvalidInputError, "points must lie within 1e15 m", sample_dem.to_crs, points)  # 1e295 degrees before
    refused(InvalidInputError, "points in the local frame must lie within 1e15 m", sample_dem.from_crs, points)


@pytest.mark.parametrize("value", [1e300, -1e300, 1e16])
def test_a_dem_of_heights_beyond_the_engines_bound_is_refused(value: float) -> None:
    z = np.full((3, 4), value)  # a flat DEM there came back with heights whose metres were lost
    transform = (30.0, 0.0, 500000.0, 0.0, -30.0, 4000000.0)
    refused(InvalidInputError, "z must lie within 1e15 m", uavcov.terrain.dem_from_array, z, transform, "EPSG:32617")


def test_a_dem_with_nodata_heights_is_still_read() -> None:
    z = np.arange(20.0).reshape(4, 5)
    z[0, 0] = np.nan
    dem = uavcov.terrain.dem_from_array(z, (30.0, 0.0, 500000.0, 0.0, -30.0, 4000000.0), "EPSG:32617")
    assert dem.nodata_cells == 1


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"mean": NAN}, InvalidInputError, "mean must be finite"),
        ({"mean": float("inf")}, InvalidInputError, "mean must be finite"),
        ({"mean": "0.5"}, InvalidTypeError, "mean must be a real number"),
        ({"mean": True}, InvalidTypeError, "mean must be a real number"),
        ({"sigma": -0.1}, InvalidInputError, "sigma must be >= 0"),
        ({"sigma": NAN}, InvalidInputError, "sigma must be finite"),
        ({"sigma": np.ones(3)}, InvalidTypeError, "sigma must be a real number"),
    ],
)
def test_a_published_value_is_a_mean_and_a_spread(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    from uavcov.paper import PublishedValue

    refused(error, words, PublishedValue, **{"mean": 0.5, "sigma": 0.1, **kwargs})


def test_the_published_values_are_unchanged() -> None:
    from uavcov.paper import PUBLISHED_TABLE1, PublishedValue

    assert PUBLISHED_TABLE1[(5, "cvt", "initial")] == PublishedValue(0.59, 0.06)
    assert PublishedValue(np.float64(0.5), 0) == PublishedValue(0.5, 0.0)


@pytest.mark.parametrize(
    "name, error, words",
    [
        (NAN, InvalidTypeError, "name must be a string"),
        (None, InvalidTypeError, "name must be a string"),
        (3, InvalidTypeError, "name must be a string"),
        ("", InvalidInputError, "name must be a non-empty string"),
        ("  ", InvalidInputError, "name must be a non-empty string"),
    ],
)
def test_an_experiment_has_a_name(name: Any, error: type[Exception], words: str) -> None:
    from uavcov.experiments import Experiment
    from uavcov.paper import TABLE1

    refused(error, words, Experiment, name, TABLE1.terrain, TABLE1.mission, (2,), ("cvt",))


@pytest.mark.parametrize(
    "seed, error, words",
    [
        (NAN, InvalidTypeError, "seed must be an integer"),
        ("0", InvalidTypeError, "seed must be an integer"),
        (True, InvalidTypeError, "seed"),
        (-1, InvalidInputError, "seed must be >= 0"),
    ],
)
def test_an_experiments_known_surface_needs_a_seed(seed: Any, error: type[Exception], words: str) -> None:
    from uavcov.paper import BUILDINGS, TABLE1

    refused(error, words, TABLE1.known, seed)  # hills: no map, but a seed all the same
    refused(error, words, BUILDINGS.known, seed)
    assert TABLE1.known(np.int64(3)) is None


@pytest.mark.parametrize(
    "source, error", [(NAN, InvalidTypeError), (None, InvalidTypeError), (["a"], InvalidTypeError), ("", InvalidInputError)]
)
def test_a_sweep_configs_source_is_a_name(source: Any, error: type[Exception]) -> None:
    from uavcov.experiments import parse_sweep_config
    from uavcov.paper import EXPERIMENTS

    data = {"base": "table1", "seeds": [0], "team_sizes": [2], "starts": ["cvt"]}
    refused(error, "source must be a", parse_sweep_config, data, bases=dict(EXPERIMENTS), source=source)


# ---------------------------------------------------------------------------------------------
# Options checked only on the path that used them


@pytest.fixture(scope="module")
def structure_prior() -> Any:
    return uavcov.structures.sample_structure_prior(uavcov.structures.girder_bridge(rng=0), 100, rng=0)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"alpha": NAN}, InvalidInputError, "alpha must be finite"),
        ({"alpha": -1.0}, InvalidInputError, "alpha must be > 0"),
        ({"alpha": "big"}, InvalidTypeError, "alpha must be a real number"),
        ({"clusters": 0}, InvalidInputError, "clusters must be >= 1"),
        ({"clusters": 2.5}, InvalidTypeError, "clusters must be an integer"),
        ({"poisson_depth": 99}, InvalidInputError, "poisson_depth must be at most 12"),
        ({"poisson_depth": NAN}, InvalidTypeError, "poisson_depth must be an integer"),
        ({"rng": "seed"}, InvalidTypeError, "rng must be None, an int"),
        ({"rng": NAN}, InvalidTypeError, "rng must be None, an int"),
    ],
)
@pytest.mark.parametrize("method", ["auto", "oriented", "model"])
def test_reconstruct_structure_checks_every_option_whatever_the_method(
    structure_prior: Any, method: str, kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    # the default method ("oriented" for points with normals) uses none of them, nor does "model"
    prior = uavcov.structures.coarse_structure_prior(uavcov.structures.girder_bridge(rng=0)) if method == "model" else structure_prior
    refused(error, words, uavcov.structures.reconstruct_structure, prior, method=method, **kwargs)


def test_reconstruct_structure_keeps_its_surface(structure_prior: Any) -> None:
    plain = uavcov.structures.reconstruct_structure(structure_prior, rng=0)
    with_options = uavcov.structures.reconstruct_structure(
        structure_prior, alpha=2.0, clusters=3, poisson_depth=5, rng=np.random.default_rng(1)
    )
    np.testing.assert_array_equal(plain.vertices, with_options.vertices)
    np.testing.assert_array_equal(plain.faces, with_options.faces)


@pytest.mark.parametrize(
    "kind, cell, error, words",
    [
        ("boxes", NAN, InvalidInputError, "cell must be finite"),
        ("boxes", -1.0, InvalidInputError, "cell must be > 0"),
        ("boxes", "1", InvalidTypeError, "cell must be a real number"),
        ("decimated", 1e-300, InvalidInputError, "cell 1e-300 m is too fine"),  # int64 keys overflowed: 8 vertices
        ("decimated", 1e-14, InvalidInputError, "is too fine"),
    ],
)
def test_coarse_structure_prior_checks_its_cell(kind: str, cell: Any, error: type[Exception], words: str) -> None:
    bridge = uavcov.structures.girder_bridge(rng=0)
    refused(error, words, uavcov.structures.coarse_structure_prior, bridge, kind, cell=cell)


@pytest.mark.parametrize(
    "n, rng, error, words",
    [
        (NAN, None, InvalidTypeError, "n must be an integer"),
        (0, None, InvalidInputError, "n must be >= 1"),
        (True, None, InvalidTypeError, "n must be an integer"),
        (10**12, None, InvalidInputError, "n must be at most"),
        (2, "x", InvalidTypeError, "rng must be None"),
        (2, NAN, InvalidTypeError, "rng must be None"),
    ],
)
@pytest.mark.parametrize("kind", ["cvt", "random", "corner"])
def test_height_above_reference_checks_its_arguments_for_every_kind(
    kind: str, n: Any, rng: Any, error: type[Exception], words: str
) -> None:
    spec = uavcov.StartSettings(kind=kind, random_altitude=(5.0, 10.0) if kind == "random" else None)
    refused(error, words, spec.height_above_reference, n, rng)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"d_max": NAN}, InvalidInputError, "d_max must be finite"),
        ({"d_max": -1.0}, InvalidInputError, "d_max must be > 0"),
        ({"d_max": "10"}, InvalidTypeError, "d_max must be a real number"),
        ({"constraints": "standoff"}, InvalidTypeError, "constraints must be a Constraints"),
        ({"constraints": NAN}, InvalidTypeError, "constraints must be a Constraints"),
    ],
)
def test_start_configuration_checks_the_options_of_other_kinds(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    from uavcov.placement import start_configuration

    refused(error, words, start_configuration, uavcov.StartSettings(kind="corner"), HILLS, HILLS, 2, rng=0, n_threads=1, **kwargs)


@pytest.mark.parametrize(
    "bounds, error, words",
    [
        ((NAN, 0.0, 30.0, 30.0), InvalidInputError, "bounds contains NaN"),
        ((30.0, 0.0, 0.0, 30.0), InvalidInputError, "bounds need xmin < xmax"),
        ((0.0, 0.0, 30.0), InvalidInputError, r"bounds must be \(xmin, ymin, xmax, ymax\)"),
        ("abc", InvalidTypeError, "bounds must be"),
    ],
)
def test_fit_footprints_checks_its_bounds_with_a_nadir_camera_too(bounds: Any, error: type[Exception], words: str) -> None:
    from uavcov.placement import fit_footprints

    sensor = uavcov.Sensor(10.0, camera=uavcov.Camera.from_fov(60, 45))
    generators = np.array([[10.0, 10.0, 5.0], [20.0, 20.0, 5.0]])
    attitudes = np.array([[0.0, -90.0]] * 2)  # nadir: no UAV stands back, so the bounds were never read
    refused(
        error, words, fit_footprints, HILLS, generators, sensor, attitudes, heights=(5.0, 10.0), bounds=bounds, n_heights=2, n_threads=1
    )


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"elev": NAN}, InvalidInputError, "elev must be finite"),
        ({"azim": "north"}, InvalidTypeError, "azim must be a real number"),
        ({"max_polygons": 0}, InvalidInputError, "max_polygons must be >= 1"),
        ({"max_polygons": NAN}, InvalidTypeError, "max_polygons must be an integer"),
        ({"raster": 0, "view": "3d"}, InvalidInputError, "raster must be >= 1"),
    ],
)
def test_a_coverage_map_checks_the_options_of_either_view(
    tmp_path: Path, kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    from uavcov.plotting import plot_coverage_map

    arguments = {
        "positions": np.array([[10.0, 10.0, 30.0]]),
        "d_max": 10.0,
        "view": "top",
        "raster": 20,
        "out": tmp_path / "m.png",
        **kwargs,
    }
    refused(error, words, plot_coverage_map, HILLS, **arguments)
    assert not (tmp_path / "m.png").exists()


@pytest.mark.parametrize("value", [1e300, -1e16])
def test_a_figure_refuses_known_points_it_would_draw_outside_its_axes(tmp_path: Path, value: float) -> None:
    from uavcov.plotting import plot_approximation

    known = np.array([[5.0, 5.0, 1.0], [value, 0.0, 0.0]])
    refused(InvalidInputError, "prior_points must lie within 1e15 m", plot_approximation, HILLS, approximation=HILLS, prior_points=known)


# ---------------------------------------------------------------------------------------------
# The simulator's flags, generators and worlds


@pytest.mark.parametrize(
    "render, error", [(NAN, InvalidTypeError), ("yes", InvalidTypeError), (1, InvalidTypeError), (None, InvalidTypeError)]
)
def test_sim_settings_render_is_a_flag(render: Any, error: type[Exception]) -> None:
    from uavcov.sim import SimSettings

    refused(error, "render must be True or False", SimSettings, render=render)
    assert SimSettings(render=np.bool_(False)).render is False


@pytest.mark.parametrize("planned", [None, NAN, "limits", {"h_min": 1.0}])
@pytest.mark.parametrize("margin", [0.0, 0.5])
def test_flight_limits_need_the_planned_constraints(planned: Any, margin: float) -> None:
    from uavcov.sim import SimSettings

    refused(InvalidTypeError, "planned must be a Constraints", SimSettings(limits_margin=margin).flight_limits, planned)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"terrain": NAN}, InvalidTypeError, "terrain must be a uavcov.Terrain or None"),
        ({"terrain": "hills"}, InvalidTypeError, "terrain must be a uavcov.Terrain or None"),
        ({"rng": NAN}, InvalidTypeError, "rng must be None, an int"),
        ({"rng": "seed"}, InvalidTypeError, "rng must be None, an int"),
    ],
)
def test_a_hovering_team_checks_its_world_and_generator_without_gusts(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    pytest.importorskip("rotorpy")
    from uavcov.sim import FlightSettings, Team

    positions = np.array([[5.0, 5.0, 30.0], [15.0, 12.0, 25.0]])
    refused(error, words, Team.hovering, positions, FlightSettings(dt=0.05, max_leg_s=2.0), **kwargs)


@pytest.mark.parametrize("rng", [NAN, "seed", [1.5]])
def test_a_depth_camera_checks_its_generator_without_noise(rng: Any) -> None:
    from uavcov.sim import DepthCamera

    camera = DepthCamera(8, 6, (60.0, 45.0), 10.0)
    refused(InvalidTypeError, "rng must be None, an int", camera.render, HILLS, np.array([10.0, 10.0, 30.0]), np.eye(3), rng=rng)


@pytest.mark.parametrize("path", [NAN, None, 3, ["run.npz"]])
def test_is_flown_file_needs_a_path(path: Any) -> None:
    from uavcov.sim import is_flown_file

    refused(InvalidTypeError, "path must be a path string", is_flown_file, path)


def test_is_flown_file_says_no_for_files_of_other_kinds(tmp_path: Path) -> None:
    from uavcov.sim import is_flown_file

    for name, data in (("empty.npz", b""), ("text.npz", b"hello"), ("zip.npz", b"PK\x03\x04cut")):
        (tmp_path / name).write_bytes(data)
        assert is_flown_file(tmp_path / name) is False
    assert is_flown_file(tmp_path / "missing.npz") is False


# ---------------------------------------------------------------------------------------------
# Points: known, targets and meshes within the engine's bound


@pytest.mark.parametrize(
    "points, words",
    [
        (np.full((3, 3), NAN), "points contains NaN"),
        ([[0.0, 0.0, 0.0], [1.0, 0.0, float("inf")]], "points contains NaN or infinite"),
        (np.full((3, 3), 1e300), "points must lie within 1e15 m"),
        ([[0.0, 0.0, 0.0], [-1e16, 0.0, 0.0]], "points must lie within 1e15 m"),
    ],
)
def test_a_prior_holds_points_s_prime_can_be_made_of(points: Any, words: str) -> None:
    refused(InvalidInputError, words, uavcov.terrain.Prior, points)


@pytest.mark.parametrize("kind", ["random", "pyramid"])
@pytest.mark.parametrize("points", [np.array([[5.0, 5.0]]), NAN, np.full((3, 3), NAN)])
def test_sample_prior_refuses_points_it_would_replace_by_others(kind: str, points: Any) -> None:
    refused(
        InvalidInputError,
        "points are the prior of kind='points' only",
        uavcov.terrain.sample_prior,
        HILLS,
        5,
        kind=kind,
        points=points,
        rng=0,
    )


@pytest.mark.parametrize("value", [1e300, -1e300, 1e16])
def test_targets_lie_within_the_engines_bound(value: float) -> None:
    points = np.array([[0.0, 0.0, 0.0], [value, 1.0, 1.0]])
    refused(InvalidInputError, "targets must lie within 1e15 m", uavcov.Targets, points)
    refused(InvalidInputError, "targets must lie within 1e15 m", uavcov.Targets.from_points, points)
    assert len(uavcov.Targets([[1e15, -1e15, 0.0]])) == 1


@pytest.mark.parametrize("value", [1e300, 1e16])
def test_degenerate_faces_refuses_vertices_whose_areas_overflow(value: float) -> None:
    from uavcov.engine import degenerate_faces

    # a real triangle read as degenerate before: its area overflowed to inf, compared with inf
    vertices = np.array([[0.0, 0.0, 0.0], [value, 0.0, 0.0], [0.0, value, 0.0]])
    refused(InvalidInputError, "vertices must lie within 1e15 m", degenerate_faces, vertices, np.array([[0, 1, 2]]))


@pytest.mark.parametrize("purpose, error", [(NAN, InvalidTypeError), (None, InvalidTypeError), ("", InvalidInputError)])
def test_as_mesh_surface_needs_a_purpose_to_name(purpose: Any, error: type[Exception]) -> None:
    from uavcov.engine import as_mesh_surface

    refused(error, "purpose must be a", as_mesh_surface, HILLS, purpose)


# ---------------------------------------------------------------------------------------------
# Corrupt files: a run file whose arrays disagree, a realistic run's rows and config


@pytest.fixture(scope="module")
def run_arrays(tmp_path_factory: Any) -> dict[str, np.ndarray]:
    settings = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=2, cao=uavcov.CAOSettings(n_candidates=10))
    result = uavcov.run_mission(HILLS, settings, rng=0, n_threads=1)
    path = uavcov.save_mission(result, tmp_path_factory.mktemp("run") / "run.npz")
    with np.load(path, allow_pickle=False) as data:
        return {name: data[name] for name in data.files}


@pytest.mark.parametrize(
    "name, value",
    [
        ("trace_measured", np.array("x")),
        ("trace_measured", np.zeros(0)),
        ("trace_values", np.zeros((3, 2))),
        ("trace_step_sizes", np.zeros(7)),
        ("trace_n_checked", np.array(["a", "b"])),
        ("trace_n_feasible", np.zeros((2, 2))),
        ("cvt_moves", np.zeros(0)),
        ("cvt_energy", np.zeros((2, 2))),
        ("cvt_generators", np.zeros((2, 2))),
        ("cvt_normals", np.zeros((3, 3))),
    ],
)
def test_a_run_file_whose_arrays_disagree_is_refused(tmp_path: Path, run_arrays: dict[str, np.ndarray], name: str, value: Any) -> None:
    np.savez(tmp_path / "run.npz", **{**run_arrays, name: value})
    refused(ResultsFormatError, f"{name} has shape", uavcov.load_mission, tmp_path / "run.npz")


@pytest.mark.parametrize("seed", [-1, -(2**40)])
def test_a_run_file_with_a_negative_seed_is_refused(tmp_path: Path, run_arrays: dict[str, np.ndarray], seed: int) -> None:
    header = {**json.loads(str(run_arrays["header"])), "seed": seed}
    np.savez(tmp_path / "run.npz", **{**run_arrays, "header": np.array(json.dumps(header))})
    refused(ResultsFormatError, "seed = .* is not an integer >= 0", uavcov.load_mission, tmp_path / "run.npz")


def test_a_run_file_still_loads_whole(tmp_path: Path, run_arrays: dict[str, np.ndarray]) -> None:
    np.savez(tmp_path / "run.npz", **run_arrays)
    result = uavcov.load_mission(tmp_path / "run.npz")
    assert result.trace.measured.shape == result.coverage.shape and result.cvt is not None
    old = uavcov.load_mission(Path(__file__).parent / "data" / "mission_before_issue41.npz")
    assert old.trace.step_sizes.shape[0] == old.coverage.shape[0] - 1


def test_the_command_line_views_a_run_file_whose_arrays_disagree_in_one_line(tmp_path: Path, run_arrays: dict[str, np.ndarray]) -> None:
    np.savez(tmp_path / "run.npz", **{**run_arrays, "trace_step_sizes": np.zeros(9)})
    done = subprocess.run([sys.executable, "-m", "uavcov", "view", str(tmp_path / "run.npz")], capture_output=True, text=True, check=False)
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1 and "trace_step_sizes has shape" in done.stderr


_REALISTIC_CONFIG = '{"seeds": [0], "starts": ["cvt"], "measurements": ["exact"]}'


@pytest.mark.parametrize(
    "config, rows, words",
    [
        (_REALISTIC_CONFIG, "", "its report cannot read: KeyError: 'iterations'"),  # a KeyError before
        (_REALISTIC_CONFIG, "\x00\xff garbage\n", "its report cannot read"),
        (_REALISTIC_CONFIG, '{"seed": 0, "start": "cvt", "measurement": "exact"}\n', "its report cannot read: KeyError"),
        (_REALISTIC_CONFIG, '{"seed": NaN, "start": 3, "measurement": null}\n', "its report cannot read"),
        (_REALISTIC_CONFIG, "3\n", "holds a row that is not a JSON object with seed, start, measurement"),
        (_REALISTIC_CONFIG, '"row"\n', "holds a row that is not a JSON object"),
    ],
)
def test_the_realistic_report_refuses_rows_and_configs_it_cannot_read(tmp_path: Path, config: str, rows: str, words: str) -> None:
    from uavcov.paper import write_realistic_report
    from uavcov.paper._realistic import CONFIG, ROWS

    (tmp_path / CONFIG).write_text(config)
    (tmp_path / ROWS).write_text(rows, encoding="latin-1")
    refused(ResultsFormatError, words, write_realistic_report, tmp_path)
    assert not (tmp_path / "runs.csv").exists()  # nothing half-written


@pytest.mark.parametrize("config", ["", "{not json", "\xff\xfe"])
def test_resuming_a_realistic_run_of_an_unreadable_config_is_refused(tmp_path: Path, config: str) -> None:
    pytest.importorskip("rotorpy")
    from uavcov.paper import reproduce_realistic
    from uavcov.paper._realistic import CONFIG

    (tmp_path / CONFIG).write_bytes(config.encode("latin-1"))
    refused(
        ResultsFormatError,
        "cannot be resumed: its config.json is missing or unreadable",
        reproduce_realistic,
        tmp_path,
        seeds="0",
        resume=True,
    )
    (tmp_path / CONFIG).unlink()
    (tmp_path / "rows.jsonl").write_text("")
    refused(ResultsFormatError, "cannot be resumed", reproduce_realistic, tmp_path, seeds="0", resume=True)


def test_the_command_line_resumes_no_realistic_run_of_a_corrupt_config_in_one_line(tmp_path: Path) -> None:
    pytest.importorskip("rotorpy")
    (tmp_path / "config.json").write_text("{not json")
    argv = [
        sys.executable,
        "-m",
        "uavcov",
        "reproduce",
        "realistic",
        "--resume",
        "--seeds",
        "0",
        "--iterations",
        "1",
        "--out",
        str(tmp_path),
    ]
    done = subprocess.run(argv, capture_output=True, text=True, check=False)
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1 and "cannot be resumed" in done.stderr


@pytest.mark.parametrize("line", ["[1, 2]", "3", "null", '"text"'])
def test_rows_of_a_long_experiment_are_objects_and_torn_lines_are_dropped(tmp_path: Path, line: str) -> None:
    from uavcov.paper._jsonl import read_rows

    path = tmp_path / "rows.jsonl"
    path.write_text('{"seed": 0}\n{"seed": 1, "cut')  # a torn last line: that run runs again
    assert read_rows(path, ("seed",)) == [{"seed": 0}]
    path.write_text(f'{{"seed": 0}}\n{line}\n')
    refused(ResultsFormatError, "line 2", read_rows, path)
    path.write_text('{"start": "cvt"}\n')
    refused(ResultsFormatError, "not a JSON object with seed", read_rows, path, ("seed",))


# ---------------------------------------------------------------------------------------------
# Booleans where numbers are meant (numpy reads True as 1), found with --every-accepted


@pytest.mark.parametrize("rng", [True, False, np.bool_(True)])
@pytest.mark.parametrize(
    "call",
    [
        lambda rng: uavcov.gaussian_hills(size=30.0, n_hills=2, rng=rng),
        lambda rng: uavcov.terrain.sample_prior(HILLS, 5, rng=rng),
        lambda rng: uavcov.placement.cvt(HILLS, 3, rng=rng, n_threads=1),
    ],
)
def test_a_flag_is_no_seed(call: Any, rng: Any) -> None:
    refused(InvalidTypeError, "rng must be None, an int", call, rng)


@pytest.mark.parametrize(
    "seed, error, words",
    [
        (None, InvalidTypeError, "seed must be an integer"),  # a new terrain at each call before
        (True, InvalidTypeError, "seed must be an integer"),
        (1.5, InvalidTypeError, "seed must be an integer"),
        (np.random.default_rng(0), InvalidTypeError, "seed must be an integer"),
        (-1, InvalidInputError, "seed must be >= 0"),
    ],
)
def test_a_hills_scenario_is_made_from_a_seed(seed: Any, error: type[Exception], words: str) -> None:
    hills = uavcov.terrain.HillsGenerator(size=30.0, n_hills=2)
    refused(error, words, hills.make, seed)
    np.testing.assert_array_equal(hills.make(np.int64(4)).vertices, hills.make(4).vertices)


@pytest.mark.parametrize(
    "corners, error, words",
    [
        ((-84.4, True, -84.38, 36.47), InvalidTypeError, "ymin must be a real number"),  # 1 degree before
        ((False, 36.45, -84.38, 36.47), InvalidTypeError, "xmin must be a real number"),
        ((-84.4, 36.45, "-84.38", 36.47), InvalidTypeError, "xmax must be a real number"),
        ((-84.4, 36.45, -84.38, NAN), InvalidInputError, "ymax must be finite"),
        ((-84.4, 36.45, [-84.38], 36.47), InvalidTypeError, "xmax must be a real number"),
    ],
)
def test_a_bbox_area_is_four_numbers(corners: tuple[Any, ...], error: type[Exception], words: str) -> None:
    refused(error, words, uavcov.field.bbox_area, *corners)


@pytest.mark.parametrize("shape", [True, (2, True), {}, {"a": 3}, "ab", (2, np.bool_(False))])
def test_standard_normal_takes_no_flag_or_mapping_for_a_shape(shape: Any) -> None:
    from uavcov.optim import standard_normal

    generator = np.random.default_rng(0)
    before = generator.bit_generator.state
    refused(InvalidTypeError, "shape must be an int or a tuple of ints", standard_normal, generator, shape)
    assert generator.bit_generator.state == before  # nothing drawn


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"noise": NAN}, InvalidInputError, "noise must be finite"),
        ({"noise": -0.1}, InvalidInputError, "noise must be >= 0"),
        ({"noise": "0.1"}, InvalidTypeError, "noise must be a real number"),
        ({"points": np.full((4, 3), 1e300)}, InvalidInputError, "points must lie within 1e15 m"),
        ({"points": [[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, -1e16]]}, InvalidInputError, "points must lie within 1e15 m"),
    ],
)
def test_a_structure_prior_checks_its_noise_and_points(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    from uavcov.structures import StructurePrior

    arguments = {"points": np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]), "normals": None, "kind": "points", **kwargs}
    refused(error, words, StructurePrior, **arguments)


# ---------------------------------------------------------------------------------------------
# A flown run's file: arrays and header checked as a mission's are


@pytest.fixture(scope="module")
def flown_arrays(tmp_path_factory: Any) -> dict[str, np.ndarray]:
    pytest.importorskip("rotorpy")
    from uavcov.sim import FlightSettings, SimSettings, fly_mission, save_flown

    settings = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=1, cao=uavcov.CAOSettings(n_candidates=10))
    flown = fly_mission(HILLS, settings, SimSettings(flight=FlightSettings(dt=0.05, max_leg_s=2.0), render=False), rng=0)
    path = save_flown(flown, tmp_path_factory.mktemp("flown") / "flown.npz", HILLS)
    with np.load(path, allow_pickle=False) as data:
        return {name: data[name] for name in data.files}


@pytest.mark.parametrize(
    "name, value, words",
    [
        ("start", np.array("x"), "start has shape"),  # a ValueError before
        ("start", np.zeros((2, 2)), "start has shape"),
        ("commanded", np.zeros(0), "commanded has shape"),
        ("commanded", np.zeros((5, 2, 3)), "commanded has shape"),
        ("sensed", np.array(["a", "b"]), "sensed has shape"),
        ("leg_ends_s", np.array("x"), "leg_ends_s has shape"),  # an IndexError before
        ("exact", np.full(2, np.nan), "exact holds NaN or infinite values"),
        ("reached", np.full((2, 2, 3), np.inf), "reached holds NaN or infinite values"),
        ("clock", np.array([0.0, np.nan]), "clock holds NaN"),
    ],
)
def test_a_flown_file_whose_arrays_disagree_is_refused(
    tmp_path: Path, flown_arrays: dict[str, np.ndarray], name: str, value: Any, words: str
) -> None:
    from uavcov.sim import load_flown

    np.savez(tmp_path / "flown.npz", **{**flown_arrays, name: value})
    refused(ResultsFormatError, words, load_flown, tmp_path / "flown.npz")


@pytest.mark.parametrize(
    "field, value, words",
    [
        ("seed", "x", "seed = 'x' is not an integer >= 0"),
        ("seed", -1, "seed = -1 is not an integer >= 0"),
        ("seed", True, "seed = True is not an integer"),
        ("measurement", "x", "measurement = 'x' is not one of"),
        ("measurement", None, "measurement = None is not one of"),
        ("failure", 3, "failure = 3 is not a message"),
        ("failure", ["crash"], "failure = \\['crash'\\] is not a message"),
    ],
)
def test_a_flown_file_whose_header_says_nonsense_is_refused(
    tmp_path: Path, flown_arrays: dict[str, np.ndarray], field: str, value: Any, words: str
) -> None:
    from uavcov.sim import load_flown

    header = {**json.loads(str(flown_arrays["header"])), field: value}
    np.savez(tmp_path / "flown.npz", **{**flown_arrays, "header": np.array(json.dumps(header))})
    refused(ResultsFormatError, words, load_flown, tmp_path / "flown.npz")


def test_a_flown_file_still_loads_whole(tmp_path: Path, flown_arrays: dict[str, np.ndarray]) -> None:
    from uavcov.sim import load_flown

    np.savez(tmp_path / "flown.npz", **flown_arrays)
    run = load_flown(tmp_path / "flown.npz")
    assert run.trajectory.shape[0] == run.coverage.shape[0] and np.isnan(run.sensed).all()  # render=False: nothing sensed


# ---------------------------------------------------------------------------------------------
# The engine's fused limit check refuses what Constraints refuses


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"h_min": -1.0}, InvalidInputError, "h_min must be >= 0"),  # admitted positions 1 m under the surface
        ({"d_safe": -1.0}, InvalidInputError, "d_safe must be >= 0"),
        ({"h_min": 10.0, "h_max": 5.0}, InvalidInputError, "h_max = 5.0 m is below h_min = 10.0 m"),
        ({"bounds": (30.0, 0.0, 0.0, 30.0)}, InvalidInputError, "bounds need xmin < xmax"),  # refused every candidate
        ({"bounds": (0.0, 0.0, 30.0, np.nan)}, InvalidInputError, "bounds contains NaN"),
        ({"h_min": True}, InvalidTypeError, "h_min must be a real number"),
    ],
)
@pytest.mark.parametrize("method", ["admissible_check", "admissible_mask"])
def test_the_fused_limit_check_refuses_limits_no_constraints_hold(
    method: str, kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    limits = {"bounds": (0.0, 0.0, 30.0, 30.0), "h_min": 2.0, "h_max": None, "z_max": 50.0, "d_safe": 1.0, "check_moves": True, **kwargs}
    current = np.array([[10.0, 10.0, 30.0], [20.0, 20.0, 30.0]])
    arguments = {"current": current, "candidates": current[None] + 1.0} if method == "admissible_mask" else {}
    refused(error, words, getattr(HILLS, method), **arguments, **limits, n_threads=1)


@pytest.mark.parametrize("shape", [(10**12,), (10**9, 1000, 3)])
def test_a_flown_file_whose_array_claims_terabytes_is_refused(tmp_path: Path, shape: tuple[int, ...]) -> None:
    import io
    import zipfile

    from uavcov.sim import load_flown

    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": shape})
    with zipfile.ZipFile(tmp_path / "flown.npz", "w") as archive:  # a MemoryError before
        archive.writestr("header.npy", header.getvalue() + bytes(64))
    refused(ResultsFormatError, "an array of it claims more memory than there is", load_flown, tmp_path / "flown.npz")
