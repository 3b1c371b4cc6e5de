"""Two cheap steps before the integer program: a better incumbent by swaps, and dominated candidates out.

Greedy's placement is a good start but seldom a local optimum of the swap neighbourhood: replacing
one pick by the candidate that gains most once it is gone (best improvement, kept ``d_safe`` from
the other picks) raises it further. A better incumbent makes the LP dual point exclude more
candidates (:func:`uavcov.cover._exact._survivors`) and narrows the gap when the solver stops.

A candidate ``a`` is dominated by ``b`` when ``b`` sees every target ``a`` sees (and more, or the
same with a lower index: a strict order, so each dominated candidate has an undominated one above
it). Without separation every placement holding ``a`` is matched by one holding its undominated
dominator (or, when that one is already in, any other candidate: coverage only grows with more
picks), so the dominated candidates leave the program without changing its optimum. With
separation the swap may break it, so this step is only taken when no two candidates conflict.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

# A swap must gain more than this share (float64 sums of shares: far above their rounding).
_IMPROVEMENT = 1e-12
# Multiply-adds the dominance test may take (candidates^2 x target groups): a few seconds at most.
_DOMINANCE_WORK = 4e10


def swap_search(columns: Any, weights: np.ndarray, picks: np.ndarray, conflicts: object | None, deadline: float) -> np.ndarray:
    """Best-improvement swaps of one pick for one candidate from ``picks`` until none gains (or ``deadline``).

    Parameters
    ----------
    columns : (C, G) float64 ndarray or scipy sparse matrix
        1 where a candidate sees a target group (sparse: the products skip the zeros).
    weights : (G,) float64 ndarray
        Each group's share.
    picks : (k,) int64 ndarray
        The start (distinct, mutually separated).
    conflicts : (C, C) scipy sparse matrix or None
        1 for a pair closer than the separation (symmetric); ``None``: no pair conflicts.
    deadline : float
        ``time.perf_counter()`` value after which no further swap is tried.

    Returns
    -------
    (k,) int64 ndarray
        The picks after the last improving swap, increasing; never covering less than ``picks``.
    """
    from scipy.sparse import csr_matrix, issparse

    matrix: Any = columns.tocsr() if issparse(columns) else csr_matrix(columns, dtype=np.float64)
    picks = np.array(picks, dtype=np.int64)

    def row(candidate: int) -> np.ndarray:
        return np.asarray(matrix[[candidate]].todense()).ravel()

    count = np.asarray(matrix[picks].sum(axis=0)).ravel()
    while picks.size and time.perf_counter() < deadline:
        taken = np.zeros(matrix.shape[0], dtype=bool)
        taken[picks] = True
        near = np.zeros(matrix.shape[0]) if conflicts is None else np.asarray(conflicts[:, picks].sum(axis=1)).ravel()  # type: ignore[index]
        best = (_IMPROVEMENT, -1, -1)
        for slot, pick in enumerate(picks):
            sees = row(pick)
            after = count - sees
            uncovered = after == 0.0
            loss = float(weights[uncovered & (sees > 0.0)].sum())
            gains = np.asarray(matrix @ np.where(uncovered, weights, 0.0)).ravel() - loss
            blocked = taken.copy()
            if conflicts is not None:
                own = np.asarray(conflicts[:, [pick]].todense()).ravel()  # type: ignore[index]
                blocked |= near - own > 0.0
            gains[blocked] = -np.inf
            candidate = int(np.argmax(gains))
            if gains[candidate] > best[0]:
                best = (float(gains[candidate]), slot, candidate)
        if best[1] < 0:
            break
        _, slot, candidate = best
        count += row(candidate) - row(int(picks[slot]))
        picks[slot] = candidate
    return np.sort(picks)


def undominated(columns: np.ndarray, k: int, deadline: float) -> np.ndarray:
    """The candidates no other candidate dominates (all of them when the test is too costly or fewer than ``k`` would be left).

    Parameters
    ----------
    columns : (C, G) bool ndarray
        Which candidate sees which target group.
    k : int
        Team size: at least ``k`` candidates are kept.
    deadline : float
        ``time.perf_counter()`` value after which the test gives up (and keeps all).

    Returns
    -------
    (C,) bool ndarray
        True for a kept candidate.
    """
    n = columns.shape[0]
    keep = np.ones(n, dtype=bool)
    if n < 2 or float(n) * n * columns.shape[1] > _DOMINANCE_WORK:
        return keep
    ones = columns.astype(np.float32)  # counts up to 2**24 target groups are exact in float32
    size = ones.sum(axis=1)
    index = np.arange(n)
    for start in range(0, n, 256):
        if time.perf_counter() > deadline:
            return np.ones(n, dtype=bool)
        rows = slice(start, min(start + 256, n))
        overlap = ones[rows] @ ones.T  # overlap[a, b]: groups both see
        inside = overlap == size[rows, None]  # a's groups all seen by b
        above = (size[None, :] > size[rows, None]) | ((size[None, :] == size[rows, None]) & (index[None, :] < index[rows, None]))
        keep[rows] = ~(inside & above).any(axis=1)
    return keep if int(keep.sum()) >= k else np.ones(n, dtype=bool)
