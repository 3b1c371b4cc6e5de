"""Sweeps of missions: rows, seeding, executors, runs.csv, resume, failures and the tables.

Through the modules the sweep machinery now lives in: :mod:`uavcov.experiments._sweep` (experiments, run
specs, executors, run_specs), :mod:`uavcov.experiments._results` (runs.csv, config.json), :mod:`uavcov.paper._reports`
(the tables) and :mod:`uavcov.paper._jobs` (reproduce); the deprecated :mod:`uavcov.experiments` shim
is checked once, at the end.

Every sweep here is tiny (a 40 m terrain on a 4 m grid, a handful of CAO iterations) so the file
stays fast; the numbers are checked against the missions run directly, not against constants.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import time

import numpy as np
import pytest

from tiny import tiny_experiment
from uavcov import run_mission
from uavcov.errors import (
    ConfigError,
    InvalidInputError,
    ResultsFolderError,
    ResultsFormatError,
    ResultsInUseError,
    SchedulerTimeoutError,
)
from uavcov.experiments import (
    RunSpec,
    dask_executor,
    experiment_specs,
    local_executor,
    parse_seeds,
    plan_execution,
    read_runs,
    run_specs,
    summarise,
)
from uavcov.experiments._results import RUN_COLUMNS
from uavcov.experiments._sweep import execute_run, settings_hash
from uavcov.paper import _data as paper
from uavcov.paper import reproduce
from uavcov.paper._reports import table1_markdown
from uavcov.records import load_mission

TIMING = {"wall_time_s", "time_measure_s", "time_optimizer_s", "time_feasibility_s", "start_time_s"}

TINY = tiny_experiment(6, team_sizes=(2, 3))


def tiny_specs(seeds=(0, 1), sizes=(2, 3), starts=("cvt", "random", "corner")):
    return experiment_specs(TINY, seeds=seeds, team_sizes=sizes, starts=starts)


def without_timing(rows):
    return [{k: v for k, v in r.items() if k not in TIMING} for r in rows]


def test_rows_match_the_missions_run_directly():
    specs = tiny_specs(seeds=(3,), sizes=(3,))
    rows = run_specs(specs, workers=1, n_threads=1)
    assert [r["run_id"] for r in rows] == [s.run_id for s in specs]
    for spec, row in zip(specs, rows, strict=True):
        assert set(RUN_COLUMNS) <= set(row)
        # The mission of the run, through the public API: terrain ``seed``, the experiment's
        # mission for this team and start, ``rng=seed`` (run_paper_mission is gone).
        mission = TINY.mission_settings(3, spec.start)
        assert spec.mission == mission
        assert (mission.n_uavs, mission.start.kind) == (3, spec.start)
        result = run_mission(TINY.terrain.make(3), mission, known=TINY.known(3), n_threads=1, rng=3)
        assert (result.seed, result.prior_kind, result.settings.n_uavs, result.settings.start.kind) == (3, "random", 3, spec.start)
        assert row["error"] == ""
        assert row["settings_hash"] == settings_hash(TINY)
        assert (row["experiment"], row["init"], row["n_uavs"], row["seed"]) == ("table1", spec.start, 3, 3)
        assert row["sensing_range"] == 12.0 and row["iterations"] == 6
        assert row["initial_coverage"] == result.initial_coverage
        assert row["max_coverage"] == result.best_coverage == max(result.coverage)
        assert row["final_coverage"] == result.coverage[-1]
        assert row["iterations_to_95"] == result.iterations_to_95
        assert 0.0 <= row["initial_coverage"] <= row["max_coverage"] <= 1.0


def test_a_seed_gives_the_same_terrain_and_prior_for_every_team_size_and_start(tmp_path):
    specs = tiny_specs(seeds=(0, 1))
    run_specs(specs, out=tmp_path, workers=1)
    results = {s.run_id: load_mission(tmp_path / "runs" / f"{s.run_id}.npz") for s in specs}
    for seed in (0, 1):
        same_seed = [results[s.run_id] for s in specs if s.seed == seed]
        first = same_seed[0]
        for other in same_seed[1:]:
            assert np.array_equal(first.terrain.grid.z, other.terrain.grid.z)
            assert np.array_equal(first.prior_points, other.prior_points)
    z0 = results[specs[0].run_id].terrain.grid.z
    z1 = next(results[s.run_id] for s in specs if s.seed == 1).terrain.grid.z
    assert not np.array_equal(z0, z1)


def test_the_run_id_names_the_settings():
    spec = tiny_specs(seeds=(7,), sizes=(3,), starts=("random",))[0]
    assert spec.run_id.startswith("table1-random-n03-s0007-")
    changed = TINY.with_changes(**{"cao.alpha0": 0.7})
    assert settings_hash(changed) != settings_hash(TINY)
    # Seeds, team sizes and starts are the run's own; they do not change the settings' hash.
    assert settings_hash(TINY.with_changes(seeds=(5,), team_sizes=(9,))) == settings_hash(TINY)
    with pytest.raises(InvalidInputError):
        RunSpec(TINY, seed=-1, n_uavs=3, start="cvt")
    with pytest.raises(InvalidInputError):
        RunSpec(TINY, seed=0, n_uavs=3, start="pairs")


def test_process_pool_dask_and_one_process_give_the_same_numbers():
    specs = tiny_specs(seeds=(0, 1), sizes=(3,))
    serial = run_specs(specs, workers=1, n_threads=2)
    pool = run_specs(specs, workers=2, n_threads=1)
    with dask_executor(n_workers=2, timeout=30) as (executor, slots):
        assert slots == 2
        on_dask = run_specs(specs, executor=executor, n_threads=1)
    for rows in (serial, pool, on_dask):
        assert [r["error"] for r in rows] == [""] * len(specs), [r["error"] for r in rows]
    assert without_timing(serial) == without_timing(pool)
    assert without_timing(serial) == without_timing(on_dask)


def test_an_unreachable_scheduler_fails_fast_with_a_clear_error():
    started = time.perf_counter()
    with pytest.raises(SchedulerTimeoutError, match="did not answer") as error, dask_executor("tcp://127.0.0.1:9", timeout=1.0):
        pass
    assert isinstance(error.value, TimeoutError)  # except TimeoutError keeps working
    assert time.perf_counter() - started < 8.0


def test_each_run_is_in_runs_csv_as_soon_as_it_finishes(tmp_path):
    specs = tiny_specs(seeds=(0,), sizes=(2,))
    seen = []

    def check(spec, row, result):
        stored = read_runs(tmp_path / "runs.csv")
        seen.append(len(stored))
        assert stored[-1]["run_id"] == spec.run_id
        assert stored[-1]["max_coverage"] == row["max_coverage"]
        assert (tmp_path / "runs" / f"{spec.run_id}.npz").is_file()

    run_specs(specs, out=tmp_path, workers=2, n_threads=1, on_result=check)
    assert seen == [1, 2, 3]


def test_resume_runs_only_what_is_missing_and_never_duplicates(tmp_path):
    specs = tiny_specs(seeds=(0, 1), sizes=(2,))
    full = run_specs(specs, workers=1)
    run_specs(specs[:2], out=tmp_path, workers=1)
    before = (tmp_path / "runs.csv").read_bytes()
    with pytest.raises(ResultsInUseError, match="already holds 2 run") as refused:
        run_specs(specs, out=tmp_path, workers=1)
    assert "--" not in str(refused.value).replace(str(tmp_path), "")  # the library names no CLI flag
    assert (tmp_path / "runs.csv").read_bytes() == before
    ran = []
    rows = run_specs(specs, out=tmp_path, workers=1, resume=True, on_result=lambda s, r, m: ran.append(s.run_id))
    assert ran == [s.run_id for s in specs[2:]]
    stored = read_runs(tmp_path / "runs.csv")
    assert sorted(r["run_id"] for r in stored) == sorted(s.run_id for s in specs)
    assert without_timing(rows) == without_timing(full)
    # Resuming a finished sweep runs nothing.
    again = []
    run_specs(specs, out=tmp_path, workers=1, resume=True, on_result=lambda s, r, m: again.append(s))
    assert again == [] and len(read_runs(tmp_path / "runs.csv")) == len(specs)


def test_a_line_cut_off_by_a_crash_is_ignored_then_dropped_on_resume(tmp_path):
    specs = tiny_specs(seeds=(0,), sizes=(2,))
    run_specs(specs[:1], out=tmp_path, workers=1)
    with open(tmp_path / "runs.csv", "a") as handle:
        handle.write(specs[1].run_id + ",table1,random,2,0,12.0,6,0.41")  # no newline: a cut-off write
    assert [r["run_id"] for r in read_runs(tmp_path / "runs.csv")] == [specs[0].run_id]
    run_specs(specs, out=tmp_path, workers=1, resume=True)
    stored = read_runs(tmp_path / "runs.csv")
    assert sorted(r["run_id"] for r in stored) == sorted(s.run_id for s in specs)
    assert all(r["error"] == "" for r in stored)


def test_a_failing_run_is_recorded_and_the_sweep_goes_on(tmp_path):
    # A 5 x 5 lattice 3 m apart in the corner of a 12 m square does not fit: the corner start raises.
    small = TINY.with_changes(**{"terrain.size": 12.0, "d_max": 6.0, "n_prior": 4, "constraints.d_safe": 1.0})
    specs = experiment_specs(small, seeds=(0,), team_sizes=(2, 25), starts=("random", "corner"))
    rows = run_specs(specs, out=tmp_path, workers=2, n_threads=1)
    by_id = {r["run_id"]: r for r in rows}
    failed = [s for s in specs if s.n_uavs == 25 and s.start == "corner"]
    assert len(failed) == 1
    assert by_id[failed[0].run_id]["error"].startswith("InfeasibleError")
    assert by_id[failed[0].run_id]["max_coverage"] is None
    ok = [r for r in rows if r["run_id"] != failed[0].run_id]
    assert all(r["error"] == "" and r["max_coverage"] is not None for r in ok if r["n_uavs"] == 2)
    stored = read_runs(tmp_path / "runs.csv")
    assert len(stored) == len(specs)
    # rerun="failed" (the CLI's --retry-failed) runs it again (still failing), replacing its row instead of adding one.
    ran = []
    run_specs(specs, out=tmp_path, workers=1, resume=True, rerun="failed", on_result=lambda s, r, m: ran.append(s.run_id))
    assert ran == [failed[0].run_id]
    assert len(read_runs(tmp_path / "runs.csv")) == len(specs)


def test_an_interrupted_sweep_leaves_a_clean_file_and_ends_its_workers(tmp_path):
    specs = tiny_specs(seeds=(0, 1, 2), sizes=(2, 3))
    finished = []

    def interrupt(spec, row, result):
        finished.append(spec.run_id)
        if len(finished) == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_specs(specs, out=tmp_path, workers=2, n_threads=1, on_result=interrupt)
    stored = read_runs(tmp_path / "runs.csv")
    assert [r["run_id"] for r in stored] == finished
    assert (tmp_path / "runs.csv").read_bytes().endswith(b"\n")
    rows = run_specs(specs, out=tmp_path, workers=2, n_threads=1, resume=True)
    assert len(read_runs(tmp_path / "runs.csv")) == len(specs) == len(rows)


def test_an_executor_passed_in_is_used_and_left_running():
    specs = tiny_specs(seeds=(0,), sizes=(2,), starts=("cvt",))
    with local_executor(1) as pool:
        rows = run_specs(specs, executor=pool)
        assert pool.submit(int, "7").result() == 7  # still usable
    assert rows[0]["error"] == ""


def test_duplicate_runs_and_bad_execution_plans_are_refused(tmp_path):
    spec = tiny_specs(seeds=(0,), sizes=(2,), starts=("cvt",))[0]
    with pytest.raises(ConfigError, match="more than once"):
        run_specs([spec, spec], workers=1)
    with pytest.raises(ConfigError, match="exceeds"):
        plan_execution(workers=2, n_threads=2, cores=2)
    assert plan_execution(cores=2) == plan_execution(workers=2, cores=2)
    assert plan_execution(workers=1, cores=2).n_threads == 2
    blocker = tmp_path / "a-file"
    blocker.write_text("keep me")
    # A folder that cannot be written is an OSError now (ResultsFolderError), not a ConfigError.
    with pytest.raises(ResultsFolderError, match=r"cannot write|is a file") as below_a_file:
        run_specs([spec], out=blocker / "sub", workers=1)
    with pytest.raises(ResultsFolderError, match="is a file") as a_file:
        run_specs([spec], out=blocker, workers=1)
    for error in (below_a_file.value, a_file.value):
        assert isinstance(error, OSError) and not isinstance(error, ConfigError)
    assert blocker.read_text() == "keep me"


def test_read_runs_rejects_a_foreign_file(tmp_path):
    path = tmp_path / "runs.csv"
    path.write_text("a,b\n1,2\n")
    with pytest.raises(ResultsFormatError, match="run_id"):
        read_runs(path)
    with pytest.raises(ResultsFormatError):
        read_runs(tmp_path / "missing.csv")


def test_parse_seeds():
    assert parse_seeds("0-3") == (0, 1, 2, 3)
    assert parse_seeds("1000-1001,7") == (1000, 1001, 7)
    assert parse_seeds([4, 2]) == (4, 2)
    for bad in ("", "a", "3-1", "1,1", "-2", "1,,2"):
        with pytest.raises(ConfigError):
            parse_seeds(bad)


def _row(n, start, seed, initial, best):
    return {
        "run_id": f"r{n}{start}{seed}",
        "experiment": "table1",
        "init": start,
        "n_uavs": n,
        "seed": seed,
        "initial_coverage": initial,
        "max_coverage": best,
        "final_coverage": best,
        "iterations_to_95": 3,
        "error": "",
    }


def test_summaries_and_table1_against_numpy():
    rng = np.random.default_rng(0)
    rows = []
    values = {}
    for start, (mi, mm) in {"cvt": (0.59, 0.65), "random": (0.37, 0.61), "corner": (0.1, 0.57)}.items():
        initial = mi + 0.06 * rng.standard_normal(6)
        best = mm + 0.04 * rng.standard_normal(6)
        values[start] = (initial, best)
        rows += [_row(5, start, s, float(a), float(b)) for s, (a, b) in enumerate(zip(initial, best, strict=False))]
    rows.append({**_row(5, "cvt", 99, 0.0, 0.0), "max_coverage": None, "error": "InfeasibleError: no"})
    summary = summarise(rows, by=("n_uavs", "init"))
    for start, (initial, best) in values.items():
        entry = summary[(5, start)]
        assert entry["count"] == 6
        assert entry["initial_coverage"] == pytest.approx((initial.mean(), initial.std(ddof=1)))
        assert entry["max_coverage"] == pytest.approx((best.mean(), best.std(ddof=1)))
    text = table1_markdown(rows)
    cvt_initial, cvt_max = values["cvt"]
    assert f"| 5 | ours | {cvt_initial.mean():.2f} ({cvt_initial.std(ddof=1):.2f}) | {cvt_max.mean():.2f}" in text
    assert "| 5 | paper | 0.59 (0.06) | 0.65 (0.04) | 0.37 (0.07) | 0.61 (0.05) | - | 0.57 (0.09) |" in text
    c, r, k = (values[s][1].mean() for s in ("cvt", "random", "corner"))
    assert ("holds" if c > r > k else "does NOT hold") in text
    assert "1 run(s) failed" in text and "InfeasibleError" in text
    assert math.isnan(summarise(rows[:1], by=("init",))[("cvt",)]["max_coverage"][1])


def test_reproduce_writes_runs_config_and_table(tmp_path):
    rows = reproduce("pyramid", tmp_path, seeds="0-1", iterations=3, workers=1)
    assert len(rows) == 2 and all(r["error"] == "" for r in rows)
    assert {p.name for p in tmp_path.iterdir()} >= {"runs.csv", "config.json", "pyramid.md", "runs"}
    table = (tmp_path / "pyramid.md").read_text()
    assert "0.78 (0.03)" in table and "0.91 (0.02)" in table
    # config.json: settings keyed by the settings hash (label, swept values, the experiment).
    config = json.loads((tmp_path / "config.json").read_text())
    ran = paper.PYRAMID.with_changes(iterations=3)
    assert config["format"] == "uavcov.results/1" and config["command"] == "reproduce pyramid"
    assert list(config["settings"]) == [settings_hash(ran)] == sorted({r["settings_hash"] for r in rows})
    entry = config["settings"][settings_hash(ran)]
    assert entry["label"] == "pyramid" and entry["swept"] == {}
    assert entry["experiment"]["mission"]["prior"] == "pyramid"
    assert entry["experiment"]["mission"]["iterations"] == 3
    assert entry["experiment"]["terrain_kind"] == "HillsTerrain"  # the name the settings hash has always used
    assert config["runs"]["seeds"] == [0, 1]
    assert config["runs"]["count"] == 2
    before = (tmp_path / "runs.csv").read_bytes()
    with pytest.raises(ResultsInUseError, match="already holds"):
        reproduce("pyramid", tmp_path, seeds="0-1", iterations=3, workers=1)
    with pytest.raises(ResultsInUseError, match="other settings"):
        reproduce("pyramid", tmp_path, seeds="0-1", iterations=4, workers=1, resume=True)
    assert (tmp_path / "runs.csv").read_bytes() == before
    with pytest.raises(ConfigError, match="unknown experiment"):
        reproduce("table2", tmp_path)


def test_execute_run_catches_errors():
    small = TINY.with_changes(**{"terrain.size": 12.0, "d_max": 6.0, "n_prior": 4})
    row, result = execute_run(RunSpec(small, seed=0, n_uavs=25, start="corner"))
    assert result is None and row["error"].startswith("InfeasibleError") and row["wall_time_s"] >= 0


def test_a_server_that_is_not_a_scheduler_fails_fast_with_a_clear_error():
    import socket
    import threading

    server = socket.create_server(("127.0.0.1", 0))
    port = server.getsockname()[1]

    def answer_nonsense():
        server.settimeout(10)
        with contextlib.suppress(OSError):
            while True:
                connection, _ = server.accept()
                connection.sendall(b"HTTP/1.1 400 Bad Request\r\n\r\n" * 4)
                connection.close()

    thread = threading.Thread(target=answer_nonsense, daemon=True)
    thread.start()
    started = time.perf_counter()
    try:
        with pytest.raises(ConfigError, match="Dask scheduler"), dask_executor(f"tcp://127.0.0.1:{port}", timeout=2.0):
            pass
    finally:
        server.close()
    assert time.perf_counter() - started < 8.0


def test_two_sweeps_never_write_one_directory_at_once(tmp_path):
    fcntl = pytest.importorskip("fcntl")
    spec = tiny_specs(seeds=(0,), sizes=(2,), starts=("cvt",))[0]
    run_specs([spec], out=tmp_path, workers=1)  # creates the lock file, and releases it
    before = (tmp_path / "runs.csv").read_bytes()
    other = os.open(tmp_path / ".uavcov.lock", os.O_RDWR)  # another open file: another "process"
    try:
        fcntl.flock(other, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(ResultsInUseError, match="another uavcov process"):
            run_specs([spec], out=tmp_path, workers=1, resume=True, rerun="all")
        with pytest.raises(ResultsInUseError, match="another uavcov process"):
            reproduce("pyramid", tmp_path, seeds="0", iterations=1, workers=1, resume=True)
    finally:
        os.close(other)
    assert (tmp_path / "runs.csv").read_bytes() == before
    run_specs([spec], out=tmp_path, workers=1, resume=True)  # free again
