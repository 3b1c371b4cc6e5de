"""End-to-end jobs: the paper's experiments and sweep files, run into a results folder, then reported.

Each job builds its run specs, hands them to the one function that runs specs into a folder
(:func:`uavcov.experiments.run_specs`), and writes its report from what the folder holds
(:mod:`uavcov.experiments`):

* :func:`reproduce`: one of the paper's experiments (:data:`uavcov.paper.EXPERIMENTS`) ->
  ``<name>.md`` beside the paper's numbers, and ``coverage.csv`` for the single-scenario ones;
* :func:`reproduce_all`: every experiment of the paper, each in its own folder, then
  ``report.md``: every table beside the paper's numbers, the claims of section V-C measured
  (:mod:`uavcov.experiments`) and the figures, each named with the hash of the settings it was made
  with (:func:`uavcov.experiments.experiments_hash` of :data:`uavcov.paper.EXPERIMENTS`);
* :func:`run_sweep`: a sweep file (:mod:`uavcov.experiments`) -> ``sweep.toml`` (the file as
  written) and ``summary.md``.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

from .._validate import as_tuple, is_int
from ..errors import ConfigError, MissingExtraError
from ..experiments import (
    Experiment,
    ResultsFolder,
    check_run_options,
    experiment_specs,
    experiments_hash,
    parse_seeds,
    plan_execution,
    run_specs,
)
from . import _data as paper
from ._bounds import BOUNDS_FILE, bounds_markdown, write_bounds
from ._claims import ablation_markdown, claims_markdown, verdicts_markdown
from ._oracle import oracle
from ._reports import REPORTS, coverage_curves_csv

REPORT_SEEDS: Mapping[str, tuple[int, ...]] = {"comparison": paper.HELD_OUT_SEEDS, "buildings": tuple(range(20))}
"""Seeds :func:`reproduce_all` runs where the paper shows one scenario: its claims are checked
over many (the comparison over the 40 terrains of Table 1, the buildings scene over 20 draws)."""

REPRODUCIBLE: tuple[str, ...] = tuple(paper.EXPERIMENTS)
"""The experiments :func:`reproduce` knows."""

_CURVES = ("comparison", "buildings", "example")
_BOUNDED = ("table1",)  # experiments whose report sets each start against the oracle's certified bound


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
    exclusive: bool = False,
    progress: bool | None = None,
    command: str | None = None,
    execution: Mapping[str, Any] | None = None,
) -> list[dict[str, Any]]:
    """Run one of the paper's experiments and write its results into the folder ``out``.

    Writes ``runs.csv``, ``runs/<run_id>.npz``, ``config.json`` and ``<name>.md`` (the table
    beside the paper's numbers); "comparison", "buildings" and "example" also write
    ``coverage.csv`` (coverage per iteration of every run); "table1" also writes ``bounds.csv``
    (the oracle's certified bound per terrain and team size, :func:`uavcov.paper.oracle`)
    and sets each start against it in ``table1.md``.

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
    executor, workers, n_threads, resume, rerun, save_runs, exclusive, progress, execution
        As in :func:`uavcov.experiments.run_specs`.
    command : str, optional
        What ``config.json`` records as the command (``"reproduce <name>"`` by default).

    Returns
    -------
    list of dict
        The rows.

    Raises
    ------
    ConfigError
        An unknown experiment, seeds, team sizes or starts it does not have, a bad iteration
        count; and what :func:`uavcov.experiments.run_specs` raises.
    """
    if not isinstance(name, str) or name not in paper.EXPERIMENTS:
        raise ConfigError(f"unknown experiment {name!r}; choose one of {', '.join(REPRODUCIBLE)}")
    experiment = _with_iterations(paper.EXPERIMENTS[name], iterations)
    resume, save_runs, exclusive, progress, command, execution = check_run_options(
        resume=resume, save_runs=save_runs, exclusive=exclusive, progress=progress, command=command, execution=execution
    )
    seed_list = experiment.seeds if seeds is None else parse_seeds(seeds)
    if team_sizes is not None:
        team_sizes = as_tuple(team_sizes, "team_sizes")
        if not team_sizes or any(not is_int(n) or n < 1 for n in team_sizes):
            raise ConfigError(f"team sizes must be integers >= 1, got {team_sizes}")
    if starts is not None:
        starts = as_tuple(starts, "starts")
        unknown = [s for s in starts if not isinstance(s, str) or s not in experiment.starts]
        if unknown or not starts:
            raise ConfigError(f"{name} compares the starts {', '.join(experiment.starts)}; got {', '.join(map(str, starts)) or 'none'}")
    specs = experiment_specs(experiment, seeds=seed_list, team_sizes=team_sizes, starts=starts)
    if executor is None:
        plan_execution(workers, n_threads)  # refused before the folder is made
    folder = ResultsFolder(out)
    with folder.lock():
        bounded = [BOUNDS_FILE] if name in _BOUNDED else []
        folder.claim([f"{name}.md", *(["coverage.csv"] if name in _CURVES and save_runs else []), *bounded])
        rows = run_specs(
            specs,
            out=folder,
            executor=executor,
            workers=workers,
            n_threads=n_threads,
            resume=resume,
            rerun=rerun,
            save_runs=save_runs,
            exclusive=exclusive,
            progress=progress,
            command=command or f"reproduce {name}",
            execution=execution,
        )
        report = REPORTS[name](rows)
        if bounded:
            plan = plan_execution(workers, n_threads) if executor is None else plan_execution(1, n_threads)
            bounds = oracle(experiment, seeds=seed_list, team_sizes=team_sizes, n_threads=plan.n_threads, workers=plan.workers)
            write_bounds(folder, bounds)
            report += "\n" + bounds_markdown(rows, bounds)
        folder.write_text(f"{name}.md", report)
        if name in _CURVES and save_runs:
            coverage_curves_csv(folder, rows)
    return rows


def ablate(
    out: str | os.PathLike[str],
    *,
    seeds: Iterable[int] | str | None = None,
    iterations: int | None = None,
    command: str | None = None,
    **run_options: Any,
) -> list[dict[str, Any]]:
    """The paper's model and each of ``uavcov.paper._data.ABLATIONS`` into ``out``, then ``ablation.md``.

    Every variant runs ``uavcov.paper._data.ABLATION_BASE`` (N = 5 and 12, the three starts,
    scenarios 0-9 by default) with one change; ``ablation.md`` sets the claims measured on each
    (max coverage per start, the CVT-over-random gain, the convergence share, the robustness)
    beside the paper's model, so that what drives a claim shows as the line that moves it.

    Parameters
    ----------
    out : path
    seeds, iterations
        As in :func:`reproduce`.
    command : str, optional
        What ``config.json`` records (``"reproduce ablation"`` by default).
    **run_options
        As in :func:`reproduce` (``workers``, ``n_threads``, ``resume``, ...).

    Returns
    -------
    list of dict
        The rows of every variant (their ``experiment`` column names the variant).
    """
    base = _with_iterations(paper.ABLATION_BASE, iterations)
    seed_list = base.seeds if seeds is None else parse_seeds(seeds)
    variants = [("ablation", "the paper's model (uavcov.experiments)")]
    specs = experiment_specs(base, seeds=seed_list, label="ablation")
    for change in paper.ABLATIONS:
        label = f"ablation-{change.name}"
        variants.append((label, change.what))
        specs += experiment_specs(base.with_changes(**change.changes), seeds=seed_list, label=label)
    folder = ResultsFolder(out)
    with folder.lock():
        folder.claim(["ablation.md"])
        rows = run_specs(specs, out=folder, command=command or "reproduce ablation", **run_options)
        table = ablation_markdown(rows, folder, variants)
        folder.write_text("ablation.md", "# Ablations: one change to the paper's model at a time\n\n" + table)
    return rows


def reproduce_all(
    out: str | os.PathLike[str],
    *,
    seeds: Iterable[int] | str | None = None,
    iterations: int | None = None,
    figures: Callable[[Path], list[str]] | None = None,
    **run_options: Any,
) -> dict[str, list[dict[str, Any]]]:
    """Every experiment of the paper into ``out/<name>/``, then ``out/report.md``.

    Parameters
    ----------
    out : path
    seeds : "0-39", iterable of int, optional
        The same seeds for every experiment (for a quick look); by default each experiment's
        own, and ``REPORT_SEEDS`` where the paper shows a single scenario.
    iterations : int, optional
        CAO iterations instead of the experiments' (a quick look, not the paper's runs).
    figures : callable, optional
        Draws a folder's figures into ``<folder>/figures`` and returns their file names, which
        the report links: :func:`uavcov.plotting.report_figures` (needs ``uavcov[plot]``;
        without it the report says so). ``None``: no figures.
    **run_options
        As in :func:`reproduce` (``workers``, ``n_threads``, ``resume``, ...).

    Returns
    -------
    dict
        The rows of each experiment, by name.
    """
    folder = ResultsFolder(out)
    tag = experiments_hash(paper.EXPERIMENTS)
    results: dict[str, list[dict[str, Any]]] = {}
    drawn: dict[str, list[str]] = {}
    for name in REPRODUCIBLE:
        chosen = seeds if seeds is not None else REPORT_SEEDS.get(name)
        results[name] = reproduce(name, folder.path / name, seeds=chosen, iterations=iterations, **run_options)
        drawn[name] = _figures(figures, folder.path / name) if figures is not None else []
    how = "" if seeds is None else f" with seeds {seeds}"
    how += "" if iterations is None else f" and {iterations} CAO iterations"
    parts = [
        "# The paper's experiments, reproduced",
        "",
        f"Settings: `uavcov.paper.EXPERIMENTS` {tag} (every table and figure below was made with them).",
        f"Made by `uavcov reproduce all`{how}; each experiment's runs are in its folder.",
        "Each run id and figure names the settings hash of its experiment: "
        + ", ".join(f"{name} {'/'.join(sorted({str(r['settings_hash']) for r in results[name]}))}" for name in REPRODUCIBLE)
        + ".",
        "",
    ]
    parts.append(_demote(verdicts_markdown(results, ResultsFolder(folder.path / "table1"))).rstrip() + "\n")
    for name in REPRODUCIBLE:
        table = (folder.path / name / f"{name}.md").read_text(encoding="utf-8")
        parts.append(_demote(table).rstrip() + "\n")
        if name == "table1":
            parts.append(_demote(claims_markdown(results[name], ResultsFolder(folder.path / name))).rstrip() + "\n")
        parts += [f"![{name}: {path} (settings {tag})]({name}/figures/{path})" for path in drawn[name]]
        parts.append("")
    results["ablation"] = ablate(folder.path / "ablation", seeds=seeds, iterations=iterations, **run_options)
    parts.append(_demote((folder.path / "ablation" / "ablation.md").read_text(encoding="utf-8")).rstrip() + "\n")
    if figures is not None and not any(drawn.values()):
        parts.append("No figures: drawing them needs matplotlib (`pip install 'uavcov[plot]'`).\n")
    folder.write_text("report.md", "\n".join(parts))
    return results


def _with_iterations(experiment: Experiment, iterations: Any) -> Experiment:
    """``experiment`` with ``iterations`` CAO iterations instead of its own (``None``: unchanged)."""
    if iterations is None:
        return experiment
    if not is_int(iterations) or iterations < 0:
        raise ConfigError(f"iterations must be an integer >= 0, got {iterations!r}")
    return experiment.with_changes(iterations=int(iterations))


def _demote(markdown: str) -> str:
    """Every heading one level down, so that a report's sections nest under the whole."""
    return "\n".join("#" + line if line.startswith("#") else line for line in markdown.splitlines()) + "\n"


def _figures(draw: Callable[[Path], list[str]], folder: Path) -> list[str]:
    """The figures ``draw`` makes of a folder, or none without matplotlib."""
    try:
        return list(draw(folder))
    except MissingExtraError:
        return []
