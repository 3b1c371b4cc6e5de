"""Table 1 against the certified bound: how far each start's best coverage is from the best possible.

For each scenario (terrain seed) and team size the oracle (:func:`uavcov.paper.oracle`)
certifies a bound on the true surface: no ``N`` candidates of the 5 m admissible lattice see
more. :func:`write_bounds` stores those rows as ``bounds.csv`` beside ``runs.csv``;
:func:`bounds_markdown` sets each start's best coverage as a share of its scenario's bound, with
Student's t intervals over the scenarios and paired differences against the CVT start (the same
terrain for both), the distance the UAVs flew and the start's off-line time. When the oracle
solved the lattice optimum (``oracle(..., exact=True)``), :func:`optimum_markdown` sets each
start against the optimum itself, and ``bounds.csv`` holds the optimum's columns too.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ResultsFormatError
from ..experiments import ResultsFolder, finished_rows
from ._oracle import OracleRow

BOUNDS_FILE = "bounds.csv"
_COLUMNS = tuple(f.name for f in fields(OracleRow))
# the optimum's columns, written only when the oracle solved it (a bounds.csv without them reads)
_OPTIMUM_COLUMNS = ("optimum", "optimum_bound", "optimum_status", "optimum_time_s")
_STARTS = ("cvt", "random", "corner", "greedy")


def write_bounds(folder: ResultsFolder, rows: Sequence[OracleRow]) -> Path:
    """Write the oracle's rows as ``bounds.csv`` in ``folder``."""
    columns = _COLUMNS if any(r.optimum_status for r in rows) else tuple(c for c in _COLUMNS if c not in _OPTIMUM_COLUMNS)
    return folder.write_csv(BOUNDS_FILE, columns, ([asdict(r)[c] for c in columns] for r in rows))


def read_bounds(path: str | Path) -> list[OracleRow]:
    """The rows of a ``bounds.csv`` (see :func:`write_bounds`)."""
    rows = []
    try:
        with open(path, encoding="utf-8", newline="") as handle:
            for record in csv.DictReader(handle):
                values: dict[str, Any] = {}
                for f in fields(OracleRow):
                    if f.name in _OPTIMUM_COLUMNS and f.name not in record:
                        continue  # written without the optimum: the field's default
                    text = record[f.name]
                    values[f.name] = int(text) if f.type in ("int", int) else text if f.type in ("str", str) else float(text)
                rows.append(OracleRow(**values))
    except (OSError, KeyError, ValueError, TypeError, csv.Error) as exc:
        raise ResultsFormatError(f"{path}: not a bounds.csv ({exc})") from exc
    return rows


def _runs_of(runs: Iterable[Mapping[str, Any]], scenarios: Mapping[tuple[int, int], Any]) -> tuple[list[Mapping[str, Any]], list[str]]:
    """The finished runs on ``scenarios`` (keyed by seed and team size), and the starts among them, in table order."""
    ok = [r for r in finished_rows(runs) if (int(r["seed"]), int(r["n_uavs"])) in scenarios]
    return ok, [s for s in _STARTS if any(r["init"] == s for r in ok)]


def _interval(values: np.ndarray) -> str:
    """``mean [low, high]``, a 95 % Student's t interval (the mean alone for one value)."""
    from scipy import stats

    mean = float(values.mean())
    if len(values) < 2:
        return f"{mean:.3f}"
    half = float(stats.t.ppf(0.975, len(values) - 1) * np.std(values, ddof=1) / math.sqrt(len(values)))
    return f"{mean:.3f} [{mean - half:.3f}, {mean + half:.3f}]"


def bounds_markdown(runs: Iterable[Mapping[str, Any]], bounds: Sequence[OracleRow]) -> str:
    """Each start's best coverage as a share of its scenario's certified bound, per team size.

    Parameters
    ----------
    runs : iterable of mapping
        Rows of ``runs.csv`` (Table 1's).
    bounds : sequence of OracleRow
        The oracle on the same scenarios and team sizes.
    """
    bound_of = {(r.seed, r.n_uavs): r for r in bounds}
    ok, starts = _runs_of(runs, bound_of)
    sizes = sorted({int(r["n_uavs"]) for r in ok})
    lines = [
        "# Table 1 against the certified bound",
        "",
        "Bound: per terrain, no N candidates of the admissible 5 m lattice (3 heights) over the TRUE surface see",
        "more (with or without the 1 m separation, which only lowers the best); the smaller of greedy's online",
        "bound (Leskovec et al. 2007) and the LP relaxation's dual bound, each certified by exact evaluation.",
        "Positions off the lattice can see a little more (benches/README.md measures how the bound moves as the",
        "lattice is refined). Shares are max coverage / bound per terrain: mean [95 % t interval] over the terrains.",
        "",
        "| N | terrains | bound | online / LP dual | oracle greedy | " + " | ".join(f"{s} max / bound" for s in starts) + " |",
        "|---|---|---|---|---|" + "---|" * len(starts),
    ]
    share: dict[tuple[int, str], dict[int, float]] = {}
    for r in ok:
        key = (int(r["n_uavs"]), str(r["init"]))
        share.setdefault(key, {})[int(r["seed"])] = float(r["max_coverage"]) / bound_of[(int(r["seed"]), int(r["n_uavs"]))].bound
    for n in sizes:
        of_n = [b for b in bounds if b.n_uavs == n]
        cells = [
            str(n),
            str(len(of_n)),
            f"{np.mean([b.bound for b in of_n]):.3f}",
            f"{np.mean([b.online_bound for b in of_n]):.3f} / {np.mean([b.dual_bound for b in of_n]):.3f}",
            f"{np.mean([b.coverage for b in of_n]):.3f}",
        ]
        for s in starts:
            values = share.get((n, s), {})
            cells.append(_interval(np.array(list(values.values()))) if values else "-")
        lines.append("| " + " | ".join(cells) + " |")
    lines += ["", "## Paired against the CVT start (same terrain), and the cost", ""]
    lines += [
        "Difference of max / bound, start minus CVT, mean [95 % paired t interval]; distance is the mean distance a UAV",
        "flew (m), mean over the runs; off-line is the start's time on S' (CVT, or the greedy start's lattice, matrix",
        "and greedy), mean seconds a run.",
        "",
        "| N | start | pairs | minus CVT | distance m | off-line s |",
        "|---|---|---|---|---|---|",
    ]
    for n in sizes:
        for s in starts:
            runs_here = [r for r in ok if int(r["n_uavs"]) == n and r["init"] == s]
            if not runs_here:
                continue
            cvt = share.get((n, "cvt"), {})
            own = share.get((n, s), {})
            seeds = sorted(set(cvt) & set(own))
            diff = "-" if s == "cvt" or not seeds else _interval(np.array([own[k] - cvt[k] for k in seeds]))
            distance = _mean_of(runs_here, "distance_mean_m")
            offline = _mean_of(runs_here, "start_time_s")
            lines.append(f"| {n} | {s} | {len(seeds)} | {diff} | {distance} | {offline} |")
    text = "\n".join(lines) + "\n"
    if any(b.optimum_status for b in bounds):
        text += "\n" + optimum_markdown(runs, bounds)
    return text


@dataclass(frozen=True)
class _Solved:
    """An oracle row's optimum columns, present."""

    n_uavs: int
    coverage: float
    optimum: float
    optimum_bound: float
    optimum_status: str
    optimum_time_s: float

    @classmethod
    def of(cls, row: OracleRow) -> _Solved:
        if row.optimum is None or row.optimum_bound is None or row.optimum_time_s is None:
            raise ResultsFormatError(f"seed {row.seed}, N = {row.n_uavs}: an optimum status without its values")
        return cls(row.n_uavs, row.coverage, row.optimum, row.optimum_bound, row.optimum_status, row.optimum_time_s)


def optimum_markdown(runs: Iterable[Mapping[str, Any]], bounds: Sequence[OracleRow]) -> str:
    """Each start's best coverage as a share of its scenario's lattice optimum, per team size.

    Parameters
    ----------
    runs : iterable of mapping
        Rows of ``runs.csv`` (Table 1's); may be empty (then only the optimum's columns).
    bounds : sequence of OracleRow
        The oracle with ``exact=True`` on the same scenarios and team sizes.
    """
    solved = {(r.seed, r.n_uavs): _Solved.of(r) for r in bounds if r.optimum_status}
    ok, starts = _runs_of(runs, solved)
    lines = [
        "## Table 1 against the lattice optimum",
        "",
        "Optimum: per terrain, the best N candidates of the same lattice kept 1 m apart, by integer programming",
        "(`uavcov.cover.exact_placement`, HiGHS; proved within a relative gap of 1e-4 where 'proved' counts it,",
        "else the gap left at the time limit). Shares are max coverage / optimum per terrain: mean [95 % t interval];",
        "above 1 where CAO's positions off the lattice beat every lattice placement. Where not proved, 'optimum' is the",
        "best placement found (never below greedy's) and the certified bound says how far above it the optimum may be.",
        "",
        "| N | terrains | proved | optimum | certified bound | gap left (max) | solve s (median) | oracle greedy / optimum | "
        + " | ".join(f"{s} max / optimum" for s in starts)
        + " |",
        "|---|---|---|---|---|---|---|---|" + "---|" * len(starts),
    ]
    for n in sorted({n for _, n in solved}):
        of_n = [b for b in solved.values() if b.n_uavs == n]
        cells = [
            str(n),
            str(len(of_n)),
            str(sum(b.optimum_status == "optimal" for b in of_n)),
            f"{np.mean([b.optimum for b in of_n]):.4f}",
            f"{np.mean([b.optimum_bound for b in of_n]):.4f}",
            f"{max(b.optimum_bound - b.optimum for b in of_n):.4f}",
            f"{np.median([b.optimum_time_s for b in of_n]):.1f}",
            _interval(np.array([b.coverage / b.optimum for b in of_n])),
        ]
        for s in starts:
            shares = [
                float(r["max_coverage"]) / solved[(int(r["seed"]), n)].optimum for r in ok if int(r["n_uavs"]) == n and r["init"] == s
            ]
            cells.append(_interval(np.array(shares)) if shares else "-")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _mean_of(rows: Sequence[Mapping[str, Any]], column: str) -> str:
    values = [float(r[column]) for r in rows if r.get(column) is not None and not math.isnan(float(r[column]))]
    return f"{np.mean(values):.2f}" if values else "-"


def optimum_sweep_markdown(bounds: Sequence[OracleRow], time_limit: float) -> str:
    """The exact placement's sweep per team size: proved, gaps, wall times and the overshoot past ``time_limit``.

    Parameters
    ----------
    bounds : sequence of OracleRow
        Oracle rows with the optimum's columns (others are skipped).
    time_limit : float
        The limit the rows were solved with, seconds (the overshoot is each row's whole
        ``exact_placement`` call minus it).
    """
    solved = [_Solved.of(r) for r in bounds if r.optimum_status]
    lines = [
        "| N | instances | proved (gap <= 1e-4) | gap <= 1e-3 | gap median | gap max | s median | s max | overshoot max s |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    groups = [(str(n), [b for b in solved if b.n_uavs == n]) for n in sorted({b.n_uavs for b in solved})]
    for label, rows in [*groups, ("all", solved)] if solved else []:
        relative = np.array([(b.optimum_bound - b.optimum) / b.optimum_bound if b.optimum_bound > 0 else 0.0 for b in rows])
        times = np.array([b.optimum_time_s for b in rows])
        lines.append(
            f"| {label} | {len(rows)} | {sum(b.optimum_status == 'optimal' for b in rows)} | {int(np.sum(relative <= 1e-3))} | "
            f"{np.median(relative):.1e} | {relative.max():.1e} | {np.median(times):.1f} | {times.max():.1f} | "
            f"{times.max() - time_limit:+.1f} |"
        )
    return "\n".join(lines) + "\n"
