"""Figures of many runs: coverage per iteration and Table 1's means, ours beside the paper's.

- :func:`plot_coverage_curves`: coverage per iteration, mean and one sigma per start (Fig. 5d,
  Fig. 6, Fig. 8);
- :func:`plot_table1`: the means of Table 1 as bars, ours beside the paper's
  (``published_values``).

Each takes mission results, paths to saved runs or rows of a ``runs.csv``, draws into a new
``matplotlib.figure.Figure`` or the ``ax`` it is given, saves to ``out`` when asked and returns
the figure.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from .._validate import as_bool, as_optional_str, is_0d_array
from ..errors import InvalidTypeError, ResultsFormatError
from . import _runs
from ._canvas import (
    INIT_COLOURS,
    _finish,
    _line,
    _new_axes,
    _patch,
)
from ._inputs import _as_result, _curve, _setting
from ._runs import _number

# ---------------------------------------------------------------------------------------------
# Fig. 5d / 6 / 8: coverage per iteration


def _group_results(results: Any, group_by: str) -> dict[str, list[Any]]:
    if isinstance(results, Mapping):
        groups = {str(k): list(v) if isinstance(v, (list, tuple)) else [v] for k, v in results.items()}
    else:
        if isinstance(results, (str, os.PathLike)) or not isinstance(results, Iterable) or is_0d_array(results):
            results = [results]
        groups = {}
        for item in results:
            r = _as_result(item, ("coverage",))
            if group_by == "none":
                key = "runs"
            else:
                key = str(_setting(r, group_by))
                if key == "None":
                    raise ResultsFormatError(f"a result's spec has no {group_by!r} to group by")
            groups.setdefault(key, []).append(r)
    if not groups or not any(groups.values()):
        raise ResultsFormatError("no results to plot (empty)")
    return {k: [_as_result(r, ("coverage",)) for r in v] for k, v in groups.items() if v}


def _curve_stats(curves: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean and sample sigma (``ddof=1``, as the tables) per iteration over the runs that
    reached it, and how many did."""
    length = max(c.shape[0] for c in curves)
    stack = np.full((len(curves), length), np.nan)
    for i, c in enumerate(curves):
        stack[i, : c.shape[0]] = c
    count = np.isfinite(stack).sum(axis=0)
    mean = np.nanmean(stack, axis=0)
    squares = np.nansum((stack - mean) ** 2, axis=0)
    sigma = np.where(count > 1, np.sqrt(squares / np.maximum(count - 1, 1)), 0.0)
    return mean, sigma, count


def plot_coverage_curves(
    results: Any,
    *,
    group_by: str = "start",
    running_max: bool = False,
    show_runs: bool | None = None,
    reference: Mapping[str, float] | None = None,
    ax: Any = None,
    out: Any = None,
    title: str | None = None,
    dpi: float = 110.0,
) -> Any:
    """Coverage per iteration, one colour per group: the mean with a band of one sigma.

    Paper Fig. 5d (one run), Fig. 6 (three starts on one terrain) and Fig. 8 (buildings).

    Parameters
    ----------
    results : MissionResult, path, sequence of them, or mapping label -> sequence
        The runs. A mapping gives the groups and their legend labels directly.
    group_by : str
        Setting that splits a sequence into groups (default "start": cvt / random / corner);
        "none" puts every run in one group.
    running_max : bool
        Plot the best coverage so far instead of the coverage at each iteration.
    show_runs : bool, optional
        Draw each run thinly under the mean; default when a group has at most 10 runs.
    reference : mapping label -> float, optional
        A published value per group (e.g. the paper's Fig. 6 maxima), a share of the surface in
        [0, 1], drawn as a dashed line.
    ax : matplotlib Axes, optional
        Ordinary (2D) axes to draw in instead of a new figure.
    out : path, optional
        Save the figure there (format from the suffix).
    title : str, optional
        Replaces "Coverage during the optimisation".
    dpi : float
        Resolution of the saved file.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if not isinstance(group_by, str):
        raise InvalidTypeError(f"group_by must be a string, got {type(group_by).__name__}")
    running_max = as_bool(running_max, "running_max")
    if show_runs is not None:
        show_runs = as_bool(show_runs, "show_runs")
    if reference is not None and not isinstance(reference, Mapping):
        raise InvalidTypeError(f"reference must be None or a mapping of group names to shares, got {type(reference).__name__}")
    title = as_optional_str(title, "title")
    groups = _group_results(results, group_by)
    fig, ax = _new_axes(ax, three_d=False, figsize=(6.6, 4.2))
    handles = []
    fallback = iter(["#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"] * 10)
    order = sorted(groups, key=lambda k: (list(INIT_COLOURS).index(k) if k in INIT_COLOURS else 99, k))
    for key in order:
        runs = groups[key]
        curves = [_curve(r.coverage) for r in runs]
        if running_max:
            curves = [np.maximum.accumulate(c) for c in curves]
        colour = INIT_COLOURS.get(key) or next(fallback)
        mean, sigma, count = _curve_stats(curves)
        k = np.arange(mean.shape[0])
        if show_runs if show_runs is not None else len(curves) <= 10:
            for c in curves if len(curves) > 1 else []:
                ax.plot(np.arange(c.shape[0]), c, color=colour, linewidth=0.5, alpha=0.35)
        if len(curves) > 1:
            ax.fill_between(k, mean - sigma, mean + sigma, color=colour, alpha=0.18, linewidth=0)
        best = max(float(c.max()) for c in curves)
        what = f"{len(curves)} runs, mean and one sigma" if len(curves) > 1 else "1 run"
        ax.plot(k, mean, color=colour, linewidth=1.8)
        handles.append(_line(f"{key} ({what}; max {best:.3f})", color=colour, linewidth=1.8))
        if (count < len(curves)).any():
            ax.axvline(int(np.argmax(count < len(curves))), color=colour, linewidth=0.6, linestyle=":")
        if reference is not None and key in reference:
            value = float(reference[key])
            ax.axhline(value, color=colour, linewidth=1.0, linestyle="--")
            handles.append(_line(f"{key}: the paper's max ({value:.2f})", color=colour, linewidth=1.0, linestyle="--"))
    ax.set_xlabel("iteration")
    quality = all(_setting(r, "objective") == "quality" for runs in groups.values() for r in runs)  # what the curves measure
    if quality:
        ax.set_ylabel("best quality-weighted coverage so far" if running_max else "quality-weighted coverage")
    else:
        ax.set_ylabel("best coverage so far" if running_max else "coverage (share of the surface seen)")
    ax.grid(True, linewidth=0.4, alpha=0.5)
    ax.set_title(title or "Coverage during the optimisation", fontsize=10)
    ax.legend(handles=handles, fontsize=8, loc="lower right", framealpha=0.9)
    if fig.get_layout_engine() is None and ax is fig.axes[0] and len(fig.axes) == 1:
        fig.set_layout_engine("constrained")
    return _finish(fig, out, dpi)


# ---------------------------------------------------------------------------------------------
# Table 1 beside the paper


def plot_table1(
    rows: Any,
    *,
    metric: str = "max_coverage",
    paper: bool = True,
    ax: Any = None,
    out: Any = None,
    dpi: float = 110.0,
) -> Any:
    """Grouped bars: mean ``metric`` (with one sigma) per start and team size, ours beside the paper's.

    Parameters
    ----------
    rows : iterable of mappings, or a path to runs.csv
        Rows with at least ``experiment``, ``init``, ``n_uavs`` and ``metric`` (strings as the
        ``csv`` module gives them, or numbers and None). Rows whose value is empty, None or NaN
        (failed runs) are left out and counted in the title.
    metric : str
        Column to compare: "max_coverage" (paper Table 1's "Max.") or "initial_coverage".
    paper : bool
        Draw the paper's value (hatched) beside ours where it publishes one for the row's
        experiment ("table1", "pyramid"), start and N.
    ax, out, dpi
        As for :func:`plot_coverage_curves`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if not isinstance(metric, str) or not metric:
        raise InvalidTypeError(f"metric must be a column name (a string), got {type(metric).__name__}")
    if isinstance(rows, (str, os.PathLike)):
        rows = _runs._read_runs(rows)
    if isinstance(rows, Mapping) or not isinstance(rows, Iterable) or is_0d_array(rows):
        raise InvalidTypeError("rows must be an iterable of mappings (csv.DictReader rows) or a runs.csv path")
    rows = list(rows)
    if not rows:
        raise ResultsFormatError("no runs to plot (empty)")
    values: dict[tuple[str, str, int], list[float]] = {}
    failed = 0
    for index, row in enumerate(rows):
        if not isinstance(row, Mapping):
            raise InvalidTypeError(f"row {index} is a {type(row).__name__}, not a mapping")
        for column in ("experiment", "init", "n_uavs"):
            if column not in row:
                raise ResultsFormatError(f"row {index} of the runs has no {column!r} column")
        n = _number(row, "n_uavs", index)
        value = _number(row, metric, index)
        if value is None or n is None:
            failed += 1
            continue
        values.setdefault((str(row["experiment"]), str(row["init"]), int(n)), []).append(value)
    if not values:
        raise ResultsFormatError(f"no run has a value for {metric!r} ({failed} failed)")
    experiments = sorted({e for e, _, _ in values})
    series = sorted(
        {(e, i) for e, i, _ in values}, key=lambda s: (s[0], list(INIT_COLOURS).index(s[1]) if s[1] in INIT_COLOURS else 99, s[1])
    )
    sizes = sorted({n for _, _, n in values})
    published = published_values() if as_bool(paper, "paper") else {}

    fig, ax = _new_axes(ax, three_d=False, figsize=(max(6.0, 1.6 + 1.5 * len(sizes) * max(1, len(series)) / 3), 4.4))
    bars_per_series = 2 if any((e, metric, i, n) in published for e, i in series for n in sizes) else 1
    width = 0.8 / (len(series) * bars_per_series)
    fallback = iter(["#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"] * 10)
    handles = []
    for s_index, (experiment, init) in enumerate(series):
        colour = INIT_COLOURS.get(init) or next(fallback)
        name = init if len(experiments) == 1 else f"{experiment}/{init}"
        for n_index, n in enumerate(sizes):
            base = n_index - 0.4 + s_index * bars_per_series * width + width / 2
            ours = values.get((experiment, init, n))
            if ours:
                mean = float(np.mean(ours))
                sigma = float(np.std(ours, ddof=1)) if len(ours) > 1 else 0.0
                ax.bar(
                    base,
                    mean,
                    width,
                    yerr=sigma,
                    color=colour,
                    edgecolor="black",
                    linewidth=0.4,
                    error_kw={"elinewidth": 0.8, "capsize": 2},
                )
                ax.text(base, 0.01, f"{len(ours)}", ha="center", va="bottom", fontsize=6, color="white")
            ref = published.get((experiment, metric, init, n))
            if ref is not None and bars_per_series == 2:
                ax.bar(
                    base + width,
                    ref[0],
                    width,
                    yerr=ref[1],
                    color=colour,
                    alpha=0.35,
                    hatch="///",
                    edgecolor="black",
                    linewidth=0.4,
                    error_kw={"elinewidth": 0.8, "capsize": 2},
                )
        handles.append(_patch(colour, f"{name}: ours"))
        if bars_per_series == 2 and any((experiment, metric, init, n) in published for n in sizes):
            from matplotlib.patches import Patch

            handles.append(Patch(facecolor=colour, alpha=0.35, hatch="///", edgecolor="black", linewidth=0.4, label=f"{name}: paper"))
    ax.set_xticks(range(len(sizes)), [f"N = {n}" for n in sizes])
    ax.set_xlim(-0.6, len(sizes) - 0.4)
    ax.set_ylim(0.0, 1.08)
    ax.set_ylabel(f"mean {metric.replace('_', ' ')} (error bar: one sigma)")
    ax.set_xlabel("team size (white digits: our runs per bar)")
    ax.grid(True, axis="y", linewidth=0.4, alpha=0.5)
    note = f"; {failed} failed run(s) left out" if failed else ""
    ax.set_title(f"{', '.join(experiments)}: {metric.replace('_', ' ')} by start and team size{note}", fontsize=10)
    # Below the axes: bars may reach the top anywhere.
    ax.legend(
        handles=handles, fontsize=7, ncol=max(1, min(len(handles), 6)), loc="upper center", bbox_to_anchor=(0.5, -0.14), framealpha=0.9
    )
    if fig.get_layout_engine() is None and len(fig.axes) == 1:
        fig.set_layout_engine("constrained")
    return _finish(fig, out, dpi)


def published_values() -> dict[tuple[str, str, str, int], tuple[float, float]]:
    """The paper's numbers the bars can stand beside: ``(experiment, metric, init, N) -> (mean, sigma)``.

    From :mod:`uavcov.experiments`: Table 1 (experiment "table1", d_max = 25 m, 40 terrains) and the
    pyramid prior of section V-D (experiment "pyramid", N = 12, CVT start). ``metric`` is a
    ``runs.csv`` column: "initial_coverage" or "max_coverage".

    Returns
    -------
    dict
        ``(experiment, metric, init, N) -> (mean, sigma)``, shares of the surface in [0, 1].
    """
    from ..paper import PUBLISHED_PYRAMID, PUBLISHED_TABLE1  # only here: the paper's tables are not needed to draw our own runs

    metrics = {"initial": "initial_coverage", "max": "max_coverage"}
    values = {("table1", metrics[kind], init, int(n)): (v.mean, v.sigma) for (n, init, kind), v in PUBLISHED_TABLE1.items()}
    for kind, v in PUBLISHED_PYRAMID.items():
        values[("pyramid", metrics[kind], "cvt", 12)] = (v.mean, v.sigma)
    return values
