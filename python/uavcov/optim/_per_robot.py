"""Per-robot CAO: every UAV fits its own estimator on its own coordinates, from its marginal contribution."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from .._validate import as_generator
from ..errors import InvalidTypeError
from ._candidates import _draw_zeta, _solo_choices, _team_move
from ._checks import _as_team_and_marginals, _check_common, _check_start, _Feasibility
from ._monomials import _n_distinct_monomials, _refresh_robot_terms
from ._protocol import FeasibleFn
from ._settings import CAOSettings
from ._surrogate import _fit_and_score_robots, _scale, _window_start
from ._trace import OptimizerTrace, _finish


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
    rng = as_generator(rng)
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
