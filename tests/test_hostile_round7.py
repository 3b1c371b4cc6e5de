"""Hostile input, round seven: what got through the six rounds before.

The Dask path of a sweep (a scheduler timeout of 1e300 s waited forever, a local cluster of a
billion workers was started, an ``inproc://`` or ``ucx://`` address left a Client whose clean-up
printed a traceback at exit), executors and callbacks that are none (``run_specs`` raised
AttributeError deep in its loop), a legacy ``RandomState`` (numpy wraps it without a
SeedSequence, and a mission's ``spawn`` raised numpy's TypeError), 0-d arrays where a sequence
is meant (numpy's "iteration over a 0-d array"), a ``RAYON_NUM_THREADS`` of thousands (the core
started every thread it asked for), a figure's dpi at which FreeType cannot size text, and
results file names holding control characters. Files are in
``tests/test_hostile_round7_files.py``. Each class is tried with several hostile values, each
asserting the precise error of :mod:`uavcov.errors` and a message naming what is wrong, and the
right answer where the input is a good one.
"""

from __future__ import annotations

import concurrent.futures as cf
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import uavcov
from refusals import refused
from uavcov.errors import ConfigError, InvalidInputError, InvalidTypeError, ResultsFormatError
from uavcov.experiments import ExecutionPlan, ResultsFolder, dask_executor, experiment_specs, parse_seeds, run_specs, summarise
from uavcov.paper import TABLE1

HILLS = uavcov.gaussian_hills(size=30, spacing=1, n_hills=2, rng=0)
SETTINGS = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=2, cao=uavcov.CAOSettings(n_candidates=10))
TINY = TABLE1.with_changes(**{"terrain.spacing": 4.0, "iterations": 1})


@pytest.fixture(scope="module")
def mission() -> Any:
    return uavcov.run_mission(HILLS, SETTINGS, n_threads=1, rng=0)


@pytest.fixture(scope="module")
def specs() -> list[Any]:
    return experiment_specs(TINY, seeds=[0, 1], team_sizes=[2], starts=["cvt"])


# ---------------------------------------------------------------------------------------------
# The Dask path: a timeout past any clock, a cluster of a billion workers, protocols of no scheduler


def _enter(*args: Any, **kwargs: Any) -> None:
    with dask_executor(*args, **kwargs):
        pass


@pytest.mark.parametrize(
    "timeout, error, words",
    [
        (1e300, ConfigError, "timeout must be at most 86400 s"),  # waited forever
        (86_401.0, ConfigError, "timeout must be at most 86400 s"),
        (float("inf"), InvalidInputError, "timeout must be finite"),
        (float("nan"), InvalidInputError, "timeout must be finite"),  # Dask read it as a unit "nans"
        (-1.0, InvalidInputError, "timeout must be > 0"),  # Dask read "-1.0s" as an address error
        (0.0, InvalidInputError, "timeout must be > 0"),
        ("10", InvalidTypeError, "timeout must be a real number"),  # a ValueError of str.format
        (True, InvalidTypeError, "timeout must be a real number"),
    ],
)
def test_dask_executor_refuses_a_timeout_that_is_not_one(timeout: Any, error: type[Exception], words: str) -> None:
    refused(error, words, _enter, "tcp://127.0.0.1:1", timeout=timeout)


@pytest.mark.parametrize("n_workers", [10**9, 4097, np.int64(10**9), 0, -1, True, 2.5])
def test_dask_executor_refuses_a_worker_count_beyond_the_limit_before_any_cluster(n_workers: Any) -> None:
    refused(ConfigError, r"Dask workers must be an integer in \[1, 4096\]", _enter, None, n_workers)


@pytest.mark.parametrize("address", ["inproc://x", "ucx://host:1", "udp://host:1", "tcp://host:0"])
def test_dask_executor_refuses_a_protocol_no_scheduler_answers_on(address: str) -> None:
    pytest.importorskip("distributed")
    refused(ConfigError, "is not the address of a Dask scheduler", _enter, address, timeout=1.0)


# ---------------------------------------------------------------------------------------------
# run_specs: an executor and a callback that are none, worker counts read as "unset"


@pytest.mark.parametrize("executor", [object(), "tcp://host:8786", 3, True])
def test_run_specs_refuses_an_executor_that_is_none(specs: list[Any], executor: Any) -> None:
    refused(InvalidTypeError, "executor must be a concurrent.futures.Executor", run_specs, specs, executor=executor)


@pytest.mark.parametrize("on_result", [3, "print", True])
def test_run_specs_refuses_a_callback_that_is_none(specs: list[Any], on_result: Any) -> None:
    refused(InvalidTypeError, "on_result must be None or a function", run_specs, specs, workers=1, on_result=on_result)


@pytest.mark.parametrize(
    "workers, n_threads, words",
    [(0, None, "workers must be >= 1"), (10**9, None, "workers must be at most 4,096"), (None, 0, "n_threads must be >= 1")],
)
def test_run_specs_with_an_executor_refuses_counts_it_read_as_unset(specs: list[Any], workers: Any, n_threads: Any, words: str) -> None:
    with cf.ThreadPoolExecutor(1) as pool:
        refused(InvalidInputError, words, run_specs, specs, executor=pool, workers=workers, n_threads=n_threads)


def test_run_specs_on_a_thread_pool_gives_the_rows_of_one_process(specs: list[Any]) -> None:
    alone = run_specs(specs, workers=1, n_threads=1)
    with cf.ThreadPoolExecutor(2) as pool:
        pooled = run_specs(specs, executor=pool, n_threads=1)
    keys = ("run_id", "initial_coverage", "final_coverage", "error")
    assert [[r[k] for k in keys] for r in pooled] == [[r[k] for k in keys] for r in alone]


def test_an_execution_plan_holds_at_most_the_worker_limit() -> None:
    refused(InvalidInputError, "workers must be at most 4,096", ExecutionPlan, 10**12, 1)
    assert ExecutionPlan(4096, 1).workers == 4096


# ---------------------------------------------------------------------------------------------
# Generators that cannot be split into streams: a legacy RandomState and legacy seeding


def _legacy_generator() -> np.random.Generator:
    bits = np.random.MT19937()
    bits._legacy_seeding(3)
    return np.random.Generator(bits)


@pytest.mark.parametrize("make_rng", [lambda: np.random.RandomState(0), _legacy_generator], ids=["RandomState", "legacy-seeded"])
@pytest.mark.parametrize(
    "call",
    [
        lambda rng: uavcov.run_mission(HILLS, SETTINGS, n_threads=1, rng=rng),  # numpy's spawn TypeError
        lambda rng: uavcov.gaussian_hills(size=10, spacing=1, n_hills=2, rng=rng),  # taken silently
        lambda rng: uavcov.placement.cvt(HILLS, 3, rng=rng, n_threads=1),
        lambda rng: uavcov.terrain.sample_prior(HILLS, 10, rng=rng),
    ],
    ids=["run_mission", "gaussian_hills", "cvt", "sample_prior"],
)
def test_a_generator_that_cannot_spawn_streams_is_refused_everywhere(make_rng: Any, call: Any) -> None:
    refused(InvalidTypeError, "rng must be None, an int, a SeedSequence or a numpy Generator", call, make_rng())


@pytest.mark.parametrize(
    "rng",
    [np.random.SeedSequence(5), np.random.PCG64(5), np.random.default_rng(5)],
    ids=["SeedSequence", "PCG64", "Generator"],
)
def test_seed_sequences_bit_generators_and_generators_still_seed_like_their_seed(rng: Any) -> None:
    made = uavcov.gaussian_hills(size=10, spacing=1, n_hills=2, rng=rng)
    assert np.array_equal(made.vertices, uavcov.gaussian_hills(size=10, spacing=1, n_hills=2, rng=5).vertices)


# ---------------------------------------------------------------------------------------------
# 0-d arrays: iterable to Python's eyes, "iteration over a 0-d array" to numpy's


@pytest.mark.parametrize("value", [np.array(3), np.array(2.0), np.array(np.nan)], ids=["int", "float", "nan"])
@pytest.mark.parametrize(
    "call, error, words",
    [
        (lambda v: uavcov.sample_dem(window=v), InvalidTypeError, "window must be a sequence, got a 0-d array"),
        (lambda v: experiment_specs(TINY, seeds=[0], team_sizes=v, starts=["cvt"]), InvalidTypeError, "team_sizes must be a sequence"),
        (lambda v: experiment_specs(TINY, seeds=[0], team_sizes=[2], starts=v), InvalidTypeError, "starts must be a sequence"),
        (lambda v: uavcov.terrain.RasterGrid((1.0, 0.0, 0.0, 0.0, -1.0, 10.0), v), InvalidTypeError, "shape must be a sequence"),
        (summarise, InvalidTypeError, "rows must be a sequence"),
        (parse_seeds, ConfigError, "seeds must be a string"),
    ],
    ids=["sample_dem", "team_sizes", "starts", "RasterGrid", "summarise", "parse_seeds"],
)
def test_a_0d_array_is_no_sequence(call: Any, error: type[Exception], words: str, value: np.ndarray) -> None:
    refused(error, words, call, value)


def test_a_1d_array_is_still_a_sequence() -> None:
    assert parse_seeds(np.array([3, 1])) == (3, 1)
    assert len(experiment_specs(TINY, seeds=np.array([0]), team_sizes=np.array([2]), starts=np.array(["cvt"]))) == 1


@pytest.mark.parametrize("value", [np.array(3), np.array(1.0)])
def test_figures_of_rows_refuse_a_0d_array(mission: Any, value: np.ndarray) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_coverage_curves, plot_table1

    refused(InvalidTypeError, "rows must be an iterable of mappings", plot_table1, value)
    # a single run is read as a list of one; a 0-d array is no run
    refused(ResultsFormatError, "ndarray is not a complete mission result", plot_coverage_curves, value)


# ---------------------------------------------------------------------------------------------
# RAYON_NUM_THREADS, read by the core when n_threads is None: thousands of threads were started


@pytest.mark.parametrize("value", ["5000", "+2000", " 1025 ", "9" * 30, "1" * 5000])
def test_a_rayon_num_threads_beyond_the_limit_is_refused(monkeypatch: Any, value: str) -> None:
    monkeypatch.setenv("RAYON_NUM_THREADS", value)
    refused(InvalidInputError, "RAYON_NUM_THREADS asks for .* threads, more than 1024", uavcov.Visibility, HILLS, 10.0)
    refused(InvalidInputError, "RAYON_NUM_THREADS", uavcov.terrain.sample_prior, HILLS, 10, rng=0)  # any call of the core
    assert uavcov.Visibility(HILLS, 10.0, n_threads=1).coverage(np.array([[5.0, 5.0, 20.0]])) >= 0.0  # a count given wins


@pytest.mark.parametrize("value", ["2", " 2 ", "0", "-3", "many", "", "1024"])
def test_a_rayon_num_threads_the_core_uses_or_ignores_is_taken(monkeypatch: Any, value: str) -> None:
    expected = uavcov.Visibility(HILLS, 10.0, n_threads=1).coverage(np.array([[5.0, 5.0, 20.0]]))
    monkeypatch.setenv("RAYON_NUM_THREADS", value if value != "1024" else "1")  # 1024 itself is checked below, not started
    assert uavcov.Visibility(HILLS, 10.0).coverage(np.array([[5.0, 5.0, 20.0]])) == expected
    from uavcov._validate import _check_rayon_num_threads

    monkeypatch.setenv("RAYON_NUM_THREADS", value)
    _check_rayon_num_threads()  # the limit itself passes


# ---------------------------------------------------------------------------------------------
# A dpi at which FreeType cannot size the figures' text ("invalid ppem value", a RuntimeError)


@pytest.mark.parametrize("dpi", [2.5, 5.0, 9.99])
def test_a_figure_refuses_a_dpi_its_text_cannot_be_drawn_at(mission: Any, tmp_path: Path, dpi: float) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_camera_views, plot_coverage_curves, plot_cvt

    refused(InvalidInputError, "dpi must be at least 10", plot_coverage_curves, [mission], dpi=dpi)
    refused(InvalidInputError, "dpi must be at least 10", plot_cvt, mission, out=tmp_path / "cvt.png", dpi=dpi)
    poses = np.array([[10.0, 10.0, 20.0, 0.0, -90.0]])
    refused(InvalidInputError, "dpi must be at least 10", plot_camera_views, HILLS, poses, [uavcov.Sensor(10.0)], dpi=dpi)
    assert list(tmp_path.iterdir()) == []


def test_a_figure_at_the_lowest_dpi_is_drawn(mission: Any, tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_cvt

    plot_cvt(mission, out=tmp_path / "cvt.png", dpi=10.0)
    assert (tmp_path / "cvt.png").stat().st_size > 0


# ---------------------------------------------------------------------------------------------
# Results file names with control characters: legal on Linux, shown by no listing as they are


@pytest.mark.parametrize("name", ["a\nb.txt", "tab\there.txt", "esc\x1b[31m.txt", "del\x7f.txt", "bell\x07"])
def test_a_results_file_name_with_control_characters_is_refused(tmp_path: Path, name: str) -> None:
    folder = ResultsFolder(tmp_path / "results")
    refused(InvalidInputError, "without control characters", folder.write_text, name, "x")
    refused(InvalidInputError, "without control characters", folder.write_csv, name, ["a"], [[1]])
    refused(InvalidInputError, "without control characters", folder.run_file, name)
    assert not (tmp_path / "results").exists() or list((tmp_path / "results").iterdir()) == []


def test_a_results_file_name_in_any_script_is_kept(tmp_path: Path) -> None:
    folder = ResultsFolder(tmp_path / "results")
    assert folder.write_text("résumé-東京.txt", "x").read_text() == "x"


# ---------------------------------------------------------------------------------------------
# run_specs' about: written to config.json unchecked (inf as "Infinity", a set failed the write)


@pytest.mark.parametrize(
    "about, words",
    [
        ({"x": float("inf")}, "about must hold JSON values"),  # written as Infinity, no strict reader reads it
        ({"x": float("nan")}, "about must hold JSON values"),
        ({"x": {1, 2}}, "about must hold JSON values"),  # a TypeError of the writer
        ({"x": b"bytes"}, "about must hold JSON values"),
        ({1: 2}, "about must have non-empty string keys"),  # written as "1"
        ([("x", 1)], "about must be None or a mapping"),
    ],
)
def test_run_specs_refuses_an_about_config_json_cannot_hold(tmp_path: Path, specs: list[Any], about: Any, words: str) -> None:
    refused(InvalidTypeError, words, run_specs, specs, out=tmp_path / "out", workers=1, about=about)
    assert not (tmp_path / "out").exists()


def test_run_specs_records_an_about_of_json_values(tmp_path: Path, specs: list[Any]) -> None:
    import json

    run_specs(specs[:1], out=tmp_path / "out", workers=1, about={"note": "dev seeds", "value": np.float64(1.5), "list": [1, 2]})
    recorded = json.loads((tmp_path / "out" / "config.json").read_text())["about"]
    assert recorded == {"note": "dev seeds", "value": 1.5, "list": [1, 2]}
