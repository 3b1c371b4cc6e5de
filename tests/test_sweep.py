"""The guarantees of the restructured upper floors: uavcov.experiments._sweep, uavcov.paper._jobs, the results folder.

* every command (reproduce, sweep, demo) runs through :func:`uavcov.experiments._sweep.run_specs` and writes
  the one ``config.json`` schema;
* a folder holding runs of other settings is refused on resume, even without its config.json,
  and nothing in it changes; ``exclusive=True`` refuses a folder holding other runs;
* library errors name no command-line flag;
* :meth:`Experiment.with_changes` refuses the ``flight.<key>`` names of earlier releases;
* the same specs give the same rows on one process, on a process pool and run directly.

Everything is tiny (a 4-5 m grid, a few iterations) so the file stays fast.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from tiny import tiny_experiment
from uavcov.cli import EXIT_OK, main
from uavcov.errors import (
    ConfigError,
    InvalidInputError,
    InvalidTypeError,
    ResultsFolderError,
    ResultsInUseError,
    UavcovError,
)
from uavcov.experiments import (
    Experiment,
    ResultsFolder,
    RunSpec,
    experiment_specs,
    parse_seeds,
    parse_sweep_config,
    plan_execution,
    read_runs,
    run_specs,
    run_sweep,
)
from uavcov.experiments._results import CONFIG_FORMAT, RUN_COLUMNS
from uavcov.experiments._sweep import settings_hash
from uavcov.paper import EXPERIMENTS as PAPER_EXPERIMENTS
from uavcov.paper import _data as paper
from uavcov.paper import _jobs as jobs
from uavcov.paper._reports import REPORTS
from uavcov.records import load_mission

TIMING = {"wall_time_s", "time_measure_s", "time_optimizer_s", "time_feasibility_s", "start_time_s"}

# The brief's small Table 1: the paper's settings on a 4 m grid, 3 iterations.
SMALL = paper.TABLE1.with_changes(**{"terrain.spacing": 4.0, "iterations": 3})

# Smaller still, for the folder tests: a 40 m terrain, 2 UAVs.
TINY = tiny_experiment(2)

TINY_SWEEP = {
    "name": "tiny",
    "seeds": [0],
    "team_sizes": [2],
    "starts": ["cvt", "random"],
    "d_max": 12.0,
    "n_prior": 8,
    "iterations": 2,
    "terrain": {"size": 40.0, "spacing": 4.0, "heights": [2.0, 8.0], "sigma": 6.0},
    "cao": {"n_candidates": 20},
    "cvt": {"samples_per_iteration": 400, "max_iterations": 20},
}


def without_timing(rows):
    return [{k: v for k, v in r.items() if k not in TIMING} for r in rows]


def tiny_specs(experiment=TINY, seeds=(0,), sizes=(2,), starts=("cvt", "random")):
    return experiment_specs(experiment, seeds=seeds, team_sizes=sizes, starts=starts)


def files(directory):
    return {str(p.relative_to(directory)): p.read_bytes() for p in sorted(directory.rglob("*")) if p.is_file()}


def flagless(error, tmp_path) -> str:
    text = str(error).replace(str(tmp_path), "<tmp>")
    assert "--" not in text, text
    return text


# ---------------------------------------------------------------------------------------------
# Identical rows however they are run


def test_the_same_specs_give_the_same_rows_in_one_process_on_a_pool_and_run_directly(tmp_path):
    specs = experiment_specs(SMALL, seeds=[0, 1], team_sizes=[5], starts=["cvt", "random", "corner"])
    serial = run_specs(specs, out=tmp_path / "one", workers=1, n_threads=1)
    pool = run_specs(specs, out=tmp_path / "pool", workers=2, n_threads=1)
    assert [r["error"] for r in serial + pool] == [""] * 2 * len(specs)
    assert without_timing(serial) == without_timing(pool)
    # What each folder holds reads back as the rows returned (exactly: floats round-trip).
    for name, rows in (("one", serial), ("pool", pool)):
        stored = {r["run_id"]: r for r in read_runs(tmp_path / name / "runs.csv")}
        assert [stored[s.run_id] for s in specs] == rows
    for spec, row in zip(specs, serial, strict=True):
        direct = spec.run(n_threads=1)
        assert row["initial_coverage"] == direct.initial_coverage
        assert row["max_coverage"] == direct.best_coverage
        assert row["final_coverage"] == direct.final_coverage
        assert (row["best_iteration"], row["iterations_to_95"], row["evaluations"]) == (
            direct.best_iteration,
            direct.iterations_to_95,
            direct.evaluations,
        )
        assert (direct.seed, direct.settings.n_uavs, direct.settings.start.kind) == (spec.seed, 5, spec.start)
        for name in ("one", "pool"):
            saved = load_mission(tmp_path / name / "runs" / f"{spec.run_id}.npz")
            np.testing.assert_array_equal(saved.coverage, direct.coverage)
            np.testing.assert_array_equal(saved.trajectory, direct.trajectory)


def test_reproduce_writes_its_report_from_what_the_folder_reads_back(tmp_path):
    rows = jobs.reproduce("example", tmp_path, iterations=2, workers=1, n_threads=1)
    (spec,) = experiment_specs(paper.EXAMPLE.with_changes(iterations=2))
    assert [r["run_id"] for r in rows] == [spec.run_id]
    direct = spec.run(n_threads=1)
    assert rows[0]["max_coverage"] == direct.best_coverage and rows[0]["n_uavs"] == 9
    stored = read_runs(tmp_path / "runs.csv")
    assert stored == rows
    assert (tmp_path / "example.md").read_text() == REPORTS["example"](stored)
    # A resume returns the stored rows: the same report, the same coverage curves.
    curves = (tmp_path / "coverage.csv").read_bytes()
    again = jobs.reproduce("example", tmp_path, iterations=2, workers=1, resume=True)
    assert again == stored
    assert (tmp_path / "example.md").read_text() == REPORTS["example"](stored)
    assert (tmp_path / "coverage.csv").read_bytes() == curves


# ---------------------------------------------------------------------------------------------
# One config.json schema


def test_reproduce_sweep_and_demo_write_the_one_config_schema(tmp_path, capsys):
    jobs.reproduce("pyramid", tmp_path / "reproduce", seeds=[0], iterations=1, workers=1, n_threads=1)
    run_sweep(
        parse_sweep_config({**TINY_SWEEP, "sweep": {"cao.alpha0": [1.0, 2.0]}}, bases=PAPER_EXPERIMENTS), tmp_path / "sweep", workers=1
    )
    assert main(["demo", "--out", str(tmp_path / "demo"), "--iterations", "1", "--no-plots", "--threads", "1"]) == EXIT_OK
    capsys.readouterr()
    configs = {name: json.loads((tmp_path / name / "config.json").read_text()) for name in ("reproduce", "sweep", "demo")}
    keys = {"format", "command", "uavcov_version", "settings", "runs", "execution", "about"}
    for name, config in configs.items():
        assert set(config) == keys, name
        assert config["format"] == CONFIG_FORMAT == "uavcov.results/1"
        assert set(config["runs"]) == {"seeds", "team_sizes", "starts", "count"}, name
        hashes = {r["settings_hash"] for r in read_runs(tmp_path / name / "runs.csv")}
        assert set(config["settings"]) == hashes, name
        for entry in config["settings"].values():
            assert set(entry) == {"label", "swept", "experiment"}, name
            assert {"terrain", "mission", "terrain_kind"} <= set(entry["experiment"]), name
    assert [configs[n]["command"] for n in ("reproduce", "sweep", "demo")] == ["reproduce pyramid", "sweep", "demo"]
    assert configs["sweep"]["about"]["axes"] == ["cao.alpha0"]
    assert sorted(e["swept"]["cao.alpha0"] for e in configs["sweep"]["settings"].values()) == [1.0, 2.0]
    assert configs["demo"]["runs"]["count"] == 1 and configs["demo"]["runs"]["team_sizes"] == [9]


# ---------------------------------------------------------------------------------------------
# Resume, exclusive: refused, and nothing changes


def test_resume_with_other_settings_is_refused_even_without_config_json(tmp_path):
    run_specs(tiny_specs(), out=tmp_path, workers=1)
    (tmp_path / "config.json").unlink()
    before = files(tmp_path)
    other = tiny_specs(TINY.with_changes(**{"cao.alpha0": 0.5}))
    assert settings_hash(other[0].experiment) != settings_hash(TINY)
    for rerun in ("none", "failed", "all"):
        with pytest.raises(ResultsInUseError, match="other settings") as refused:
            run_specs(other, out=tmp_path, workers=1, resume=True, rerun=rerun)
        assert settings_hash(TINY) in flagless(refused.value, tmp_path)
        assert files(tmp_path) == before  # nothing appended, dropped or written (no config.json either)
    # The same through reproduce: another iteration count is another setting.
    jobs.reproduce("example", tmp_path / "example", iterations=1, workers=1, save_runs=False)
    (tmp_path / "example" / "config.json").unlink()
    before = files(tmp_path / "example")
    with pytest.raises(ResultsInUseError, match="other settings"):
        jobs.reproduce("example", tmp_path / "example", iterations=2, workers=1, resume=True, save_runs=False)
    assert files(tmp_path / "example") == before


def test_resume_with_the_same_settings_adds_only_the_missing_runs(tmp_path):
    specs = tiny_specs(seeds=(0, 1))
    run_specs(specs[:1], out=tmp_path, workers=1)
    (tmp_path / "config.json").unlink()  # not needed to resume: runs.csv names the settings
    ran = []
    run_specs(specs, out=tmp_path, workers=1, resume=True, on_result=lambda s, r, m: ran.append(s.run_id))
    assert ran == [s.run_id for s in specs[1:]]
    assert sorted(r["run_id"] for r in read_runs(tmp_path / "runs.csv")) == sorted(s.run_id for s in specs)
    assert json.loads((tmp_path / "config.json").read_text())["runs"]["count"] == len(specs)


def test_a_refused_rerun_deletes_nothing(tmp_path):
    # The same runs (same label, same experiment, same run ids), recorded once as a plain sweep
    # and once as a sweep over a single d_max value: config.json's settings differ ("swept").
    plain = parse_sweep_config(TINY_SWEEP, bases=PAPER_EXPERIMENTS)
    swept = parse_sweep_config({**TINY_SWEEP, "sweep": {"d_max": [12.0]}}, bases=PAPER_EXPERIMENTS)
    assert [s.run_id for s in plain.specs()] == [s.run_id for s in swept.specs()]
    run_sweep(plain, tmp_path, workers=1)
    before = read_runs(tmp_path / "runs.csv")
    with pytest.raises(ResultsInUseError, match=r"another kind of sweep|other settings"):
        run_sweep(swept, tmp_path, workers=1, resume=True, rerun="all")
    assert read_runs(tmp_path / "runs.csv") == before


def test_exclusive_refuses_a_folder_with_other_runs(tmp_path):
    first, second = tiny_specs()
    run_specs([first], out=tmp_path, workers=1)
    before = files(tmp_path)
    with pytest.raises(ResultsInUseError, match="other results") as refused:
        run_specs([second], out=tmp_path, workers=1, resume=True, exclusive=True)
    assert first.run_id in flagless(refused.value, tmp_path)
    with pytest.raises(ResultsInUseError, match="other results"):
        run_specs([second], out=tmp_path, workers=1, resume=True, rerun="all", exclusive=True)
    assert files(tmp_path) == before
    # Without exclusive the same resume adds the run; with it, the folder's own runs are fine.
    run_specs([first, second], out=tmp_path, workers=1, resume=True, exclusive=True)
    run_specs([first, second], out=tmp_path, workers=1, resume=True, rerun="all", exclusive=True)
    assert sorted(r["run_id"] for r in read_runs(tmp_path / "runs.csv")) == sorted([first.run_id, second.run_id])
    # Through reproduce too (the demo's folder holds its own run only).
    with pytest.raises(ResultsInUseError, match="other results"):
        jobs.reproduce("example", tmp_path, iterations=1, workers=1, resume=True, exclusive=True)


# ---------------------------------------------------------------------------------------------
# Error types and messages


def test_error_types_of_the_results_folder(tmp_path):
    spec = tiny_specs(starts=("cvt",))[0]
    blocker = tmp_path / "a-file"
    blocker.write_text("keep me")
    for out in (blocker, blocker / "sub"):
        with pytest.raises(ResultsFolderError) as error:
            run_specs([spec], out=out, workers=1)
        assert isinstance(error.value, OSError) and isinstance(error.value, UavcovError)
        flagless(error.value, tmp_path)
        with pytest.raises(OSError, match=r"is a file|cannot write"):
            jobs.reproduce("example", out, iterations=0, workers=1)
    assert blocker.read_text() == "keep me"
    fcntl = pytest.importorskip("fcntl")
    import os

    folder = ResultsFolder(tmp_path / "locked")
    other = os.open(folder.path / ".uavcov.lock", os.O_RDWR | os.O_CREAT)
    try:
        fcntl.flock(other, fcntl.LOCK_EX | fcntl.LOCK_NB)
        for call in (
            lambda: run_specs([spec], out=folder.path, workers=1),
            lambda: jobs.reproduce("example", folder.path, iterations=0, workers=1),
            lambda: run_sweep(parse_sweep_config(TINY_SWEEP, bases=PAPER_EXPERIMENTS), folder.path, workers=1),
        ):
            with pytest.raises(ResultsInUseError, match="another uavcov process") as error:
                call()
            assert isinstance(error.value, ConfigError)
            flagless(error.value, tmp_path)
    finally:
        os.close(other)
    assert not folder.runs_csv.exists()


def test_library_messages_name_no_command_line_flag(tmp_path):
    spec = tiny_specs(starts=("cvt",))[0]
    run_specs([spec], out=tmp_path, workers=1)
    failures = [
        lambda: run_specs([spec], out=tmp_path, workers=1),  # holds runs, no resume
        lambda: run_specs(tiny_specs(TINY.with_changes(iterations=1), starts=("cvt",)), out=tmp_path, resume=True),
        lambda: run_specs([spec, spec], workers=1),
        lambda: run_specs([spec], rerun="some"),
        lambda: plan_execution(workers=2, n_threads=2, cores=2),
        lambda: plan_execution(workers=0),
        lambda: parse_seeds("3-1"),
        lambda: jobs.reproduce("table2", tmp_path),
        lambda: jobs.reproduce("example", tmp_path, iterations=-1),
        lambda: jobs.reproduce("example", tmp_path, starts=["corner"]),
        lambda: jobs.reproduce("example", tmp_path, team_sizes=[0]),
        lambda: parse_sweep_config({"iteratoins": 3}, bases=PAPER_EXPERIMENTS),
    ]
    for failure in failures:
        with pytest.raises(UavcovError) as error:
            failure()
        flagless(error.value, tmp_path)


# ---------------------------------------------------------------------------------------------
# Experiment.with_changes


def test_the_flight_group_of_earlier_releases_is_refused():
    with pytest.raises(InvalidInputError):
        paper.TABLE1.with_changes(**{"flight.h_min": 2.0})
    assert paper.TABLE1.with_changes(**{"constraints.h_min": 2.0}).mission.constraints.h_min == 2.0


@pytest.mark.filterwarnings("ignore:the flight group is deprecated:DeprecationWarning")
def test_with_changes_shortcuts_and_unknown_names():
    e = paper.TABLE1
    assert e.with_changes(d_max=20.0) == e.with_changes(**{"mission.d_max": 20.0})
    assert e.with_changes(d_max=20.0).d_max == 20.0
    assert e.with_changes(iterations=7).iterations == 7 == e.with_changes(iterations=7).mission.iterations
    assert e.with_changes(**{"cao.alpha0": 1.5}).mission.cao.alpha0 == 1.5
    assert e.with_changes(**{"start.altitude": 4.0}).mission.start.altitude == 4.0
    assert e.with_changes(prior="pyramid").prior == "pyramid" == e.with_changes(prior="pyramid").mission.prior
    assert e.with_changes(**{"terrain.spacing": 4.0}).terrain.spacing == 4.0
    assert paper.BUILDINGS.with_changes(prior="map") == paper.BUILDINGS and paper.BUILDINGS.prior == "map"
    assert e.with_changes() == e
    for bad in (
        {"flight.nope": 1.0},
        {"flight.kind": "cvt"},
        {"nope": 1.0},
        {"terrain.nope": 1.0},
        {"mission.nope": 1.0},
        {"cao.nope": 1.0},
        {"start.nope": 1.0},
        {"constraints.nope": 1.0},
        {"d_max.x": 1.0},
        {"prior": "bogus"},
        {"prior": "map"},  # hills: no map to know
    ):
        with pytest.raises(InvalidInputError):
            e.with_changes(**bad)


def test_a_bad_random_altitude_is_an_invalid_input_error():
    with pytest.raises(InvalidInputError, match="random_altitude"):
        paper.TABLE1.with_changes(**{"start.random_altitude": 7.0})


def test_experiment_checks_its_fields():
    with pytest.raises(InvalidTypeError):
        Experiment("x", terrain="hills", mission=paper.TABLE1.mission, team_sizes=(5,), starts=("cvt",))
    with pytest.raises(InvalidInputError):
        paper.TABLE1.with_changes(team_sizes=(0,))
    with pytest.raises(InvalidInputError):
        paper.TABLE1.with_changes(starts=("cvtt",))
    with pytest.raises(InvalidInputError):
        paper.TABLE1.mission_settings(5, "pairs")
    spec = paper.TABLE1.mission_settings(8, "random")
    assert (spec.n_uavs, spec.start.kind) == (8, "random")
    assert paper.TABLE1.known(0) is None
    assert paper.BUILDINGS.known(0) is not None


def test_a_workers_runs_on_one_terrain_share_it_and_answer_as_on_a_fresh_one():
    """Runs keep the last terrain made (the objectives of one surface share its skylines)."""
    from uavcov import run_mission

    experiment = paper.TABLE1.with_changes(**{"terrain.spacing": 2.0, "iterations": 12})
    specs = experiment_specs(experiment, seeds=[7], team_sizes=[5], starts=["cvt", "random", "corner"])
    kept = [spec.run(n_threads=1) for spec in specs]
    assert kept[0].terrain is kept[1].terrain is kept[2].terrain
    for spec, result in zip(specs, kept, strict=True):
        fresh = run_mission(experiment.terrain.make(7), spec.mission, n_threads=1, rng=7)
        assert fresh.terrain is not result.terrain
        np.testing.assert_array_equal(fresh.coverage, result.coverage)
        np.testing.assert_array_equal(fresh.trajectory, result.trajectory)


def test_run_spec_rows_and_ids():
    spec = RunSpec(TINY, seed=3, n_uavs=2, start="random", extra=(("cao.alpha0", 1.0),))
    row = spec.row_template()
    assert list(row)[: len(RUN_COLUMNS)] == list(RUN_COLUMNS) and row["cao.alpha0"] == 1.0
    assert row["settings_hash"] == settings_hash(TINY) and spec.run_id.endswith(settings_hash(TINY))
    assert spec.run_id == f"table1-random-n02-s0003-{settings_hash(TINY)}"
    assert RunSpec(TINY, 3, 2, "random", label="a b/c").run_id.startswith("a_b_c-random-")
    assert settings_hash(TINY.with_changes(seeds=(9,), team_sizes=(7,), starts=("cvt",))) == settings_hash(TINY)
    assert settings_hash(TINY.with_changes(name="other")) == settings_hash(TINY)


def test_a_sweep_file_starts_from_the_bases_it_is_given():
    """experiments knows no paper: the caller gives the bases, and a sweep without ``base`` starts from the first."""
    own = {"mine": tiny_experiment(), **PAPER_EXPERIMENTS}
    config = parse_sweep_config({"team_sizes": [2]}, bases=own)
    assert config.base == "mine" and config.variants[0][0].terrain == own["mine"].terrain
    assert parse_sweep_config({}, bases=PAPER_EXPERIMENTS).base == "table1"
    with pytest.raises(ConfigError, match="base"):
        parse_sweep_config({"base": "table1"}, bases={"mine": tiny_experiment()})
    for bad in (None, {}, {"mine": 1}, [tiny_experiment()], "table1"):
        with pytest.raises(InvalidTypeError, match="bases"):
            parse_sweep_config({}, bases=bad)
