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
runs are reproducible from ``rng`` alone. ``tests/cao_reference.py`` holds the surrogate's maths in
numpy and ``_monomials._refresh_terms_numpy`` the refresh's draws, the references the tests hold
the kernels to.

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

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from .._validate import as_generator
from ..errors import InvalidTypeError
from ._candidates import _best_feasible, _draw_zeta, _hold_inadmissible
from ._checks import _as_value, _check_common, _check_start, _Feasibility
from ._monomials import _first_terms, _refresh_terms
from ._protocol import FeasibleFn, StopRule
from ._settings import CAOSettings
from ._surrogate import _fit_and_score, _scale, _window_start
from ._trace import OptimizerTrace, _finish


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
        :func:`uavcov.limits.closest_admissible`).
    feasible : callable or None
        ``feasible(current, candidates)`` with ``current`` ``(N, d)`` and ``candidates``
        ``(M, N, d)`` returns an ``(M,)`` bool mask of admissible candidates (see
        :func:`uavcov.limits.feasibility`). ``None`` means unconstrained.
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
    rng = as_generator(rng)
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
