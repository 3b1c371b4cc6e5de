"""The structures experiment (issue 42): ``uavcov reproduce structures``.

On seeded structures of :data:`uavcov.structures.STRUCTURE_FAMILIES` that no one tuned on (the
family's seed is the run's seed), the README's structure settings (8 UAVs, d_max 15 m, 100
known points, a 2 m standoff, every move checked), two starts, each one
:func:`uavcov.run_mission` with the 3D flight limits:

``cvt3d``
    The 3D prior (``n_prior`` random points on the structure), S' by
    :func:`~uavcov.structures.reconstruct_structure` (the outer surface, wound outward), CVT on S'
    (with a normal weight, ``CVTSettings.normal_weight``, when one is chosen: regions that face
    one way), each generator flown out of S' along its region's facing
    (:func:`~uavcov.placement.fly_out`).
``cvt_hf``
    The height-field prior (``n_prior`` random x-y points of the structure's top and the four
    corners, S' by Delaunay in x-y), CVT on it (its normal weight chosen the same way),
    ``offset`` metres above it.
``greedy3d``
    The 3D prior's S' as for ``cvt3d``, and on it the full-knowledge reference's greedy: points
    of S' ``spacing`` metres apart flown out along S''s normals the way the CVT generators are
    (:func:`~uavcov.placement.fly_out`), greedy picks by the coverage each adds on S' (the
    structure's ``"greedy"`` start). It tells the prior from the CVT's objective (generators
    spread evenly over S', not placed for coverage).
``cvt3d_paper``
    Diagnostic: ``cvt3d`` with the paper's CVT (normal weight 0), at the offset chosen for it.
``cvt_true``, ``greedy_true``
    Diagnostics: ``cvt3d`` and ``greedy3d`` with the real structure's solid surface in place of
    S' (a perfect prior), at the settings chosen for them (none of their own to choose). They
    tell what each start's objective reaches when the prior is not the limit.

Per structure, the full-knowledge reference: greedy on viewpoints 3, 6 and 9 m out along the
*true* structure's normals (:func:`~uavcov.cover.viewpoint_offsets`), the same team and
separation, with its certified bound (:func:`~uavcov.cover.greedy_placement`). Every run
records its best coverage as a share of both, how many of its start points lie inside a solid
of the real structure before :func:`~uavcov.limits.closest_admissible`, and (``cvt3d``) the
share of S''s area facing into the structure.

The open settings, each start's offset from S', CAO's step scale (``CAOSettings.alpha0``: a start
already near a good placement wants small steps, one far from it large ones), ``greedy3d``'s
candidate spacing on S' and the CVT starts' normal weight, are chosen on the development seeds; the report is on the report
seeds. The report seeds' missions fly on past ``iterations`` to ``trace_iterations`` (their
``best`` is still the best after ``iterations``; ``best_at`` the best after each checkpoint), so
the report also says what more flight time gives each start. Runs go to this process, a local
process pool or any ``concurrent.futures`` executor (a Dask cluster's), with the same rows.
Rows go to ``rows.jsonl`` in the results folder one by one as runs finish (a run cut
off by a kill leaves at most a torn last line, dropped on resume), so ``resume=True`` skips
every finished run and the rows equal an uninterrupted run's.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Executor, wait
from dataclasses import asdict, dataclass, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import (
    MAX_ITERATIONS,
    MAX_SAMPLES,
    MAX_SWEEP_FILE_BYTES,
    MAX_UAVS,
    MAX_WORKERS,
    as_bool,
    as_count,
    as_finite_float,
    as_non_negative_float,
    as_path,
    as_positive_float,
    read_regular_file,
)
from ..errors import ConfigError, InvalidInputError, InvalidTypeError, ResultsFormatError, UavcovError
from ._jsonl import append_row, read_rows
from ._structures_rows import DEFAULT_CAO_STEP, setting_of

STARTS = ("cvt3d", "cvt_hf", "greedy3d")
DIAGNOSTICS = {"cvt_true": "cvt3d", "greedy_true": "greedy3d"}
"""Report-only starts, each run at the offset chosen for the start it names."""
PAPER_CVT = "cvt3d_paper"
"""Report-only: ``cvt3d`` with the paper's CVT (no normal weight), at the offset and CAO step
chosen for it among those settings: what the normal weight adds, paired on the report seeds."""
CANDIDATE_STARTS = ("greedy3d", "greedy_true")
"""The starts with a candidate spacing on S' to choose besides the offset."""
CVT_STARTS = ("cvt3d", "cvt_hf")
"""The starts with a normal weight of their CVT to choose besides the offset."""
REFERENCE = "greedy"
ROWS = "rows.jsonl"
CONFIG = "config.json"
REPORT = "structures.md"
CHECKPOINTS = (0, 10, 25, 50, 100, 200, 400, 800)
"""Iterations after which every mission row records its best coverage (``best_at``), besides
``iterations`` and the run's last."""


@dataclass(frozen=True)
class StructuresExperiment:
    """The structures experiment's settings (what ``config.json`` records).

    Attributes
    ----------
    families : tuple of str
        Keys of :data:`uavcov.structures.STRUCTURE_FAMILIES`.
    report_seeds, dev_seeds : tuple of int
        The structures reported, and those the offsets are chosen on (disjoint).
    n_uavs : int
    d_max, h_min, d_safe, ceiling : float
        Sensing range, standoff, separation, and the ceiling above the structure's top (m).
    n_prior : int
        Known points (both priors).
    iterations : int
        CAO iterations per run: each row's ``best`` is the best coverage after them (and the
        settings are chosen by it).
    trace_iterations : int
        The report seeds' missions fly on to this many iterations (at least ``iterations``; CAO's
        first ``iterations`` do not depend on it), so the report can say what more flight time
        gives (500: the paper's bound on its runs, "which ensure the convergence"); every mission
        row's ``best_at`` holds the best after each checkpoint it reached (0, 10, 25, 50, 100,
        200, 400, 800 iterations, ``iterations`` and its last).
    offsets : tuple of float
        Candidate offsets from S' of each start (m), chosen on the development seeds.
    greedy_spacings : tuple of float
        Candidate spacings of ``greedy3d``'s points on S' (m), chosen on the development seeds.
    normal_weights : tuple of float
        Candidate normal weights of the CVT starts' tessellation (``CVTSettings.normal_weight``,
        m; 0 is the paper's CVT), chosen on the development seeds.
    cao_steps : tuple of float
        Candidate step scales of CAO (``CAOSettings.alpha0``, m; 1.5 is its default), chosen on
        the development seeds for every start.
    reference_distances : tuple of float
        The full-knowledge candidates' offsets along the true normals (m).
    reference_spacing, target_spacing : float
        Candidates' and targets' spacing on the structure (m).
    """

    families: tuple[str, ...] = ("building", "girder_bridge", "arch_bridge", "tower", "pylon")
    report_seeds: tuple[int, ...] = tuple(range(16))
    dev_seeds: tuple[int, ...] = (1000, 1001, 1002, 1003)
    n_uavs: int = 8
    d_max: float = 15.0
    h_min: float = 2.0
    d_safe: float = 1.0
    ceiling: float = 10.0
    n_prior: int = 100
    iterations: int = 100
    trace_iterations: int = 500
    offsets: tuple[float, ...] = (2.5, 3.0, 4.0, 6.0)
    greedy_spacings: tuple[float, ...] = (2.0, 4.0)
    normal_weights: tuple[float, ...] = (0.0, 5.0, 10.0, 20.0)
    cao_steps: tuple[float, ...] = (0.5, 0.75, 1.5, 3.0)
    reference_distances: tuple[float, ...] = (3.0, 6.0, 9.0)
    reference_spacing: float = 3.0
    target_spacing: float = 1.0

    def __post_init__(self) -> None:
        from ..structures import STRUCTURE_FAMILIES

        try:
            _check_fields(self)
        except InvalidTypeError:
            raise
        except InvalidInputError as exc:  # a bad value of the experiment's settings, like those below
            raise ConfigError(str(exc)) from None
        unknown = [f for f in self.families if f not in STRUCTURE_FAMILIES]
        if unknown or not self.families:
            raise ConfigError(f"families must be among {sorted(STRUCTURE_FAMILIES)}, got {list(self.families)}")
        if set(self.report_seeds) & set(self.dev_seeds):
            raise ConfigError(f"report seeds {sorted(set(self.report_seeds) & set(self.dev_seeds))} are also development seeds")
        if not self.report_seeds or not self.dev_seeds or not self.offsets or not self.greedy_spacings:
            raise ConfigError("the experiment needs report seeds, development seeds, offsets and greedy spacings")
        if not all(np.isfinite(v) and v > 0 for v in (*self.offsets, *self.greedy_spacings)):
            raise ConfigError(f"offsets and greedy spacings must be finite and > 0 m, got {self.offsets} and {self.greedy_spacings}")
        if not self.normal_weights or not all(np.isfinite(w) and 0 <= w <= 1e15 for w in self.normal_weights):
            raise ConfigError(f"normal weights must be finite, >= 0 and at most 1e15 m, got {self.normal_weights}")
        if self.trace_iterations < self.iterations:
            raise ConfigError(f"trace_iterations must be >= iterations ({self.iterations}), got {self.trace_iterations}")
        if not self.cao_steps or not all(np.isfinite(a) and 0 < a <= 1e15 for a in self.cao_steps):
            raise ConfigError(f"CAO steps must be finite, > 0 and at most 1e15 m, got {self.cao_steps}")


def _check_fields(experiment: StructuresExperiment) -> None:
    """Every field's type and range (checked, not converted: a valid experiment records as given)."""
    for name in (
        "families",
        "report_seeds",
        "dev_seeds",
        "offsets",
        "greedy_spacings",
        "normal_weights",
        "cao_steps",
        "reference_distances",
    ):
        values = getattr(experiment, name)
        if isinstance(values, (str, bytes)) or not isinstance(values, (tuple, list)):
            raise InvalidTypeError(f"{name} must be a tuple, got {type(values).__name__}")
    for family in experiment.families:
        if not isinstance(family, str):
            raise InvalidTypeError(f"families must be names, got {family!r}")
    for seed in (*experiment.report_seeds, *experiment.dev_seeds):
        as_count(seed, "seeds", 2**63 - 1, minimum=0)
    for name in ("offsets", "greedy_spacings", "cao_steps", "reference_distances"):
        for value in getattr(experiment, name):
            as_positive_float(value, name)
    for value in experiment.normal_weights:
        as_finite_float(value, "normal_weights")
    as_count(experiment.n_uavs, "n_uavs", MAX_UAVS)
    as_count(experiment.n_prior, "n_prior", MAX_SAMPLES)
    as_count(experiment.iterations, "iterations", MAX_ITERATIONS, minimum=0)
    as_count(experiment.trace_iterations, "trace_iterations", MAX_ITERATIONS, minimum=0)
    for name in ("d_max", "ceiling", "reference_spacing", "target_spacing"):
        as_positive_float(getattr(experiment, name), name)
    for name in ("h_min", "d_safe"):
        as_non_negative_float(getattr(experiment, name), name)


Task = tuple[str, str, int, float, float, float, float]
"""(family, start, seed, offset, spacing, normal_weight, cao_step); start ``"greedy"`` is the
reference (offset 0), spacing is the greedy starts' (0 for the others), normal_weight the CVT
starts' (0 for the others), cao_step CAO's ``alpha0``."""


def _structure(experiment: StructuresExperiment, family: str, seed: int) -> Any:
    from ..structures import STRUCTURE_FAMILIES

    return STRUCTURE_FAMILIES[family](rng=seed)


def _limits(experiment: StructuresExperiment, structure: Any) -> Any:
    from ..limits import Constraints

    top = float(structure.surface.bounds[1, 2])
    return Constraints(
        clearance="standoff", h_min=experiment.h_min, d_safe=experiment.d_safe, z_max=top + experiment.ceiling, check_moves=True
    )


def _reference(experiment: StructuresExperiment, family: str, seed: int) -> dict[str, Any]:
    from ..cover import greedy_placement, viewpoint_offsets
    from ..engine import Visibility

    structure = _structure(experiment, family, seed)
    limits = _limits(experiment, structure)
    targets = structure.targets(spacing=experiment.target_spacing)
    candidates = viewpoint_offsets(
        structure.surface, limits, experiment.reference_distances, spacing=experiment.reference_spacing, n_threads=1
    )
    vis = Visibility(structure.surface, experiment.d_max, targets, n_threads=1)
    placed = greedy_placement(vis, candidates, experiment.n_uavs, d_safe=experiment.d_safe, n_threads=1)
    seen = np.asarray(vis.seen(np.ascontiguousarray(placed.positions)), dtype=bool)
    total = float(targets.weights.sum())
    weights = {name: float(targets.weights[targets.parts == k].sum()) / total for k, name in enumerate(structure.part_names)}
    return {
        "coverage": placed.coverage,
        "bound": placed.bound,
        "candidates": placed.n_candidates,
        "parts": structure.coverage_by_part(seen, targets),
        "part_weights": {name: w for name, w in weights.items() if w > 0.0},
    }


def _mission(experiment: StructuresExperiment, task: Task) -> dict[str, Any]:
    from ..cover import GreedySettings
    from ..mission import MissionSettings, run_mission
    from ..placement import CVTSettings, StartSettings
    from ..structures import reconstruction_error
    from ..terrain import sample_prior

    family, start, seed, offset, spacing, weight, step = task
    structure = _structure(experiment, family, seed)
    limits = _limits(experiment, structure)
    reference = "prior" if start == "cvt_hf" else "normal"
    if start in CANDIDATE_STARTS:
        begin = StartSettings(
            kind="greedy", altitude=offset, altitude_reference=reference, climb=0.5, greedy=GreedySettings(spacing=spacing)
        )
    else:
        begin = StartSettings(kind="cvt", altitude=offset, altitude_reference=reference, climb=0.5)
    flight = experiment.trace_iterations if seed in experiment.report_seeds else experiment.iterations
    settings = MissionSettings(
        n_uavs=experiment.n_uavs,
        d_max=experiment.d_max,
        n_prior=experiment.n_prior,
        iterations=flight,
        start=begin,
        constraints=limits,
        cvt=CVTSettings(normal_weight=weight),
    )
    settings = replace(settings, cao=replace(settings.cao, alpha0=step))
    targets = structure.targets(spacing=experiment.target_spacing)
    known: Any = None
    if start == "cvt_hf":
        known = sample_prior(structure.surface, experiment.n_prior, kind="random", rng=seed)
    elif start in DIAGNOSTICS:
        known = _true_solid(structure)
    result = run_mission(structure, settings, known=known, targets=targets, rng=seed, n_threads=1)
    row: dict[str, Any] = {
        "initial": result.initial_coverage,
        "inside_before": int(structure.surface.inside(result.start_positions, n_threads=1).sum()),
    }
    row.update(_best_after(experiment, structure, targets, result))
    if start in ("cvt3d", "greedy3d", PAPER_CVT):
        # The S' the start was placed on.
        row["inward_share"] = reconstruction_error(structure, result.approximation, n_samples=4000, rng=seed).inward_area_share
    return row


def _best_after(experiment: StructuresExperiment, structure: Any, targets: Any, result: Any) -> dict[str, Any]:
    """``best`` and ``parts`` after ``experiment.iterations`` (a report mission flies on), and
    ``best_at``: the best after each checkpoint the mission reached."""
    from ..engine import Visibility

    coverage = result.coverage
    last = coverage.size - 1
    best = int(np.argmax(coverage[: experiment.iterations + 1]))  # the first best, as the trace's
    if best == result.trace.best_iteration:
        parts = dict(result.coverage_by_part or {})
    else:
        vis = Visibility(structure.surface, experiment.d_max, targets, n_threads=1)
        seen = np.asarray(vis.seen(np.ascontiguousarray(result.trajectory[best])), dtype=bool)
        parts = structure.coverage_by_part(seen, targets)
    reached = sorted({k for k in CHECKPOINTS if k <= last} | {min(experiment.iterations, last), last})
    running = np.maximum.accumulate(coverage)
    return {
        "best": float(coverage[best]),
        "parts": parts,
        "best_at": {str(k): float(running[k]) for k in reached},
    }


def _true_solid(structure: Any) -> Any:
    """The real structure's surface without its ground sheet (the diagnostics' S')."""
    from ..engine import Terrain

    ground = -1 if structure.ground_part is None else structure.ground_part
    return Terrain(structure.surface.vertices, structure.surface.faces[structure.face_parts != ground])


def run_task(experiment: StructuresExperiment, task: Task) -> dict[str, Any]:
    """One row: a mission, or the reference (``start == "greedy"``); errors are recorded, not raised."""
    family, start, seed, offset, spacing, weight, step = task
    row: dict[str, Any] = {
        "family": family,
        "start": start,
        "seed": seed,
        "offset": offset,
        "spacing": spacing,
        "normal_weight": weight,
        "cao_step": step,
        "error": "",
    }
    began = time.perf_counter()
    try:
        if start == REFERENCE:
            row.update(_reference(experiment, family, seed))
        else:
            row.update(_mission(experiment, task))
    except UavcovError as exc:
        row["error"] = f"{type(exc).__name__}: {exc}"
    row["time_s"] = time.perf_counter() - began
    return row


def _key(row: dict[str, Any]) -> Task:
    try:
        return (str(row["family"]), str(row["start"]), int(row["seed"]), *setting_of(row))
    except (KeyError, TypeError, ValueError) as exc:
        raise ResultsFormatError(f"a row of {ROWS} lacks its run's family, start, seed or settings ({type(exc).__name__}: {exc})") from None


def _run_tasks(
    experiment: StructuresExperiment, tasks: Sequence[Task], path: Path, workers: int, executor: Executor | None
) -> list[dict[str, Any]]:
    """Run what ``path`` does not hold yet, appending each row as it finishes: in this process,
    on ``executor`` (a Dask cluster's, say) or on a local process pool of ``workers``."""
    from ..experiments import local_executor

    done = {_key(r): r for r in read_rows(path)}
    todo = [t for t in tasks if t not in done]
    if executor is None and (workers <= 1 or len(todo) <= 1):
        for task in todo:
            row = run_task(experiment, task)
            append_row(path, row)
            done[task] = row
        return [done[t] for t in tasks]
    pool = executor if executor is not None else local_executor(min(workers, len(todo)))
    running: set[Any] = set()
    try:
        running = {pool.submit(run_task, experiment, t) for t in todo}
        while running:
            finished, running = wait(running, return_when=FIRST_COMPLETED)
            for future in finished:
                row = future.result()
                append_row(path, row)
                done[_key(row)] = row
    finally:  # on an error or a Ctrl-C, what has not started is cancelled, not run on
        if executor is None:
            pool.shutdown(wait=False, cancel_futures=True)
        else:  # a cluster the caller owns: only our own runs
            for future in running:
                future.cancel()
    return [done[t] for t in tasks]


Setting = tuple[float, float, float, float]
"""A start's (offset, spacing, normal weight, CAO step)."""


def _settings(experiment: StructuresExperiment, start: str) -> list[Setting]:
    """A start's (offset, spacing, normal weight, CAO step) candidates on the development seeds."""
    spacings = experiment.greedy_spacings if start in CANDIDATE_STARTS else (0.0,)
    weights = experiment.normal_weights if start in CVT_STARTS else (0.0,)
    return [(o, s, w, a) for o in experiment.offsets for s in spacings for w in weights for a in experiment.cao_steps]


def choose_offsets(experiment: StructuresExperiment, rows: list[dict[str, Any]]) -> dict[str, Setting]:
    """Each start's (offset, spacing, normal weight, CAO step): the best mean best coverage over
    every family's development seeds (ties: the smaller offset, then the wider spacing, the fewer
    candidates, then the smaller normal weight, the paper's CVT first, then the larger step)."""
    from ._structures_report import dev_scores

    chosen = {}
    for start in STARTS:
        options = _settings(experiment, start)
        scores = dev_scores(rows, list(experiment.families), start)
        score = {o: scores.get(o, -np.inf) for o in options}
        chosen[start] = max(options, key=lambda o: (score[o], -o[0], o[1], -o[2], o[3]))
        if start == "cvt3d":
            paper = [o for o in options if o[2] == 0.0]
            chosen[PAPER_CVT] = max(paper, key=lambda o: (score[o], -o[0], o[3]))
    return chosen


def reproduce_structures(
    out: str | os.PathLike[str],
    experiment: StructuresExperiment | None = None,
    *,
    workers: int = 1,
    executor: Executor | None = None,
    resume: bool = False,
    progress: Callable[[str], None] | None = None,
) -> list[dict[str, Any]]:
    """Run the experiment into ``out``: ``config.json``, ``rows.jsonl``, ``structures.md``.

    Parameters
    ----------
    out : path
        The results folder; with ``resume=False`` it must not hold rows already.
    experiment : StructuresExperiment, optional
    workers : int
        Processes at once on a local process pool (1: this process).
    executor : concurrent.futures.Executor, optional
        Run on this instead of a local pool, e.g. a Dask cluster's
        (:func:`uavcov.experiments.dask_executor`); the rows are the same.
    resume : bool
        Continue ``out``: skip the runs already in ``rows.jsonl`` (settings must match).

    Returns
    -------
    list of dict
        The report seeds' rows (missions and references), in task order.
    """
    from ._structures_report import write_report

    experiment = StructuresExperiment() if experiment is None else experiment
    if not isinstance(experiment, StructuresExperiment):
        raise InvalidTypeError(f"experiment must be a StructuresExperiment, got {type(experiment).__name__}")
    as_count(workers, "workers", MAX_WORKERS)
    if executor is not None and not isinstance(executor, Executor):
        raise InvalidTypeError(f"executor must be a concurrent.futures.Executor, got {type(executor).__name__}")
    resume = as_bool(resume, "resume")
    if progress is not None and not callable(progress):
        raise InvalidTypeError(f"progress must be callable, got {type(progress).__name__}")
    folder = as_path(out, "out")
    folder.mkdir(parents=True, exist_ok=True)
    config = {"experiment": "structures", "settings": asdict(experiment)}
    config_path, rows_path = folder / CONFIG, folder / ROWS
    if rows_path.exists() and not config_path.exists():
        raise ConfigError(f"{folder} holds rows without their {CONFIG}: choose another --out")
    if config_path.exists() or rows_path.exists():
        if not resume:
            raise ConfigError(f"{folder} holds a structures run already: resume it (--resume) or choose another --out")
        if _read_config(config_path) != json.loads(json.dumps(config)):
            raise ConfigError(f"{folder} was run with other settings; choose another --out")
    else:
        config_path.write_text(json.dumps(config, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    say = progress or (lambda message: None)
    dev = _dev_tasks(experiment)
    say(f"{len(dev)} development runs")
    dev_rows = _run_tasks(experiment, dev, rows_path, workers, executor)
    chosen = choose_offsets(experiment, dev_rows)
    report = _report_tasks(experiment, chosen)
    say(f"offsets chosen {chosen}; {len(report)} report runs")
    rows = _run_tasks(experiment, report, rows_path, workers, executor)
    write_report(folder / REPORT, experiment, chosen, rows, dev_rows)
    return rows


def _dev_tasks(experiment: StructuresExperiment) -> list[Task]:
    return [
        (f, s, seed, *o) for f in experiment.families for s in STARTS for seed in experiment.dev_seeds for o in _settings(experiment, s)
    ]


def _report_tasks(experiment: StructuresExperiment, chosen: dict[str, Setting]) -> list[Task]:
    settings = {**chosen, **{d: chosen[s] for d, s in DIAGNOSTICS.items()}}
    tasks = [(f, s, seed, *settings[s]) for f in experiment.families for seed in experiment.report_seeds for s in settings]
    reference = (0.0, 0.0, 0.0, DEFAULT_CAO_STEP)
    return tasks + [(f, REFERENCE, seed, *reference) for f in experiment.families for seed in experiment.report_seeds]


def _read_config(path: Path) -> dict[str, Any]:
    # A FIFO named config.json would block the read forever (a resume hung on one).
    text = read_regular_file(path, "structures experiment's config", ResultsFormatError, MAX_SWEEP_FILE_BYTES)
    try:
        config = json.loads(text.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:  # RecursionError: arrays nested thousands deep
        raise ResultsFormatError(f"cannot read {path}: {type(exc).__name__}: {exc}") from None
    if not isinstance(config, dict):
        raise ResultsFormatError(f"{path} is not a JSON object")
    return config


def report_from_folder(folder: str | os.PathLike[str]) -> str:
    """The report's Markdown rebuilt from a finished results folder (``config.json``, ``rows.jsonl``)."""
    from ._structures_report import report_markdown

    path = Path(folder)
    config = _read_config(path / CONFIG)
    settings = config.get("settings")
    if not isinstance(settings, dict) or set(settings) - {f.name for f in fields(StructuresExperiment)}:
        raise ResultsFormatError(f"{path / CONFIG} does not hold a structures experiment's settings")
    values: dict[str, Any] = {k: tuple(v) if isinstance(v, list) else v for k, v in settings.items()}
    experiment = StructuresExperiment(**values)
    done = {_key(r): r for r in read_rows(path / ROWS)}
    missing = [t for t in _dev_tasks(experiment) if t not in done]
    if missing:
        raise ConfigError(f"{path} misses {len(missing)} development run(s): finish it with --resume")
    dev_rows = [done[t] for t in _dev_tasks(experiment)]
    chosen = choose_offsets(experiment, dev_rows)
    report = _report_tasks(experiment, chosen)
    if any(t not in done for t in report):
        raise ConfigError(f"{path} misses report runs: finish it with --resume")
    return report_markdown(experiment, chosen, [done[t] for t in report], dev_rows)
