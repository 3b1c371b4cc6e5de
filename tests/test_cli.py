"""The command line: every command end to end on tiny settings, and every kind of bad input.

Bad input must give a clear message (``uavcov <command>: error: <message>``, the message the
library's own, naming no command-line flag), a non-zero exit code, and leave whatever is already
in ``--out`` as it was.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tiny import TINY_TOML
from uavcov.cli import EXIT_BAD_INPUT, EXIT_INTERRUPTED, EXIT_OK, EXIT_PIPE_CLOSED, EXIT_RUNS_FAILED, main
from uavcov.experiments import available_cores, read_runs
from uavcov.experiments._results import CONFIG_FORMAT

TINY_SWEEP = TINY_TOML + '\n[sweep]\n"cao.alpha0" = [1.0, 2.0]\n'


def write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


def error_message(err: str, command: str, tmp_path: Path) -> str:
    """The message of the CLI's one error line (``uavcov <command>: error: ...``), paths left out."""
    lines = [line for line in err.splitlines() if line.startswith(f"uavcov {command}: error: ")]
    assert len(lines) == 1, err
    return lines[0].removeprefix(f"uavcov {command}: error: ").replace(str(tmp_path), "<tmp>")


def snapshot(directory: Path) -> dict[str, bytes]:
    return {str(p.relative_to(directory)): p.read_bytes() for p in sorted(directory.rglob("*")) if p.is_file()}


def test_sweep_end_to_end(tmp_path, capsys):
    config = write(tmp_path / "tiny.toml", TINY_SWEEP.format(iterations=4))
    out = tmp_path / "out"
    assert main(["sweep", str(config), "--out", str(out), "--workers", "1", "--no-progress"]) == EXIT_OK
    rows = read_runs(out / "runs.csv")
    assert len(rows) == 2 * 2 * 1 * 2  # alpha0 values x seeds x team sizes x starts
    assert sorted({r["cao.alpha0"] for r in rows}) == ["1.0", "2.0"]
    assert all(r["experiment"] == "tiny" and r["error"] == "" for r in rows)
    assert len(list((out / "runs").glob("*.npz"))) == len(rows)
    resolved = json.loads((out / "config.json").read_text())
    assert resolved["format"] == CONFIG_FORMAT and resolved["command"] == "sweep"
    assert resolved["about"]["name"] == "tiny" and resolved["about"]["axes"] == ["cao.alpha0"]
    # One entry per settings hash: the label, the swept values, and the experiment they give.
    assert sorted(resolved["settings"]) == sorted({r["settings_hash"] for r in rows})
    entries = list(resolved["settings"].values())
    assert sorted(v["experiment"]["mission"]["cao"]["alpha0"] for v in entries) == [1.0, 2.0]
    assert sorted(v["swept"]["cao.alpha0"] for v in entries) == [1.0, 2.0]
    assert all(v["label"] == "tiny" for v in entries)
    assert all(v["experiment"]["terrain"]["spacing"] == 4.0 for v in entries)
    assert resolved["runs"] == {"seeds": [0, 1], "team_sizes": [2], "starts": ["cvt", "corner"], "count": len(rows)}
    assert (out / "sweep.toml").read_text() == config.read_text()
    summary = (out / "summary.md").read_text()
    assert summary.count("| 1.0 | 2 |") == 2 and summary.count("| 2.0 | 2 |") == 2
    capsys.readouterr()
    # Rerunning into the same directory without --resume is refused and changes nothing.
    before = snapshot(out)
    assert main(["sweep", str(config), "--out", str(out), "--workers", "1"]) == EXIT_BAD_INPUT
    message = error_message(capsys.readouterr().err, "sweep", tmp_path)
    assert "already holds 8 run(s)" in message and "resume" in message
    assert "--" not in message  # the library names no flag (it used to say --resume)
    assert snapshot(out) == before
    # --resume of a finished sweep runs nothing and keeps every row once.
    assert main(["sweep", str(config), "--out", str(out), "--workers", "1", "--resume"]) == EXIT_OK
    assert len(read_runs(out / "runs.csv")) == len(rows)
    # Other settings into the same directory, even with --resume, are refused.
    other = write(tmp_path / "other.toml", TINY_SWEEP.format(iterations=5).replace('name = "tiny"', 'name = "tiny"'))
    assert main(["sweep", str(other), "--out", str(out), "--resume"]) == EXIT_BAD_INPUT
    message = error_message(capsys.readouterr().err, "sweep", tmp_path)
    assert "other settings" in message and "--" not in message
    assert snapshot(out)["runs.csv"] == before["runs.csv"]


@pytest.mark.parametrize(
    "text, message",
    [
        ("name = \n", "not valid TOML"),
        ("iteratoins = 5\n", "did you mean 'iterations'"),
        ("[cao]\nalpha = 1.0\n", "did you mean 'alpha0'"),
        ("[terrain]\nsigmaa = 3.0\n", "did you mean 'sigma'"),
        ('[sweep]\n"cao.alpah0" = [1.0]\n', "did you mean 'cao.alpha0'"),
        ("d_max = -5.0\n", "d_max"),
        ("iterations = -1\n", "iterations"),
        ("team_sizes = [0]\n", "team_sizes"),
        ('starts = ["cvtt"]\n', "did you mean 'cvt'"),
        ('seeds = "5-1"\n', "backwards"),
        ("[cao]\nalpha0 = -1.0\n", "alpha0"),
        ("[cao]\nn_candidates = 2.5\n", "integer"),
        ("[terrain]\nspacing = 3.0\n", "multiple of the spacing"),
        pytest.param(
            '[cvt]\npreset = "lloid"\n',
            "did you mean 'lloyd'",
        ),
        ('[cvt]\npreset = "lloid"\n', "cvt.preset"),
        ("[constraints]\nh_min = 60.0\nz_max = 50.0\n", "h_min"),
        ("[flight]\nh_min = 2.0\n", "flight"),  # the table of earlier releases is gone
        ('prior = "map"\n', "buildings"),
        ("[sweep]\nd_max = []\n", "non-empty list"),
        ("[sweep]\nseeds = [1, 2]\n", "top level"),
    ],
)
def test_bad_config_files_are_refused_before_anything_runs(tmp_path, capsys, text, message):
    # Should a check ever let the file through, keep the sweep it would run to a single short run.
    guard = {"seeds": "seeds = [0]", "team_sizes": "team_sizes = [2]", "starts": 'starts = ["cvt"]', "iterations": "iterations = 0"}
    prefix = "".join(line + "\n" for key, line in guard.items() if key not in text)
    config = write(tmp_path / "bad.toml", prefix + text)
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("precious")
    before = snapshot(out)
    assert main(["sweep", str(config), "--out", str(out)]) == EXIT_BAD_INPUT
    err = capsys.readouterr().err
    assert "error" in err and message.lower() in err.lower()
    assert "Traceback" not in err
    assert snapshot(out) == before


def test_a_missing_config_file(tmp_path, capsys):
    assert main(["sweep", str(tmp_path / "nope.toml")]) == EXIT_BAD_INPUT
    assert "cannot read" in capsys.readouterr().err


def test_an_out_that_cannot_be_written(tmp_path, capsys):
    config = write(tmp_path / "tiny.toml", TINY_SWEEP.format(iterations=1))
    blocker = write(tmp_path / "a-file", "keep me")
    assert main(["sweep", str(config), "--out", str(blocker / "sub"), "--workers", "1"]) == EXIT_BAD_INPUT
    assert "cannot write" in error_message(capsys.readouterr().err, "sweep", tmp_path)
    assert main(["reproduce", "example", "--out", str(blocker), "--workers", "1"]) == EXIT_BAD_INPUT
    assert "is a file" in error_message(capsys.readouterr().err, "reproduce", tmp_path)
    assert main(["demo", "--out", str(blocker), "--iterations", "0", "--no-plots"]) == EXIT_BAD_INPUT
    assert "is a file" in error_message(capsys.readouterr().err, "demo", tmp_path)
    assert blocker.read_text() == "keep me"


def test_a_scheduler_that_does_not_answer(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "runs.csv").write_text("precious")
    started = time.perf_counter()
    code = main(["reproduce", "example", "--out", str(out), "--scheduler", "tcp://127.0.0.1:9", "--scheduler-timeout", "1"])
    assert code == EXIT_BAD_INPUT  # a SchedulerTimeoutError is bad input too
    assert time.perf_counter() - started < 10.0
    assert "did not answer" in error_message(capsys.readouterr().err, "reproduce", tmp_path)
    assert (out / "runs.csv").read_text() == "precious"


def test_oversubscribed_threads_are_refused(tmp_path, capsys):
    cores = available_cores()
    code = main(["reproduce", "example", "--out", str(tmp_path / "o"), "--workers", str(cores), "--threads", "2"])
    assert code == EXIT_BAD_INPUT
    assert "exceeds" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_argument_errors_exit_2(capsys):
    for argv in (["reproduce", "table2"], ["reproduce", "table1", "--iterations", "-3"], ["demo", "--seed", "x"], []):
        with pytest.raises(SystemExit) as exit_info:
            main(argv)
        assert exit_info.value.code == 2
    capsys.readouterr()


def test_a_warning_is_one_line_naming_the_command(tmp_path, capsys):
    import warnings

    import numpy as np

    heights = np.full((11, 11), 3.0)
    heights[0, 0] = np.nan  # a corner without ground: sample_prior warns that S' leaves it out
    np.save(tmp_path / "heights.npy", heights)
    text = (
        TINY_TOML.format(iterations=1)
        .replace("size = 40.0\nspacing = 4.0\nheights = [2.0, 8.0]\nsigma = 6.0", 'kind = "file"\npath = "heights.npy"\nspacing = 4.0')
        .replace('starts = ["cvt", "corner"]', 'starts = ["cvt"]')
    )
    config = write(tmp_path / "nodata.toml", text)
    before = warnings.showwarning
    assert main(["sweep", str(config), "--out", str(tmp_path / "out"), "--workers", "1", "--no-progress"]) == EXIT_OK
    err = capsys.readouterr().err
    said = [line for line in err.splitlines() if ": warning:" in line]
    assert said and all(line.startswith("uavcov sweep: warning: 1 corner(s)") for line in said), err
    assert "mission.py" not in err and "prior = " not in err, err  # no source line of the package
    assert warnings.showwarning is before  # main() leaves Python's warnings as they were


@pytest.mark.parametrize("command", ["demo", "reproduce", "sweep", "plot", "view", "plan"])
def test_each_command_help_says_what_it_does(command, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main([command, "--help"])
    assert exit_info.value.code == 0
    help_text = capsys.readouterr().out
    assert f"\nuavcov {command}: " in help_text, help_text  # its description, not only its flags
    said = {"sweep": "the sweep file", "plot": "a results folder", "reproduce": "which experiment", "plan": "GeoTIFF"}
    assert said.get(command, "") in help_text  # and what its positional argument is


def test_reproduce_help_says_how_many_runs_each_experiment_makes(capsys):
    from uavcov.paper import EXPERIMENTS
    from uavcov.paper import _data as paper_data

    with pytest.raises(SystemExit) as exit_info:
        main(["reproduce", "--help"])
    assert exit_info.value.code == 0
    lines = {line.split()[0]: line for line in capsys.readouterr().out.splitlines() if line.startswith("  ") and line.split()}
    for name, experiment in EXPERIMENTS.items():
        runs = len(experiment.seeds) * len(experiment.team_sizes) * len(experiment.starts)
        assert f"; {runs} run" in lines[name], (name, runs, lines.get(name))
    base = paper_data.ABLATION_BASE
    variants = 1 + len(paper_data.ABLATIONS)
    assert f"{len(paper_data.ABLATIONS)} single changes" in lines["ablation"]
    assert f"; {variants * len(base.seeds) * len(base.team_sizes) * len(base.starts)} runs" in lines["ablation"]
    for name in ("structures", "realistic", "flown-table1", "all"):
        assert name in lines


def test_reproduce_records_failed_runs_and_exits_1(tmp_path, capsys):
    config = write(
        tmp_path / "fail.toml",
        TINY_SWEEP.format(iterations=2)
        .replace("team_sizes = [2]", "team_sizes = [2, 30]")
        .replace("size = 40.0", "size = 12.0")
        .replace("spacing = 4.0", "spacing = 2.0"),
    )
    out = tmp_path / "out"
    assert main(["sweep", str(config), "--out", str(out), "--workers", "1", "--no-save-runs"]) == EXIT_RUNS_FAILED
    err = capsys.readouterr().err
    assert "failed" in err
    rows = read_runs(out / "runs.csv")
    assert len(rows) == 2 * 2 * 2 * 2  # alpha0 values x seeds x team sizes x starts
    assert {r["error"] != "" for r in rows} == {True, False}
    assert not (out / "runs").exists() or not list((out / "runs").glob("*.npz"))


def test_demo(tmp_path, capsys):
    out = tmp_path / "demo"
    assert main(["demo", "--out", str(out), "--iterations", "3", "--no-plots", "--threads", "1"]) == EXIT_OK
    text = capsys.readouterr().out
    assert "9 UAVs" in text and "d_max = 35 m" in text
    rows = read_runs(out / "runs.csv")
    assert len(rows) == 1 and rows[0]["n_uavs"] == 9 and rows[0]["sensing_range"] == 35.0
    assert f"{rows[0]['initial_coverage']:.3f}" in text and f"{rows[0]['max_coverage']:.3f}" in text
    assert (out / "runs" / f"{rows[0]['run_id']}.npz").is_file()
    config = json.loads((out / "config.json").read_text())
    assert config["format"] == CONFIG_FORMAT and config["command"] == "demo"
    assert list(config["settings"]) == [rows[0]["settings_hash"]]
    assert {p.name for p in out.iterdir()} >= {"runs.csv", "config.json", "example.md", "coverage.csv", "runs"}
    # The demo again into its own directory replaces its run instead of adding a second row.
    assert main(["demo", "--out", str(out), "--iterations", "3", "--no-plots", "--threads", "1"]) == EXIT_OK
    again = read_runs(out / "runs.csv")
    assert len(again) == 1 and again[0]["max_coverage"] == rows[0]["max_coverage"]
    capsys.readouterr()
    # Another seed is another run: the demo's folder holds its own run only, so it is refused.
    assert main(["demo", "--out", str(out), "--iterations", "3", "--no-plots", "--threads", "1", "--seed", "1"]) == EXIT_BAD_INPUT
    assert "other results" in error_message(capsys.readouterr().err, "demo", tmp_path)
    assert read_runs(out / "runs.csv") == again


def test_plot_without_plotting_gives_a_clear_error(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "uavcov.plotting", None)  # import of it now raises ImportError
    assert main(["plot", str(tmp_path)]) == EXIT_BAD_INPUT
    assert "uavcov[plot]" in capsys.readouterr().err
    assert main(["plot", str(tmp_path / "missing")]) == EXIT_BAD_INPUT


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)
    return env


def test_python_dash_m_is_the_same_command(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "uavcov", "reproduce", "--help"], check=False, capture_output=True, text=True, timeout=60, env=_env()
    )
    assert done.returncode == 0
    assert "table1" in done.stdout and "--scheduler" in done.stdout and "--resume" in done.stdout


def test_ctrl_c_leaves_a_clean_runs_file_and_resume_finishes_it(tmp_path):
    # Runs of about 0.1 s each, so that the signal lands in the middle of the sweep.
    text = TINY_SWEEP.format(iterations=400).replace("seeds = [0, 1]", 'seeds = "0-5"').replace("spacing = 4.0", "spacing = 2.0")
    config = write(tmp_path / "long.toml", text)
    out = tmp_path / "out"
    command = [sys.executable, "-m", "uavcov", "sweep", str(config), "--out", str(out), "--workers", "2", "--no-progress"]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=_env())
    runs = out / "runs.csv"
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        if runs.exists() and len(read_runs(runs)) >= 2:
            break
        if process.poll() is not None:
            break
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=60)
    total = 2 * 6 * 2  # alpha0 values x seeds x starts
    rows = read_runs(runs)
    assert runs.read_bytes().endswith(b"\n")
    assert len({r["run_id"] for r in rows}) == len(rows)
    if process.returncode == EXIT_INTERRUPTED:
        assert "--resume" in err and "Traceback" not in err
        assert 2 <= len(rows) < total
    else:  # the machine was fast enough to finish before the signal landed
        assert process.returncode == EXIT_OK and len(rows) == total
    done = subprocess.run(command + ["--resume"], check=False, capture_output=True, text=True, timeout=300, env=_env())
    assert done.returncode == EXIT_OK, done.stderr
    final = read_runs(runs)
    assert len(final) == total and len({r["run_id"] for r in final}) == total


def test_plot_redraws_figures_from_a_results_directory(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    config = write(tmp_path / "tiny.toml", TINY_SWEEP.format(iterations=3).replace('"cao.alpha0" = [1.0, 2.0]', '"cao.alpha0" = [1.0]'))
    out = tmp_path / "out"
    assert main(["sweep", str(config), "--out", str(out), "--workers", "1", "--no-progress"]) == EXIT_OK
    capsys.readouterr()
    figures = tmp_path / "figures"
    assert main(["plot", str(out), "--out", str(figures), "--max-runs", "1", "--no-animation"]) == EXIT_OK
    printed = capsys.readouterr().out.split()
    assert printed and all(Path(p).is_file() and Path(p).parent == figures for p in printed)
    assert any(p.endswith(".png") for p in printed)


def test_version_and_help_texts_match_the_readme(capsys):
    """``uavcov --version`` prints the package's version; the help names what the README names."""
    import uavcov

    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == EXIT_OK
    assert capsys.readouterr().out.strip() == f"uavcov {uavcov.__version__}"
    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")
    assert "uavcov --version" in readme
    with pytest.raises(SystemExit):
        main(["view", "--help"])
    view_help = capsys.readouterr().out
    assert "--run RUN_ID" in view_help and "--run RUN_ID" in readme
    with pytest.raises(SystemExit):
        main(["plan", "--help"])
    plan_help = " ".join(capsys.readouterr().out.split())
    assert "N sparse points (default full)" in plan_help


def test_a_reader_that_goes_away_stops_the_command_without_a_word(tmp_path):
    # `uavcov demo | head -1`: the reader closes the pipe after the first line.
    command = [sys.executable, "-m", "uavcov", "demo", "--out", str(tmp_path / "demo")]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=_env())
    assert process.stdout is not None and process.stdout.readline().startswith(b"uavcov demo")
    process.stdout.close()
    _, err = process.communicate(timeout=120)
    assert process.returncode == EXIT_PIPE_CLOSED == 141
    assert err == b""


def test_a_broken_pipe_that_is_not_standard_output_is_one_line_of_error(capsys):
    from types import SimpleNamespace

    from uavcov.cli import _run

    def run(args):
        raise BrokenPipeError(32, "Broken pipe")  # as a worker's pipe would

    assert _run(SimpleNamespace(run=run, command="sweep")) == EXIT_BAD_INPUT
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "uavcov sweep: error: BrokenPipeError" in err
