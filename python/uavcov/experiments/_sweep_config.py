"""Sweep configuration files (TOML): parsing, validation, and the runs they describe.

A sweep starts from one of the experiments it is given (``bases``: the command line gives the
paper's, :data:`uavcov.paper.EXPERIMENTS`; ``base``, the first by default), changes any of
its settings, and runs every combination of the lists under ``[sweep]`` for every seed, team size
and start. See ``examples/sweep.toml``::

    name = "alpha-sweep"          # the experiment column of runs.csv, and part of every run id
    base = "table1"               # table1, pyramid, example, comparison or buildings
    seeds = "1000-1009"           # or a list of ints
    team_sizes = [5, 12]
    starts = ["cvt", "random"]    # cvt, random, corner, pairs
    d_max = 25.0
    prior = "random"              # random, pyramid, or map (buildings terrain only)
    n_prior = 30
    iterations = 200

    [terrain]                     # kind = "hills" or "buildings", then that kind's fields
    spacing = 1.0                 # (or kind = "file", path = "my_dem.tif": a surface of your own)

    [start]                       # any field of uavcov.placement.StartSettings (altitude, climb, ...)
    [constraints]                 # h_min, z_max, d_safe, check_moves (uavcov.limits.Constraints)
    [cao]                         # any field of uavcov.optim.CAOSettings
    [cvt]                         # any field of uavcov.placement.CVTSettings

    objective = "quality"         # coverage (the paper's) or quality (needs a camera)
    attitude = [0.0, -60.0]       # every camera's (yaw, pitch), degrees
    footprint_start = true        # lift each start until its camera's view matches its cell
    [sensor]                      # uavcov.Sensor's fields; d_max is the top-level d_max unless set
    good_gsd_m = 0.02
    [sensor.camera]               # uavcov.Camera's fields, or hfov_deg and vfov_deg
    hfov_deg = 84.0
    vfov_deg = 62.0
    [gimbal]                      # uavcov.Gimbal: free_yaw, pitch_range, alpha0_deg
    free_yaw = true

    [sweep]                       # every combination of these lists
    "cao.alpha0" = [1.0, 1.5]
    d_max = [20.0, 25.0]
    "sensor.camera.hfov_deg" = [60.0, 84.0]

A setting whose default is "none" (for example ``cao.n_regressors``) takes the string
``"none"`` for that default. Every error is a
:class:`~uavcov.errors.ConfigError` naming the file and the key; an unknown key comes with the closest
valid one.
"""

from __future__ import annotations

import dataclasses
import difflib
import itertools
import math
import os
import tomllib
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from .._validate import (
    MAX_ITERATIONS,
    MAX_RUNS,
    MAX_SEEDS,
    MAX_SWEEP_FILE_BYTES,
    MAX_UAVS,
    as_path,
    as_str,
    is_0d_array,
    is_int,
    read_regular_file,
)
from ..engine import Camera, Gimbal, Sensor, Terrain
from ..errors import ConfigError, InvalidInputError, InvalidTypeError
from ..limits import Constraints
from ..optim import CAOSettings
from ..placement import ALTITUDE_REFERENCES, CORNERS, PRESETS, START_KINDS, CVTSettings, StartSettings
from ..settings import OBJECTIVES
from ..terrain import BuildingsGenerator, HillsGenerator
from ._sweep import Experiment, RunSpec, experiment_specs
from ._terrain_file import terrain_file

STARTS: tuple[str, ...] = START_KINDS
"""Starts a sweep may compare ("pairs": half the team on each of two opposite sides)."""

PRIORS: tuple[str, ...] = ("random", "pyramid", "map")
"""Priors: random samples plus the corners, the pyramid (corners and centre), a buildings map."""

_TOP_SCALARS = ("d_max", "prior", "n_prior", "iterations", "objective", "attitude", "footprint_start")
_TOP_KEYS = (
    ("name", "base", "description", "seeds", "team_sizes", "starts")
    + _TOP_SCALARS
    + (
        "terrain",
        "start",
        "constraints",
        "cao",
        "cvt",
        "sensor",
        "gimbal",
        "sweep",
    )
)
_TERRAINS: Mapping[str, type] = {"hills": HillsGenerator, "buildings": BuildingsGenerator}
_MAX_ITERATIONS = MAX_ITERATIONS
_MAX_RUNS = MAX_RUNS


def _suggest(key: str, valid: Sequence[str]) -> str:
    close = difflib.get_close_matches(key, list(valid), n=1, cutoff=0.5)
    return f"; did you mean {close[0]!r}?" if close else f"; valid keys: {', '.join(sorted(valid))}"


def _field_names(cls: type) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(cls))


def _defaults(cls: type) -> dict[str, Any]:
    instance = cls()
    return {name: getattr(instance, name) for name in _field_names(cls)}


# The defaults of each table's keys (their types coerce the TOML values).
_GROUPS: Mapping[str, dict[str, Any]] = {
    "start": {k: v for k, v in _defaults(StartSettings).items() if k != "kind"},
    "constraints": {k: v for k, v in _defaults(Constraints).items() if k != "bounds"},
    "cao": _defaults(CAOSettings),
    "cvt": _defaults(CVTSettings),
}


class _Source:
    """Where a key came from, for error messages."""

    def __init__(self, name: str) -> None:
        self.name = name

    def error(self, key: str, message: str) -> ConfigError:
        return ConfigError(f"{self.name}: {key}: {message}")


def _coerce(value: Any, default: Any, key: str, source: _Source) -> Any:
    """``value`` converted to the type of the field's ``default``, and one of its choices if it has some."""
    coerced = _coerce_type(value, default, key, source)
    choices = _CHOICES.get(".".join(key.split(".")[-2:]))
    if choices is not None and coerced not in choices:
        raise source.error(key, f"must be one of {', '.join(choices)}, got {coerced!r}{_suggest(str(coerced), choices)}")
    return coerced


def _coerce_type(value: Any, default: Any, key: str, source: _Source) -> Any:  # noqa: PLR0911 (one return per TOML type)
    """``value`` converted to the type of the field's ``default`` (TOML gives ints, floats, lists)."""
    if isinstance(value, str) and value.lower() == "none" and default is None:
        return None
    if isinstance(value, dict):
        raise source.error(key, "expected a value, got a table")
    if isinstance(default, bool):
        if not isinstance(value, bool):
            raise source.error(key, f"expected true or false, got {value!r}")
        return value
    if isinstance(default, int) or (default is None and key.rsplit(".", maxsplit=1)[-1] in _INT_OR_NONE):
        if isinstance(value, bool) or not isinstance(value, int):
            raise source.error(key, f"expected an integer, got {value!r}")
        return value
    if isinstance(default, float):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise source.error(key, f"expected a number, got {value!r}")
        if not math.isfinite(value):
            raise source.error(key, f"expected a finite number, got {value!r}")
        return float(value)
    if isinstance(default, tuple):
        if not isinstance(value, list) or len(value) != len(default):
            raise source.error(key, f"expected a list of {len(default)} numbers, got {value!r}")
        return tuple(_coerce_type(v, d, key, source) for v, d in zip(value, default, strict=True))
    if isinstance(default, str):
        if not isinstance(value, str):
            raise source.error(key, f"expected a string, got {value!r}")
        return value
    return value


# The camera tables: a Sensor (its d_max the sweep's unless set), its Camera (by sensor and lens,
# or by fields of view), and a Gimbal. Their values are checked by the objects themselves.
_SENSOR_KEYS: Mapping[str, Any] = {"d_max": None, "d_min": 0.0, "max_gsd_m": None, "max_incidence_deg": None, "good_gsd_m": None}
_CAMERA_KEYS: Mapping[str, Any] = {
    "sensor_width_mm": 1.0,
    "sensor_height_mm": 1.0,
    "focal_length_mm": 1.0,
    "image_width_px": 1,
    "image_height_px": 1,
    "hfov_deg": 1.0,
    "vfov_deg": 1.0,
}
_GIMBAL_KEYS: Mapping[str, Any] = {"free_yaw": False, "pitch_range": (0.0, 0.0), "alpha0_deg": 1.0}
_CAMERA_AXES = tuple(f"sensor.{k}" for k in _SENSOR_KEYS) + tuple(f"sensor.camera.{k}" for k in _CAMERA_KEYS)
_CAMERA_AXES += tuple(f"gimbal.{k}" for k in _GIMBAL_KEYS)


def _camera_key_default(key: str) -> Any:
    group, _, name = key.rpartition(".")
    table = {"sensor": _SENSOR_KEYS, "sensor.camera": _CAMERA_KEYS, "gimbal": _GIMBAL_KEYS}[group]
    return table[name]


def _camera_tables(data: Mapping[str, Any], source: _Source) -> dict[str, Any]:
    """The ``[sensor]``, ``[sensor.camera]`` and ``[gimbal]`` tables as flat dotted keys."""
    flat: dict[str, Any] = {}
    for group, keys in (("sensor", _SENSOR_KEYS), ("gimbal", _GIMBAL_KEYS)):
        if group not in data:
            continue
        table = data[group]
        if not isinstance(table, dict):
            raise source.error(group, f"expected a table [{group}], got {table!r}")
        for key, value in table.items():
            if group == "sensor" and key == "camera":
                if not isinstance(value, dict):
                    raise source.error("sensor.camera", f"expected a table [sensor.camera], got {value!r}")
                for name, raw in value.items():
                    if name not in _CAMERA_KEYS:
                        raise source.error(f"sensor.camera.{name}", f"unknown key{_suggest(name, tuple(_CAMERA_KEYS))}")
                    flat[f"sensor.camera.{name}"] = _coerce_camera_value(raw, f"sensor.camera.{name}", source)
                flat.setdefault("sensor.camera", True)
            elif key not in keys:
                valid = (*keys, "camera") if group == "sensor" else tuple(keys)
                raise source.error(f"{group}.{key}", f"unknown key{_suggest(key, valid)}")
            else:
                flat[f"{group}.{key}"] = _coerce_camera_value(value, f"{group}.{key}", source)
        flat.setdefault(group, True)
    return flat


def _coerce_camera_value(value: Any, key: str, source: _Source) -> Any:
    default = _camera_key_default(key.removeprefix("sweep."))
    if isinstance(value, str) and value.lower() == "none":
        return None
    return _coerce_type(value, 0.0 if default is None else default, key, source)


def _camera_objects(flat: Mapping[str, Any], d_max: float, source: _Source) -> dict[str, Any]:
    """The mission's ``sensor`` and ``gimbal`` from the flat camera keys (none: no change)."""
    changes: dict[str, Any] = {}
    if "sensor" in flat:
        sensor_values = {k.split(".", 1)[1]: v for k, v in flat.items() if k.split(".", 1)[0] == "sensor" and k.count(".") == 1}
        sensor_values.pop("camera", None)
        if sensor_values.get("d_max") is None:
            sensor_values["d_max"] = d_max
        camera = None
        lens = {k.rsplit(".", 1)[1]: v for k, v in flat.items() if k.startswith("sensor.camera.")}
        if "sensor.camera" in flat or lens:
            try:
                if "hfov_deg" in lens or "vfov_deg" in lens:
                    if {"sensor_width_mm", "sensor_height_mm", "focal_length_mm"} & set(lens):
                        raise InvalidInputError("give the fields of view or the sensor and lens, not both")
                    camera = Camera.from_fov(lens.pop("hfov_deg", None), lens.pop("vfov_deg", None), **lens)
                else:
                    camera = Camera(**lens)
            except (InvalidInputError, InvalidTypeError, TypeError) as exc:
                raise source.error("sensor.camera", str(exc)) from None
        try:
            changes["sensor"] = Sensor(camera=camera, **sensor_values)
        except (InvalidInputError, InvalidTypeError, TypeError) as exc:
            raise source.error("sensor", str(exc)) from None
    if "gimbal" in flat:
        try:
            changes["gimbal"] = Gimbal(**{k.split(".", 1)[1]: v for k, v in flat.items() if k.startswith("gimbal.")})
        except (InvalidInputError, InvalidTypeError, TypeError) as exc:
            raise source.error("gimbal", str(exc)) from None
    return changes


# Settings that take one of a few names, so a typo gets the closest one.
_CHOICES: Mapping[str, tuple[str, ...]] = {
    "objective": OBJECTIVES,
    "cvt.preset": tuple(PRESETS),
    "start.altitude_reference": ALTITUDE_REFERENCES,
    "start.corner": CORNERS,
}

# Fields whose default is None but which take an integer otherwise.
_INT_OR_NONE = frozenset({"n_regressors", "robot_regressors", "check_batch", "samples_per_iteration"})


def _check_range(experiment: Experiment, source: _Source) -> None:
    """Ranges the settings objects do not check themselves."""
    if not (math.isfinite(experiment.d_max) and experiment.d_max > 0):
        raise source.error("d_max", f"must be > 0 metres, got {experiment.d_max}")
    if not 0 <= experiment.iterations <= _MAX_ITERATIONS:
        raise source.error("iterations", f"must be in [0, {_MAX_ITERATIONS}], got {experiment.iterations}")
    if experiment.prior not in PRIORS:
        raise source.error("prior", f"must be one of {', '.join(PRIORS)}, got {experiment.prior!r}{_suggest(experiment.prior, PRIORS)}")
    if experiment.prior == "map" and not isinstance(experiment.terrain, BuildingsGenerator):
        raise source.error("prior", "'map' needs a buildings terrain (terrain.kind = \"buildings\")")
    if isinstance(experiment.terrain, Terrain):  # a surface of the user's own: checked when read
        return
    terrain = experiment.generator
    if isinstance(terrain, HillsGenerator):
        # A whole number of cells is the generator's own check (HillsGenerator refuses others when made).
        cells = terrain.size / terrain.spacing
        if cells > 4000:
            raise source.error("terrain.spacing", f"{cells:.0f} x {cells:.0f} cells is beyond what a sweep can afford")
    else:
        for name in ("size", "spacing", "map_spacing"):
            if not getattr(terrain, name) > 0:
                raise source.error(f"terrain.{name}", f"must be > 0, got {getattr(terrain, name)}")
        if terrain.n_buildings < 0:
            raise source.error("terrain.n_buildings", f"must be >= 0, got {terrain.n_buildings}")
        for name in ("gap", "position_error", "size_error", "height_error"):
            if getattr(terrain, name) < 0:
                raise source.error(f"terrain.{name}", f"must be >= 0, got {getattr(terrain, name)}")
        for name in ("footprint", "heights"):
            low, high = getattr(terrain, name)
            if not 0 < low <= high:
                raise source.error(f"terrain.{name}", f"must be (low, high) with 0 < low <= high, got {(low, high)}")


@dataclass(frozen=True)
class SweepConfig:
    """A parsed, validated sweep.

    Attributes
    ----------
    name : str
        Label of every run (the ``experiment`` column).
    base : str
        The paper experiment the settings start from.
    variants : tuple of (Experiment, tuple of (key, value))
        One experiment per combination of the ``[sweep]`` lists, with the swept values.
    seeds, team_sizes, starts : tuple
    axes : tuple of str
        The swept keys, in file order.
    description : str
    """

    name: str
    base: str
    variants: tuple[tuple[Experiment, tuple[tuple[str, Any], ...]], ...]
    seeds: tuple[int, ...]
    team_sizes: tuple[int, ...]
    starts: tuple[str, ...]
    axes: tuple[str, ...] = ()
    description: str = ""

    def specs(self) -> list[RunSpec]:
        """Every run: variants x seeds x team sizes x starts."""
        specs: list[RunSpec] = []
        for experiment, extra in self.variants:
            specs.extend(
                experiment_specs(experiment, seeds=self.seeds, team_sizes=self.team_sizes, starts=self.starts, label=self.name, extra=extra)
            )
        return specs


def load_sweep_config(path: str | os.PathLike[str], *, bases: Mapping[str, Experiment]) -> SweepConfig:
    """Read and validate a TOML sweep file.

    ``bases`` are the experiments its ``base`` may name, the first by default
    (:data:`uavcov.paper.EXPERIMENTS` for the paper's).

    Raises
    ------
    ConfigError
        The file is missing or unreadable, is not valid TOML (with the line), has an unknown key
        (with the closest valid one), a value of the wrong type or out of range.
    """
    path = as_path(path, "path")
    text = read_regular_file(path, "sweep file", ConfigError, MAX_SWEEP_FILE_BYTES)
    try:
        data = tomllib.loads(text.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{path} is not UTF-8 text: {exc}") from exc
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path} is not valid TOML: {exc}") from exc
    except RecursionError:  # tomllib parses nested arrays recursively
        raise ConfigError(f"{path} nests arrays or tables too deeply to be a sweep file") from None
    return parse_sweep_config(data, bases=bases, source=str(path), default_name=path.stem)


def _group_changes(group: str, table: Any, defaults: Mapping[str, Any], source: _Source) -> dict[str, Any]:
    if not isinstance(table, dict):
        raise source.error(group, f"expected a table [{group}], got {table!r}")
    changes = {}
    for key, value in table.items():
        if key not in defaults:
            raise source.error(f"{group}.{key}", f"unknown key{_suggest(key, tuple(defaults))}")
        changes[f"{group}.{key}"] = _coerce(value, defaults[key], f"{group}.{key}", source)
    return changes


def _build(base: Experiment, changes: Mapping[str, Any], source: _Source) -> Experiment:
    try:
        experiment = base.with_changes(**changes)
    except (InvalidInputError, InvalidTypeError, TypeError, ValueError) as exc:
        # Name the key that fails on its own, when one does; else the ones changed together.
        culprits = []
        for key, value in changes.items():
            try:
                base.with_changes(**{key: value})
            except (InvalidInputError, InvalidTypeError, TypeError, ValueError):
                culprits.append(key)
        keys = ", ".join(culprits or list(changes)) or "the settings"
        raise ConfigError(f"{source.name}: {keys}: {exc}") from exc
    _check_range(experiment, source)
    return experiment


def _terrain_changes(base: Experiment, terrain_table: Any, source: str, src: _Source) -> tuple[Experiment, dict[str, Any], dict[str, Any]]:
    """The base with the table's terrain kind, that kind's defaults, and the table's changes.

    The terrain kind decides which fields [terrain] takes; switching kind starts from its defaults.
    """
    if not isinstance(terrain_table, dict):
        raise src.error("terrain", f"expected a table [terrain], got {terrain_table!r}")
    terrain_table = dict(terrain_table)
    kind = terrain_table.pop("kind", "buildings" if isinstance(base.terrain, BuildingsGenerator) else "hills")
    if kind == "file":  # a surface of the user's own, the same for every seed: no terrain setting to sweep
        return dataclasses.replace(base, terrain=terrain_file(terrain_table, source)), {}, {}
    if not isinstance(kind, str) or kind not in _TERRAINS:  # a list or table is no kind (and no key of _TERRAINS)
        kinds = (*_TERRAINS, "file")
        raise src.error("terrain.kind", f"must be 'hills', 'buildings' or 'file', got {kind!r}{_suggest(str(kind), kinds)}")
    terrain_cls = _TERRAINS[kind]
    if not isinstance(base.terrain, terrain_cls):
        base = dataclasses.replace(base, terrain=terrain_cls())
    terrain_defaults = _defaults(terrain_cls)
    return base, terrain_defaults, _group_changes("terrain", terrain_table, terrain_defaults, src)


def parse_sweep_config(
    data: Mapping[str, Any], *, bases: Mapping[str, Experiment], source: str = "<sweep>", default_name: str = "sweep"
) -> SweepConfig:
    """Validate a sweep given as a mapping (the parsed TOML) over the experiments ``bases``; see the module docstring."""
    src = _Source(as_str(source, "source"))
    if not isinstance(data, Mapping):
        raise ConfigError(f"{source}: a sweep is a table of settings, got {type(data).__name__}")
    for key in data:
        if key not in _TOP_KEYS:
            raise src.error(key, f"unknown key{_suggest(key, _TOP_KEYS)}")

    name = data.get("name", default_name)
    if not isinstance(name, str) or not name.strip():
        raise src.error("name", f"expected a non-empty string, got {name!r}")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise src.error("description", f"expected a string, got {description!r}")
    experiments = bases
    if not isinstance(experiments, Mapping) or not experiments or not all(isinstance(e, Experiment) for e in experiments.values()):
        raise InvalidTypeError(f"bases must be a non-empty mapping of names to Experiment, got {type(bases).__name__}")
    base_name = data.get("base", next(iter(experiments)))
    if base_name not in experiments:
        raise src.error("base", f"must be one of {', '.join(experiments)}, got {base_name!r}{_suggest(str(base_name), tuple(experiments))}")
    base = experiments[base_name]

    base, terrain_defaults, changes = _terrain_changes(base, data.get("terrain", {}), source, src)
    for group, defaults in _GROUPS.items():
        if group in data:
            changes.update(_group_changes(group, data[group], defaults, src))
    top_defaults = {
        "d_max": base.mission.d_max,
        "prior": base.prior,
        "n_prior": base.mission.n_prior,
        "iterations": base.mission.iterations,
        "objective": base.mission.objective,
        "attitude": base.mission.attitude,
        "footprint_start": base.mission.footprint_start,
    }
    for key in _TOP_SCALARS:
        if key in data:
            changes[key] = _coerce(data[key], top_defaults[key], key, src)
    cameras = _camera_tables(data, src)
    changes.update(_camera_objects(cameras, changes.get("d_max", base.mission.d_max), src))

    starts_default = tuple(s for s in base.starts if s in STARTS)
    starts = _string_list(data.get("starts", list(starts_default)), "starts", STARTS, src)
    team_sizes = _int_list(data.get("team_sizes", list(base.team_sizes)), "team_sizes", src)
    try:
        seeds = parse_seeds(data.get("seeds", base.seeds))
    except ConfigError as exc:
        raise src.error("seeds", str(exc)) from None
    changes["starts"] = starts
    changes["team_sizes"] = team_sizes
    common = _build(base, changes, src)

    sweep = data.get("sweep", {})
    if not isinstance(sweep, dict):
        raise src.error("sweep", f"expected a table [sweep], got {sweep!r}")
    valid_axes = list(_TOP_SCALARS) + [f"terrain.{k}" for k in terrain_defaults]
    valid_axes += [f"{g}.{k}" for g, defaults in _GROUPS.items() for k in defaults]
    valid_axes += list(_CAMERA_AXES)
    axes: list[str] = []
    values: list[list[Any]] = []
    for key, options in sweep.items():
        if key in ("seeds", "team_sizes", "starts"):
            raise src.error(f"sweep.{key}", f"{key} is already a grid axis: set it at the top level")
        if key not in valid_axes:
            raise src.error(f"sweep.{key}", f"unknown setting{_suggest(key, valid_axes)}")
        if not isinstance(options, list) or not options:
            raise src.error(f"sweep.{key}", f"expected a non-empty list of values, got {options!r}")
        group, _, field_name = key.rpartition(".")
        if key in _CAMERA_AXES:
            if key.partition(".")[0] not in cameras:
                raise src.error(f"sweep.{key}", f"sweeps a field of [{key.partition('.')[0]}]: give that table first")
            coerced = [_coerce_camera_value(v, f"sweep.{key}", src) for v in options]
        else:
            if group == "terrain":
                default = terrain_defaults[field_name]
            elif group:
                default = _GROUPS[group][field_name]
            else:
                default = top_defaults[key]
            coerced = [_coerce(v, default, f"sweep.{key}", src) for v in options]
        if len(set(map(repr, coerced))) != len(coerced):
            raise src.error(f"sweep.{key}", "a value is listed twice")
        axes.append(key)
        values.append(coerced)

    total = math.prod(len(v) for v in values) * len(seeds) * len(team_sizes) * len(starts)
    if total > _MAX_RUNS:  # before a single variant is built
        raise ConfigError(f"{source}: the sweep has {total:,} runs, more than uavcov's limit of {_MAX_RUNS:,}; split it")
    variants = []
    for combination in itertools.product(*values):
        extra = tuple(zip(axes, combination, strict=True))
        plain = {k: v for k, v in extra if k not in _CAMERA_AXES}
        swept_cameras = {k: v for k, v in extra if k in _CAMERA_AXES}
        if swept_cameras or ("d_max" in plain and "sensor" in cameras):  # rebuild the sensor: its range follows d_max
            plain.update(_camera_objects({**cameras, **swept_cameras}, plain.get("d_max", common.mission.d_max), src))
        variants.append((_build(common, plain, src) if plain else common, extra))
    return SweepConfig(
        name=name.strip(),
        base=base_name,
        variants=tuple(variants),
        seeds=seeds,
        team_sizes=team_sizes,
        starts=starts,
        axes=tuple(axes),
        description=description,
    )


def _string_list(value: Any, key: str, allowed: Sequence[str], source: _Source) -> tuple[str, ...]:
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not value:
        raise source.error(key, f"expected a non-empty list, got {value!r}")
    for item in value:
        if not isinstance(item, str) or item not in allowed:
            raise source.error(key, f"{item!r} is not one of {', '.join(allowed)}{_suggest(str(item), allowed)}")
    if len(set(value)) != len(value):
        raise source.error(key, "a value is listed twice")
    return tuple(value)


def _int_list(value: Any, key: str, source: _Source) -> tuple[int, ...]:
    if isinstance(value, int) and not isinstance(value, bool):
        value = [value]
    if not isinstance(value, list) or not value:
        raise source.error(key, f"expected a non-empty list of integers, got {value!r}")
    for item in value:
        if isinstance(item, bool) or not isinstance(item, int) or item < 1:
            raise source.error(key, f"expected integers >= 1, got {item!r}")
        if key == "team_sizes" and item > MAX_UAVS:
            raise source.error(key, f"a team of {item:,} UAVs is beyond uavcov's limit of {MAX_UAVS:,}")
    if len(set(value)) != len(value):
        raise source.error(key, "a value is listed twice")
    return tuple(value)


def parse_seeds(text: str | Iterable[int]) -> tuple[int, ...]:
    """Seeds from ``"0-39"``, ``"0,3,7"``, ``"1000-1009,2000"`` or an iterable of ints.

    Raises
    ------
    ConfigError
        Anything else, a negative seed, an empty or reversed range, a repeated seed, or more
        than a million seeds (:data:`uavcov._validate.MAX_SEEDS`; checked before any list is
        made).
    """
    if isinstance(text, str):
        seeds: list[int] = []
        for part in text.replace(" ", "").split(","):
            if not part:
                raise ConfigError(f"seeds {text!r}: an empty item")
            low, dash, high = part.partition("-")
            try:
                a = int(low)
                b = int(high) if dash else a
            except ValueError:
                raise ConfigError(f"seeds {text!r}: {part!r} is not a seed or a range like 0-39") from None
            if b < a:
                raise ConfigError(f"seeds {text!r}: the range {part} runs backwards")
            if len(seeds) + (b - a + 1) > MAX_SEEDS:
                raise ConfigError(f"seeds {text!r}: more than {MAX_SEEDS:,} seeds (uavcov's limit); split the sweep")
            seeds.extend(range(a, b + 1))
    elif isinstance(text, (bytes, Mapping)) or not isinstance(text, Iterable) or is_0d_array(text):
        raise ConfigError(f'seeds must be a string like "0-39" or a list of integers, got {text!r}')
    else:
        seeds = []
        for s in text:
            if not is_int(s):
                raise ConfigError(f"seeds must be integers, got {s!r}")
            if len(seeds) >= MAX_SEEDS:
                raise ConfigError(f"more than {MAX_SEEDS:,} seeds (uavcov's limit); split the sweep")
            seeds.append(int(s))
    if not seeds:
        raise ConfigError("no seeds given")
    if min(seeds) < 0:
        raise ConfigError(f"seeds must be >= 0, got {min(seeds)}")
    if len(set(seeds)) != len(seeds):
        raise ConfigError("a seed is listed twice")
    return tuple(seeds)
