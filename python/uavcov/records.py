"""Mission results on disk: one ``.npz`` per run, readable without rerunning anything.

A run file holds the arrays of a :class:`~uavcov.mission.MissionResult` (true and approximating
surfaces, prior, start, CVT, trajectory, coverage) and a JSON header with the settings and the
scalars. :func:`load_mission` rebuilds the result, so figures and tables can be redrawn from
stored runs; a file from an unknown format, or one missing a field, raises
:class:`~uavcov.errors.ResultsFormatError` naming what is missing.
"""

from __future__ import annotations

import json
import math
import numbers
import os
import zipfile
import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ._io import atomic_write_with, make_parent
from ._validate import as_non_negative_float, checked_path_text, open_regular_file, read_only
from .engine import Terrain
from .errors import InvalidTypeError, ResultsFormatError, UavcovError
from .mission import MissionResult
from .optim import OptimizerTrace
from .placement import START_KINDS, CVTResult
from .settings import MissionSettings

__all__ = ["FORMAT", "save_mission", "load_mission"]

FORMAT = "uavcov.mission/2"
"""Format tag written in every run file; bump on any incompatible change."""

_FORMAT_1 = "uavcov.mission/1"  # a flat settings record instead of the MissionSettings; still read

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


def _as_path(path: Any) -> Path:
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidTypeError(f"path must be a string or os.PathLike, got {type(path).__name__}")
    return Path(checked_path_text(os.fspath(path), "path"))  # "" would be the working directory


# The header's scalars and their types: a file that says n_uavs = "many" is refused, not loaded.
_INT = (numbers.Integral,)
_REAL = (numbers.Real,)
_SCALAR_TYPES = {
    "best_coverage": _REAL,
    "initial_coverage": _REAL,
    "final_coverage": _REAL,
    "best_iteration": _INT,
    "iterations_to_95": _INT,
    "evaluations": _INT,
    "wall_time_s": _REAL,
    "time_measure_s": _REAL,
    "time_optimizer_s": _REAL,
    "start_time_s": _REAL,
}
_TRACE_TYPES = {"best_value": _REAL, "best_iteration": _INT, "evaluations": _INT}
_CVT_TYPES = {"iterations": _INT, "converged": (bool,), "seed": _INT}


def _check_fields(record: Any, types: Mapping[str, tuple[type, ...]], where: str, path: Path) -> None:
    if not isinstance(record, dict):
        raise ResultsFormatError(f"{path}: {where} must be a JSON object, got {type(record).__name__}")
    for name, kinds in types.items():
        if name not in record:
            continue  # missing fields are reported by name where they are read
        value = record[name]
        ok = isinstance(value, kinds) and (kinds == (bool,) or not isinstance(value, bool))
        if not ok:
            raise ResultsFormatError(f"{path}: {where}.{name} = {value!r} is not {'an integer' if kinds is _INT else 'a number'}")


def _check_durations(header: Mapping[str, Any], path: Path) -> None:
    """The record's durations are seconds >= 0 (``start_time_s`` NaN when unknown): a file that
    says -inf s, 10^400 s or "5" s is refused."""
    for where, names in (("scalars", ("wall_time_s", "start_time_s")), ("trace", tuple(n for pair in _TRACE_TIMES for n in pair))):
        record = header[where]
        for name in names:
            value = record.get(name, 0.0)
            if name == "start_time_s" and isinstance(value, float) and math.isnan(value):
                continue
            try:
                as_non_negative_float(value, name)
            except UavcovError:
                raise ResultsFormatError(f"{path}: {where}.{name} = {value!r} is not a duration (seconds >= 0)") from None


def _check_best(trace: OptimizerTrace, path: Path) -> None:
    """The trace's best iteration, value and positions and its evaluations restate its arrays, as
    every optimiser records them (``uavcov.optim._trace``): a file that says otherwise is refused."""
    best = int(np.argmax(trace.values)) if trace.values.size else 0
    restated = {
        "best_iteration": (trace.best_iteration, best),
        "best_value": (trace.best_value, float(trace.values[best]) if trace.values.size else None),
        "evaluations": (trace.evaluations, int(trace.values.shape[0])),
    }
    for name, (recorded, computed) in restated.items():
        if recorded != computed:
            raise ResultsFormatError(
                f"{path}: trace.{name} = {recorded!r} disagrees with the trace's values stored beside it ({computed!r})"
            )
    if trace.values.size and not np.array_equal(trace.best_positions, trace.trajectory[best]):
        raise ResultsFormatError(f"{path}: trace_best_positions disagrees with the trajectory at the best iteration ({best})")


def _check_arrays(arrays: dict[str, np.ndarray], spec: MissionSettings, cvt: Mapping[str, Any] | None, path: Path) -> None:
    """The arrays' shapes agree with each other, with the spec and with the CVT's record ``cvt`` (a corrupt file is refused)."""
    n_uavs = spec.n_uavs
    state = 3 + len(spec.free_angles)  # the optimiser's variables per UAV: a position, then free camera angles
    configurations = arrays["coverage"].shape[0] if arrays["coverage"].ndim == 1 else None
    moves = None if configurations is None else configurations - 1
    expected = {
        "prior_points": (None, 3),
        "start_positions": (n_uavs, 3),
        "coverage": (None,),
        "trace_trajectory": (configurations, n_uavs, state),
        "trace_values": (configurations,),
        "trace_measured": (configurations,),
        "trace_step_sizes": (moves,),
        "trace_n_checked": (moves,),
        "trace_n_feasible": (moves,),
        "trace_best_positions": (n_uavs, state),
    }
    check_shapes(arrays, expected, path)
    if cvt is not None:  # the CVT's record: its generators, and one value per iteration of each curve
        curves = {f"cvt_{name}": (cvt.get("iterations"),) for name in _CVT_ARRAYS[1:]}
        check_shapes(arrays, {"cvt_generators": (None, 3), **curves}, path)
        if "cvt_normals" in arrays:
            check_shapes(arrays, {"cvt_normals": arrays["cvt_generators"].shape}, path)


def check_shapes(arrays: Mapping[str, np.ndarray], expected: Mapping[str, tuple[int | None, ...]], path: Path) -> None:
    """Each named array of a stored run holds numbers in the shape expected (None: any length along
    that axis); :class:`~uavcov.errors.ResultsFormatError` naming the first that does not."""
    for name, shape in expected.items():
        array = arrays[name]
        if (
            array.dtype.kind not in "fiu"
            or array.ndim != len(shape)
            or any(want is not None and got != want for got, want in zip(array.shape, shape, strict=True))
        ):
            wanted = "(" + ", ".join("n" if d is None else str(d) for d in shape) + ")"
            raise ResultsFormatError(f"{path}: {name} has shape {array.shape} and dtype {array.dtype}, expected numbers of shape {wanted}")


def save_mission(result: MissionResult, path: str | os.PathLike[str]) -> Path:
    """Write ``result`` to ``path`` (an ``.npz`` file), atomically: a reader never sees half a file.

    Everything :func:`load_mission` needs to give the run back (settings, seed, true surface,
    S', prior, start, CVT, the optimiser's trace); ``uavcov view`` and ``uavcov plot`` read it.

    Parameters
    ----------
    result : MissionResult
        What :func:`uavcov.run_mission` returned.
    path : str or PathLike
        The file; ``.npz`` by convention.

    Returns
    -------
    Path
        The file written.

    Examples
    --------
    >>> import pathlib, tempfile, uavcov
    >>> hills = uavcov.gaussian_hills(size=40.0, spacing=2.0, n_hills=3, rng=1)
    >>> run = uavcov.run_mission(hills, uavcov.MissionSettings(n_uavs=3, d_max=15.0, iterations=5), rng=0)
    >>> path = uavcov.save_mission(run, pathlib.Path(tempfile.mkdtemp()) / "run.npz")
    >>> back = uavcov.load_mission(path)
    >>> back.best_coverage == run.best_coverage, back.trajectory.shape
    (True, (6, 3, 3))
    """
    if not isinstance(result, MissionResult):
        raise InvalidTypeError(f"result must be a MissionResult, got {type(result).__name__}")
    path = _as_path(path)
    trace = result.trace
    header = {
        "format": FORMAT,
        "spec": result.settings.as_dict(),
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
            "start_time_s": result.start_time_s,
        },
        "trace": {
            "kind": trace.kind,
            "best_value": trace.best_value,
            "best_iteration": trace.best_iteration,
            "evaluations": trace.evaluations,
            **{name: getattr(trace, name) for name, _ in _TRACE_TIMES},
            "relocations": np.asarray(trace.relocations).tolist(),
        },
        "cvt": None
        if result.cvt is None
        else {"iterations": result.cvt.iterations, "converged": result.cvt.converged, "seed": result.cvt.seed},
    }
    if result.coverage_by_part is not None:  # a structure's run; absent from every other file
        header["coverage_by_part"] = dict(result.coverage_by_part)
    arrays: dict[str, np.ndarray] = {
        "header": np.array(json.dumps(header)),
        "prior_points": result.prior_points,
        "start_positions": result.start_positions,
        "coverage": result.coverage,
        "distance_flown": result.distance_flown,  # for readers without uavcov; load_mission checks it
        **_surface_arrays("terrain", result.terrain),
        **_surface_arrays("approximation", result.approximation),
        **{f"trace_{name}": np.asarray(getattr(trace, name)) for name in _TRACE_ARRAYS},
    }
    if result.cvt is not None:
        arrays.update({f"cvt_{name}": np.asarray(getattr(result.cvt, name)) for name in _CVT_ARRAYS})
        if result.cvt.normals is not None:
            arrays["cvt_normals"] = np.asarray(result.cvt.normals)
    atomic_write_with(make_parent(path), lambda out: np.savez_compressed(out, **arrays))  # type: ignore[arg-type]
    return path


def _npz_arrays(handle: Any, path: Path) -> dict[str, Any]:
    """Every array of the ``.npz`` archive open in ``handle`` (``path`` names it in errors)."""
    try:
        data = np.load(handle, allow_pickle=False)
        if not isinstance(data, np.lib.npyio.NpzFile):  # a bare .npy array, not an archive
            raise ValueError("a single array, not an archive of a run's arrays")
        with data:
            return {name: data[name] for name in data.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error, KeyError, NotImplementedError) as exc:
        # EOFError: an empty file; zlib.error, BadZipFile: a corrupt member; ValueError: not numpy
        raise ResultsFormatError(f"{path} is not a readable uavcov run file: {type(exc).__name__}: {exc}") from exc
    except MemoryError:
        raise ResultsFormatError(f"{path} is not a uavcov run file: an array of it claims more memory than there is") from None


def load_mission(path: str | os.PathLike[str]) -> MissionResult:
    """Read a run written by :func:`save_mission`: the :class:`~uavcov.MissionResult` it held.

    Files written before the trace's timings took their ``_s`` names (``time_measure``,
    ``time_feasibility``, ``time_own``) load as well.

    Parameters
    ----------
    path : str or PathLike
        The ``.npz`` file (a results folder keeps its runs as ``runs/<run_id>.npz``).

    Raises
    ------
    ResultsFormatError
        The file does not exist, is not a run file, comes from another format version, or lacks
        a field (the message names it).
    """
    path = _as_path(path)
    if not path.is_file():
        raise ResultsFormatError(f"no run file at {path}")
    # one opened file for the checks and the read: a file swapped for a FIFO in between would block np.load
    with open_regular_file(path, "run file", ResultsFormatError) as handle:
        magic = handle.read(6)
        if magic and not magic.startswith((b"PK", b"\x93NUMPY")):  # numpy would speak of pickles
            raise ResultsFormatError(f"{path} is not a uavcov run file: not a .npz archive (a run is what save_mission writes)")
        handle.seek(0)
        arrays = _npz_arrays(handle, path)
    _require(arrays, ("header",), path)
    if arrays["header"].shape != () or arrays["header"].dtype.kind != "U":
        raise ResultsFormatError(f"{path} has a header that is not a JSON text")
    try:
        header = json.loads(str(arrays["header"]))
    except (json.JSONDecodeError, RecursionError) as exc:
        raise ResultsFormatError(f"{path} has an unreadable header: {exc}") from exc
    if not isinstance(header, dict):
        raise ResultsFormatError(f"{path} has a header that is not a JSON object")
    if header.get("format") not in (FORMAT, _FORMAT_1):
        raise ResultsFormatError(f"{path} has format {header.get('format')!r}; this uavcov reads {FORMAT!r}")
    _require(header, ("settings" if header["format"] == _FORMAT_1 else "spec", "scalars", "trace"), path)
    _require(arrays, ("prior_points", "start_positions", "coverage", *(f"trace_{n}" for n in _TRACE_ARRAYS)), path)
    _check_fields(header["scalars"], _SCALAR_TYPES, "scalars", path)
    _check_fields(header["trace"], _TRACE_TYPES, "trace", path)
    if header.get("cvt") is not None:
        _check_fields(header["cvt"], _CVT_TYPES, "cvt", path)
    try:
        if header["format"] == _FORMAT_1:
            spec, seed, prior_kind = _spec_of_format_1(header)
        else:
            spec, seed, prior_kind = MissionSettings.from_dict(header["spec"]), header["seed"], header["prior_kind"]
        if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
            raise ResultsFormatError(f"{path}: seed = {seed!r} is not an integer >= 0")
        if not isinstance(prior_kind, str):
            raise ResultsFormatError(f"{path}: prior_kind = {prior_kind!r} is not a string")
        if header.get("cvt") is not None:
            _require(arrays, tuple(f"cvt_{n}" for n in _CVT_ARRAYS), path)
        _check_arrays(arrays, spec, header.get("cvt"), path)
        _check_durations(header, path)
        t = header["trace"]
        trace = OptimizerTrace(
            kind=t["kind"],
            **{name: arrays[f"trace_{name}"] for name in _TRACE_ARRAYS},
            best_value=t["best_value"],
            best_iteration=t["best_iteration"],
            evaluations=t["evaluations"],
            settings=spec.cao,
            **{new: t[old] if old in t and new not in t else t[new] for new, old in _TRACE_TIMES},
            relocations=_relocations(t.get("relocations", []), arrays["coverage"].shape[0], spec.n_uavs, path),
        )
        _check_best(trace, path)
        cvt = None
        if header.get("cvt") is not None:
            # Records written before the CVT's facings have none.
            normals = arrays.get("cvt_normals")
            cvt = CVTResult(**{n: arrays[f"cvt_{n}"] for n in _CVT_ARRAYS}, **header["cvt"], normals=normals)
        s = header["scalars"]
        parts = header.get("coverage_by_part")
        if parts is not None and (
            not isinstance(parts, dict) or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in parts.values())
        ):
            raise ResultsFormatError(f"{path}: coverage_by_part is not a mapping of part names to shares")
        result = MissionResult(
            settings=spec,
            seed=seed,
            prior_kind=prior_kind,
            terrain=_surface("terrain", arrays, path),
            prior_points=arrays["prior_points"],
            approximation=_surface("approximation", arrays, path),
            start_positions=arrays["start_positions"],
            cvt=cvt,
            trace=trace,
            wall_time_s=s["wall_time_s"],
            start_time_s=s.get("start_time_s", math.nan),
            coverage_by_part=None if parts is None else {str(k): float(v) for k, v in parts.items()},
        )
        # the header's other scalars and the coverage array restate the trace (for readers
        # without uavcov): the result reads them from the trace, so they must agree with it
        if not np.array_equal(arrays["coverage"], result.coverage):
            raise ResultsFormatError(f"{path}: coverage disagrees with the trace's values stored beside it")
        if "distance_flown" in arrays and not np.array_equal(arrays["distance_flown"], result.distance_flown):
            raise ResultsFormatError(f"{path}: distance_flown disagrees with the trajectory stored beside it")
    except ResultsFormatError:
        raise
    except (KeyError, TypeError, AttributeError, ValueError, UavcovError) as exc:
        raise ResultsFormatError(f"{path} is missing or has a malformed field: {type(exc).__name__}: {exc}") from exc
    return result


def _relocations(raw: Any, n_configurations: int, n_uavs: int, path: Path) -> np.ndarray:
    """The trace's escape flights ``(R, 3)``, each ``(uav, first, last)`` within the run."""
    rows = np.asarray(raw, dtype=np.int64).reshape(-1, 3) if isinstance(raw, list) else None
    inside = rows is not None and bool(
        ((rows[:, 0] >= 0) & (rows[:, 0] < n_uavs) & (rows[:, 1] >= 0) & (rows[:, 1] < rows[:, 2]) & (rows[:, 2] < n_configurations)).all()
    )
    if rows is None or not inside:
        raise ResultsFormatError(f"{path}: trace.relocations must be a list of (uav, first, last) within the run, got {raw!r}")
    return read_only(rows)


def _spec_of_format_1(header: dict[str, Any]) -> tuple[MissionSettings, int | None, str]:
    """The MissionSettings a format-1 file's flat settings record describes.

    Format 1 recorded a start built outside the mission as "given"; its kind is taken as "cvt"
    when the file holds a CVT run, else "random" (the runs.csv row names the true start).
    """
    raw = dict(header["settings"])
    kind = raw["start"] if raw["start"] in START_KINDS else ("cvt" if header.get("cvt") is not None else "random")
    spec = MissionSettings.from_dict(
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
