"""The realistic scenario's report, rebuilt from its rows at any time (finished or not):
``realistic.md`` (the table per start and measurement, the paper's finding scene by scene, the
sensed gap), ``runs.csv``, ``coverage.csv`` and the figures coverage against flight time (the
paper's Fig. 8 in seconds) and against rotor energy."""

from __future__ import annotations

import csv
import io
import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_write
from .._validate import as_path
from ..errors import ConfigError, MissingExtraError, ResultsFormatError
from ._jsonl import read_rows

__all__ = ["write_realistic_report", "realistic_report_markdown"]

_CURVES = ("curve_clock_s", "curve_energy_j", "curve_exact", "curve_sensed", "kinematic_curve")


def _number(value: Any) -> float:
    return float("nan") if value is None or value == "" else float(value)


def _stat(rows: list[dict[str, Any]], key: str, scale: float = 1.0, digits: int = 3) -> str:
    values = np.array([_number(r[key]) for r in rows], dtype=float) * scale
    values = values[np.isfinite(values)]
    return f"{values.mean():.{digits}f} ({values.std():.{digits}f})" if values.size else "-"


def _least(rows: list[dict[str, Any]], key: str, digits: int = 2) -> str:
    values = np.array([_number(r.get(key)) for r in rows], dtype=float)
    values = values[np.isfinite(values)]
    return f"{values.min():.{digits}f}" if values.size else "-"


def _count(rows: list[dict[str, Any]], key: str) -> str:
    values = [r.get(key) for r in rows]
    known = [int(v) for v in values if v is not None and v != ""]
    return str(sum(known)) if known else "-"


def _groups(rows: list[dict[str, Any]]) -> list[tuple[str, str, list[dict[str, Any]]]]:
    return [
        (start, measurement, mine)
        for start in sorted({r["start"] for r in rows})
        for measurement in sorted({r["measurement"] for r in rows})
        if (mine := [r for r in rows if r["start"] == start and r["measurement"] == measurement])
    ]


def _table(rows: list[dict[str, Any]]) -> str:
    lines = [
        (
            "| start | measurement | runs | failed | flown best | kinematic best | flown - kinematic | sensed - exact "
            "| flight time (s) | time to 95 % (s) | energy per UAV (kJ) |"
        ),
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for start, measurement, mine in _groups(rows):
        lines.append(
            f"| {start} | {measurement} | {len(mine)} | {sum(bool(r['failure']) for r in mine)} | {_stat(mine, 'flown_best')} "
            f"| {_stat(mine, 'kinematic_best')} | {_stat(mine, 'best_difference')} | {_stat(mine, 'mean_sensed_gap')} "
            f"| {_stat(mine, 'flight_time_s', digits=0)} | {_stat(mine, 'time_to_95_s', digits=0)} "
            f"| {_stat(mine, 'energy_j_mean', 1e-3, 1)} |"
        )
    return "\n".join(lines) + "\n"


def _safety_table(rows: list[dict[str, Any]]) -> str:
    """Every flown state against the limits; in brackets the straight commanded moves sampled at
    the same instants (what the kinematic model flies), where the rows have them."""
    lines = [
        (
            "| start | measurement | runs | least clearance (m) | least distance to the mesh, flown (straight) (m) "
            "| states under h_min, flown (straight) | over h_max, flown (straight) | closer than d_safe | max deviation (m) "
            "| max overshoot (m) |"
        ),
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for start, measurement, mine in _groups(rows):
        lines.append(
            f"| {start} | {measurement} | {len(mine)} | {_least(mine, 'min_clearance_m')} "
            f"| {_least(mine, 'min_distance_m')} ({_least(mine, 'straight_min_distance_m')}) "
            f"| {_count(mine, 'below_h_min')} ({_count(mine, 'straight_below_h_min')}) "
            f"| {_count(mine, 'above_h_max')} ({_count(mine, 'straight_above_h_max')}) | {_count(mine, 'too_close')} "
            f"| {_stat(mine, 'max_deviation_m', digits=3)} | {_stat(mine, 'max_overshoot_m', digits=3)} |"
        )
    return "\n".join(lines) + "\n"


def _finding(rows: list[dict[str, Any]]) -> str:
    """The paper's finding scene by scene: the CVT start against the two pairs, per measurement."""
    lines = [
        (
            "| measurement | scenes with both starts | CVT best higher | CVT initial higher | CVT faster to 95 % "
            "| CVT - pairs, best (mean) | CVT - pairs, time to 95 % (s, mean) |"
        ),
        "|---|---|---|---|---|---|---|",
    ]
    for measurement in sorted({r["measurement"] for r in rows}):
        by = {(r["seed"], r["start"]): r for r in rows if r["measurement"] == measurement and not r["failure"]}
        seeds = sorted(s for s, start in by if start == "cvt" and (s, "pairs") in by)
        if not seeds:
            continue
        cvt, pairs = [by[(s, "cvt")] for s in seeds], [by[(s, "pairs")] for s in seeds]

        def diff(key: str, cvt: list[dict[str, Any]] = cvt, pairs: list[dict[str, Any]] = pairs) -> np.ndarray:
            return np.array([_number(a[key]) - _number(b[key]) for a, b in zip(cvt, pairs, strict=True)])

        best, initial, t95 = diff("flown_best"), diff("flown_initial"), diff("time_to_95_s")
        lines.append(
            f"| {measurement} | {len(seeds)} | {int((best > 0).sum())} | {int((initial > 0).sum())} | {int((t95 < 0).sum())} "
            f"| {np.nanmean(best):+.3f} | {np.nanmean(t95):+.0f} |"
        )
    return "\n".join(lines) + "\n"


def _csv(rows: list[dict[str, Any]], columns: list[str]) -> bytes:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=columns, lineterminator="\n", extrasaction="ignore")
    writer.writeheader()
    writer.writerows(rows)
    return buffer.getvalue().encode()


def _curve_rows(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    out = []
    for r in rows:
        for k, (t, j, e, s) in enumerate(zip(r["curve_clock_s"], r["curve_energy_j"], r["curve_exact"], r["curve_sensed"], strict=True)):
            out.append(
                {
                    "seed": r["seed"],
                    "start": r["start"],
                    "measurement": r["measurement"],
                    "k": k,
                    "clock_s": t,
                    "energy_j": j,
                    "exact": e,
                    "sensed": s,
                }
            )
    return out


def _figures(folder: Path, rows: list[dict[str, Any]]) -> list[str]:
    try:
        import matplotlib as mpl

        mpl.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:
        raise MissingExtraError(f"the realistic figures need matplotlib: pip install 'uavcov[plot]' ({exc})") from exc
    written = []
    colours = {"cvt": "tab:blue", "pairs": "tab:orange"}
    for name, key, xlabel, scale in (
        ("time", "curve_clock_s", "mission time (s)", 1.0),
        ("energy", "curve_energy_j", "rotor energy per UAV (kJ)", 1e-3),
    ):
        measurements = sorted({r["measurement"] for r in rows})
        fig, axes = plt.subplots(1, len(measurements), figsize=(5.5 * len(measurements), 4.0), squeeze=False, sharey=True)
        for ax, measurement in zip(axes[0], measurements, strict=True):
            labelled: set[str] = set()
            for r in rows:
                if r["measurement"] != measurement:
                    continue
                x = np.array([_number(v) for v in r[key]]) * scale
                y = np.array([_number(v) for v in r["curve_exact"]])
                label = r["start"] if r["start"] not in labelled else None
                labelled.add(r["start"])
                ax.plot(x, y, color=colours.get(r["start"], "tab:green"), alpha=0.5, lw=1.0, label=label)
            ax.set_title(f"CAO on the {measurement} measurement")
            ax.set_xlabel(xlabel)
            ax.legend()
        axes[0][0].set_ylabel("exact coverage at the reached states")
        fig.tight_layout()
        path = folder / f"realistic_coverage_{name}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path.name)
    return written


def _limits(config: dict[str, Any]) -> str:
    """The flight limits a folder was flown under, in words."""
    standoff = config.get("standoff_m")
    if standoff is None:
        return "Limits: the paper's eq. 2 (clearance straight down between h_min and h_max)."
    margin = config["sim"].get("limits_margin", 0.0)
    planned = f", planned {margin:g} m inside them (h_min and d_safe higher, h_max, z_max and the x-y bounds closer)" if margin else ""
    return (
        f"Limits: a 3D standoff (`--standoff {standoff:g}`): every waypoint at least {standoff:g} m from the nearest "
        "surface, wall or ground, and at most h_max from it; every move keeping it and d_safe between its ends "
        f"(sampled every 0.1 m) and the legs flown in step{planned} (not the paper's eq. 2: an ablation). The safety "
        "table judges the flown states against the limits themselves."
    )


def realistic_report_markdown(config: dict[str, Any], rows: list[dict[str, Any]], figures: list[str]) -> str:
    """The report's Markdown: settings, progress, the table, the finding, the figures."""
    planned = len(config["seeds"]) * len(config["starts"]) * len(config["measurements"])
    seeds = config["seeds"]
    walls = np.array([_number(r["wall_time_s"]) for r in rows])
    flights = np.array([_number(r["flight_time_s"]) for r in rows])
    speed = f"{np.nansum(flights) / np.nansum(walls):.2f}x real time" if rows else "-"
    parts = [
        "# Realistic scenario (paper Figs. 7-8, flown)\n",
        (
            f"Scenes {seeds[0]}-{seeds[-1]} ({len(seeds)}), starts {', '.join(config['starts'])}, CAO measurements "
            f"{', '.join(config['measurements'])}, {config['iterations']} CAO iterations: {len(rows)} of {planned} runs done "
            f"({np.nansum(walls) / 3600:.1f} h of wall time, the flights at {speed}). {_limits(config)}\n"
        ),
        (
            "Mean (standard deviation) over the runs; `sensed - exact` is the mean over a run's measurements of the "
            "sensed coverage minus the exact one at the same reached states.\n"
        ),
        _table(rows),
        (
            "Safety: every flown state (each 10 ms of each UAV) against the flight limits; in brackets the straight "
            "commanded moves sampled at the same instants, what the kinematic model flies (where the rows have them).\n"
        ),
        _safety_table(rows),
        *(
            ["The paper's finding (the CVT start higher and faster than two pairs), scene by scene:\n", _finding(rows)]
            if {"cvt", "pairs"} <= {r["start"] for r in rows}
            else []
        ),
        *(f"![{name}]({name})\n" for name in figures),
    ]
    return "\n".join(parts)


def _realistic_config(path: Path) -> dict[str, Any]:
    """A realistic run's ``config.json``, with the lists its report orders the rows by."""
    try:
        config = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:  # RecursionError: arrays nested thousands deep
        raise ResultsFormatError(f"{path} is not JSON: {exc}") from exc
    if not isinstance(config, dict) or not all(isinstance(config.get(key), list) for key in ("seeds", "starts", "measurements")):
        raise ResultsFormatError(f"{path} is not a realistic run's config (it needs the lists seeds, starts and measurements)")
    return config


def write_realistic_report(folder: str | os.PathLike[str]) -> Path:
    """(Re)write the report of the realistic run in ``folder`` from its rows; returns ``realistic.md``."""
    from ._realistic import CONFIG, ROW_KEYS, ROWS, realistic_rows_columns

    path = as_path(folder, "folder")
    if not (path / CONFIG).is_file():
        raise ConfigError(f"{path} holds no realistic run (no {CONFIG})")
    config = _realistic_config(path / CONFIG)
    rows = read_rows(path / ROWS, ROW_KEYS)
    order = {
        (s, st, m): k
        for k, (s, st, m) in enumerate((s, st, m) for s in config["seeds"] for st in config["starts"] for m in config["measurements"])
    }
    try:  # a row or a config.json missing what the report reads is a corrupt folder, not a KeyError
        rows.sort(key=lambda r: order.get((r["seed"], r["start"], r["measurement"]), len(order)))
        runs_csv = _csv(rows, realistic_rows_columns())
        coverage_csv = _csv(_curve_rows(rows), ["seed", "start", "measurement", "k", "clock_s", "energy_j", "exact", "sensed"])
        figures = _figures(path, rows) if rows else []
        markdown = realistic_report_markdown(config, rows, figures)
    except (KeyError, TypeError, ValueError, IndexError) as exc:
        raise ResultsFormatError(f"{path} holds rows or a {CONFIG} its report cannot read: {type(exc).__name__}: {exc}") from None
    atomic_write(path / "runs.csv", runs_csv)
    atomic_write(path / "coverage.csv", coverage_csv)
    report = path / "realistic.md"
    atomic_write(report, markdown.encode())
    return report
