"""The paper's realistic scenario flown (Figs. 7-8 with seconds): ``uavcov reproduce realistic``.

Four quadrotors (RotorPy's Hummingbird set, the closest to the paper's AR.Drone 2.0) with the
paper's 8 m omnidirectional sensor rendered as a depth camera, on the 24 m x 24 m buildings
scenes of :data:`uavcov.paper.BUILDINGS` (the same generator, mission and constraints: the CVT
start on the simplified map against two pairs at opposite sides). Every scene, start and
measurement (CAO maximising the exact coverage at the reached states, or the sensed one) is
flown once, beside its kinematic twin (:func:`uavcov.mission.run_mission`, same seed).

Long: rows go to ``rows.jsonl`` one by one as runs finish (:mod:`._jsonl`), so ``resume=True``
continues a stopped run; every flown run's states go to ``states/`` (what ``uavcov view``
shows); :func:`write_realistic_report` rebuilds ``realistic.md``, ``runs.csv``, ``coverage.csv``
and the figures from the rows at any time, finished or not.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Callable, Iterable
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import as_finite_float
from ..engine import Targets
from ..errors import ConfigError, InvalidInputError, ResultsFormatError
from ..experiments import Experiment, parse_seeds
from ..field import write_seen_ply
from ..mission import run_mission
from ..sim import MEASUREMENTS, FlownMission, SimSettings, fly_mission, save_flown
from ._data import BUILDINGS, TABLE1
from ._jsonl import append_row, read_rows

__all__ = [
    "REALISTIC_SEEDS",
    "REALISTIC_DEV_SEEDS",
    "FLOWN_TABLE1_SEEDS",
    "reproduce_realistic",
    "reproduce_flown_table1",
    "realistic_rows",
    "fly_experiment",
]

REALISTIC_SEEDS: tuple[int, ...] = tuple(range(20))
"""The 20 scenes of the realistic scenario (held-out seeds, as the buildings experiment's)."""
REALISTIC_DEV_SEEDS: tuple[int, ...] = (1000, 1001)
"""The development scenes the flight and sensing settings (dwell, control period, integrator,
depth resolution) were chosen on; the report is on :data:`REALISTIC_SEEDS`."""

_COLUMNS = (
    "seed", "start", "measurement", "iterations", "flown_best", "kinematic_best", "best_difference", "flown_initial",
    "kinematic_initial", "sensed_best", "mean_sensed_gap", "flight_time_s", "time_to_95_s", "energy_j_mean", "energy_j_max",
    "distance_m_mean", "min_clearance_m", "min_distance_m", "min_separation_m", "violations", "below_h_min", "above_h_max",
    "straight_above_h_max", "straight_below_h_min", "straight_min_distance_m", "too_close", "max_deviation_m",
    "max_overshoot_m", "failure", "wall_time_s",
)  # fmt: skip
ROWS = "rows.jsonl"
ROW_KEYS = ("seed", "start", "measurement")
"""What names a row of ``ROWS``: its scene, start and CAO measurement."""
CONFIG = "config.json"
STARTS = ("cvt", "pairs")


def realistic_rows(flown: FlownMission, kinematic_best: float, start: str) -> dict[str, Any]:
    """One ``runs.csv`` row: the flown mission beside its kinematic twin."""
    safety = flown.safety
    gap = flown.sensed - flown.exact
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
        "straight_below_h_min": safety.straight_below_h_min if safety else 0,
        "straight_min_distance_m": safety.straight_min_distance if safety else math.nan,
        "too_close": safety.too_close if safety else 0,
        "max_deviation_m": safety.max_deviation if safety else math.nan,
        "max_overshoot_m": safety.max_overshoot if safety else math.nan,
        "failure": flown.failure or "",
        "wall_time_s": flown.wall_time_s,
    }


def realistic_rows_columns() -> list[str]:
    """The columns of ``runs.csv``: :func:`realistic_rows`' keys."""
    return list(_COLUMNS)


def energy_at_measurements(run: FlownMission) -> np.ndarray:
    """Mean rotor energy per UAV (J) spent up to each measurement, from the first."""
    spent = np.cumsum(run.leg_energy_j.mean(axis=1))
    return np.asarray(spent[: run.exact.size] - spent[0]) if spent.size else np.empty(0)


def _finite(values: np.ndarray) -> list[float | None]:
    """JSON has no NaN: a missing value is null."""
    return [float(v) if math.isfinite(v) else None for v in np.asarray(values, dtype=np.float64)]


def _run(
    experiment: Experiment, n_uavs: int, task: tuple[int, str, str], iterations: int, sim: SimSettings, folder: Path, first: bool
) -> dict[str, Any]:
    """Fly one task and its kinematic twin; the row carries the curves the report draws."""
    seed, start, measurement = task
    terrain, known = experiment.scenario(seed), experiment.known(seed)
    spec = experiment.mission_settings(n_uavs, start).with_changes(iterations=iterations)
    flown = fly_mission(terrain, spec, replace(sim, measurement=measurement), known=known, rng=seed)
    kinematic = run_mission(terrain, spec, known=known, n_threads=1, rng=seed)
    name = f"s{seed:04d}_{start}_{measurement}"
    save_flown(flown, folder / "states" / f"{name}.npz", terrain)
    if first and len(flown.map_points):  # the paper's Fig. 7 (right): the team's fused cloud
        write_seen_ply(folder / f"realistic_cloud_{name}.ply", Targets(flown.map_points), np.ones(len(flown.map_points)))
    row = realistic_rows(flown, kinematic.best_coverage, start)
    row.update(
        curve_clock_s=_finite(flown.clock),
        curve_energy_j=_finite(energy_at_measurements(flown)),
        curve_exact=_finite(flown.exact),
        curve_sensed=_finite(flown.sensed),
        kinematic_curve=_finite(kinematic.coverage),
        kinematic_initial=float(kinematic.coverage[0]),
    )
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in row.items()}


def _config(
    name: str,
    n_uavs: int,
    seeds: tuple[int, ...],
    starts: tuple[str, ...],
    measurements: tuple[str, ...],
    iterations: int,
    sim: SimSettings,
) -> dict[str, Any]:
    """What a results folder was run with (JSON-ready): a resumed run must match it."""
    settings = asdict(sim)
    # Later settings at their defaults leave the config as it was: folders made before stay resumable.
    if not settings["flight"]["synchronous"]:
        del settings["flight"]["synchronous"]
    if not settings["limits_margin"]:
        del settings["limits_margin"]
    config = {
        "experiment": name, "n_uavs": n_uavs, "seeds": seeds, "starts": starts, "measurements": measurements,
        "iterations": iterations, "sim": settings,
    }  # fmt: skip
    return dict(json.loads(json.dumps(config, default=str)))


def reproduce_realistic(
    out: str | os.PathLike[str],
    *,
    seeds: Iterable[int] | str | None = None,
    starts: Iterable[str] = STARTS,
    measurements: Iterable[str] = MEASUREMENTS,
    iterations: int = 200,
    sim: SimSettings | None = None,
    resume: bool = False,
    progress: Callable[[str], None] | None = None,
    standoff: float | None = None,
) -> list[dict[str, Any]]:
    """Fly the paper's realistic scenario into ``out`` (resumable) and write its report there.

    Parameters
    ----------
    out : path
        Results folder (created): ``config.json``, ``rows.jsonl``, ``states/``, the report.
    seeds : iterable of int or str, optional
        Scenes (default the 20 scenes 0-19, ``REALISTIC_SEEDS``; a string such as ``"0-4"``).
    starts : iterable of str, default ("cvt", "pairs")
    measurements : iterable of str, default ("exact", "sensed")
        CAO's measurement (:data:`uavcov.sim.MEASUREMENTS`); each is one run per scene and start.
    iterations : int, default 200
        CAO iterations of every run.
    sim : SimSettings, optional
        How the team flies and senses (default :class:`SimSettings`: the omnidirectional depth
        camera at 64 x 128 pixels, settled legs without dwell; its ``measurement`` is replaced
        by each of ``measurements``).
    resume : bool
        Continue ``out``: skip the runs already in ``rows.jsonl`` (the settings must match).
    progress : callable, optional
        Called with one line per finished run.
    standoff : float, optional
        Metres. ``None`` (default): the paper's limits, eq. 2 (``h_min`` = 1 m to ``h_max`` =
        6 m of clearance straight down), which admit waypoints and moves millimetres from a
        wall. A value flies the team under a 3D standoff instead
        (``Constraints(clearance="standoff", move_step=0.1)``): every waypoint at least
        ``standoff`` and at most ``h_max`` from the nearest surface, wall or ground, every move
        keeping ``standoff`` and ``d_safe`` between its ends (sampled every 0.1 m), the legs
        flown in step (``FlightSettings(synchronous=True)``), planned ``LIMITS_MARGIN`` inside
        the limits the flown states are judged against (``SimSettings(limits_margin=...)``):
        mechanisms the paper's simulations lack, an ablation reported beside the paper's limits.

    Returns
    -------
    list of dict
        The rows, in task order (scene, start, measurement).
    """
    experiment = BUILDINGS
    if standoff is not None:
        standoff = as_finite_float(standoff, "standoff")
        paper, size = BUILDINGS.mission.constraints, BUILDINGS.generator.size
        ceiling = paper.h_max - 2.0 * LIMITS_MARGIN  # type: ignore[operator]
        if not 0.0 < standoff < ceiling:
            raise InvalidInputError(f"standoff must be in (0, {ceiling:g}) m, got {standoff}")
        experiment = BUILDINGS.with_changes(
            **{
                "constraints.clearance": "standoff",
                "constraints.move_step": MOVE_STEP,
                # planned inside the flight limits by the margin the flown path needs
                "constraints.h_min": standoff + LIMITS_MARGIN,
                "constraints.h_max": paper.h_max - LIMITS_MARGIN,  # type: ignore[operator]
                "constraints.d_safe": paper.d_safe + LIMITS_MARGIN,
                "constraints.z_max": paper.z_max - LIMITS_MARGIN,
                "constraints.bounds": (LIMITS_MARGIN, LIMITS_MARGIN, size - LIMITS_MARGIN, size - LIMITS_MARGIN),
            }
        )
    chosen = REALISTIC_SEEDS if seeds is None else tuple(parse_seeds(seeds) if isinstance(seeds, str) else seeds)
    starts, measurements = tuple(starts), tuple(measurements)
    if not starts or not set(starts) <= set(STARTS):
        raise InvalidInputError(f"starts must be among {STARTS}, got {starts}")
    if not measurements or not set(measurements) <= set(MEASUREMENTS):
        raise InvalidInputError(f"measurements must be among {MEASUREMENTS}, got {measurements}")
    sim = SimSettings() if sim is None else sim
    if standoff is not None:
        sim = replace(sim, flight=replace(sim.flight, synchronous=True), limits_margin=LIMITS_MARGIN)
    config = _config("realistic", 4, chosen, starts, measurements, iterations, sim)
    if standoff is not None:  # absent from the paper's limits' config, which stands as it was
        config["standoff_m"] = standoff
    return fly_experiment(Path(out), experiment, config, sim, resume=resume, progress=progress)


def fly_experiment(
    folder: Path,
    experiment: Experiment,
    config: dict[str, Any],
    sim: SimSettings,
    *,
    resume: bool,
    progress: Callable[[str], None] | None,
) -> list[dict[str, Any]]:
    """Fly every task of ``config`` (scene x start x measurement) not yet in ``folder``'s rows, one
    by one, each row appended as it finishes; then rewrite the report from the rows."""
    from ._realistic_report import write_realistic_report

    folder.mkdir(parents=True, exist_ok=True)
    config_path, rows_path = folder / CONFIG, folder / ROWS
    if config_path.exists() or rows_path.exists():
        if not resume:
            raise ConfigError(f"{folder} holds a flown experiment already: resume it (--resume) or choose another --out")
        try:
            if config_path.exists() and not config_path.is_file():  # a FIFO would block the read forever
                raise OSError(f"{CONFIG} is not a regular file")
            recorded = json.loads(config_path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
            raise ResultsFormatError(f"{folder} cannot be resumed: its {CONFIG} is missing or unreadable ({exc})") from None
        if recorded != config:
            raise ConfigError(f"{folder} was run with other settings; choose another --out")
    else:
        config_path.write_text(json.dumps(config, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    tasks = [(seed, start, m) for seed in config["seeds"] for start in config["starts"] for m in config["measurements"]]
    done = {(r["seed"], r["start"], r["measurement"]): r for r in read_rows(rows_path, ROW_KEYS)}
    say = progress or (lambda message: None)
    for k, task in enumerate(tasks):
        if task in done:
            continue
        row = _run(experiment, config["n_uavs"], task, config["iterations"], sim, folder, first=k == 0)
        append_row(rows_path, row)
        done[task] = row
        outcome = f"failed: {row['failure']}" if row["failure"] else f"best {row['flown_best']:.3f} (kinematic {row['kinematic_best']:.3f})"
        say(f"{len(done)}/{len(tasks)}: scene {task[0]} {task[1]} {task[2]}: {outcome}, {row['wall_time_s']:.0f} s")
    write_realistic_report(folder)
    return [done[t] for t in tasks]


MOVE_STEP = 0.1
"""Metres between the samples of a move under ``reproduce_realistic(standoff=...)``: a move may
come nearer than sampled by half of it (5 cm), beside the flown path's 3 cm from its move."""
LIMITS_MARGIN = MOVE_STEP / 2 + 0.03
"""Metres the standoff scenario plans inside its flight limits: half a move's sampling step plus
the flown path's farthest from its straight move (2.9 cm over the 80 runs planned without it)."""

FLOWN_TABLE1_SEEDS: tuple[int, ...] = (0, 1, 2)
"""The terrains of Table 1 flown at N = 12 (the first three of its held-out seeds)."""


def reproduce_flown_table1(
    out: str | os.PathLike[str],
    *,
    seeds: Iterable[int] | str | None = None,
    starts: Iterable[str] = ("cvt", "random", "corner"),
    iterations: int = 100,
    sim: SimSettings | None = None,
    resume: bool = False,
    progress: Callable[[str], None] | None = None,
) -> list[dict[str, Any]]:
    """Table 1 at N = 12 flown against kinematic on a few terrains (resumable, as
    :func:`reproduce_realistic`): the paper's three starts, CAO on the exact measurement (the
    table's), ``iterations`` CAO iterations (the table's 500 are 5 times the flight)."""
    chosen = FLOWN_TABLE1_SEEDS if seeds is None else tuple(parse_seeds(seeds) if isinstance(seeds, str) else seeds)
    starts = tuple(starts)
    if not starts or not set(starts) <= {"cvt", "random", "corner"}:
        raise InvalidInputError(f"starts must be among ('cvt', 'random', 'corner'), got {starts}")
    sim = SimSettings(render=False) if sim is None else sim
    config = _config("table1", 12, chosen, starts, ("exact",), iterations, sim)
    return fly_experiment(Path(out), TABLE1, config, sim, resume=resume, progress=progress)
