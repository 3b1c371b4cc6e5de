"""The paper's experiments and any sweep of missions, run on a ``concurrent.futures`` executor.

A sweep is a list of :class:`RunSpec`: one mission of a :class:`~uavcov.paper.PaperExperiment`
(every setting of the experiment, frozen) for one scenario seed, one team size and one start.
:func:`run_specs` runs such a list on a local process pool (spawn context), a Dask cluster
(:func:`dask_executor`) or any executor you pass, and returns one row per run (a ``dict`` with
the columns of :data:`RUN_COLUMNS`). With ``out=DIR`` it also

* appends each row to ``DIR/runs.csv`` the moment its run finishes (flushed and synced), so an
  interrupted sweep loses nothing and ``resume=True`` skips finished runs without duplicating
  one;
* records a run that raises with its error (column ``error``) and goes on;
* saves each run's whole result with :func:`uavcov.records.save_mission` as
  ``DIR/runs/<run_id>.npz`` (``save_runs=False`` for huge sweeps).

:func:`reproduce` runs one of the paper's experiments end to end and writes the Markdown tables
beside the paper's numbers (``table1.md``, ``pyramid.md``, ...) and the resolved configuration
(``config.json``).

Seeds: every run is a pure function of its settings and its seed
-----------------------------------------------------------------
A run is :func:`uavcov.paper.run_paper_mission` ``(experiment, seed=s, n_uavs=N, start=...)``:

* the true surface is drawn with ``rng=s`` from the experiment's terrain settings alone, so the
  same seed gives the same terrain for every team size, every start and every experiment that
  shares the terrain settings (Table 1 and the pyramid compare on the same 40 terrains);
* the buildings scene's simplified map is drawn with ``numpy.random.default_rng([s, 1])``;
* the mission runs with ``rng=s``: it spawns three independent child generators (``numpy``
  ``SeedSequence.spawn``) for the prior samples, the start and the optimiser, so every team size
  and start on one terrain sees the same prior points.

Nothing depends on the executor, on the order runs finish in, or on the Rust thread count (the
coverage is a count of seen targets, summed in a fixed order), so the same specs give the same
numbers on a process pool, on Dask and in one process.

Threads: a run uses ``n_threads`` Rust threads for its coverage measurements; :func:`run_specs`
picks ``max(1, cores // workers)`` and refuses ``workers * n_threads`` beyond the cores (the
local pool), since oversubscribed threads only slow every run down.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import csv
import dataclasses
import hashlib
import io
import json
import math
import multiprocessing
import os
import signal
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator, Mapping, Sequence

import numpy as np

from . import paper
from .errors import ConfigError, InvalidInputError, InvalidTypeError, ResultsFormatError
from .mission import MissionResult
from .paper import PaperExperiment

__all__ = [
    "RUN_COLUMNS",
    "RunSpec",
    "ExecutionPlan",
    "experiment_specs",
    "settings_hash",
    "execute_run",
    "run_specs",
    "read_runs",
    "available_cores",
    "plan_execution",
    "local_executor",
    "dask_executor",
    "reproduce",
    "REPRODUCIBLE",
    "summarise",
    "table1_markdown",
    "pyramid_markdown",
    "comparison_markdown",
    "buildings_markdown",
    "example_markdown",
    "parse_seeds",
    "prepare_out_dir",
    "out_dir_lock",
    "write_config",
    "paper_experiments",
]

RUN_COLUMNS: tuple[str, ...] = (
    "run_id",
    "experiment",
    "init",
    "n_uavs",
    "seed",
    "sensing_range",
    "iterations",
    "initial_coverage",
    "max_coverage",
    "final_coverage",
    "best_iteration",
    "iterations_to_95",
    "evaluations",
    "wall_time_s",
    "time_measure_s",
    "time_optimizer_s",
    "time_feasibility_s",
    "settings_hash",
    "error",
)
"""Columns of ``runs.csv``, in order; a sweep adds one column per swept setting after these.

``run_id`` names the run (:attr:`RunSpec.run_id`); ``experiment`` is its label, ``init`` its
start, ``sensing_range`` is d_max (m); ``initial_coverage``, ``max_coverage`` (the best reached),
``final_coverage`` are shares of the surface; ``best_iteration`` and ``iterations_to_95`` (first
iteration at 95 % of the best) count CAO iterations; ``wall_time_s`` is the whole mission and
``time_measure_s``, ``time_optimizer_s``, ``time_feasibility_s`` its coverage measurements, the
optimiser's own work and the constraint checks (the rest is prior, S', CVT and start);
``settings_hash`` is :func:`settings_hash`; ``error`` is empty for a run that finished.
"""

_INT_COLUMNS = frozenset({"n_uavs", "seed", "iterations", "best_iteration", "iterations_to_95", "evaluations"})
_FLOAT_COLUMNS = frozenset(
    {
        "sensing_range",
        "initial_coverage",
        "max_coverage",
        "final_coverage",
        "wall_time_s",
        "time_measure_s",
        "time_optimizer_s",
        "time_feasibility_s",
    }
)

REPRODUCIBLE: tuple[str, ...] = ("table1", "pyramid", "example", "comparison", "buildings")
"""The experiments :func:`reproduce` knows."""


def paper_experiments() -> Mapping[str, PaperExperiment]:
    """The paper's experiments with their chosen settings, by name (:data:`uavcov.paper.EXPERIMENTS`).

    The one place this module reads the calibrated settings, so that a change of
    :mod:`uavcov.paper` reaches every command.
    """
    return paper.EXPERIMENTS


# ---------------------------------------------------------------------------------------------
# Run specifications


def settings_hash(experiment: PaperExperiment) -> str:
    """Eight hex digits that change with any setting of ``experiment`` a run depends on.

    The name, the seeds, the team sizes and the starts are left out: a run names its own seed,
    team size and start, so adding seeds or team sizes to an experiment keeps the identity of
    the runs already made (``--resume`` then runs only the new ones).
    """
    if not isinstance(experiment, PaperExperiment):
        raise InvalidTypeError(f"experiment must be a PaperExperiment, got {type(experiment).__name__}")
    settings = dataclasses.asdict(experiment)
    for key in ("name", "seeds", "team_sizes", "starts"):
        settings.pop(key, None)
    settings["terrain_kind"] = type(experiment.terrain).__name__
    text = json.dumps(settings, sort_keys=True, default=_json_default)
    return hashlib.sha256(text.encode()).hexdigest()[:8]


def _json_default(value: Any) -> Any:
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (np.floating,)):
        return float(value)
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"cannot write {type(value).__name__} as JSON")


def _is_int(value: Any) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


@dataclass(frozen=True)
class RunSpec:
    """One mission of a sweep: an experiment's settings, a seed, a team size and a start.

    Attributes
    ----------
    experiment : PaperExperiment
        Every setting of the run (terrain, prior, sensing range, iterations, flight, CAO, CVT).
    seed : int
        The scenario (>= 0); see the module notes for what it seeds.
    n_uavs : int
        Team size (> 0).
    start : str
        One of ``experiment.starts``.
    label : str
        The ``experiment`` column of ``runs.csv``; ``experiment.name`` by default.
    extra : tuple of (str, value)
        Extra columns of the row (a sweep writes the values of its swept settings here).
    """

    experiment: PaperExperiment
    seed: int
    n_uavs: int
    start: str
    label: str = ""
    extra: tuple[tuple[str, Any], ...] = ()

    def __post_init__(self) -> None:
        if not isinstance(self.experiment, PaperExperiment):
            raise InvalidTypeError(f"experiment must be a PaperExperiment, got {type(self.experiment).__name__}")
        if not _is_int(self.seed) or self.seed < 0:
            raise InvalidInputError(f"seed must be an integer >= 0, got {self.seed!r}")
        if not _is_int(self.n_uavs) or self.n_uavs < 1:
            raise InvalidInputError(f"n_uavs must be an integer >= 1, got {self.n_uavs!r}")
        if self.start not in self.experiment.starts:
            raise InvalidInputError(
                f"start must be one of {self.experiment.starts} for {self.experiment.name}, got {self.start!r}"
            )
        object.__setattr__(self, "seed", int(self.seed))
        object.__setattr__(self, "n_uavs", int(self.n_uavs))
        object.__setattr__(self, "label", self.label or self.experiment.name)
        object.__setattr__(self, "extra", tuple((str(k), v) for k, v in self.extra))

    @property
    def settings_hash(self) -> str:
        """:func:`settings_hash` of the experiment."""
        return settings_hash(self.experiment)

    @property
    def run_id(self) -> str:
        """A name unique to the run's settings, seed, team size and start, safe as a file name.

        ``<label>-<start>-n<N>-s<seed>-<settings hash>``, e.g. ``table1-cvt-n05-s0003-1a2b3c4d``.
        """
        label = "".join(c if c.isalnum() or c in "._-" else "_" for c in self.label)
        return f"{label}-{self.start}-n{self.n_uavs:02d}-s{self.seed:04d}-{self.settings_hash}"

    def row_template(self) -> dict[str, Any]:
        """The row of this run with every result column empty."""
        # None where a result is missing, as read_runs gives back an empty cell.
        row: dict[str, Any] = {name: None for name in RUN_COLUMNS}
        row["error"] = ""
        row.update(
            run_id=self.run_id,
            experiment=self.label,
            init=self.start,
            n_uavs=self.n_uavs,
            seed=self.seed,
            sensing_range=float(self.experiment.d_max),
            iterations=int(self.experiment.iterations),
            settings_hash=self.settings_hash,
        )
        row.update(dict(self.extra))
        return row

    def run(self, n_threads: int | None = 1) -> MissionResult:
        """Run the mission (:func:`uavcov.paper.run_paper_mission`)."""
        return paper.run_paper_mission(
            self.experiment, seed=self.seed, n_uavs=self.n_uavs, start=self.start, n_threads=n_threads
        )


def experiment_specs(
    experiment: PaperExperiment,
    *,
    seeds: Iterable[int] | None = None,
    team_sizes: Iterable[int] | None = None,
    starts: Iterable[str] | None = None,
    label: str | None = None,
    extra: Sequence[tuple[str, Any]] = (),
) -> list[RunSpec]:
    """Every run of ``experiment``: seeds x team sizes x starts (the experiment's own by default).

    Runs are ordered seed-major, so an interrupted sweep has whole scenarios done.
    """
    if not isinstance(experiment, PaperExperiment):
        raise InvalidTypeError(f"experiment must be a PaperExperiment, got {type(experiment).__name__}")
    seeds = tuple(experiment.seeds if seeds is None else seeds)
    team_sizes = tuple(experiment.team_sizes if team_sizes is None else team_sizes)
    starts = tuple(experiment.starts if starts is None else starts)
    for name, values in (("seeds", seeds), ("team_sizes", team_sizes), ("starts", starts)):
        if not values:
            raise InvalidInputError(f"{name} is empty: the sweep has no run")
    unknown = [s for s in starts if s not in experiment.starts]
    if unknown:
        raise InvalidInputError(f"starts {unknown} are not starts of {experiment.name} {experiment.starts}")
    return [
        RunSpec(experiment, seed, n, start, label=label or experiment.name, extra=tuple(extra))
        for seed in seeds
        for n in team_sizes
        for start in starts
    ]


# ---------------------------------------------------------------------------------------------
# One run


def _one_line(text: str) -> str:
    return " | ".join(part.strip() for part in str(text).splitlines() if part.strip())


def execute_run(spec: RunSpec, n_threads: int | None = 1, keep_result: bool = True) -> tuple[dict[str, Any], MissionResult | None]:
    """Run one spec and return its row (and the result, unless ``keep_result`` is False).

    This is the function the executors run. It never raises for a failing mission: the row then
    carries ``error = "<ExceptionType>: <message>"`` and the result is None.
    """
    row = spec.row_template()
    started = time.perf_counter()
    try:
        result = spec.run(n_threads=n_threads)
    except Exception as exc:  # a failing run is recorded; the sweep goes on
        row["error"] = _one_line(f"{type(exc).__name__}: {exc}")
        row["wall_time_s"] = time.perf_counter() - started
        return row, None
    row.update(
        initial_coverage=float(result.initial_coverage),
        max_coverage=float(result.best_coverage),
        final_coverage=float(result.final_coverage),
        best_iteration=int(result.best_iteration),
        iterations_to_95=int(result.iterations_to_95),
        evaluations=int(result.evaluations),
        wall_time_s=float(result.wall_time_s),
        time_measure_s=float(result.time_measure_s),
        time_optimizer_s=float(result.time_optimizer_s),
        time_feasibility_s=float(result.trace.time_feasibility),
    )
    return row, (result if keep_result else None)


# ---------------------------------------------------------------------------------------------
# runs.csv


def _format(value: Any) -> str:
    if isinstance(value, float):
        return repr(value)  # round-trips exactly
    if isinstance(value, (list, tuple)):
        return json.dumps(list(value))
    return "" if value is None else str(value)


def _csv_line(values: Sequence[Any]) -> str:
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow([_format(v) for v in values])
    return buffer.getvalue()


def _parse(name: str, text: str) -> Any:
    if text == "":
        return None if name != "error" else ""
    if name in _INT_COLUMNS:
        return int(text)
    if name in _FLOAT_COLUMNS:
        return float(text)
    return text


def _complete_lines(path: Path) -> tuple[str, int]:
    """The text of ``path`` up to its last newline, and the byte length of that part."""
    data = path.read_bytes()
    end = data.rfind(b"\n") + 1
    return data[:end].decode("utf-8"), end


def read_runs(path: str | os.PathLike[str]) -> list[dict[str, Any]]:
    """Read a ``runs.csv``: one ``dict`` per run, numbers as numbers, empty cells as None.

    A last line without its newline (a write cut off by a crash) is ignored: every complete row
    is returned. Columns beyond :data:`RUN_COLUMNS` (swept settings) come back as strings.

    Raises
    ------
    ResultsFormatError
        No such file, or its header lacks a column of :data:`RUN_COLUMNS`.
    """
    path = Path(path)
    if not path.is_file():
        raise ResultsFormatError(f"no runs file at {path}")
    text, _ = _complete_lines(path)
    reader = csv.reader(io.StringIO(text))
    header = next(reader, None)
    if header is None:
        return []
    missing = [c for c in RUN_COLUMNS if c not in header]
    if missing:
        raise ResultsFormatError(f"{path} is not a uavcov runs file: it lacks the column(s) {', '.join(missing)}")
    rows = []
    for line_number, cells in enumerate(reader, start=2):
        if len(cells) != len(header):
            raise ResultsFormatError(f"{path}, line {line_number}: {len(cells)} cells for {len(header)} columns")
        rows.append({name: _parse(name, cell) for name, cell in zip(header, cells)})
    return rows


class _RunsFile:
    """``runs.csv`` opened for appending one complete line per finished run."""

    def __init__(self, path: Path, columns: Sequence[str]) -> None:
        self.path = path
        self.columns = list(columns)
        fresh = not path.exists() or path.stat().st_size == 0
        if not fresh:
            text, end = _complete_lines(path)
            header = next(csv.reader(io.StringIO(text)), None)
            if header != self.columns:
                raise ConfigError(
                    f"{path} has the columns {header}, this sweep writes {self.columns}: "
                    "it holds another kind of sweep; choose another --out"
                )
            if end != path.stat().st_size:
                # A line cut off by a crash: drop it (its run was not finished) before appending.
                with open(path, "r+b") as handle:
                    handle.truncate(end)
        self.handle = open(path, "a", encoding="utf-8", newline="")
        if fresh:
            self._write(_csv_line(self.columns))

    def _write(self, line: str) -> None:
        self.handle.write(line)
        self.handle.flush()
        os.fsync(self.handle.fileno())

    def append(self, row: Mapping[str, Any]) -> None:
        self._write(_csv_line([row.get(c, "") for c in self.columns]))

    def close(self) -> None:
        self.handle.close()


def _rewrite_without(path: Path, drop: set[str]) -> None:
    """Rewrite ``runs.csv`` atomically without the rows whose run_id is in ``drop``."""
    text, _ = _complete_lines(path)
    lines = text.splitlines(keepends=True)
    if not lines:
        return
    header = next(csv.reader(io.StringIO(lines[0])))
    index = header.index("run_id")
    kept = [lines[0]]
    for line in io.StringIO("".join(lines[1:])):
        cells = next(csv.reader(io.StringIO(line)))
        if cells[index] not in drop:
            kept.append(line)
    _atomic_write(path, "".join(kept))


def _atomic_write(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=path.suffix)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as out:
            out.write(text)
            out.flush()
            os.fsync(out.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


# ---------------------------------------------------------------------------------------------
# Output directory and configuration


def prepare_out_dir(out: str | os.PathLike[str]) -> Path:
    """Create ``out`` if needed and check that files can be written there.

    Raises
    ------
    ConfigError
        ``out`` is a file, cannot be created, or is not writable. Nothing in it is touched.
    """
    path = Path(out)
    if path.exists() and not path.is_dir():
        raise ConfigError(f"--out {path} is a file, not a directory")
    try:
        path.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(dir=path, prefix=".write-test-")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise ConfigError(f"cannot write to --out {path}: {exc.strerror or exc}") from exc
    return path


_HELD_LOCKS: dict[Path, tuple[int, int]] = {}


@contextlib.contextmanager
def out_dir_lock(out: Path | None) -> Iterator[None]:
    """Hold ``out/.uavcov.lock`` so that two sweeps never write one directory at once.

    An advisory ``flock``: the system drops it when the process dies, so a crash leaves no stale
    lock. Re-entrant within one process. Does nothing for ``out=None`` or where ``fcntl`` is
    missing (Windows).

    Raises
    ------
    ConfigError
        Another process holds the lock.
    """
    if out is None:
        yield
        return
    try:
        import fcntl
    except ImportError:  # no advisory locks here; the sweep runs unguarded
        yield
        return
    key = out.resolve()
    if key in _HELD_LOCKS:
        fd, depth = _HELD_LOCKS[key]
        _HELD_LOCKS[key] = (fd, depth + 1)
        try:
            yield
        finally:
            fd, depth = _HELD_LOCKS[key]
            _HELD_LOCKS[key] = (fd, depth - 1)
        return
    fd = os.open(key / ".uavcov.lock", os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        raise ConfigError(f"another uavcov process is writing to {out}; wait for it or choose another --out") from None
    _HELD_LOCKS[key] = (fd, 1)
    try:
        yield
    finally:
        del _HELD_LOCKS[key]
        os.close(fd)  # closing the descriptor releases the lock


def write_config(out: Path, config: Mapping[str, Any], *, resume: bool) -> Path:
    """Write the resolved configuration as ``out/config.json`` (atomically).

    On ``resume``, an existing ``config.json`` must describe the same settings (its ``"settings"``
    entry; seeds, team sizes and execution may differ): results of two configurations are never
    mixed in one directory.

    Raises
    ------
    ConfigError
        The directory holds results of other settings.
    """
    path = out / "config.json"
    if path.exists():
        try:
            previous = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError):
            previous = None
        if previous is not None and resume:
            old = json.dumps(previous.get("settings"), sort_keys=True, default=_json_default)
            new = json.dumps(config.get("settings"), sort_keys=True, default=_json_default)
            if old != new:
                raise ConfigError(
                    f"{out} holds results of other settings (see {path}); resume them with the same settings, "
                    "or choose another --out"
                )
    _atomic_write(path, json.dumps(config, indent=2, sort_keys=True, default=_json_default) + "\n")
    return path


# ---------------------------------------------------------------------------------------------
# Executors


def available_cores() -> int:
    """Cores this process may run on (the affinity mask, not the machine's count)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


@dataclass(frozen=True)
class ExecutionPlan:
    """How many runs go at once and how many Rust threads each gets.

    ``workers * n_threads`` never exceeds the cores of the machine for local execution.
    """

    workers: int
    n_threads: int


def plan_execution(workers: int | None = None, n_threads: int | None = None, cores: int | None = None) -> ExecutionPlan:
    """Resolve ``workers`` and ``n_threads`` for ``cores`` cores (this machine's by default).

    ``workers`` defaults to every core (capped at 1 when ``n_threads`` fills the machine);
    ``n_threads`` to ``max(1, cores // workers)``.

    Raises
    ------
    ConfigError
        Not positive integers, or ``workers * n_threads`` above the cores.
    """
    cores = available_cores() if cores is None else cores
    for name, value in (("workers", workers), ("threads", n_threads)):
        if value is not None and (not _is_int(value) or value < 1):
            raise ConfigError(f"--{name} must be an integer >= 1, got {value!r}")
    if workers is None:
        workers = max(1, cores // (n_threads or 1))
    if n_threads is None:
        n_threads = max(1, cores // workers)
    if workers * n_threads > cores:
        raise ConfigError(
            f"{workers} workers x {n_threads} threads = {workers * n_threads} exceeds the {cores} cores: "
            "oversubscribed threads slow every run down; lower --workers or --threads"
        )
    return ExecutionPlan(int(workers), int(n_threads))


def _ignore_sigint() -> None:
    # Ctrl-C is the parent's to handle: it stops the sweep, then ends the workers itself.
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def local_executor(workers: int) -> cf.ProcessPoolExecutor:
    """A process pool of ``workers`` processes started with the spawn context.

    Spawn, not fork: a forked child would inherit the parent's Rust thread pools in a state it
    cannot use, and spawn behaves the same on every platform.
    """
    return cf.ProcessPoolExecutor(
        max_workers=workers, mp_context=multiprocessing.get_context("spawn"), initializer=_ignore_sigint
    )


def _stop_pool(executor: cf.Executor) -> None:
    """Shut a pool down now: cancel what has not started and end our own worker processes."""
    executor.shutdown(wait=False, cancel_futures=True)
    processes = getattr(executor, "_processes", None) or {}
    for process in list(processes.values()):
        with contextlib.suppress(Exception):
            process.terminate()
    for process in list(processes.values()):
        with contextlib.suppress(Exception):
            process.join(timeout=5)


@contextlib.contextmanager
def dask_executor(
    scheduler: str | None = None, n_workers: int | None = None, *, timeout: float = 10.0
) -> Iterator[tuple[cf.Executor, int]]:
    """A ``concurrent.futures`` executor on a Dask cluster (the ``uavcov[distributed]`` extra).

    Parameters
    ----------
    scheduler : str, optional
        Address of a running scheduler (``tcp://host:8786``).
    n_workers : int, optional
        Without ``scheduler``: start a local cluster of this many worker processes, one thread
        each (every core by default).
    timeout : float
        Seconds to wait for the scheduler before giving up.

    Yields
    ------
    (executor, slots)
        The executor, and how many runs the cluster runs at once (its worker threads).

    Raises
    ------
    ConfigError
        Dask is not installed, or the scheduler does not answer within ``timeout``.
    """
    try:
        import logging

        from distributed import Client, LocalCluster
    except ImportError as exc:
        raise ConfigError(f"Dask is not installed: pip install 'uavcov[distributed]' ({exc})") from exc
    cluster = None
    try:
        if scheduler is not None:
            try:
                client = Client(scheduler, timeout=f"{timeout}s", set_as_default=False)
            except (OSError, TimeoutError) as exc:
                raise ConfigError(f"the Dask scheduler at {scheduler} did not answer within {timeout:g} s: {exc}") from exc
            except Exception as exc:  # a bad address, or something that is not a Dask scheduler answered
                raise ConfigError(f"cannot use {scheduler!r} as a Dask scheduler: {type(exc).__name__}: {exc}") from exc
        else:
            workers = available_cores() if n_workers is None else n_workers
            if not _is_int(workers) or workers < 1:
                raise ConfigError(f"--dask-workers must be an integer >= 1, got {workers!r}")
            cluster = LocalCluster(
                n_workers=int(workers),
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                silence_logs=logging.ERROR,
            )
            client = Client(cluster, set_as_default=False)
        try:
            slots = max(1, sum(client.nthreads().values()))
            yield client.get_executor(), slots
        finally:
            client.close()
    finally:
        if cluster is not None:
            cluster.close()


# ---------------------------------------------------------------------------------------------
# Running a list of specs


def _progress_bar(total: int, enabled: bool | None) -> Any:
    if enabled is None:
        enabled = sys.stderr.isatty()
    if not enabled or total == 0:
        return None
    try:
        from tqdm import tqdm  # type: ignore[import-untyped]
    except ImportError:
        return None
    return tqdm(total=total, unit="run", dynamic_ncols=True, smoothing=0.05)


def _runs_path(out: Path) -> Path:
    return out / "runs.csv"


def run_specs(
    specs: Sequence[RunSpec],
    *,
    out: str | os.PathLike[str] | None = None,
    executor: cf.Executor | None = None,
    workers: int | None = None,
    n_threads: int | None = None,
    resume: bool = False,
    rerun: str = "none",
    save_runs: bool = True,
    progress: bool | None = None,
    on_result: Callable[[RunSpec, dict[str, Any], MissionResult | None], None] | None = None,
) -> list[dict[str, Any]]:
    """Run every spec and return one row per spec, in the order of ``specs``.

    Parameters
    ----------
    specs : sequence of RunSpec
        The runs (run ids must be unique).
    out : path, optional
        Directory for ``runs.csv`` and ``runs/<run_id>.npz``; nothing is written without it.
    executor : concurrent.futures.Executor, optional
        Where the runs go (e.g. from :func:`dask_executor`); it is not shut down here. Without
        it: one run at a time in this process when ``workers`` is 1, else a spawn process pool
        of ``workers`` processes made (and ended) here.
    workers, n_threads : int, optional
        Runs at once and Rust threads per run (see :func:`plan_execution`). With an
        ``executor``, ``n_threads`` defaults to 1.
    resume : bool
        Skip the specs whose run id is already in ``out/runs.csv`` (their stored rows are
        returned). Without it, an ``out`` whose ``runs.csv`` holds rows is refused.
    rerun : {"none", "failed", "all"}
        With ``resume``: run again the stored runs that failed, or every stored run of ``specs``
        (their old rows are removed first, so no run is ever listed twice).
    save_runs : bool
        Save each result as ``out/runs/<run_id>.npz``.
    progress : bool, optional
        A progress bar with ETA on stderr (tqdm); by default only when stderr is a terminal.
    on_result : callable, optional
        Called in this process as ``on_result(spec, row, result)`` after each finished run
        (``result`` is None for a failed run).

    Returns
    -------
    list of dict
        One row per spec with the columns of :data:`RUN_COLUMNS` plus each spec's ``extra``.

    Raises
    ------
    ConfigError
        ``out`` not writable or holding rows without ``resume``, duplicate run ids, or a bad
        ``workers`` / ``n_threads``.
    KeyboardInterrupt
        After Ctrl-C, once pending runs are cancelled and the workers ended; every finished run
        is already in ``runs.csv``.

    Examples
    --------
    >>> from uavcov import paper
    >>> from uavcov.experiments import experiment_specs, run_specs
    >>> small = paper.TABLE1.with_changes(**{"terrain.spacing": 4.0, "iterations": 5})
    >>> rows = run_specs(experiment_specs(small, seeds=[0], team_sizes=[5], starts=["cvt"]), workers=1)
    >>> rows[0]["init"], 0.0 < rows[0]["initial_coverage"] <= 1.0
    ('cvt', True)
    """
    specs = list(specs)
    for spec in specs:
        if not isinstance(spec, RunSpec):
            raise InvalidTypeError(f"specs must be RunSpec objects, got {type(spec).__name__}")
    if rerun not in ("none", "failed", "all"):
        raise InvalidInputError(f"rerun must be 'none', 'failed' or 'all', got {rerun!r}")
    ids = [s.run_id for s in specs]
    if len(set(ids)) != len(ids):
        duplicates = sorted({i for i in ids if ids.count(i) > 1})
        raise ConfigError(f"the sweep lists the same run more than once: {', '.join(duplicates[:5])}")
    if executor is None:
        plan = plan_execution(workers, n_threads)
    else:
        plan = ExecutionPlan(workers or 1, n_threads or 1)

    extra_columns: list[str] = []
    for spec in specs:
        for key, _ in spec.extra:
            if key not in extra_columns and key not in RUN_COLUMNS:
                extra_columns.append(key)
    columns = list(RUN_COLUMNS) + extra_columns
    out_path = None if out is None else prepare_out_dir(out)
    with out_dir_lock(out_path):
        return _run_locked(specs, columns, plan, out_path, executor, resume, rerun, save_runs, progress, on_result)


def _run_locked(
    specs: list[RunSpec],
    columns: list[str],
    plan: ExecutionPlan,
    out_path: Path | None,
    executor: cf.Executor | None,
    resume: bool,
    rerun: str,
    save_runs: bool,
    progress: bool | None,
    on_result: Callable[[RunSpec, dict[str, Any], MissionResult | None], None] | None,
) -> list[dict[str, Any]]:
    """The body of :func:`run_specs`, once its arguments are checked and ``out`` is locked."""
    ids = [s.run_id for s in specs]
    done: dict[str, dict[str, Any]] = {}
    runs_file: _RunsFile | None = None
    if out_path is not None:
        csv_path = _runs_path(out_path)
        stored = read_runs(csv_path) if csv_path.exists() else []
        if stored and not resume:
            raise ConfigError(
                f"{csv_path} already holds {len(stored)} run(s): pass --resume to continue that sweep, "
                "or choose another --out (nothing was changed)"
            )
        wanted = set(ids)
        drop = set()
        if rerun == "all":
            drop = {r["run_id"] for r in stored if r["run_id"] in wanted}
        elif rerun == "failed":
            drop = {r["run_id"] for r in stored if r["run_id"] in wanted and r["error"]}
        if drop:
            _rewrite_without(csv_path, drop)
        done = {r["run_id"]: r for r in stored if r["run_id"] in wanted and r["run_id"] not in drop}
        runs_file = _RunsFile(csv_path, columns)
        if save_runs:
            (out_path / "runs").mkdir(exist_ok=True)

    rows: dict[str, dict[str, Any]] = dict(done)
    todo = [s for s in specs if s.run_id not in done]
    bar = _progress_bar(len(todo), progress)

    def finish(spec: RunSpec, row: dict[str, Any], result: MissionResult | None) -> None:
        if result is not None and out_path is not None and save_runs:
            from .records import save_mission  # records sits beside this module, not below it

            try:
                save_mission(result, out_path / "runs" / f"{spec.run_id}.npz")
            except OSError as exc:
                row["error"] = _one_line(f"saving the run failed: {exc}")
        if runs_file is not None:
            runs_file.append(row)
        rows[spec.run_id] = row
        if on_result is not None:
            on_result(spec, row, result)
        if bar is not None:
            bar.update(1)
            failed = sum(1 for r in rows.values() if r.get("error"))
            if failed:
                bar.set_postfix(failed=failed)

    keep = out_path is not None and save_runs or on_result is not None
    own_pool: cf.Executor | None = None
    try:
        if executor is None and plan.workers == 1:
            for spec in todo:
                row, result = execute_run(spec, plan.n_threads, keep)
                finish(spec, row, result)
        else:
            pool = executor
            if pool is None:
                own_pool = pool = local_executor(min(plan.workers, max(1, len(todo))))
            futures = {pool.submit(execute_run, spec, plan.n_threads, keep): spec for spec in todo}
            try:
                for future in cf.as_completed(futures):
                    spec = futures[future]
                    try:
                        row, result = future.result()
                    except Exception as exc:  # the worker died or the cluster lost the task
                        row, result = spec.row_template(), None
                        row["error"] = _one_line(f"{type(exc).__name__}: {exc}")
                    finish(spec, row, result)
            except BaseException:
                for future in futures:
                    future.cancel()
                raise
    finally:
        if own_pool is not None:
            _stop_pool(own_pool)
        if bar is not None:
            bar.close()
        if runs_file is not None:
            runs_file.close()
    return [rows[i] for i in ids]


# ---------------------------------------------------------------------------------------------
# Summaries and tables


def _finished(rows: Iterable[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    return [r for r in rows if not r.get("error") and r.get("max_coverage") is not None]


def summarise(
    rows: Iterable[Mapping[str, Any]], by: Sequence[str] = ("experiment", "n_uavs", "init"), metrics: Sequence[str] = ("initial_coverage", "max_coverage", "final_coverage", "iterations_to_95")
) -> dict[tuple[Any, ...], dict[str, Any]]:
    """Mean and standard deviation of ``metrics`` over the finished runs, grouped ``by`` columns.

    The standard deviation is the sample one (``ddof=1``; NaN for a single run). Runs are summed
    in seed order, so the numbers do not depend on the order runs finished in.

    Returns
    -------
    dict
        ``key tuple -> {"count": n, "<metric>": (mean, sigma), ...}``, keys sorted.
    """
    groups: dict[tuple[Any, ...], list[Mapping[str, Any]]] = {}
    for row in sorted(_finished(rows), key=lambda r: (r.get("seed") or 0, str(r.get("run_id")))):
        groups.setdefault(tuple(row.get(k) for k in by), []).append(row)
    summary = {}
    for key in sorted(groups, key=lambda k: tuple(str(x).zfill(8) for x in k)):
        members = groups[key]
        entry: dict[str, Any] = {"count": len(members)}
        for metric in metrics:
            values = np.array([float(m[metric]) for m in members], dtype=float)
            sigma = float(np.std(values, ddof=1)) if len(values) > 1 else math.nan
            entry[metric] = (float(np.mean(values)), sigma)
        summary[key] = entry
    return summary


def _cell(value: tuple[float, float] | None, digits: int = 2) -> str:
    if value is None:
        return "-"
    mean, sigma = value
    return f"{mean:.{digits}f}" if math.isnan(sigma) else f"{mean:.{digits}f} ({sigma:.{digits}f})"


def _seed_text(rows: Sequence[Mapping[str, Any]]) -> str:
    seeds = sorted({int(r["seed"]) for r in rows})
    if not seeds:
        return "no seeds"
    if seeds == list(range(seeds[0], seeds[-1] + 1)) and len(seeds) > 2:
        return f"seeds {seeds[0]}-{seeds[-1]}"
    return "seeds " + ", ".join(str(s) for s in seeds)


def _failures(rows: Sequence[Mapping[str, Any]]) -> str:
    failed = [r for r in rows if r.get("error")]
    if not failed:
        return ""
    lines = [f"\n{len(failed)} run(s) failed and are left out (see the `error` column of runs.csv):\n"]
    for r in failed[:10]:
        lines.append(f"- `{r['run_id']}`: {r['error']}")
    return "\n".join(lines) + "\n"


_METRIC = {"initial": "initial_coverage", "max": "max_coverage"}


def table1_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """Table 1 as Markdown: ours, mean (sigma) over the terrains, beside the paper's.

    Also lists the reproduction bar of issue 6 per cell: mean within 0.05 of the paper's, sigma
    within a factor of 2, and the order CVT > random > corner of mean max coverage per N.
    """
    rows = list(rows)
    ok = _finished(rows)
    summary = summarise(ok, by=("n_uavs", "init"))
    sizes = sorted({int(r["n_uavs"]) for r in rows}) or sorted({n for n, _, _ in paper.PUBLISHED_TABLE1})
    columns = [("cvt", "initial"), ("cvt", "max"), ("random", "initial"), ("random", "max"), ("corner", "initial"), ("corner", "max")]

    def ours(n: int, start: str, metric: str) -> tuple[float, float] | None:
        entry = summary.get((n, start))
        return None if entry is None else entry[_METRIC[metric]]

    counts = sorted({e["count"] for e in summary.values()})
    lines = [
        "# Table 1: coverage, mean (sigma) over the terrains",
        "",
        f"Ours: {_seed_text(ok)}, {'/'.join(str(c) for c in counts) or 0} terrain(s) per cell; the paper: 40 terrains.",
        "d_max = 25 m, 30 prior samples, CAO; \"max\" is the best coverage reached during the run.",
        "",
        "| N | | " + " | ".join(f"{s} {m}" for s, m in columns) + " |",
        "|---|---|" + "---|" * len(columns),
    ]
    for n in sizes:
        lines.append(f"| {n} | ours | " + " | ".join(_cell(ours(n, s, m)) for s, m in columns) + " |")
        published = []
        for s, m in columns:
            value = paper.PUBLISHED_TABLE1.get((n, s, m))
            published.append("-" if value is None else f"{value.mean:.2f} ({value.sigma:.2f})")
        lines.append(f"| {n} | paper | " + " | ".join(published) + " |")

    checks = ["", "## Against the paper", ""]
    total = passed = 0
    for (n, s, m), value in sorted(paper.PUBLISHED_TABLE1.items()):
        got = ours(n, s, m)
        if got is None:
            continue
        total += 1
        mean_ok = abs(got[0] - value.mean) <= 0.05 + 1e-12
        sigma_ok = not math.isnan(got[1]) and value.sigma / 2 <= got[1] <= value.sigma * 2
        passed += mean_ok and sigma_ok
        if not (mean_ok and sigma_ok):
            reasons = []
            if not mean_ok:
                reasons.append(f"mean {got[0]:.3f} vs {value.mean:.2f} (off by {got[0] - value.mean:+.3f})")
            if not sigma_ok:
                reasons.append(f"sigma {got[1]:.3f} vs {value.sigma:.2f}")
            checks.append(f"- N = {n}, {s} {m}: " + "; ".join(reasons))
    checks.insert(3, f"{passed} of {total} cells have the mean within 0.05 and sigma within a factor of 2 of the paper's.")
    checks.insert(4, "")
    for n in sizes:
        maxima = [ours(n, s, "max") for s in ("cvt", "random", "corner")]
        if any(v is None for v in maxima):
            continue
        c, r, k = (v[0] for v in maxima)  # type: ignore[index]
        order = "holds" if c > r > k else "does NOT hold"
        checks.append(f"- N = {n}: CVT > random > corner in mean max coverage {order} ({c:.3f}, {r:.3f}, {k:.3f})")
    return "\n".join(lines + checks) + "\n" + _failures(rows)


def pyramid_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The pyramid prior (N = 12, 4 corners and the centre known) beside the paper's numbers."""
    rows = list(rows)
    ok = _finished(rows)
    summary = summarise(ok, by=("n_uavs", "init"))
    lines = [
        "# Pyramid prior: coverage, mean (sigma) over the terrains",
        "",
        f"Ours: {_seed_text(ok)}; the paper: 40 terrains. Only the 4 corners and the centre are known.",
        "",
        "| N | start | runs | initial (ours) | initial (paper) | max (ours) | max (paper) |",
        "|---|---|---|---|---|---|---|",
    ]
    published = paper.PUBLISHED_PYRAMID
    for (n, start), entry in summary.items():
        lines.append(
            f"| {n} | {start} | {entry['count']} | {_cell(entry['initial_coverage'])} | "
            f"{published['initial'].mean:.2f} ({published['initial'].sigma:.2f}) | {_cell(entry['max_coverage'])} | "
            f"{published['max'].mean:.2f} ({published['max'].sigma:.2f}) |"
        )
    checks = [""]
    for (n, start), entry in summary.items():
        for metric, column in (("initial", "initial_coverage"), ("max", "max_coverage")):
            off = entry[column][0] - published[metric].mean
            verdict = "within" if abs(off) <= 0.05 + 1e-12 else "NOT within"
            checks.append(f"- N = {n}, {metric}: {verdict} 0.05 of the paper's ({off:+.3f})")
    return "\n".join(lines + checks) + "\n" + _failures(rows)


def comparison_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The paper's Fig. 6 comparison (one scenario, three starts) beside its max coverages."""
    rows = list(rows)
    ok = _finished(rows)
    summary = summarise(ok, by=("n_uavs", "init"))
    lines = [
        "# Single-scenario comparison (paper Fig. 6)",
        "",
        f"Ours: {_seed_text(ok)}. Coverage per iteration is in coverage.csv.",
        "",
        "| N | start | runs | initial | max (ours) | max (paper) | iterations to 95 % |",
        "|---|---|---|---|---|---|---|",
    ]
    for (n, start), entry in summary.items():
        paper_max = paper.PUBLISHED_FIG6_MAX.get(start)
        lines.append(
            f"| {n} | {start} | {entry['count']} | {_cell(entry['initial_coverage'])} | {_cell(entry['max_coverage'])} | "
            f"{'-' if paper_max is None else f'{paper_max:.2f}'} | {_cell(entry['iterations_to_95'], 0)} |"
        )
    return "\n".join(lines) + "\n" + _failures(rows)


def buildings_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The buildings scene: CVT start from the simplified map against two pairs on opposite sides."""
    rows = list(rows)
    ok = _finished(rows)
    summary = summarise(ok, by=("n_uavs", "init"))
    lines = [
        "# Buildings scene (paper Figs. 7-8)",
        "",
        f"Ours: {_seed_text(ok)}. The paper: the CVT start begins higher and converges faster than two",
        "pairs of UAVs started on opposite sides (no numbers published). Coverage per iteration is in coverage.csv.",
        "",
        "| N | start | runs | initial | max | final | iterations to 95 % |",
        "|---|---|---|---|---|---|---|",
    ]
    for (n, start), entry in summary.items():
        lines.append(
            f"| {n} | {start} | {entry['count']} | {_cell(entry['initial_coverage'])} | {_cell(entry['max_coverage'])} | "
            f"{_cell(entry['final_coverage'])} | {_cell(entry['iterations_to_95'], 0)} |"
        )
    return "\n".join(lines) + "\n" + _failures(rows)


def example_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The illustrative example (paper Fig. 5): one run per seed, its coverage at a glance."""
    rows = list(rows)
    lines = [
        "# Illustrative example (paper Fig. 5)",
        "",
        "The paper: 9 UAVs, d_max = 35 m, 30 prior samples; the final coverage is close to 1.",
        "",
        "| seed | N | start | iterations | initial | max | final | iterations to 95 % | seconds |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in _finished(rows):
        lines.append(
            f"| {r['seed']} | {r['n_uavs']} | {r['init']} | {r['iterations']} | {r['initial_coverage']:.3f} | "
            f"{r['max_coverage']:.3f} | {r['final_coverage']:.3f} | {r['iterations_to_95']} | {r['wall_time_s']:.1f} |"
        )
    return "\n".join(lines) + "\n" + _failures(rows)


_TABLES: Mapping[str, Callable[[Sequence[Mapping[str, Any]]], str]] = {
    "table1": table1_markdown,
    "pyramid": pyramid_markdown,
    "comparison": comparison_markdown,
    "buildings": buildings_markdown,
    "example": example_markdown,
}


# ---------------------------------------------------------------------------------------------
# The paper's experiments end to end


def parse_seeds(text: str | Iterable[int]) -> tuple[int, ...]:
    """Seeds from ``"0-39"``, ``"0,3,7"``, ``"1000-1009,2000"`` or an iterable of ints.

    Raises
    ------
    ConfigError
        Anything else, a negative seed, an empty or reversed range, or a repeated seed.
    """
    if isinstance(text, str):
        seeds: list[int] = []
        for part in text.replace(" ", "").split(","):
            if not part:
                raise ConfigError(f"seeds {text!r}: an empty item")
            low, dash, high = part.partition("-")
            try:
                a = int(low)
                b = int(high) if dash else a
            except ValueError:
                raise ConfigError(f"seeds {text!r}: {part!r} is not a seed or a range like 0-39") from None
            if b < a:
                raise ConfigError(f"seeds {text!r}: the range {part} runs backwards")
            seeds.extend(range(a, b + 1))
    else:
        seeds = list(text)
        for s in seeds:
            if not _is_int(s):
                raise ConfigError(f"seeds must be integers, got {s!r}")
        seeds = [int(s) for s in seeds]
    if not seeds:
        raise ConfigError("no seeds given")
    if min(seeds) < 0:
        raise ConfigError(f"seeds must be >= 0, got {min(seeds)}")
    if len(set(seeds)) != len(seeds):
        raise ConfigError("a seed is listed twice")
    return tuple(seeds)


def _curves(out: Path, rows: Sequence[Mapping[str, Any]]) -> Path | None:
    """Write ``coverage.csv``: the coverage per iteration of every stored run, one column each."""
    from .records import load_mission

    columns: list[tuple[str, np.ndarray]] = []
    for r in _finished(rows):
        path = out / "runs" / f"{r['run_id']}.npz"
        if path.is_file():
            columns.append((f"{r['init']}-n{r['n_uavs']}-s{r['seed']}", load_mission(path).coverage))
    if not columns:
        return None
    length = max(len(c) for _, c in columns)
    lines = [_csv_line(["iteration"] + [name for name, _ in columns])]
    for k in range(length):
        lines.append(_csv_line([k] + [float(c[k]) if k < len(c) else "" for _, c in columns]))
    path = out / "coverage.csv"
    _atomic_write(path, "".join(lines))
    return path


def reproduce(
    name: str,
    out: str | os.PathLike[str],
    *,
    seeds: Iterable[int] | str | None = None,
    team_sizes: Iterable[int] | None = None,
    starts: Iterable[str] | None = None,
    iterations: int | None = None,
    executor: cf.Executor | None = None,
    workers: int | None = None,
    n_threads: int | None = None,
    resume: bool = False,
    rerun: str = "none",
    save_runs: bool = True,
    progress: bool | None = None,
    execution: Mapping[str, Any] | None = None,
) -> list[dict[str, Any]]:
    """Run one of the paper's experiments and write its results into ``out``.

    Writes ``runs.csv``, ``runs/<run_id>.npz``, ``config.json`` (the resolved settings) and
    ``<name>.md`` (the table beside the paper's numbers); "comparison", "buildings" and
    "example" also write ``coverage.csv`` (coverage per iteration of every run).

    Parameters
    ----------
    name : {"table1", "pyramid", "example", "comparison", "buildings"}
    out : path
    seeds : "0-39", iterable of int, optional
        Scenarios (the experiment's published seeds by default: 0-39 for Table 1).
    team_sizes, starts : optional
        Subsets of the experiment's (all by default).
    iterations : int, optional
        CAO iterations instead of the experiment's (a different setting: a different run id).
    executor, workers, n_threads, resume, rerun, save_runs, progress
        As in :func:`run_specs`.
    execution : mapping, optional
        How it was run (recorded in ``config.json``).

    Returns
    -------
    list of dict
        The rows.
    """
    experiments = paper_experiments()
    if name not in experiments:
        raise ConfigError(f"unknown experiment {name!r}; choose one of {', '.join(REPRODUCIBLE)}")
    experiment = experiments[name]
    if iterations is not None:
        if not _is_int(iterations) or iterations < 0:
            raise ConfigError(f"--iterations must be an integer >= 0, got {iterations!r}")
        experiment = experiment.with_changes(iterations=int(iterations))
    seed_list = experiment.seeds if seeds is None else parse_seeds(seeds)
    if team_sizes is not None:
        team_sizes = tuple(team_sizes)
        if not team_sizes or any(not _is_int(n) or n < 1 for n in team_sizes):
            raise ConfigError(f"team sizes must be integers >= 1, got {team_sizes}")
    if starts is not None:
        starts = tuple(starts)
        unknown = [s for s in starts if s not in experiment.starts]
        if unknown or not starts:
            raise ConfigError(f"{name} compares the starts {', '.join(experiment.starts)}; got {', '.join(starts) or 'none'}")
    specs = experiment_specs(experiment, seeds=seed_list, team_sizes=team_sizes, starts=starts)
    out_path = prepare_out_dir(out)
    # The "settings" entry must not change under a resume; seeds are allowed to grow.
    resolved = {"settings_hash": settings_hash(experiment), **dataclasses.asdict(experiment)}
    resolved.pop("seeds", None)
    config = {
        "command": f"reproduce {name}",
        "uavcov_version": _version(),
        "settings_source": "uavcov.paper",
        "settings": {name: resolved},
        "runs": {
            "seeds": list(seed_list),
            "team_sizes": list(team_sizes or experiment.team_sizes),
            "starts": list(starts or experiment.starts),
            "count": len(specs),
        },
        "seeding": "uavcov.paper.run_paper_mission(experiment, seed=..., n_uavs=..., start=...); "
        "see the Seeds section of uavcov.paper and uavcov.experiments",
        "execution": dict(execution or {}),
    }
    with out_dir_lock(out_path):
        _check_resume_target(out_path, resume)
        write_config(out_path, config, resume=resume)
        rows = run_specs(
            specs,
            out=out_path,
            executor=executor,
            workers=workers,
            n_threads=n_threads,
            resume=resume,
            rerun=rerun,
            save_runs=save_runs,
            progress=progress,
        )
        _atomic_write(out_path / f"{name}.md", _TABLES[name](rows))
        if name in ("comparison", "buildings", "example") and save_runs:
            _curves(out_path, rows)
    return rows


def _check_resume_target(out: Path, resume: bool) -> None:
    """Refuse before writing anything when ``out`` holds runs and ``resume`` is off."""
    csv_path = _runs_path(out)
    if not resume and csv_path.exists():
        stored = read_runs(csv_path)
        if stored:
            raise ConfigError(
                f"{csv_path} already holds {len(stored)} run(s): pass --resume to continue that sweep, "
                "or choose another --out (nothing was changed)"
            )


def _version() -> str:
    try:
        from . import __version__

        return str(__version__)
    except ImportError:  # the extension is missing; the version is only informative here
        return "unknown"
