"""Run files: the trace's timings under their ``_s`` names, and files written before them still load."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

import uavcov
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
