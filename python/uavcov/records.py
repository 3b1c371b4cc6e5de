"""Mission results on disk: one ``.npz`` per run, readable without rerunning anything.

A run file holds the arrays of a :class:`~uavcov.mission.MissionResult` (true and approximating
surfaces, prior, start, CVT, trajectory, coverage) and a JSON header with the settings and the
scalars. :func:`load_mission` rebuilds the result, so figures and tables can be redrawn from
stored runs; a file from an unknown format, or one missing a field, raises
:class:`~uavcov.errors.ResultsFormatError` naming what is missing.
"""

from __future__ import annotations

import json
import os
import tempfile
import zipfile
from pathlib import Path
from typing import Any

import numpy as np

from .cao import OptimizerTrace
from .cvt import CVTResult
from .errors import ResultsFormatError, UavcovError
from .mission import MissionResult, MissionSpec
from .starts import START_KINDS
from .surface import Terrain

__all__ = ["FORMAT", "save_mission", "load_mission"]

FORMAT = "uavcov.mission/2"
"""Format tag written in every run file; bump on any incompatible change."""

_FORMAT_1 = "uavcov.mission/1"  # a flat settings record instead of the MissionSpec; still read

_TRACE_ARRAYS = ("trajectory", "values", "measured", "step_sizes", "n_checked", "n_feasible", "best_positions")
_TRACE_TIMES = (("time_measure_s", "time_measure"), ("time_feasibility_s", "time_feasibility"), ("time_optimizer_s", "time_own"))
"""The trace's timings in the header: the name written, and the name of files from before the ``_s`` names."""
_CVT_ARRAYS = ("generators", "moves", "drift", "energy")


def _surface_arrays(prefix: str, terrain: Terrain) -> dict[str, np.ndarray]:
    if terrain.grid is not None:
        g = terrain.grid
        return {
            f"{prefix}_grid_z": np.asarray(g.z),
            f"{prefix}_grid_spacing": np.asarray(g.spacing, dtype=float),
            f"{prefix}_grid_origin": np.asarray(g.origin, dtype=float),
        }
    return {f"{prefix}_vertices": np.asarray(terrain.vertices), f"{prefix}_faces": np.asarray(terrain.faces)}


def _surface(prefix: str, arrays: dict[str, np.ndarray], path: Path) -> Terrain:
    if f"{prefix}_grid_z" in arrays:
        return Terrain.from_grid(
            arrays[f"{prefix}_grid_z"], tuple(arrays[f"{prefix}_grid_spacing"]), tuple(arrays[f"{prefix}_grid_origin"])
        )
    _require(arrays, (f"{prefix}_vertices", f"{prefix}_faces"), path)
    return Terrain(arrays[f"{prefix}_vertices"], arrays[f"{prefix}_faces"])


def _require(mapping: Any, names: tuple[str, ...], path: Path) -> None:
    missing = [n for n in names if n not in mapping]
    if missing:
        raise ResultsFormatError(f"{path} is missing {', '.join(missing)}")


def save_mission(result: MissionResult, path: str | os.PathLike[str]) -> Path:
    """Write ``result`` to ``path`` (an ``.npz`` file), atomically: a reader never sees half a file.

    Returns
    -------
    Path
        The file written.
    """
    path = Path(path)
    trace = result.trace
    header = {
        "format": FORMAT,
        "spec": result.spec.as_dict(),
        "seed": result.seed,
        "prior_kind": result.prior_kind,
        "scalars": {
            "best_coverage": result.best_coverage,
            "initial_coverage": result.initial_coverage,
            "final_coverage": result.final_coverage,
            "best_iteration": result.best_iteration,
            "iterations_to_95": result.iterations_to_95,
            "evaluations": result.evaluations,
            "wall_time_s": result.wall_time_s,
            "time_measure_s": result.time_measure_s,
            "time_optimizer_s": result.time_optimizer_s,
        },
        "trace": {
            "kind": trace.kind,
            "best_value": trace.best_value,
            "best_iteration": trace.best_iteration,
            "evaluations": trace.evaluations,
            **{name: getattr(trace, name) for name, _ in _TRACE_TIMES},
        },
        "cvt": None
        if result.cvt is None
        else {"iterations": result.cvt.iterations, "converged": result.cvt.converged, "seed": result.cvt.seed},
    }
    arrays: dict[str, np.ndarray] = {
        "header": np.array(json.dumps(header)),
        "prior_points": result.prior_points,
        "start_positions": result.start_positions,
        "coverage": result.coverage,
        **_surface_arrays("terrain", result.terrain),
        **_surface_arrays("approximation", result.approximation),
        **{f"trace_{name}": np.asarray(getattr(trace, name)) for name in _TRACE_ARRAYS},
    }
    if result.cvt is not None:
        arrays.update({f"cvt_{name}": np.asarray(getattr(result.cvt, name)) for name in _CVT_ARRAYS})
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=".npz")
    try:
        with os.fdopen(fd, "wb") as out:
            np.savez_compressed(out, **arrays)  # type: ignore[arg-type]
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def load_mission(path: str | os.PathLike[str]) -> MissionResult:
    """Read a run written by :func:`save_mission`.

    Files written before the trace's timings took their ``_s`` names (``time_measure``,
    ``time_feasibility``, ``time_own``) load as well.

    Raises
    ------
    ResultsFormatError
        The file does not exist, is not a run file, comes from another format version, or lacks
        a field (the message names it).
    """
    path = Path(path)
    if not path.is_file():
        raise ResultsFormatError(f"no run file at {path}")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in data.files}
    except (OSError, ValueError, zipfile.BadZipFile) as exc:
        raise ResultsFormatError(f"{path} is not a uavcov run file: {exc}") from exc
    _require(arrays, ("header",), path)
    try:
        header = json.loads(str(arrays["header"]))
    except json.JSONDecodeError as exc:
        raise ResultsFormatError(f"{path} has an unreadable header: {exc}") from exc
    if not isinstance(header, dict):
        raise ResultsFormatError(f"{path} has a header that is not a JSON object")
    if header.get("format") not in (FORMAT, _FORMAT_1):
        raise ResultsFormatError(f"{path} has format {header.get('format')!r}; this uavcov reads {FORMAT!r}")
    _require(header, ("settings" if header["format"] == _FORMAT_1 else "spec", "scalars", "trace"), path)
    _require(arrays, ("prior_points", "start_positions", "coverage", *(f"trace_{n}" for n in _TRACE_ARRAYS)), path)
    try:
        if header["format"] == _FORMAT_1:
            spec, seed, prior_kind = _spec_of_format_1(header)
        else:
            spec, seed, prior_kind = MissionSpec.from_dict(header["spec"]), header["seed"], str(header["prior_kind"])
        t = header["trace"]
        trace = OptimizerTrace(
            kind=t["kind"],
            **{name: arrays[f"trace_{name}"] for name in _TRACE_ARRAYS},
            best_value=t["best_value"],
            best_iteration=t["best_iteration"],
            evaluations=t["evaluations"],
            settings=spec.cao,
            **{new: t[old] if old in t and new not in t else t[new] for new, old in _TRACE_TIMES},
        )
        cvt = None
        if header.get("cvt") is not None:
            _require(arrays, tuple(f"cvt_{n}" for n in _CVT_ARRAYS), path)
            cvt = CVTResult(**{n: arrays[f"cvt_{n}"] for n in _CVT_ARRAYS}, **header["cvt"])
        s = header["scalars"]
        return MissionResult(
            spec=spec,
            seed=seed,
            prior_kind=prior_kind,
            terrain=_surface("terrain", arrays, path),
            prior_points=arrays["prior_points"],
            approximation=_surface("approximation", arrays, path),
            start_positions=arrays["start_positions"],
            cvt=cvt,
            trajectory=trace.trajectory,
            coverage=arrays["coverage"],
            best_positions=trace.best_positions,
            trace=trace,
            **s,
        )
    except (KeyError, TypeError, AttributeError, UavcovError) as exc:
        raise ResultsFormatError(f"{path} is missing or has a malformed field: {exc}") from exc


def _spec_of_format_1(header: dict[str, Any]) -> tuple[MissionSpec, int | None, str]:
    """The MissionSpec a format-1 file's flat settings record describes.

    Format 1 recorded a start built outside the mission as "given"; its kind is taken as "cvt"
    when the file holds a CVT run, else "random" (the runs.csv row names the true start).
    """
    raw = dict(header["settings"])
    kind = raw["start"] if raw["start"] in START_KINDS else ("cvt" if header.get("cvt") is not None else "random")
    spec = MissionSpec.from_dict(
        {
            "n_uavs": raw["n_uavs"],
            "d_max": raw["d_max"],
            "prior": raw["prior_kind"] if raw["prior_kind"] in ("random", "pyramid") else "random",
            "n_prior": raw["n_prior"],
            "start": {"kind": kind, "altitude": raw["start_altitude"]},
            "constraints": {"h_min": raw["h_min"], "z_max": raw["z_max"], "d_safe": raw["d_safe"], "check_moves": raw["check_moves"]},
            "cao": raw["cao"],
            "optimizer": raw["optimizer"],
            "iterations": raw["iterations"],
        }
    )
    return spec, raw.get("seed"), str(raw["prior_kind"])
