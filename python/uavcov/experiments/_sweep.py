"""Experiments and sweeps: specs x seeds -> missions on an executor, into a results folder.

An :class:`Experiment` is a family of missions: a scenario generator (one true surface per
seed), a :class:`~uavcov.settings.MissionSettings`, and the team sizes, starts and seeds it runs.
A :class:`RunSpec` is one of its missions: one seed, one team size, one start. :func:`run_specs`
runs a list of them on a local process pool (spawn context), a Dask cluster
(:func:`dask_executor`) or any ``concurrent.futures`` executor, and returns one row per run (a
``dict`` with the columns of ``runs.csv``). With ``out=`` it writes a
results folder (:class:`uavcov.experiments.ResultsFolder`): every command that runs missions (the
paper's reproductions, sweep files, the demo) goes through it.

Seeds: every run is a pure function of its settings and its seed
-----------------------------------------------------------------
Run ``(experiment, seed=s, n_uavs=N, start=k)`` draws the true surface with
``experiment.terrain.make(s)`` (and the buildings scene's simplified map with
``numpy.random.default_rng([s, 1])``), or takes the experiment's own surface when its terrain is
a :class:`~uavcov.Terrain` (the same for every seed), then runs :func:`uavcov.mission.run_mission` with
``rng=s``, whose three child streams (prior, start, optimiser) make every team size and start
on one terrain see the same prior points. Nothing depends on the executor, on the order runs
finish in, or on the Rust thread count, so the same specs give the same numbers on a process
pool, on Dask and in one process.

Threads: a run uses ``n_threads`` Rust threads for its coverage measurements; :func:`run_specs`
picks them with :func:`uavcov.experiments.plan_execution`.
"""

from __future__ import annotations

import collections
import concurrent.futures as cf
import dataclasses
import hashlib
import json
import os
import sys
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validate import MAX_RUNS, MAX_UAVS, as_non_negative_int, as_optional_str, as_str, as_tuple, is_int, within_file_name_limit
from ..engine import Terrain
from ..errors import ConfigError, InvalidInputError, InvalidTypeError, ResultsFormatError, ResultsInUseError
from ..mission import MissionResult, run_mission
from ..placement import START_KINDS
from ..records import save_mission
from ..settings import PRIOR_KINDS, MissionSettings, nested_replace
from ..terrain import BuildingsGenerator, HillsGenerator
from ._executors import ExecutionPlan, local_executor, stop_pool
from ._results import RUN_COLUMNS, ResultsFolder, RunsFile, config_document, json_default
from ._run_options import as_extra, check_run_options, checked_execution
from ._scenarios import scenario_surface, surface_settings

# Settings of the mission that an experiment's changes may name without the "mission." prefix.
_LATER_MISSION_FIELDS = frozenset({"sensor", "attitude", "objective", "gimbal", "footprint_start", "escape"})
_LATER_NESTED_FIELDS = (
    ("cao", "infeasible"),
    ("constraints", "clearance"),
    ("constraints", "move_step"),
    ("start", "greedy"),
    ("cvt", "normal_weight"),
)
"""Fields of the mission's settings objects added later, left out of the settings hash at their defaults."""
_MISSION_SHORTCUTS = _LATER_MISSION_FIELDS | {"d_max", "n_prior", "iterations", "optimizer", "start", "constraints", "cvt", "cao"}


# ---------------------------------------------------------------------------------------------
# Experiments and runs


@dataclass(frozen=True)
class Experiment:
    """A family of missions: a scenario generator, a mission, team sizes, starts and seeds.

    Attributes
    ----------
    name : str
        The label of its runs ("table1", "pyramid", a sweep's name, ...).
    terrain : HillsGenerator, BuildingsGenerator or Terrain
        The scenario generator: seed -> true surface. With a buildings scene the team knows its
        simplified map beforehand (the paper's Figs. 7-8); with hills, ``mission.prior``. A
        :class:`~uavcov.Terrain` of your own is the true surface of every seed (the seed then
        draws the prior, the start and the optimiser's steps); the settings hash holds a digest
        of its geometry, so another surface makes other run ids.
    mission : MissionSettings
        Every setting of a mission; ``n_uavs`` and ``start.kind`` are set per run from
        ``team_sizes`` and ``starts``.
    team_sizes : tuple of int
        The team sizes ``N`` it sweeps.
    starts : tuple of str
        The starts it compares (kinds of :class:`uavcov.placement.StartSettings`).
    seeds : tuple of int
        The scenarios it runs by default.
    """

    name: str
    terrain: HillsGenerator | BuildingsGenerator | Terrain
    mission: MissionSettings
    team_sizes: tuple[int, ...]
    starts: tuple[str, ...]
    seeds: tuple[int, ...] = field(default=())

    def __post_init__(self) -> None:
        as_str(self.name, "name")  # the label of its runs, in runs.csv and every message
        if not isinstance(self.terrain, (HillsGenerator, BuildingsGenerator, Terrain)):
            raise InvalidTypeError(f"terrain must be a HillsGenerator, BuildingsGenerator or Terrain, got {type(self.terrain).__name__}")
        if not isinstance(self.mission, MissionSettings):
            raise InvalidTypeError(f"mission must be a MissionSettings, got {type(self.mission).__name__}")
        sizes = as_tuple(self.team_sizes, "team_sizes")
        if not sizes or not all(is_int(n) and 1 <= n <= MAX_UAVS for n in sizes):
            raise InvalidInputError(f"team_sizes must be integers from 1 to {MAX_UAVS:,}, got {self.team_sizes}")
        starts = as_tuple(self.starts, "starts")
        unknown = [s for s in starts if not isinstance(s, str) or s not in START_KINDS]
        if not starts or unknown:
            raise InvalidInputError(f"starts must be some of {START_KINDS}, got {self.starts}")
        seeds = as_tuple(self.seeds, "seeds")
        if not all(is_int(s) and s >= 0 for s in seeds):
            raise InvalidInputError(f"seeds must be integers >= 0, got {self.seeds}")
        for n in sizes:  # each team's mission within the size limits, checked before any run
            self.mission.with_changes(n_uavs=int(n))
        object.__setattr__(self, "team_sizes", tuple(int(n) for n in sizes))
        object.__setattr__(self, "starts", starts)
        object.__setattr__(self, "seeds", tuple(int(s) for s in seeds))

    @property
    def prior(self) -> str:
        """What is known beforehand: "map" (a buildings scene's simplified map), or ``mission.prior``."""
        return "map" if isinstance(self.terrain, BuildingsGenerator) else self.mission.prior

    @property
    def d_max(self) -> float:
        """The sensing range, metres (``mission.d_max``)."""
        return self.mission.d_max

    @property
    def iterations(self) -> int:
        """Optimiser iterations (``mission.iterations``)."""
        return self.mission.iterations

    def mission_settings(self, n_uavs: int, start: str) -> MissionSettings:
        """The mission of one run: team size ``n_uavs``, start ``start``."""
        if not isinstance(start, str) or start not in self.starts:
            raise InvalidInputError(f"start must be one of {self.starts} for {self.name}, got {start!r}")
        return self.mission.with_changes(n_uavs=n_uavs, **{"start.kind": start})

    @property
    def generator(self) -> HillsGenerator | BuildingsGenerator:
        """The scenario generator, for what only a generator has (its size, spacing, ...).

        Raises
        ------
        ConfigError
            The experiment's terrain is a surface of its own, not a generator.
        """
        if isinstance(self.terrain, Terrain):
            raise ConfigError(f"{self.name} runs on a surface of its own, not on a scenario generator")
        return self.terrain

    def scenario(self, seed: int) -> Terrain:
        """The true surface of scenario ``seed``: the generator's, or the experiment's own surface."""
        return scenario_surface(self.terrain, seed)

    def known(self, seed: int) -> Terrain | None:
        """What the team is told of scenario ``seed`` beforehand, when it is not ``mission.prior``'s sample."""
        seed = as_non_negative_int(seed, "seed")  # a scenario's seed, whether or not this terrain draws a map from it
        return self.terrain.simplified_map(seed) if isinstance(self.terrain, BuildingsGenerator) else None

    def with_changes(self, **changes: Any) -> Experiment:
        """A copy with some settings replaced, by dotted name.

        ``"terrain.spacing"``, ``"mission.cao.alpha0"``; the mission's settings also without the
        prefix (``"d_max"``, ``"iterations"``, ``"cao.alpha0"``, ``"start.altitude"``,
        ``"constraints.h_min"``); ``"prior"`` takes "random", "pyramid" or, for a buildings
        scene, "map".
        ``"__"`` may stand for the dot.

        Raises
        ------
        InvalidInputError
            An unknown name, or a value its settings object refuses.
        """
        resolved: dict[str, Any] = {}
        for key, value in changes.items():
            dotted = key.replace("__", ".")
            head, _, rest = dotted.partition(".")
            if head == "prior" and not rest:
                if value == "map":
                    if not isinstance(changes.get("terrain", self.terrain), BuildingsGenerator) and "terrain.kind" not in changes:
                        raise InvalidInputError("the 'map' prior goes with a BuildingsGenerator, and only with it")
                    continue
                if not isinstance(value, str) or value not in PRIOR_KINDS:
                    raise InvalidInputError(f"prior must be one of {(*PRIOR_KINDS, 'map')}, got {value!r}")
                dotted = "mission.prior"
            elif head in _MISSION_SHORTCUTS:
                dotted = "mission." + dotted
            resolved[dotted] = value
        return nested_replace(self, resolved)

    def cells(self) -> list[tuple[int, str]]:
        """Every ``(n_uavs, start)`` pair the experiment runs for each seed."""
        return [(n, s) for n in self.team_sizes for s in self.starts]


def experiment_settings(experiment: Experiment) -> dict[str, Any]:
    """The settings a run of ``experiment`` depends on, as plain data (JSON-ready).

    The name, the seeds, the team sizes and the starts are left out (a run names its own seed,
    team size and start), and so are the mission's ``n_uavs`` and ``start.kind`` they set.
    """
    if not isinstance(experiment, Experiment):
        raise InvalidTypeError(f"experiment must be an Experiment, got {type(experiment).__name__}")
    if isinstance(experiment.terrain, Terrain):  # not a dataclass: its geometry by digest
        settings: dict[str, Any] = {"terrain": surface_settings(experiment.terrain), "mission": dataclasses.asdict(experiment.mission)}
    else:
        settings = dataclasses.asdict(experiment)
        for key in ("name", "seeds", "team_sizes", "starts"):
            settings.pop(key)
    settings["mission"].pop("n_uavs")
    settings["mission"]["start"].pop("kind")
    # Mission fields added after the paper's experiments were published leave the settings (and
    # so the run ids of every earlier sweep) as they were while they keep their defaults.
    for name in _LATER_MISSION_FIELDS:
        if getattr(experiment.mission, name) == _field_default(MissionSettings, name):
            settings["mission"].pop(name)
    for group, name in _LATER_NESTED_FIELDS:
        value = getattr(getattr(experiment.mission, group), name)
        if value == _field_default(type(getattr(experiment.mission, group)), name):
            settings["mission"][group].pop(name)
    settings["terrain_kind"] = "surface" if isinstance(experiment.terrain, Terrain) else experiment.terrain.kind
    return settings


def _field_default(cls: type, name: str) -> Any:
    """The default of field ``name`` of dataclass ``cls`` (made by its factory when it has one)."""
    found = next(f for f in dataclasses.fields(cls) if f.name == name)
    return found.default_factory() if found.default_factory is not dataclasses.MISSING else found.default


def settings_hash(experiment: Experiment) -> str:
    """Eight hex digits that change with any setting of ``experiment`` a run depends on.

    See ``experiment_settings`` (the settings without the seeds, team sizes and starts): adding
    seeds or team sizes to an experiment keeps the identity of the runs already made (a resume
    then runs only the new ones).
    """
    text = json.dumps(experiment_settings(experiment), sort_keys=True, default=json_default)
    return hashlib.sha256(text.encode()).hexdigest()[:8]


def experiments_hash(experiments: Mapping[str, Experiment]) -> str:
    """Eight hex digits that change with any setting of any of ``experiments`` (and their names, seeds, sizes, starts).

    ``experiments_hash(uavcov.paper.EXPERIMENTS)`` names the paper's settings a report was made with.
    """
    if not isinstance(experiments, Mapping) or not all(isinstance(e, Experiment) for e in experiments.values()):
        raise InvalidTypeError(f"experiments must be a mapping of names to Experiments, got {type(experiments).__name__}")
    settings = {
        name: {**experiment_settings(e), "seeds": list(e.seeds), "team_sizes": list(e.team_sizes), "starts": list(e.starts)}
        for name, e in sorted(experiments.items())
    }
    text = json.dumps(settings, sort_keys=True, default=json_default)
    return hashlib.sha256(text.encode()).hexdigest()[:8]


@dataclass(frozen=True)
class RunSpec:
    """One mission of a sweep: an experiment's settings, a seed, a team size and a start.

    Attributes
    ----------
    experiment : Experiment
        Every setting of the run.
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

    experiment: Experiment
    seed: int
    n_uavs: int
    start: str
    label: str = ""
    extra: tuple[tuple[str, Any], ...] = ()

    def __post_init__(self) -> None:
        if not isinstance(self.experiment, Experiment):
            raise InvalidTypeError(f"experiment must be an Experiment, got {type(self.experiment).__name__}")
        if not is_int(self.seed) or self.seed < 0:
            raise InvalidInputError(f"seed must be an integer >= 0, got {self.seed!r}")
        if not is_int(self.n_uavs) or not 1 <= self.n_uavs <= MAX_UAVS:
            raise InvalidInputError(f"n_uavs must be an integer from 1 to {MAX_UAVS:,}, got {self.n_uavs!r}")
        if not isinstance(self.start, str) or self.start not in self.experiment.starts:
            raise InvalidInputError(f"start must be one of {self.experiment.starts} for {self.experiment.name}, got {self.start!r}")
        object.__setattr__(self, "seed", int(self.seed))
        object.__setattr__(self, "n_uavs", int(self.n_uavs))
        object.__setattr__(self, "label", as_optional_str(self.label, "label") or self.experiment.name)
        within_file_name_limit(self.run_id + ".npz", f"label {self.label[:40]!r}...: its run file (runs/<run_id>.npz)")
        object.__setattr__(self, "extra", as_extra(self.extra))
        # a swept setting may repeat a column of its row (iterations), never contradict it
        repeated = [(key, value) for key, value in self.extra if key in RUN_COLUMNS]
        own = self.row_template(with_extra=False) if repeated else {}
        contradicted = [key for key, value in repeated if not np.array_equal(own[key], value)]
        if contradicted:
            raise InvalidInputError(f"extra contradicts the row's own columns {contradicted} (run_id, seed, ... are the spec's)")

    @property
    def settings_hash(self) -> str:
        """``settings_hash`` of the experiment."""
        return settings_hash(self.experiment)

    @property
    def run_id(self) -> str:
        """A name unique to the run's settings, seed, team size and start, safe as a file name.

        ``<label>-<start>-n<N>-s<seed>-<settings hash>``, e.g. ``table1-cvt-n05-s0003-1a2b3c4d``.
        """
        label = "".join(c if c.isalnum() or c in "._-" else "_" for c in self.label)
        return f"{label}-{self.start}-n{self.n_uavs:02d}-s{self.seed:04d}-{self.settings_hash}"

    @property
    def mission(self) -> MissionSettings:
        """The mission this run runs."""
        return self.experiment.mission_settings(self.n_uavs, self.start)

    def row_template(self, with_extra: bool = True) -> dict[str, Any]:
        """The row of this run with every result column empty (None, as read_runs gives back)."""
        row: dict[str, Any] = dict.fromkeys(RUN_COLUMNS)
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
        if with_extra:
            row.update(dict(self.extra))
        return row

    def run(self, n_threads: int | None = 1) -> MissionResult:
        """Run the mission: terrain ``seed``, then :func:`uavcov.mission.run_mission` with ``rng=seed``."""
        terrain = self.experiment.scenario(self.seed)
        return run_mission(terrain, self.mission, known=self.experiment.known(self.seed), n_threads=n_threads, rng=self.seed)


def experiment_specs(
    experiment: Experiment,
    *,
    seeds: Iterable[int] | None = None,
    team_sizes: Iterable[int] | None = None,
    starts: Iterable[str] | None = None,
    label: str | None = None,
    extra: Sequence[tuple[str, Any]] = (),
) -> list[RunSpec]:
    """Every run of ``experiment``: seeds x team sizes x starts (the experiment's own by default).

    Runs are ordered seed-major, so an interrupted sweep has whole scenarios done.

    Raises
    ------
    InvalidInputError
        An empty list, a start the experiment does not compare, an ``extra`` that names a
        column twice or contradicts a column of the row (``run_id``, ``seed``, ...).
    InvalidTypeError
        A ``label`` not a string, an ``extra`` not (column, value) pairs of JSON values.
    """
    if not isinstance(experiment, Experiment):
        raise InvalidTypeError(f"experiment must be an Experiment, got {type(experiment).__name__}")
    label = as_optional_str(label, "label")
    extra = as_extra(extra)
    seeds = as_tuple(experiment.seeds if seeds is None else seeds, "seeds")
    team_sizes = as_tuple(experiment.team_sizes if team_sizes is None else team_sizes, "team_sizes")
    starts = as_tuple(experiment.starts if starts is None else starts, "starts")
    for name, values in (("seeds", seeds), ("team_sizes", team_sizes), ("starts", starts)):
        if not values:
            raise InvalidInputError(f"{name} is empty: the sweep has no run")
    count = len(seeds) * len(team_sizes) * len(starts)
    if count > MAX_RUNS:
        raise InvalidInputError(
            f"{len(seeds):,} seeds x {len(team_sizes)} team sizes x {len(starts)} starts make {count:,} runs, "
            f"more than uavcov's limit of {MAX_RUNS:,}; split the sweep"
        )
    unknown = [s for s in starts if not isinstance(s, str) or s not in experiment.starts]
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
    except Exception as exc:  # noqa: BLE001 (a failing run is recorded; the sweep goes on)
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
        time_feasibility_s=float(result.trace.time_feasibility_s),
        distance_mean_m=float(result.distance_flown.mean()),
        distance_max_m=float(result.distance_flown.max()),
        start_time_s=float(result.start_time_s),
    )
    return row, (result if keep_result else None)


# ---------------------------------------------------------------------------------------------
# Running a list of specs


def _progress_bar(total: int, enabled: bool | None) -> Any:
    if enabled is None:
        enabled = sys.stderr.isatty()
    if not enabled or total == 0:
        return None
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm(total=total, unit="run", dynamic_ncols=True, smoothing=0.05)


def _configuration(
    specs: Sequence[RunSpec], command: str | None, execution: Mapping[str, Any] | None, about: Mapping[str, Any] | None
) -> dict[str, Any]:
    """The ``config.json`` of a folder these specs are run into."""
    settings: dict[str, Any] = {}
    for spec in specs:
        key = spec.settings_hash
        if key not in settings:
            settings[key] = {"label": spec.label, "swept": dict(spec.extra), "experiment": experiment_settings(spec.experiment)}
    runs = {
        "seeds": sorted({s.seed for s in specs}),
        "team_sizes": sorted({s.n_uavs for s in specs}),
        "starts": list(dict.fromkeys(s.start for s in specs)),
        "count": len(specs),
    }
    return config_document(command, settings, runs, execution=execution, about=about)


def run_specs(
    specs: Sequence[RunSpec],
    *,
    out: str | os.PathLike[str] | ResultsFolder | None = None,
    executor: cf.Executor | None = None,
    workers: int | None = None,
    n_threads: int | None = None,
    resume: bool = False,
    rerun: str = "none",
    save_runs: bool = True,
    exclusive: bool = False,
    progress: bool | None = None,
    command: str | None = "run_specs",
    execution: Mapping[str, Any] | None = None,
    about: Mapping[str, Any] | None = None,
    on_result: Callable[[RunSpec, dict[str, Any], MissionResult | None], None] | None = None,
) -> list[dict[str, Any]]:
    """Run every spec and return one row per spec, in the order of ``specs``.

    Parameters
    ----------
    specs : sequence of RunSpec
        The runs (run ids must be unique).
    out : path or ResultsFolder, optional
        The results folder: ``runs.csv``, ``runs/<run_id>.npz`` and ``config.json`` (see
        :mod:`uavcov.experiments`); nothing is written without it.
    executor : concurrent.futures.Executor, optional
        Where the runs go (e.g. from :func:`dask_executor`); it is not shut down here. Without
        it: one run at a time in this process when ``workers`` is 1, else a spawn process pool
        of ``workers`` processes made (and ended) here.
    workers, n_threads : int, optional
        Runs at once and Rust threads per run (see :func:`plan_execution`). With an
        ``executor``, ``n_threads`` defaults to 1.
    resume : bool
        Skip the specs whose run id is already in ``runs.csv`` (their stored rows are
        returned). Without it, a folder whose ``runs.csv`` holds rows is refused.
    rerun : {"none", "failed", "all"}
        With ``resume``: run again the stored runs that failed, or every stored run of ``specs``
        (their old rows are removed first, so no run is ever listed twice).
    save_runs : bool
        Save each result as ``runs/<run_id>.npz``.
    exclusive : bool
        Refuse a folder that holds rows of runs not in ``specs``.
    progress : bool, optional
        A progress bar with ETA on stderr (tqdm); by default only when stderr is a terminal.
    command, execution, about
        What ``config.json`` records (see ``config_document``).
    on_result : callable, optional
        Called in this process as ``on_result(spec, row, result)`` after each finished run
        (``result`` is None for a failed run).

    Returns
    -------
    list of dict
        One row per spec with the columns of ``RUN_COLUMNS`` plus each
        spec's ``extra``.

    Raises
    ------
    ResultsInUseError
        The folder holds rows without ``resume``, rows of other settings, or is being written
        by another process.
    ResultsFolderError
        The folder cannot be written.
    ConfigError
        Duplicate run ids, or a bad ``workers`` / ``n_threads``.
    KeyboardInterrupt
        After Ctrl-C, once pending runs are cancelled and the workers ended; every finished run
        is already in ``runs.csv``.

    Examples
    --------
    >>> from uavcov.experiments import experiment_specs, run_specs
    >>> from uavcov.paper import TABLE1
    >>> small = TABLE1.with_changes(**{"terrain.spacing": 4.0, "iterations": 5})
    >>> rows = run_specs(experiment_specs(small, seeds=[0], team_sizes=[5], starts=["cvt"]), workers=1)
    >>> rows[0]["init"], 0.0 < rows[0]["initial_coverage"] <= 1.0
    ('cvt', True)
    """
    resume, save_runs, exclusive, progress, command, execution = check_run_options(
        resume=resume, save_runs=save_runs, exclusive=exclusive, progress=progress, command=command, execution=execution
    )
    specs = list(specs)
    for spec in specs:
        if not isinstance(spec, RunSpec):
            raise InvalidTypeError(f"specs must be RunSpec objects, got {type(spec).__name__}")
    if not isinstance(rerun, str) or rerun not in ("none", "failed", "all"):
        raise InvalidInputError(f"rerun must be 'none', 'failed' or 'all', got {rerun!r}")
    ids = [s.run_id for s in specs]
    if len(set(ids)) != len(ids):
        duplicates = sorted(i for i, count in collections.Counter(ids).items() if count > 1)
        raise ConfigError(f"the sweep lists the same run more than once: {', '.join(duplicates[:5])}")
    plan, about = checked_execution(executor, workers, n_threads, on_result, about)

    extra_columns: list[str] = []
    for spec in specs:
        for key, _ in spec.extra:
            if key not in extra_columns and key not in RUN_COLUMNS:
                extra_columns.append(key)
    columns = list(RUN_COLUMNS) + extra_columns
    if out is None:
        return _run(specs, plan, None, None, executor, progress, False, on_result, {})
    folder = out if isinstance(out, ResultsFolder) else ResultsFolder(out)
    with folder.lock():
        # Every check first, then the writes: a refused run changes nothing in the folder.
        folder.claim()
        done, drop = _prepare(folder, specs, resume, rerun, exclusive)
        columns = folder.columns_for(columns)
        folder.check_columns(columns)
        folder.write_config(_configuration(specs, command, execution, about), resume=resume)
        if drop:
            folder.drop_runs(drop)
        folder.remove_leftovers()
        runs_file = folder.open_runs(columns)
        try:
            if save_runs:
                (folder.path / "runs").mkdir(exist_ok=True)
            return _run(specs, plan, folder if save_runs else None, runs_file, executor, progress, save_runs, on_result, done)
        finally:
            runs_file.close()


def _prepare(
    folder: ResultsFolder, specs: Sequence[RunSpec], resume: bool, rerun: str, exclusive: bool
) -> tuple[dict[str, dict[str, Any]], set[str]]:
    """Check what the folder holds against the specs: the stored rows kept, and the run ids to run again."""
    stored = folder.read_runs()
    if stored and not resume:
        raise ResultsInUseError(
            f"{folder.runs_csv} already holds {len(stored)} run(s): resume that sweep or write to another folder (nothing was changed)"
        )
    twice = [
        i for i, n in collections.Counter(r["run_id"] for r in stored).items() if n > 1
    ]  # a resume would keep one row and ignore the other
    if twice:
        raise ResultsFormatError(f"{folder.runs_csv} holds the run {twice[0]} twice: keep one of its rows, or write to another folder")
    wanted = {s.run_id for s in specs}
    if exclusive:
        others = [r["run_id"] for r in stored if r["run_id"] not in wanted]
        if others:
            raise ResultsInUseError(f"{folder.runs_csv} holds other results ({others[0]}, ...); write to another folder")
    hashes = {s.settings_hash for s in specs}
    foreign = sorted({str(r["settings_hash"]) for r in stored if r["settings_hash"] not in hashes})
    if foreign:
        raise ResultsInUseError(
            f"{folder.runs_csv} holds runs of other settings (settings hash {foreign[0]}); resume them with the same settings, "
            "or write to another folder"
        )
    drop: set[str] = set()
    if rerun == "all":
        drop = {r["run_id"] for r in stored if r["run_id"] in wanted}
    elif rerun == "failed":
        drop = {r["run_id"] for r in stored if r["run_id"] in wanted and r["error"]}
    return {r["run_id"]: r for r in stored if r["run_id"] in wanted and r["run_id"] not in drop}, drop


def _run(
    specs: list[RunSpec],
    plan: ExecutionPlan,
    save_to: ResultsFolder | None,
    runs_file: RunsFile | None,
    executor: cf.Executor | None,
    progress: bool | None,
    save_runs: bool,
    on_result: Callable[[RunSpec, dict[str, Any], MissionResult | None], None] | None,
    done: dict[str, dict[str, Any]],
) -> list[dict[str, Any]]:
    """Run the specs not in ``done``, recording each as it finishes; rows in the order of ``specs``."""
    rows: dict[str, dict[str, Any]] = dict(done)
    todo = [s for s in specs if s.run_id not in done]
    bar = _progress_bar(len(todo), progress)

    def finish(spec: RunSpec, row: dict[str, Any], result: MissionResult | None) -> None:
        if result is not None and save_to is not None:
            try:
                save_mission(result, save_to.run_file(spec.run_id))
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

    keep = save_runs or on_result is not None
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
                    except Exception as exc:  # noqa: BLE001 (the worker died or the cluster lost the task)
                        row, result = spec.row_template(), None
                        row["error"] = _one_line(f"{type(exc).__name__}: {exc}")
                    finish(spec, row, result)
            except BaseException:
                for future in futures:
                    future.cancel()
                raise
    finally:
        if own_pool is not None:
            stop_pool(own_pool)
        if bar is not None:
            bar.close()
    return [rows[s.run_id] for s in specs]
