"""``uavcov reproduce structures`` (issue 42): rows, resume after kill -9, refusals."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import pytest

from uavcov.errors import ConfigError
from uavcov.paper import StructuresExperiment, reproduce_structures
from uavcov.paper._structures_report import paired_interval

SMALL = StructuresExperiment(
    families=("pylon",),
    report_seeds=(0,),
    dev_seeds=(1000,),
    offsets=(6.0,),
    iterations=3,
    trace_iterations=12,
    reference_spacing=6.0,
    target_spacing=2.0,
    greedy_spacings=(6.0,),
    normal_weights=(0.0, 10.0),
    cao_steps=(0.75, 1.5),
)
CHILD = """
import sys
from uavcov.paper import StructuresExperiment, reproduce_structures
experiment = StructuresExperiment(
    families=("pylon",), report_seeds=(0,), dev_seeds=(1000,), offsets=(6.0,), iterations=3, trace_iterations=12,
    reference_spacing=6.0, target_spacing=2.0,
    greedy_spacings=(6.0,), normal_weights=(0.0, 10.0), cao_steps=(0.75, 1.5),
)
reproduce_structures(sys.argv[1], experiment, workers=1)
"""


def _without_time(rows: list[dict]) -> list[dict]:
    return [{k: v for k, v in r.items() if k != "time_s"} for r in rows]


def test_resume_after_kill_9_gives_the_rows_of_an_uninterrupted_run(tmp_path: Path) -> None:
    whole = reproduce_structures(tmp_path / "whole", SMALL)
    assert len(whole) == 7 and not any(r["error"] for r in whole)
    assert {r["start"] for r in whole} == {"cvt3d", "cvt3d_paper", "cvt_hf", "greedy3d", "cvt_true", "greedy_true", "greedy"}
    # The diagnostics take the settings chosen on S' and run on the report seed only; the
    # paper's CVT is the one without a normal weight.
    settings = {r["start"]: (r["offset"], r["spacing"], r["normal_weight"], r["cao_step"]) for r in whole}
    assert settings["cvt_true"] == settings["cvt3d"] and settings["greedy_true"] == settings["greedy3d"]
    assert settings["greedy3d"][:3] == (6.0, 6.0, 0.0) and settings["cvt3d_paper"][:3] == (6.0, 0.0, 0.0)
    assert {s[3] for s in settings.values()} <= {0.75, 1.5}
    cut = tmp_path / "cut"
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(cut)])
    rows = cut / "rows.jsonl"
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and child.poll() is None:
        if rows.exists() and rows.read_text(encoding="utf-8").count("\n") >= 2:
            break
        time.sleep(0.05)
    if child.poll() is None:
        os.kill(child.pid, signal.SIGKILL)
    child.wait()
    finished = rows.read_text(encoding="utf-8").count("\n")
    assert finished >= 1
    # A line torn by the kill is dropped on resume, and its run runs again.
    with rows.open("a", encoding="utf-8") as handle:
        handle.write('{"family": "pylon", "start": "cvt3')
    resumed = reproduce_structures(cut, SMALL, resume=True)
    assert _without_time(resumed) == _without_time(whole)
    report = (cut / "structures.md").read_text(encoding="utf-8")
    # The table (five 3D starts), greedy on S' against the CVT, the normal weight's gain, why
    # each falls short, and the best after 3, 10 and 12 iterations.
    assert report.count("| pylon |") == 15 and report.count("| all |") == 10
    # Every row says which parts it saw; greedy's also each part's share of the targets.
    assert all(r["parts"] for r in resumed)
    weights = next(r for r in resumed if r["start"] == "greedy")["part_weights"]
    assert abs(sum(weights.values()) - 1.0) < 1e-12


def test_a_used_folder_needs_resume_and_the_same_settings(tmp_path: Path) -> None:
    reproduce_structures(tmp_path, SMALL)
    with pytest.raises(ConfigError, match="resume"):
        reproduce_structures(tmp_path, SMALL)
    other = replace(SMALL, iterations=4)
    with pytest.raises(ConfigError, match="other settings"):
        reproduce_structures(tmp_path, other, resume=True)


@pytest.mark.parametrize(
    "bad",
    [
        {"families": ("castle",)},
        {"families": ()},
        {"report_seeds": (1000,)},
        {"offsets": ()},
        {"offsets": (float("nan"),)},
        {"greedy_spacings": ()},
        {"greedy_spacings": (0.0,)},
        {"greedy_spacings": (-2.0,)},
        {"normal_weights": ()},
        {"normal_weights": (-1.0,)},
        {"normal_weights": (1e300,)},
        {"cao_steps": ()},
        {"cao_steps": (0.0,)},
        {"cao_steps": (float("inf"),)},
        {"trace_iterations": 50},
    ],
)
def test_bad_settings_are_config_errors(bad: dict) -> None:
    with pytest.raises(ConfigError):
        StructuresExperiment(**bad)


def test_the_paired_interval_is_the_t_interval() -> None:
    mean, low, high = paired_interval([0.8, 0.9, 0.85, 0.95], [0.7, 0.8, 0.8, 0.8])
    # By hand: differences 0.1, 0.1, 0.05, 0.15; sd 0.0408; t(0.975, 3) = 3.182.
    assert mean == pytest.approx(0.1)
    assert high - mean == pytest.approx(3.182446 * 0.0408248 / 2, rel=1e-4)
    assert low == pytest.approx(2 * mean - high)


def test_flying_on_leaves_the_rows_after_iterations_unchanged(tmp_path: Path) -> None:
    """The report missions fly on to trace_iterations; what they record after ``iterations``
    (best, parts, initial) is what a mission stopped there records, and ``best_at`` agrees with
    it at every checkpoint both reached."""
    short = reproduce_structures(tmp_path / "short", replace(SMALL, trace_iterations=3))
    long = reproduce_structures(tmp_path / "long", SMALL)
    missions = [(a, b) for a, b in zip(short, long, strict=True) if a["start"] != "greedy"]
    assert len(missions) == 6
    for a, b in missions:
        assert (a["start"], a["best"], a["parts"], a["initial"]) == (b["start"], b["best"], b["parts"], b["initial"])
        assert set(a["best_at"]) == {"0", "3"} and set(b["best_at"]) == {"0", "3", "10", "12"}
        assert a["best_at"]["3"] == b["best_at"]["3"] == b["best"]
        values = [b["best_at"][k] for k in ("0", "3", "10", "12")]
        assert values == sorted(values) and values[0] <= b["initial"] + 1e-12
    # The development missions stop at ``iterations``.
    rows = (tmp_path / "long" / "rows.jsonl").read_text(encoding="utf-8").splitlines()
    dev = [json.loads(line) for line in rows if '"seed": 1000' in line]
    assert dev and all(set(r["best_at"]) == {"0", "3"} for r in dev)


def test_a_dask_cluster_gives_the_rows_of_one_process(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    from uavcov.experiments import dask_executor

    serial = reproduce_structures(tmp_path / "serial", SMALL)
    with dask_executor(n_workers=2, timeout=30) as (executor, _):
        on_dask = reproduce_structures(tmp_path / "dask", SMALL, executor=executor)
    pooled = reproduce_structures(tmp_path / "pool", SMALL, workers=2)
    assert _without_time(on_dask) == _without_time(serial) == _without_time(pooled)


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--workers", "2", "--dask-workers", "1"], "--workers is for the local process pool"),
        (["--scheduler", "not an address"], "Dask scheduler"),
        (["--scheduler", "tcp://127.0.0.1:0"], "Dask scheduler"),
    ],
)
def test_the_command_refuses_a_mixed_or_bad_cluster_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str], argv, words) -> None:
    pytest.importorskip("distributed")
    from uavcov.cli import main

    code = main(["reproduce", "structures", "--out", str(tmp_path / "out"), *argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and words in err[0], err
    assert not (tmp_path / "out").exists()  # refused before any folder is made


@pytest.mark.parametrize(
    "bad",
    [
        {"workers": 0},
        {"workers": -2},
        {"workers": "2"},
        {"workers": True},
        {"workers": 2.5},
        {"executor": "pool"},
        {"executor": object()},
        {"resume": "yes"},
        {"experiment": 3},
        {"progress": 5},
    ],
)
def test_bad_run_options_are_refused_before_any_run(tmp_path: Path, bad: dict) -> None:
    """Refused with uavcov.errors before a folder is made (``workers=0`` once ran the whole
    default experiment in this process)."""
    from uavcov.errors import InvalidInputError, InvalidTypeError

    with pytest.raises((InvalidInputError, InvalidTypeError)):
        reproduce_structures(tmp_path / "out", **bad)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "config, rows",
    [
        ("{not json", None),
        ("[1, 2]", None),
        ('{"experiment": "structures", "settings": {"colour": "red"}}', None),
        (None, "3\n"),
        (None, '{"family": "pylon"}\n'),
        (None, '{"family": "pylon", "start": "cvt3d", "seed": "x", "offset": 6}\n'),
    ],
)
def test_a_corrupt_folder_is_a_results_format_error(tmp_path: Path, config, rows) -> None:
    from uavcov.errors import ResultsFormatError
    from uavcov.paper._structures import report_from_folder

    folder = tmp_path / "run"
    reproduce_structures(folder, replace(SMALL, trace_iterations=3))
    if config is not None:
        (folder / "config.json").write_text(config, encoding="utf-8")
    if rows is not None:
        with (folder / "rows.jsonl").open("a", encoding="utf-8") as handle:
            handle.write(rows)
    with pytest.raises(ResultsFormatError):
        report_from_folder(folder)
    if config is not None:  # a resume reads the same config: unreadable, or not this experiment's
        with pytest.raises((ResultsFormatError, ConfigError)):
            reproduce_structures(folder, replace(SMALL, trace_iterations=3), resume=True)


def test_rows_without_their_config_are_refused(tmp_path: Path) -> None:
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "rows.jsonl").write_text('{"family": "pylon"}\n', encoding="utf-8")
    with pytest.raises(ConfigError, match=r"without their config\.json"):
        reproduce_structures(folder, SMALL, resume=True)


@pytest.mark.parametrize("kind", ["fifo", "folder"])
def test_a_config_that_is_no_file_is_refused_before_it_is_read(tmp_path: Path, kind: str) -> None:
    """A FIFO named config.json blocked a resume's read forever; a folder is no config either."""
    import os

    from uavcov.errors import ResultsFormatError
    from uavcov.paper._structures import report_from_folder

    folder = tmp_path / "run"
    folder.mkdir()
    if kind == "fifo":
        os.mkfifo(folder / "config.json")
    else:
        (folder / "config.json").mkdir()
    with pytest.raises(ResultsFormatError, match="not a regular file" if kind == "fifo" else "is a directory"):
        reproduce_structures(folder, SMALL, resume=True)
    with pytest.raises(ResultsFormatError, match="not a regular file" if kind == "fifo" else "is a directory"):
        report_from_folder(folder)
