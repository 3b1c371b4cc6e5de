"""Summaries of the rows of ``runs.csv``, and a sweep file run into a results folder.

:func:`summarise` gives mean and sigma per cell of any study's runs; :func:`run_sweep` runs a
sweep file (:class:`uavcov.experiments.SweepConfig`) into a folder and writes its ``summary.md``.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from .._validate import as_tuple
from ..errors import InvalidTypeError, ResultsFormatError
from ._executors import plan_execution
from ._results import ResultsFolder, format_cell
from ._sweep import run_specs
from ._sweep_config import SweepConfig


def finished_rows(rows: Iterable[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    """The rows of runs that finished (no error, a coverage).

    Raises
    ------
    InvalidTypeError
        ``rows`` not a sequence of mappings (the rows of ``runs.csv``).
    """
    rows = as_tuple(rows, "rows")
    for row in rows:
        if not isinstance(row, Mapping):
            raise InvalidTypeError(f"rows must be mappings (rows of runs.csv), got {type(row).__name__}")
    return [r for r in rows if not r.get("error") and r.get("max_coverage") is not None]


def row_number(row: Mapping[str, Any], column: str, kind: type[float | int] = float) -> Any:
    """``row[column]`` (a row of ``runs.csv``, values as read or as written) as a ``kind``.

    Raises
    ------
    InvalidTypeError
        ``row`` not a mapping, ``column`` not a column name, ``kind`` neither float nor int.
    ResultsFormatError
        The row lacks ``column``, or it holds no number (no integer for ``kind=int``).
    """
    if not isinstance(row, Mapping):
        raise InvalidTypeError(f"row must be a mapping (a row of runs.csv), got {type(row).__name__}")
    column = as_column_name(column, "column")
    if kind is not float and kind is not int:
        raise InvalidTypeError(f"kind must be float or int, got {kind!r}")
    if column not in row:
        raise ResultsFormatError(f"rows must have the column {column!r}, a row has only {sorted(map(str, row))}")
    value = row[column]
    try:
        number = float(value)
        if kind is int and not number.is_integer():
            raise ValueError("not an integer")
    except (TypeError, ValueError, OverflowError) as exc:
        raise ResultsFormatError(f"rows' column {column!r} must hold {kind.__name__}s, got {value!r}") from exc
    return int(number) if kind is int else number


def as_column_name(value: Any, name: str) -> str:
    """A column name of runs.csv given in ``name`` (a non-empty string)."""
    if not isinstance(value, str) or not value:
        raise InvalidTypeError(f"{name} must hold column names (non-empty strings), got {value!r}")
    return value


def summarise(
    rows: Iterable[Mapping[str, Any]],
    by: Sequence[str] = ("experiment", "n_uavs", "init"),
    metrics: Sequence[str] = ("initial_coverage", "max_coverage", "final_coverage", "iterations_to_95"),
) -> dict[tuple[Any, ...], dict[str, Any]]:
    """Mean and standard deviation of ``metrics`` over the finished runs, grouped ``by`` columns.

    The standard deviation is the sample one (``ddof=1``; NaN for a single run). Runs are summed
    in seed order, so the numbers do not depend on the order runs finished in.

    Returns
    -------
    dict
        ``key tuple -> {"count": n, "<metric>": (mean, sigma), ...}``, keys sorted.

    Raises
    ------
    InvalidTypeError
        ``rows`` not mappings; ``by`` or ``metrics`` not column names.
    ResultsFormatError
        A finished row without a metric, or with one that is not a number.
    """
    by = tuple(as_column_name(column, "by") for column in as_tuple(by, "by"))
    metrics = tuple(as_column_name(column, "metrics") for column in as_tuple(metrics, "metrics"))
    groups: dict[tuple[Any, ...], list[Mapping[str, Any]]] = {}
    for row in sorted(finished_rows(rows), key=lambda r: (r.get("seed") or 0, str(r.get("run_id")))):
        groups.setdefault(tuple(row.get(k) for k in by), []).append(row)
    summary = {}
    for key in sorted(groups, key=lambda k: tuple(str(x).zfill(8) for x in k)):
        members = groups[key]
        entry: dict[str, Any] = {"count": len(members)}
        for metric in metrics:
            values = np.array([row_number(m, metric) for m in members], dtype=float)
            sigma = float(np.std(values, ddof=1)) if len(values) > 1 else math.nan
            entry[metric] = (float(np.mean(values)), sigma)
        summary[key] = entry
    return summary


def _cell_text(value: Any) -> str:
    return value if isinstance(value, str) else format_cell(value)


def sweep_markdown(config: Any, rows: Sequence[Mapping[str, Any]]) -> str:
    """Mean (sigma) of the coverage per swept value, team size and start.

    ``config`` is the :class:`uavcov.experiments.SweepConfig` the rows were run from (its name,
    base, description, seeds and axes).
    """
    by = tuple(config.axes) + ("n_uavs", "init")
    # Swept values read back from runs.csv are strings; compare them as written.
    normalised = [{**r, **{a: _cell_text(r.get(a)) for a in config.axes}} for r in rows]
    summary = summarise(normalised, by=by)
    header = list(config.axes) + ["N", "start", "runs", "initial", "max", "final", "iterations to 95 %"]
    lines = [
        f"# Sweep {config.name}",
        "",
        config.description or f"Based on {config.base}; {len(config.seeds)} seed(s). Mean (sigma) over the seeds.",
        "",
        "| " + " | ".join(header) + " |",
        "|" + "---|" * len(header),
    ]
    for key, entry in summary.items():
        cells = [str(k) for k in key] + [str(entry["count"])]
        for metric in ("initial_coverage", "max_coverage", "final_coverage", "iterations_to_95"):
            mean, sigma = entry[metric]
            cells.append(f"{mean:.3f}" if math.isnan(sigma) else f"{mean:.3f} ({sigma:.3f})")
        lines.append("| " + " | ".join(cells) + " |")
    failed = [r for r in rows if r.get("error")]
    if failed:
        lines += ["", f"{len(failed)} run(s) failed (see the `error` column of runs.csv)."]
    return "\n".join(lines) + "\n"


def run_sweep(
    config: SweepConfig,
    out: str | os.PathLike[str],
    *,
    source_text: str | None = None,
    execution: Mapping[str, Any] | None = None,
    **run_options: Any,
) -> list[dict[str, Any]]:
    """Run a sweep into the folder ``out``: ``runs.csv``, ``runs/``, ``config.json``, ``summary.md``.

    ``source_text`` (the TOML as written) is kept as ``sweep.toml``. ``run_options`` go to
    :func:`uavcov.experiments.run_specs` (``executor``, ``workers``, ``n_threads``, ``resume``,
    ``rerun``, ``save_runs``, ``progress``).
    """
    if run_options.get("executor") is None:
        plan_execution(run_options.get("workers"), run_options.get("n_threads"))  # refused before the folder is made
    specs = config.specs()  # a spec refused (a name too long for its run files) before the folder is made too
    folder = ResultsFolder(out)
    about = {"name": config.name, "base": config.base, "description": config.description, "axes": list(config.axes)}
    with folder.lock():
        folder.claim([*(["sweep.toml"] if source_text is not None else []), "summary.md"])
        rows = run_specs(specs, out=folder, command="sweep", execution=execution, about=about, **run_options)
        if source_text is not None:
            folder.write_text("sweep.toml", source_text)
        folder.write_text("summary.md", sweep_markdown(config, rows))
    return rows
