"""The structures experiment (issue 42): ``uavcov reproduce structures``.

On seeded structures of :data:`uavcov.structures.STRUCTURE_FAMILIES` that no one tuned on (the
family's seed is the run's seed), the README's structure settings (8 UAVs, d_max 15 m, 100
known points, a 2 m standoff, every move checked), two starts, each one
:func:`uavcov.run_mission` with the 3D flight limits:

``cvt3d``
    The 3D prior (``n_prior`` random points on the structure), S' by
    :func:`~uavcov.structures.reconstruct_structure` (the outer surface, wound outward), CVT on S',
    each generator flown out of S' along its normal (:func:`~uavcov.placement.fly_out`).
``cvt_hf``
    The height-field prior (``n_prior`` random x-y points of the structure's top and the four
    corners, S' by Delaunay in x-y), CVT on it, ``offset`` metres above it.

Per structure, the full-knowledge reference: greedy on viewpoints 3, 6 and 9 m out along the
*true* structure's normals (:func:`~uavcov.cover.viewpoint_offsets`), the same team and
separation, with its certified bound (:func:`~uavcov.cover.greedy_placement`). Every run
records its best coverage as a share of both, how many of its start points lie inside a solid
of the real structure before :func:`~uavcov.limits.closest_admissible`, and (``cvt3d``) the
share of S''s area facing into the structure.

The open setting, each start's offset from S', is chosen on the development seeds; the report
is on the report seeds. Rows go to ``rows.jsonl`` in the results folder one by one as runs
finish (a run cut off by a kill leaves at most a torn last line, dropped on resume), so
``resume=True`` skips every finished run and the rows equal an uninterrupted run's.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ConfigError, UavcovError
from ._jsonl import append_row, read_rows

STARTS = ("cvt3d", "cvt_hf")
REFERENCE = "greedy"
ROWS = "rows.jsonl"
CONFIG = "config.json"
REPORT = "structures.md"


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
        CAO iterations per run.
    offsets : tuple of float
        Candidate offsets from S' of each start (m), chosen on the development seeds.
    reference_distances : tuple of float
        The full-knowledge candidates' offsets along the true normals (m).
    reference_spacing, target_spacing : float
        Candidates' and targets' spacing on the structure (m).
    """

    families: tuple[str, ...] = ("building", "girder_bridge", "arch_bridge", "tower", "pylon")
    report_seeds: tuple[int, ...] = (0, 1, 2, 3, 4, 5, 6, 7)
    dev_seeds: tuple[int, ...] = (1000, 1001)
    n_uavs: int = 8
    d_max: float = 15.0
    h_min: float = 2.0
    d_safe: float = 1.0
    ceiling: float = 10.0
    n_prior: int = 100
    iterations: int = 100
    offsets: tuple[float, ...] = (3.0, 6.0)
    reference_distances: tuple[float, ...] = (3.0, 6.0, 9.0)
    reference_spacing: float = 3.0
    target_spacing: float = 1.0

    def __post_init__(self) -> None:
        from ..structures import STRUCTURE_FAMILIES

        unknown = [f for f in self.families if f not in STRUCTURE_FAMILIES]
        if unknown or not self.families:
            raise ConfigError(f"families must be among {sorted(STRUCTURE_FAMILIES)}, got {list(self.families)}")
        if set(self.report_seeds) & set(self.dev_seeds):
            raise ConfigError(f"report seeds {sorted(set(self.report_seeds) & set(self.dev_seeds))} are also development seeds")
        if not self.report_seeds or not self.dev_seeds or not self.offsets:
            raise ConfigError("the experiment needs report seeds, development seeds and offsets")


Task = tuple[str, str, int, float]
"""(family, start, seed, offset); start ``"greedy"`` is the reference (offset 0)."""


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
    placed = greedy_placement(
        Visibility(structure.surface, experiment.d_max, targets, n_threads=1),
        candidates,
        experiment.n_uavs,
        d_safe=experiment.d_safe,
        n_threads=1,
    )
    return {"coverage": placed.coverage, "bound": placed.bound, "candidates": placed.n_candidates}


def _mission(experiment: StructuresExperiment, family: str, start: str, seed: int, offset: float) -> dict[str, Any]:
    from ..mission import MissionSettings, run_mission
    from ..placement import StartSettings
    from ..structures import reconstruction_error
    from ..terrain import sample_prior

    structure = _structure(experiment, family, seed)
    limits = _limits(experiment, structure)
    reference = "normal" if start == "cvt3d" else "prior"
    begin = StartSettings(kind="cvt", altitude=offset, altitude_reference=reference, climb=0.5)
    settings = MissionSettings(
        n_uavs=experiment.n_uavs,
        d_max=experiment.d_max,
        n_prior=experiment.n_prior,
        iterations=experiment.iterations,
        start=begin,
        constraints=limits,
    )
    targets = structure.targets(spacing=experiment.target_spacing)
    known = sample_prior(structure.surface, experiment.n_prior, kind="random", rng=seed) if start == "cvt_hf" else None
    result = run_mission(structure, settings, known=known, targets=targets, rng=seed, n_threads=1)
    row: dict[str, Any] = {
        "initial": result.initial_coverage,
        "best": result.best_coverage,
        "inside_before": int(structure.surface.inside(result.start_positions, n_threads=1).sum()),
    }
    if start == "cvt3d":
        # The S' the start was placed on.
        row["inward_share"] = reconstruction_error(structure, result.approximation, n_samples=4000, rng=seed).inward_area_share
    return row


def run_task(experiment: StructuresExperiment, task: Task) -> dict[str, Any]:
    """One row: a mission, or the reference (``start == "greedy"``); errors are recorded, not raised."""
    family, start, seed, offset = task
    row: dict[str, Any] = {"family": family, "start": start, "seed": seed, "offset": offset, "error": ""}
    began = time.perf_counter()
    try:
        row.update(_reference(experiment, family, seed) if start == REFERENCE else _mission(experiment, family, start, seed, offset))
    except UavcovError as exc:
        row["error"] = f"{type(exc).__name__}: {exc}"
    row["time_s"] = time.perf_counter() - began
    return row


def _key(row: dict[str, Any]) -> Task:
    return (str(row["family"]), str(row["start"]), int(row["seed"]), float(row["offset"]))


def _run_tasks(experiment: StructuresExperiment, tasks: Sequence[Task], path: Path, workers: int) -> list[dict[str, Any]]:
    done = {_key(r): r for r in read_rows(path)}
    todo = [t for t in tasks if t not in done]
    if workers <= 1 or len(todo) <= 1:
        for task in todo:
            row = run_task(experiment, task)
            append_row(path, row)
            done[task] = row
    else:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            running = {pool.submit(run_task, experiment, t) for t in todo}
            while running:
                finished, running = wait(running, return_when=FIRST_COMPLETED)
                for future in finished:
                    row = future.result()
                    append_row(path, row)
                    done[_key(row)] = row
    return [done[t] for t in tasks]


def _mean(rows: list[dict[str, Any]], family: str, start: str, offset: float) -> float:
    values = [r["best"] for r in rows if r["family"] == family and r["start"] == start and r["offset"] == offset and not r["error"]]
    return float(np.mean(values)) if values else -np.inf


def choose_offsets(experiment: StructuresExperiment, rows: list[dict[str, Any]]) -> dict[str, float]:
    """Each start's offset: the best mean best coverage over every family's development seeds."""
    chosen = {}
    for start in STARTS:
        score = {o: float(np.mean([_mean(rows, f, start, o) for f in experiment.families])) for o in experiment.offsets}
        chosen[start] = max(experiment.offsets, key=lambda o: (score[o], -o))
    return chosen


def reproduce_structures(
    out: str | os.PathLike[str],
    experiment: StructuresExperiment | None = None,
    *,
    workers: int = 1,
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
        Processes at once (1: this process).
    resume : bool
        Continue ``out``: skip the runs already in ``rows.jsonl`` (settings must match).

    Returns
    -------
    list of dict
        The report seeds' rows (missions and references), in task order.
    """
    from ._structures_report import write_report

    experiment = experiment or StructuresExperiment()
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    config = {"experiment": "structures", "settings": asdict(experiment)}
    config_path, rows_path = folder / CONFIG, folder / ROWS
    if config_path.exists() or rows_path.exists():
        if not resume:
            raise ConfigError(f"{folder} holds a structures run already: resume it (--resume) or choose another --out")
        if json.loads(config_path.read_text(encoding="utf-8")) != json.loads(json.dumps(config)):
            raise ConfigError(f"{folder} was run with other settings; choose another --out")
    else:
        config_path.write_text(json.dumps(config, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    say = progress or (lambda message: None)
    dev = _dev_tasks(experiment)
    say(f"{len(dev)} development runs")
    dev_rows = _run_tasks(experiment, dev, rows_path, workers)
    chosen = choose_offsets(experiment, dev_rows)
    report = _report_tasks(experiment, chosen)
    say(f"offsets chosen {chosen}; {len(report)} report runs")
    rows = _run_tasks(experiment, report, rows_path, workers)
    write_report(folder / REPORT, experiment, chosen, rows, dev_rows)
    return rows


def _dev_tasks(experiment: StructuresExperiment) -> list[Task]:
    return [(f, s, seed, o) for f in experiment.families for s in STARTS for seed in experiment.dev_seeds for o in experiment.offsets]


def _report_tasks(experiment: StructuresExperiment, chosen: dict[str, float]) -> list[Task]:
    tasks = [(f, s, seed, chosen[s]) for f in experiment.families for seed in experiment.report_seeds for s in STARTS]
    return tasks + [(f, REFERENCE, seed, 0.0) for f in experiment.families for seed in experiment.report_seeds]


def report_from_folder(folder: str | os.PathLike[str]) -> str:
    """The report's Markdown rebuilt from a finished results folder (``config.json``, ``rows.jsonl``)."""
    from ._structures_report import report_markdown

    path = Path(folder)
    settings = json.loads((path / CONFIG).read_text(encoding="utf-8"))["settings"]
    fields: dict[str, Any] = {k: tuple(v) if isinstance(v, list) else v for k, v in settings.items()}
    experiment = StructuresExperiment(**fields)
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
