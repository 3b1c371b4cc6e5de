"""The paper's realistic scenario flown (Figs. 7-8 with seconds): ``uavcov reproduce realistic``.

Four quadrotors (RotorPy's Hummingbird set, the closest to the paper's AR.Drone 2.0) with the
paper's 8 m omnidirectional sensor rendered as a depth camera, on the 24 m x 24 m buildings
scenes of :data:`uavcov.experiments.BUILDINGS` (the same generator, mission and constraints: the
CVT start on the simplified map against two pairs at opposite sides). Every scene and start is
flown once with CAO measuring at the reached states, and run once kinematically
(:func:`uavcov.mission.run_mission`, same seed) beside it.

Writes ``runs.csv`` (one row a run), ``coverage.csv`` (every measurement: mission seconds,
exact and sensed coverage, cumulative energy), ``realistic.md`` (the table), the figures
coverage against time and against energy, and the first CVT run's fused cloud as PLY.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_write
from ..engine import Targets
from ..errors import InvalidInputError, MissingExtraError
from ..experiments import parse_seeds
from ..field import write_seen_ply
from ..mission import run_mission
from ..sim import FlownMission, SimSettings, fly_mission
from ._data import BUILDINGS

__all__ = ["REALISTIC_SEEDS", "reproduce_realistic", "realistic_rows"]

REALISTIC_SEEDS: tuple[int, ...] = tuple(range(20))
"""The 20 scenes of the realistic scenario (held-out seeds, as the buildings experiment's)."""

_COLUMNS = (
    "seed",
    "start",
    "measurement",
    "iterations",
    "flown_best",
    "kinematic_best",
    "best_difference",
    "flown_initial",
    "sensed_best",
    "mean_sensed_gap",
    "flight_time_s",
    "time_to_95_s",
    "energy_j_mean",
    "energy_j_max",
    "distance_m_mean",
    "min_clearance_m",
    "min_distance_m",
    "min_separation_m",
    "violations",
    "below_h_min",
    "above_h_max",
    "straight_above_h_max",
    "too_close",
    "max_deviation_m",
    "max_overshoot_m",
    "failure",
    "wall_time_s",
)


def realistic_rows(flown: FlownMission, kinematic_best: float, start: str) -> dict[str, Any]:
    """One ``runs.csv`` row: the flown mission beside its kinematic twin."""
    safety = flown.safety
    gap = flown.exact - flown.sensed
    return {
        "seed": flown.seed,
        "start": start,
        "measurement": flown.sim.measurement,
        "iterations": len(flown.exact) - 1,
        "flown_best": flown.best_coverage,
        "kinematic_best": kinematic_best,
        "best_difference": flown.best_coverage - kinematic_best,
        "flown_initial": float(flown.exact[0]) if flown.exact.size else math.nan,
        "sensed_best": float(np.nanmax(flown.sensed)) if np.isfinite(flown.sensed).any() else math.nan,
        "mean_sensed_gap": float(np.nanmean(gap)) if np.isfinite(gap).any() else math.nan,
        "flight_time_s": flown.flight_time_s,
        "time_to_95_s": flown.time_to_fraction(0.95),
        "energy_j_mean": float(flown.energy_j.mean()),
        "energy_j_max": float(flown.energy_j.max()),
        "distance_m_mean": float(flown.distance_m.mean()),
        "min_clearance_m": safety.min_clearance if safety else math.nan,
        "min_distance_m": safety.min_distance if safety else math.nan,
        "min_separation_m": safety.min_separation if safety else math.nan,
        "violations": safety.violations if safety else 0,
        "below_h_min": safety.below_h_min if safety else 0,
        "above_h_max": safety.above_h_max if safety else 0,
        "straight_above_h_max": safety.straight_above_h_max if safety else 0,
        "too_close": safety.too_close if safety else 0,
        "max_deviation_m": safety.max_deviation if safety else math.nan,
        "max_overshoot_m": safety.max_overshoot if safety else math.nan,
        "failure": flown.failure or "",
        "wall_time_s": flown.wall_time_s,
    }


def _csv(rows: list[dict[str, Any]], columns: Iterable[str]) -> bytes:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(columns), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return buffer.getvalue().encode()


def _curve_rows(flown: FlownMission, start: str) -> list[dict[str, Any]]:
    energy = _energy_at_measurements(flown)
    return [
        {"seed": flown.seed, "start": start, "k": k, "clock_s": float(t), "energy_j": float(j), "exact": float(e), "sensed": float(s)}
        for k, (t, j, e, s) in enumerate(zip(flown.clock, energy, flown.exact, flown.sensed, strict=True))
    ]


def _table(rows: list[dict[str, Any]]) -> str:
    lines = [
        (
            "| start | runs | failed | flown best | kinematic best | flown - kinematic | sensed gap | flight time (s) "
            "| time to 95 % (s) | energy per UAV (kJ) | min clearance (m) | max deviation (m) | states under h_min "
            "| over h_max (straight moves) |"
        ),
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for start in sorted({r["start"] for r in rows}):
        mine = [r for r in rows if r["start"] == start]

        def stat(key: str, scale: float = 1.0, digits: int = 3, mine: list[dict[str, Any]] = mine) -> str:
            values = np.array([float(r[key]) for r in mine], dtype=float) * scale
            values = values[np.isfinite(values)]
            return f"{values.mean():.{digits}f} ({values.std():.{digits}f})" if values.size else "-"

        lines.append(
            f"| {start} | {len(mine)} | {sum(bool(r['failure']) for r in mine)} | {stat('flown_best')} | "
            f"{stat('kinematic_best')} | "
            f"{stat('best_difference')} | {stat('mean_sensed_gap')} | {stat('flight_time_s', digits=0)} | "
            f"{stat('time_to_95_s', digits=0)} | "
            f"{stat('energy_j_mean', 1e-3, 1)} | {stat('min_clearance_m', digits=2)} | {stat('max_deviation_m', digits=2)} | "
            f"{sum(int(r['below_h_min']) for r in mine)} | "
            f"{sum(int(r['above_h_max']) for r in mine)} ({sum(int(r['straight_above_h_max']) for r in mine)}) |"
        )
    return "\n".join(lines) + "\n"


def _figures(out: Path, curves: dict[str, list[FlownMission]]) -> list[str]:
    try:
        import matplotlib as mpl

        mpl.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:
        raise MissingExtraError(f"the realistic figures need matplotlib: pip install 'uavcov[plot]' ({exc})") from exc
    written = []
    for name, xlabel in (("time", "mission time (s)"), ("energy", "rotor energy per UAV (kJ)")):
        fig, ax = plt.subplots(figsize=(6.0, 4.0))
        for (start, runs), colour in zip(sorted(curves.items()), ("tab:blue", "tab:orange", "tab:green"), strict=False):
            for k, run in enumerate(runs):
                x = run.clock if name == "time" else _energy_at_measurements(run) / 1e3
                ax.plot(x, run.exact, color=colour, alpha=0.6, lw=1.0, label=start if k == 0 else None)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("exact coverage at the reached states")
        ax.legend()
        fig.tight_layout()
        path = out / f"realistic_coverage_{name}.png"
        fig.savefig(path, dpi=120)
        plt.close(fig)
        written.append(path.name)
    return written


def _energy_at_measurements(run: FlownMission) -> np.ndarray:
    """Mean rotor energy per UAV (J) spent up to each measurement."""
    spent = np.cumsum(run.leg_energy_j.mean(axis=1))
    return np.asarray(spent[: run.exact.size] - spent[0]) if spent.size else np.empty(0)


def reproduce_realistic(
    out: str | os.PathLike[str],
    *,
    seeds: Iterable[int] | str | None = None,
    starts: Iterable[str] = ("cvt", "pairs"),
    iterations: int = 200,
    sim: SimSettings | None = None,
) -> list[dict[str, Any]]:
    """Fly the paper's realistic scenario and write its results into ``out``.

    Parameters
    ----------
    out : path
        Results folder (created).
    seeds : iterable of int or str, optional
        Scenes (default ``REALISTIC_SEEDS``; a string such as ``"0-4"``).
    starts : iterable of str, default ("cvt", "pairs")
    iterations : int, default 200
        CAO iterations of every run.
    sim : SimSettings, optional
        How the team flies and senses (default :class:`SimSettings`: exact measurement, the
        omnidirectional depth camera at 64 x 128 pixels).

    Returns
    -------
    list of dict
        The rows of ``runs.csv``.
    """
    chosen = REALISTIC_SEEDS if seeds is None else tuple(parse_seeds(seeds) if isinstance(seeds, str) else seeds)
    starts = tuple(starts)
    if not set(starts) <= {"cvt", "pairs"}:
        raise InvalidInputError(f"starts must be among ('cvt', 'pairs'), got {starts}")
    sim = SimSettings() if sim is None else sim
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    rows: list[dict[str, Any]] = []
    curve_rows: list[dict[str, Any]] = []
    curves: dict[str, list[FlownMission]] = {s: [] for s in starts}
    for seed in chosen:
        terrain = BUILDINGS.terrain.make(seed)
        known = BUILDINGS.known(seed)
        for start in starts:
            spec = BUILDINGS.mission_settings(4, start).with_changes(iterations=iterations)
            flown = fly_mission(terrain, spec, sim, known=known, rng=seed)
            kinematic = run_mission(terrain, spec, known=known, n_threads=1, rng=seed)
            rows.append(realistic_rows(flown, kinematic.best_coverage, start))
            curve_rows.extend(_curve_rows(flown, start))
            curves[start].append(flown)
            if start == starts[0] and seed == chosen[0] and len(flown.map_points):
                write_seen_ply(
                    folder / f"realistic_cloud_s{seed:04d}_{start}.ply", Targets(flown.map_points), np.ones(len(flown.map_points))
                )
            atomic_write(folder / "runs.csv", _csv(rows, _COLUMNS))
    atomic_write(folder / "coverage.csv", _csv(curve_rows, ("seed", "start", "k", "clock_s", "energy_j", "exact", "sensed")))
    figures = _figures(folder, curves)
    report = [
        "# Realistic scenario (paper Figs. 7-8, flown)\n",
        f"Seeds {chosen[0]}-{chosen[-1]} ({len(chosen)} scenes), {iterations} CAO iterations, measurement {sim.measurement}.\n",
        _table(rows),
        *(f"![{name}]({name})\n" for name in figures),
    ]
    atomic_write(folder / "realistic.md", "\n".join(report).encode())
    return rows
