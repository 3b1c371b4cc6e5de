"""The initial UAV positions the paper compares: CVT, random and corner, behind one interface.

:func:`initial_positions` returns ``N`` positions on (or a fixed height above) the given surface,
in the paper the approximating surface S':

``"cvt"``
    The generators of the constrained CVT of S' (:func:`uavcov.cvt.cvt`).
``"random"``
    Uniform over the region: ``(x, y)`` uniform over the surface's bounding rectangle, redrawn
    where no surface lies below (nodata), on the surface's top (``ground_height``).
``"corner"``
    A compact square lattice in one corner of the bounding rectangle: ``ceil(sqrt(N))`` columns,
    ``spacing`` metres apart (about 3 m in ``paper-setup.md``), the first point ``spacing / 2``
    in from both edges, filled row by row away from the corner.

Lifting to flying height above the *real* terrain and pushing to admissible positions is not
done here: that is :func:`uavcov.constraints.closest_admissible`'s job. ``altitude`` only adds a
fixed height to every position (0 by default: on the surface).
"""

from __future__ import annotations

import inspect
import math
from typing import Any, Mapping

import numpy as np

from ._validate import as_generator, as_non_negative_float, as_positive_float, as_positive_int
from .cvt import cvt
from .errors import InfeasibleError, InvalidInputError, InvalidTypeError
from .surface import Terrain

__all__ = ["initial_positions", "START_KINDS", "CORNERS"]

START_KINDS = ("cvt", "random", "corner")
"""The kinds :func:`initial_positions` knows."""

CORNERS = ("sw", "se", "ne", "nw")
"""Corners of the bounding rectangle: south-west is ``(xmin, ymin)``, north is +y, east +x."""

# Rounds of redraws over nodata before "random" gives up: each round redraws every missing point,
# so only a surface covering almost none of its rectangle can exhaust them.
_MAX_ROUNDS = 100



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
            f"a {rows} x {columns} lattice {spacing} m apart needs {width} m x {depth} m, "
            f"the region is {xmax - xmin} m x {ymax - ymin} m"
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
        raise InfeasibleError(f"corner lattice point {bad} at x-y {tuple(xy[bad])} stands over no surface (nodata)")
    return np.column_stack([xy, z])


def _cvt_options(kind: str, cvt_options: Any) -> dict[str, Any]:
    """The extra keyword arguments for :func:`uavcov.cvt.cvt`, checked by name."""
    if cvt_options is None:
        return {}
    if not isinstance(cvt_options, Mapping):
        raise InvalidTypeError(f"cvt_options must be a mapping, got {type(cvt_options).__name__}")
    options = dict(cvt_options)
    if kind != "cvt" and options:
        raise InvalidInputError(f"cvt_options apply to kind='cvt' only, got kind={kind!r}")
    own = {"surface", "n", "rng", "n_threads"}
    known = set(inspect.signature(cvt).parameters) - own
    unknown = sorted(set(options) - known)
    if unknown:
        raise InvalidInputError(
            f"cvt_options: unknown or not allowed here {unknown}; allowed {sorted(known)} "
            "(rng and n_threads go to initial_positions itself)"
        )
    return options


def initial_positions(
    kind: str,
    surface: Terrain,
    n: int,
    *,
    altitude: float = 0.0,
    rng: Any = None,
    corner: str = "sw",
    spacing: float = 3.0,
    cvt_options: Mapping[str, Any] | None = None,
    n_threads: int | None = None,
) -> np.ndarray:
    """Start positions of ``n`` UAVs over ``surface``, by one of the paper's initialisations.

    Parameters
    ----------
    kind : {"cvt", "random", "corner"}
        The initialisation (see the module docstring).
    surface : Terrain
        The surface the starts are computed on (the approximating surface S' in the paper).
    n : int
        Number of UAVs, >= 1.
    altitude : float, default 0.0
        Metres added to every position's z (>= 0). The default leaves the starts on the surface;
        lifting above the real terrain is :func:`uavcov.constraints.closest_admissible`'s job.
    rng : None, int or numpy.random.Generator
        Randomness for "cvt" and "random" ("corner" is deterministic and ignores it).
    corner : {"sw", "se", "ne", "nw"}, default "sw"
        Which corner of the bounding rectangle the "corner" lattice fills ("sw" is
        ``(xmin, ymin)``).
    spacing : float, default 3.0
        Distance between neighbouring "corner" lattice points, metres (> 0).
    cvt_options : mapping, optional
        Keyword arguments for :func:`uavcov.cvt.cvt` ("cvt" only), e.g. ``{"preset": "lloyd"}``.
    n_threads : int, optional
        Threads for the Rust side; all cores by default.

    Returns
    -------
    (n, 3) float64 ndarray
        Positions, metres: on the surface, plus ``altitude`` in z.

    Raises
    ------
    InvalidInputError
        An unknown kind or corner, ``n < 1``, negative ``altitude``, ``spacing <= 0``, or options
        :func:`uavcov.cvt.cvt` refuses.
    InfeasibleError
        The corner lattice does not fit in the region or stands over nodata, or the surface
        covers almost none of its rectangle ("random").
    InvalidTypeError
        ``surface`` is not a Terrain, or an argument of the wrong type.
    """
    if not isinstance(kind, str):
        raise InvalidTypeError(f"kind must be a string, got {type(kind).__name__}")
    if kind not in START_KINDS:
        raise InvalidInputError(f"kind must be one of {START_KINDS}, got {kind!r}")
    if not isinstance(surface, Terrain):
        raise InvalidTypeError(f"surface must be a uavcov Terrain, got {type(surface).__name__}")
    n = as_positive_int(n, "n")
    lift = as_non_negative_float(altitude, "altitude")
    if not isinstance(corner, str):
        raise InvalidTypeError(f"corner must be a string, got {type(corner).__name__}")
    if corner not in CORNERS:
        raise InvalidInputError(f"corner must be one of {CORNERS}, got {corner!r}")
    step = as_positive_float(spacing, "spacing")
    if n_threads is not None:
        as_positive_int(n_threads, "n_threads")
    options = _cvt_options(kind, cvt_options)

    if kind == "cvt":
        positions = cvt(surface, n, rng=rng, n_threads=n_threads, **options).generators
    elif kind == "random":
        positions = _random(surface, n, as_generator(rng), n_threads)
    else:
        positions = _corner(surface, n, corner, step, n_threads)

    out = np.array(positions, dtype=np.float64)
    out[:, 2] += lift
    return out
