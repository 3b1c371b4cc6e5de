"""CAO's candidates: the perturbations drawn, and the feasible one chosen (lazily, best first)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ._checks import _Feasibility
from ._draws import standard_normal
from ._settings import CAOSettings


def _draw_zeta(settings: CAOSettings, shape: tuple[int, ...], rng: np.random.Generator) -> np.ndarray:
    if settings.perturbation == "gaussian":
        # numpy's draw, bit for bit and with the same generator state after, at a third of
        # the cost (uavcov.optim)
        return standard_normal(rng, shape)
    bound = math.sqrt(3.0)
    return rng.uniform(-bound, bound, size=shape)


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
