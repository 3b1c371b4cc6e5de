"""Hostile input, round six, files: what got through the five rounds before in what is read and written.

Files that are no regular file (a FIFO blocked the reader forever, ``/dev/zero`` filled the
memory), empty paths read as the working directory, PLY and binary STL files that disagree with
their headers, run files and results folders whose records restate their contents wrongly (a
run listed twice, a column named twice, a JSON member named twice), writers that replaced a
device by a file or blocked on a FIFO, and names too long for any file system. Numbers and
arrays are in ``tests/test_hostile_round6.py``. Each class is tried with several hostile
values, each asserting the precise error of :mod:`uavcov.errors` and a message naming what is
wrong, or the right answer.
"""

from __future__ import annotations

import dataclasses
import json
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import uavcov
from refusals import refused
from uavcov.cli import EXIT_BAD_INPUT, main
from uavcov.errors import ConfigError, InvalidInputError, MeshError, ResultsFormatError
from uavcov.experiments import ResultsFolder, load_sweep_config, parse_sweep_config, read_runs
from uavcov.paper import EXPERIMENTS

HILLS = uavcov.gaussian_hills(size=30, spacing=1, n_hills=2, rng=0)
UAVS = np.array([[10.0, 10.0, 30.0], [20.0, 20.0, 30.0]])
HUGE = 10**400  # an int float() cannot hold


@pytest.fixture(scope="module")
def mission() -> Any:
    settings = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=2, cao=uavcov.CAOSettings(n_candidates=10))
    return uavcov.run_mission(HILLS, settings, n_threads=1, rng=0)


# ---------------------------------------------------------------------------------------------
# Files that are no regular file: a FIFO blocked the reader forever, /dev/zero never ended


def _outcome_in_a_child(code: str, cwd: Path) -> str:
    """What ``code`` prints in a child process (a blocking read would hang it: the timeout fails the test)."""
    child = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=cwd, capture_output=True, text=True, timeout=120, check=False)
    assert child.returncode == 0, child.stderr
    return child.stdout.strip()


_READ_A_FIFO = """
import uavcov, uavcov.sim, uavcov.terrain, uavcov.structures, uavcov.experiments, uavcov.paper
from uavcov.errors import UavcovError
try:
    print("answered", {call})
except UavcovError as exc:
    print(type(exc).__name__, exc)
"""


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
@pytest.mark.parametrize(
    "name, call, outcome",
    [
        ("fifo.obj", "uavcov.terrain.load_mesh('fifo.obj')", "MeshError"),
        ("fifo.ply", "uavcov.terrain.load_mesh('fifo.ply')", "MeshError"),
        ("fifo.obj", "uavcov.terrain.read_mesh_dem('fifo.obj', crs='EPSG:32617')", "MeshError"),
        ("fifo.stl", "uavcov.structures.load_structure('fifo.stl')", "MeshError"),
        ("fifo.toml", "uavcov.experiments.load_sweep_config('fifo.toml', bases=uavcov.paper.EXPERIMENTS)", "ConfigError"),
        ("fifo.npz", "uavcov.sim.is_flown_file('fifo.npz')", "answered False"),
    ],
)
def test_a_fifo_is_refused_without_blocking(tmp_path: Path, name: str, call: str, outcome: str) -> None:
    os.mkfifo(tmp_path / name)
    said = _outcome_in_a_child(_READ_A_FIFO.format(call=call), tmp_path)
    assert said.startswith(outcome), said
    if outcome != "answered False":
        assert "not a regular file" in said, said


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
@pytest.mark.parametrize("terrain", ['path = "fifo.npy"\nspacing = 1.0', 'path = "fifo.obj"', 'path = "fifo.ply"'])
def test_a_sweep_on_a_fifo_terrain_is_refused_without_blocking(tmp_path: Path, terrain: str) -> None:
    os.mkfifo(tmp_path / terrain.split('"')[1])
    (tmp_path / "sweep.toml").write_text(f'[terrain]\nkind = "file"\n{terrain}\n')
    said = _outcome_in_a_child(
        _READ_A_FIFO.format(call="uavcov.experiments.load_sweep_config('sweep.toml', bases=uavcov.paper.EXPERIMENTS)"), tmp_path
    )
    assert said.startswith("ConfigError") and "not a regular file" in said, said


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/null", "/dev/urandom"])
def test_a_device_is_no_sweep_file(device: str) -> None:
    if not os.path.exists(device):
        pytest.skip(f"no {device}")
    refused(ConfigError, "not a regular file", load_sweep_config, device, bases=EXPERIMENTS)


def test_a_sweep_file_of_megabytes_is_refused_before_it_is_read(tmp_path: Path) -> None:
    path = tmp_path / "big.toml"
    path.write_text("# padding\n" * 200_000)
    refused(ConfigError, "bytes, more than the 1,048,576", load_sweep_config, path, bases=EXPERIMENTS)


@pytest.mark.parametrize("kind", ["[]", '["hills"]', "{}", "{ a = 1 }", "1", "true"])
def test_a_terrain_kind_that_is_no_word_is_a_config_error(kind: str) -> None:
    import tomllib

    data = tomllib.loads(f"[terrain]\nkind = {kind}\n")
    refused(ConfigError, "terrain.kind: must be 'hills', 'buildings' or 'file'", parse_sweep_config, data, bases=EXPERIMENTS)


# ---------------------------------------------------------------------------------------------
# Empty paths: Path("") is the working directory


@pytest.mark.parametrize(
    "call",
    [
        uavcov.load_mission,
        ResultsFolder,
        read_runs,
        lambda p: load_sweep_config(p, bases=EXPERIMENTS),
        uavcov.terrain.load_mesh,
    ],
    ids=["load_mission", "ResultsFolder", "read_runs", "load_sweep_config", "load_mesh"],
)
@pytest.mark.parametrize("path, words", [("", "an empty path"), ("a\0b", "holds a NUL character"), (Path("x\0"), "holds a NUL")])
def test_an_empty_path_or_one_with_a_nul_is_refused(call: Any, path: Any, words: str, tmp_path: Path, monkeypatch: Any) -> None:
    monkeypatch.chdir(tmp_path)
    refused(InvalidInputError, words, call, path)
    assert list(tmp_path.iterdir()) == []  # nothing written in the working directory


@pytest.mark.parametrize(
    "argv",
    [
        ["demo", "--out", "", "--iterations", "1", "--no-plots"],
        ["reproduce", "table1", "--out", "", "--seeds", "0", "--team-sizes", "2", "--iterations", "1", "--no-plots"],
        ["sweep", ""],
        ["sweep", "x.toml", "--out", ""],
        ["plot", ""],
        ["view", "", "--out", "v.html"],
        ["view", "run.npz", "--out", ""],
        ["plan", "--sample", "--uavs", "2", "--d-max", "100", "--out", ""],
        ["plan", "", "--uavs", "2", "--d-max", "100"],
        ["plan", "--sample", "--aoi", "", "--uavs", "2", "--d-max", "100"],
        ["plan", "--structure", "", "--uavs", "2", "--d-max", "100", "--anchor", "0,0,0"],
    ],
)
def test_the_command_line_refuses_an_empty_path_and_writes_nothing(argv: list[str], tmp_path: Path, monkeypatch: Any, capsys: Any) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exit_info:  # argparse's error, on one line
        main(argv)
    code = exit_info.value.code
    err = capsys.readouterr().err.strip().splitlines()
    assert code == EXIT_BAD_INPUT and len(err) == 1 and "expected a file or folder name, got an empty one" in err[0], err
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------------------------------------
# PLY files shorter than their header, or whose header announces what no file of their size holds

_PLY_HEADER = (
    "ply\nformat ascii 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\nproperty float z\n"
    "element face {nf}\nproperty list uchar int vertex_indices\nend_header\n"
)
_SQUARE = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n"


@pytest.mark.parametrize(
    "nv, nf, body, words",
    [
        (4, 2, _SQUARE + "3 0 1 2\n", "announces 2 faces, 1 triangles were read"),
        (4, 3, _SQUARE + "3 0 1 2\n3 1 3 2\n", "announces 3 faces, 2 triangles were read"),
        (5, 2, _SQUARE + "3 0 1 2\n3 1 3 2\n", "announces 2 faces, 1 triangles were read"),  # a face line read as vertex 5
        (10**12, 1, _SQUARE + "3 0 1 2\n", "announces 1,000,000,000,000 vertex elements, more than the file's"),
        (4, 10**9, _SQUARE + "3 0 1 2\n", "announces 1,000,000,000 face elements"),
    ],
)
def test_a_ply_file_shorter_than_its_header_is_refused(tmp_path: Path, nv: int, nf: int, body: str, words: str) -> None:
    path = tmp_path / "mesh.ply"
    path.write_text(_PLY_HEADER.format(nv=nv, nf=nf) + body)
    refused(MeshError, words, uavcov.terrain.load_mesh, path)


def test_a_binary_ply_announcing_billions_of_vertices_is_refused_before_reading(tmp_path: Path) -> None:
    path = tmp_path / "mesh.ply"
    header = _PLY_HEADER.format(nv=4_000_000_000, nf=1).replace("ascii", "binary_little_endian")
    path.write_bytes(header.encode() + bytes(36))
    refused(MeshError, "announces 4,000,000,000 vertex elements", uavcov.terrain.load_mesh, path)


@pytest.mark.parametrize(
    "nf, faces, area",
    [(2, "3 0 1 2\n3 1 3 2\n", 1.0), (1, "4 0 1 3 2\n", 1.0), (1, "3 0 1 2\n", 0.5)],
)
def test_a_whole_ply_file_still_loads(tmp_path: Path, nf: int, faces: str, area: float) -> None:
    path = tmp_path / "mesh.ply"
    path.write_text(_PLY_HEADER.format(nv=4, nf=nf) + _SQUARE + faces)
    assert uavcov.terrain.load_mesh(path).terrain.area == pytest.approx(area)


# ---------------------------------------------------------------------------------------------
# A results folder whose records are no regular file: reading them blocked a resume forever

_RESUME_ON_A_SPECIAL_RECORD = """
import uavcov.experiments, uavcov.paper
from uavcov.errors import UavcovError
from uavcov.paper._jsonl import read_rows
try:
    {call}
    print("answered")
except UavcovError as exc:
    print(type(exc).__name__, exc)
"""


def _special(path: Path, kind: str) -> None:
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "device":
        path.symlink_to("/dev/zero")
    else:
        path.mkdir()


@pytest.mark.skipif(not hasattr(os, "mkfifo") or not os.path.exists("/dev/zero"), reason="needs FIFOs and /dev/zero")
@pytest.mark.parametrize("kind", ["fifo", "device", "folder"])
@pytest.mark.parametrize(
    "record, call, outcome",
    [
        ("config.json", "uavcov.experiments.ResultsFolder('.').check_config({'settings': {}}, resume=True)", "ResultsInUseError"),
        ("config.json", "uavcov.experiments.ResultsFolder('.').check_config({'settings': {}}, resume=False)", "ResultsInUseError"),
        ("rows.jsonl", "read_rows(__import__('pathlib').Path('rows.jsonl'))", "ResultsFormatError"),
    ],
)
def test_a_record_that_is_no_regular_file_is_refused_without_blocking(
    tmp_path: Path, kind: str, record: str, call: str, outcome: str
) -> None:
    _special(tmp_path / record, kind)
    said = _outcome_in_a_child(_RESUME_ON_A_SPECIAL_RECORD.format(call=call), tmp_path)
    assert said.startswith(outcome) and "not a regular file" in said, said


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
@pytest.mark.parametrize(
    "argv",
    [
        ["demo", "--out", "F", "--iterations", "1", "--no-plots", "--threads", "1"],
        ["reproduce", "table1", "--out", "F", "--seeds", "0", "--team-sizes", "2", "--iterations", "1", "--no-plots", "--workers", "1"],
        ["reproduce", "table1", "--resume", "--out", "F", "--seeds", "0", "--team-sizes", "2", "--iterations", "1", "--no-plots"],
    ],
)
def test_the_command_line_refuses_a_fifo_config_in_one_line(tmp_path: Path, argv: list[str]) -> None:
    (tmp_path / "F").mkdir()
    os.mkfifo(tmp_path / "F" / "config.json")
    done = subprocess.run([sys.executable, "-m", "uavcov", *argv], cwd=tmp_path, capture_output=True, text=True, timeout=120, check=False)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == EXIT_BAD_INPUT and len(lines) == 1 and "config.json" in lines[0], done.stderr
    left = sorted(p.name for p in (tmp_path / "F").iterdir() if p.name != ".uavcov.lock")  # the lock is taken first
    assert left == ["config.json"]  # no run written beside it


# ---------------------------------------------------------------------------------------------
# A run file whose header restates its trace wrongly, or says -inf seconds, was loaded as it said


@pytest.fixture(scope="module")
def run_arrays(tmp_path_factory: Any) -> dict[str, np.ndarray]:
    settings = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=3, cao=uavcov.CAOSettings(n_candidates=10))
    path = tmp_path_factory.mktemp("run") / "run.npz"
    uavcov.save_mission(uavcov.run_mission(HILLS, settings, n_threads=1, rng=0), path)
    with np.load(path, allow_pickle=False) as data:
        return dict(data)


def _tampered(run_arrays: dict[str, np.ndarray], tmp_path: Path, where: str, name: str, raw: str) -> Path:
    header = json.loads(str(run_arrays["header"]))
    header[where][name] = "__VALUE__"
    path = tmp_path / "tampered.npz"
    np.savez(path, **{**run_arrays, "header": np.array(json.dumps(header).replace('"__VALUE__"', raw))})
    return path


@pytest.mark.parametrize("raw", ["-1", "-1e400", "1e400", "NaN", '"5"', "[]", "null", "true", "1" + "0" * 400])
@pytest.mark.parametrize("where, name", [("scalars", "wall_time_s"), ("trace", "time_measure_s"), ("trace", "time_optimizer_s")])
def test_a_run_file_with_a_duration_that_is_none_is_refused(
    run_arrays: dict[str, np.ndarray], tmp_path: Path, where: str, name: str, raw: str
) -> None:
    path = _tampered(run_arrays, tmp_path, where, name, raw)
    refused(ResultsFormatError, f"{where}.{name} = .* is not (a duration|a number)", uavcov.load_mission, path)


@pytest.mark.parametrize(
    "name, raw",
    [
        ("best_iteration", "1000000000"),
        ("best_iteration", "-1"),
        ("best_iteration", "4"),  # the run has 4 configurations: 0..3
        ("best_value", "1e400"),
        ("best_value", "1.0"),
        ("best_value", "-0.0"),
        ("evaluations", "1000000000"),
        ("evaluations", "0"),
    ],
)
def test_a_run_file_whose_best_disagrees_with_its_trace_is_refused(
    run_arrays: dict[str, np.ndarray], tmp_path: Path, name: str, raw: str
) -> None:
    path = _tampered(run_arrays, tmp_path, "trace", name, raw)
    refused(ResultsFormatError, f"trace.{name} = .* disagrees with the trace's values stored beside it", uavcov.load_mission, path)


def test_a_run_file_whose_best_positions_are_elsewhere_is_refused(run_arrays: dict[str, np.ndarray], tmp_path: Path) -> None:
    path = tmp_path / "moved.npz"
    np.savez(path, **{**run_arrays, "trace_best_positions": run_arrays["trace_best_positions"] + 1.0})
    refused(ResultsFormatError, "trace_best_positions disagrees with the trajectory", uavcov.load_mission, path)


@pytest.mark.parametrize(
    "seed, error, words", [("-1", InvalidInputError, "seed must be >= 0"), (str(2**64), InvalidInputError, "below 2\\*\\*64")]
)
def test_a_run_file_with_a_cvt_seed_no_core_ran_is_refused(
    run_arrays: dict[str, np.ndarray], tmp_path: Path, seed: str, error: type[Exception], words: str
) -> None:
    path = _tampered(run_arrays, tmp_path, "cvt", "seed", seed)
    refused(ResultsFormatError, words, uavcov.load_mission, path)
    refused(error, words, dataclasses.replace, uavcov.load_mission(_tampered(run_arrays, tmp_path, "cvt", "seed", "7")).cvt, seed=int(seed))


def test_an_untampered_run_file_and_an_old_one_still_load(run_arrays: dict[str, np.ndarray], tmp_path: Path) -> None:
    path = _tampered(run_arrays, tmp_path, "scalars", "start_time_s", "NaN")  # an unknown start time is NaN
    assert uavcov.load_mission(path).trace.best_iteration == json.loads(str(run_arrays["header"]))["trace"]["best_iteration"]
    assert uavcov.load_mission(Path(__file__).parent / "data" / "mission_before_issue41.npz").trace.evaluations > 0


# ---------------------------------------------------------------------------------------------
# JSON objects that name a member twice: Python keeps the last, other readers the first

_RING = [[-84.27, 36.58], [-84.26, 36.58], [-84.26, 36.59], [-84.27, 36.58]]
_OTHER_RING = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 0.0]]


@pytest.mark.parametrize(
    "text, name",
    [
        (f'{{"type": "Polygon", "coordinates": {[_OTHER_RING]}, "coordinates": {[_RING]}}}', "coordinates"),
        (f'{{"type": "Point", "type": "Polygon", "coordinates": {[_RING]}}}', "type"),
        (f'{{"type": "Feature", "geometry": {{"type": "Polygon", "coordinates": {[_RING]}, "coordinates": []}}}}', "coordinates"),
        ('{"type": "FeatureCollection", "features": [], "features": [{"type": "Feature", "geometry": null}]}', "features"),
    ],
)
def test_an_area_naming_a_member_twice_is_refused(tmp_path: Path, text: str, name: str) -> None:
    path = tmp_path / "area.geojson"
    path.write_text(text)
    refused(InvalidInputError, f"the name '{name}' appears twice in one object", uavcov.field.read_area, path)


def test_strict_json_files_refuse_a_name_given_twice_and_read_the_rest(tmp_path: Path) -> None:
    from uavcov.field._strict_json import read_json

    path = tmp_path / "plan.json"
    path.write_text('{"a": 1, "b": {"c": 2, "c": 3}}')
    refused(InvalidInputError, "the name 'c' appears twice", read_json, path)
    path.write_text('{"a": 1, "b": {"c": 2, "d": [{"c": 3}]}}')  # the same name in two objects is no repeat
    assert read_json(path) == {"a": 1, "b": {"c": 2, "d": [{"c": 3}]}}
    path.write_text(json.dumps({"type": "Polygon", "coordinates": [_RING]}))
    assert uavcov.field.read_area(path).polygons[0][0].shape == (3, 2)


_RUNS_HEADER = (
    "run_id,experiment,init,n_uavs,seed,sensing_range,iterations,initial_coverage,max_coverage,final_coverage,best_iteration,"
    "iterations_to_95,evaluations,wall_time_s,time_measure_s,time_optimizer_s,time_feasibility_s,settings_hash,error"
)
_RUNS_ROW = "r,table1,cvt,2,0,25.0,1,0.3,0.3,0.3,0,0,2,0.1,0.01,0.01,0.01,abc,"


@pytest.mark.parametrize("extra, repeated", [(",d_max,d_max", "d_max"), (",a,b,a", "a"), (",seed", "seed")])
def test_a_runs_file_naming_a_column_twice_is_refused(tmp_path: Path, extra: str, repeated: str) -> None:
    path = tmp_path / "runs.csv"
    cells = ",1" * extra.count(",")
    path.write_text(_RUNS_HEADER + extra + "\n" + _RUNS_ROW + cells + "\n")
    refused(ResultsFormatError, f"names the column\\(s\\) {repeated} twice in its header", read_runs, path)
    path.write_text(_RUNS_HEADER + ",d_max\n" + _RUNS_ROW + ",20.0\n")
    assert read_runs(path)[0]["d_max"] == "20.0"


# ---------------------------------------------------------------------------------------------
# Writers: a device, FIFO or folder where the file goes (as root, the rename replaced /dev/null
# by a file), a file where its folder goes, a format matplotlib does not write


def _stand_in(tmp_path: Path, what: str) -> Path:
    if what == "fifo":
        os.mkfifo(tmp_path / "target.png")
        return tmp_path / "target.png"
    if what == "folder":
        (tmp_path / "target.png").mkdir()
        return tmp_path / "target.png"
    if what == "link to a device":
        (tmp_path / "target.png").symlink_to("/dev/null")
        return tmp_path / "target.png"
    return Path("/dev/null")


@pytest.mark.skipif(not hasattr(os, "mkfifo") or not os.path.exists("/dev/null"), reason="needs FIFOs and /dev/null")
@pytest.mark.parametrize(
    "what, words", [("fifo", "a FIFO, socket or device"), ("folder", "a folder"), ("device", "a FIFO, socket or device")]
)
@pytest.mark.parametrize("writer", ["save_mission", "plot_coverage_map", "write_view", "ply"])
def test_a_writer_refuses_what_is_no_file_where_its_file_goes(mission: Any, tmp_path: Path, what: str, words: str, writer: str) -> None:
    from uavcov.errors import ResultsFolderError

    target = _stand_in(tmp_path, what)
    calls = {
        "save_mission": lambda: uavcov.save_mission(mission, target),
        "plot_coverage_map": lambda: pytest.importorskip("uavcov.plotting").plot_coverage_map(mission, out=target),
        "write_view": lambda: pytest.importorskip("uavcov.plotting").write_view(mission, target),
        "ply": lambda: pytest.importorskip("uavcov.plotting").plot_point_cloud(mission, ply=target),
    }
    if writer != "save_mission":
        pytest.importorskip("matplotlib" if writer != "write_view" else "plotly")
    refused(ResultsFolderError, f"cannot write {re.escape(str(target))}: {words} stands there, not a file", calls[writer])
    assert os.path.exists("/dev/null") and not Path("/dev/null").is_file()  # the device is still one


@pytest.mark.skipif(not os.path.exists("/dev/null"), reason="needs /dev/null")
def test_a_link_where_the_file_goes_is_replaced_not_followed(mission: Any, tmp_path: Path) -> None:
    target = _stand_in(tmp_path, "link to a device")
    uavcov.save_mission(mission, target)
    assert target.is_file() and not target.is_symlink() and not Path("/dev/null").is_file()
    assert uavcov.load_mission(target).seed == mission.seed


@pytest.mark.parametrize("writer", ["save_mission", "plot_coverage_map"])
@pytest.mark.parametrize("below", ["afile/x.png", "afile/deeper/x.png"])
def test_a_writer_whose_folder_is_a_file_says_so(mission: Any, tmp_path: Path, writer: str, below: str) -> None:
    from uavcov.errors import ResultsFolderError

    (tmp_path / "afile").write_text("")
    target = tmp_path / below
    call = {"save_mission": uavcov.save_mission, "plot_coverage_map": None}[writer]
    if call is None:
        plotting = pytest.importorskip("uavcov.plotting")
        pytest.importorskip("matplotlib")
        refused(ResultsFolderError, "cannot make the folder of", plotting.plot_coverage_map, mission, out=target)
    else:
        refused(ResultsFolderError, "cannot make the folder of", call, mission, target)


@pytest.mark.parametrize("name", ["figure.npz", "figure.txt", "figure.html", "figure.p_n_g"])
def test_a_figure_refuses_a_format_matplotlib_does_not_write(mission: Any, tmp_path: Path, name: str) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_coverage_map

    refused(InvalidInputError, "names no picture format matplotlib writes", plot_coverage_map, mission, out=tmp_path / name)
    assert list(tmp_path.iterdir()) == []
    assert plot_coverage_map(mission, out=tmp_path / "figure.PNG") is not None and (tmp_path / "figure.PNG").is_file()


# ---------------------------------------------------------------------------------------------
# A resumed folder whose runs.csv holds one run twice: the resume kept one row and ignored the other


@pytest.fixture(scope="module")
def table1_folder(tmp_path_factory: Any) -> Path:
    out = tmp_path_factory.mktemp("table1") / "out"
    argv = ["reproduce", "table1", "--seeds", "0", "--team-sizes", "2", "--starts", "cvt,random", "--iterations", "1"]
    assert main([*argv, "--no-plots", "--workers", "1", "--threads", "1", "--no-progress", "--out", str(out)]) == 0
    return out


@pytest.mark.parametrize("line, change", [(1, None), (2, None), (1, ("0.3", "0.9"))])
def test_a_resume_refuses_a_runs_file_that_holds_one_run_twice(
    table1_folder: Path, tmp_path: Path, capsys: Any, line: int, change: tuple[str, str] | None
) -> None:
    import shutil

    folder = tmp_path / "out"
    shutil.copytree(table1_folder, folder)
    lines = (folder / "runs.csv").read_text().splitlines(keepends=True)
    repeated = lines[line] if change is None else lines[line].replace(*change)
    (folder / "runs.csv").write_text("".join([*lines, repeated]))
    argv = ["reproduce", "table1", "--resume", "--seeds", "0", "--team-sizes", "2", "--starts", "cvt,random", "--iterations", "1"]
    capsys.readouterr()
    code = main([*argv, "--no-plots", "--workers", "1", "--threads", "1", "--no-progress", "--out", str(folder)])
    err = capsys.readouterr().err.strip().splitlines()
    run_id = lines[line].split(",")[0]
    assert code == EXIT_BAD_INPUT and len(err) == 1 and f"holds the run {run_id} twice" in err[0], err
    (folder / "runs.csv").write_text("".join(lines))  # whole again, it resumes: nothing to run
    assert main([*argv, "--no-plots", "--workers", "1", "--threads", "1", "--no-progress", "--out", str(folder)]) == 0


@pytest.mark.parametrize("out", ["", "a\0b"])
def test_figures_refuse_an_empty_output_path_and_write_nothing_in_the_working_directory(
    mission: Any, table1_folder: Path, tmp_path: Path, monkeypatch: Any, out: str
) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_coverage_map, plot_directory

    monkeypatch.chdir(tmp_path)
    words = "out is an empty path" if not out else "out holds a NUL character"
    refused(InvalidInputError, words, plot_directory, table1_folder, out=out, animation=False, max_runs=0)
    refused(InvalidInputError, words, plot_coverage_map, mission, out=out)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("out, words", [("", "out is an empty path"), ("x\0y", "out holds a NUL character")])
def test_a_plan_folder_is_never_the_working_directory_by_an_empty_name(tmp_path: Path, monkeypatch: Any, out: str, words: str) -> None:
    from uavcov.field import check_plan_folder
    from uavcov.field._results_folder import write_files

    monkeypatch.chdir(tmp_path)
    refused(InvalidInputError, words, check_plan_folder, out)
    refused(InvalidInputError, words, write_files, {"plan.json": b"{}"}, out)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("label", ["x" * 300, "é" * 120, "a" * 230])
def test_a_label_whose_run_files_no_file_system_holds_is_refused_before_any_run(label: str) -> None:
    from uavcov.experiments import RunSpec, experiment_specs
    from uavcov.paper import TABLE1

    refused(InvalidInputError, "past the 255 bytes a file name may have", RunSpec, TABLE1, 0, 2, "cvt", label=label)
    refused(InvalidInputError, "past the 255 bytes", experiment_specs, TABLE1, seeds=[0], team_sizes=[2], starts=["cvt"], label=label)


def test_a_long_label_that_fits_is_kept() -> None:
    from uavcov.experiments import RunSpec
    from uavcov.paper import TABLE1

    spec = RunSpec(TABLE1, 0, 2, "cvt", label="a" * 200)
    assert len((spec.run_id + ".npz").encode()) <= 255 and spec.run_id.startswith("a" * 200)


def test_a_sweep_named_beyond_a_file_name_is_refused_before_its_folder_is_made(tmp_path: Path, capsys: Any) -> None:
    config = tmp_path / "long.toml"
    config.write_text(f'name = "{"n" * 260}"\nbase = "table1"\nseeds = [0]\nteam_sizes = [2]\nstarts = ["cvt"]\niterations = 1\n')
    code = main(["sweep", str(config), "--out", str(tmp_path / "out"), "--workers", "1", "--threads", "1", "--no-progress"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == EXIT_BAD_INPUT and len(err) == 1 and "255 bytes a file name may have" in err[0], err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", ["p" * 250, "é" * 127, "q" * 255])
def test_a_plan_folder_named_near_the_limit_is_written_and_replaced(tmp_path: Path, name: str) -> None:
    from uavcov.field._results_folder import write_files

    out = tmp_path / name
    assert [p.name for p in write_files({"plan.json": b"{}"}, out)] == ["plan.json"]
    assert [p.name for p in write_files({"plan.json": b'{"a": 1}'}, out)] == ["plan.json"]  # replaced as a whole
    assert (out / "plan.json").read_bytes() == b'{"a": 1}' and sorted(p.name for p in tmp_path.iterdir()) == [name]


def _binary_stl(count: int, triangles: int, tail: bytes = b"") -> bytes:
    import struct

    triangle = struct.pack("<12f", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0) + b"\0\0"
    return b"\0" * 80 + struct.pack("<I", count) + triangle * triangles + tail


@pytest.mark.parametrize(
    "data, words",
    [
        (_binary_stl(2, 1), "announces 2 triangles \\(184 bytes\\), the file has 134 bytes"),
        (_binary_stl(1, 3), "announces 1 triangles \\(134 bytes\\), the file has 234 bytes"),
        (_binary_stl(2**32 - 1, 1), "announces 4,294,967,295 triangles"),
        (_binary_stl(0, 1), "announces 0 triangles"),
        (_binary_stl(1, 1, b"\0" * 20), "the file has 154 bytes"),
    ],
)
def test_a_binary_stl_whose_size_disagrees_with_its_count_is_refused(tmp_path: Path, data: bytes, words: str) -> None:
    path = tmp_path / "mesh.stl"
    path.write_bytes(data)
    refused(MeshError, words, uavcov.terrain.load_mesh, path)


def test_a_whole_binary_stl_and_one_whose_header_says_solid_still_load(tmp_path: Path) -> None:
    path = tmp_path / "mesh.stl"
    path.write_bytes(_binary_stl(1, 1))
    assert uavcov.terrain.load_mesh(path).terrain.area == pytest.approx(0.5)
    path.write_bytes(b"solid but binary" + _binary_stl(1, 1)[16:])  # some exporters write "solid" in a binary header
    assert uavcov.terrain.load_mesh(path).terrain.area == pytest.approx(0.5)
