"""The initial UAV positions the paper compares: CVT, random, corner and pairs, behind one door.

:func:`start_configuration` places ``N`` UAVs on a surface, in the paper the approximating
surface S', by the kind its :class:`StartSettings` names, then lifts them to their flying height:

``"cvt"``
    The generators of the constrained CVT of S' (:func:`uavcov.placement.cvt`).
``"random"``
    Uniform over the region: ``(x, y)`` uniform over the surface's bounding rectangle, redrawn
    where no surface lies below (nodata), on the surface's top (``ground_height``).
``"corner"``
    A compact square lattice in one corner of the bounding rectangle: ``ceil(sqrt(N))`` columns,
    ``spacing`` metres apart (about 3 m in ``paper-setup.md``), the first point ``spacing / 2``
    in from both edges, filled row by row away from the corner.
``"pairs"``
    The buildings scene's baseline (paper Fig. 8): half the team side by side at the middle of
    the west edge, half at the east edge, ``spacing`` metres apart and ``spacing / 2`` in.
``"greedy"``
    What the paper dismissed as too costly: a global placement on S'. Lazy greedy over an
    admissible lattice of viewpoints above the surface (:func:`uavcov.cover.viewpoint_lattice`,
    limits judged on the surface), coverage measured on the surface's own targets with range
    ``d_max`` (:class:`uavcov.cover.CoverageProblem`). In a mission
    (:func:`start_configuration`) the candidates are one layer at the start's altitude above S'
    and the picks fly at that altitude like every other start's; :func:`greedy_start` returns
    picks from the whole flight band.

:class:`StartSettings` says how a mission starts: the kind, and the height the start flies at
(above the real ground the UAVs sense, or above S'); :func:`start_configuration` builds that
start, the one pipeline every mission and experiment goes through. Pushing it to admissible
positions is :func:`uavcov.limits.closest_admissible`'s job.

A structure's start (``altitude_reference="normal"``, ``STRUCTURE_START_KINDS``) goes through
the same :func:`start_configuration`: the CVT generators flown out along S''s outward normals,
greedy's picks among viewpoints flown out the same way (coverage counted on S'), uniform draws
in the admissible volume of the flight limits, or a launch pad on the real ground (the pieces
of :mod:`uavcov.placement._starts3d`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .._validate import MAX_SAMPLES, as_count, as_generator, as_non_negative_float, as_positive_float, as_positive_int
from ..cover import CoverageProblem, GreedyResult, GreedySettings, greedy_placement, surface_normals, viewpoint_lattice
from ..engine import Targets, Terrain, Visibility
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError
from ..limits import Constraints, feasibility
from ._cvt import CVTResult, CVTSettings, cvt
from ._starts3d import facing_directions, fly_out, launch_pad_start, random_volume_start

START_KINDS = ("cvt", "random", "corner", "pairs", "greedy")
"""The kinds of :class:`StartSettings` on a height field (a structure's are :data:`STRUCTURE_START_KINDS`)."""

CORNERS = ("sw", "se", "ne", "nw")
"""Corners of the bounding rectangle: south-west is ``(xmin, ymin)``, north is +y, east +x."""

ALTITUDE_REFERENCES = ("ground", "prior", "normal")
"""What a start's altitude is measured from: the real ground under each UAV, S' straight below,
or S' along its outward normal (a structure: a 3D standoff)."""

STRUCTURE_START_KINDS = ("cvt", "greedy", "random", "launch_pad")
"""The kinds a structure's start (``altitude_reference="normal"``, :func:`start_configuration`) knows."""

# Rounds of redraws over nodata before "random" gives up: each round redraws every missing point,
# so only a surface covering almost none of its rectangle can exhaust them.
_MAX_ROUNDS = 100

# The "greedy" start's default lattice (a field default of StartSettings: one shared frozen value).
_DEFAULT_GREEDY = GreedySettings()


def _rectangle(surface: Terrain) -> tuple[float, float, float, float]:
    b = np.asarray(surface.bounds, dtype=np.float64)
    return float(b[0, 0]), float(b[0, 1]), float(b[1, 0]), float(b[1, 1])


def _random(surface: Terrain, n: int, generator: np.random.Generator, threads: int | None) -> np.ndarray:
    xmin, ymin, xmax, ymax = _rectangle(surface)
    found: list[np.ndarray] = []
    count = 0
    for _ in range(_MAX_ROUNDS):
        if count == n:
            break
        xy = generator.uniform([xmin, ymin], [xmax, ymax], size=(n - count, 2))
        z = surface.ground_height(xy, n_threads=threads)
        keep = np.isfinite(z)
        found.append(np.column_stack([xy[keep], z[keep]]))
        count += int(keep.sum())
    if count < n:
        raise InfeasibleError(
            f"found only {count} of {n} positions over the surface after {_MAX_ROUNDS} rounds of uniform draws: "
            "the surface covers almost none of its bounding rectangle"
        )
    return np.concatenate(found)


def _corner(surface: Terrain, n: int, corner: str, spacing: float, threads: int | None) -> np.ndarray:
    xmin, ymin, xmax, ymax = _rectangle(surface)
    columns = math.ceil(math.sqrt(n))
    rows = math.ceil(n / columns)
    width, depth = columns * spacing, rows * spacing
    if width > xmax - xmin or depth > ymax - ymin:
        raise InfeasibleError(
            f"a {rows} x {columns} lattice {spacing} m apart needs {width} m x {depth} m, the region is {xmax - xmin} m x {ymax - ymin} m"
        )
    k = np.arange(n)
    offset_x = spacing / 2 + (k % columns) * spacing
    offset_y = spacing / 2 + (k // columns) * spacing
    x = xmin + offset_x if corner in ("sw", "nw") else xmax - offset_x
    y = ymin + offset_y if corner in ("sw", "se") else ymax - offset_y
    xy = np.column_stack([x, y])
    z = surface.ground_height(xy, n_threads=threads)
    if not np.isfinite(z).all():
        bad = int(np.flatnonzero(~np.isfinite(z))[0])
        raise InfeasibleError(
            f"corner lattice point {bad} at x-y ({xy[bad, 0]:g}, {xy[bad, 1]:g}) m stands over no surface (nodata): "
            f"pick a corner with ground under it (StartSettings(corner=...), one of sw, se, nw, ne) or another start"
        )
    return np.column_stack([xy, z])


def _pairs(surface: Terrain, n: int, spacing: float, threads: int | None) -> np.ndarray:
    xmin, ymin, xmax, ymax = _rectangle(surface)
    west = math.ceil(n / 2)
    y_mid = 0.5 * (ymin + ymax)
    rows = []
    for k in range(n):
        side, index = (0, k) if k < west else (1, k - west)
        count = west if side == 0 else n - west
        y = y_mid + (index - (count - 1) / 2) * spacing
        x = xmin + spacing / 2 if side == 0 else xmax - spacing / 2
        rows.append((x, y))
    xy = np.array(rows, dtype=np.float64)
    z = surface.ground_height(xy, n_threads=threads)
    if not np.isfinite(z).all():
        bad = int(np.flatnonzero(~np.isfinite(z))[0])
        raise InfeasibleError(f"pairs start point {bad} at x-y ({xy[bad, 0]:g}, {xy[bad, 1]:g}) stands over no surface (nodata)")
    return np.column_stack([xy, z])


def greedy_start(
    surface: Terrain,
    n: int,
    d_max: float,
    constraints: Constraints,
    settings: GreedySettings | None = None,
    *,
    n_threads: int | None = None,
) -> GreedyResult:
    """The ``"greedy"`` start: lazy greedy of ``n`` viewpoints on ``surface`` alone (S' in a mission).

    Candidates are :func:`uavcov.cover.viewpoint_lattice` over ``surface`` under
    ``constraints``; coverage is measured on ``surface``'s default targets with range ``d_max``;
    picks are kept ``constraints.d_safe`` apart unless ``settings.separation`` is off. The
    result's ``matrix_time_s + greedy_time_s`` plus the lattice's time is the start's off-line
    time (:attr:`GreedyResult.offline_time_s`).
    """
    started = time.perf_counter()
    settings = GreedySettings() if settings is None else settings
    lattice = viewpoint_lattice(surface, constraints, settings, n_threads=n_threads)
    problem = CoverageProblem(Visibility(surface, as_positive_float(d_max, "d_max"), n_threads=n_threads), lattice, n_threads=n_threads)
    result = problem.greedy(n, constraints.d_safe if settings.separation else 0.0)
    return replace(result, offline_time_s=time.perf_counter() - started)


@dataclass(frozen=True)
class StartSettings:
    """How a mission starts: where on S' the team is placed, and how high it flies.

    Attributes
    ----------
    kind : {"cvt", "random", "corner", "pairs", "greedy", "launch_pad"}, default "cvt"
        The initialisation (see the module docstring); computed on S'. ``"launch_pad"`` only
        with ``altitude_reference="normal"``, ``"corner"`` and ``"pairs"`` only without.
    altitude : float, default 5.0
        Metres above the reference at which the start flies (>= 0).
    altitude_reference : {"ground", "prior", "normal"}, default "ground"
        What ``altitude`` is measured from: the real ground under each UAV (what the UAVs sense
        on take-off; S' where the real surface has a hole), or S' itself (the paper's reading:
        the CVT generators lie on S'). ``"normal"`` is a structure's start
        (:func:`start_configuration`): "cvt" flies each generator ``altitude`` metres out along
        S''s outward normal (a standoff, under a deck as well as above it); "greedy" picks
        among points of S' ``greedy.spacing`` apart flown out the same way, by the coverage each
        adds on S' (``structure_greedy_start``; needs ``d_max``); "random" draws the
        team uniformly in the admissible volume of the flight limits (``altitude`` unused);
        "launch_pad" puts a compact lattice on the real ground at ``corner`` of the flight box,
        ``corner_altitude`` (else ``altitude``) above it.
    climb : float, default 0.0
        A UAV that the real ground forces up (under ``h_min`` of clearance) is put this many
        metres above ``h_min`` (:func:`uavcov.limits.closest_admissible`). Left exactly on
        the ``h_min`` boundary, a UAV makes every candidate that lowers it infeasible; with ``k``
        UAVs there, only ``2**-k`` of CAO's joint candidates are feasible.
    corner : {"sw", "se", "ne", "nw"}, default "sw"
        The corner the "corner" lattice fills.
    corner_spacing : float, default 3.0
        Distance between neighbouring UAVs of the "corner" lattice and of a "pairs" side, metres.
    corner_altitude : float, optional
        The height of the "corner" and "pairs" starts above the reference instead of
        ``altitude``.
    random_altitude : (float, float), optional
        When given, the "random" start draws each UAV's height above the reference uniformly
        from this range instead of flying at ``altitude``.
    greedy : GreedySettings, default GreedySettings()
        The "greedy" start's candidate lattice on S': its x-y spacing and camera angles (one
        layer of viewpoints ``altitude`` above S'; the picks then fly at ``altitude`` above the
        reference, as every start does). A structure's: ``spacing`` is the distance between
        the points of S' flown out (``n_heights`` and the camera angles unused).
    """

    kind: str = "cvt"
    altitude: float = 5.0
    altitude_reference: str = "ground"
    climb: float = 0.0
    corner: str = "sw"
    corner_spacing: float = 3.0
    corner_altitude: float | None = None
    random_altitude: tuple[float, float] | None = None
    greedy: GreedySettings = _DEFAULT_GREEDY

    def __post_init__(self) -> None:
        if isinstance(self.greedy, Mapping):  # as read back from a settings document
            values: dict[str, Any] = {k: tuple(v) if isinstance(v, list) else v for k, v in self.greedy.items()}
            object.__setattr__(self, "greedy", GreedySettings(**values))
        if not isinstance(self.greedy, GreedySettings):
            raise InvalidTypeError(f"greedy must be a GreedySettings, got {type(self.greedy).__name__}")
        if not isinstance(self.kind, str) or self.kind not in (*START_KINDS, "launch_pad"):
            raise InvalidInputError(f"kind must be one of {(*START_KINDS, 'launch_pad')}, got {self.kind!r}")
        object.__setattr__(self, "altitude", as_non_negative_float(self.altitude, "altitude"))
        object.__setattr__(self, "climb", as_non_negative_float(self.climb, "climb"))
        object.__setattr__(self, "corner_spacing", as_positive_float(self.corner_spacing, "corner_spacing"))
        if not isinstance(self.altitude_reference, str) or self.altitude_reference not in ALTITUDE_REFERENCES:
            raise InvalidInputError(f"altitude_reference must be one of {ALTITUDE_REFERENCES}, got {self.altitude_reference!r}")
        if (self.altitude_reference == "normal" and self.kind not in STRUCTURE_START_KINDS) or (
            self.kind == "launch_pad" and self.altitude_reference != "normal"
        ):
            raise InvalidInputError(
                f"kind={self.kind!r} with altitude_reference={self.altitude_reference!r}: a structure's start "
                f'(altitude_reference="normal") is one of {STRUCTURE_START_KINDS}, and "launch_pad" is a structure\'s only'
            )
        if not isinstance(self.corner, str) or self.corner not in CORNERS:
            raise InvalidInputError(f"corner must be one of {CORNERS}, got {self.corner!r}")
        if self.corner_altitude is not None:
            object.__setattr__(self, "corner_altitude", as_non_negative_float(self.corner_altitude, "corner_altitude"))
        if self.random_altitude is not None:
            if not isinstance(self.random_altitude, (tuple, list)) or len(self.random_altitude) != 2:
                raise InvalidInputError(f"random_altitude must be (low, high), got {self.random_altitude!r}")
            low, high = (as_non_negative_float(v, "random_altitude") for v in self.random_altitude)
            if low > high:
                raise InvalidInputError(f"random_altitude must be (low, high) with low <= high, got {self.random_altitude}")
            object.__setattr__(self, "random_altitude", (low, high))

    def height_above_reference(self, n: int, rng: np.random.Generator) -> np.ndarray | float:
        """The height of each UAV above the reference, metres (draws from ``rng`` for a random height)."""
        n, rng = as_count(n, "n", MAX_SAMPLES), as_generator(rng)  # checked for every kind, not only the one that draws
        if self.kind == "random" and self.random_altitude is not None:
            return rng.uniform(*self.random_altitude, size=n)
        if self.kind in ("corner", "pairs", "launch_pad") and self.corner_altitude is not None:
            return self.corner_altitude
        return self.altitude


def start_configuration(
    spec: StartSettings,
    approximation: Terrain,
    terrain: Terrain,
    n: int,
    *,
    cvt_settings: CVTSettings | None = None,
    rng: Any = None,
    n_threads: int | None = None,
    d_max: float | None = None,
    constraints: Constraints | None = None,
    keep_out: Callable[[np.ndarray], Any] | None = None,
) -> tuple[np.ndarray, CVTResult | GreedyResult | None]:
    """The start of a mission: placed on S', lifted to its flying height.

    The positions are placed on ``approximation`` by ``spec.kind`` (see the module docstring;
    the CVT's and the greedy placement's records are kept); their height is then ``spec``'s
    above the reference:
    the real ground under each UAV (``terrain``; S' over a hole of it) or S'. The result still
    has to be made admissible (:func:`uavcov.limits.closest_admissible` with
    ``climb=spec.climb``).

    Parameters
    ----------
    spec : StartSettings
    approximation : Terrain
        S', the surface the start is computed on.
    terrain : Terrain
        The real surface, whose ground the UAVs sense on take-off.
    n : int
        Team size.
    cvt_settings : CVTSettings, optional
        For ``kind="cvt"``.
    rng : None, int or numpy.random.Generator
        The start's randomness (CVT or random positions, random heights), drawn in that order.
    n_threads : int, optional
        Threads for the Rust side, 1 to 1024; ``None`` (the default) is rayon's default:
        ``RAYON_NUM_THREADS`` if set, else every core. Results do not depend on it.
    d_max : float, optional
        The sensing range ("greedy": required).
    constraints : Constraints, optional
        The flight limits ("greedy": its candidates keep to them on S'; default ``Constraints()``).
        For a structure's start (``altitude_reference="normal"``): "random" draws in their
        admissible volume over ``terrain``, "launch_pad" stands at a corner of their x-y bounds
        (``None``: the defaults with ``clearance="standoff"``).
    keep_out : callable, optional
        For a structure's "cvt" and "greedy" starts: points known to be inside the structure
        besides S' (``StructurePrior.behind``), which no generator or candidate is flown to (see
        ``fly_out``).

    Returns
    -------
    positions : (n, 3) float64 ndarray
        Metres.
    record : CVTResult, GreedyResult or None
        The CVT run for ``kind="cvt"``; the greedy placement on S', its bound and its off-line
        time for ``kind="greedy"``.
    """
    if not isinstance(spec, StartSettings):
        raise InvalidTypeError(f"spec must be a StartSettings, got {type(spec).__name__}")
    for name, surface in (("approximation", approximation), ("terrain", terrain)):
        if not isinstance(surface, Terrain):
            raise InvalidTypeError(f"{name} must be a uavcov Terrain, got {type(surface).__name__}")
    n = as_count(n, "n", MAX_SAMPLES)
    if n_threads is not None:
        as_positive_int(n_threads, "n_threads")
    generator = as_generator(rng)
    # The options of some kinds only, checked for all: one a kind ignores is still a mistake.
    d_max = None if d_max is None else as_positive_float(d_max, "d_max")
    if constraints is not None and not isinstance(constraints, Constraints):
        raise InvalidTypeError(f"constraints must be a Constraints, got {type(constraints).__name__}")
    if spec.altitude_reference == "normal":
        if spec.kind == "greedy":
            placed = structure_greedy_start(spec, approximation, terrain, n, d_max, constraints, keep_out=keep_out, n_threads=n_threads)
            return np.array(placed.positions, dtype=np.float64), placed
        return _structure_start(spec, approximation, terrain, n, cvt_settings, constraints, generator, n_threads, keep_out)
    tessellation: CVTResult | GreedyResult | None = None
    if spec.kind == "greedy":
        tessellation = _greedy_layer(spec, approximation, n, d_max, constraints, n_threads)
        positions = np.array(tessellation.positions, dtype=np.float64)
        positions[:, 2] = approximation.ground_height(positions[:, :2], n_threads=n_threads)  # back on S', as the other kinds are
    elif spec.kind == "cvt":
        tessellation = cvt(approximation, n, cvt_settings, rng=generator, n_threads=n_threads)
        positions = np.array(tessellation.generators, dtype=np.float64)
    elif spec.kind == "random":
        positions = _random(approximation, n, generator, n_threads)
    elif spec.kind == "corner":
        positions = _corner(approximation, n, spec.corner, spec.corner_spacing, n_threads)
    else:
        positions = _pairs(approximation, n, spec.corner_spacing, n_threads)
    if spec.altitude_reference == "ground":
        ground = terrain.ground_height(positions[:, :2], n_threads=n_threads)
        # Over a nodata hole of the real surface there is no ground to measure from: keep S' height.
        positions[:, 2] = np.where(np.isnan(ground), positions[:, 2], ground)
    positions[:, 2] += spec.height_above_reference(n, generator)
    return positions, tessellation


def _greedy_layer(
    spec: StartSettings, approximation: Terrain, n: int, d_max: float | None, constraints: Constraints | None, n_threads: int | None
) -> GreedyResult:
    """Greedy's ``n`` picks among one layer of viewpoints ``spec.altitude`` above S'.

    One layer at the start's own height, so that the starts differ in their x-y placement only.
    Picks from the whole flight band sit on its floor or ceiling, and a team with ``k`` UAVs on a
    limit is left ``2**-k`` of CAO's moves: in Table 1 at N = 20, 19 of 40 such runs never moved.
    """
    if d_max is None:
        raise InvalidInputError("the greedy start needs the sensing range: give d_max")
    limits = (Constraints() if constraints is None else constraints).resolve(approximation)
    layer = replace(limits, h_min=min(spec.altitude, limits.z_max), h_max=None)
    placed = greedy_start(approximation, n, d_max, layer, replace(spec.greedy, n_heights=1), n_threads=n_threads)
    if placed.positions.shape[0] < n:
        raise InfeasibleError(f"the greedy start placed only {placed.positions.shape[0]} of {n} UAVs d_safe apart on its lattice")
    return placed


def _structure_limits(constraints: Constraints | None, terrain: Terrain) -> Constraints:
    """A structure start's flight limits resolved on the real surface (default: a standoff, every move checked)."""
    if constraints is None:
        constraints = Constraints(clearance="standoff", check_moves=True)
    if not isinstance(constraints, Constraints):
        raise InvalidTypeError(f"constraints must be a Constraints, got {type(constraints).__name__}")
    return constraints.resolve(terrain)


def structure_greedy_start(
    spec: StartSettings,
    approximation: Terrain,
    terrain: Terrain,
    n: int,
    d_max: float | None,
    constraints: Constraints | None = None,
    *,
    keep_out: Callable[[np.ndarray], Any] | None = None,
    n_threads: int | None = None,
) -> GreedyResult:
    """A structure's ``"greedy"`` start: the full-knowledge reference's greedy, on S' alone.

    Candidates are points of S' about ``spec.greedy.spacing`` metres apart, each flown
    ``spec.altitude`` metres out along S''s outward normal by :func:`fly_out` (outside S', at the
    standoff from it, over the real ground's lowest point, out of ``keep_out``), as the CVT
    start's generators are; those outside the flight box or over the ceiling are dropped.
    Greedy then picks ``n`` of them, ``d_safe`` apart, by the share of S''s own targets each adds
    within ``d_max`` (:func:`uavcov.cover.greedy_placement`). What the
    start knows is S' and the known points only; the real structure enters with
    :func:`uavcov.limits.closest_admissible`, as for every start.

    Parameters
    ----------
    spec : StartSettings
        ``kind="greedy"``, ``altitude_reference="normal"``, ``altitude > 0`` (metres).
    approximation, terrain : Terrain
        S' and the real surface (only its lowest point, the sensed ground, is used).
    n : int
    d_max : float
        Sensing range, metres.
    constraints : Constraints, optional
    keep_out : callable, optional
        See :func:`fly_out`.
    n_threads : int, optional

    Returns
    -------
    GreedyResult
        The picks (coverage and bound are S''s, not the real structure's).

    Raises
    ------
    InvalidInputError
        No ``d_max`` (or not finite and > 0), or ``altitude`` 0.
    InfeasibleError
        Fewer than ``n`` admissible candidates ``d_safe`` apart.
    """
    if d_max is None:
        raise InvalidInputError("the greedy start needs the sensing range: give d_max")
    d_max = as_positive_float(d_max, "d_max")
    if not spec.altitude > 0.0:
        raise InvalidInputError("a structure's greedy start needs altitude > 0 (its candidates' standoff from S')")
    started = time.perf_counter()
    limits = _structure_limits(constraints, terrain)
    spacing = spec.greedy.spacing
    anchors, normals = surface_normals(approximation, _spread(approximation, spacing, _CANDIDATES_PER_UAV * n).points)
    floor = float(np.asarray(terrain.bounds)[0, 2])
    candidates, _ = fly_out(approximation, anchors, normals, spec.altitude, floor=floor, keep_out=keep_out, n_threads=n_threads)
    # fly_out keeps the standoff from S'; the flight box and the ceiling are known too. (The limits'
    # own check on S' would also ask for S' straight below, which beside a wall there is not.)
    xmin, ymin, xmax, ymax = limits.flight_box
    x, y, z = candidates.T
    candidates = candidates[(x >= xmin) & (x <= xmax) & (y >= ymin) & (y <= ymax) & (z <= limits.z_max)]
    if candidates.shape[0] < n:
        raise InfeasibleError(f"only {candidates.shape[0]} of the greedy start's viewpoints around S' are admissible, {n} UAVs to place")
    visibility = Visibility(approximation, d_max, _spread(approximation, 1.0, _LEAST_TARGETS), n_threads=n_threads)
    placed = greedy_placement(visibility, candidates, n, d_safe=limits.d_safe if spec.greedy.separation else 0.0, n_threads=n_threads)
    if placed.positions.shape[0] < n:
        raise InfeasibleError(f"the greedy start placed only {placed.positions.shape[0]} of {n} UAVs d_safe apart around S'")
    return replace(placed, offline_time_s=time.perf_counter() - started)


def _spread(surface: Terrain, spacing: float, at_least: int) -> Targets:
    """Points of ``surface`` about ``spacing`` metres apart (closer on a surface too small to hold
    ``at_least`` of them at that spacing), each weighted by the area it stands for.

    The surface's own targets at one per ``spacing``^2 (:meth:`Terrain.default_targets`), which
    give at least one point per triangle; on a mesh with more triangles than that (S' grown into
    an envelope: thousands of triangles smaller than the spacing), one point per cube of side
    ``spacing``, holding the cube's area, so that the greedy start weighs as many candidates
    against as many targets as the area asks, whatever the tessellation.
    """
    cell = min(spacing, float(np.sqrt(surface.area / at_least)))
    targets = surface.default_targets(density=1.0 / cell**2)
    if surface.n_faces <= surface.area / cell**2:
        return targets
    cells = np.floor((targets.points - targets.points.min(axis=0)) / cell).astype(np.int64)
    _, first, which = np.unique(cells, axis=0, return_index=True, return_inverse=True)
    weights = np.zeros(first.size)
    np.add.at(weights, which.reshape(-1), targets.weights)
    return Targets(targets.points[first], weights)


# The greedy start's least numbers of candidates (per UAV) and of targets on S': on a structure
# a few metres across (a 1 m box, a sign on a pole) one point per spacing^2 of S''s envelope left
# 1-4 candidates for 8 UAVs, and 2 per UAV still left 3-4 of 20 runs unable to place 8 d_safe
# apart (scripts/unseen_shapes.py --kinds tiny,sign_on_pole); the families' S' hold 22 or more
# at the spacings the experiment offers, and 350 or more targets.
_CANDIDATES_PER_UAV = 4
_LEAST_TARGETS = 100


def _structure_start(
    spec: StartSettings,
    approximation: Terrain,
    terrain: Terrain,
    n: int,
    cvt_settings: CVTSettings | None,
    constraints: Constraints | None,
    generator: np.random.Generator,
    n_threads: int | None,
    keep_out: Callable[[np.ndarray], Any] | None = None,
) -> tuple[np.ndarray, CVTResult | None]:
    """A start around a structure (``altitude_reference="normal"``), see :class:`StartSettings`."""
    limits = _structure_limits(constraints, terrain)
    if spec.kind == "cvt":
        # Along S''s face normal at each generator: under a deck the UAV goes down, beside a
        # pier sideways, where "above S'" would put every UAV on top of the structure.
        tessellation = cvt(approximation, n, cvt_settings, rng=generator, n_threads=n_threads)
        anchors, normals = surface_normals(approximation, tessellation.generators)
        normals = facing_directions(tessellation, normals, cvt_settings)
        if not spec.altitude > 0.0:
            return anchors, tessellation
        # Outside S' and at the standoff from it: a normal into a fold of S' flies farther out.
        # Never under the real ground (sensed; S' has none): S''s bottom faces down.
        floor = float(np.asarray(terrain.bounds)[0, 2])
        positions, _ = fly_out(approximation, anchors, normals, spec.altitude, floor=floor, keep_out=keep_out, n_threads=n_threads)
        return positions, tessellation
    xmin, ymin, xmax, ymax = limits.flight_box
    low = float(np.asarray(terrain.bounds)[0, 2])
    if spec.kind == "random":
        # Anywhere the limits allow a UAV, each judged alone (no move, no team): the volume the
        # true surface leaves, which the UAVs sense; separation is kept between the draws.
        alone = replace(limits, d_safe=0.0, check_moves=False)

        feasible = feasibility(alone, terrain, n_threads=n_threads)

        def admissible(points: np.ndarray) -> np.ndarray:
            return np.asarray(feasible(points[:1], points[:, None, :]), dtype=bool)

        top = limits.z_max
        if not top > low:
            raise InfeasibleError(f"the flight box is empty: z_max = {top} m is not above the surface's lowest point {low} m")
        box = [[xmin, ymin, low], [xmax, ymax, top]]
        return random_volume_start(box, n, admissible, separation=limits.d_safe, rng=generator), None
    # launch_pad: the paper's corner start, on the real ground at a corner of the flight box.
    columns = math.ceil(math.sqrt(n))
    rows = math.ceil(n / columns)
    half_x, half_y = columns * spec.corner_spacing / 2, rows * spec.corner_spacing / 2
    if 2 * half_x > xmax - xmin or 2 * half_y > ymax - ymin:
        raise InfeasibleError(
            f"a {rows} x {columns} launch pad {spec.corner_spacing} m apart does not fit in the {xmax - xmin} m x {ymax - ymin} m region"
        )
    x = xmin + half_x if spec.corner in ("sw", "nw") else xmax - half_x
    y = ymin + half_y if spec.corner in ("sw", "se") else ymax - half_y
    ground = float(terrain.ground_height(np.array([[x, y]]), n_threads=n_threads)[0])
    if not math.isfinite(ground):
        raise InfeasibleError(f"the launch pad at x-y ({x}, {y}) stands over no surface")
    height = float(spec.height_above_reference(n, generator))
    return launch_pad_start([x, y, ground], n, spacing=spec.corner_spacing, altitude=height), None
