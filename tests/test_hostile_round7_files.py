"""Hostile input, round seven, files and the command line: what got through the six rounds before.

JSON and TOML nested thousands deep (Python's parsers raise ``RecursionError``, which escaped a
results folder's ``config.json``, the structures and realistic configs, a flown run's header and
a sweep file as a traceback), a ``.npy`` terrain of complex or boolean heights (the cast dropped
the imaginary part with a warning and ran), and the command line's Dask options (a scheduler
timeout of 1e300 s waited forever; an ``inproc://`` or ``ucx://`` address printed a traceback at
exit after its one line). Numbers, generators and executors are in
``tests/test_hostile_round7.py``. Each class is tried with several hostile values, each asserting
the precise error of :mod:`uavcov.errors` and a message naming what is wrong, and the right
answer where the input is a good one.
"""

from __future__ import annotations

import io
import os
import subprocess
import sys
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from refusals import refused
from uavcov.cli import EXIT_BAD_INPUT, main
from uavcov.errors import ConfigError, ResultsFormatError, ResultsInUseError
from uavcov.experiments import experiment_specs, load_sweep_config, run_specs
from uavcov.paper import EXPERIMENTS, TABLE1

TINY = TABLE1.with_changes(**{"terrain.spacing": 4.0, "iterations": 0})
SWEEP_HEAD = 'base = "table1"\nseeds = [0]\nteam_sizes = [2]\nstarts = ["cvt"]\niterations = 0\n'


def _nested(depth: int, kind: str) -> str:
    """A JSON text of arrays or objects nested ``depth`` deep."""
    if kind == "arrays":
        return "[" * depth + "]" * depth
    return '{"a": ' * depth + "{}" + "}" * depth


# ---------------------------------------------------------------------------------------------
# JSON nested thousands deep: Python's parser raises RecursionError, a traceback before


DEPTHS = [pytest.param(100_000, "arrays", id="arrays-1e5"), pytest.param(100_000, "objects", id="objects-1e5")]


@pytest.mark.parametrize("depth, kind", DEPTHS)
def test_a_results_folder_whose_config_nests_beyond_reason_is_not_ours(tmp_path: Path, depth: int, kind: str) -> None:
    (tmp_path / "config.json").write_text(_nested(depth, kind))
    specs = experiment_specs(TINY, seeds=[0], team_sizes=[2], starts=["cvt"])
    refused(ResultsInUseError, "is not a uavcov results file", run_specs, specs, out=tmp_path, workers=1, progress=False)
    assert sorted(p.name for p in tmp_path.iterdir() if p.name != ".uavcov.lock") == ["config.json"]  # nothing written beside it


@pytest.mark.parametrize("depth, kind", DEPTHS)
def test_a_structures_config_nested_beyond_reason_is_a_format_error(tmp_path: Path, depth: int, kind: str) -> None:
    from uavcov.paper import reproduce_structures

    (tmp_path / "config.json").write_text(_nested(depth, kind))
    refused(ResultsFormatError, "cannot read .*config.json: RecursionError", reproduce_structures, tmp_path, resume=True)


@pytest.mark.parametrize("depth, kind", DEPTHS)
def test_a_realistic_config_nested_beyond_reason_is_a_format_error(tmp_path: Path, depth: int, kind: str) -> None:
    from uavcov.paper import write_realistic_report

    (tmp_path / "config.json").write_text(_nested(depth, kind))
    (tmp_path / "rows.jsonl").write_text("")
    refused(ResultsFormatError, "config.json is not JSON: maximum recursion depth", write_realistic_report, tmp_path)


@pytest.mark.parametrize("depth, kind", DEPTHS)
def test_a_flown_run_whose_header_nests_beyond_reason_is_a_format_error(tmp_path: Path, depth: int, kind: str) -> None:
    from uavcov.sim import is_flown_file, load_flown

    member = io.BytesIO()
    np.save(member, np.array(_nested(depth, kind)))
    path = tmp_path / "flown.npz"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("header.npy", member.getvalue())
    refused(ResultsFormatError, "is not a readable flown run: RecursionError", load_flown, path)
    assert is_flown_file(path) is False


@pytest.mark.parametrize("depth", [2_000, 20_000])
@pytest.mark.parametrize("where", ["d_max = {}", "[sweep]\nd_max = {}"])
def test_a_sweep_file_nested_beyond_reason_is_a_config_error(tmp_path: Path, depth: int, where: str) -> None:
    path = tmp_path / "deep.toml"
    path.write_text(SWEEP_HEAD + where.format("[" * depth + "]" * depth) + "\n")
    refused(ConfigError, "nests arrays or tables too deeply to be a sweep file", load_sweep_config, path, bases=dict(EXPERIMENTS))


def test_the_command_line_refuses_a_deep_sweep_file_in_one_line(tmp_path: Path, capsys: Any) -> None:
    path = tmp_path / "deep.toml"
    path.write_text(SWEEP_HEAD + "d_max = " + "[" * 5000 + "]" * 5000 + "\n")
    assert main(["sweep", str(path), "--out", str(tmp_path / "out")]) == EXIT_BAD_INPUT
    assert capsys.readouterr().err.strip().count("\n") == 0
    assert not (tmp_path / "out").exists()


# ---------------------------------------------------------------------------------------------
# A .npy terrain of heights that are no real numbers: complex lost its imaginary part, bool read as metres


def _npy_sweep(tmp_path: Path, heights: np.ndarray) -> Path:
    np.save(tmp_path / "heights.npy", heights)
    path = tmp_path / "sweep.toml"
    path.write_text(SWEEP_HEAD + '[terrain]\nkind = "file"\npath = "heights.npy"\nspacing = 1.0\n')
    return path


@pytest.mark.parametrize(
    "heights",
    [
        np.zeros((20, 20), complex),
        np.full((20, 20), 1 + 2j, np.complex64),
        np.ones((20, 20), bool),
        np.ones((20, 20), "m8[s]"),
        np.ones((20, 20), "U3"),
    ],
    ids=["complex128", "complex64", "bool", "timedelta", "str"],
)
def test_a_npy_terrain_of_heights_that_are_no_real_numbers_is_refused(tmp_path: Path, heights: np.ndarray) -> None:
    path = _npy_sweep(tmp_path, heights)
    refused(ConfigError, "heights must be real numbers, got dtype", load_sweep_config, path, bases=dict(EXPERIMENTS))


@pytest.mark.parametrize("dtype", [np.float16, np.float32, np.int8, np.uint16])
def test_a_npy_terrain_of_real_heights_of_any_width_is_read_as_metres(tmp_path: Path, dtype: Any) -> None:
    heights = np.arange(400).reshape(20, 20) % 7
    config = load_sweep_config(_npy_sweep(tmp_path, heights.astype(dtype)), bases=dict(EXPERIMENTS))
    surface = config.specs()[0].experiment.scenario(0)
    assert np.array_equal(surface.grid.z, heights.astype(np.float64))


# ---------------------------------------------------------------------------------------------
# The command line's Dask options: a timeout past the clock hung, two protocols printed a traceback


def _cli_in_a_child(argv: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    """``uavcov argv`` in its own process: what it prints at exit (a Client's clean-up) counts too."""
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    return subprocess.run(
        [sys.executable, "-m", "uavcov", *argv], cwd=cwd, capture_output=True, text=True, timeout=120, check=False, env=env
    )


@pytest.mark.parametrize("address", ["inproc://x", "ucx://host:1"])
def test_the_command_line_refuses_a_scheduler_of_another_protocol_in_one_line(tmp_path: Path, address: str) -> None:
    pytest.importorskip("distributed")
    (tmp_path / "s.toml").write_text(SWEEP_HEAD)
    done = _cli_in_a_child(["sweep", "s.toml", "--out", "out", "--scheduler", address, "--scheduler-timeout", "1"], tmp_path)
    assert done.returncode == EXIT_BAD_INPUT
    assert done.stderr.strip().splitlines() == [done.stderr.strip()], done.stderr  # no traceback at exit
    assert "is none of tcp, tls, ws, wss" in done.stderr


@pytest.mark.parametrize("timeout, words", [("1e300", "at most 86400 s"), ("86401", "at most 86400 s"), ("inf", "must be finite")])
def test_the_command_line_refuses_a_scheduler_timeout_past_a_day_at_once(tmp_path: Path, capsys: Any, timeout: str, words: str) -> None:
    pytest.importorskip("distributed")
    (tmp_path / "s.toml").write_text(SWEEP_HEAD)
    argv = ["sweep", str(tmp_path / "s.toml"), "--out", str(tmp_path / "out"), "--scheduler", "tcp://127.0.0.1:1"]
    assert main([*argv, "--scheduler-timeout", timeout]) == EXIT_BAD_INPUT
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    assert words in err


# ---------------------------------------------------------------------------------------------
# A file that changes between its check and its read: swapped for a FIFO (the read blocked
# forever), or grown past its limit (read whole). The checks are now made on the opened file.


def _changing_after_the_check(monkeypatch: Any, change: str) -> None:
    """Make the check by name pass, then change the file before it is read."""
    import uavcov._validate as validate

    checked = validate.regular_file

    def check_then_change(path: Path, *args: Any) -> Path:
        result = checked(path, *args)
        if change == "fifo":
            path.unlink()
            os.mkfifo(path)
        else:
            with open(path, "ab") as grown:
                grown.write(b"#" * (2 << 20))
        return result

    monkeypatch.setattr(validate, "regular_file", check_then_change)


def _with_an_alarm(call: Any, *args: Any, **kwargs: Any) -> None:
    """``call`` under a 30 s alarm: a read blocked on a FIFO fails the test instead of hanging it."""
    import signal

    def stop(*_: Any) -> None:
        raise TimeoutError("the read blocked")

    previous = signal.signal(signal.SIGALRM, stop)
    signal.alarm(30)
    try:
        call(*args, **kwargs)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


CHANGES = [("fifo", "it changed since it was checked"), ("grown", "it grew since it was checked")]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
@pytest.mark.parametrize("change, words", CHANGES)
def test_a_sweep_file_changed_after_its_check_is_refused(tmp_path: Path, monkeypatch: Any, change: str, words: str) -> None:
    path = tmp_path / "s.toml"
    path.write_text(SWEEP_HEAD)
    _changing_after_the_check(monkeypatch, change)
    refused(ConfigError, words, _with_an_alarm, load_sweep_config, path, bases=dict(EXPERIMENTS))


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
@pytest.mark.parametrize("change, words", CHANGES)
def test_a_structures_config_changed_after_its_check_is_refused(tmp_path: Path, monkeypatch: Any, change: str, words: str) -> None:
    from uavcov.paper import reproduce_structures

    (tmp_path / "config.json").write_text("{}")
    _changing_after_the_check(monkeypatch, change)
    refused(ResultsFormatError, words, _with_an_alarm, reproduce_structures, tmp_path, resume=True)


def test_a_sweep_file_that_stays_put_is_read_whole(tmp_path: Path) -> None:
    path = tmp_path / "s.toml"
    path.write_text(SWEEP_HEAD + "d_max = 12.5\n")
    config = load_sweep_config(path, bases=dict(EXPERIMENTS))
    assert config.specs()[0].experiment.mission.d_max == 12.5


def _swapped_for_a_fifo_after_is_file(monkeypatch: Any, target: Path) -> None:
    """``Path.is_file`` answers for ``target`` as it is, then swaps it for a FIFO (the race, made certain)."""
    answer = Path.is_file

    def is_file_then_swap(self: Path) -> bool:
        result = answer(self)
        if self == target and result:
            self.unlink()
            os.mkfifo(self)
        return result

    monkeypatch.setattr(Path, "is_file", is_file_then_swap)


@pytest.fixture(scope="module")
def run_file(tmp_path_factory: Any) -> bytes:
    import uavcov

    hills = uavcov.gaussian_hills(size=20, spacing=2, n_hills=2, rng=0)
    settings = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=1, cao=uavcov.CAOSettings(n_candidates=10))
    path = uavcov.save_mission(uavcov.run_mission(hills, settings, n_threads=1, rng=0), tmp_path_factory.mktemp("run") / "run.npz")
    return Path(path).read_bytes()


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_a_run_file_swapped_for_a_fifo_after_its_check_is_refused(tmp_path: Path, monkeypatch: Any, run_file: bytes) -> None:
    import uavcov

    path = tmp_path / "run.npz"
    path.write_bytes(run_file)
    _swapped_for_a_fifo_after_is_file(monkeypatch, path)
    refused(ResultsFormatError, "is not a regular file \\(it changed since it was checked\\)", _with_an_alarm, uavcov.load_mission, path)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_a_flown_file_swapped_for_a_fifo_after_its_check_is_refused(tmp_path: Path, monkeypatch: Any, run_file: bytes) -> None:
    from uavcov.sim import is_flown_file, load_flown

    loaded, asked = tmp_path / "a.npz", tmp_path / "b.npz"
    loaded.write_bytes(run_file)
    _swapped_for_a_fifo_after_is_file(monkeypatch, loaded)
    refused(ResultsFormatError, "it changed since it was checked", _with_an_alarm, load_flown, loaded)
    asked.write_bytes(run_file)
    _swapped_for_a_fifo_after_is_file(monkeypatch, asked)
    answers: list[bool] = []
    _with_an_alarm(lambda: answers.append(is_flown_file(asked)))
    assert answers == [False]  # answered, not blocked


def test_a_run_file_that_stays_put_still_loads(tmp_path: Path, run_file: bytes) -> None:
    import uavcov

    path = tmp_path / "run.npz"
    path.write_bytes(run_file)
    assert uavcov.load_mission(path).trace.values.shape[0] == 2
