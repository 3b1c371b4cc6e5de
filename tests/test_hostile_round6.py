"""Hostile input, round six: what got through the five rounds before.

Numbers that ``float()`` cannot hold (an int or Fraction past 1.8e308) or that numpy counts as
integers without being numbers of anything (``np.timedelta64``), masked arrays read as the data
under their mask, unsigned indices that wrapped to negative ones, files that are no regular
file (a FIFO blocked the reader forever, ``/dev/zero`` filled the memory), empty paths read as
the working directory, PLY files shorter than their header says, and counts that overflowed
the core (a CVT ``window``, a subnormal ``move_step``). Each class is tried with several hostile
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
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import uavcov
from refusals import refused
from uavcov.cli import EXIT_BAD_INPUT, main
from uavcov.errors import ConfigError, InvalidInputError, InvalidTypeError, MeshError, ResultsFormatError
from uavcov.experiments import ResultsFolder, load_sweep_config, parse_sweep_config, read_runs
from uavcov.limits import Constraints, feasibility
from uavcov.paper import EXPERIMENTS

HILLS = uavcov.gaussian_hills(size=30, spacing=1, n_hills=2, rng=0)
UAVS = np.array([[10.0, 10.0, 30.0], [20.0, 20.0, 30.0]])
HUGE = 10**400  # an int float() cannot hold

# ---------------------------------------------------------------------------------------------
# Numbers float() cannot hold: an OverflowError leaked from every float setting


SETTINGS = [
    (uavcov.MissionSettings, {"n_uavs": 2, "d_max": 10.0}, "d_max"),
    (uavcov.PlanSettings, {"n_uavs": 2, "d_max": 10.0}, "h_min"),
    (uavcov.PlanSettings, {"n_uavs": 2, "d_max": 10.0}, "cruise_speed"),
    (uavcov.CVTSettings, {}, "tol"),
    (uavcov.CVTSettings, {}, "normal_weight"),
    (uavcov.CAOSettings, {}, "alpha0"),
    (uavcov.Constraints, {}, "z_max"),
    (uavcov.StartSettings, {}, "altitude"),
    (uavcov.EscapeSettings, {}, "hop"),
]


@pytest.mark.parametrize("value", [HUGE, -HUGE, Fraction(HUGE), Fraction(-HUGE, 3)])
@pytest.mark.parametrize("cls, base, field", SETTINGS, ids=[f"{c.__name__}.{f}" for c, _, f in SETTINGS])
def test_a_number_beyond_the_largest_float_is_refused_not_an_overflow(cls: Any, base: dict[str, Any], field: str, value: Any) -> None:
    refused(InvalidInputError, f"{field} must be finite, got a number beyond the largest float", cls, **{**base, field: value})


@pytest.mark.parametrize("value", [HUGE, Fraction(HUGE)])
@pytest.mark.parametrize("cls, base, field", SETTINGS[:4], ids=[f"{c.__name__}.{f}" for c, _, f in SETTINGS[:4]])
def test_replace_checks_again_what_the_constructor_checks(cls: Any, base: dict[str, Any], field: str, value: Any) -> None:
    settings = cls(**base)
    refused(InvalidInputError, f"{field} must be finite", dataclasses.replace, settings, **{field: value})


@pytest.mark.parametrize(
    "call",
    [
        lambda v: uavcov.Terrain.from_grid(np.zeros((4, 4)), spacing=v),
        lambda v: uavcov.Visibility(HILLS, v, n_threads=1),
        lambda v: uavcov.gaussian_hills(size=v, spacing=1, n_hills=2, rng=0),
    ],
    ids=["from_grid-spacing", "Visibility-d_max", "gaussian_hills-size"],
)
@pytest.mark.parametrize("value", [HUGE, -HUGE, 3 * HUGE])
def test_functions_refuse_a_number_beyond_the_largest_float(call: Any, value: Any) -> None:
    refused(InvalidInputError, "beyond the largest float", call, value)


def test_exact_fractions_and_numpy_scalars_within_range_keep_their_value() -> None:
    assert uavcov.CVTSettings(tol=Fraction(1, 4)).tol == 0.25
    assert uavcov.MissionSettings(n_uavs=np.int64(3), d_max=np.float32(12.5)).d_max == 12.5
    assert uavcov.MissionSettings(n_uavs=np.uint8(3), d_max=10**20).d_max == 1e20


# ---------------------------------------------------------------------------------------------
# np.timedelta64: an integer to numpy, not a count or a length


@pytest.mark.parametrize(
    "make, error, words",
    [
        (lambda td: uavcov.MissionSettings(n_uavs=td, d_max=10.0), InvalidTypeError, "n_uavs must be an integer, got timedelta64"),
        (lambda td: uavcov.MissionSettings(n_uavs=2, d_max=td), InvalidTypeError, "d_max must be a real number, got timedelta64"),
        (lambda td: uavcov.CVTSettings(window=td), InvalidTypeError, "window must be an integer"),
        (lambda td: uavcov.CAOSettings(n_candidates=td), InvalidTypeError, "n_candidates must be an integer"),
        (lambda td: uavcov.PlanSettings(n_uavs=2, d_max=10.0, hold_s=td), InvalidTypeError, "hold_s must be a real number"),
        (lambda td: uavcov.Terrain.from_grid(np.zeros((4, 4)), spacing=td), InvalidTypeError, "spacing must be a real number"),
    ],
)
@pytest.mark.parametrize("td", [np.timedelta64(5), np.timedelta64(5, "s"), np.timedelta64(1, "D")])
def test_a_timedelta_is_no_number(make: Any, error: type[Exception], words: str, td: Any) -> None:
    refused(error, words, make, td)


@pytest.mark.parametrize("unit", ["s", "ms", "D"])
@pytest.mark.parametrize(
    "make, words",
    [
        (lambda a: uavcov.Terrain(np.eye(3), a.reshape(1, 3)), "faces must hold integers, got dtype timedelta64"),
        (lambda a: uavcov.Terrain.from_grid(np.resize(a, (3, 3)), spacing=1.0), "z must hold real numbers, got dtype timedelta64"),
        (lambda a: uavcov.Terrain.from_grid(np.zeros((4, 4)), spacing=1.0, origin=a[:2]), "origin must be a real number"),
        (lambda a: uavcov.Visibility(HILLS, 10.0, n_threads=1).coverage(np.resize(a, (2, 3))), "uavs must hold real numbers"),
    ],
)
def test_timedelta_arrays_are_refused_as_numbers_and_indices(make: Any, words: str, unit: str) -> None:
    refused(InvalidTypeError, words, make, np.array([0, 1, 2], dtype=f"m8[{unit}]"))


# ---------------------------------------------------------------------------------------------
# Masked arrays: np.asarray reads the data under the mask


@pytest.mark.parametrize(
    "mask",
    [[[0, 0, 1], [0, 0, 0]], [[1, 0, 0], [0, 0, 0]], [[1, 1, 1], [1, 1, 1]]],
)
def test_masked_positions_are_refused_not_read_under_their_mask(mask: Any) -> None:
    visibility = uavcov.Visibility(HILLS, 10.0, n_threads=1)
    masked = np.ma.masked_array(UAVS, mask=mask)
    refused(InvalidInputError, "uavs has masked entries", visibility.coverage, masked)
    # a mesh's masked vertices are no-data, which a mesh cannot have
    refused(MeshError, "vertices contain NaN", uavcov.Terrain, np.ma.masked_array(np.eye(3), mask=np.eye(3)), [[0, 1, 2]])


@pytest.mark.parametrize("masked_value", [0.0, 1e300, -7.0])
def test_masked_heights_of_a_grid_are_nodata_whatever_the_data_under_them(masked_value: float) -> None:
    heights = np.zeros((5, 5))
    heights[2, 2] = masked_value
    mask = np.zeros((5, 5), bool)
    mask[2, 2] = True
    with_nan = heights.copy()
    with_nan[2, 2] = np.nan
    masked = uavcov.Terrain.from_grid(np.ma.masked_array(heights, mask=mask), spacing=1.0)
    nodata = uavcov.Terrain.from_grid(with_nan, spacing=1.0)
    assert masked.area == nodata.area == 13.0  # the 16 unit squares less the 4 round the hole, less 0.5 for each of 6 triangles
    np.testing.assert_array_equal(masked.vertices, nodata.vertices)
    np.testing.assert_array_equal(masked.faces, nodata.faces)


def test_a_mask_that_hides_nothing_reads_as_its_data() -> None:
    visibility = uavcov.Visibility(HILLS, 10.0, n_threads=1)
    assert visibility.coverage(np.ma.masked_array(UAVS, mask=False)) == visibility.coverage(UAVS)


@pytest.mark.parametrize("mask", [[False, True], [True, False], [True, True]])
def test_masked_flags_and_indices_are_refused(mask: list[bool]) -> None:
    from uavcov._validate import as_bool_array, as_index_array

    refused(InvalidInputError, "seen has masked entries", as_bool_array, np.ma.masked_array([True, False], mask=mask), "seen", 2)
    refused(InvalidInputError, "faces has masked entries", as_index_array, np.ma.masked_array([[0, 1]], mask=[mask]), "faces", columns=2)


# ---------------------------------------------------------------------------------------------
# Other array-likes that are not plain float64 arrays: the same answer as the plain array


@pytest.mark.parametrize(
    "convert",
    [
        np.matrix,
        lambda a: a.astype(">f8"),
        lambda a: a.astype(np.float32),
        lambda a: a.astype(np.longdouble),
        np.asfortranarray,
        lambda a: np.repeat(a, 2, axis=1)[:, ::2],
        lambda a: a[::-1][::-1],
        lambda a: a.tolist(),
        lambda a: tuple(map(tuple, a)),
    ],
    ids=["matrix", "big-endian", "float32", "longdouble", "fortran", "strided", "negative-stride", "list", "tuple"],
)
@pytest.mark.filterwarnings("ignore:the matrix subclass:PendingDeprecationWarning")
def test_array_likes_of_real_numbers_give_the_plain_arrays_answer(convert: Any) -> None:
    visibility = uavcov.Visibility(HILLS, 10.0, n_threads=1)
    assert visibility.coverage(convert(UAVS)) == visibility.coverage(UAVS)


@pytest.mark.parametrize(
    "value, error, words",
    [
        (np.array([[0, 1, 2**64 - 1]], dtype=np.uint64), InvalidInputError, "faces holds an index beyond int64"),
        (np.array([[0, 1, 2**63]], dtype=np.uint64), InvalidInputError, "faces holds an index beyond int64"),
        (np.array([[0, 1, 2]], dtype="m8"), InvalidTypeError, "faces must hold integers"),
        (np.array([[True, False, True]]), InvalidTypeError, "faces must hold integers"),
    ],
)
def test_face_indices_that_int64_would_wrap_are_refused(value: np.ndarray, error: type[Exception], words: str) -> None:
    refused(error, words, uavcov.Terrain, np.eye(3), value)


def test_unsigned_face_indices_within_int64_are_read() -> None:
    faces = np.array([[0, 1, 2]], dtype=np.uint64)
    assert uavcov.Terrain(np.eye(3), faces).area == uavcov.Terrain(np.eye(3), [[0, 1, 2]]).area


# ---------------------------------------------------------------------------------------------
# Counts that overflowed the core


@pytest.mark.parametrize("window", [2**64, 10**60, 10**6 + 1])
def test_a_cvt_window_beyond_the_iteration_limit_is_refused(window: int) -> None:
    refused(InvalidInputError, "window must be at most 1,000,000", uavcov.CVTSettings, window=window)
    refused(InvalidInputError, "window must be at most", dataclasses.replace, uavcov.CVTSettings(), window=window)


@pytest.mark.parametrize("move_step", [5e-324, 1e-300, 1e-310])
def test_a_subnormal_move_step_is_refused_before_its_sample_count_overflows(move_step: float) -> None:
    limits = Constraints(move_step=move_step, check_moves=True).resolve(HILLS)
    check = feasibility(limits, HILLS, n_threads=1)
    refused(InvalidInputError, "is over 10000 samples", check, UAVS, UAVS[None] + 1.0)


def test_a_fine_move_step_still_checks_moves() -> None:
    limits = Constraints(move_step=0.5, check_moves=True).resolve(HILLS)
    assert feasibility(limits, HILLS, n_threads=1)(UAVS, UAVS[None] + 1.0).tolist() == [True]


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
# Subnormal settings whose derived constants underflowed: the error named the constant, not the setting


@pytest.mark.parametrize("d_max", [5e-324, 1e-323, 1.7e308])
def test_a_range_that_leaves_cao_no_first_step_is_refused_by_its_name(d_max: float) -> None:
    from uavcov.optim import cao_preset

    refused(InvalidInputError, re.escape(f"d_max = {d_max} m gives CAO no first step"), cao_preset, "plateau", d_max)
    if d_max < 1.0:
        refused(InvalidInputError, "d_max = .* gives CAO no first step", uavcov.PlanSettings, n_uavs=2, d_max=d_max)


def test_a_tiny_range_keeps_its_first_step() -> None:
    from uavcov.optim import cao_preset

    assert cao_preset("plateau", 1e-300).alpha0 == pytest.approx(2e-301)


@pytest.mark.parametrize("fov", [5e-324, 1e-323, 2e-323])
@pytest.mark.parametrize("name", ["hfov_deg", "vfov_deg"])
def test_a_field_of_view_too_narrow_for_its_sensor_is_refused_by_its_name(fov: float, name: str) -> None:
    angles = {"hfov_deg": 60.0, "vfov_deg": 45.0, name: fov}
    refused(InvalidInputError, f"{name} must be in \\(0, 180\\) degrees, got .*, too narrow", uavcov.Camera.from_fov, **angles)


def test_a_narrow_field_of_view_is_still_a_camera() -> None:
    assert uavcov.Camera.from_fov(1e-6, 45.0).hfov_deg == pytest.approx(1e-6)


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
# A .plan's numbers reach the vehicle as 32-bit floats: 1e308 s was an endless hold, 5e-324 m/s none


@pytest.mark.parametrize("field", ["hold_s", "cruise_speed", "hover_speed"])
@pytest.mark.parametrize("value", [1e308, 3.5e38, 5e-324, 1e-40])
def test_a_plan_refuses_a_mission_item_value_float32_cannot_carry(field: str, value: float) -> None:
    refused(
        InvalidInputError,
        re.escape(f"{field} = {value} is beyond what a mission item's 32-bit float holds"),
        uavcov.PlanSettings,
        n_uavs=2,
        d_max=10.0,
        **{field: value},
    )


@pytest.mark.parametrize("hold, kept", [(0.0, 0.0), (-0.0, 0.0), (1e-30, 1e-30), (3e38, 3e38), (60, 60.0)])
def test_a_hold_float32_carries_is_kept(hold: float, kept: float) -> None:
    settings = uavcov.PlanSettings(n_uavs=2, d_max=10.0, hold_s=hold)
    assert settings.hold_s == kept and str(settings.hold_s) == str(kept)


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
# Found by the fuzz harness's new values (scripts/fuzz_public_api.py --values "10**400;timedelta64;...")


@pytest.mark.parametrize("n", [HUGE, 10**20, 1001])
def test_check_team_refuses_a_team_beyond_the_limit_before_its_volume_overflows(n: int) -> None:
    limits = Constraints().resolve(HILLS)
    refused(InvalidInputError, "number of UAVs must be at most 1,000", limits.check_team, n, HILLS)


@pytest.mark.parametrize(
    "field, value, words",
    [
        ("longitude", HUGE, "anchor longitude must be finite and within"),
        ("latitude", -HUGE, "anchor latitude must be finite and within"),
        ("height", HUGE, "anchor height must be finite and within"),
        ("longitude", np.timedelta64(5, "s"), "anchor longitude must be a number"),
        ("height", np.timedelta64(1, "D"), "anchor height must be a number"),
    ],
)
def test_a_geo_anchor_refuses_numbers_float_cannot_hold_and_timedeltas(field: str, value: Any, words: str) -> None:
    refused(InvalidInputError, words, uavcov.field.GeoAnchor, **{"longitude": 5.0, "latitude": 45.0, "height": 0.0, field: value})


@pytest.mark.parametrize("c", [np.timedelta64(0), np.timedelta64(1, "s"), True, 1.0])
def test_a_candidate_index_is_an_integer_not_a_timedelta(c: Any) -> None:
    from uavcov.cover import CoverageProblem

    visibility = uavcov.Visibility(HILLS, 10.0, n_threads=1)
    problem = CoverageProblem(visibility, UAVS, n_threads=1)
    refused(InvalidTypeError, "c must be an int", problem.seen, c)
    assert problem.seen(np.int64(1)).shape == problem.seen(1).shape


@pytest.fixture(scope="module")
def mission() -> Any:
    settings = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=2, cao=uavcov.CAOSettings(n_candidates=10))
    return uavcov.run_mission(HILLS, settings, n_threads=1, rng=0)


@pytest.mark.parametrize("max_polygons", [HUGE, 10**9, 2**64])
def test_a_figure_refuses_a_polygon_count_beyond_the_limit(mission: Any, max_polygons: int) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_cvt

    refused(InvalidInputError, "max_polygons must be at most 100,000,000", plot_cvt, mission, max_polygons=max_polygons)


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"max_frames": np.timedelta64(5)}, "max_frames must be an integer >= 2"),
        ({"max_vertices": np.timedelta64(100, "s")}, "max_vertices must be an integer >= 16"),
        ({"max_frames": True}, "max_frames must be an integer >= 2"),
    ],
)
def test_a_view_counts_frames_and_vertices_in_integers(mission: Any, kwargs: dict[str, Any], words: str) -> None:
    pytest.importorskip("plotly")
    from uavcov.plotting import view

    refused(InvalidInputError, words, view, mission, **kwargs)


@pytest.mark.parametrize("configuration", [np.timedelta64(1), np.timedelta64(0, "s")])
def test_a_coverage_map_takes_an_iteration_not_a_timedelta(mission: Any, configuration: Any) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_coverage_map

    with pytest.raises(uavcov.errors.UavcovError) as caught:
        plot_coverage_map(mission, configuration=configuration)
    assert "configuration" in str(caught.value)


@pytest.mark.parametrize("trajectory", [HUGE, Fraction(HUGE), [[[HUGE, 0, 0]]]])
def test_a_trajectory_beyond_the_largest_float_is_no_trajectory(trajectory: Any) -> None:
    from uavcov.plotting._inputs import _trajectory

    refused(ResultsFormatError, "the trajectory is not numeric", _trajectory, trajectory)


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


@pytest.mark.parametrize(
    "obj, changes, words",
    [
        (uavcov.MissionSettings(n_uavs=2, d_max=10.0), {5: 1}, "a field name must be a string"),
        (uavcov.MissionSettings(n_uavs=2, d_max=10.0), {None: 1}, "a field name must be a string"),
        (uavcov.MissionSettings(n_uavs=2, d_max=10.0), {b"start.kind": "random"}, "a field name must be a string"),
        (uavcov.MissionSettings(n_uavs=2, d_max=10.0), [("start.kind", "random")], "changes must be a mapping"),
        (uavcov.MissionSettings, {"n_uavs": 3}, "changes a settings dataclass"),
        ({"n_uavs": 2}, {"n_uavs": 3}, "changes a settings dataclass"),
    ],
)
def test_nested_replace_takes_a_dataclass_and_names_that_are_strings(obj: Any, changes: Any, words: str) -> None:
    from uavcov.settings import nested_replace

    refused(InvalidTypeError, words, nested_replace, obj, changes)


def test_nested_replace_still_reaches_nested_fields() -> None:
    from uavcov.settings import nested_replace

    changed = nested_replace(uavcov.MissionSettings(n_uavs=2, d_max=10.0), {"start.kind": "random", "cao__history": 3})
    assert (changed.start.kind, changed.cao.history) == ("random", 3)


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

    refused(InvalidInputError, "would pass the 255 bytes a file name may have", RunSpec, TABLE1, 0, 2, "cvt", label=label)
    refused(InvalidInputError, "would pass the 255 bytes", experiment_specs, TABLE1, seeds=[0], team_sizes=[2], starts=["cvt"], label=label)


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


@pytest.mark.parametrize("pixels", [HUGE, 2**64, 1_000_001])
@pytest.mark.parametrize("name", ["image_width_px", "image_height_px"])
def test_a_camera_of_more_pixels_than_any_is_refused(pixels: int, name: str) -> None:
    sizes = {"image_width_px": 4000, "image_height_px": 3000, name: pixels}
    refused(InvalidInputError, f"{name} must be at most 1,000,000 pixels", uavcov.Camera, 13.2, 8.8, 8.8, **sizes)
    refused(InvalidInputError, f"{name} must be at most 1,000,000 pixels", uavcov.Camera.from_fov, 60.0, 45.0, **sizes)


def test_a_camera_of_a_million_pixels_a_side_is_one() -> None:
    camera = uavcov.Camera(13.2, 8.8, 8.8, 1_000_000, 1_000_000)
    assert camera.gsd_m(10.0) == pytest.approx(10.0 * 13.2 / (8.8 * 1_000_000))


@pytest.mark.parametrize("max_sweeps", [HUGE, 2**64, 10**6 + 1])
def test_closest_admissible_refuses_sweeps_beyond_the_iteration_limit(max_sweeps: int) -> None:
    from uavcov.limits import closest_admissible

    limits = Constraints().resolve(HILLS)
    refused(InvalidInputError, "max_sweeps must be at most 1,000,000", closest_admissible, limits, HILLS, UAVS, max_sweeps=max_sweeps)


# ---------------------------------------------------------------------------------------------
# Subnormal sizes and rates (the fuzz harness's 5e-324): counts of cells or frames that overflowed


@pytest.mark.parametrize("step", [5e-324, 1e-310, 1e-300])
def test_a_subnormal_cell_is_refused_before_its_count_overflows(step: float) -> None:
    from uavcov.structures import girder_bridge, height_field_violation
    from uavcov.terrain import approximation_error, buildings_scene, sample_prior

    refused(InvalidInputError, "size \\(24 m\\) in cells of .* m is .* cells, more than 10,000", buildings_scene, spacing=step, rng=0)
    refused(
        InvalidInputError,
        "resolution \\(.* m\\) in cells of .* m is .* cells, more than 10,000",
        height_field_violation,
        girder_bridge(rng=0),
        resolution=step,
    )
    approx = uavcov.terrain.approximate_surface(sample_prior(HILLS, 30, rng=0).points)
    refused(
        InvalidInputError,
        "resolution \\(.* m\\) in cells of .* m is .* cells, more than 10,000",
        approximation_error,
        HILLS,
        approx,
        resolution=step,
    )


@pytest.mark.parametrize("dpi", [5e-324, 1e-300, 0.5])
def test_a_figure_refuses_a_dpi_below_one(mission: Any, dpi: float) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_coverage_curves, plot_coverage_map

    refused(InvalidInputError, "dpi must be at least 1", plot_coverage_map, mission, dpi=dpi)
    refused(InvalidInputError, "dpi must be at least 1", plot_coverage_curves, [mission], dpi=dpi)


@pytest.mark.parametrize("fps", [5e-324, 1e-300, 0.0009])
def test_an_animation_refuses_an_fps_whose_frames_never_end(mission: Any, tmp_path: Path, fps: float) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import animate_mission

    refused(InvalidInputError, "fps must be at least 0.001", animate_mission, mission, tmp_path / "run.gif", fps=fps)
    assert list(tmp_path.iterdir()) == []
