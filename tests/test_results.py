"""The results folder (uavcov.experiments._results): the one reader of runs.csv, appending, config.json, the lock.

These tests drive :mod:`uavcov.experiments._results` directly, with hand-written files; the end-to-end
guarantees (resume, exclusive, the same config.json for every command) are in test_sweep.py.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from uavcov.errors import (
    ConfigError,
    InvalidInputError,
    ResultsFolderError,
    ResultsFormatError,
    ResultsInUseError,
    UavcovError,
)
from uavcov.experiments import ResultsFolder, read_runs
from uavcov.experiments._results import CONFIG_FORMAT, RUN_COLUMNS, RunsFile, atomic_write, config_document, csv_line, format_cell
from uavcov.plotting import _runs as plotting_runs


def row(run_id: str, **cells) -> dict:
    values = dict.fromkeys(RUN_COLUMNS)
    values.update(
        run_id=run_id,
        experiment="table1",
        init="cvt",
        n_uavs=5,
        seed=0,
        sensing_range=25.0,
        iterations=3,
        initial_coverage=0.1 + 0.2,  # 0.30000000000000004: must come back exactly
        max_coverage=0.5,
        final_coverage=0.45,
        best_iteration=2,
        iterations_to_95=1,
        evaluations=4,
        wall_time_s=1.25,
        time_measure_s=0.5,
        time_optimizer_s=0.25,
        time_feasibility_s=0.125,
        settings_hash="0a1b2c3d",
        error="",
    )
    values.update(cells)
    return values


def write_runs(path: Path, rows, columns=RUN_COLUMNS) -> Path:
    path.write_text(csv_line(columns) + "".join(csv_line([r.get(c) for c in columns]) for r in rows), encoding="utf-8")
    return path


# ---------------------------------------------------------------------------------------------
# read_runs


def test_read_runs_gives_numbers_back_exactly_and_empty_cells_as_none(tmp_path):
    failed = row("b", initial_coverage=None, max_coverage=None, final_coverage=None, best_iteration=None, error="InfeasibleError: no")
    path = write_runs(tmp_path / "runs.csv", [row("a"), failed])
    first, second = read_runs(path)
    assert first == row("a")
    assert isinstance(first["n_uavs"], int) and first["initial_coverage"] == 0.1 + 0.2
    assert second["max_coverage"] is None and second["best_iteration"] is None
    assert second["error"] == "InfeasibleError: no"
    assert read_runs(write_runs(tmp_path / "empty.csv", [])) == []
    (tmp_path / "nothing.csv").write_bytes(b"")
    assert read_runs(tmp_path / "nothing.csv") == []


def test_read_runs_keeps_extra_columns_as_strings(tmp_path):
    columns = (*RUN_COLUMNS, "cao.alpha0")
    path = write_runs(tmp_path / "runs.csv", [{**row("a"), "cao.alpha0": 1.0}], columns)
    (only,) = read_runs(path)
    assert only["cao.alpha0"] == "1.0"


def test_read_runs_ignores_a_last_line_cut_short(tmp_path):
    path = write_runs(tmp_path / "runs.csv", [row("a"), row("b")])
    whole = read_runs(path)
    with open(path, "a", encoding="utf-8") as handle:
        handle.write(csv_line(list(row("c").values())).rstrip("\n")[:40])  # a write cut off by a crash
    assert read_runs(path) == whole
    # Even a cut inside a quoted cell, or a cut header with no row at all.
    with open(path, "a", encoding="utf-8") as handle:
        handle.write('\n"unterminated, quote')
    path.write_bytes(path.read_bytes().replace(b'\n"unterminated', b'"unterminated'))
    assert read_runs(path) == whole
    header_only = tmp_path / "header.csv"
    header_only.write_text(",".join(RUN_COLUMNS)[:30], encoding="utf-8")
    assert read_runs(header_only, required=()) == []


@pytest.mark.parametrize(
    "content,message",
    [
        (b"a,b\n1,2\n", "run_id"),
        (",".join(RUN_COLUMNS).encode() + b"\n\xff\xfe,1\n", "UTF-8"),
        (",".join(RUN_COLUMNS).encode() + b"\nonly,three,cells\n", "3 cells"),
        (csv_line(RUN_COLUMNS).encode() + csv_line([*row("a").values()][:3] + ["five"] + [*row("a").values()][4:]).encode(), "n_uavs"),
        (csv_line(RUN_COLUMNS).encode() + csv_line({**row("a"), "max_coverage": "high"}.values()).encode(), "max_coverage"),
    ],
)
def test_read_runs_refuses_what_is_not_a_runs_file(tmp_path, content, message):
    path = tmp_path / "runs.csv"
    path.write_bytes(content)
    with pytest.raises(ResultsFormatError, match=message):
        read_runs(path)


def test_read_runs_of_a_missing_file(tmp_path):
    with pytest.raises(ResultsFormatError, match="no runs file"):
        read_runs(tmp_path / "missing.csv")
    assert ResultsFolder(tmp_path / "fresh").read_runs() == []


def test_plotting_reads_runs_through_the_same_reader(tmp_path):
    path = write_runs(tmp_path / "runs.csv", [row("a"), row("b", max_coverage=None, error="x")])
    with open(path, "a", encoding="utf-8") as handle:
        handle.write("c,table1,cvt,5")  # cut short
    assert plotting_runs._read_runs(path) == read_runs(path, required=plotting_runs.RUNS_COLUMNS) == read_runs(path)
    # A file with only the columns the figures need is enough for plotting, not for a sweep.
    columns = plotting_runs.RUNS_COLUMNS
    small = write_runs(tmp_path / "small.csv", [row("a")], columns)
    assert plotting_runs._read_runs(small) == [{c: row("a")[c] for c in columns}]
    with pytest.raises(ResultsFormatError, match="run_id"):
        read_runs(small)
    with pytest.raises(ResultsFormatError, match="max_coverage"):
        plotting_runs._read_runs(write_runs(tmp_path / "less.csv", [row("a")], columns[:-1]))


# ---------------------------------------------------------------------------------------------
# RunsFile


def test_runs_file_drops_a_cut_line_before_appending(tmp_path):
    path = write_runs(tmp_path / "runs.csv", [row("a")])
    with open(path, "a", encoding="utf-8") as handle:
        handle.write("b,table1,cvt,5,0,25.0,3,0.4")  # no newline: run b never finished
    runs = RunsFile(path, RUN_COLUMNS)
    try:
        assert not path.read_bytes().endswith(b"0.4")  # dropped on opening
        runs.append(row("c"))
    finally:
        runs.close()
    assert [r["run_id"] for r in read_runs(path)] == ["a", "c"]
    assert path.read_bytes().endswith(b"\n") and path.read_text().count("\n") == 3


def test_runs_file_starts_over_when_even_the_header_was_cut(tmp_path):
    path = tmp_path / "runs.csv"
    path.write_text(",".join(RUN_COLUMNS)[:30], encoding="utf-8")  # a crash during the first write
    assert read_runs(path, required=()) == []
    runs = RunsFile(path, RUN_COLUMNS)
    runs.append(row("a"))
    runs.close()
    assert [r["run_id"] for r in read_runs(path)] == ["a"]


def test_runs_file_writes_the_header_once_and_missing_cells_empty(tmp_path):
    path = tmp_path / "runs.csv"
    for run_id in ("a", "b"):
        runs = RunsFile(path, RUN_COLUMNS)
        runs.append({"run_id": run_id, "error": ""})
        runs.close()
    stored = read_runs(path)
    assert [r["run_id"] for r in stored] == ["a", "b"]
    assert stored[0]["max_coverage"] is None and stored[0]["error"] == ""
    assert path.read_text().count("run_id") == 1


def test_runs_file_refuses_other_columns(tmp_path):
    path = write_runs(tmp_path / "runs.csv", [row("a")])
    before = path.read_bytes()
    with pytest.raises(ResultsInUseError, match="another kind of sweep"):
        RunsFile(path, (*RUN_COLUMNS, "d_max"))
    assert path.read_bytes() == before


def test_format_cell_and_csv_line():
    assert format_cell(0.1 + 0.2) == "0.30000000000000004"
    assert format_cell(None) == "" and format_cell(3) == "3" and format_cell((1.0, 2.5)) == "[1.0, 2.5]"
    assert csv_line(["a,b", 1, None]) == '"a,b",1,\n'


# ---------------------------------------------------------------------------------------------
# config.json


def test_config_document_is_the_one_schema():
    document = config_document("sweep", {"0a1b2c3d": {"label": "x", "swept": {}, "experiment": {}}}, {"count": 1})
    assert set(document) == {"format", "command", "uavcov_version", "settings", "runs", "execution", "about"}
    assert document["format"] == CONFIG_FORMAT == "uavcov.results/1"
    assert document["execution"] == {} and document["about"] == {}
    from uavcov._core import __version__

    assert document["uavcov_version"] == str(__version__)


def test_write_config_refuses_other_settings_on_resume(tmp_path):
    folder = ResultsFolder(tmp_path)
    first = config_document("sweep", {"h1": {"label": "x", "swept": {}, "experiment": {"d_max": 25.0}}}, {"count": 1})
    folder.write_config(first, resume=False)
    # Other runs and execution with the same settings: fine on resume.
    more = {**first, "runs": {"count": 4}, "execution": {"workers": 2}}
    folder.write_config(more, resume=True)
    assert json.loads(folder.config_json.read_text())["runs"] == {"count": 4}
    other = config_document("sweep", {"h2": {"label": "x", "swept": {}, "experiment": {"d_max": 20.0}}}, {"count": 1})
    before = folder.config_json.read_bytes()
    with pytest.raises(ResultsInUseError, match="other settings") as refused:
        folder.write_config(other, resume=True)
    assert "--" not in str(refused.value).replace(str(tmp_path), "")
    assert folder.config_json.read_bytes() == before
    # Without resume the caller has already checked the folder holds no runs: it is replaced.
    folder.write_config(other, resume=False)
    assert "h2" in json.loads(folder.config_json.read_text())["settings"]


def test_atomic_write_leaves_no_temporary_file(tmp_path):
    target = tmp_path / "a.md"
    atomic_write(target, "one\n")
    atomic_write(target, "two\n")
    assert target.read_text() == "two\n"
    assert [p.name for p in tmp_path.iterdir()] == ["a.md"]


# ---------------------------------------------------------------------------------------------
# The folder


def test_a_file_in_place_of_the_folder_is_a_results_folder_error(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("keep me")
    for path, message in ((blocker, "is a file"), (blocker / "sub", "cannot write")):
        with pytest.raises(ResultsFolderError, match=message) as error:
            ResultsFolder(path)
        assert isinstance(error.value, OSError) and isinstance(error.value, UavcovError)
        assert not isinstance(error.value, ValueError)  # not bad input: the disk said no
        assert "--" not in str(error.value).replace(str(tmp_path), "")
    assert blocker.read_text() == "keep me"


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="needs file permissions that bind (not root)")
def test_a_folder_that_cannot_be_written_is_a_results_folder_error(tmp_path):
    locked = tmp_path / "ro"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        with pytest.raises(ResultsFolderError, match="cannot write"):
            ResultsFolder(locked)
    finally:
        locked.chmod(0o700)


def test_a_locked_folder_is_a_results_in_use_error(tmp_path):
    fcntl = pytest.importorskip("fcntl")
    folder = ResultsFolder(tmp_path)
    with folder.lock():
        with folder.lock():  # re-entrant in one process
            pass
        with ResultsFolder(tmp_path).lock():  # another object on the same folder: the same process
            pass
    other = os.open(tmp_path / ".uavcov.lock", os.O_RDWR)  # another open file description: another "process"
    try:
        fcntl.flock(other, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(ResultsInUseError, match="another uavcov process") as error, folder.lock():
            pass
        assert isinstance(error.value, ConfigError) and isinstance(error.value, InvalidInputError)
        assert "--" not in str(error.value).replace(str(tmp_path), "")
    finally:
        os.close(other)
    with folder.lock():  # free again
        pass


def test_drop_runs_rewrites_runs_csv_without_those_rows(tmp_path):
    folder = ResultsFolder(tmp_path)
    write_runs(folder.runs_csv, [row("a"), row("b"), row("c")])
    with open(folder.runs_csv, "a", encoding="utf-8") as handle:
        handle.write("d,table1")  # a cut line is not kept either
    folder.drop_runs({"b"})
    assert [r["run_id"] for r in folder.read_runs()] == ["a", "c"]
    assert folder.runs_csv.read_bytes().endswith(b"\n")
    assert folder.run_file("a") == tmp_path / "runs" / "a.npz"
    assert folder.write_text("x.md", "hi\n") == tmp_path / "x.md"
