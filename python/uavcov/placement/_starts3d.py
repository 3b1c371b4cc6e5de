"""Starts for a structure (any triangle mesh, not a height field), and cameras that face it.

Three starts, each on S' given as a generic :class:`~uavcov.Terrain` mesh:

:func:`standoff_start`
    The CVT generators of S' (:func:`uavcov.placement.cvt`, general on meshes), each flown out
    along S''s outward normal at the generator to ``standoff`` metres (farther, or lifted, where
    that point would be inside S' or nearer to it: ``fly_out``), with the camera looking
    back at its generator (heading and pitch from the normal, :func:`facing_attitudes`).
    The normal is the *face* normal of the triangle the generator lies on (on an edge or vertex
    shared by several, the mean of their distinct planes' normals), not an interpolated vertex
    normal (nor an area-weighted one): a
    structure is made of flat faces meeting at sharp edges, and on a coarse S' a vertex normal
    smears that edge over the whole face (a box's eight vertex normals all point diagonally, so
    a generator in the middle of a wall would be flown out at 55 degrees off the wall's normal).
``random_volume_start``
    Uniform in a flight box, kept where a given ``admissible(points) -> bool`` predicate
    accepts (the 3D flight limits), by rejection, deterministic for a given ``rng``.
``launch_pad_start``
    The paper's "corner": a compact square lattice centred on a take-off pad.

The height-field starts (:func:`uavcov.placement.initial_positions`) are untouched.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import (
    MAX_GENERATORS,
    MAX_SAMPLES,
    as_count,
    as_finite_float,
    as_float_array,
    as_generator,
    as_non_negative_float,
    as_points,
    as_positive_float,
    read_only,
)
from ..cover import surface_normals
from ..engine import Gimbal, Terrain, as_mesh_surface, gimbal_pitch_limits
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError
from ._cvt import CVTResult, CVTSettings, cvt

# Rounds of rejection draws before a random start gives up; each round draws a batch at least
# _MIN_BATCH large, so a feasible share of the box under about 1/(rounds * batch) exhausts them.
_MAX_ROUNDS = 200
_MIN_BATCH = 256


def _is_closed(faces: np.ndarray) -> bool:
    """Whether every edge is met once in each direction (closed solids wound consistently)."""
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    forward = np.unique(edges, axis=0)
    backward = np.unique(edges[:, ::-1], axis=0)
    return forward.shape == backward.shape and bool((forward == backward).all())


# How far along its normal a generator is tried, in standoffs, before it is lifted instead.
_FLY_OUT_STEPS = (1.0, 1.5, 2.0, 3.0, 4.0)


def facing_directions(tessellation: CVTResult, face_normals: np.ndarray, settings: CVTSettings | None) -> np.ndarray:
    """The directions to fly each CVT generator out along: with a normal-weighted CVT
    (``CVTSettings.normal_weight > 0``) its region's facing, which is what the region shows a
    camera there (S''s face normal at the generator itself may belong to a corner or a small
    face the region barely holds); the face normals otherwise, and where a facing is zero."""
    facings = tessellation.normals
    if settings is None or settings.normal_weight <= 0.0 or facings is None:
        return face_normals
    usable = np.linalg.norm(facings, axis=1) > 0.5
    return np.where(usable[:, None], facings, face_normals)


def fly_out(
    surface: Terrain,
    anchors: Any,
    normals: Any,
    standoff: float,
    *,
    floor: float | None = None,
    keep_out: Callable[[np.ndarray], Any] | None = None,
    n_threads: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Points ``standoff`` out from S' along its outward normals, each outside S' and at least
    ``standoff`` from it.

    Each anchor is flown out to ``standoff`` metres along its normal; where that point is inside
    S' (a normal facing into a fold of S'; ray parity, when S' is closed) or nearer than
    ``standoff`` to another part of it, the anchor is flown out farther (1.5, 2, 3, 4
    standoffs), and the first point outside S' at the standoff is kept. Where no step reaches
    the standoff (a generator in a concave corner: the ground stays as near however far it
    goes), the first step outside S' is kept and the flight limits settle its distance. One that
    no step takes out of S' is *lifted*: put straight above its anchor at ``standoff`` over
    S''s top, which is outside S' and at least ``standoff`` from it whatever S' is; the flight
    limits then bring it back down against the real structure.

    With ``floor`` (the height of the real ground, which the team senses: S' has none), no step
    goes below ``floor + standoff``: a generator on S''s bottom (closed underneath at the lowest
    known points, facing down) flown down would land under the ground, so its step is raised to
    the standoff over the ground and then judged as any other (outside S', at the standoff from
    it).

    With ``keep_out`` (a predicate of what else is known to be solid: the known points' vote,
    :meth:`uavcov.structures.StructurePrior.behind`, which sees a girder or a balcony S' does not
    resolve), a step it marks counts as inside S': the generator is flown farther, or lifted.

    Parameters
    ----------
    surface : Terrain
        S', wound outward.
    anchors, normals : (n, 3) array_like of float
        Points on S' and S''s outward unit normals there.
    standoff : float
        Metres (> 0).
    floor : float, optional
        The real ground's height, metres: no position below ``floor + standoff``.
    keep_out : callable, optional
        ``keep_out(points (m, 3)) -> (m,)`` bool: points known to be inside the structure.
    n_threads : int, optional

    Returns
    -------
    positions : (n, 3) float64 ndarray
    lifted : (n,) bool ndarray
        The positions that were lifted over S'.
    """
    surface = as_mesh_surface(surface, "a start")
    base = as_points(anchors, "anchors")
    direction = as_points(normals, "normals")
    if direction.shape != base.shape:
        raise InvalidInputError(f"{direction.shape[0]} normals for {base.shape[0]} anchors")
    distance_out = as_positive_float(standoff, "standoff")
    # Ray parity tells inside from outside only on a closed S' (a reconstruction); on an open
    # one (a deck sheet, a ground plane) a point under the sheet would count as inside.
    closed = _is_closed(surface.faces)
    tolerance = 1e-9 * max(1.0, float(np.abs(surface.bounds).max()))
    trials = base[None] + np.asarray(_FLY_OUT_STEPS)[:, None, None] * distance_out * direction[None]  # (steps, n, 3)
    if floor is not None:
        trials[..., 2] = np.maximum(trials[..., 2], as_finite_float(floor, "floor") + distance_out)
    flat = trials.reshape(-1, 3)
    outside = ~surface.inside(flat, n_threads=n_threads) if closed else np.ones(flat.shape[0], dtype=bool)
    if keep_out is not None:
        known_inside = np.asarray(keep_out(flat))
        if known_inside.shape != (flat.shape[0],) or known_inside.dtype != np.bool_:
            raise InvalidInputError(f"keep_out must return a ({flat.shape[0]},) bool array, got {known_inside.dtype} {known_inside.shape}")
        outside &= ~known_inside
    outside = outside.reshape(trials.shape[:2])
    clear = outside & (surface.distance(flat, n_threads=n_threads) >= distance_out - tolerance).reshape(trials.shape[:2])
    # The first step outside S' at the standoff; else (a generator in a concave corner, which
    # no step along its normal frees) the first step outside S', left to the flight limits.
    chosen = np.where(clear.any(axis=0), np.argmax(clear, axis=0), np.argmax(outside, axis=0))
    pending = np.asarray(~outside.any(axis=0), dtype=bool)
    positions: np.ndarray = trials[chosen, np.arange(base.shape[0])]
    top = float(surface.bounds[1, 2])
    positions[pending] = np.column_stack([base[pending, :2], np.full(int(pending.sum()), top + distance_out)])
    return positions, pending


def facing_attitudes(directions: Any) -> np.ndarray:
    """The heading and gimbal pitch that point a camera's optical axis along each direction.

    Heading clockwise from north (+y), in ``[0, 360)``; pitch from -90 (down) to +90 (up), as
    :func:`uavcov.engine.camera_axes` takes them (its ``forward`` is then the unit direction). A
    vertical direction has no heading of its own: it gets 0.

    Parameters
    ----------
    directions : (n, 3) array_like of float
        Non-zero vectors (any length).

    Returns
    -------
    (n, 2) float64 ndarray
        ``(yaw, pitch)`` in degrees.

    Examples
    --------
    >>> facing_attitudes([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 1.0]]).tolist()
    [[0.0, -90.0], [90.0, 0.0], [180.0, 45.0]]
    """
    d = as_points(directions, "directions")
    horizontal = np.hypot(d[:, 0], d[:, 1])
    if not (np.hypot(horizontal, d[:, 2]) > 0.0).all():
        raise InvalidInputError("a camera direction must be a non-zero vector")
    level = horizontal > 1e-12 * np.abs(d[:, 2])
    yaw = np.where(level, np.degrees(np.arctan2(d[:, 0], d[:, 1])) % 360.0, 0.0)
    pitch = np.degrees(np.arctan2(d[:, 2], horizontal))
    return np.column_stack([yaw, pitch])


def _pitch_limits(gimbal: Any) -> tuple[float, float]:
    if isinstance(gimbal, str):
        return gimbal_pitch_limits(gimbal)
    if isinstance(gimbal, Gimbal):
        if gimbal.pitch_range is None:
            raise InvalidInputError("the gimbal states no pitch_range: give the range it reaches (Gimbal(pitch_range=...))")
        return gimbal.pitch_range
    raise InvalidTypeError(f"gimbal must be a capability name or a uavcov.Gimbal, got {type(gimbal).__name__}")


def check_reachable(pitch_deg: Any, gimbals: Any) -> np.ndarray:
    """Which of ``gimbals`` reaches each required pitch; refuses a pitch that none reaches.

    Parameters
    ----------
    pitch_deg : (n,) array_like of float
        Required pitches, degrees.
    gimbals : str, Gimbal or sequence of them
        What the team carries: capability names of ``uavcov.engine._sensors.GIMBAL_PITCH_LIMITS``
        or gimbals with a ``pitch_range``. One for the whole team, or a list of options.

    Returns
    -------
    (n,) int64 ndarray
        For each pitch, the index of the first gimbal that reaches it (0 for a single gimbal).

    Raises
    ------
    InfeasibleError
        Some pitch lies outside every gimbal's range (the message names the UAVs and a
        capability class that would reach them).
    """
    options = [gimbals] if isinstance(gimbals, (str, Gimbal)) else list(gimbals) if isinstance(gimbals, (list, tuple)) else None
    if not options:
        raise InvalidTypeError(f"gimbals must be a capability name, a Gimbal or a non-empty list of them, got {gimbals!r}")
    limits = np.array([_pitch_limits(g) for g in options])
    pitch = as_float_array(pitch_deg, "pitch_deg", ndim=1)
    reach = (pitch[:, None] >= limits[None, :, 0]) & (pitch[:, None] <= limits[None, :, 1])
    missing = np.flatnonzero(~reach.any(axis=1))
    if missing.size:
        shown = ", ".join(f"UAV {i} at {pitch[i]:.1f}" for i in missing[:5])
        needed = "upward" if pitch[missing].max() > gimbal_pitch_limits("three_axis")[1] else "three_axis"
        raise InfeasibleError(
            f"{missing.size} camera pitch(es) no given gimbal reaches ({shown} degrees; ranges {limits.tolist()}): "
            f"a camera that must point up needs a gimbal that can, e.g. Gimbal.preset({needed!r})"
        )
    first: np.ndarray = np.argmax(reach, axis=1).astype(np.int64)
    return first


@dataclass(frozen=True, eq=False)
class StandoffStart:
    """A start flown out from S' along its normals, each camera looking back at its generator.

    Attributes
    ----------
    positions : (n, 3) float64
        The UAVs, metres: ``anchors + standoff * normals``.
    anchors : (n, 3) float64
        The CVT generators on S', metres.
    normals : (n, 3) float64
        S''s outward unit face normal at each generator.
    attitudes : (n, 2) float64
        Heading and pitch, degrees, pointing each camera along the inward normal (at its
        anchor), clipped to the gimbal's range only if asked to.
    distance : (n,) float64
        Each position's least distance to S', metres: at least ``standoff`` (``fly_out``
        flies a generator farther out where another part of S' is nearer).
    tessellation : CVTResult
        The CVT run.
    lifted : (n,) bool
        The positions no step along the normal freed, lifted over S' (``fly_out``).
    """

    positions: np.ndarray
    anchors: np.ndarray
    normals: np.ndarray
    attitudes: np.ndarray
    distance: np.ndarray
    tessellation: CVTResult
    lifted: np.ndarray

    def __post_init__(self) -> None:
        for name in ("positions", "anchors", "normals", "attitudes", "distance"):
            object.__setattr__(self, name, read_only(np.array(getattr(self, name), dtype=np.float64)))
        object.__setattr__(self, "lifted", read_only(np.array(self.lifted, dtype=bool)))


def standoff_start(
    surface: Terrain,
    n: int,
    standoff: float,
    *,
    gimbal: Any = "upward",
    clip_pitch: bool = False,
    cvt_settings: CVTSettings | None = None,
    rng: Any = None,
    n_threads: int | None = None,
) -> StandoffStart:
    """CVT generators of ``surface`` flown out along its outward normals to ``standoff`` metres
    (each outside S' and at least ``standoff`` from it, see ``fly_out``).

    Parameters
    ----------
    surface : Terrain
        S', a closed or open mesh with outward (right-hand, counter-clockwise) faces.
    n : int
        Team size, 1 to 10 000.
    standoff : float
        Metres from each generator along its normal (> 0).
    gimbal : str, Gimbal or list of them, default "upward"
        What the cameras can reach (see ``check_reachable``).
    clip_pitch : bool, default False
        ``False`` refuses a start whose camera would have to look beyond every gimbal's range;
        ``True`` clips such a pitch into the first gimbal's range instead (the camera then does
        not face its generator squarely).
    cvt_settings : CVTSettings, optional
    rng : None, int or numpy.random.Generator
        The CVT's randomness.
    n_threads : int, optional
        Threads for the Rust side; results do not depend on it.

    Raises
    ------
    InfeasibleError
        A camera pitch that no gimbal reaches (unless ``clip_pitch``).
    InvalidInputError
        An empty mesh, ``standoff <= 0``, a bad ``n``.
    """
    surface = as_mesh_surface(surface, "a start")
    n = as_count(n, "n", MAX_GENERATORS)
    distance_out = as_positive_float(standoff, "standoff")
    if not isinstance(clip_pitch, bool):
        raise InvalidTypeError(f"clip_pitch must be a bool, got {type(clip_pitch).__name__}")
    tessellation = cvt(surface, n, cvt_settings, rng=rng, n_threads=n_threads)
    anchors, normals = surface_normals(surface, tessellation.generators)
    normals = facing_directions(tessellation, normals, cvt_settings)
    positions, lifted = fly_out(surface, anchors, normals, distance_out, n_threads=n_threads)
    attitudes = facing_attitudes(anchors - positions)
    if clip_pitch:
        first = gimbal[0] if isinstance(gimbal, (list, tuple)) and gimbal else gimbal
        low, high = _pitch_limits(first)
        attitudes[:, 1] = np.clip(attitudes[:, 1], low, high)
    else:
        check_reachable(attitudes[:, 1], gimbal)
    distance = np.linalg.norm(positions - surface.closest_point(positions, n_threads=n_threads), axis=1)
    return StandoffStart(positions, anchors, normals, attitudes, distance, tessellation, lifted)


def random_volume_start(
    box: Any,
    n: int,
    admissible: Callable[[np.ndarray], Any],
    *,
    separation: float = 0.0,
    rng: Any = None,
) -> np.ndarray:
    """``n`` positions uniform in the flight box where ``admissible`` accepts them, by rejection.

    Each round draws a batch uniform in ``box``, asks ``admissible`` once for the whole batch,
    and keeps, in draw order, the accepted points at least ``separation`` from every point kept
    before. The result is the uniform distribution on the admissible volume (conditioned on the
    separation), and the same for the same ``rng``.

    Parameters
    ----------
    box : (2, 3) array_like of float
        ``[[xmin, ymin, zmin], [xmax, ymax, zmax]]``, metres, finite, each max > min.
    n : int
        Team size.
    admissible : callable
        ``admissible(points (m, 3)) -> (m,)`` bool: whether a UAV may be there (for a structure,
        the 3D flight limits: standoff, not inside a solid, under the ceiling).
    separation : float, default 0
        Least distance between two UAVs, metres (``d_safe``).
    rng : None, int or numpy.random.Generator

    Returns
    -------
    (n, 3) float64 ndarray

    Raises
    ------
    InfeasibleError
        Fewer than ``n`` admissible, separated points after 200 rounds.
    InvalidInputError
        A bad box, or ``admissible`` answering with the wrong shape.
    """
    bounds = as_float_array(box, "box")
    if bounds.shape != (2, 3) or not np.isfinite(bounds).all() or not (bounds[1] > bounds[0]).all():
        raise InvalidInputError(f"box must be finite [[xmin, ymin, zmin], [xmax, ymax, zmax]] with max > min, got {box!r}")
    n = as_count(n, "n", MAX_SAMPLES)
    gap = as_non_negative_float(separation, "separation")
    if not callable(admissible):
        raise InvalidTypeError(f"admissible must be callable, got {type(admissible).__name__}")
    generator = as_generator(rng)
    kept = np.empty((n, 3))
    count = 0
    for _ in range(_MAX_ROUNDS):
        batch = max(_MIN_BATCH, 4 * (n - count))
        draws = generator.uniform(bounds[0], bounds[1], size=(batch, 3))
        answer = np.asarray(admissible(draws))
        if answer.shape != (batch,) or answer.dtype != np.bool_:
            raise InvalidInputError(f"admissible must return a ({batch},) bool array for {batch} points, got {answer.dtype} {answer.shape}")
        for point in draws[answer]:
            if gap > 0.0 and count and (np.linalg.norm(kept[:count] - point, axis=1) < gap).any():
                continue
            kept[count] = point
            count += 1
            if count == n:
                return kept
    raise InfeasibleError(
        f"found only {count} of {n} admissible positions {gap} m apart in {_MAX_ROUNDS} rounds of uniform draws in the box "
        f"{bounds.tolist()}: the admissible volume is (almost) empty or too small for the team"
    )


def launch_pad_start(pad: Any, n: int, *, spacing: float = 3.0, altitude: float = 0.0) -> np.ndarray:
    """A compact square lattice centred on a take-off pad: the paper's "corner" start for a structure.

    ``ceil(sqrt(n))`` columns along x, filled row by row along y, ``spacing`` apart, centred on
    the pad's ``(x, y)``, all at the pad's height plus ``altitude``.

    Parameters
    ----------
    pad : (3,) array_like of float
        The pad's centre on the ground, metres.
    n : int
    spacing : float, default 3.0
        Metres (> 0).
    altitude : float, default 0
        Metres above the pad (>= 0).

    Examples
    --------
    >>> launch_pad_start([10.0, 0.0, 2.0], 3, spacing=2.0).tolist()
    [[9.0, -1.0, 2.0], [11.0, -1.0, 2.0], [9.0, 1.0, 2.0]]
    """
    centre = as_float_array(pad, "pad")
    if centre.shape != (3,) or not np.isfinite(centre).all():
        raise InvalidInputError(f"pad must be a finite (x, y, z), got {pad!r}")
    n = as_count(n, "n", MAX_SAMPLES)
    step = as_positive_float(spacing, "spacing")
    lift = as_non_negative_float(altitude, "altitude")
    columns = math.ceil(math.sqrt(n))
    rows = math.ceil(n / columns)
    k = np.arange(n)
    x = centre[0] + (k % columns - (columns - 1) / 2) * step
    y = centre[1] + (k // columns - (rows - 1) / 2) * step
    return np.column_stack([x, y, np.full(n, centre[2] + lift)])
