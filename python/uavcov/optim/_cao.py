"""Cognitive-based adaptive optimisation (CAO): the paper's on-line optimiser (section IV-B).

CAO maximises a function it can only *measure*: it never sees the surface, only the value of
``measure`` at the positions the team actually visits, and, through ``feasible``, whether a
candidate configuration is admissible. Each iteration it

1. measures the objective once, at the current configuration ``x_k`` (optionally with simulated
   Gaussian noise);
2. fits a surrogate ``theta^T phi(u)`` by ridge-regularised least squares on the ``L + T_h``
   measurements before this one (iterations ``l_k ... k - 1`` of the paper's eq. 4), where
   ``u = (x - x_k) / s_k`` are coordinates normalised around the current state and ``phi``
   holds ``L`` regressors: a constant, every linear term, and random 2nd- and 3rd-order
   monomials of ``u``;
3. draws ``M`` candidates ``x_k + alpha_k zeta`` (``zeta`` zero-mean, unit-variance; candidate 0
   is the unperturbed state), drops the infeasible ones, and moves to the candidate the
   surrogate rates best (the team stays when none is feasible);
4. keeps the nonlinear monomials that contributed most to the fit and redraws the others.

The step ``alpha_k = alpha_0 ((1 + A) / (k + 1 + A)) ** decay`` satisfies the stochastic
approximation conditions (``alpha_k -> 0``, ``sum alpha_k = inf``, ``sum alpha_k^2 < inf``) for
``0.5 < decay <= 1``. Coverage can fall between iterations (there is no acceptance test), so the
trace records the best configuration measured, not only the last one.

Steps 2 and 3's surrogate (the design matrix, the ridge fit, the scores of the ``M``
candidates) runs in Rust, one call per iteration (``uavcov._core.Surrogate``, nalgebra); every
random draw is ``rng``'s own stream (the Gaussian perturbations through
:func:`uavcov.optim.standard_normal` and the monomials' refresh through
``uavcov.optim._draws.redraw_monomials``, numpy's values and generator state computed in Rust), so
runs are reproducible from ``rng`` alone. ``_fit_and_score_numpy`` and ``_refresh_terms_numpy``
are the same maths and draws in numpy, the references the tests hold the kernels to.

Two optimisers share one interface (``Optimizer``): :func:`cao`, centralised over the joint
``3N`` state, and :func:`per_robot_cao`, where every UAV fits its own estimator on its own three
coordinates from its marginal contribution to the coverage.

Choices the paper leaves open, and what is done here:

* Normalisation scale ``s_k``: ``max(alpha_k, r_k)`` with ``r_k`` the root-mean-square per-
  coordinate distance of the fitting window from ``x_k``. The window points then have
  coordinates of order one, so 3rd-order monomials do not explode on old, far samples, and the
  candidates sit inside the fitted region. (On concave quadratics, 500 iterations, this ended
  20-25 % closer to the optimum than ``s_k = alpha_k``.)
* Before the window fills (fewer samples than regressors) the ridge fit is under-determined;
  it is used as is. Its linear part is then a shrunk gradient estimate in the span of the moves
  made so far, which is informative, not the near-zero minimum-norm fit of an unregularised
  pseudo-inverse. (Fitting only the linear terms until the window fills was tried: on concave
  quadratics it was no better at the end and slower over the first 50 iterations.)
* Ties: when the surrogate rates several feasible candidates equally (at iteration 0 it is a
  constant, and on a coverage plateau every measurement is equal), one of them is chosen at
  random. Taking the first one would pick "stay" and freeze the team for ever.
* Regressor strength (which monomials survive a redraw): ``|theta_j|`` times the root-mean-square
  of the monomial over the window, i.e. what the term contributes to the fit.
* Feasibility is checked lazily, best-rated candidates first (``CAOSettings.check_batch``): the
  move is the one checking all ``M`` would give, for a fraction of the surface queries.

A known limit of the method, not of this code: a UAV that leaves the sensing range of every
target (for example above ``d_max`` over flat ground) no longer changes the measurement, so
nothing pulls it back; keep ``z_max`` within reach of the ground where that matters.
"""

from __future__ import annotations

import contextlib
import functools
import math
import numbers
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any, Protocol

import numpy as np

from .. import _core
from .._validate import (
    as_float_array,
    as_non_negative_float,
    as_non_negative_int,
    as_points,
    as_positive_float,
    as_positive_int,
    read_only,
)
from ..errors import InfeasibleError, InvalidInputError, InvalidTypeError
from ._draws import redraw_monomials, standard_normal

FeasibleFn = Callable[[np.ndarray, np.ndarray], np.ndarray]

_PERTURBATIONS = ("gaussian", "uniform")
INFEASIBLE_RULES = ("drop", "hold")
"""How centralised CAO treats a candidate in which some UAVs' perturbed positions are inadmissible."""


# --------------------------------------------------------------------------------------------
# Settings and results
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CAOSettings:
    """Constants of CAO. The paper publishes none; the defaults follow ``paper-setup.md``.

    Parameters
    ----------
    n_regressors : int or None, default None
        ``L``, regressors of the centralised surrogate: 1 constant + ``dN`` linear terms (``d = 3``
        coordinates per UAV, more when camera angles are optimised) + the rest random 2nd/3rd-order
        monomials. ``None`` means ``1 + dN + max(10, N)``. Must be at least ``1 + dN``.
    history : int, default 10
        ``T_h``: iteration ``k`` fits the ``L + T_h`` measurements ``l_k ... k - 1`` (eq. 4).
    n_candidates : int, default 200
        ``M``: candidate configurations per iteration, the unperturbed state included.
    alpha0 : float, default 1.5
        Initial perturbation size ``alpha_0`` in metres (standard deviation per coordinate).
    stability : float, default 50.0
        ``A`` in ``alpha_k = alpha_0 ((1 + A) / (k + 1 + A)) ** decay``; larger keeps steps large
        for longer.
    decay : float, default 0.602
        Exponent of the step decay. ``0.5 < decay <= 1`` satisfies the paper's conditions; 0 gives
        a constant step.
    ridge : float, default 1e-3
        Ridge penalty on every coefficient but the constant, relative to the mean squared
        residual: the fit minimises ``mean(residual^2) + ridge * |theta[1:]|^2``.
    measurement_noise : float, default 0.0
        Standard deviation of Gaussian noise added to each measurement (coverage units), to
        exercise CAO's filtering. The trace keeps the noise-free values too.
    keep_fraction : float, default 0.5
        Share of the nonlinear monomials kept (the strongest) when the others are redrawn, in
        ``[0, 1]``.
    perturbation : {"gaussian", "uniform"}, default "gaussian"
        Law of ``zeta``: standard normal, or uniform on ``[-sqrt(3), sqrt(3)]`` (also unit
        variance, bounded steps).
    robot_regressors : int or None, default None
        Regressors of each per-robot estimator (:func:`per_robot_cao`), on 3 coordinates:
        ``None`` means ``1 + 3 + 6 = 10``; at most ``1 + 3 + 16 = 20`` (every distinct 2nd- and
        3rd-order monomial of three variables).
    check_batch : int or None, default 16
        Candidates are checked for feasibility best-rated first, ``check_batch`` at a time (the
        batch doubling each round), until the best feasible one is known; usually the first
        batch settles it, which spares the clearance queries of the other ``M - 16``. ``None``
        checks all ``M`` at once. The choice is the same either way (feasibility is judged per
        candidate); only ``OptimizerTrace.n_feasible`` counts fewer.
    infeasible : {"drop", "hold"}, default "drop"
        What centralised CAO does with a candidate in which some UAV's perturbed position is
        inadmissible on its own (out of the flight band or the region, in the ground, a move
        through it). ``"drop"``, the paper's eq. 6 as written: the whole candidate configuration
        is neglected. ``"hold"``: those UAVs keep their current positions within it (their
        perturbation is zeroed before the surrogate rates the candidate) and the others still
        move; the repaired candidate must then pass the team check (separation). ``feasible``
        is called once per UAV on one-UAV slices ``(1, d)`` and ``(M, 1, d)`` to judge the
        positions alone.
    """

    n_regressors: int | None = None
    history: int = 10
    n_candidates: int = 200
    alpha0: float = 1.5
    stability: float = 50.0
    decay: float = 0.602
    ridge: float = 1e-3
    measurement_noise: float = 0.0
    keep_fraction: float = 0.5
    perturbation: str = "gaussian"
    robot_regressors: int | None = None
    check_batch: int | None = 16
    infeasible: str = "drop"

    def __post_init__(self) -> None:
        def put(name: str, value: Any) -> None:
            object.__setattr__(self, name, value)

        if self.n_regressors is not None:
            put("n_regressors", as_positive_int(self.n_regressors, "n_regressors"))
        if self.robot_regressors is not None:
            value = as_positive_int(self.robot_regressors, "robot_regressors")
            if not 4 <= value <= 4 + _n_distinct_monomials(3):
                raise InvalidInputError(
                    f"robot_regressors must be in [4, {4 + _n_distinct_monomials(3)}] "
                    f"(constant, 3 linear terms, up to 16 distinct monomials), got {value}"
                )
            put("robot_regressors", value)
        if self.check_batch is not None:
            put("check_batch", as_positive_int(self.check_batch, "check_batch"))
        put("history", as_non_negative_int(self.history, "history"))
        put("n_candidates", as_positive_int(self.n_candidates, "n_candidates"))
        put("alpha0", as_positive_float(self.alpha0, "alpha0"))
        put("stability", as_non_negative_float(self.stability, "stability"))
        put("decay", as_non_negative_float(self.decay, "decay"))
        put("ridge", as_positive_float(self.ridge, "ridge"))
        put("measurement_noise", as_non_negative_float(self.measurement_noise, "measurement_noise"))
        keep = as_non_negative_float(self.keep_fraction, "keep_fraction")
        if keep > 1.0:
            raise InvalidInputError(f"keep_fraction must be in [0, 1], got {keep}")
        put("keep_fraction", keep)
        if not isinstance(self.perturbation, str):
            raise InvalidTypeError(f"perturbation must be a string, got {type(self.perturbation).__name__}")
        if self.perturbation not in _PERTURBATIONS:
            raise InvalidInputError(f"perturbation must be one of {_PERTURBATIONS}, got {self.perturbation!r}")
        if self.infeasible not in INFEASIBLE_RULES:
            raise InvalidInputError(f"infeasible must be one of {INFEASIBLE_RULES}, got {self.infeasible!r}")

    def regressors_for(self, n_uavs: int, n_coordinates: int = 3) -> int:
        """Return ``L`` for a team of ``n_uavs``, checking it against ``1 + dN`` and the monomial count.

        ``n_coordinates`` is ``d``, the decision variables per UAV: 3 for a position, more when
        a camera's heading or pitch is optimised too (:class:`uavcov.engine.Gimbal`).
        """
        n_uavs = as_positive_int(n_uavs, "number of UAVs")
        d = as_positive_int(n_coordinates, "coordinates per UAV")
        dim = d * n_uavs
        value = 1 + dim + max(10, n_uavs) if self.n_regressors is None else self.n_regressors
        if value < 1 + dim:
            raise InvalidInputError(
                f"n_regressors must be at least 1 + {d}N = {1 + dim} for N = {n_uavs} (the constant and every linear term), got {value}"
            )
        if value - 1 - dim > _n_distinct_monomials(dim):
            raise InvalidInputError(
                f"n_regressors = {value} asks for more distinct 2nd/3rd-order monomials than "
                f"{dim} coordinates have ({_n_distinct_monomials(dim)})"
            )
        return value

    def robot_regressors_value(self) -> int:
        """Return the regressor count of each per-robot estimator."""
        return 10 if self.robot_regressors is None else self.robot_regressors

    def step_size(self, k: int | np.ndarray) -> float | np.ndarray:
        """``alpha_k`` in metres for iteration ``k`` (0-based; ``alpha_0`` at ``k = 0``).

        Examples
        --------
        >>> s = CAOSettings()
        >>> s.step_size(0), round(s.step_size(100), 3)
        (1.5, 0.78)
        """
        ratio = (1.0 + self.stability) / (np.asarray(k, dtype=np.float64) + 1.0 + self.stability)
        result = self.alpha0 * ratio**self.decay
        return float(result) if np.ndim(result) == 0 else result

    def resolved(self, n_uavs: int, n_coordinates: int = 3) -> CAOSettings:
        """These settings with every ``None`` replaced by the value used for ``n_uavs`` UAVs."""
        return replace(
            self,
            n_regressors=self.regressors_for(n_uavs, n_coordinates),
            robot_regressors=self.robot_regressors_value(),
        )


@dataclass(frozen=True, eq=False)
class OptimizerTrace:
    """What one optimiser run did, iteration by iteration. Picklable.

    ``K`` is the number of iterations (moves); the run measured ``K + 1`` configurations.

    Attributes
    ----------
    kind : str
        ``"cao"``, ``"per_robot"`` or ``"escape"``.
    trajectory : ndarray, shape (K + 1, N, d)
        The decision variables at every iteration, positions in metres first (``d = 3`` unless
        :func:`cao` was given more per UAV); ``trajectory[0]`` is the start.
    values : ndarray, shape (K + 1,)
        Objective at each configuration, noise-free (what ``measure`` returned).
    measured : ndarray, shape (K + 1,)
        What the optimiser saw: ``values`` plus the simulated measurement noise.
    step_sizes : ndarray, shape (K,)
        ``alpha_k`` used at each iteration, metres.
    n_checked : ndarray, shape (K,), int64
        Candidates checked for feasibility at each iteration (all of them when
        ``settings.check_batch`` is None; see there).
    n_feasible : ndarray, shape (K,), int64
        Feasible candidates among those checked (0 means the team stayed: none was feasible).
    best_positions : ndarray, shape (N, d)
        The configuration with the highest noise-free value (the first one on ties).
    best_value : float
    best_iteration : int
    evaluations : int
        Calls of ``measure`` (``K + 1``).
    settings : CAOSettings
        The settings used, with ``None`` resolved.
    time_measure_s, time_feasibility_s, time_optimizer_s : float
        Seconds spent in ``measure``, in ``feasible``, and in the optimiser's own work (the
        names of :class:`~uavcov.MissionResult`).
    relocations : ndarray, shape (R, 3), int64
        The escapes of ``uavcov.optim._escape.escape_cao``, one row ``(uav, first, last)`` each: the
        UAV flew from its position at iteration ``first`` to the one at ``last`` through the
        configurations in between (every other UAV holding still); empty for other optimisers.
    """

    kind: str
    trajectory: np.ndarray
    values: np.ndarray
    measured: np.ndarray
    step_sizes: np.ndarray
    n_checked: np.ndarray
    n_feasible: np.ndarray
    best_positions: np.ndarray
    best_value: float
    best_iteration: int
    evaluations: int
    settings: CAOSettings
    time_measure_s: float = field(default=0.0)
    time_feasibility_s: float = field(default=0.0)
    time_optimizer_s: float = field(default=0.0)
    relocations: np.ndarray = field(default_factory=lambda: read_only(np.empty((0, 3), dtype=np.int64)))

    @property
    def n_iterations(self) -> int:
        """``K``, the number of moves."""
        return int(self.trajectory.shape[0] - 1)

    @property
    def final_positions(self) -> np.ndarray:
        """``(N, 3)`` positions after the last iteration."""
        last: np.ndarray = self.trajectory[-1]
        return last

    def best_so_far(self) -> np.ndarray:
        """``(K + 1,)`` running maximum of :attr:`values`."""
        best: np.ndarray = np.maximum.accumulate(self.values)
        return best


class Optimizer(Protocol):
    """The interface every optimiser of uavcov follows (see :func:`cao` for the arguments)."""

    def __call__(
        self,
        measure: Callable[[np.ndarray], Any],
        x0: Any,
        *,
        feasible: FeasibleFn | None,
        iterations: int,
        settings: CAOSettings = ...,
        rng: Any = None,
    ) -> OptimizerTrace: ...


# --------------------------------------------------------------------------------------------
# Regressors: monomials of normalised coordinates
# --------------------------------------------------------------------------------------------
#
# A nonlinear term is three indices into the coordinates augmented with a column of ones (index
# ``dim``), so u_i * u_j is (i, j, dim) and u_i * u_j * u_l is (i, j, l); every term is a
# product of three gathered columns, which vectorises over candidates and robots alike.


def _n_distinct_monomials(dim: int) -> int:
    """Distinct monomials of degree 2 and 3 in ``dim`` variables."""
    return math.comb(dim + 1, 2) + math.comb(dim + 2, 3)


@functools.lru_cache(maxsize=64)
def _all_monomials(dim: int) -> np.ndarray:
    """Every distinct degree-2 and degree-3 monomial, as sorted index triples (read-only)."""
    rows = []
    for i in range(dim):
        for j in range(i, dim):
            rows.append((i, j, dim))
            rows.extend((i, j, k) for k in range(j, dim))
    return read_only(np.array(rows, dtype=np.int64).reshape(-1, 3))


def _draw_monomials(count: int, dim: int, existing: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Draw ``count`` random monomials distinct from each other and from ``existing`` rows.

    Degree 2 or 3 with equal probability, variables uniform with replacement (so squares and
    cubes occur). Falls back to sampling without replacement from the full list when rejection
    would be slow (few variables).
    """
    if count == 0:
        return np.empty((0, 3), dtype=np.int64)
    # a sorted index triple as one integer, so that membership is a set of ints
    base = dim + 1
    taken = {(a * base + b) * base + c for a, b, c in existing.tolist()}
    total = _n_distinct_monomials(dim)
    if total - len(taken) < count:  # guarded by regressors_for; kept as an internal check
        raise InvalidInputError(f"cannot draw {count} new monomials of {dim} variables")
    if 4 * (len(taken) + count) > total:
        every = _all_monomials(dim)
        pool = [row for row in every.tolist() if (row[0] * base + row[1]) * base + row[2] not in taken]
        chosen = rng.choice(len(pool), size=count, replace=False)
        return np.array([pool[c] for c in chosen], dtype=np.int64)
    out: list[int] = []
    while len(out) < count:
        need = count - len(out)
        # A few dozen triples a call: plain Python on lists beats numpy's per-call cost here
        # (the draws are numpy's, so the stream is the same).
        rows = rng.integers(0, dim, size=(2 * need + 4, 3)).tolist()
        quadratic = (rng.random(2 * need + 4) < 0.5).tolist()
        for row, square in zip(rows, quadratic, strict=True):
            if square:
                row[2] = dim
            a, b, c = sorted(row)
            key = (a * base + b) * base + c
            if key not in taken:
                taken.add(key)
                out.append(key)
                if len(out) == count:
                    break
    return np.array([(key // (base * base), key // base % base, key % base) for key in out], dtype=np.int64)


def _first_terms(count: int, dim: int, rng: np.random.Generator) -> np.ndarray:
    """``_draw_monomials(count, dim, none, rng)``, in Rust for numpy's ``PCG64`` (as :func:`_refresh_terms`)."""
    none = np.empty((0, 3), dtype=np.int64)
    drawn = redraw_monomials(none, np.empty(0), 0, count, dim, rng)
    return _draw_monomials(count, dim, none, rng) if drawn is None else drawn


def _design(u: np.ndarray, terms: np.ndarray) -> np.ndarray:
    """Regressor matrix ``(n, 1 + dim + n_terms)`` of points ``u`` of shape ``(n, dim)``."""
    ones = np.ones((*u.shape[:-1], 1))
    if terms.shape[0] == 0:
        return np.concatenate([ones, u], axis=-1)
    augmented = np.concatenate([u, ones], axis=-1)
    mono = augmented[..., terms[:, 0]] * augmented[..., terms[:, 1]] * augmented[..., terms[:, 2]]
    return np.concatenate([ones, u, mono], axis=-1)


def _every_monomial3(u: np.ndarray) -> np.ndarray:
    """All 16 monomials of degree 2 and 3 of ``u`` ``(..., 3)``, in ``_all_monomials(3)`` order."""
    x, y, z = u[..., 0], u[..., 1], u[..., 2]
    xx, yy, zz, xy, xz, yz = x * x, y * y, z * z, x * y, x * z, y * z
    cols = [xx, xx * x, xy * x, xz * x, xy, xy * y, xy * z, xz, xz * z,
            yy, yy * y, yz * y, yz, yz * z, zz, zz * z]  # fmt: skip
    return np.stack(cols, axis=-1)


def _robot_design(u: np.ndarray, selected: np.ndarray) -> np.ndarray:
    """Per-robot regressors ``(N, n, 20)`` of ``u`` ``(N, n, 3)``: constant, linear, 16 monomials.

    ``selected`` ``(N, 16)`` bool marks each robot's active monomials; the other columns are
    zero. A zero column changes nothing in a ridge fit (its coefficient is exactly 0), so this
    is the fit on the active columns only, without a per-robot gather.
    """
    ones = np.ones((*u.shape[:-1], 1))
    mono = _every_monomial3(u) * selected[:, None, :]
    return np.concatenate([ones, u, mono], axis=-1)


def _refresh_robot_terms(selected: np.ndarray, strength: np.ndarray, keep_fraction: float, rng: np.random.Generator) -> np.ndarray:
    """:func:`_refresh_terms` for every robot at once, on ``(N, 16)`` masks of active monomials.

    ``strength`` is ``(N, 16)`` (zero for inactive monomials).
    """
    n_terms = int(selected[0].sum())
    n_keep = math.ceil(keep_fraction * n_terms)
    if n_keep >= n_terms:
        return selected
    # strongest active first; inactive ones sort last whatever their (zero) strength
    rank_key = np.where(selected, -strength, np.inf)
    order = np.argsort(rank_key, axis=1, kind="stable")
    fresh = np.zeros_like(selected)
    np.put_along_axis(fresh, order[:, :n_keep], True, axis=1)
    keys = rng.random(selected.shape)
    keys[fresh] = np.inf  # never redraw a kept one
    redraw = np.argsort(keys, axis=1, kind="stable")[:, : n_terms - n_keep]
    np.put_along_axis(fresh, redraw, True, axis=1)
    return fresh


def _ridge(phi: np.ndarray, y: np.ndarray, ridge: float) -> np.ndarray:
    """Coefficients minimising ``mean((phi theta - y)^2) + ridge |theta[1:]|^2``.

    ``phi`` is ``(..., W, L)`` and ``y`` ``(..., W)``; column 0 is the constant, left unpenalised.
    ``y`` is centred first so the solve only carries the variations (better conditioned).
    """
    n_samples = phi.shape[-2]
    if n_samples == 0:  # nothing measured yet: a flat surrogate (every candidate ties)
        return np.zeros(phi.shape[:-2] + phi.shape[-1:])
    mean = y.mean(axis=-1, keepdims=True)
    yc = y - mean
    gram = np.swapaxes(phi, -1, -2) @ phi
    rhs = np.swapaxes(phi, -1, -2) @ yc[..., None]
    penalty = np.full(phi.shape[-1], ridge * n_samples)
    penalty[0] = 0.0
    gram = gram + np.diag(penalty)
    # The constant column is all ones and every other column is penalised, so the system is
    # positive definite; the pseudo-inverse only guards against round-off on extreme inputs.
    try:
        theta = np.linalg.solve(gram, rhs)[..., 0]
    except np.linalg.LinAlgError:
        theta = (np.linalg.pinv(gram) @ rhs)[..., 0]
    theta[..., 0] += mean[..., 0]
    return theta


def _strength(phi: np.ndarray, theta: np.ndarray, first: int) -> np.ndarray:
    """Contribution of nonlinear regressors ``first:``: ``|theta_j| * rms(phi[:, j])``."""
    rms = np.sqrt(np.mean(phi[..., first:] ** 2, axis=-2))
    strength: np.ndarray = np.abs(theta[..., first:]) * rms
    return strength


def _refresh_terms(terms: np.ndarray, strength: np.ndarray, keep_fraction: float, dim: int, rng: np.random.Generator) -> np.ndarray:
    """Keep the strongest monomials (ties by position) and redraw the others.

    :func:`_refresh_terms_numpy`'s terms and draws, made in one Rust call when ``rng`` is
    numpy's ``PCG64`` (``uavcov.optim._draws.redraw_monomials``), else by that reference.
    """
    n_terms = terms.shape[0]
    n_keep = math.ceil(keep_fraction * n_terms)
    if n_keep >= n_terms:
        return terms
    drawn = redraw_monomials(terms, strength, n_keep, n_terms - n_keep, dim, rng)
    return _refresh_terms_numpy(terms, strength, keep_fraction, dim, rng) if drawn is None else drawn


def _refresh_terms_numpy(terms: np.ndarray, strength: np.ndarray, keep_fraction: float, dim: int, rng: np.random.Generator) -> np.ndarray:
    """:func:`_refresh_terms` with numpy's draws: the reference the kernel is held to."""
    n_terms = terms.shape[0]
    n_keep = math.ceil(keep_fraction * n_terms)
    if n_keep >= n_terms:
        return terms
    order = np.argsort(-strength, kind="stable")
    kept = terms[np.sort(order[:n_keep])]
    fresh = _draw_monomials(n_terms - n_keep, dim, kept, rng)
    return np.concatenate([kept, fresh], axis=0)


def _window_start(k: int, n_window: int) -> int:
    """``l_k = max(0, k - L - T_h)`` of the paper's eq. 4: iteration ``k`` fits ``l_k ... k - 1``.

    The window holds the ``L + T_h`` measurements before ``x_k``'s own (``n_window = L + T_h``),
    so the move from ``x_k`` is chosen on what was measured before reaching it; at ``k = 0`` it
    is empty and the surrogate is flat.
    """
    return max(0, k - n_window)


def _scale(window: np.ndarray, centre: np.ndarray, alpha: float) -> np.ndarray:
    """Normalisation scale(s) ``max(alpha, rms distance per coordinate)`` over the window.

    ``window`` is ``(W, ..., d)`` and ``centre`` ``(..., d)``; one scale per leading estimator.
    """
    if window.shape[0] == 0:
        return np.broadcast_to(np.float64(alpha), centre.shape[:-1]).copy()
    if window.ndim == 2:  # one estimator: np.mean's own reduction, without its dispatch (same bits)
        squares = window - centre
        squares *= squares
        spread = np.sqrt(np.add.reduce(squares, axis=None) / squares.size)
    else:
        spread = np.sqrt(np.mean((window - centre) ** 2, axis=(0, -1)))
    scale: np.ndarray = np.maximum(alpha, spread)
    return scale


# --------------------------------------------------------------------------------------------
# The surrogate's kernels: Rust (one call per iteration), and their numpy references
# --------------------------------------------------------------------------------------------


def _fit_and_score(
    window: np.ndarray, values: np.ndarray, terms: np.ndarray, candidates: np.ndarray, ridge: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fit the centralised surrogate and score the candidates: ``(theta, scores, strength)``.

    ``window`` ``(W, d)`` and ``candidates`` ``(M, d)`` are normalised coordinates, ``values``
    ``(W,)`` what was measured at the window's points, ``terms`` ``(T, 3)`` the monomials.
    ``strength`` ``(T,)`` is :func:`_strength` of the monomials. The Rust kernel
    (``uavcov._core.Surrogate.fit``, nalgebra); :func:`_fit_and_score_numpy` is its reference.
    """
    return _core.Surrogate.fit(window, values, terms, candidates, ridge)


def _fit_and_score_robots(
    window: np.ndarray, values: np.ndarray, active: np.ndarray, candidates: np.ndarray, ridge: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every robot's surrogate at once: ``window`` ``(N, W, 3)``, ``values`` ``(N, W)``,
    ``active`` ``(N, 16)`` bool (each robot's monomials), ``candidates`` ``(N, M, 3)`` ->
    ``theta`` ``(N, 20)``, ``scores`` ``(N, M)``, ``strength`` ``(N, 16)``. Rust kernel;
    :func:`_fit_and_score_robots_numpy` is its reference.
    """
    return _core.Surrogate.fit_robots(window, values, _all_monomials(3), active, candidates, ridge)


def _fit_and_score_numpy(
    window: np.ndarray, values: np.ndarray, terms: np.ndarray, candidates: np.ndarray, ridge: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """numpy reference of :func:`_fit_and_score` (same maths, LAPACK's solve)."""
    dim = window.shape[-1]
    with _one_blas_thread():
        phi = _design(window, terms)
        theta = _ridge(phi, values, ridge)
        scores = _design(candidates, terms) @ theta
    strength = _strength(phi, theta, 1 + dim) if window.shape[0] else np.zeros(terms.shape[0])
    return theta, scores, strength


def _fit_and_score_robots_numpy(
    window: np.ndarray, values: np.ndarray, active: np.ndarray, candidates: np.ndarray, ridge: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """numpy reference of :func:`_fit_and_score_robots`."""
    with _one_blas_thread():
        phi = _robot_design(window, active)  # (N, W, 20)
        theta = _ridge(phi, values, ridge)  # (N, 20)
        scores = (  # theta . phi(candidates) without building phi for the M candidates
            theta[:, :1]
            + np.einsum("nmk,nk->nm", candidates, theta[:, 1:4])
            + np.einsum("nmj,nj->nm", _every_monomial3(candidates), theta[:, 4:] * active)
        )
    strength = _strength(phi, theta, 4) if window.shape[1] else np.zeros(active.shape)
    return theta, scores, strength


# --------------------------------------------------------------------------------------------
# Shared plumbing
# --------------------------------------------------------------------------------------------


@functools.lru_cache(maxsize=1)
def _blas_controller() -> Any:
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:  # declared as a dependency; without it CAO is only slower
        return None
    return ThreadpoolController()


def _one_blas_thread() -> contextlib.AbstractContextManager[Any]:
    """Run CAO's small matrix products on one BLAS thread.

    The fit works on matrices of about 100 x 100: a multi-threaded BLAS spends longer waking
    its threads than computing, and far longer when the cores are busy with the coverage
    engine or other runs (measured: a 91 x 81 Gram matrix took 0.29 ms with 2 threads on a
    loaded 2-core machine, 0.05 ms with one). Only CAO's own work is limited, never ``measure``.
    """
    controller = _blas_controller()
    if controller is None:
        return contextlib.nullcontext()
    limited: contextlib.AbstractContextManager[Any] = controller.limit(limits=1, user_api="blas")
    return limited


def _check_common(x0: Any, feasible: Any, iterations: Any, settings: Any, *, positions_only: bool = True) -> tuple[np.ndarray, int]:
    if not isinstance(settings, CAOSettings):
        raise InvalidTypeError(f"settings must be a CAOSettings, got {type(settings).__name__}")
    if positions_only:
        x0 = as_points(x0, "x0")
    else:
        x0 = as_float_array(x0, "x0")
        if x0.ndim != 2 or x0.shape[0] == 0 or x0.shape[1] < 3:
            raise InvalidInputError(f"x0 must have shape (N, d) with N >= 1 and d >= 3 (a position, then any angles), got {x0.shape}")
    iterations = as_non_negative_int(iterations, "iterations")
    if feasible is not None and not callable(feasible):
        raise InvalidTypeError(f"feasible must be callable or None, got {type(feasible).__name__}")
    return x0, iterations


def _draw_zeta(settings: CAOSettings, shape: tuple[int, ...], rng: np.random.Generator) -> np.ndarray:
    if settings.perturbation == "gaussian":
        # numpy's draw, bit for bit and with the same generator state after, at a third of
        # the cost (uavcov.optim)
        return standard_normal(rng, shape)
    bound = math.sqrt(3.0)
    return rng.uniform(-bound, bound, size=shape)


def _as_value(raw: Any, what: str, k: int) -> float:
    if isinstance(raw, bool) or not isinstance(raw, (numbers.Real, np.floating, np.integer)):
        if isinstance(raw, np.ndarray) and raw.ndim == 0:
            raw = raw.item()
        else:
            raise InvalidTypeError(f"{what} must return a real number, got {type(raw).__name__} at iteration {k}")
    value = float(raw)
    if not math.isfinite(value):
        raise InvalidInputError(f"{what} returned {value} at iteration {k}")
    return value


class _Feasibility:
    """Calls the user's feasibility test, checks what it returns and times it."""

    def __init__(self, feasible: FeasibleFn | None) -> None:
        self.feasible = feasible
        self.seconds = 0.0

    def __call__(self, current: np.ndarray, candidates: np.ndarray) -> np.ndarray:
        if self.feasible is None:
            return np.ones(candidates.shape[0], dtype=bool)
        start = time.perf_counter()
        mask = self.feasible(current.copy(), candidates.copy())
        self.seconds += time.perf_counter() - start
        mask = np.asarray(mask)
        if mask.shape != (candidates.shape[0],) or mask.dtype != np.bool_:
            raise InvalidInputError(
                f"feasible must return a ({candidates.shape[0]},) bool array, got shape {mask.shape} dtype {mask.dtype}"
            )
        return mask


def _hold_inadmissible(zeta: np.ndarray, alpha: float, current: np.ndarray, check: _Feasibility) -> np.ndarray:
    """``zeta`` ``(M, N * d)`` with the perturbation of every UAV whose perturbed position is
    inadmissible on its own set to zero (that UAV holds its position in that candidate)."""
    n_cand = zeta.shape[0]
    n_uavs, n_coords = current.shape
    steps = zeta.reshape(n_cand, n_uavs, n_coords)
    held = steps.copy()
    for i in range(n_uavs):
        moved = np.flatnonzero((steps[:, i] != 0.0).any(axis=1))
        if moved.size:
            ends = current[i] + alpha * steps[moved, i]
            alone = check(current[i : i + 1], ends[:, None, :])
            held[moved[~alone], i] = 0.0
    return held.reshape(n_cand, n_uavs * n_coords)


def _check_start(check: _Feasibility, x0: np.ndarray) -> None:
    if not check(x0, x0[None])[0]:
        raise InfeasibleError("the start configuration is infeasible; move it first with uavcov.placement.closest_admissible")


def _pick_best(score: np.ndarray, allowed: np.ndarray, rng: np.random.Generator) -> int:
    """Index of the best allowed score; near-ties (1e-12 relative) are broken at random."""
    idx = np.flatnonzero(allowed)
    allowed_scores = score[idx]
    top = float(allowed_scores.max())
    tol = 1e-12 * max(1.0, abs(top))
    ties = idx[allowed_scores >= top - tol]
    return int(ties[0] if ties.size == 1 else ties[rng.integers(ties.size)])


def _best_feasible(
    score: np.ndarray,
    candidates: Callable[[Any], np.ndarray],
    current: np.ndarray,
    check: _Feasibility,
    batch: int | None,
    rng: np.random.Generator,
) -> tuple[int | None, int, int]:
    """The candidate :func:`_pick_best` would choose among the feasible ones, checking lazily.

    Candidates are checked best score first, in doubling batches, until every candidate that
    could tie with the best feasible one has been judged; the result, and the random draw for
    ties, are then those of checking all of them. ``candidates(idx)`` gives the configurations
    ``(len(idx), N, d)`` of the candidates ``idx`` (an index array or a slice), so only those
    checked are made. Returns ``(index or None, checked, feasible)``.
    """
    n = score.shape[0]
    if batch is None or batch >= n:
        mask = check(current, candidates(slice(None)))
        return (_pick_best(score, mask, rng) if mask.any() else None), n, int(mask.sum())
    order = np.argsort(-score, kind="stable")
    ranked = score[order]  # best first: a batch's best feasible score is its first feasible one's
    allowed = np.zeros(n, dtype=bool)
    checked = 0
    top = None
    while checked < n:
        idx = order[checked : checked + batch]
        ok = check(current, candidates(idx))
        allowed[idx] = ok
        if top is None:
            first = int(ok.argmax())
            if ok[first]:
                top = float(ranked[checked + first])
        checked += idx.size
        batch *= 2
        if top is not None and (checked >= n or ranked[checked] < top - 1e-12 * max(1.0, abs(top))):
            break
    if top is None:
        return None, checked, 0
    return _pick_best(score, allowed, rng), checked, int(allowed.sum())


_SOLO_POINTS = 1 << 20
"""Most UAV positions one call of :func:`_solo_choices` asks the feasibility test about."""


def _solo_choices(moves: np.ndarray, current: np.ndarray, check: _Feasibility, batch: int | None) -> tuple[np.ndarray, int, int]:
    """Each UAV's best-ranked move that is admissible when it alone moves.

    ``moves`` ``(N, M, 3)`` holds every UAV's perturbed positions, best-ranked first, its
    unperturbed position among them (admissible, since ``current`` is). Ranks are checked in
    doubling batches for the UAVs still undecided, each as the configuration ``current`` with that
    UAV moved. Returns the rank per UAV ``(N,)`` (-1 where none is admissible: that UAV stays),
    and the configurations checked and found admissible.
    """
    n_uavs, n_moves = moves.shape[:2]
    rank = np.zeros(n_uavs, dtype=np.int64)
    pending = np.arange(n_uavs)
    start = checked = found = 0
    width = n_moves if batch is None else batch
    while pending.size and start < n_moves:
        width = max(1, min(width, _SOLO_POINTS // (pending.size * n_uavs)))
        ranks = np.arange(start, min(n_moves, start + width))
        configs = np.broadcast_to(current, (pending.size, ranks.size, n_uavs, 3)).copy()
        configs[np.arange(pending.size)[:, None], np.arange(ranks.size)[None, :], pending[:, None]] = moves[
            pending[:, None], ranks[None, :]
        ]
        ok = check(current, configs.reshape(-1, n_uavs, 3)).reshape(pending.size, ranks.size)
        checked += ok.size
        found += int(ok.sum())
        decided = ok.any(axis=1)
        rank[pending[decided]] = ranks[np.argmax(ok[decided], axis=1)]
        pending = pending[~decided]
        start += ranks.size
        width *= 2
    rank[pending] = -1  # none admissible, not even staying (a test that refuses everything): it stays
    return rank, checked, found


def _team_move(chosen: np.ndarray, gain: np.ndarray, current: np.ndarray, check: _Feasibility) -> tuple[np.ndarray, int, int]:
    """The team on every UAV's own move ``chosen`` ``(N, 3)``, or, when those clash, with the
    movers of least predicted ``gain`` ``(N,)`` held back: a quarter of them, a half, three
    quarters, all. One feasibility call; returns the new positions, configurations checked and
    found admissible.
    """
    movers = np.flatnonzero((chosen != current).any(axis=1))
    if movers.size == 0:
        return current.copy(), 0, 0
    movers = movers[np.argsort(gain[movers], kind="stable")]  # least promising first
    teams = np.empty((5, *current.shape))
    for t, share in enumerate((0.0, 0.25, 0.5, 0.75, 1.0)):
        teams[t] = chosen
        held = movers[: math.ceil(share * movers.size)]
        teams[t, held] = current[held]
    ok = check(current, teams)
    first = int(np.argmax(ok)) if ok.any() else teams.shape[0] - 1
    return teams[first].copy(), int(ok.size), int(ok.sum())


def _finish(
    kind: str,
    traj: np.ndarray,
    values: np.ndarray,
    measured: np.ndarray,
    steps: np.ndarray,
    n_checked: np.ndarray,
    n_feasible: np.ndarray,
    settings: CAOSettings,
    t_measure: float,
    t_feasible: float,
    t_total: float,
) -> OptimizerTrace:
    best = int(np.argmax(values))
    return OptimizerTrace(
        kind=kind,
        trajectory=read_only(traj),
        values=read_only(values),
        measured=read_only(measured),
        step_sizes=read_only(steps),
        n_checked=read_only(n_checked),
        n_feasible=read_only(n_feasible),
        best_positions=read_only(traj[best].copy()),
        best_value=float(values[best]),
        best_iteration=best,
        evaluations=int(values.shape[0]),
        settings=settings,
        time_measure_s=t_measure,
        time_feasibility_s=t_feasible,
        time_optimizer_s=max(0.0, t_total - t_measure - t_feasible),
    )


# --------------------------------------------------------------------------------------------
# Centralised CAO
# --------------------------------------------------------------------------------------------


def cao(
    measure: Callable[[np.ndarray], float],
    x0: Any,
    *,
    feasible: FeasibleFn | None,
    iterations: int,
    settings: CAOSettings = CAOSettings(),
    rng: Any = None,
) -> OptimizerTrace:
    """Maximise ``measure`` over the joint ``dN`` decision variables with centralised CAO.

    Parameters
    ----------
    measure : callable
        ``measure(x)`` with ``x`` of shape ``(N, d)`` returns the objective (a finite float, e.g.
        the coverage share). Called exactly once per visited configuration.
    x0 : array_like, shape (N, d), d >= 3
        Start: each UAV's position in metres, then any further variables (``d = 3`` for
        positions alone; a mission that optimises camera angles appends them, scaled so that one
        unit of the step is ``Gimbal.alpha0_deg / alpha0`` degrees, :class:`uavcov.Gimbal`). Every
        coordinate is perturbed by the same ``alpha_k`` (eq. 5). Must be feasible (see
        :func:`uavcov.placement.closest_admissible`).
    feasible : callable or None
        ``feasible(current, candidates)`` with ``current`` ``(N, d)`` and ``candidates``
        ``(M, N, d)`` returns an ``(M,)`` bool mask of admissible candidates (see
        :func:`uavcov.placement.feasibility`). ``None`` means unconstrained.
    iterations : int
        ``K >= 0`` moves; the run measures ``K + 1`` configurations.
    settings : CAOSettings
    rng : None, int or numpy.random.Generator
        Source of every random draw (candidates, monomials, noise, ties).

    Returns
    -------
    OptimizerTrace

    Raises
    ------
    InvalidInputError, InvalidTypeError
        Bad shapes, non-finite values, wrong types, or a ``measure``/``feasible`` that returns
        something else than documented.
    InfeasibleError
        The start is not feasible.

    Examples
    --------
    One UAV climbing a concave quadratic whose top is at (10, 20, 30), without constraints:

    >>> import numpy as np
    >>> top = np.array([[10.0, 20.0, 30.0]])
    >>> trace = cao(lambda x: -float(np.sum((x - top) ** 2)), np.zeros((1, 3)), feasible=None, iterations=200, rng=0)
    >>> trace.evaluations, bool(np.abs(trace.best_positions - top).max() < 0.1)  # within 10 cm of the top
    (201, True)
    """
    return _cao_run(measure, x0, feasible=feasible, iterations=iterations, settings=settings, rng=rng)


StopRule = Callable[[np.ndarray], bool]
"""``stop(measured)``: called after each measurement with the values measured so far ``(k + 1,)``."""


def _cao_run(
    measure: Callable[[np.ndarray], float],
    x0: Any,
    *,
    feasible: FeasibleFn | None,
    iterations: int,
    settings: CAOSettings,
    rng: Any,
    stop: StopRule | None = None,
) -> OptimizerTrace:
    """:func:`cao`, ended early (the trace then shorter) as soon as ``stop`` says so.

    ``stop`` sees only what the optimiser measured (with its simulated noise); it runs after the
    measurement of iteration ``k`` and before any draw of that iteration, so a run that is never
    stopped makes the same draws and the same trace as :func:`cao`.
    """
    x0, n_iter = _check_common(x0, feasible, iterations, settings, positions_only=False)
    if not callable(measure):
        raise InvalidTypeError(f"measure must be callable, got {type(measure).__name__}")
    n_uavs, n_coords = x0.shape
    dim = n_coords * n_uavs
    settings = settings.resolved(n_uavs, n_coords)
    n_reg = int(settings.n_regressors)  # type: ignore[arg-type]
    n_terms = n_reg - 1 - dim
    n_window = n_reg + settings.history
    n_cand = settings.n_candidates
    rng = np.random.default_rng(rng)
    check = _Feasibility(feasible)
    t_start = time.perf_counter()
    _check_start(check, x0)

    traj = np.empty((n_iter + 1, dim))
    values = np.empty(n_iter + 1)
    measured = np.empty(n_iter + 1)
    steps = settings.step_size(np.arange(n_iter)) if n_iter else np.empty(0)
    steps = np.asarray(steps, dtype=np.float64).reshape(n_iter)
    n_checked = np.zeros(n_iter, dtype=np.int64)
    n_feasible = np.zeros(n_iter, dtype=np.int64)
    terms = _first_terms(n_terms, dim, rng)
    t_measure = 0.0

    x = x0.reshape(dim).copy()
    for k in range(n_iter + 1):
        traj[k] = x
        t0 = time.perf_counter()
        value = _as_value(measure(x.reshape(n_uavs, n_coords).copy()), "measure", k)
        t_measure += time.perf_counter() - t0
        values[k] = value
        measured[k] = value + settings.measurement_noise * rng.standard_normal() if settings.measurement_noise else value
        if k == n_iter:
            break
        if stop is not None and stop(measured[: k + 1]):
            n_iter = k
            break

        alpha = float(steps[k])
        lo = _window_start(k, n_window)
        window = traj[lo:k]
        scale = float(_scale(window, x, alpha))
        zeta = _draw_zeta(settings, (n_cand, dim), rng)
        zeta[0] = 0.0
        if settings.infeasible == "hold":
            zeta = _hold_inadmissible(zeta, alpha, x.reshape(n_uavs, n_coords), check)
        _, predicted, strength = _fit_and_score((window - x) / scale, measured[lo:k], terms, zeta * (alpha / scale), settings.ridge)

        def candidates(idx: Any, x: np.ndarray = x, alpha: float = alpha, zeta: np.ndarray = zeta) -> np.ndarray:
            moved: np.ndarray = (x + alpha * zeta[idx]).reshape(-1, n_uavs, n_coords)
            return moved

        choice, n_checked[k], n_feasible[k] = _best_feasible(
            predicted, candidates, x.reshape(n_uavs, n_coords), check, settings.check_batch, rng
        )
        if choice is not None:
            x = x + alpha * zeta[choice]
        if n_terms and k > lo:
            terms = _refresh_terms(terms, strength, settings.keep_fraction, dim, rng)

    t_total = time.perf_counter() - t_start
    return _finish(
        "cao",
        traj[: n_iter + 1].reshape(n_iter + 1, n_uavs, n_coords),
        values[: n_iter + 1],
        measured[: n_iter + 1],
        steps[:n_iter],
        n_checked[:n_iter],
        n_feasible[:n_iter],
        settings,
        t_measure,
        check.seconds,
        t_total,
    )


# --------------------------------------------------------------------------------------------
# Per-robot CAO
# --------------------------------------------------------------------------------------------


def _as_team_and_marginals(raw: Any, n_uavs: int, k: int) -> tuple[float, np.ndarray]:
    if not isinstance(raw, tuple) or len(raw) != 2:
        raise InvalidTypeError(
            f"per-robot measure must return (team value, marginals of shape ({n_uavs},)), got {type(raw).__name__} at iteration {k}"
        )
    team = _as_value(raw[0], "measure (team value)", k)
    marginals = np.asarray(raw[1], dtype=np.float64) if not isinstance(raw[1], (str, bytes)) else None
    if marginals is None or marginals.shape != (n_uavs,) or not np.isfinite(marginals).all():
        raise InvalidInputError(f"per-robot measure must return finite marginals of shape ({n_uavs},) at iteration {k}")
    return team, marginals


def per_robot_cao(
    measure: Callable[[np.ndarray], tuple[float, np.ndarray]],
    x0: Any,
    *,
    feasible: FeasibleFn | None,
    iterations: int,
    settings: CAOSettings = CAOSettings(),
    rng: Any = None,
) -> OptimizerTrace:
    """Per-robot CAO: every UAV fits its own estimator on its own 3 coordinates.

    UAV ``i`` regresses its marginal contribution ``m_i`` (for coverage: what the team loses
    without it) on its own normalised position. The gradient of ``m_i`` in ``x_i`` equals that of
    the team objective, since the team without ``i`` does not depend on ``x_i``, so each UAV climbs
    the team objective using only its own estimate. The others' moves act on ``m_i`` as noise.

    Selection: each UAV ranks its ``M`` perturbations (the unperturbed one included) by its own
    surrogate and takes the best-ranked one that is admissible when it alone moves, the others
    where they are (:func:`_solo_choices`); the team then makes all these moves at once, or,
    when they clash (the safety distance couples the UAVs that move), holds back its least
    promising movers a quarter at a time (:func:`_team_move`). So each UAV's constraints bind
    only its own move: a team of 100 keeps moving where asking all of them to find admissible
    perturbations of the same rank would leave it in place.

    Parameters
    ----------
    measure : callable
        ``measure(x)`` with ``x`` of shape ``(N, 3)`` returns ``(team_value, marginals)``: the
        team objective (float, recorded in the trace) and each UAV's marginal contribution
        ``(N,)``. One call per visited configuration.
    x0, feasible, iterations, settings, rng
        As in :func:`cao`; ``settings.robot_regressors`` sets each estimator's size, and the
        window is ``robot_regressors + history`` measurements. ``settings.measurement_noise``
        is added, independently, to the team value and to each marginal.

    Returns
    -------
    OptimizerTrace
        ``values`` holds the team values.
    """
    x0, n_iter = _check_common(x0, feasible, iterations, settings)
    if not callable(measure):
        raise InvalidTypeError(f"measure must be callable, got {type(measure).__name__}")
    n_uavs = x0.shape[0]
    settings = settings.resolved(n_uavs)
    n_reg = settings.robot_regressors_value()
    n_terms = n_reg - 4
    n_window = n_reg + settings.history
    n_cand = settings.n_candidates
    rng = np.random.default_rng(rng)
    check = _Feasibility(feasible)
    t_start = time.perf_counter()
    _check_start(check, x0)

    traj = np.empty((n_iter + 1, n_uavs, 3))
    values = np.empty(n_iter + 1)
    measured = np.empty(n_iter + 1)
    marg = np.empty((n_iter + 1, n_uavs))
    steps = np.asarray(settings.step_size(np.arange(n_iter)) if n_iter else np.empty(0), dtype=np.float64)
    steps = steps.reshape(n_iter)
    n_checked = np.zeros(n_iter, dtype=np.int64)
    n_feasible = np.zeros(n_iter, dtype=np.int64)
    terms = np.zeros((n_uavs, _n_distinct_monomials(3)), dtype=bool)  # active monomials per UAV
    np.put_along_axis(terms, np.argsort(rng.random(terms.shape), axis=1)[:, :n_terms], True, axis=1)
    t_measure = 0.0
    robots = np.arange(n_uavs)

    x = x0.copy()
    for k in range(n_iter + 1):
        traj[k] = x
        t0 = time.perf_counter()
        team, marginals = _as_team_and_marginals(measure(x.copy()), n_uavs, k)
        t_measure += time.perf_counter() - t0
        values[k] = team
        noise = settings.measurement_noise
        measured[k] = team + noise * rng.standard_normal() if noise else team
        marg[k] = marginals + noise * rng.standard_normal(n_uavs) if noise else marginals
        if k == n_iter:
            break

        alpha = float(steps[k])
        lo = _window_start(k, n_window)
        window = traj[lo:k]  # (W, N, 3)
        scale = _scale(window, x, alpha)  # (N,)
        u = np.swapaxes(window - x, 0, 1) / scale[:, None, None]  # (N, W, 3)
        zeta = _draw_zeta(settings, (n_cand, n_uavs, 3), rng)
        zeta[0] = 0.0
        uc = np.swapaxes(zeta, 0, 1) * (alpha / scale)[:, None, None]  # (N, M, 3)
        _, score, strength = _fit_and_score_robots(u, marg[lo:k].T, terms, uc, settings.ridge)  # score (N, M)
        # rank each robot's perturbations, best first; a flat estimator (all scores equal, as
        # at iteration 0) ranks them at random, or "stay" would win every tie
        order = np.argsort(-score, axis=1, kind="stable")  # (N, M)
        top = np.abs(score).max(axis=1)
        flat = score.max(axis=1) - score.min(axis=1) <= 1e-12 * np.maximum(1.0, top)
        if flat.any():
            order[flat] = rng.permuted(np.tile(np.arange(n_cand), (int(flat.sum()), 1)), axis=1)
        moves = x[:, None] + alpha * zeta[order.T, robots[None, :]].swapaxes(0, 1)  # (N, M, 3), best first
        rank, solo_checked, solo_feasible = _solo_choices(moves, x, check, settings.check_batch)
        stays = rank < 0
        rank[stays] = 0
        picked = order[robots, rank]  # the perturbation each UAV takes (0: the unperturbed one)
        picked[stays] = 0
        chosen = np.where(stays[:, None], x, moves[robots, rank])
        x, team_checked, team_feasible = _team_move(chosen, score[robots, picked] - score[:, 0], x, check)
        n_checked[k], n_feasible[k] = solo_checked + team_checked, solo_feasible + team_feasible
        if n_terms and k > lo:
            terms = _refresh_robot_terms(terms, strength, settings.keep_fraction, rng)

    t_total = time.perf_counter() - t_start
    return _finish("per_robot", traj, values, measured, steps, n_checked, n_feasible, settings, t_measure, check.seconds, t_total)
