"""``uavcov reproduce structures`` (issue 42): rows, resume after kill -9, refusals."""

from __future__ import annotations

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
    families=("pylon",), report_seeds=(0,), dev_seeds=(1000,), offsets=(6.0,), iterations=3, reference_spacing=6.0, target_spacing=2.0,
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
    # The table (five 3D starts), greedy on S' against the CVT, the normal weight's gain, and
    # why each falls short.
    assert report.count("| pylon |") == 12 and report.count("| all |") == 7
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
