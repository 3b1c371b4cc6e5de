"""Every figure of a results directory, redrawn from what is stored, without rerunning anything.

:func:`plot_directory` reads ``runs.csv`` through :func:`uavcov.plotting._runs._read_runs` (the
bars of Table 1; the experiment and start of each stored run) and the runs saved in
``runs/*.npz``, and calls the figure functions of :mod:`uavcov.plotting._figures`, :mod:`uavcov.plotting._curves` and
:func:`~uavcov.plotting.animate_mission`. It reads cells with :func:`_runs._number`, so rows may
hold strings or parsed numbers.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import as_bool, as_count
from ..errors import InvalidTypeError, ResultsFolderError, ResultsFormatError
from ..records import load_mission
from . import _runs
from ._animation import animate_mission
from ._canvas import _close, _finish, _matplotlib, check_output
from ._curves import plot_coverage_curves, plot_table1
from ._distance import plot_coverage_distance
from ._figures import plot_approximation, plot_coverage_map, plot_cvt, plot_point_cloud
from ._runs import _number


def _safe(text: str) -> str:
    """``text`` usable in a file name: anything but letters, digits, ``-_.`` becomes ``_``."""
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in text)


def plot_directory(directory: Any, out: Any = None, *, max_runs: int = 6, animation: bool = True, dpi: float = 110.0) -> list[Path]:
    """Redraw every figure of a results directory from what is stored, without rerunning anything.

    Reads ``DIR/runs.csv`` (one row per run) and ``DIR/runs/*.npz`` (runs saved by
    :func:`uavcov.records.save_mission`, named ``<run_id>.npz``; the row with that ``run_id``
    gives the run's experiment and start) and writes, into ``out`` (default ``DIR/figures``):

    - ``<experiment>_max_coverage.png`` and ``<experiment>_initial_coverage.png``: the bars of
      :func:`plot_table1`, beside the paper where it has numbers (only for experiments with
      several runs per start and team size);
    - ``<experiment>_coverage_distance.png``: ``uavcov.plotting._distance.plot_coverage_distance``, max
      coverage against the distance flown (where ``runs.csv`` records it);
    - ``<experiment>_coverage_N<n>_d<d_max>.png``: :func:`plot_coverage_curves` of every stored
      run of that experiment, team size and range, one colour per start (the paper's Fig. 6
      maxima drawn for the "comparison" experiment);
    - for up to ``max_runs`` stored runs (the first of each experiment, start and team size,
      then in name order): ``<run>_approximation.png``, ``<run>_cvt.png`` (CVT starts),
      ``<run>_coverage_map.png``, ``<run>_coverage_top.png``, ``<run>_point_cloud.png`` and
      ``<run>_seen.ply``;
    - ``<run>_animation.gif`` for the first of them when ``animation`` is true.

    ``dpi`` is the resolution of the PNG files.

    Returns
    -------
    list of Path
        The files written, in that order.

    Raises
    ------
    ResultsFormatError
        No such directory, nothing to plot in it, a ``runs.csv`` without a required column, or
        a stored run that cannot be read (the message names the file and what is missing).
    ResultsFolderError
        ``out`` is a file or cannot be made.
    ImportError
        matplotlib is not installed (the ``uavcov[plot]`` extra).
    """
    if not isinstance(directory, (str, os.PathLike)):
        raise InvalidTypeError(f"directory must be a path string or os.PathLike, got {type(directory).__name__}")
    directory = Path(directory)
    if not directory.is_dir():
        raise ResultsFormatError(f"no results directory at {directory}")
    limit = as_count(max_runs, "max_runs", 1_000_000, minimum=0)
    animation = as_bool(animation, "animation")
    given, dpi = check_output(out, dpi)
    target = directory / "figures" if given is None else given
    runs_csv = directory / "runs.csv"
    run_files = _stored_runs(directory)
    if not runs_csv.is_file() and not run_files:
        raise ResultsFormatError(f"{directory} holds neither runs.csv nor runs/*.npz: nothing to plot")
    _matplotlib()
    if target.exists() and not target.is_dir():
        raise ResultsFolderError(f"the figures folder {target} is a file, not a directory")
    try:
        target.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ResultsFolderError(f"cannot make the figures folder {target}: {exc.strerror or exc}") from exc
    from ..paper import PUBLISHED_FIG6_MAX

    written: list[Path] = []
    rows = _runs._read_runs(runs_csv) if runs_csv.is_file() else []
    if not rows and not run_files:
        raise ResultsFormatError(f"{directory} holds an empty runs.csv and no runs/*.npz: nothing to plot")
    # Every figure names the settings its runs were made with (the hashes of runs.csv).
    hashes = sorted({str(r["settings_hash"]) for r in rows if r.get("settings_hash")})
    stamp = f"settings {', '.join(hashes[:3])}{' ...' if len(hashes) > 3 else ''}" if hashes else None

    def emit(fig: Any, path: Path) -> None:
        if stamp:
            # The bottom right corner: titles are centred at the top, axis labels centred below.
            fig.text(0.998, 0.002, stamp, ha="right", va="bottom", fontsize=7, color="0.45")
        _finish(fig, path, dpi)
        _close(fig)
        written.append(path)

    _bar_figures(rows, target, emit)

    # Curves of every stored run; whole results are kept only for the runs drawn one by one.
    row_of = {str(r.get("run_id")): r for r in rows if r.get("run_id")}
    curves: dict[tuple[str, int, float], dict[str, list[Any]]] = {}
    chosen: list[tuple[Path, Any]] = []
    kinds: set[tuple[str, str, int]] = set()
    for f in run_files:
        result = load_mission(f)
        row = row_of.get(f.stem, {})
        experiment = str(row.get("experiment") or "runs")
        init = str(row.get("init") or result.settings.start.kind)
        n, d = int(result.settings.n_uavs), float(result.settings.d_max)
        curves.setdefault((experiment, n, d), {}).setdefault(init, []).append(_Curve(result.coverage))
        if (experiment, init, n) not in kinds and len(chosen) < limit:
            kinds.add((experiment, init, n))
            chosen.append((f, result))
    for f in run_files:
        if len(chosen) >= limit:
            break
        if all(f != c for c, _ in chosen):
            chosen.append((f, load_mission(f)))
    for (experiment, n, d), groups in sorted(curves.items()):
        reference = dict(PUBLISHED_FIG6_MAX) if experiment == "comparison" else None
        title = f"{experiment}: coverage during the optimisation, N = {n}, d_max = {d:g} m"
        emit(plot_coverage_curves(groups, reference=reference, title=title), target / f"{_safe(experiment)}_coverage_N{n}_d{d:g}.png")

    for index, (f, r) in enumerate(chosen):
        stem = _safe(f.stem)
        figures: list[tuple[str, Any, dict[str, Any]]] = [("approximation", plot_approximation, {})]
        if r.cvt is not None:
            figures.append(("cvt", plot_cvt, {}))
        figures += [("coverage_map", plot_coverage_map, {}), ("coverage_top", plot_coverage_map, {"view": "top"})]
        for suffix, draw, options in figures:
            emit(draw(r, **options), target / f"{stem}_{suffix}.png")
        ply = target / f"{stem}_seen.ply"
        emit(plot_point_cloud(r, ply=ply), target / f"{stem}_point_cloud.png")
        written.append(ply)
        if animation and index == 0:
            written.append(animate_mission(r, target / f"{stem}_animation.gif"))
    return written


def _bar_figures(rows: list[dict[str, Any]], target: Path, emit: Callable[[Any, Path], None]) -> None:
    """Table 1's bars (and coverage against distance) of each experiment whose cells hold several runs."""
    by_experiment: dict[str, list[dict[str, Any]]] = {}
    for row in rows:
        by_experiment.setdefault(str(row.get("experiment") or "runs"), []).append(row)
    for experiment, group in sorted(by_experiment.items()):
        cells: dict[tuple[str, float | None], int] = {}
        for index, row in enumerate(group):
            if _number(row, "max_coverage", index) is not None:
                key = (str(row["init"]), _number(row, "n_uavs", index))
                cells[key] = cells.get(key, 0) + 1
        if not cells or max(cells.values()) < 2:
            continue  # one run per bar is a number, not a distribution: the curves show it
        for metric in ("max_coverage", "initial_coverage"):
            if metric not in group[0] or all(_number(r, metric, i) is None for i, r in enumerate(group)):
                continue
            emit(plot_table1(group, metric=metric), target / f"{_safe(experiment)}_{metric}.png")
        if any(_number(r, "distance_mean_m", i) is not None for i, r in enumerate(group) if "distance_mean_m" in r):
            emit(plot_coverage_distance(group), target / f"{_safe(experiment)}_coverage_distance.png")


def _stored_runs(directory: Path, *, folder: Path | None = None) -> list[Path]:
    """The runs a results folder stores, ``directory/runs/*.npz`` (or ``folder/*.npz``), in name order."""
    where = directory / "runs" if folder is None else folder
    if not where.is_dir():
        return []
    # Not the hidden files: ".tmp-*.npz" is what a save cut short by a crash leaves behind.
    return sorted(f for f in where.glob("*.npz") if not f.name.startswith(".") and f.is_file())


class _Curve:
    """Just the coverage curve of a stored run (what the curves figure needs)."""

    def __init__(self, coverage: np.ndarray) -> None:
        self.coverage = np.asarray(coverage)


def report_figures(folder: str | os.PathLike[str]) -> list[str]:
    """Draw a results folder's figures for a report (two runs each, no animation) into
    ``<folder>/figures``; their PNG file names. What :func:`uavcov.paper.reproduce_all`
    takes as ``figures=``."""
    return [os.path.basename(p) for p in plot_directory(folder, max_runs=2, animation=False) if str(p).endswith(".png")]
