"""A certified bound on the best ``k`` candidates from the LP relaxation of weighted maximum coverage.

The online bound of Leskovec et al. (2007) adds the ``k`` largest marginal gains to a
placement's coverage; once a handful of candidates each see a large share of what is left it
exceeds the ceiling and certifies nothing (Table 1's terrains: N >= 8). The LP relaxation

    max sum_t w_t z_t   s.t.  z_t <= sum_{s sees t} x_s,  z_t <= 1,  sum_s x_s <= k,  x >= 0

has an optimum at least OPT (every placement of ``k`` candidates is a feasible 0/1 point), and by
weak duality every ``u`` with ``0 <= u_t <= w_t`` bounds that optimum:

    OPT <= k * max_s sum_{t seen by s} u_t + sum_t (w_t - u_t).

So the certificate is ``u`` itself, whatever produced it: :func:`dual_bound` asks scipy's HiGHS
(interior point) for the duals of the LP, on clusters of nearby targets for speed, clips them
into the box, and :func:`certificate_value` evaluates the right-hand side on the full matrix,
plus a rounding margin. The separation between picks only removes
placements, so the bound also holds with it. ``x_s <= 1`` is left out: with ``z <= 1`` it never
binds at an optimum, and without it the dual has exactly the form above.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import read_only

# Sums of at most T non-negative float64 terms of total <= 1 are off by at most T * eps each;
# the margin covers the k-fold max and the sum (share units).
_ROUNDING = 4.0 * np.finfo(np.float64).eps


@dataclass(frozen=True)
class DualCertificate:
    """A dual-feasible point of the LP relaxation and the bound it certifies.

    Attributes
    ----------
    bound : float
        No ``k`` candidates see a larger weighted share of the targets together:
        ``certificate_value`` of :attr:`u`.
    u : (T,) float64 ndarray
        The certificate, a share per target, ``0 <= u_t <= w_t / sum(w)``.
    lp_value : float
        The LP optimum the solver reported (share); ``bound`` is within rounding of it when
        the solver succeeded. NaN when it did not (then ``u`` is the trivial point ``w``).
    k : int
        Team size.
    solve_time_s : float
        Wall time of grouping, solving and evaluating, seconds.
    """

    bound: float
    u: np.ndarray
    lp_value: float
    k: int
    solve_time_s: float


def certificate_value(seen: np.ndarray, shares: np.ndarray, u: np.ndarray, k: int) -> float:
    """``k * max_s sum_{t seen by s} u_t + sum_t (shares_t - u_t)``, plus a rounding margin.

    Parameters
    ----------
    seen : (C, T) bool ndarray
        Which candidate sees which target.
    shares : (T,) float64 ndarray
        Target weights as shares (summing to 1).
    u : (T,) float64 ndarray
        Clipped into ``[0, shares]`` first, so any ``u`` gives a valid bound.
    k : int
    """
    u = np.clip(np.asarray(u, dtype=np.float64), 0.0, shares)
    per_candidate = seen.astype(np.float64) @ u if seen.shape[0] else np.zeros(1)
    rest = float(np.sum(shares - u))
    n = max(seen.shape[1], 1)
    return float(k * per_candidate.max() + rest + (k + 1) * n * _ROUNDING)


def dual_bound(
    seen: np.ndarray,
    weights: np.ndarray,
    k: int,
    points: np.ndarray | None = None,
    cell: float | None = None,
    *,
    time_limit: float | None = None,
    sparse: Any = None,
) -> DualCertificate:
    """The LP relaxation's dual certificate for the best ``k`` of ``seen``'s candidates.

    With ``cell``, the LP is solved on clusters of targets (the ``cell``-metre boxes of
    ``points``) with the certificate kept proportional to the weights inside a cluster
    (``u_t = rho_c w_t``): a smaller LP whose dual is still a dual point of the full one, so the
    bound stays certified, a little above the full LP's optimum (Table 1's terrains, N = 5:
    0.7208 with 3 m cells against 0.7202 for the full LP, 20x faster; benches/README.md).

    Parameters
    ----------
    seen : (C, T) bool ndarray
        Which candidate sees which target.
    weights : (T,) float64 ndarray
        Target weights (non-negative, positive sum).
    k : int
        Team size, at least 1.
    points : (T, 3) float64 ndarray, optional
        The targets, metres (needed with ``cell``).
    cell : float, optional
        Cluster size, metres; ``None``: every target its own row (the full LP).
    time_limit : float, optional
        Seconds from the call's start the LP may take (HiGHS gets what is left after the
        matrices are made); stopped, the certificate is the trivial point (still a bound).
    sparse : (C, T) scipy sparse float64 matrix, optional
        ``seen`` as 0/1, already made: the matrices and the certificate's evaluation then use
        it instead of float copies of the dense matrix (the same bound up to the order of
        summation, covered by the rounding margin; seconds saved on 10^8 cells).

    Returns
    -------
    DualCertificate
        Its ``bound`` is a share, at most 1.
    """
    from scipy.optimize import linprog
    from scipy.sparse import coo_matrix, csr_matrix, hstack, identity, vstack

    started = time.perf_counter()
    seen = np.asarray(seen, dtype=bool)
    shares = np.asarray(weights, dtype=np.float64) / float(np.sum(weights))
    n_candidates, n_targets = seen.shape
    if cell is None or points is None:
        cluster = np.arange(n_targets)
    else:
        cluster = np.unique(np.floor(np.asarray(points, dtype=np.float64) / cell).astype(np.int64), axis=0, return_inverse=True)[1].ravel()
    n_clusters = int(cluster.max()) + 1 if n_targets else 0
    cluster_weight = np.bincount(cluster, weights=shares, minlength=n_clusters)
    # a[s, c]: the share of cluster c's weight that candidate s sees, in [0, 1]
    spread = coo_matrix((shares, (np.arange(n_targets), cluster)), shape=(n_targets, n_clusters)).tocsr()
    ratio_of = np.divide(1.0, cluster_weight, out=np.zeros(n_clusters), where=cluster_weight > 0)
    seen_share = ((csr_matrix(seen, dtype=np.float64) if sparse is None else sparse) @ spread) @ coo_matrix(
        (ratio_of, (np.arange(n_clusters), np.arange(n_clusters)))
    ).tocsr()
    lp_value = float("nan")
    u = shares.copy()  # trivial certificate: k * (best single candidate), if the solver fails
    if n_clusters and n_candidates:
        # variables: x (C) then z (M); rows: z_c - sum_s a[s, c] x_s <= 0 (M), sum x <= k (1)
        a_ub = vstack(
            [
                hstack([-seen_share.T.tocsr(), identity(n_clusters, format="csr")]),
                hstack([csr_matrix(np.ones((1, n_candidates))), csr_matrix((1, n_clusters))]),
            ]
        ).tocsr()
        b_ub = np.zeros(n_clusters + 1)
        b_ub[-1] = k
        cost = np.concatenate([np.zeros(n_candidates), -cluster_weight])
        bounds = [(0.0, None)] * n_candidates + [(0.0, 1.0)] * n_clusters
        options = {} if time_limit is None else {"time_limit": max(float(time_limit) - (time.perf_counter() - started), 1e-3)}
        result = linprog(cost, A_ub=a_ub, b_ub=b_ub, bounds=bounds, method="highs-ipm", options=options)
        if result.status == 0:
            lp_value = float(-result.fun)
            y = np.clip(-np.asarray(result.ineqlin.marginals[:n_clusters], dtype=np.float64), 0.0, cluster_weight)
            u = shares * (y * ratio_of)[cluster]
            unseen = ~seen.any(axis=0) if sparse is None else np.asarray(sparse.sum(axis=0)).ravel() == 0.0
            u[unseen] = shares[unseen]  # in no candidate's sum: their whole weight is free
    if sparse is None:
        bound = min(certificate_value(seen, shares, u, k), 1.0)
    else:  # certificate_value's sum, on the sparse matrix
        u = np.clip(u, 0.0, shares)
        per_candidate = np.asarray(sparse @ u).ravel() if n_candidates else np.zeros(1)
        rest = float(np.sum(shares - u))
        bound = min(float(k * per_candidate.max() + rest + (k + 1) * max(n_targets, 1) * _ROUNDING), 1.0)
    return DualCertificate(bound=bound, u=read_only(u), lp_value=lp_value, k=int(k), solve_time_s=time.perf_counter() - started)
