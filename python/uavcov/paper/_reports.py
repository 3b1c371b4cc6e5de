"""Reports of a results folder: Markdown tables beside the paper's numbers, and coverage curves.

Every function here only reads: rows of ``runs.csv`` (:func:`uavcov.experiments.read_runs`) and the
runs stored beside it. :func:`summarise` gives mean and sigma per cell; ``table1_markdown`` and
its siblings set a reproduction beside :mod:`uavcov.experiments`'s published numbers, with the checks
the reproduction is held to; ``coverage_curves_csv`` writes the coverage per iteration of
every stored run.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..experiments import ResultsFolder, finished_rows, summarise
from ..records import load_mission
from . import _data as paper


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
    lines += [f"- `{r['run_id']}`: {r['error']}" for r in failed[:10]]
    return "\n".join(lines) + "\n"


_METRIC = {"initial": "initial_coverage", "max": "max_coverage"}


def table1_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """Table 1 as Markdown: ours, mean (sigma) over the terrains, beside the paper's.

    Also lists the reproduction bar per cell (mean within 0.05 of the paper's, sigma within a
    factor of 2) and the order CVT > random > corner of mean max coverage per N.
    """
    rows = list(rows)
    ok = finished_rows(rows)
    summary = summarise(ok, by=("n_uavs", "init"))
    sizes = sorted({int(r["n_uavs"]) for r in rows}) or sorted({n for n, _, _ in paper.PUBLISHED_TABLE1})
    columns = [("cvt", "initial"), ("cvt", "max"), ("random", "initial"), ("random", "max"), ("corner", "initial"), ("corner", "max")]
    if any(r.get("init") == "greedy" for r in rows):  # greedy on S' (issue 36): new runs, no published numbers
        columns += [("greedy", "initial"), ("greedy", "max")]

    def ours(n: int, start: str, metric: str) -> tuple[float, float] | None:
        entry = summary.get((n, start))
        return None if entry is None else entry[_METRIC[metric]]

    counts = sorted({e["count"] for e in summary.values()})
    lines = [
        "# Table 1: coverage, mean (sigma) over the terrains",
        "",
        f"Ours: {_seed_text(ok)}, {'/'.join(str(c) for c in counts) or 0} terrain(s) per cell; the paper: 40 terrains.",
        'd_max = 25 m, 30 prior samples, CAO; "max" is the best coverage reached during the run.',
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


def _table(title: str, intro: Sequence[str], header: Sequence[str], body: Iterable[Sequence[str]]) -> list[str]:
    """A Markdown section: ``# title``, the intro lines, then a table of ``header`` and ``body`` rows."""
    lines = [f"# {title}", "", *intro, "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(cells) + " |" for cells in body]


def _by_start(rows: Sequence[Mapping[str, Any]]) -> tuple[list[Mapping[str, Any]], dict[tuple[Any, ...], dict[str, Any]]]:
    ok = finished_rows(rows)
    return ok, summarise(ok, by=("n_uavs", "init"))


def _published(value: Any) -> str:
    return f"{value.mean:.2f} ({value.sigma:.2f})"


def pyramid_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The pyramid prior (N = 12, 4 corners and the centre known) beside the paper's numbers."""
    rows = list(rows)
    ok, summary = _by_start(rows)
    published = paper.PUBLISHED_PYRAMID
    lines = _table(
        "Pyramid prior: coverage, mean (sigma) over the terrains",
        [f"Ours: {_seed_text(ok)}; the paper: 40 terrains. Only the 4 corners and the centre are known."],
        ["N", "start", "runs", "initial (ours)", "initial (paper)", "max (ours)", "max (paper)"],
        (
            [
                str(n),
                start,
                str(e["count"]),
                _cell(e["initial_coverage"]),
                _published(published["initial"]),
                _cell(e["max_coverage"]),
                _published(published["max"]),
            ]
            for (n, start), e in summary.items()
        ),
    )
    checks = [""]
    for (n, _start), entry in summary.items():
        for metric, column in (("initial", "initial_coverage"), ("max", "max_coverage")):
            off = entry[column][0] - published[metric].mean
            verdict = "within" if abs(off) <= 0.05 + 1e-12 else "NOT within"
            checks.append(f"- N = {n}, {metric}: {verdict} 0.05 of the paper's ({off:+.3f})")
    return "\n".join(lines + checks) + "\n" + _failures(rows)


def comparison_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The paper's Fig. 6 comparison (one scenario, three starts) beside its max coverages."""
    rows = list(rows)
    ok, summary = _by_start(rows)

    def paper_max(start: str) -> str:
        value = paper.PUBLISHED_FIG6_MAX.get(start)
        return "-" if value is None else f"{value:.2f}"

    lines = _table(
        "Single-scenario comparison (paper Fig. 6)",
        [f"Ours: {_seed_text(ok)}. Coverage per iteration is in coverage.csv."],
        ["N", "start", "runs", "initial", "max (ours)", "max (paper)", "iterations to 95 %"],
        (
            [
                str(n),
                start,
                str(e["count"]),
                _cell(e["initial_coverage"]),
                _cell(e["max_coverage"]),
                paper_max(start),
                _cell(e["iterations_to_95"], 0),
            ]
            for (n, start), e in summary.items()
        ),
    )
    return "\n".join(lines) + "\n" + _failures(rows)


def buildings_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The buildings scene: CVT start from the simplified map against two pairs on opposite sides."""
    rows = list(rows)
    ok, summary = _by_start(rows)
    lines = _table(
        "Buildings scene (paper Figs. 7-8)",
        [
            f"Ours: {_seed_text(ok)}. The paper: the CVT start begins higher and converges faster than two",
            "pairs of UAVs started on opposite sides (no numbers published). Coverage per iteration is in coverage.csv.",
        ],
        ["N", "start", "runs", "initial", "max", "final", "iterations to 95 %"],
        (
            [
                str(n),
                start,
                str(e["count"]),
                _cell(e["initial_coverage"]),
                _cell(e["max_coverage"]),
                _cell(e["final_coverage"]),
                _cell(e["iterations_to_95"], 0),
            ]
            for (n, start), e in summary.items()
        ),
    )
    return "\n".join(lines) + "\n" + _failures(rows)


def example_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The illustrative example (paper Fig. 5): one run per seed, its coverage at a glance."""
    rows = list(rows)
    lines = _table(
        "Illustrative example (paper Fig. 5)",
        ["The paper: 9 UAVs, d_max = 35 m, 30 prior samples; the final coverage is close to 1."],
        ["seed", "N", "start", "iterations", "initial", "max", "final", "iterations to 95 %", "seconds"],
        (
            [
                str(r["seed"]),
                str(r["n_uavs"]),
                str(r["init"]),
                str(r["iterations"]),
                f"{r['initial_coverage']:.3f}",
                f"{r['max_coverage']:.3f}",
                f"{r['final_coverage']:.3f}",
                str(r["iterations_to_95"]),
                f"{r['wall_time_s']:.1f}",
            ]
            for r in finished_rows(rows)
        ),
    )
    return "\n".join(lines) + "\n" + _failures(rows)


REPORTS: Mapping[str, Callable[[Sequence[Mapping[str, Any]]], str]] = {
    "table1": table1_markdown,
    "pyramid": pyramid_markdown,
    "comparison": comparison_markdown,
    "buildings": buildings_markdown,
    "example": example_markdown,
}


def coverage_curves_csv(folder: ResultsFolder, rows: Sequence[Mapping[str, Any]]) -> Path | None:
    """Write ``coverage.csv``: the coverage per iteration of every stored run, one column each."""
    columns: list[tuple[str, np.ndarray]] = []
    for r in finished_rows(rows):
        path = folder.run_file(str(r["run_id"]))
        if path.is_file():
            columns.append((f"{r['init']}-n{r['n_uavs']}-s{r['seed']}", load_mission(path).coverage))
    if not columns:
        return None
    length = max(len(c) for _, c in columns)
    header = ["iteration"] + [name for name, _ in columns]
    return folder.write_csv("coverage.csv", header, ([k] + [float(c[k]) if k < len(c) else "" for _, c in columns] for k in range(length)))
