"""uavcov.paper._jobs.reproduce_all: every experiment into its folder, one report naming its settings."""

from __future__ import annotations

import dataclasses

import pytest

from uavcov.errors import ConfigError
from uavcov.experiments import experiments_hash, read_runs
from uavcov.paper import _data as paper
from uavcov.paper import _jobs as jobs


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("all")
    results = jobs.reproduce_all(out, seeds=[0], iterations=2, figures=None, workers=1, n_threads=1)
    return out, results


def test_every_experiment_has_its_folder_and_the_report_names_the_settings(quick):
    out, results = quick
    assert set(results) == {*paper.EXPERIMENTS, "ablation"}
    for name, experiment in paper.EXPERIMENTS.items():
        rows = read_runs(out / name / "runs.csv")
        assert len(rows) == len(experiment.team_sizes) * len(experiment.starts) == len(results[name])
        assert not any(r["error"] for r in rows)
    report = (out / "report.md").read_text(encoding="utf-8")
    assert f"`uavcov.paper.EXPERIMENTS` {experiments_hash(paper.EXPERIMENTS)}" in report
    for heading in (
        "## Table 1",
        "## The paper's claims on Table 1",
        "## Pyramid prior",
        "## Illustrative example",
        "## Single-scenario comparison",
        "## Buildings scene",
        "## Ablations",
    ):
        assert heading in report
    assert "with seeds [0] and 2 CAO iterations" in report
    # each experiment's own table is in the report, one heading level down
    table1 = (out / "table1" / "table1.md").read_text(encoding="utf-8")
    assert table1.splitlines()[2] in report
    # Table 1 against the oracle's certified bound, greedy on S' beside the paper's starts
    from uavcov.paper._bounds import read_bounds

    bounds = read_bounds(out / "table1" / "bounds.csv")
    assert [(b.seed, b.n_uavs) for b in bounds] == [(0, n) for n in paper.TABLE1.team_sizes]
    assert all(b.coverage <= b.bound == min(b.online_bound, b.dual_bound) <= 1.0 for b in bounds)
    assert "## Table 1 against the certified bound" in report and "greedy max / bound" in report
    greedy = [r for r in read_runs(out / "table1" / "runs.csv") if r["init"] == "greedy"]
    assert len(greedy) == 4 and all(r["start_time_s"] > 0 for r in greedy)


def test_the_ablation_runs_each_change_beside_the_papers_model(quick):
    from uavcov.experiments import ResultsFolder
    from uavcov.records import load_mission

    out, results = quick
    rows = results["ablation"]
    labels = ["ablation", *(f"ablation-{a.name}" for a in paper.ABLATIONS)]
    assert sorted({r["experiment"] for r in rows}) == sorted(labels)
    per_variant = len(paper.ABLATION_BASE.team_sizes) * len(paper.ABLATION_BASE.starts)
    assert len(rows) == per_variant * len(labels) and not any(r["error"] for r in rows)
    # one settings hash per variant: each runs its own change, and the base is Table 1's model
    hashes = {r["experiment"]: r["settings_hash"] for r in rows}
    assert len(set(hashes.values())) == len(labels)
    folder = ResultsFolder(out / "ablation")
    by_label = {r["experiment"]: r for r in rows if r["init"] == "corner" and r["n_uavs"] == 12}
    base = load_mission(folder.run_file(by_label["ablation"]["run_id"]))
    assert base.settings.constraints == paper.TABLE1.mission_settings(12, "corner").constraints.resolve(base.terrain)
    assert load_mission(folder.run_file(by_label["ablation-no-ceiling"]["run_id"])).settings.constraints.h_max is None
    assert load_mission(folder.run_file(by_label["ablation-noise"]["run_id"])).settings.cao.measurement_noise == 0.015
    assert load_mission(folder.run_file(by_label["ablation-corner-launch"]["run_id"])).settings.start.corner_altitude == 8.0
    table = (out / "ablation" / "ablation.md").read_text(encoding="utf-8")
    assert table.count("\n| ") == len(labels) + 1  # the header and one line per variant
    for change in paper.ABLATIONS:
        assert change.what in table


def test_the_settings_hash_follows_every_setting_of_the_paper():
    base = experiments_hash(paper.EXPERIMENTS)
    assert base == experiments_hash(dict(paper.EXPERIMENTS)) and len(base) == 8
    changed = dict(paper.EXPERIMENTS, table1=paper.TABLE1.with_changes(**{"cao.alpha0": 2.9}))
    assert experiments_hash(changed) != base
    fewer = dict(paper.EXPERIMENTS, comparison=dataclasses.replace(paper.COMPARISON, seeds=(0, 1)))
    assert experiments_hash(fewer) != base


def test_the_many_scenario_claims_run_more_than_the_papers_single_scenario():
    assert jobs.REPORT_SEEDS["comparison"] == paper.HELD_OUT_SEEDS and len(jobs.REPORT_SEEDS["buildings"]) >= 20
    with pytest.raises(ConfigError, match="unknown experiment"):
        jobs.reproduce("everything", "unused")


def test_the_command_line_runs_all_and_refuses_a_choice_within_one(tmp_path, capsys):
    from uavcov.cli import EXIT_BAD_INPUT, EXIT_OK, main

    args = ["reproduce", "all", "--out", str(tmp_path / "all"), "--seeds", "0", "--iterations", "1", "--no-plots", "--workers", "1"]
    assert main(args) == EXIT_OK
    assert (tmp_path / "all" / "report.md").is_file() and (tmp_path / "all" / "buildings" / "buildings.md").is_file()
    assert main([*args, "--team-sizes", "5"]) == EXIT_BAD_INPUT
    errors = [line for line in capsys.readouterr().err.splitlines() if "error:" in line]
    assert len(errors) == 1 and "not with all" in errors[0]


def test_the_command_line_runs_the_ablation_and_refuses_a_choice_within_it(tmp_path, capsys):
    from uavcov.cli import EXIT_BAD_INPUT, EXIT_OK, main

    args = ["reproduce", "ablation", "--out", str(tmp_path / "ab"), "--seeds", "0", "--iterations", "1", "--no-plots", "--workers", "1"]
    assert main(args) == EXIT_OK
    table = (tmp_path / "ab" / "ablation.md").read_text(encoding="utf-8")
    assert all(change.what in table for change in paper.ABLATIONS)
    assert "the paper's model" in capsys.readouterr().out  # the table is printed too
    assert main([*args[:3], str(tmp_path / "other"), "--starts", "cvt"]) == EXIT_BAD_INPUT
    errors = [line for line in capsys.readouterr().err.splitlines() if "error:" in line]
    assert len(errors) == 1 and "not with ablation" in errors[0]
    assert main(["reproduce", "ablation", "--out", str(tmp_path / "bad"), "--seeds", "x-y"]) == EXIT_BAD_INPUT
