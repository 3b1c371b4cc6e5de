"""Hostile input, round four: what ``scripts/fuzz_public_api.py`` left after round three.

Each class is tried with several hostile values, each asserting the precise error of
:mod:`uavcov.errors` and a message naming the argument: silent wrong answers first (a NaN step
size, a wind clock that accepted any time, ragged seen flags), then the flags and records of a
reproduction.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
import pytest

from refusals import refused
from uavcov.errors import InvalidInputError, InvalidTypeError
from uavcov.optim import CAOSettings

# ---------------------------------------------------------------------------------------------
# Silent wrong answers


@pytest.mark.parametrize(
    "k, error, words",
    [
        (float("nan"), InvalidInputError, "k must be finite"),
        (float("inf"), InvalidInputError, "k must be finite"),
        (-1, InvalidInputError, "k must be >= 0"),
        ([0, float("nan")], InvalidInputError, "k contains NaN"),
        (np.array([3, -2]), InvalidInputError, "k must be >= 0"),
        ([[0], [1, 2]], InvalidInputError, "k cannot be read"),
        ("3", InvalidTypeError, "k must be a real number"),
        (True, InvalidTypeError, "k must be a real number"),
    ],
)
def test_step_size_refuses_iterations_that_are_not_ones(k: Any, error: type[Exception], words: str) -> None:
    refused(error, words, CAOSettings().step_size, k)


def test_step_size_keeps_its_answers_for_iterations() -> None:
    settings = CAOSettings()
    assert settings.step_size(0) == 1.5 and isinstance(settings.step_size(np.int64(4)), float)
    assert np.ndim(settings.step_size(np.array(3))) == 0
    np.testing.assert_array_equal(settings.step_size([0, 1, 2]), settings.step_size(np.arange(3)))


@pytest.mark.parametrize(
    "t, position, error, words",
    [
        (float("nan"), np.zeros(3), InvalidInputError, "t must be finite"),
        (float("inf"), np.zeros(3), InvalidInputError, "t must be finite"),
        (-0.01, np.zeros(3), InvalidInputError, "t must be >= 0"),
        (1e300, np.zeros(3), InvalidInputError, "t must be at most"),
        ("1.0", np.zeros(3), InvalidTypeError, "t must be a real number"),
        (1.0, [0.0, float("nan"), 0.0], InvalidInputError, "position contains NaN"),
        (1.0, [0.0, 0.0], InvalidInputError, "position must have 3 components"),
    ],
)
def test_dryden_update_refuses_times_and_positions_that_are_not_ones(t: Any, position: Any, error: type[Exception], words: str) -> None:
    from uavcov.sim import DrydenGusts

    gusts = DrydenGusts([1.0, 0.0, 0.0], [0.5, 0.5, 0.2], 0.01, 3.0, np.random.default_rng(0))
    before = gusts.gust.copy()
    refused(error, words, gusts.update, t, position)
    np.testing.assert_array_equal(gusts.gust, before)  # a refused call does not advance the gusts


@pytest.fixture(scope="module")
def bridge_and_targets() -> Any:
    from uavcov.structures import girder_bridge

    bridge = girder_bridge(rng=0)
    return bridge, bridge.targets(spacing=2.0)


@pytest.mark.parametrize(
    "make_seen, words",
    [
        (lambda n: [[True], [False, True]], "seen cannot be read"),
        (lambda n: np.ones(n - 1, dtype=bool), "seen must be a"),
        (lambda n: np.ones(n + 1, dtype=bool), "seen must be a"),
        (lambda n: np.ones((n, 1), dtype=bool), "seen must be a"),
        (np.ones, "seen must be a"),
        (lambda n: True, "seen must be a"),
    ],
)
def test_coverage_by_part_refuses_seen_flags_that_are_not_ones(bridge_and_targets: Any, make_seen: Any, words: str) -> None:
    bridge, targets = bridge_and_targets
    refused(InvalidInputError, words, bridge.coverage_by_part, make_seen(len(targets)), targets)


@pytest.mark.parametrize(
    "make_seen, with_targets, error, words",
    [
        (lambda n: [[1.0], [0.0, 1.0]], False, InvalidInputError, "seen cannot be read"),
        (lambda n: [[True], [False, True]], True, InvalidInputError, "seen cannot be read"),
        (lambda n: np.ones(n + 1), False, InvalidInputError, "seen has"),
        (lambda n: np.ones(n - 1, dtype=bool), True, InvalidInputError, "seen has"),
        (lambda n: np.full(n, 2.0), False, InvalidInputError, "seen: per-face shares"),
        (lambda n: ["a"] * n, False, InvalidTypeError, "seen must hold real numbers"),
    ],
)
def test_plot_structure_seen_refuses_seen_that_is_not_one(
    bridge_and_targets: Any, make_seen: Any, with_targets: bool, error: type[Exception], words: str
) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_structure_seen

    bridge, targets = bridge_and_targets
    n = len(targets) if with_targets else bridge.surface.n_faces
    kwargs = {"targets": targets} if with_targets else {}
    refused(error, words, plot_structure_seen, bridge.surface, make_seen(n), **kwargs)


def test_plot_structure_seen_refuses_a_ragged_ground(bridge_and_targets: Any) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_structure_seen

    bridge, _ = bridge_and_targets
    shares = np.zeros(bridge.surface.n_faces)
    refused(InvalidInputError, "ground cannot be read", plot_structure_seen, bridge.surface, shares, ground=[[True], [True, False]])
    refused(InvalidInputError, "ground must be a", plot_structure_seen, bridge.surface, shares, ground=np.ones(3))


# ---------------------------------------------------------------------------------------------
# The flags and records of a reproduction, refused before any folder is made


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"execution": 5}, InvalidTypeError, "execution must be None or a mapping"),
        ({"execution": "process pool"}, InvalidTypeError, "execution must be None or a mapping"),
        ({"execution": {1: "a"}}, InvalidTypeError, "execution must have non-empty string keys"),
        ({"execution": {"a": object()}}, InvalidTypeError, "execution must hold JSON values"),
        ({"execution": {"a": float("nan")}}, InvalidTypeError, "execution must hold JSON values"),
        ({"save_runs": np.array([True, False])}, InvalidTypeError, "save_runs must be True or False"),
        ({"save_runs": "no"}, InvalidTypeError, "save_runs must be True or False"),
        ({"exclusive": 1}, InvalidTypeError, "exclusive must be True or False"),
        ({"resume": None}, InvalidTypeError, "resume must be True or False"),
        ({"progress": "yes"}, InvalidTypeError, "progress must be True or False"),
        ({"command": 3}, InvalidTypeError, "command must be None or a string"),
        ({"command": ["reproduce"]}, InvalidTypeError, "command must be None or a string"),
    ],
)
def test_reproduce_refuses_flags_and_records_that_are_not_ones(
    tmp_path: Any, kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    from uavcov.paper import reproduce

    out = tmp_path / "out"
    refused(error, words, reproduce, "table1", out, seeds=[0], **kwargs)
    assert not os.path.exists(out)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"extra": 5}, InvalidTypeError, "extra must be a sequence"),
        ({"extra": {"a": 1}}, InvalidTypeError, "extra must be a sequence"),
        ({"extra": [("a", 1, 2)]}, InvalidTypeError, "extra must hold \\(column, value\\) pairs"),
        ({"extra": ["ab"]}, InvalidTypeError, "extra must hold \\(column, value\\) pairs"),
        ({"extra": [(1, 2)]}, InvalidTypeError, "extra must name its columns"),
        ({"extra": [("", 2)]}, InvalidTypeError, "extra must name its columns"),
        ({"extra": [("a", 1), ("a", 2)]}, InvalidInputError, "extra names a column more than once"),
        ({"extra": [("run_id", "other")]}, InvalidInputError, "extra contradicts the row's own columns"),
        ({"extra": [("seed", 7)]}, InvalidInputError, "extra contradicts the row's own columns"),
        ({"extra": [("a", object())]}, InvalidTypeError, "extra must hold JSON values"),
        ({"extra": [("a", float("inf"))]}, InvalidTypeError, "extra must hold JSON values"),
        ({"label": 3}, InvalidTypeError, "label must be None or a string"),
        ({"label": ["table1"]}, InvalidTypeError, "label must be None or a string"),
    ],
)
def test_experiment_specs_and_run_spec_refuse_a_malformed_extra_or_label(
    kwargs: dict[str, Any], error: type[Exception], words: str
) -> None:
    from uavcov.experiments import RunSpec, experiment_specs
    from uavcov.paper import TABLE1

    refused(error, words, experiment_specs, TABLE1, seeds=[0], team_sizes=[5], starts=["cvt"], **kwargs)
    refused(error, words, RunSpec, TABLE1, 0, 5, "cvt", **kwargs)


def test_an_extra_may_repeat_a_column_of_its_row() -> None:
    from uavcov.experiments import experiment_specs
    from uavcov.paper import TABLE1

    (spec,) = experiment_specs(TABLE1, seeds=[0], team_sizes=[5], starts=["cvt"], extra=[("iterations", TABLE1.iterations), ("d", 2.0)])
    assert spec.row_template()["iterations"] == TABLE1.iterations and spec.row_template()["d"] == 2.0


# ---------------------------------------------------------------------------------------------
# The experiments layer's row helpers

ROW = {
    "experiment": "a",
    "n_uavs": "5",
    "init": "cvt",
    "seed": 0,
    "run_id": "a-cvt",
    "error": "",
    "initial_coverage": "0.1",
    "max_coverage": "0.5",
    "final_coverage": "0.4",
    "iterations_to_95": "10",
}


def _row_helpers() -> list[Any]:
    from uavcov.experiments import finished_rows, summarise
    from uavcov.paper._claims import speed

    return [finished_rows, summarise, speed]


@pytest.mark.parametrize(
    "rows, words",
    [
        (5, "rows must be a sequence"),
        ("abc", "rows must be a sequence"),
        ({"max_coverage": 0.5}, "rows must be a sequence"),
        ([1, 2], "rows must be mappings"),
        ([None], "rows must be mappings"),
        ([["max_coverage", 0.5]], "rows must be mappings"),
    ],
)
def test_row_helpers_refuse_rows_that_are_not_mappings(rows: Any, words: str) -> None:
    for helper in _row_helpers():
        refused(InvalidTypeError, words, helper, rows)


@pytest.mark.parametrize(
    "row, words",
    [
        ({"max_coverage": 0.5}, "rows must have the column"),
        ({**ROW, "iterations_to_95": None}, "column 'iterations_to_95' must hold floats"),
        ({**ROW, "iterations_to_95": "soon"}, "column 'iterations_to_95' must hold floats"),
        ({k: v for k, v in ROW.items() if k != "iterations_to_95"}, "rows must have the column 'iterations_to_95'"),
    ],
)
def test_summarise_and_speed_refuse_rows_without_their_columns(row: dict[str, Any], words: str) -> None:
    from uavcov.errors import ResultsFormatError

    for helper in _row_helpers()[1:]:
        refused(ResultsFormatError, words, helper, [row])


@pytest.mark.parametrize("n_uavs", ["2.5", "five", None, [5]])
def test_speed_refuses_a_team_size_that_is_not_one(n_uavs: Any) -> None:
    from uavcov.errors import ResultsFormatError
    from uavcov.paper._claims import speed

    refused(ResultsFormatError, "column 'n_uavs' must hold ints", speed, [{**ROW, "n_uavs": n_uavs}])


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"by": 5}, "by must be a sequence"),
        ({"by": [1]}, "by must hold column names"),
        ({"metrics": "max_coverage"}, "metrics must be a sequence"),
        ({"metrics": [None]}, "metrics must hold column names"),
    ],
)
def test_summarise_refuses_columns_that_are_not_names(kwargs: dict[str, Any], words: str) -> None:
    from uavcov.experiments import summarise

    refused(InvalidTypeError, words, summarise, [ROW], **kwargs)


def test_row_helpers_keep_their_answers() -> None:
    finished_rows, summarise, speed = _row_helpers()
    assert finished_rows(iter([ROW, {**ROW, "error": "boom"}])) == [ROW]
    assert summarise([ROW])[("a", "5", "cvt")]["max_coverage"][0] == 0.5
    assert speed([ROW]) == {(5, "cvt"): (10.0, 10.0)}


# ---------------------------------------------------------------------------------------------
# Settings checked when they are given: a DEM window, generators, an area of interest


@pytest.mark.parametrize(
    "window, error, words",
    [
        (True, InvalidTypeError, "window must be a sequence"),
        (5, InvalidTypeError, "window must be a sequence"),
        (2.5, InvalidTypeError, "window must be a sequence"),
        ("abcd", InvalidTypeError, "window must be a sequence"),
        ({0: 5}, InvalidTypeError, "window must be a sequence"),
        ((0, 5, 0, True), InvalidInputError, "window must be four integers"),
        ((0, 5), InvalidInputError, "window must be four integers"),
        ((0, 5, 0, 6.0), InvalidInputError, "window must be four integers"),
        ((-10, -2, 0, 6), InvalidInputError, "window must be four integers >= 0"),
    ],
)
def test_sample_dem_refuses_windows_that_are_not_ones(window: Any, error: type[Exception], words: str) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.terrain import sample_dem

    refused(error, words, sample_dem, window=window)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"heights": None}, InvalidTypeError, "heights must hold real numbers"),
        ({"heights": "ab"}, InvalidTypeError, "heights must be a numeric array"),
        ({"heights": (5.0,)}, InvalidInputError, "heights must be a number or a \\(low, high\\) pair"),
        ({"heights": (-1.0, 3.0)}, InvalidInputError, "heights must be >= 0"),
        ({"heights": (9.0, 3.0)}, InvalidInputError, "heights must have low <= high"),
        ({"heights": (1.0, float("nan"))}, InvalidInputError, "heights contains NaN"),
        ({"size": 1e15}, InvalidInputError, "size .*uavcov's size limit"),
        ({"spacing": 0.3}, InvalidInputError, "size .*must be a positive multiple of the spacing"),
        ({"n_hills": 10**12}, InvalidInputError, "n_hills must be at most"),
        ({"sigma": 1e300}, InvalidInputError, "sigma must have a finite, non-zero square"),
    ],
)
def test_hills_generator_checks_its_settings_when_made(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    from uavcov.terrain import HillsGenerator

    refused(error, words, HillsGenerator, **kwargs)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"heights": None}, InvalidTypeError, "heights must hold real numbers"),
        ({"heights": (0.0, 3.0)}, InvalidInputError, "heights must be > 0"),
        ({"footprint": (5.0, 2.0)}, InvalidInputError, "footprint must have low <= high"),
        ({"size": 1e15}, InvalidInputError, "size .*uavcov's size limit"),
        ({"size": "24"}, InvalidTypeError, "size must be a real number"),
        ({"spacing": 0.7}, InvalidInputError, "size .*must be a positive multiple of the spacing"),
        ({"map_spacing": 0.7}, InvalidInputError, "map_spacing: size"),
        ({"n_buildings": -1}, InvalidInputError, "n_buildings must be >= 0"),
        ({"n_buildings": 2.5}, InvalidTypeError, "n_buildings must be an integer"),
        ({"gap": float("nan")}, InvalidInputError, "gap must be finite"),
        ({"height_error": -1.0}, InvalidInputError, "height_error must be >= 0"),
    ],
)
def test_buildings_generator_checks_its_settings_when_made(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    from uavcov.terrain import BuildingsGenerator

    refused(error, words, BuildingsGenerator, **kwargs)


def test_generators_keep_their_settings_as_given() -> None:
    from uavcov.terrain import BuildingsGenerator, HillsGenerator

    assert HillsGenerator(heights=[5, 25]).heights == (5.0, 25.0)
    assert BuildingsGenerator(size=24, heights=[3, 10]).size == 24  # as given: the settings hash reads it


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"polygons": True}, InvalidTypeError, "polygons must be a sequence"),
        ({"polygons": 5}, InvalidTypeError, "polygons must be a sequence"),
        ({"polygons": "ab"}, InvalidTypeError, "polygons must be a sequence"),
        ({"polygons": [3]}, InvalidTypeError, "polygons\\[0\\] must be a sequence"),
        ({"polygons": [[None]]}, InvalidTypeError, "polygon 0 ring 0 must hold real numbers"),
        ({"polygons": []}, InvalidInputError, "holds no polygon"),
        ({"polygons": [[[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]]], "source": 5}, InvalidTypeError, "source must be None or a string"),
    ],
)
def test_area_of_interest_refuses_polygons_that_are_not_ones(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    from uavcov.field import AreaOfInterest

    refused(error, words, AreaOfInterest, **kwargs)


# ---------------------------------------------------------------------------------------------
# A raster's indices, a results folder's file names


@pytest.mark.parametrize(
    "first, second, error, words",
    [
        (1.5, 0, InvalidTypeError, "must hold integers"),
        (True, 0, InvalidTypeError, "must hold integers"),
        ("a", 0, InvalidTypeError, "must hold integers"),
        (None, 0, InvalidTypeError, "must hold integers"),
        (10**30, 0, InvalidTypeError, "must hold integers"),
        ([[1], [1, 2]], 0, InvalidInputError, "cannot be read as an array"),
        (-1, 0, InvalidInputError, "must lie in \\[0, 10\\)"),
        (10, 0, InvalidInputError, "must lie in \\[0, 10\\)"),
        (0, 20, InvalidInputError, "must lie in \\[0, 20\\)"),
        ([1, 2], [1], InvalidInputError, "must have one shape"),
    ],
)
def test_raster_grid_refuses_indices_that_are_not_ones(first: Any, second: Any, error: type[Exception], words: str) -> None:
    from uavcov.terrain import RasterGrid

    grid = RasterGrid((1.0, 0.0, 0.0, 0.0, -1.0, 10.0), (10, 20))
    first_is_hostile = not isinstance(first, int) or first != 0
    for call, names in ((grid.node_of_pixel, ("rows", "cols")), (grid.pixel_of_node, ("i", "j"))):
        named = names[0] if first_is_hostile else names[1]
        if isinstance(second, list):  # two shapes: both named
            named = f"{names[0]} and {names[1]}"
        refused(error, f"^{named} {words}", call, first, second)


def test_raster_grid_keeps_its_answers_and_checks_itself() -> None:
    from uavcov.terrain import RasterGrid

    grid = RasterGrid((1.0, 0.0, 0.0, 0.0, -1.0, 10.0), (10, 20))
    assert [int(v) for v in grid.node_of_pixel(0, 3)] == [9, 3]
    np.testing.assert_array_equal(grid.pixel_of_node(*grid.node_of_pixel([0, 9], [1, 19]))[0], [0, 9])
    refused(InvalidTypeError, "transform must hold real numbers", RasterGrid, None, (1, 1))
    refused(InvalidInputError, "transform must be six numbers", RasterGrid, (1.0, 2.0), (1, 1))
    refused(InvalidInputError, "shape must be >= 1", RasterGrid, (1.0, 0.0, 0.0, 0.0, -1.0, 0.0), (0, 5))
    refused(InvalidTypeError, "shape must be a sequence", RasterGrid, (1.0, 0.0, 0.0, 0.0, -1.0, 0.0), 5)


HOSTILE_NAMES = [
    ("../x", InvalidInputError, "must be a plain file name"),
    ("/tmp/x", InvalidInputError, "must be a plain file name"),
    ("a/b.csv", InvalidInputError, "must be a plain file name"),
    ("a\0b", InvalidInputError, "must be a plain file name"),
    ("..", InvalidInputError, "must be a plain file name"),
    ("", InvalidInputError, "must be a plain file name"),
    (5, InvalidTypeError, "must be a file name \\(a string\\)"),
    (None, InvalidTypeError, "must be a file name \\(a string\\)"),
]


@pytest.mark.parametrize("name, error, words", HOSTILE_NAMES)
def test_results_folder_refuses_names_that_leave_it(tmp_path: Any, name: Any, error: type[Exception], words: str) -> None:
    from uavcov.experiments import ResultsFolder

    folder = ResultsFolder(tmp_path / "out")
    refused(error, "name " + words, folder.write_text, name, "text")
    refused(error, "name " + words, folder.write_csv, name, ["a"], [[1]])
    refused(error, "run_id " + words, folder.run_file, name)
    assert not (tmp_path / "x").exists() and not (tmp_path / "out" / "a").exists()


@pytest.mark.parametrize(
    "call, error, words",
    [
        (lambda f: f.write_text("a.md", 5), InvalidTypeError, "text must be a string"),
        (lambda f: f.write_text("a.md", b"x"), InvalidTypeError, "text must be a string"),
        (lambda f: f.write_csv("a.csv", "abc", []), InvalidTypeError, "header must be a sequence"),
        (lambda f: f.write_csv("a.csv", [1, 2], []), InvalidTypeError, "header must hold column names"),
        (lambda f: f.write_csv("a.csv", [], []), InvalidTypeError, "header must hold column names"),
        (lambda f: f.write_csv("a.csv", ["a"], [[1, 2]]), InvalidInputError, "rows must have 1 values"),
        (lambda f: f.write_csv("a.csv", ["a"], ["x"]), InvalidTypeError, "rows must be a sequence"),
        (lambda f: f.write_csv("a.csv", ["a"], 5), InvalidTypeError, "rows must be a sequence"),
    ],
)
def test_results_folder_refuses_text_headers_and_rows_that_are_not_ones(
    tmp_path: Any, call: Any, error: type[Exception], words: str
) -> None:
    from uavcov.experiments import ResultsFolder

    folder = ResultsFolder(tmp_path / "out")
    refused(error, words, call, folder)
    assert not (tmp_path / "out" / "a.csv").exists() and not (tmp_path / "out" / "a.md").exists()
    assert folder.write_csv("b.csv", ["a", "b"], [[1, 2.5]]).read_text() == "a,b\n1,2.5\n"


@pytest.mark.parametrize(
    "seed, error, words",
    [
        (None, InvalidTypeError, "seed must be an integer"),
        (2.5, InvalidTypeError, "seed must be an integer"),
        (-1, InvalidInputError, "seed must be >= 0"),
    ],
)
def test_buildings_simplified_map_refuses_seeds_that_are_not_ones(seed: Any, error: type[Exception], words: str) -> None:
    from uavcov.terrain import BuildingsGenerator

    refused(error, words, BuildingsGenerator().simplified_map, seed)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"row": None}, InvalidTypeError, "row must be a mapping"),
        ({"row": [("n_uavs", 5)]}, InvalidTypeError, "row must be a mapping"),
        ({"column": ["n_uavs"]}, InvalidTypeError, "column must hold column names"),
        ({"column": ""}, InvalidTypeError, "column must hold column names"),
        ({"kind": float("nan")}, InvalidTypeError, "kind must be float or int"),
        ({"kind": str}, InvalidTypeError, "kind must be float or int"),
    ],
)
def test_row_number_refuses_arguments_that_are_not_ones(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    from uavcov.experiments import row_number

    refused(error, words, row_number, **{"row": ROW, "column": "n_uavs", "kind": int, **kwargs})
    assert row_number(ROW, "n_uavs", int) == 5 and row_number(ROW, "max_coverage") == 0.5


# ---------------------------------------------------------------------------------------------
# Found by the whole harness (scripts/fuzz_public_api.py --no-cli) once the above were fixed


@pytest.mark.parametrize(
    "required, words",
    [
        (None, "required must be a sequence"),
        (5, "required must be a sequence"),
        ("max_coverage", "required must be a sequence"),
        ([["run_id"]], "required must hold column names"),
        (np.ones((2, 5)), "required must hold column names"),
    ],
)
def test_read_runs_refuses_required_columns_that_are_not_names(tmp_path: Any, required: Any, words: str) -> None:
    from uavcov.experiments import read_runs

    path = tmp_path / "runs.csv"
    path.write_text("run_id\nx\n")
    refused(InvalidTypeError, words, read_runs, path, required=required)


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"metric": ["max_coverage"]}, "metric must be a column name"),
        ({"metric": np.ones(3)}, "metric must be a column name"),
        ({"metric": ""}, "metric must be a column name"),
        ({"paper": np.ones(3)}, "paper must be True or False"),
        ({"paper": "yes"}, "paper must be True or False"),
    ],
)
def test_plot_table1_refuses_a_metric_or_paper_that_is_not_one(kwargs: dict[str, Any], words: str) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_table1

    refused(InvalidTypeError, words, plot_table1, [ROW], **kwargs)


@pytest.mark.parametrize(
    "legs, error, words",
    [
        ([[0], [0, 0], [0]], InvalidInputError, "leg_of_state cannot be read as an array"),
        (np.zeros(3), InvalidTypeError, "leg_of_state must hold integers"),
        (np.array([True, False, True]), InvalidTypeError, "leg_of_state must hold integers"),
        (np.array([0, 0, 1]), InvalidInputError, "leg_of_state must be 3 leg indices"),
        (np.array([0, -1, 0]), InvalidInputError, "leg_of_state must be 3 leg indices"),
        (np.zeros(2, dtype=int), InvalidInputError, "leg_of_state must be 3 leg indices"),
    ],
)
def test_check_flight_refuses_legs_that_are_not_ones(legs: Any, error: type[Exception], words: str) -> None:
    import uavcov
    from uavcov.sim import check_flight

    hills = uavcov.gaussian_hills(size=30, spacing=1, n_hills=2, rng=0)
    pair = [[10.0, 10.0, 30.0], [20.0, 20.0, 30.0]]
    positions, ends = np.array([pair] * 3), np.array([pair])
    refused(error, words, check_flight, hills, uavcov.Constraints().resolve(hills), positions, legs, ends, ends)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"workers": float("nan")}, InvalidTypeError, "workers must be an integer"),
        ({"workers": 2.5}, InvalidTypeError, "workers must be an integer"),
        ({"workers": 0}, InvalidInputError, "workers must be >= 1"),
        ({"n_threads": float("inf")}, InvalidTypeError, "n_threads must be an integer"),
        ({"n_threads": np.ones(3)}, InvalidTypeError, "n_threads must be an integer"),
        ({"n_threads": 10**6}, InvalidInputError, "n_threads must be at most"),
    ],
)
def test_execution_plan_refuses_counts_that_are_not_ones(kwargs: dict[str, Any], error: type[Exception], words: str) -> None:
    from uavcov.experiments import ExecutionPlan

    refused(error, words, ExecutionPlan, **{"workers": 1, "n_threads": 1, **kwargs})
    assert ExecutionPlan(np.int64(2), 3) == ExecutionPlan(2, 3)
