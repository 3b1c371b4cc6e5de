"""What one mission runs: :class:`MissionSettings`, and its form as a plain dict.

A :class:`MissionSettings` says everything one mission runs (team, sensor, what is known
beforehand, the start, the flight constraints, the CVT and the optimiser), frozen and
picklable; :func:`uavcov.mission.run_mission` runs it. :meth:`MissionSettings.as_dict` and
:meth:`MissionSettings.from_dict` carry it through JSON (run files, results folders, sweep
configurations), and :func:`nested_replace` changes its fields by dotted names
(``"start.kind"``), as sweeps vary them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields, is_dataclass, replace
from typing import TYPE_CHECKING, Any, TypeVar

from ._validate import (
    MAX_ITERATIONS,
    MAX_PAIR_CHECKS,
    MAX_SAMPLES,
    MAX_TRAJECTORY,
    MAX_UAVS,
    as_bool,
    as_count,
    as_float_array,
    as_positive_float,
)
from .engine import Camera, Gimbal, Sensor, camera_axes
from .errors import InvalidInputError, InvalidTypeError
from .limits import Constraints
from .optim import MARGINAL_OPTIMIZERS, OPTIMIZERS, CAOSettings, EscapeSettings
from .placement import CVTSettings, StartSettings

__all__ = ["MissionSettings", "PRIOR_KINDS", "OBJECTIVES", "nested_replace"]

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

_Settings = TypeVar("_Settings", bound="DataclassInstance")

OBJECTIVES = ("coverage", "quality")
"""What a mission maximises: the seen share, or the quality-weighted coverage."""

PRIOR_KINDS = ("random", "pyramid")
"""What :class:`MissionSettings` can sample as the prior (anything else is passed as ``known``)."""


def _mission_constraints() -> Constraints:
    # Bounds are the true surface's; moves are checked on meshes (buildings), not on grids.
    return Constraints(check_moves=None)


@dataclass(frozen=True)
class MissionSettings:
    """Every setting of one mission. Frozen and picklable; compare and hash it as a value.

    Attributes
    ----------
    n_uavs : int
        Team size ``N`` (> 0).
    d_max : float
        Sensing range, metres (> 0).
    prior : {"random", "pyramid"}, default "random"
        What is known beforehand when :func:`run_mission` is not given it (``known=``):
        ``n_prior`` random points plus the 4 corners, or the 4 corners and the centre.
    n_prior : int, default 30
        Random known points for ``prior="random"``.
    start : StartSettings
        The start (kind, altitude rule, corner lattice); a CVT start by default.
    constraints : Constraints
        The flight constraints of eq. 2 (``h_min``, ``z_max``, ``d_safe``, ``check_moves``);
        ``bounds=None`` stands for the true surface's x-y bounds and ``check_moves=None`` for
        "on for general meshes, off for elevation grids".
    cvt : CVTSettings
        The constrained CVT's constants (``start.kind == "cvt"``).
    cao : CAOSettings
        The optimiser's constants.
    optimizer : {"cao", "per_robot", "escape"}, default "cao"
        Centralised CAO, one estimator per UAV, or centralised CAO that relocates its least
        useful UAV when it stalls (its settings: ``escape``, :class:`~uavcov.EscapeSettings`).
    iterations : int, default 500
        Optimiser iterations (measurements minus one); 0 measures the start only.
    sensor : Sensor or sequence of Sensor, optional
        Every UAV's sensor (:mod:`uavcov.engine`), or one per UAV (``n_uavs`` of them: a team
        that mixes ranges and cameras); ``None`` is the paper's omnidirectional one of range
        ``d_max``.
    attitude : (float, float), default (0.0, -90.0)
        ``(yaw, pitch)`` in degrees of every UAV's camera (heading clockwise from north, gimbal
        pitch from -90, nadir, to 0, level; above 0 only with a ``gimbal`` whose ``pitch_range``
        reaches it), fixed during the mission; read when ``sensor`` has a camera.
    objective : {"coverage", "quality"}, default "coverage"
        What the optimiser maximises: the seen share, or the quality-weighted coverage
        (:meth:`uavcov.Visibility.quality_coverage`, centralised CAO only).
    gimbal : Gimbal, optional
        Camera angles the optimiser moves beside the positions (heading, pitch within a range;
        centralised CAO only); ``attitude`` is then where they start. ``None``: fixed angles.
    footprint_start : bool, default False
        Lift each start position (any start kind) to the height above S' at which its camera's
        view of S' best matches its Voronoi cell, and turn the free angles likewise
        (:func:`uavcov.placement.fit_footprints`, between the flight band's ``h_min`` and
        ``h_max``, or the camera's range without a ceiling; positions given to
        :func:`run_mission` are flown as given). Needs a camera.
    escape : EscapeSettings
        When the ``"escape"`` optimiser relocates a UAV and how it flies there (read only by it).

    Examples
    --------
    >>> spec = MissionSettings(n_uavs=4, d_max=20.0, iterations=50)
    >>> spec.with_changes(**{"start.kind": "random", "constraints.h_min": 1.0}).start.kind
    'random'
    """

    n_uavs: int
    d_max: float
    prior: str = "random"
    n_prior: int = 30
    start: StartSettings = field(default_factory=StartSettings)
    constraints: Constraints = field(default_factory=_mission_constraints)
    cvt: CVTSettings = field(default_factory=CVTSettings)
    cao: CAOSettings = field(default_factory=CAOSettings)
    optimizer: str = "cao"
    iterations: int = 500
    sensor: Sensor | tuple[Sensor, ...] | None = None
    attitude: tuple[float, float] = (0.0, -90.0)
    objective: str = "coverage"
    gimbal: Gimbal | None = None
    footprint_start: bool = False
    escape: EscapeSettings = field(default_factory=EscapeSettings)

    def __post_init__(self) -> None:
        object.__setattr__(self, "n_uavs", as_count(self.n_uavs, "n_uavs", MAX_UAVS))
        object.__setattr__(self, "d_max", as_positive_float(self.d_max, "d_max"))
        object.__setattr__(self, "n_prior", as_count(self.n_prior, "n_prior", MAX_SAMPLES, minimum=0))
        object.__setattr__(self, "iterations", as_count(self.iterations, "iterations", MAX_ITERATIONS, minimum=0))
        if not isinstance(self.prior, str) or self.prior not in PRIOR_KINDS:
            raise InvalidInputError(f"prior must be one of {PRIOR_KINDS} (pass anything else as known=), got {self.prior!r}")
        if not isinstance(self.optimizer, str) or self.optimizer not in OPTIMIZERS:
            raise InvalidInputError(f"optimizer must be one of {tuple(OPTIMIZERS)}, got {self.optimizer!r}")
        nested = (StartSettings, Constraints, CVTSettings, CAOSettings, EscapeSettings)
        for name, kind in zip(("start", "constraints", "cvt", "cao", "escape"), nested, strict=True):
            value = getattr(self, name)
            if not isinstance(value, kind):
                raise InvalidTypeError(f"{name} must be a {kind.__name__}, got {type(value).__name__}")
        if isinstance(self.sensor, (list, tuple)):
            if not all(isinstance(s, Sensor) for s in self.sensor):
                raise InvalidTypeError("every sensor of a team's sensor list must be a uavcov.Sensor")
            if len(self.sensor) != self.n_uavs:
                raise InvalidInputError(f"{len(self.sensor)} sensors for {self.n_uavs} UAVs: give one per UAV, or one for all")
            object.__setattr__(self, "sensor", tuple(self.sensor))
        elif self.sensor is not None and not isinstance(self.sensor, Sensor):
            raise InvalidTypeError(f"sensor must be a uavcov.Sensor, one per UAV, or None, got {type(self.sensor).__name__}")
        attitude = as_float_array(self.attitude, "attitude", allow_nan=True) if not isinstance(self.attitude, (str, bytes)) else None
        if attitude is None or attitude.shape != (2,):
            raise InvalidInputError(f"attitude must be (yaw, pitch) in degrees, got {self.attitude!r}")
        camera_axes([attitude[0]], [attitude[1]])  # finite, pitch in [-90, 90]
        object.__setattr__(self, "attitude", (float(attitude[0]), float(attitude[1])))
        if not isinstance(self.objective, str) or self.objective not in OBJECTIVES:
            raise InvalidInputError(f"objective must be one of {OBJECTIVES}, got {self.objective!r}")
        if self.objective == "quality" and self.optimizer in MARGINAL_OPTIMIZERS:
            raise InvalidInputError("the quality objective needs the centralised optimizer 'cao' (per-robot marginals are coverage's)")
        self._check_camera_options()
        self._check_size()

    def team_sensors(self) -> list[Sensor] | None:
        """Each UAV's sensor (``n_uavs`` of them), or ``None`` for the paper's sensor."""
        if self.sensor is None:
            return None
        return list(self.sensor) if isinstance(self.sensor, tuple) else [self.sensor] * self.n_uavs

    @property
    def has_camera(self) -> bool:
        """Whether some UAV sees through a camera (poses then carry yaw and pitch)."""
        sensors = self.team_sensors()
        return sensors is not None and any(s.camera is not None for s in sensors)

    def _check_camera_options(self) -> None:
        has_camera = self.has_camera
        if self.gimbal is not None:
            if not isinstance(self.gimbal, Gimbal):
                raise InvalidTypeError(f"gimbal must be a uavcov.Gimbal or None, got {type(self.gimbal).__name__}")
            if self.gimbal.free_angles and not has_camera:
                raise InvalidInputError("a gimbal's free angles need a sensor with a camera (sensor=Sensor(..., camera=...))")
            if self.gimbal.free_angles and self.optimizer != "cao":
                raise InvalidInputError("optimising camera angles needs the centralised optimizer 'cao'")
            bounds = self.gimbal.pitch_range
            if bounds is not None and not bounds[0] <= self.attitude[1] <= bounds[1]:
                raise InvalidInputError(f"attitude's pitch {self.attitude[1]} lies outside the gimbal's pitch_range {bounds}")
        bounds = None if self.gimbal is None else self.gimbal.pitch_range
        if self.attitude[1] > 0.0 and bounds is None:
            # Above the horizon only a gimbal that says it can: a mapping gimbal cannot point up.
            raise InvalidInputError(
                f"attitude's pitch {self.attitude[1]} looks above the horizon: a camera can point up only on a gimbal "
                "whose pitch_range reaches it (gimbal=Gimbal(pitch_range=...) or Gimbal.preset('upward'))"
            )
        object.__setattr__(self, "footprint_start", as_bool(self.footprint_start, "footprint_start"))
        if self.footprint_start and not has_camera:
            raise InvalidInputError("footprint_start needs a sensor with a camera")

    @property
    def free_angles(self) -> tuple[str, ...]:
        """The camera angles the optimiser moves (``"yaw"``, ``"pitch"``), in their state order."""
        return () if self.gimbal is None else self.gimbal.free_angles

    def _check_size(self) -> None:
        """Refuse a mission whose records or optimiser steps would not fit in memory (the size limits
        of :mod:`uavcov._validate`), before anything is allocated."""
        positions = (self.iterations + 1) * self.n_uavs
        if positions > MAX_TRAJECTORY:
            raise InvalidInputError(
                f"{self.iterations:,} iterations x {self.n_uavs:,} UAVs would record {positions:,} positions, "
                f"more than uavcov's limit of {MAX_TRAJECTORY:,}; use fewer iterations or UAVs"
            )
        d_safe = self.constraints.d_safe
        if d_safe is not None and d_safe > 0.0 and self.n_uavs > 1:
            checks = self.cao.n_candidates * self.n_uavs * (self.n_uavs - 1) // 2
            if checks > MAX_PAIR_CHECKS:
                raise InvalidInputError(
                    f"{self.n_uavs:,} UAVs kept d_safe apart with {self.cao.n_candidates:,} candidates a step need "
                    f"{checks:,} distance checks a step, more than uavcov's limit of {MAX_PAIR_CHECKS:,}; "
                    "use fewer UAVs or cao.n_candidates (or d_safe = 0)"
                )

    def with_changes(self, **changes: Any) -> MissionSettings:
        """A copy with some fields replaced; nested ones as ``"start.kind"`` or ``"cao.alpha0"``.

        Raises
        ------
        InvalidInputError
            A name that is not a field (the message lists the fields).
        """
        return nested_replace(self, changes)

    def as_dict(self) -> dict[str, Any]:
        """Plain ``dict`` (nested settings included), ready for JSON."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> MissionSettings:
        """The inverse of :meth:`as_dict` (lists where tuples were are accepted).

        Raises
        ------
        InvalidInputError
            An unknown or missing field.
        InvalidTypeError
            Not a mapping.
        """
        if not isinstance(data, dict):
            raise InvalidTypeError(f"a mission spec must be a mapping, got {type(data).__name__}")
        spec: MissionSettings = _dataclass_from_dict(cls, data, "mission")
        return spec


def _sensor_from_dict(raw: Any, where: str) -> Sensor | tuple[Sensor, ...] | None:
    if raw is None:
        return None
    if isinstance(raw, list):  # one per UAV
        team = tuple(_sensor_from_dict(one, f"{where}[{k}]") for k, one in enumerate(raw))
        if any(s is None for s in team):
            raise InvalidTypeError(f"{where}: a team's sensor list holds a null")
        return team  # type: ignore[return-value]
    if not isinstance(raw, dict):
        raise InvalidTypeError(f"{where} must be a mapping or null, got {type(raw).__name__}")
    values = dict(raw)
    camera = values.get("camera")
    if camera is not None:
        if not isinstance(camera, dict):
            raise InvalidTypeError(f"{where}.camera must be a mapping or null, got {type(camera).__name__}")
        values["camera"] = Camera(**camera)
    try:
        return Sensor(**values)
    except TypeError as exc:
        raise InvalidInputError(f"{where}: {exc}") from None


def _dataclass_from_dict(cls: type, data: dict[str, Any], where: str) -> Any:
    nested = {"start": StartSettings, "constraints": Constraints, "cvt": CVTSettings, "cao": CAOSettings, "escape": EscapeSettings}
    names = {f.name for f in fields(cls)}
    unknown = sorted(set(data) - names)
    if unknown:
        raise InvalidInputError(f"{where}: unknown field(s) {unknown}; the fields are {sorted(names)}")
    values: dict[str, Any] = {}
    for key, raw in data.items():
        if cls is MissionSettings and key == "sensor":
            values[key] = _sensor_from_dict(raw, f"{where}.sensor")
        elif cls is MissionSettings and key == "gimbal" and raw is not None:
            if not isinstance(raw, dict):
                raise InvalidTypeError(f"{where}.gimbal must be a mapping or null, got {type(raw).__name__}")
            values[key] = _dataclass_from_dict(Gimbal, raw, f"{where}.gimbal")
        elif cls is MissionSettings and key in nested:
            if not isinstance(raw, dict):
                raise InvalidTypeError(f"{where}.{key} must be a mapping, got {type(raw).__name__}")
            values[key] = _dataclass_from_dict(nested[key], raw, f"{where}.{key}")
        else:
            values[key] = tuple(raw) if isinstance(raw, list) else raw
    try:
        return cls(**values)
    except TypeError as exc:  # a required field is missing
        raise InvalidInputError(f"{where}: {exc}") from None


def nested_replace(obj: _Settings, changes: dict[str, Any]) -> _Settings:
    """``dataclasses.replace`` that also reaches into nested dataclasses by dotted names.

    ``nested_replace(spec, {"start.kind": "random", "iterations": 10})``. ``"__"`` may stand
    for the dot (keyword-argument friendly).

    Raises
    ------
    InvalidInputError
        A name that is not a field of the object it names.
    InvalidTypeError
        ``obj`` is no dataclass, ``changes`` no mapping, or a name no string.
    """
    if not is_dataclass(obj) or isinstance(obj, type):
        raise InvalidTypeError(f"nested_replace changes a settings dataclass, got {type(obj).__name__}")
    if not isinstance(changes, Mapping):
        raise InvalidTypeError(f"changes must be a mapping of dotted field names to values, got {type(changes).__name__}")
    top: dict[str, Any] = {}
    inner: dict[str, dict[str, Any]] = {}
    names = {f.name for f in fields(obj)}
    for key, value in changes.items():
        if not isinstance(key, str):
            raise InvalidTypeError(f"a field name must be a string such as 'start.kind', got {key!r}")
        head, _, rest = key.replace("__", ".").partition(".")
        if head not in names:
            raise InvalidInputError(f"{type(obj).__name__} has no field {head!r}; its fields are {sorted(names)}")
        if rest:
            inner.setdefault(head, {})[rest] = value
        else:
            top[head] = value
    for head, sub in inner.items():
        current = top.get(head, getattr(obj, head))
        if not is_dataclass(current) or isinstance(current, type):
            raise InvalidInputError(f"{type(obj).__name__}.{head} has no fields to set ({sorted(sub)})")
        top[head] = nested_replace(current, sub)
    return replace(obj, **top)
