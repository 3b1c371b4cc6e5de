"""Run files: the trace's timings under their ``_s`` names, and files written before them still load."""

from __future__ import annotations

import dataclasses
import json
import pickle
import warnings
from pathlib import Path

import numpy as np
import pytest

import uavcov
from uavcov.errors import ResultsFormatError
from uavcov.records import FORMAT, load_mission, save_mission

_RENAMED = {"time_measure_s": "time_measure", "time_feasibility_s": "time_feasibility", "time_optimizer_s": "time_own"}


@pytest.fixture(scope="module")
def run():
    terrain = uavcov.gaussian_hills(size=30.0, spacing=1.0, n_hills=3, rng=2)
    return uavcov.run_mission(terrain, uavcov.MissionSettings(n_uavs=2, d_max=15.0, n_prior=8, iterations=5), rng=1, n_threads=1)


def _header(path) -> dict:
    with np.load(path) as data:
        return json.loads(str(data["header"]))


def test_timings_are_written_under_the_s_names(run, tmp_path):
    header = _header(save_mission(run, tmp_path / "run.npz"))
    assert header["format"] == FORMAT
    for new, old in _RENAMED.items():
        assert header["trace"][new] == getattr(run.trace, new)
        assert old not in header["trace"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)  # loading reads no deprecated name
        loaded = load_mission(tmp_path / "run.npz")
    for new in _RENAMED:
        assert getattr(loaded.trace, new) == getattr(run.trace, new)


def test_a_file_with_the_old_timing_names_still_loads(run, tmp_path):
    path = save_mission(run, tmp_path / "run.npz")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    header = json.loads(str(arrays["header"]))
    header["trace"] = {_RENAMED.get(k, k): v for k, v in header["trace"].items()}
    assert "time_own" in header["trace"] and "time_optimizer_s" not in header["trace"]
    arrays["header"] = np.array(json.dumps(header))
    np.savez(tmp_path / "old.npz", **arrays)
    loaded = load_mission(tmp_path / "old.npz")
    for new in _RENAMED:
        assert getattr(loaded.trace, new) == getattr(run.trace, new)
    np.testing.assert_array_equal(loaded.trajectory, run.trajectory)


def test_a_file_without_a_timing_names_the_new_field(run, tmp_path):
    path = save_mission(run, tmp_path / "run.npz")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    header = json.loads(str(arrays["header"]))
    del header["trace"]["time_feasibility_s"]
    arrays["header"] = np.array(json.dumps(header))
    np.savez(tmp_path / "partial.npz", **arrays)
    with pytest.raises(uavcov.errors.ResultsFormatError, match="time_feasibility_s"):
        load_mission(tmp_path / "partial.npz")


# ---------------------------------------------------------------------------------------------
# Issue 41: MissionResult reads what its trace holds (properties), and files written before load


_FROM_TRACE = (
    "best_coverage",
    "initial_coverage",
    "final_coverage",
    "best_iteration",
    "iterations_to_95",
    "evaluations",
    "time_measure_s",
    "time_optimizer_s",
)
_OLD_FILE = Path(__file__).parent / "data" / "mission_before_issue41.npz"


def test_a_file_written_before_the_result_read_its_trace_still_loads():
    """``tests/data/mission_before_issue41.npz`` was written by ``save_mission`` when
    MissionResult still stored these figures as fields; each property gives what was stored."""
    with np.load(_OLD_FILE) as data:
        header = json.loads(str(data["header"]))
        stored = {name: data[name] for name in ("coverage", "trace_trajectory", "trace_best_positions", "distance_flown")}
    result = load_mission(_OLD_FILE)
    for name in _FROM_TRACE:
        assert getattr(result, name) == header["scalars"][name], name
    assert result.wall_time_s == header["scalars"]["wall_time_s"]
    assert result.start_time_s == header["scalars"]["start_time_s"]
    assert np.array_equal(result.coverage, stored["coverage"])
    assert np.array_equal(result.trajectory, stored["trace_trajectory"][..., :3])
    assert np.array_equal(result.best_positions, stored["trace_best_positions"][..., :3])
    assert np.array_equal(result.distance_flown, stored["distance_flown"])
    assert result.seed == header["seed"] == 0


def test_the_result_restates_nothing_its_trace_holds(run, tmp_path):
    names = {f.name for f in dataclasses.fields(run)}
    assert not names & ({"trajectory", "coverage", "best_positions"} | set(_FROM_TRACE))
    assert run.best_coverage == run.trace.best_value and run.evaluations == run.trace.evaluations
    assert np.array_equal(run.coverage, run.trace.values)
    assert np.shares_memory(run.trajectory, run.trace.trajectory)  # positions only: a view, not a copy
    # the file still holds every scalar and the coverage, for readers without uavcov
    header = _header(save_mission(run, tmp_path / "run.npz"))
    assert {name: header["scalars"][name] for name in _FROM_TRACE} == {name: getattr(run, name) for name in _FROM_TRACE}
    again = pickle.loads(pickle.dumps(run))
    assert np.array_equal(again.trajectory, run.trajectory) and again.best_iteration == run.best_iteration


def test_a_file_whose_coverage_disagrees_with_its_trace_is_refused(run, tmp_path):
    path = save_mission(run, tmp_path / "run.npz")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["coverage"] = arrays["coverage"] + 0.25
    np.savez_compressed(tmp_path / "bad.npz", **arrays)
    with pytest.raises(ResultsFormatError, match="coverage disagrees"):
        load_mission(tmp_path / "bad.npz")
