"""Coverage against the distance flown: what each start's best coverage costs in flight (issue 36)."""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from .._validate import is_0d_array
from ..errors import InvalidTypeError, ResultsFormatError
from . import _runs
from ._canvas import INIT_COLOURS, _finish, _new_axes
from ._runs import _number

_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*")


def plot_coverage_distance(rows: Any, *, ax: Any = None, out: Any = None, dpi: float = 110.0) -> Any:
    """Best coverage against the mean distance a UAV flew, one colour per start, one marker per team size.

    Parameters
    ----------
    rows : iterable of mappings, or a path to runs.csv
        Rows with ``init``, ``n_uavs``, ``max_coverage`` and ``distance_mean_m`` (metres); rows
        without a value (failed runs, folders made before the distance was recorded) are left out.
    ax, out, dpi
        As for :func:`uavcov.plotting.plot_coverage_curves`.

    Returns
    -------
    matplotlib.figure.Figure
        Each run a faint dot; each start and team size its mean with one sigma in both directions.
    """
    if isinstance(rows, (str, os.PathLike)):
        rows = _runs._read_runs(rows)
    if isinstance(rows, Mapping) or not isinstance(rows, Iterable) or is_0d_array(rows):
        raise InvalidTypeError("rows must be an iterable of mappings (csv.DictReader rows) or a runs.csv path")
    points: dict[tuple[str, int], list[tuple[float, float]]] = {}
    for index, row in enumerate(rows):
        if not isinstance(row, Mapping):
            raise InvalidTypeError(f"row {index} is a {type(row).__name__}, not a mapping")
        n, coverage = _number(row, "n_uavs", index), _number(row, "max_coverage", index)
        distance = _number(row, "distance_mean_m", index) if "distance_mean_m" in row else None
        if n is None or coverage is None or distance is None:
            continue
        points.setdefault((str(row.get("init")), int(n)), []).append((distance, coverage))
    if not points:
        raise ResultsFormatError("no run has both a max coverage and a distance flown")
    sizes = sorted({n for _, n in points})
    fig, ax = _new_axes(ax, three_d=False, figsize=(6.4, 4.6))
    fallback = iter(["#9467bd", "#8c564b", "#e377c2", "#7f7f7f"] * 10)
    colours: dict[str, str] = {}
    for (init, n), values in sorted(points.items()):
        colour = colours.setdefault(init, INIT_COLOURS.get(init) or next(fallback))
        marker = _MARKERS[sizes.index(n) % len(_MARKERS)]
        xy = np.array(values)
        ax.scatter(xy[:, 0], xy[:, 1], s=6, color=colour, alpha=0.25, marker=marker, linewidths=0)
        spread = xy.std(axis=0, ddof=1) if len(xy) > 1 else np.zeros(2)
        ax.errorbar(
            *xy.mean(axis=0),
            xerr=spread[0],
            yerr=spread[1],
            color=colour,
            marker=marker,
            markersize=6,
            markeredgecolor="black",
            capsize=2,
            linewidth=0.8,
        )
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=c, marker="o", linestyle="", label=init) for init, c in colours.items()]
    handles += [
        Line2D([], [], color="0.3", marker=_MARKERS[i % len(_MARKERS)], linestyle="", label=f"N = {n}") for i, n in enumerate(sizes)
    ]
    ax.legend(handles=handles, fontsize=7, loc="lower right", framealpha=0.9)
    ax.set_xlabel("mean distance a UAV flew (m)")
    ax.set_ylabel("max coverage")
    ax.grid(True, linewidth=0.4, alpha=0.5)
    ax.set_title("Best coverage against distance flown (mean, one sigma; dots: runs)", fontsize=10)
    if fig.get_layout_engine() is None and len(fig.axes) == 1:
        fig.set_layout_engine("constrained")
    return _finish(fig, out, dpi)
