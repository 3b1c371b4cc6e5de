"""From a geo-referenced DEM to a static team configuration: the paper's method on real ground.

:func:`plan` runs one mission (:func:`uavcov.mission.run_mission`) on a :class:`~uavcov.terrain.GeoDem`
as the true surface and returns a :class:`FlightPlan`: the best configuration CAO found, in the
local frame, in the DEM's CRS and in WGS84, with altitudes above the DEM's datum ("AMSL"), above
the ground under each UAV and above the take-off point, the coverage of the area, which cells
are seen and by how many UAVs, and the transit altitude each UAV flies to its position.

What is known beforehand (``PlanSettings.prior``):

* ``"full"``: the whole DEM. S', the surface the CVT start is computed on, is the DEM itself,
  cut to the area of interest (grid nodes outside it become nodata, so no CVT sample lies there).
* an integer ``n``: sparse points as in the paper: ``n`` grid nodes drawn at random inside the
  area, plus the vertices of the convex hull of the area's nodes (the paper's 4 corners, for a
  rectangle), and S' their Delaunay interpolant (:func:`uavcov.terrain.approximate_surface`); its
  CVT region is that hull, which for a non-convex area is larger than the area.

Coverage targets are the DEM's own: its valid grid nodes (pixel centres) inside the area (for a
mesh, its area-weighted points inside the area), each weighted by the ground area it stands for.
The UAVs stay inside the area's bounding box (the flight limits take a rectangle, not a polygon)
at ``h_min`` to ``h_max`` above the ground under them and ``d_safe`` apart.

Defaults: the CVT's own (:class:`~uavcov.CVTSettings`), and the optimiser's ``"plateau"``
preset scaled with the sensing range (:func:`uavcov.optim.cao_preset`: ``alpha_k = alpha0 (1 + A)
/ (k + 1 + A)``, ``alpha0 = 0.2 d_max``, ``A = 5``): a plan keeps the best configuration seen, so
it takes the larger step budget, which reaches higher coverage; the start flies at the middle of
``[h_min, h_max]`` above the ground and a UAV forced up by the ground is put
``min(1 m, (h_max - h_min) / 4)`` above ``h_min``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .._validate import (
    MAX_SAMPLES,
    as_count,
    as_float_array,
    as_generator,
    as_non_negative_float,
    as_positive_float,
    is_int,
    read_only,
)
from ..engine import Gimbal, Sensor, Targets, Terrain, Visibility, camera_axes
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError
from ..limits import Constraints
from ..mission import MissionResult, run_mission
from ..optim import CAOSettings, cao_preset
from ..placement import CVTSettings, StartSettings
from ..settings import MissionSettings
from ..terrain import GeoDem, approximate_surface, metres_per_degree, sample_node_prior
from ._area import AreaOfInterest

TAKEOFF_FRAMES = ("wgs84", "dem")
"""How a take-off point is given: (longitude, latitude) in WGS84, or (x, y) in the DEM's CRS."""

_FOOTPRINT_VERTICES = 48
MAX_RANGE_M = 100_000.0
"""The longest sensing range a plan takes, metres: far beyond a UAV's sensor, and short enough that
every footprint has a longitude and latitude (a range of 1e300 m has no outline on the Earth)."""


def _mission_item_value(value: float, name: str) -> float:
    """``value`` when a 32-bit float holds it: a vehicle gets a ``.plan``'s items as MAVLink float32
    parameters, where 1e308 s becomes an endless hold and a subnormal speed 0 m/s."""
    if value != 0.0 and not _FLOAT32_TINY <= value <= _FLOAT32_MAX:
        raise InvalidInputError(
            f"{name} = {value} is beyond what a mission item's 32-bit float holds ({_FLOAT32_TINY:.3g} to {_FLOAT32_MAX:.3g})"
        )
    return value + 0.0  # -0.0 is 0.0 in a file


_FLOAT32_TINY, _FLOAT32_MAX = float(np.finfo(np.float32).tiny), float(np.finfo(np.float32).max)


@dataclass(frozen=True)
class PlanSettings:
    """Everything a plan is made from, besides the DEM and the area. Frozen and picklable.

    The mission's own settings (team, sensor, camera, CVT, CAO, iterations) are checked once, by
    the :class:`~uavcov.MissionSettings` they make (:attr:`mission`); the fields here add what a
    plan on a real site needs: a flight band above the ground, a take-off point, what is known
    beforehand and the speeds of the ``.plan`` files.

    Attributes
    ----------
    n_uavs : int
        Team size (1 to 1000).
    d_max : float
        Sensing range, metres (> 0): every UAV's sensor (the paper's omnidirectional one, or
        ``sensor``'s camera up to this range).
    h_min, h_max : float
        Least and most height above the ground under each UAV, metres (``0 <= h_min < h_max``).
    d_safe : float
        Least distance between two UAVs, metres (>= 0).
    takeoff : (float, float), optional
        The take-off point (home): (longitude, latitude) or (x, y) in the DEM's CRS
        (``takeoff_frame``); it must lie over valid DEM ground. ``None``: the area's grid node
        closest to the area's centroid.
    takeoff_frame : {"wgs84", "dem"}
    prior : "full" or int
        What is known beforehand: the whole DEM, or that many sparse points (see the module).
    iterations : int
        CAO iterations (0 keeps the start).
    sensor : Sensor or sequence of Sensor, optional
        Every UAV's sensor (``Sensor(d_max, camera=...)``, pointed by ``attitude``), or one per
        UAV (a mixed team, each to its own range); ``None`` is the omnidirectional
        sensor of range ``d_max``. Incidence limits and view quality use the DEM's node normals
        (:meth:`uavcov.Terrain.vertex_normals`; a mesh DEM takes neither).
    attitude : (float, float)
        The camera's (yaw, pitch), degrees (see :mod:`uavcov.engine`); yaw is the heading in the
        DEM's local frame (its +y), where a free heading starts.
    gimbal : Gimbal, optional
        Camera angles CAO optimises beside the positions (heading; pitch within a range).
    footprint_start : bool
        Lift each CVT generator to the height whose camera view of S' matches its cell (and turn
        its free angles), :func:`uavcov.placement.fit_footprints`. Needs a camera.
    cao : CAOSettings, optional
        ``None``: the optimiser's ``"plateau"`` preset scaled to ``d_max``
        (:func:`uavcov.optim.cao_preset`).
    cvt : CVTSettings
        The constrained CVT's constants.
    hold_s : float
        Seconds each UAV holds its position (the loiter item of its ``.plan``).
    cruise_speed, hover_speed : float
        Metres per second, written into the ``.plan`` files.
    """

    n_uavs: int
    d_max: float
    h_min: float = 10.0
    h_max: float = 60.0
    d_safe: float = 5.0
    takeoff: tuple[float, float] | None = None
    takeoff_frame: str = "wgs84"
    prior: str | int = "full"
    iterations: int = 300
    sensor: Sensor | tuple[Sensor, ...] | None = None
    attitude: tuple[float, float] = (0.0, -90.0)
    gimbal: Gimbal | None = None
    footprint_start: bool = False
    cao: CAOSettings | None = None
    cvt: CVTSettings = field(default_factory=CVTSettings)
    hold_s: float = 60.0
    cruise_speed: float = 10.0
    hover_speed: float = 5.0

    def __post_init__(self) -> None:
        h_min, h_max = as_non_negative_float(self.h_min, "h_min"), as_positive_float(self.h_max, "h_max")
        if not h_min < h_max:
            raise InfeasibleError(f"h_min = {h_min} m must be below h_max = {h_max} m")
        constraints = Constraints(h_min=h_min, h_max=h_max, d_safe=self.d_safe, check_moves=None)
        object.__setattr__(self, "h_min", h_min)
        object.__setattr__(self, "h_max", h_max)
        object.__setattr__(self, "d_safe", constraints.d_safe)
        if self.takeoff is not None:
            pair = as_float_array(self.takeoff, "takeoff", ndim=1)
            if pair.shape != (2,):
                raise InvalidInputError(f"takeoff must be a pair (longitude, latitude) or (x, y), got {self.takeoff!r}")
            object.__setattr__(self, "takeoff", (float(pair[0]), float(pair[1])))
        if not isinstance(self.takeoff_frame, str) or self.takeoff_frame not in TAKEOFF_FRAMES:
            raise InvalidInputError(f"takeoff_frame must be one of {TAKEOFF_FRAMES}, got {self.takeoff_frame!r}")
        if is_int(self.prior):
            object.__setattr__(self, "prior", as_count(self.prior, "prior (sparse points)", MAX_SAMPLES))
        elif not isinstance(self.prior, str) or self.prior != "full":
            raise InvalidInputError(f"prior must be 'full' or a number of sparse points, got {self.prior!r}")
        object.__setattr__(self, "hold_s", _mission_item_value(as_non_negative_float(self.hold_s, "hold_s"), "hold_s"))
        object.__setattr__(self, "cruise_speed", _mission_item_value(as_positive_float(self.cruise_speed, "cruise_speed"), "cruise_speed"))
        object.__setattr__(self, "hover_speed", _mission_item_value(as_positive_float(self.hover_speed, "hover_speed"), "hover_speed"))
        if self.cao is not None and not isinstance(self.cao, CAOSettings):
            raise InvalidTypeError(f"cao must be a CAOSettings or None, got {type(self.cao).__name__}")
        mission = MissionSettings(
            n_uavs=self.n_uavs,
            d_max=self.d_max,
            start=StartSettings(
                kind="cvt",
                altitude=0.5 * (h_min + h_max),
                altitude_reference="ground",
                climb=min(1.0, 0.25 * (h_max - h_min)),
            ),
            constraints=constraints,
            cvt=self.cvt,
            cao=self.cao if self.cao is not None else cao_preset("plateau", self.d_max),
            iterations=self.iterations,
            sensor=self.sensor,
            attitude=self.attitude,
            gimbal=self.gimbal,
            footprint_start=self.footprint_start,
        )
        for name in ("n_uavs", "d_max", "iterations", "sensor", "attitude", "footprint_start"):
            object.__setattr__(self, name, getattr(mission, name))
        ranges = [self.d_max] + [s.d_max for s in mission.team_sensors() or []]
        if max(ranges) > MAX_RANGE_M:
            raise InvalidInputError(
                f"a sensing range of {max(ranges):g} m is beyond the {MAX_RANGE_M / 1000:g} km a plan on real ground "
                "considers (its footprints are drawn on the map)"
            )
        object.__setattr__(self, "_mission", mission)

    @property
    def mission(self) -> MissionSettings:
        """The mission these settings fly: a CVT start in the middle of the flight band, then CAO.

        Its constraints hold the flight band and the separation; :func:`plan` adds the area's
        bounds and the ceiling.
        """
        mission: MissionSettings = self.__dict__["_mission"]
        return mission

    def team_sensors(self) -> list[Sensor] | None:
        """Each UAV's sensor, or ``None`` for the omnidirectional sensor of range ``d_max``."""
        return self.mission.team_sensors()


@dataclass(frozen=True, eq=False)
class FlightPlan:
    """A static configuration on real ground, in every frame an operator needs. Frozen, picklable.

    Attributes
    ----------
    settings : PlanSettings
    dem : GeoDem
        The true surface and its CRS.
    area : AreaOfInterest or None
    mission : MissionResult
        The mission that found the configuration (start, trajectory, coverage per iteration).
    positions_local : (N, 3) float64
        Metres in the DEM's local frame.
    positions_crs : (N, 3) float64
        (x, y) in the DEM's CRS, and the altitude above the DEM's datum (= ``altitude_amsl``).
    positions_wgs84 : (N, 2) float64
        (longitude, latitude), degrees, WGS84.
    altitude_amsl, altitude_agl, altitude_home : (N,) float64
        Altitude above the DEM's vertical datum, above the ground under the UAV, and above the
        take-off point's ground, metres.
    ground_amsl : (N,) float64
        The DEM's height under each UAV.
    transit_amsl : (N,) float64
        The altitude (DEM datum) each UAV flies from the take-off point to its position: ``h_min``
        above the highest ground of the straight path, and no lower than its hold altitude.
    takeoff_local : (3,) float64
        The take-off point on the ground, local metres.
    takeoff_wgs84 : (3,) float64
        (longitude, latitude, ground height in the DEM's datum).
    targets : Targets
        The coverage targets (inside the area), local metres.
    target_pixels : (T, 2) int64 or None
        Raster (row, col) of each target (None for a mesh).
    seen : (T,) bool
        Targets seen by at least one UAV (the engine's seen mask).
    seen_count : (T,) int64
        How many UAVs see each target.
    quality : (T,) float64 or None
        The best view quality of each target over the team (:meth:`uavcov.Visibility.quality`:
        resolution against the sensor's ``good_gsd_m``, times the cosine of the incidence), 0
        where nobody sees it; ``None`` on a mesh DEM (no node normals).
    coverage : float
        Weighted share of the area's targets seen, in [0, 1].
    initial_coverage : float
        The same at the admissible CVT start.
    area_m2 : float
        Ground area of the targets (sum of their weights), square metres.
    prior_points : (n, 3) float64
        The known points S' was built from (empty for ``prior="full"``).
    attitudes : (N, 2) float64 or None
        Each camera's heading (degrees clockwise from true north, in ``[0, 360)``) and gimbal
        pitch (degrees, -90 nadir); ``None`` for the omnidirectional sensor.
    attitudes_local : (N, 2) float64 or None
        The same with the heading from the local frame's +y (the DEM's grid north), as the
        engine poses the cameras.
    seed : int or None
        The seed the plan was made from (``rng`` when an integer): the same seed, settings and
        DEM give the same plan.
    """

    settings: PlanSettings
    dem: GeoDem
    area: AreaOfInterest | None
    mission: MissionResult
    positions_local: np.ndarray
    positions_crs: np.ndarray
    positions_wgs84: np.ndarray
    altitude_amsl: np.ndarray
    altitude_agl: np.ndarray
    altitude_home: np.ndarray
    ground_amsl: np.ndarray
    transit_amsl: np.ndarray
    takeoff_local: np.ndarray
    takeoff_wgs84: np.ndarray
    targets: Targets
    target_pixels: np.ndarray | None
    seen: np.ndarray
    seen_count: np.ndarray
    coverage: float
    initial_coverage: float
    area_m2: float
    prior_points: np.ndarray
    attitudes: np.ndarray | None = None
    attitudes_local: np.ndarray | None = None
    quality: np.ndarray | None = None
    seed: int | None = None

    def __repr__(self) -> str:
        # A summary: the fields hold the DEM, the mission and per-target arrays (thousands of characters).
        return (
            f"FlightPlan({self.n_uavs} UAVs over {self.dem.crs_name}: coverage {self.coverage:.3f} of "
            f"{self.area_m2 / 1e6:.3f} km^2 (start {self.initial_coverage:.3f}), seed {self.seed})"
        )

    @property
    def n_uavs(self) -> int:
        """Team size."""
        return int(self.positions_local.shape[0])

    @property
    def home_amsl(self) -> float:
        """The take-off point's ground height, DEM datum (the ``.plan`` files' home altitude)."""
        return float(self.takeoff_wgs84[2])

    def footprints_local(self) -> list[np.ndarray]:
        """Per UAV, the ``(k, 2)`` local outline of what its sensor reaches on the horizontal plane
        through the ground under it: the range circle for the omnidirectional sensor, the image's
        four corner rays (each cut at the range) for a camera; an empty array when the ground is
        out of range. This is reach, not sight: the coverage raster has what is seen."""
        team = self.settings.team_sensors()
        outlines: list[np.ndarray] = []
        for k, (position, agl) in enumerate(zip(self.positions_local, self.altitude_agl, strict=True)):
            sensor = None if team is None else team[k]
            reach = self.settings.d_max if sensor is None else sensor.d_max
            if sensor is None or sensor.camera is None:
                if agl >= reach:
                    outlines.append(np.empty((0, 2)))
                    continue
                radius = math.sqrt(reach * reach - agl * agl)
                angle = np.linspace(0.0, 2.0 * math.pi, _FOOTPRINT_VERTICES, endpoint=False)
                outlines.append(np.column_stack([position[0] + radius * np.cos(angle), position[1] + radius * np.sin(angle)]))
                continue
            yaw, pitch = self.settings.attitude if self.attitudes_local is None else self.attitudes_local[k]
            forward, right, up = (axis[0] for axis in camera_axes([yaw], [pitch]))
            th, tv = sensor.camera.tan_half_fov
            corners = []
            for sx, sy in ((-1, 1), (1, 1), (1, -1), (-1, -1)):
                ray = forward + sx * th * right + sy * tv * up
                ray = ray / np.linalg.norm(ray)
                t = reach if ray[2] >= 0.0 else min(reach, agl / -ray[2])
                corners.append(position[:2] + t * ray[:2])
            outlines.append(np.array(corners))
        return outlines


def _check_inputs(dem: Any, settings: Any, area: Any) -> None:
    if not isinstance(dem, GeoDem):
        raise InvalidTypeError(f"dem must be a uavcov.terrain.GeoDem (read_dem, sample_dem, ...), got {type(dem).__name__}")
    if not isinstance(settings, PlanSettings):
        raise InvalidTypeError(f"settings must be a PlanSettings, got {type(settings).__name__}")
    if area is not None and not isinstance(area, AreaOfInterest):
        raise InvalidTypeError(f"area must be an AreaOfInterest or None, got {type(area).__name__}")


def _area_targets(dem: GeoDem, area: AreaOfInterest | None) -> tuple[Targets, np.ndarray]:
    """The targets inside the area, and the mask of the DEM's targets they are."""
    every = dem.terrain.default_targets()
    normals = dem.terrain.vertex_normals() if dem.terrain.grid is not None else None  # incidence and quality on a subset
    inside = np.ones(len(every), dtype=bool) if area is None else area.contains(every.points[:, :2], dem)
    if not inside.any():
        low, high = dem.to_wgs84(dem.terrain.bounds)[:, :2]
        raise InvalidInputError(
            f"the area of interest ({area.source if area else ''}) holds no valid DEM cell: it lies outside the DEM "
            f"(longitudes {low[0]:.6f}..{high[0]:.6f}, latitudes {low[1]:.6f}..{high[1]:.6f}) or over nodata"
        )
    return Targets(every.points[inside], every.weights[inside], None if normals is None else normals[inside]), inside


def _known_surface(dem: GeoDem, settings: PlanSettings, targets: Targets, rng: np.random.Generator) -> tuple[Terrain, np.ndarray]:
    """S' (the surface the CVT runs on) and the known points behind it."""
    terrain = dem.terrain
    points = targets.points
    if settings.prior == "full":
        grid = terrain.grid
        if grid is None:  # a mesh: its faces whose centroid is a target's neighbourhood inside the area
            return _mesh_inside(terrain, points), np.empty((0, 3))
        z = np.full(grid.shape, np.nan)
        i, j = _nodes(grid.origin, grid.spacing, points)
        z[i, j] = grid.z[i, j]
        complete = np.isfinite(z[:-1, :-1]) & np.isfinite(z[1:, :-1]) & np.isfinite(z[:-1, 1:]) & np.isfinite(z[1:, 1:])
        if not complete.any():
            raise InvalidInputError("the area of interest holds no whole DEM cell (four valid corners): it is too small for a plan")
        return Terrain.from_grid(z, grid.spacing, origin=grid.origin), np.empty((0, 3))
    try:
        known = sample_node_prior(points, int(settings.prior), rng=rng).points
    except InvalidInputError as exc:
        raise InvalidInputError(f"the area of interest: {exc}") from None
    return approximate_surface(known), known


def _mesh_inside(terrain: Terrain, inside_points: np.ndarray) -> Terrain:
    from scipy.spatial import cKDTree

    vertices, faces = terrain.vertices, terrain.faces
    centroids = vertices[faces].mean(axis=1)
    tree = cKDTree(inside_points[:, :2])
    distance, _ = tree.query(centroids[:, :2])
    # A face belongs to the area when a target inside the area is no farther than its own size.
    size = np.linalg.norm(vertices[faces[:, 0]] - vertices[faces[:, 1]], axis=1)
    keep = distance <= np.maximum(size, 1.0)
    if not keep.any():
        raise InvalidInputError("no face of the mesh lies inside the area of interest")
    used, renumbered = np.unique(faces[keep], return_inverse=True)
    return Terrain(vertices[used], renumbered.reshape(-1, 3))


def _nodes(origin: tuple[float, float], spacing: tuple[float, float], points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Grid node ``(i, j)`` (row 0 south) of points standing on grid nodes."""
    j = np.rint((points[:, 0] - origin[0]) / spacing[0]).astype(np.int64)
    i = np.rint((points[:, 1] - origin[1]) / spacing[1]).astype(np.int64)
    return i, j


def _takeoff(dem: GeoDem, settings: PlanSettings, targets: Targets) -> np.ndarray:
    """The take-off point on the ground, local metres ``(3,)``."""
    if settings.takeoff is None:
        centroid = np.average(targets.points[:, :2], axis=0, weights=targets.weights)
        nearest = int(np.argmin(np.sum((targets.points[:, :2] - centroid) ** 2, axis=1)))
        return np.array(targets.points[nearest], dtype=np.float64)
    wgs84 = settings.takeoff_frame == "wgs84"
    xy = dem.from_wgs84([settings.takeoff])[0, :2] if wgs84 else dem.crs_to_local_xy([settings.takeoff])[0]
    ground = float(dem.terrain.ground_height(xy.reshape(1, 2))[0])
    if not math.isfinite(ground):
        raise InvalidInputError(
            f"the take-off point {settings.takeoff} ({settings.takeoff_frame}) has no DEM ground under it (outside the DEM or nodata)"
        )
    return np.array([xy[0], xy[1], ground])


def _transit(dem: GeoDem, takeoff: np.ndarray, positions: np.ndarray, h_min: float) -> np.ndarray:
    """Local z of each UAV's transit: ``h_min`` over the highest ground of its straight path."""
    terrain = dem.terrain
    grid = terrain.grid
    step = 0.5 * min(grid.spacing) if grid is not None else 1.0
    heights = np.empty(positions.shape[0])
    for k, target in enumerate(positions):
        length = float(np.hypot(*(target[:2] - takeoff[:2])))
        count = min(max(2, math.ceil(length / step) + 1), 100_000)
        t = np.linspace(0.0, 1.0, count)[:, None]
        ground = terrain.ground_height(takeoff[:2] + t * (target[:2] - takeoff[:2]))
        highest = float(np.nanmax(ground)) if np.isfinite(ground).any() else takeoff[2]
        heights[k] = max(highest + h_min, target[2], takeoff[2] + h_min)
    return heights


def plan(
    dem: GeoDem,
    settings: PlanSettings,
    *,
    area: AreaOfInterest | None = None,
    rng: Any = None,
    n_threads: int | None = None,
) -> FlightPlan:
    """The paper's method on a real DEM: CVT start on S', then CAO with the DEM as the true surface.

    Parameters
    ----------
    dem : GeoDem
        The true surface with its CRS (:func:`uavcov.terrain.read_dem`, :func:`uavcov.terrain.sample_dem`).
    settings : PlanSettings
    area : AreaOfInterest, optional
        Restricts the targets, S' and the flight box; the whole DEM by default.
    rng : None, int or numpy.random.Generator
        Split into the sparse prior's stream and the mission's; the same seed gives the same plan.
    n_threads : int, optional
        Rust threads (results do not depend on it).

    Returns
    -------
    FlightPlan

    Raises
    ------
    InvalidInputError
        The area is outside the DEM or too small, the take-off point has no ground, ...
    InfeasibleError
        The team cannot keep its separation inside the area between ``h_min`` and ``h_max``.
    """
    _check_inputs(dem, settings, area)
    terrain = dem.terrain
    targets, _ = _area_targets(dem, area)
    prior_rng, mission_rng = as_generator(rng).spawn(2)
    xy = targets.points[:, :2]
    (xmin, ymin), (xmax, ymax) = xy.min(axis=0), xy.max(axis=0)
    if not (xmin < xmax and ymin < ymax):
        raise InvalidInputError("the area of interest holds DEM nodes on one line only: it is too small for a plan")
    takeoff = _takeoff(dem, settings, targets)
    approximation, known = _known_surface(dem, settings, targets, prior_rng)

    top = float(terrain.bounds[1, 2])
    constraints = replace(
        settings.mission.constraints,
        bounds=(float(xmin), float(ymin), float(xmax), float(ymax)),
        z_max=top + settings.h_max + 1.0,  # h_max above ground is the ceiling that binds
    )
    spec = replace(settings.mission, constraints=constraints)
    mission = run_mission(terrain, spec, known=approximation, targets=targets, rng=mission_rng, n_threads=n_threads)
    positions = np.array(mission.best_positions, dtype=np.float64)

    vis = Visibility(terrain, settings.d_max, targets, n_threads=n_threads)
    sensors = settings.team_sensors()
    local_attitudes = mission.best_attitudes
    poses = positions if local_attitudes is None else np.column_stack([positions, local_attitudes])
    seen = np.asarray(vis.seen(poses, sensors=sensors), dtype=bool)
    count = np.zeros(len(targets), dtype=np.int64)
    for k in range(settings.n_uavs):
        count += vis.seen(poses[k : k + 1], sensors=None if sensors is None else sensors[k : k + 1])
    coverage = vis.coverage(poses, sensors=sensors)

    ground = terrain.ground_height(positions[:, :2])
    crs_positions = dem.to_crs(positions)
    ground_amsl = dem.to_crs(np.column_stack([positions[:, :2], ground]))[:, 2]
    takeoff_wgs84 = dem.to_wgs84(takeoff.reshape(1, 3))[0]
    transit_local = _transit(dem, takeoff, positions, settings.h_min)
    transit_amsl = dem.to_crs(np.column_stack([positions[:, :2], transit_local]))[:, 2]

    pixels = None
    grid, raster = terrain.grid, dem.raster
    if grid is not None and raster is not None:
        i, j = _nodes(grid.origin, grid.spacing, targets.points)
        rows, cols = raster.pixel_of_node(i, j)
        pixels = np.column_stack([rows, cols]).astype(np.int64)

    attitudes = None
    if local_attitudes is not None:
        attitudes = np.column_stack([_true_headings(dem, positions, local_attitudes[:, 0]), local_attitudes[:, 1]])

    def frozen(array: Any) -> np.ndarray:
        return read_only(np.array(array, dtype=np.float64))

    return FlightPlan(
        settings=settings,
        dem=dem,
        area=area,
        mission=mission,
        positions_local=frozen(positions),
        positions_crs=frozen(crs_positions),
        positions_wgs84=frozen(dem.to_wgs84(positions)[:, :2]),
        altitude_amsl=frozen(crs_positions[:, 2]),
        altitude_agl=frozen(positions[:, 2] - ground),
        altitude_home=frozen(crs_positions[:, 2] - takeoff_wgs84[2]),
        ground_amsl=frozen(ground_amsl),
        transit_amsl=frozen(transit_amsl),
        takeoff_local=frozen(takeoff),
        takeoff_wgs84=frozen(takeoff_wgs84),
        targets=targets,
        target_pixels=pixels,
        seen=seen,
        seen_count=count,
        coverage=float(coverage),
        initial_coverage=float(mission.initial_coverage),
        area_m2=float(targets.total_weight),
        prior_points=frozen(known.reshape(-1, 3)),
        attitudes=None if attitudes is None else frozen(attitudes),
        attitudes_local=None if local_attitudes is None else frozen(local_attitudes),
        quality=None if targets.normals is None else frozen(vis.quality(poses, sensors=sensors)),
        seed=int(rng) if is_int(rng) else None,
    )


def _true_headings(dem: GeoDem, positions: np.ndarray, local_yaw: np.ndarray) -> np.ndarray:
    """Compass headings from true north (degrees in [0, 360)) of headings ``local_yaw`` measured
    from the local frame's +y: a projected CRS's grid north is not true north (meridian
    convergence), so each heading is carried to WGS84 by a point 1 m ahead of its UAV."""
    yaw = np.radians(np.fmod(local_yaw, 360.0))  # reduced exactly first, as the engine does
    ahead = positions.copy()
    ahead[:, 0] += np.sin(yaw)
    ahead[:, 1] += np.cos(yaw)
    here, there = dem.to_wgs84(positions)[:, :2], dem.to_wgs84(ahead)[:, :2]
    out = np.empty(positions.shape[0])
    for k in range(positions.shape[0]):
        east_per_degree, north_per_degree = metres_per_degree(float(here[k, 1]))
        d_lon = float(there[k, 0] - here[k, 0])
        if abs(d_lon) > 180.0:  # the 1 m step crossed the antimeridian, where longitudes wrap
            d_lon -= math.copysign(360.0, d_lon)
        east = d_lon * east_per_degree
        north = (there[k, 1] - here[k, 1]) * north_per_degree
        out[k] = math.degrees(math.atan2(east, north)) % 360.0
    return out
