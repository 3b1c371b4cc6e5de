"""Kills: the pool dies with its parent, and a sweep killed at any moment resumes to the same rows
(issue 14, item 6, and the kill test it asks for).

Each sweep runs in its own process (``python -m uavcov sweep``), killed with SIGKILL: no clean-up
of ours runs. Processes are found through /proc (Linux), so the file is skipped elsewhere.
"""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tiny import TINY_TOML
from uavcov.cli import EXIT_OK, main
from uavcov.experiments import read_runs
from uavcov.records import load_mission

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc (Linux)")

SWEEP = TINY_TOML.replace('name = "tiny"', 'name = "kill"').replace("seeds = [0, 1]", 'seeds = "0-{last_seed}"')

TIMING = {"wall_time_s", "time_measure_s", "time_optimizer_s", "time_feasibility_s", "start_time_s"}


def _state(pid: int) -> str | None:
    """The /proc state letter of ``pid`` (None when it is gone)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as stat:
            return stat.read().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return None


def _alive(pid: int) -> bool:
    return _state(pid) not in (None, "Z", "X")  # a zombie has stopped running: only its entry is left


def _children(pid: int) -> list[int]:
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat", encoding="ascii") as stat:
                    parent = int(stat.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            if parent == pid:
                found.append(int(entry))
    return found


def _cmdline(pid: int) -> str:
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as handle:
            return handle.read().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return ""


def _sweep(config: Path, out: Path, *extra: str) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        [sys.executable, "-m", "uavcov", "sweep", str(config), "--out", str(out), "--no-progress", *extra],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )


def _rows_on_disk(out: Path) -> int:
    path = out / "runs.csv"
    return len(read_runs(path)) if path.exists() else 0


def _wait_for_rows(out: Path, rows: int, process: subprocess.Popen[bytes], timeout: float = 60.0) -> None:
    """Return once ``out/runs.csv`` holds ``rows`` rows, or the sweep has ended, or at ``timeout``."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and process.poll() is None:
        try:
            if _rows_on_disk(out) >= rows:
                return
        except (OSError, ValueError):
            pass  # caught mid-write: look again
        time.sleep(0.01)


def test_pool_workers_and_resource_tracker_die_with_a_killed_parent(tmp_path):
    config = tmp_path / "long.toml"
    config.write_text(SWEEP.format(last_seed=5, iterations=2000), encoding="utf-8")
    parent = _sweep(config, tmp_path / "out", "--workers", "2", "--threads", "1")
    try:
        deadline = time.monotonic() + 60
        workers: list[int] = []
        while time.monotonic() < deadline:
            kids = _children(parent.pid)
            workers = [k for k in kids if "spawn_main" in _cmdline(k)]
            if len(workers) == 2 and any("resource_tracker" in _cmdline(k) for k in kids):
                break
            time.sleep(0.05)
        kids = _children(parent.pid)
        assert len(workers) == 2, [_cmdline(k) for k in kids]
        tracker = [k for k in kids if "resource_tracker" in _cmdline(k)]
        assert tracker, [_cmdline(k) for k in kids]
        time.sleep(0.5)  # the workers are inside their first runs
    finally:
        parent.send_signal(signal.SIGKILL)
        parent.wait()
    orphans = workers + tracker
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(_alive(pid) for pid in orphans):
        time.sleep(0.05)
    left = {pid: _cmdline(pid) for pid in orphans if _alive(pid)}
    for pid in left:  # do not leave them behind for the rest of the suite
        os.kill(pid, signal.SIGKILL)
    assert not left, f"still running 10 s after their parent was killed: {left}"


def test_a_sweep_killed_at_random_moments_resumes_to_the_same_rows(tmp_path):
    config = tmp_path / "kill.toml"
    config.write_text(SWEEP.format(last_seed=9, iterations=150), encoding="utf-8")
    reference = tmp_path / "reference"
    assert main(["sweep", str(config), "--out", str(reference), "--workers", "1", "--no-progress"]) == EXIT_OK
    expected = {r["run_id"]: r for r in read_runs(reference / "runs.csv")}
    assert len(expected) == 20

    out = tmp_path / "killed"
    rng = random.Random(14)
    kills = 0
    for round_number in range(6):
        workers = ["--workers", "2", "--threads", "1"] if round_number % 2 else ["--workers", "1"]
        done = _rows_on_disk(out)
        process = _sweep(config, out, *workers, *(["--resume"] if out.exists() else []))
        # The moment is set by progress, not by the clock, so a faster engine still dies mid-sweep:
        # 0 more rows is a kill during start-up, k rows a kill after the k-th, plus a random slice
        # of the next run (so some kills fall while a row is being written).
        _wait_for_rows(out, done + rng.randint(0, 2), process)
        time.sleep(rng.uniform(0.0, 0.1))
        if process.poll() is None:
            process.send_signal(signal.SIGKILL)
            kills += 1
        process.wait()
        if (out / "runs.csv").exists():
            rows = read_runs(out / "runs.csv")  # readable after every kill: a cut last line is ignored
            assert len({r["run_id"] for r in rows}) == len(rows)
    assert kills == 6  # every round dies mid-sweep: it stops after at most a few new rows of the 20
    finish = _sweep(config, out, "--workers", "1", *(["--resume"] if out.exists() else []))
    assert finish.wait(timeout=120) == EXIT_OK

    rows = read_runs(out / "runs.csv")
    assert sorted(r["run_id"] for r in rows) == sorted(expected)  # exactly one row per run
    for row in rows:
        want = expected[row["run_id"]]
        assert {k: v for k, v in row.items() if k not in TIMING} == {k: v for k, v in want.items() if k not in TIMING}
        assert not row["error"]
    for run_id, want in expected.items():
        stored = load_mission(out / "runs" / f"{run_id}.npz")
        assert stored.best_coverage == want["max_coverage"] and stored.final_coverage == want["final_coverage"]
    assert not [p.name for p in (out / "runs").iterdir() if p.name.startswith(".")]  # no leftover of a cut save
    assert (out / "summary.md").exists() and (out / "config.json").exists()


_POOL_SCRIPT = r"""
import sys, threading, time
from uavcov.experiments._executors import local_executor

futures = []

def start():
    pool = local_executor(1)
    futures.append((pool, pool.submit(time.sleep, 600)))

if sys.argv[1] == "main":
    start()
else:  # made and used by a thread that then ends: the worker must outlive that thread
    thread = threading.Thread(target=start)
    thread.start()
    thread.join()
time.sleep(2.0)
print("running" if futures[0][1].running() else "not running", flush=True)
time.sleep(600)
"""


@pytest.mark.parametrize("where", ["main", "thread"])
def test_a_pool_made_anywhere_dies_with_its_killed_parent(where):
    parent = subprocess.Popen([sys.executable, "-c", _POOL_SCRIPT, where], stdout=subprocess.PIPE, text=True)
    try:
        assert parent.stdout is not None
        assert parent.stdout.readline().strip() == "running"  # not killed with the thread that started it
        workers = [k for k in _children(parent.pid) if "spawn_main" in _cmdline(k)]
        assert len(workers) == 1
    finally:
        parent.send_signal(signal.SIGKILL)
        parent.wait()
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(_alive(pid) for pid in workers):
        time.sleep(0.05)
    left = [pid for pid in workers if _alive(pid)]
    for pid in left:
        os.kill(pid, signal.SIGKILL)
    assert not left
