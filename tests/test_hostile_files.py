"""Hostile files and folders: a clear ``uavcov.errors`` error (or, for the CLI, exit 2 and one line),
never a raw traceback, never results of two configurations in one folder, never a write outside
the results folder, one file mode (issue 14, items 3, 5, 7, 8, 10).

Everything runs tiny sweeps (a 40 m terrain on a 4 m grid, 2 UAVs, a few iterations).
"""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import time
import zipfile
from pathlib import Path

import numpy as np
import pytest

from tiny import TINY_TOML, tiny_experiment
from uavcov import MissionSettings, Terrain, run_mission
from uavcov._validate import MAX_RUNS, MAX_SEEDS, MAX_UAVS
from uavcov.cli import EXIT_BAD_INPUT, EXIT_OK, main
from uavcov.errors import (
    ConfigError,
    InvalidInputError,
    InvalidTypeError,
    ResultsFolderError,
    ResultsFormatError,
    ResultsInUseError,
)
from uavcov.experiments import experiment_specs, parse_seeds, parse_sweep_config, read_runs, run_specs
from uavcov.experiments._results import CONFIG_FORMAT
from uavcov.experiments._sweep import settings_hash
from uavcov.paper import EXPERIMENTS as PAPER_EXPERIMENTS
from uavcov.paper import _data as paper
from uavcov.records import load_mission, save_mission

TINY = tiny_experiment(2)


def tiny_specs(experiment=TINY, seeds=(0,)):
    return experiment_specs(experiment, seeds=seeds, team_sizes=[2], starts=["cvt"])


def write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


def snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (links as their target's name), to show that nothing changed."""
    out = {}
    for path in sorted(folder.rglob("*")):
        key = str(path.relative_to(folder))
        if path.is_symlink():
            out[key] = b"-> " + os.readlink(path).encode()
        elif path.is_file() and path.name != ".uavcov.lock":
            out[key] = path.read_bytes()
    return out


def cli(capsys, *argv: str) -> tuple[int, str]:
    """Run the CLI in this process: its exit code and its stderr (checked to be one error line, no traceback)."""
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err
    assert "Traceback" not in err, err
    if code == EXIT_BAD_INPUT:
        lines = [line for line in err.splitlines() if line.strip()]
        assert len(lines) == 1 and lines[0].startswith(f"uavcov {argv[0]}: error: "), err
        assert "--" not in lines[0].partition("error: ")[2].replace(str(argv[-1]), ""), lines[0]  # no flag named
    return code, err


@pytest.fixture(scope="module")
def swept(tmp_path_factory) -> Path:
    """A finished tiny sweep folder (copied by the tests that change it)."""
    folder = tmp_path_factory.mktemp("swept") / "out"
    config = write(folder.parent / "tiny.toml", TINY_TOML.format(iterations=2))
    assert main(["sweep", str(config), "--out", str(folder), "--workers", "1", "--no-progress"]) == EXIT_OK
    return folder


def copy_of(folder: Path, where: Path) -> Path:
    import shutil

    return Path(shutil.copytree(folder, where / "copy", symlinks=True))


# ---------------------------------------------------------------------------------------------
# Item 3 (Python side): sizes checked against documented limits before anything is allocated

_UNDER_2_GIB = r"""
import resource, sys
resource.setrlimit(resource.RLIMIT_AS, (2 * 1024**3, 2 * 1024**3))
import numpy as np
import uavcov
from uavcov.errors import UavcovError
try:
    exec(sys.argv[1])
    print("no error")
except UavcovError as exc:
    print("error", type(exc).__name__, exc)
except BaseException as exc:
    print("other", type(exc).__module__, type(exc).__name__, exc)
"""


@pytest.mark.parametrize(
    "code",
    [
        "uavcov.placement.cvt(uavcov.Terrain.from_grid(np.zeros((11, 11)), 1.0), 30000)",
        "uavcov.placement.cvt(uavcov.Terrain.from_grid(np.zeros((11, 11)), 1.0), 10**6)",
        "uavcov.run_mission(uavcov.Terrain.from_grid(np.zeros((11, 11)), 1.0), uavcov.MissionSettings(n_uavs=30000, d_max=5.0))",
        "from uavcov.experiments._sweep_config import parse_seeds; parse_seeds('0-999999999')",
        "from uavcov.experiments._sweep_config import parse_seeds; parse_seeds(range(10**12))",
    ],
)
def test_huge_sizes_are_refused_before_any_allocation(code):
    # Under a 2 GiB address space: a MemoryError, an abort or a hang would show here.
    started = time.perf_counter()
    result = subprocess.run([sys.executable, "-c", _UNDER_2_GIB, code], capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.startswith("error InvalidInputError") or result.stdout.startswith("error ConfigError"), result.stdout
    assert "limit" in result.stdout
    assert time.perf_counter() - started < 60


def test_the_limits_are_generous_and_documented():
    import uavcov._validate as limits

    names = ("MAX_UAVS", "MAX_GENERATORS", "MAX_SAMPLES", "MAX_ITERATIONS", "MAX_TRAJECTORY", "MAX_PAIR_CHECKS", "MAX_SEEDS", "MAX_RUNS")
    for name in names:
        assert f":data:`{name}`" in limits.__doc__, name  # the one table of limits
    assert MAX_UAVS >= 500 and MAX_SEEDS >= 100_000 and MAX_RUNS >= 100_000
    # The paper's own experiments are far inside them.
    for experiment in paper.EXPERIMENTS.values():
        assert max(experiment.team_sizes) <= MAX_UAVS


def test_team_size_limits():
    with pytest.raises(InvalidInputError, match="at most 1,000"):
        MissionSettings(n_uavs=MAX_UAVS + 1, d_max=10.0)
    MissionSettings(n_uavs=MAX_UAVS, d_max=10.0, constraints=TINY.mission.constraints.__class__(d_safe=0.0))
    with pytest.raises(InvalidInputError, match="distance checks"):  # d_safe pairs of 200 candidates a step
        MissionSettings(n_uavs=MAX_UAVS, d_max=10.0)
    with pytest.raises(InvalidInputError, match="positions"):  # the recorded trajectory
        MissionSettings(n_uavs=100, d_max=10.0, iterations=1_000_000)
    with pytest.raises(InvalidInputError, match="team_sizes"):
        TINY.with_changes(team_sizes=(2, 30000))
    with pytest.raises(InvalidInputError):
        experiment_specs(TINY, seeds=range(MAX_RUNS), team_sizes=[2], starts=["cvt", "random"])


def test_cvt_limits():
    from uavcov import CVTSettings
    from uavcov.placement import cvt

    square = Terrain.from_grid(np.zeros((11, 11)), 1.0)
    with pytest.raises(InvalidInputError, match="samples_per_iteration"):
        CVTSettings(samples_per_iteration=10**9)
    with pytest.raises(InvalidInputError, match="max_iterations"):
        CVTSettings(max_iterations=10**9)
    with pytest.raises(InvalidInputError, match="at most 10,000"):
        cvt(square, 10**6)


def test_seed_limits():
    with pytest.raises(ConfigError, match="1,000,000"):
        parse_seeds("0-999999999")
    with pytest.raises(ConfigError, match="1,000,000"):
        parse_seeds("0-10,20-99999999999999999999")
    assert len(parse_seeds("0-999")) == 1000


def test_a_sweep_of_a_huge_team_is_refused_before_it_runs(tmp_path, capsys):
    config = write(tmp_path / "big.toml", TINY_TOML.format(iterations=2).replace("team_sizes = [2]", "team_sizes = [30000]"))
    code, err = cli(capsys, "sweep", config, "--out", tmp_path / "out")
    assert code == EXIT_BAD_INPUT and "30,000" in err and "1,000" in err
    assert not (tmp_path / "out").exists()
    with pytest.raises(ConfigError, match="runs"):  # a [sweep] grid beyond the run limit, refused before it is built
        parse_sweep_config(
            {"seeds": "0-99999", "team_sizes": [2, 3], "sweep": {"cao.alpha0": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]}}, bases=PAPER_EXPERIMENTS
        )


def test_cli_seeds_beyond_the_limit(tmp_path, capsys):
    code, err = cli(capsys, "reproduce", "table1", "--seeds", "0-999999999", "--out", tmp_path / "out")
    assert code == EXIT_BAD_INPUT and "1,000,000" in err
    assert not (tmp_path / "out").exists()


# ---------------------------------------------------------------------------------------------
# Item 5: one configuration per folder, with or without config.json


@pytest.mark.parametrize("damage", ["deleted", "garbage", "a JSON list", "unreadable"])
def test_resume_with_other_settings_is_refused_whatever_became_of_config_json(tmp_path, damage):
    out = tmp_path / "out"
    run_specs(tiny_specs(), out=out, workers=1)
    config = out / "config.json"
    if damage == "deleted":
        config.unlink()
    elif damage == "garbage":
        config.write_bytes(b"\xff\x00 not json")
    elif damage == "a JSON list":
        config.write_text("[1, 2]")
    else:
        config.write_text("{}")
        config.chmod(0)
    before = snapshot(out)
    other = tiny_specs(TINY.with_changes(**{"cao.alpha0": 0.5}))
    assert settings_hash(other[0].experiment) != settings_hash(TINY)
    for rerun in ("none", "failed", "all"):
        with pytest.raises(ResultsInUseError):
            run_specs(other, out=out, workers=1, resume=True, rerun=rerun)
        assert snapshot(out) == before if damage != "unreadable" else True
    assert {r["settings_hash"] for r in read_runs(out / "runs.csv")} == {settings_hash(TINY)}


def test_resume_of_a_sweep_with_other_settings_through_the_cli(tmp_path, capsys, swept):
    out = copy_of(swept, tmp_path)
    (out / "config.json").unlink()
    before = snapshot(out)
    other = write(tmp_path / "other.toml", TINY_TOML.format(iterations=3))
    code, err = cli(capsys, "sweep", other, "--out", out, "--resume", "--workers", "1")
    assert code == EXIT_BAD_INPUT and "other settings" in err
    assert snapshot(out) == before
    assert len({r["settings_hash"] for r in read_runs(out / "runs.csv")}) == 1


# ---------------------------------------------------------------------------------------------
# Item 7: raw tracebacks where a clear error belongs


@pytest.mark.parametrize("seeds", ["5.5", "true", "{a = 1}", '"0-3,x"', "-1", "[0, 0]", "[]"])
def test_bad_seeds_in_a_sweep_file(tmp_path, capsys, seeds):
    config = write(tmp_path / "bad.toml", TINY_TOML.format(iterations=2).replace("seeds = [0, 1]", f"seeds = {seeds}"))
    code, err = cli(capsys, "sweep", config, "--out", tmp_path / "out")
    assert code == EXIT_BAD_INPUT and "seeds" in err
    with pytest.raises(ConfigError):
        parse_seeds(5.5)  # type: ignore[arg-type]


@pytest.mark.parametrize("damage", ["non-UTF-8 byte", "non-numeric cell", "binary", "bad CSV quoting"])
def test_resume_on_a_damaged_runs_csv(tmp_path, capsys, swept, damage):
    out = copy_of(swept, tmp_path)
    runs = out / "runs.csv"
    if damage == "non-UTF-8 byte":
        runs.write_bytes(runs.read_bytes() + b"\xff\xfe,\n")
    elif damage == "non-numeric cell":
        lines = runs.read_text().splitlines(keepends=True)
        cells = lines[1].split(",")
        cells[6] = "many"  # iterations
        runs.write_text(lines[0] + ",".join(cells) + "".join(lines[2:]))
    elif damage == "binary":
        runs.write_bytes(bytes(range(256)) * 4 + b"\n")
    else:
        runs.write_text(runs.read_text().splitlines(keepends=True)[0] + '"unterminated\n')
    before = snapshot(out)
    config = write(tmp_path / "tiny.toml", TINY_TOML.format(iterations=2))
    code, _ = cli(capsys, "sweep", config, "--out", out, "--resume", "--workers", "1")
    assert code == EXIT_BAD_INPUT
    assert snapshot(out) == before
    code, _ = cli(capsys, "plot", out, "--no-animation")
    assert code == EXIT_BAD_INPUT


def test_plot_on_damaged_run_files(tmp_path, capsys, swept):
    pytest.importorskip("matplotlib")
    out = copy_of(swept, tmp_path)
    run_file = min((out / "runs").glob("*.npz"))
    # A leftover of a crash is skipped (and removed by the next resume).
    (out / "runs" / ".tmp-abc123.npz").write_bytes(b"")
    code, _ = cli(capsys, "plot", out, "--no-animation", "--max-runs", "1")
    assert code == EXIT_OK
    config = write(tmp_path / "tiny.toml", TINY_TOML.format(iterations=2))
    code, _ = cli(capsys, "sweep", config, "--out", out, "--resume", "--workers", "1")
    assert code == EXIT_OK and not (out / "runs" / ".tmp-abc123.npz").exists()
    # An --out that is a file.
    blocker = write(tmp_path / "a-file", "keep me")
    code, err = cli(capsys, "plot", out, "--out", blocker, "--no-animation")
    assert code == EXIT_BAD_INPUT and "is a file" in err and blocker.read_text() == "keep me"
    # A 0-byte run file.
    run_file.write_bytes(b"")
    code, err = cli(capsys, "plot", out, "--no-animation")
    assert code == EXIT_BAD_INPUT and run_file.name in err


def test_a_bad_scheduler_address_is_one_line_and_fast(tmp_path):
    pytest.importorskip("distributed")
    config = write(tmp_path / "tiny.toml", TINY_TOML.format(iterations=2))
    for address in ("not a url", "tcp://host-without-port", "tcp://h:99999"):
        started = time.perf_counter()
        result = subprocess.run(
            [sys.executable, "-m", "uavcov", "sweep", str(config), "--out", str(tmp_path / "out"), "--scheduler", address],
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
        elapsed = time.perf_counter() - started
        assert result.returncode == EXIT_BAD_INPUT, result.stderr
        assert "Traceback" not in result.stderr and len(result.stderr.strip().splitlines()) == 1, result.stderr
        assert "Dask scheduler" in result.stderr
        assert elapsed < 15, elapsed  # no 20 s wait for a client that never started


@pytest.fixture(scope="module")
def run_file(swept) -> Path:
    return min((swept / "runs").glob("*cvt*.npz"))


def rewrite(source: Path, target: Path, *, header=None, drop=(), replace=None) -> Path:
    """A copy of the run file ``source`` with its header or arrays changed."""
    with np.load(source) as data:
        arrays = {name: data[name] for name in data.files if name not in drop}
    if header is not None:
        arrays["header"] = np.array(header if isinstance(header, str) else json.dumps(header))
    arrays.update(replace or {})
    np.savez_compressed(target, **arrays)
    return target


def corrupt_member(source: Path, target: Path, member: str = "prior_points.npy") -> Path:
    raw = bytearray(source.read_bytes())
    info = zipfile.ZipFile(io.BytesIO(bytes(raw))).getinfo(member)
    start = info.header_offset + 30 + len(info.filename) + len(info.extra)
    for k in range(start + 2, start + min(40, info.compress_size - 2)):
        raw[k] ^= 0x5A
    target.write_bytes(bytes(raw))
    return target


def test_load_mission_on_hostile_files(tmp_path, run_file):
    header = json.loads(str(np.load(run_file)["header"]))
    cases = {
        "empty": lambda p: p.write_bytes(b""),
        "text": lambda p: p.write_text("hello"),
        "a zip of nothing": lambda p: zipfile.ZipFile(p, "w").close(),
        "a bare npy": lambda p: np.save(open(p, "wb"), np.zeros(3)),  # noqa: SIM115
        "corrupt member": lambda p: corrupt_member(run_file, p),
        "cut short": lambda p: p.write_bytes(run_file.read_bytes()[: run_file.stat().st_size // 2]),
        "header a list": lambda p: rewrite(run_file, p, header="[1, 2]"),
        "header null": lambda p: rewrite(run_file, p, header="null"),
        "header not JSON": lambda p: rewrite(run_file, p, header="{"),
        "header an array": lambda p: rewrite(run_file, p, replace={"header": np.zeros(3)}),
        "no header": lambda p: rewrite(run_file, p, drop=("header",)),
        "no coverage": lambda p: rewrite(run_file, p, drop=("coverage",)),
    }
    for name, make in cases.items():
        path = tmp_path / f"{name.replace(' ', '_')}.npz"
        make(path)
        with pytest.raises(ResultsFormatError, match=path.name):
            load_mission(path)
    assert header["format"] == "uavcov.mission/2"
    for not_a_path in (12, None, b"x".decode() and 3.5, ["a"]):
        with pytest.raises(InvalidTypeError, match="path"):
            load_mission(not_a_path)  # type: ignore[arg-type]
    with pytest.raises(ResultsFormatError, match="no run file"):
        load_mission(tmp_path / "missing.npz")


def test_save_mission_of_a_wrong_type(tmp_path, run_file):
    for wrong in ("x", None, load_mission(run_file).settings):
        with pytest.raises(InvalidTypeError, match="MissionResult"):
            save_mission(wrong, tmp_path / "x.npz")  # type: ignore[arg-type]
    with pytest.raises(InvalidTypeError, match="path"):
        save_mission(load_mission(run_file), 12)  # type: ignore[arg-type]
    assert not (tmp_path / "x.npz").exists()


def test_run_mission_settings_unknown_or_not_settings():
    terrain = Terrain.from_grid(np.zeros((11, 11)), 1.0)
    with pytest.raises(InvalidTypeError, match="MissionSettings"):
        run_mission(terrain, {"n_uavs": 2, "d_max": 5.0})  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="bogus"):
        MissionSettings.from_dict({"n_uavs": 2, "d_max": 5.0, "cvt": {"bogus": 1}})


# ---------------------------------------------------------------------------------------------
# Item 8: a run file whose header holds nonsense is refused, not loaded


@pytest.mark.parametrize(
    "where, value",
    [
        (("spec", "n_uavs"), "many"),
        (("spec", "d_max"), "far"),
        (("spec", "cao", "n_candidates"), 2.5),
        (("seed",), "many"),
        (("prior_kind",), 3),
        (("scalars", "best_iteration"), "many"),
        (("scalars", "best_coverage"), "high"),
        (("scalars", "evaluations"), True),
        (("trace", "evaluations"), "many"),
        (("trace", "best_value"), None),
        (("cvt", "iterations"), "many"),
        (("cvt", "converged"), "yes"),
        (("scalars",), [1, 2]),
        (("spec", "n_uavs"), 7),  # disagrees with the arrays' team of 2
    ],
)
def test_a_header_with_nonsense_is_refused(tmp_path, run_file, where, value):
    header = json.loads(str(np.load(run_file)["header"]))
    node = header
    for key in where[:-1]:
        node = node[key]
    node[where[-1]] = value
    path = rewrite(run_file, tmp_path / "bad.npz", header=header)
    with pytest.raises(ResultsFormatError, match=r"bad\.npz"):
        load_mission(path)


def test_arrays_of_the_wrong_shape_are_refused(tmp_path, run_file):
    wrong = {"coverage": np.zeros((2, 2)), "trace_trajectory": np.zeros((3, 5, 3)), "start_positions": np.array(["a", "b"])}
    for name, array in wrong.items():
        path = rewrite(run_file, tmp_path / f"{name}.npz", replace={name: array})
        with pytest.raises(ResultsFormatError, match=name):
            load_mission(path)
    assert load_mission(run_file).settings.n_uavs == 2  # the untouched file still loads


# ---------------------------------------------------------------------------------------------
# Item 10: no write outside the folder, no silent overwrite, one file mode


def test_a_dangling_symlink_at_runs_csv_is_not_followed(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    target = tmp_path / "elsewhere" / "runs.csv"
    target.parent.mkdir()
    (out / "runs.csv").symlink_to(target)
    config = write(tmp_path / "tiny.toml", TINY_TOML.format(iterations=2))
    code, err = cli(capsys, "sweep", config, "--out", out, "--workers", "1")
    assert code == EXIT_BAD_INPUT and "symbolic link" in err
    assert not target.exists() and list(target.parent.iterdir()) == []
    assert sorted(p.name for p in out.iterdir()) == [".uavcov.lock", "runs.csv"]  # the empty lock file only
    with pytest.raises(ResultsFolderError):
        run_specs(tiny_specs(), out=out, workers=1)


@pytest.mark.parametrize("name", ["runs", "config.json", "summary.md", ".uavcov.lock", "sweep.toml"])
def test_no_symlink_of_the_folder_is_written_through(tmp_path, capsys, name):
    out = tmp_path / "out"
    out.mkdir()
    outside = tmp_path / "outside"
    outside.mkdir()
    (out / name).symlink_to(outside / name, target_is_directory=name == "runs")
    config = write(tmp_path / "tiny.toml", TINY_TOML.format(iterations=2))
    code, err = cli(capsys, "sweep", config, "--out", out, "--workers", "1")
    assert code == EXIT_BAD_INPUT, err
    assert list(outside.iterdir()) == []
    assert (out / name).is_symlink()


def test_an_unrelated_config_json_or_summary_is_not_overwritten(tmp_path, capsys):
    config = write(tmp_path / "tiny.toml", TINY_TOML.format(iterations=2))
    for name, text in (("config.json", '{"my": "settings"}'), ("summary.md", "# my notes\n"), ("config.json", "not json")):
        out = tmp_path / f"out-{name}-{len(text)}"
        out.mkdir()
        write(out / name, text)
        code, err = cli(capsys, "sweep", config, "--out", out, "--workers", "1")
        assert code == EXIT_BAD_INPUT and name in err
        assert (out / name).read_text() == text
        assert sorted(p.name for p in out.iterdir()) == sorted([name, ".uavcov.lock"])  # nothing but the empty lock file
    # The same through the library, and for reproduce's table.
    out = tmp_path / "reproduce"
    out.mkdir()
    write(out / "example.md", "mine")
    from uavcov.paper import _jobs as jobs

    with pytest.raises(ResultsInUseError, match=r"example\.md"):
        jobs.reproduce("example", out, iterations=1, workers=1, save_runs=False)
    assert (out / "example.md").read_text() == "mine"
    # Our own folder is resumed and rewritten as before.
    ours = tmp_path / "ours"
    assert main(["sweep", str(config), "--out", str(ours), "--workers", "1"]) == EXIT_OK
    assert json.loads((ours / "config.json").read_text())["format"] == CONFIG_FORMAT
    assert main(["sweep", str(config), "--out", str(ours), "--workers", "1", "--resume"]) == EXIT_OK


@pytest.mark.parametrize("umask", [0o022, 0o077, 0o002])
def test_one_file_mode(tmp_path, umask):
    previous = os.umask(umask)
    try:
        out = tmp_path / "out"
        config = write(tmp_path / "tiny.toml", TINY_TOML.format(iterations=2))
        assert main(["sweep", str(config), "--out", str(out), "--workers", "1"]) == EXIT_OK
        assert main(["sweep", str(config), "--out", str(out), "--workers", "1", "--resume", "--retry-failed"]) == EXIT_OK
    finally:
        os.umask(previous)
    modes = {str(p.relative_to(out)): p.stat().st_mode & 0o777 for p in out.rglob("*") if p.is_file()}
    assert {"runs.csv", "config.json", "summary.md", "sweep.toml", ".uavcov.lock"} <= set(modes)
    assert any(name.endswith(".npz") for name in modes)
    assert set(modes.values()) == {0o666 & ~umask}, modes


def test_a_config_json_of_an_earlier_release_is_ours(tmp_path):
    # Written before config.json had its format tag: recognised (its settings then differ), not "not uavcov's".
    out = tmp_path / "out"
    run_specs(tiny_specs(), out=out, workers=1)
    document = json.loads((out / "config.json").read_text())
    del document["format"]
    (out / "config.json").write_text(json.dumps(document))
    run_specs(tiny_specs(), out=out, workers=1, resume=True)  # the same settings: resumed
    assert json.loads((out / "config.json").read_text())["format"] == CONFIG_FORMAT
