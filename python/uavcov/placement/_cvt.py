"""Constrained centroidal Voronoi tessellation (CVT) of a surface: the paper's initial positions.

:func:`cvt` places ``N`` generators on a surface (in the paper the approximating surface S') so
that each is the constrained centroid of its Voronoi region: the surface point closest to the
region's centroid. It runs the probabilistic MacQueen method of Ju, Du and Gunzburger (paper
section IV-A) in Rust. Each iteration draws ``q`` points uniform by (density-weighted) area,
gives each to its nearest generator by 3D distance, and moves every generator ``z`` that got
samples towards their mean ``y*``::

    z <- ((a1 j + b1) z + (a2 j + b2) y*) / (j + 1),    j <- j + 1,

then projects it onto the surface. ``j`` counts a generator's updates (from 1); one without
samples neither moves nor counts. The weight on the sample mean, ``(a2 j + b2) / (j + 1)``, starts
at ``(a2 + b2) / 2`` and tends to ``a2``.

Presets of ``(alpha, beta)``
----------------------------
``"damped"`` (default)
    ``a = b = (0.5, 0.5)``: ``j`` drops out and every step is ``z <- (z + y*) / 2``, a damped
    sampled Lloyd step (the starting point of ``paper-setup.md``).
``"lloyd"``
    ``a = b = (0, 1)``: ``z <- y*``, sampled Lloyd. About twice as fast to converge as
    ``"damped"``, with three times its jitter variance.
``"annealed"``
    ``a = (0.9, 0.1)``, ``b = (0, 1)``: MacQueen-like, the step falls like ``1 / j`` from about
    1/2 to a floor of 0.1, which averages the sampling noise over about 20 iterations. Its
    shrinking steps make a move-based stop fire early, so use it to *refine* a converged CVT
    (``initial=result.generators``) or with a smaller ``tol``.

Stopping
--------
Near a CVT the sampling noise alone moves generators by about ``0.2 sqrt(area / q)`` per
iteration with the damped weights (0.3-0.5 m on a 100 m square with the default ``q``), so a
per-iteration move never falls under 0.1 m there. The run measures instead the *net* move over the last ``window``
iterations, where jitter cancels and drift adds up,
``drift_k = mean_i |z_i(k) - z_i(k - window)| / window`` (m per iteration), and stops at the
first ``drift_k < tol``, or after ``max_iterations``. Like any local rule it can stop while a
slow mode of the tessellation is still drifting: on a flat 100 m square, against k-means run to
convergence from the same start, the default stop leaves the energy 0.1-1.5 % higher (median
over starts; at most 2.6 %), against at most 1.7 % after 300 iterations (``benches/README.md``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields, replace
from types import MappingProxyType
from typing import Any

import numpy as np

from .. import _core
from .._validate import (
    MAX_GENERATORS,
    MAX_ITERATIONS,
    MAX_SAMPLES,
    as_count,
    as_float_array,
    as_generator,
    as_n_threads,
    as_non_negative_float,
    as_non_negative_int,
    as_points,
    not_a_terrain,
    read_only,
)
from ..engine import Terrain
from ..errors import InvalidInputError, InvalidTypeError

PRESETS: Mapping[str, tuple[tuple[float, float], tuple[float, float]]] = MappingProxyType(
    {
        "damped": ((0.5, 0.5), (0.5, 0.5)),
        "lloyd": ((0.0, 1.0), (0.0, 1.0)),
        "annealed": ((0.9, 0.1), (0.0, 1.0)),
    }
)
"""Named ``(alpha, beta)`` weights of the update rule (see the module docstring)."""


def default_samples_per_iteration(n: int) -> int:
    """``max(2000, 200 n)``, the samples per iteration of ``paper-setup.md``."""
    return max(2000, 200 * int(n))


def seed_from_rng(rng: Any) -> int:
    """The u64 seed the Rust core runs from: ``numpy.random.default_rng(rng).integers(2**63)``.

    An int or ``None`` gives a fresh generator (so the same int always gives the same seed); a
    ``numpy.random.Generator`` is advanced by one draw.
    """
    return int(as_generator(rng).integers(2**63))


@dataclass(frozen=True, eq=False)
class CVTResult:
    """The outcome of :func:`cvt`.

    Attributes
    ----------
    generators : (N, 3) float64 ndarray
        The generators, on the surface, metres (read-only).
    moves : (K,) float64 ndarray
        Per iteration, the mean over generators of the distance each moved, metres.
    drift : (K,) float64 ndarray
        Per iteration ``k``, the stopping statistic ``mean_i |z_i(k) - z_i(k - window)| / window``
        in metres per iteration; NaN for the first ``window - 1`` iterations.
    energy : (K,) float64 ndarray
        Per iteration, a Monte-Carlo estimate of the CVT energy per unit (density-weighted) area
        of the generators at the start of that iteration: the mean squared distance, m^2, from
        the iteration's samples to their nearest generator. Multiply by the (weighted) area for
        the integral of ``rho |y - z|^2``.
    iterations : int
        ``K``, the iterations run.
    converged : bool
        Whether the run stopped on ``tol`` rather than on ``max_iterations``.
    seed : int
        The u64 seed the run used (see ``seed_from_rng``).
    normals : (N, 3) float64 ndarray or None
        Each generator's facing: the unit direction of its region's mean outward face normal
        (zero where the region's normals cancel), the normal part of the generator that
        ``CVTSettings.normal_weight`` weighs; computed whatever the weight. ``None`` for a
        result read from a record written before it existed.
    """

    generators: np.ndarray
    moves: np.ndarray = field(repr=False)
    drift: np.ndarray = field(repr=False)
    energy: np.ndarray = field(repr=False)
    iterations: int
    converged: bool
    seed: int
    normals: np.ndarray | None = None

    def __post_init__(self) -> None:
        for name in ("generators", "moves", "drift", "energy"):
            object.__setattr__(self, name, read_only(np.array(getattr(self, name), dtype=np.float64)))
        if as_non_negative_int(self.seed, "seed") >= 2**64:  # a record read back must hold the core's u64 seed
            raise InvalidInputError(f"seed must be below 2**64 (the core's u64 seed), got {self.seed}")
        object.__setattr__(self, "iterations", as_non_negative_int(self.iterations, "iterations"))
        if self.normals is not None:
            normals = read_only(np.array(self.normals, dtype=np.float64))
            if normals.shape != self.generators.shape:
                raise InvalidInputError(f"normals must have the generators' shape {self.generators.shape}, got {normals.shape}")
            object.__setattr__(self, "normals", normals)

    @property
    def n_generators(self) -> int:
        """``N``."""
        return int(self.generators.shape[0])

    def regions(self, points: Any, *, n_threads: int | None = None) -> np.ndarray:
        """The Voronoi region (index of the nearest generator, 3D distance) of each point.

        By position alone: with ``CVTSettings.normal_weight > 0`` the run's own regions also
        weighed each sample's normal against the generators' facings (``normals``).

        Parameters
        ----------
        points : (n, 3) array_like of float
            Points, metres; usually on the surface (e.g. ``terrain.default_targets().points``).
        n_threads : int, optional
            Threads for the Rust side, 1 to 1024; ``None`` (the default) is rayon's default:
            ``RAYON_NUM_THREADS`` if set, else every core. Results do not depend on it.

        Returns
        -------
        (n,) int64 ndarray
            Indices into :attr:`generators`; ties go to the lower index.
        """
        pts = as_points(points, "points", allow_empty=True)
        return _core.CVT.regions(np.ascontiguousarray(self.generators), pts, as_n_threads(n_threads))


def _as_pair(value: Any, name: str) -> tuple[float, float]:
    if isinstance(value, (str, bytes)):
        raise InvalidTypeError(f"{name} must be a pair of numbers, got a string")
    array = as_float_array(value, name)
    if array.shape != (2,):
        raise InvalidInputError(f"{name} must be a pair ({name}1, {name}2), got shape {array.shape}")
    return float(array[0]), float(array[1])


def _weights(preset: Any, alpha: Any, beta: Any) -> tuple[tuple[float, float], tuple[float, float]]:
    if not isinstance(preset, str):
        raise InvalidTypeError(f"preset must be a string, got {type(preset).__name__}")
    if preset not in PRESETS:
        raise InvalidInputError(f"preset must be one of {sorted(PRESETS)}, got {preset!r}")
    a, b = PRESETS[preset]
    a = a if alpha is None else _as_pair(alpha, "alpha")
    b = b if beta is None else _as_pair(beta, "beta")
    for name, (w1, w2) in (("alpha", a), ("beta", b)):
        if abs(w1 + w2 - 1.0) > 1e-9:
            raise InvalidInputError(f"{name}1 + {name}2 must be 1 (the paper's constraint), got {w1} + {w2}")
        if not w2 > 0.0:
            raise InvalidInputError(f"{name}2 must be > 0 (the paper's constraint), got {w2}")
        if w1 < 0.0:
            raise InvalidInputError(f"{name}1 must be >= 0 so a step never overshoots the sample mean, got {w1}")
    return a, b


def _density(density: Any, surface: Terrain) -> np.ndarray | None:
    """Per-triangle density: an array as given, or a callable evaluated at triangle centroids."""
    if density is None:
        return None
    if callable(density):
        centroids = surface.vertices[surface.faces].mean(axis=1)
        try:
            values = density(centroids)
        except Exception as exc:
            raise InvalidInputError(f"the density callable failed on the ({len(centroids)}, 3) triangle centroids: {exc}") from exc
        what = "the density callable's output"
    else:
        values = density
        what = "density"
    array = as_float_array(values, what, allow_nan=True)
    if array.shape != (surface.n_faces,):
        raise InvalidInputError(f"{what} must have one value per triangle, shape ({surface.n_faces},), got {array.shape}")
    if not np.isfinite(array).all():
        raise InvalidInputError(f"{what} contains NaN or infinite values")
    if (array < 0.0).any():
        raise InvalidInputError(f"{what} must be >= 0 everywhere, found {array.min()}")
    if not (array > 0.0).any():
        raise InvalidInputError(f"{what} is zero over the whole surface")
    return np.ascontiguousarray(array)


_MAX_NORMAL_WEIGHT = 1e15
"""The largest ``normal_weight`` (m): the core's largest coordinate."""


@dataclass(frozen=True)
class CVTSettings:
    """The constants of :func:`cvt`: update weights, samples and the stopping rule.

    Attributes
    ----------
    preset : {"damped", "lloyd", "annealed"}, default "damped"
        Named ``(alpha, beta)`` weights (see the module docstring).
    alpha, beta : (float, float), optional
        ``(a1, a2)`` and ``(b1, b2)`` of the update rule, overriding the preset's. The paper asks
        ``a1 + a2 = b1 + b2 = 1`` and ``a2, b2 > 0``; uavcov also asks ``a1, b1 >= 0``.
    samples_per_iteration : int, optional
        ``q``; ``max(2000, 200 n)`` by default; at most 10 million
        (:data:`uavcov._validate.MAX_SAMPLES`).
    tol : float, default 0.1
        Stop once the net move per iteration over the last ``window`` iterations, averaged over
        the generators, is below ``tol`` metres (``0`` runs to ``max_iterations``).
    window : int, default 5
        Iterations the net move is measured over (at most 1 million, like ``max_iterations``).
    max_iterations : int, default 300
        At most 1 million (:data:`uavcov._validate.MAX_ITERATIONS`).
    normal_weight : float, default 0
        ``lambda``, metres: with ``lambda > 0`` a sample's squared distance to a generator also
        counts ``lambda^2 |n - m|^2``, ``n`` the outward normal of the sample's triangle and
        ``m`` the generator's facing, which follows its region's mean normal by the same update
        rule as the position. Regions then gather surface that faces one way (two points on
        faces at a right angle are ``lambda sqrt(2)`` apart besides their distance), which is
        what a camera flown out along its generator's facing sees. ``0`` is the paper's CVT, bit
        for bit. The structure starts use it (docs/structures.md, "The experiment").

    Raises
    ------
    InvalidInputError
        Weights outside the paper's constraints, an unknown preset, ``q < 1``, negative ``tol``,
        ``window < 1``, ``max_iterations < 1``, or a ``normal_weight`` negative, non-finite or
        over 1e15 m.

    Examples
    --------
    >>> CVTSettings(preset="lloyd", tol=0.05).weights()
    ((0.0, 1.0), (0.0, 1.0))
    """

    preset: str = "damped"
    alpha: tuple[float, float] | None = None
    beta: tuple[float, float] | None = None
    samples_per_iteration: int | None = None
    tol: float = 0.1
    window: int = 5
    max_iterations: int = 300
    normal_weight: float = 0.0

    def __post_init__(self) -> None:
        a, b = _weights(self.preset, self.alpha, self.beta)
        if self.alpha is not None:
            object.__setattr__(self, "alpha", a)
        if self.beta is not None:
            object.__setattr__(self, "beta", b)
        if self.samples_per_iteration is not None:
            object.__setattr__(self, "samples_per_iteration", as_count(self.samples_per_iteration, "samples_per_iteration", MAX_SAMPLES))
        object.__setattr__(self, "tol", as_non_negative_float(self.tol, "tol"))
        object.__setattr__(self, "window", as_count(self.window, "window", MAX_ITERATIONS))  # the core counts it in 64 bits
        object.__setattr__(self, "max_iterations", as_count(self.max_iterations, "max_iterations", MAX_ITERATIONS))
        weight = as_non_negative_float(self.normal_weight, "normal_weight")
        if weight > _MAX_NORMAL_WEIGHT:
            raise InvalidInputError(f"normal_weight must be at most {_MAX_NORMAL_WEIGHT:.0e} m, got {weight}")
        object.__setattr__(self, "normal_weight", weight)

    def weights(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """``((a1, a2), (b1, b2))``: the preset's, or ``alpha`` and ``beta`` where given."""
        return _weights(self.preset, self.alpha, self.beta)

    def samples_for(self, n: int) -> int:
        """``q`` for ``n`` generators."""
        n = as_count(n, "n", MAX_GENERATORS)
        return default_samples_per_iteration(n) if self.samples_per_iteration is None else self.samples_per_iteration


_SETTING_NAMES = frozenset(f.name for f in fields(CVTSettings))


def cvt(
    surface: Terrain,
    n: int,
    settings: CVTSettings | None = None,
    *,
    density: np.ndarray | Callable[[np.ndarray], np.ndarray] | None = None,
    initial: Any = None,
    rng: Any = None,
    n_threads: int | None = None,
    **options: Any,
) -> CVTResult:
    """Constrained CVT of ``n`` generators on ``surface`` (probabilistic MacQueen, in Rust).

    Parameters
    ----------
    surface : Terrain
        The surface to tessellate (in the paper, S' from :func:`uavcov.terrain.approximate_surface`).
    n : int
        Number of generators, ``1 <= n <= samples_per_iteration`` and at most 10 000.
    settings : CVTSettings, optional
        The constants (weights, samples per iteration, stopping rule); ``CVTSettings()`` by
        default.
    density : (F,) array_like or callable, optional
        A density ``>= 0`` (not zero everywhere) weighting the sampling, per triangle of
        ``surface``. A callable gets the ``(F, 3)`` triangle centroids and returns ``(F,)``: the
        density is taken constant over each triangle, its value at the centroid (refine the
        mesh for a density that varies within triangles).
    initial : (n, 3) array_like, optional
        Starting generators, projected onto the surface first; by default ``n`` random points
        drawn like the samples.
    rng : None, int or numpy.random.Generator
        Randomness; converted to a u64 seed by ``seed_from_rng``. The result depends only on
        that seed, not on ``n_threads``.
    n_threads : int, optional
        Threads for the Rust side, 1 to 1024; ``None`` (the default) is rayon's default:
        ``RAYON_NUM_THREADS`` if set, else every core. Results do not depend on it.
    **options
        Fields of :class:`CVTSettings` (``preset="lloyd"``, ``tol=0.05``, ...) overriding
        ``settings``'s.

    Returns
    -------
    CVTResult

    Raises
    ------
    InvalidInputError
        ``n < 1``, ``n > q``, settings :class:`CVTSettings` refuses, an unknown option, a density
        that is negative, NaN or zero everywhere, or ``initial`` of the wrong shape.
    InvalidTypeError
        ``surface`` is not a :class:`~uavcov.engine.Terrain`, or an argument of the wrong type.

    Examples
    --------
    >>> import numpy as np, uavcov
    >>> from uavcov.placement import cvt
    >>> square = uavcov.Terrain.from_grid(np.zeros((11, 11)), spacing=10.0)
    >>> result = cvt(square, 4, rng=0)
    >>> result.generators.shape, bool(result.converged)
    ((4, 3), True)
    """
    if not isinstance(surface, Terrain):
        raise not_a_terrain(surface, "surface")
    n = as_count(n, "n", MAX_GENERATORS)
    if settings is None:
        settings = CVTSettings()
    elif not isinstance(settings, CVTSettings):
        raise InvalidTypeError(f"settings must be a CVTSettings, got {type(settings).__name__}")
    unknown = sorted(set(options) - _SETTING_NAMES)
    if unknown:
        raise InvalidInputError(f"unknown CVT option(s) {unknown}; the options are the fields of CVTSettings: {sorted(_SETTING_NAMES)}")
    if options:
        settings = replace(settings, **options)
    (a1, a2), (b1, b2) = settings.weights()
    q = settings.samples_for(n)
    if n > q:
        raise InvalidInputError(f"{n} generators need at least as many samples per iteration, got samples_per_iteration = {q}")
    tol, window, max_iterations = settings.tol, settings.window, settings.max_iterations
    weights = _density(density, surface)
    start = None
    if initial is not None:
        start = as_points(initial, "initial")
        if start.shape[0] != n:
            raise InvalidInputError(f"initial must have shape ({n}, 3), got {start.shape}")
    threads = as_n_threads(n_threads)
    seed = seed_from_rng(rng)
    generators, normals, moves, drift, energy, iterations, converged = _core.CVT.run(
        surface.core, n, q, (a1, a2), (b1, b2), tol, window, max_iterations, seed, weights, start, threads, settings.normal_weight
    )
    return CVTResult(
        generators=generators,
        normals=normals,
        moves=moves,
        drift=drift,
        energy=energy,
        iterations=int(iterations),
        converged=bool(converged),
        seed=seed,
    )
