"""The best placement of ``k`` candidate viewpoints, proved by integer programming.

Greedy (:meth:`uavcov.cover.CoverageProblem.greedy`) and the certified bounds say how far a
placement is from the best ``k`` candidates at most; :func:`exact_placement` finds that best
placement, with the solver's proof. Weighted maximum coverage with separation is the integer
program

    max  sum_g W_g z_g
    s.t. z_g <= sum_{s sees g} x_s      (a row per group g of targets)
         sum_s x_s = k                   (<= k when the separation admits no k candidates)
         x_a + x_b <= 1                  (a pair closer than d_safe)
         x in {0, 1},  0 <= z <= 1

where a group holds the targets seen by exactly the same candidates (their weights summed: the
rows are identical otherwise), found by hashing each target's column of the seen-matrix; targets
no candidate sees are left out (they add nothing to any placement). Candidates go first that no
placement better than greedy's can hold: the LP relaxation's dual point (the certificate of
:meth:`uavcov.cover.CoverageProblem.dual_bound`) bounds every placement holding a candidate
``s`` by its own dual value plus the ``k - 1`` largest others; below greedy's coverage, ``s`` is
out (weak duality: exact, whatever the dual point). When the pairs closer than
``d_safe`` outnumber the candidates several times (cameras: every orientation at a position
conflicts with the others), each candidate's later neighbours share one row instead,
``|N(a)| x_a + sum_{b in N(a)} x_b <= |N(a)|``, the same integer points in fewer rows.

Before the program, greedy's placement is improved by best-improvement swaps of one pick
(:func:`uavcov.cover._swap_search.swap_search`), which both narrows the gap and lets the dual point
exclude more candidates; without separation, candidates another one dominates (sees a superset
of) leave too (:func:`uavcov.cover._swap_search.undominated`).

scipy's HiGHS (``scipy.optimize.milp``, branch and cut) solves it; its proven dual bound is the
certificate. The time limit is hard: it counts from the call, and HiGHS runs in a child process
(:mod:`uavcov.cover._bounded_milp`) that gets a share of the time left and is killed one second
past the deadline, because HiGHS does not check its clock inside every step (its presolve took
21.8 s of a 6.2 s limit on Table 1's terrains; two 60 s solves took about 504 s before this).
The steps before it keep to the deadline as well: the LP dual bound gets half the time left, the
swaps stop at the deadline, and no program is made with under ``_LEAST_SOLVER_S`` left.
scipy's ``milp`` takes no starting solution, so the swaps' placement is the fallback: when the
solver stops at its time or node limit (or is killed) the result is the better of that placement
and the solver's incumbent, and the bound the smallest of the solver's, greedy's online bound and
the LP dual bound (each certified on its own). Swaps, solver and evaluation are sequential and
exact: the answer does not depend on ``n_threads`` (which only builds the seen-matrix), and with
the node limit instead of the time limit (and time enough) not on the machine's speed either.

What the optimum is the optimum of: *these candidates* on *these targets* (as every bound of
:mod:`uavcov.cover._greedy`); positions off the candidates may see more.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import MAX_UAVS, as_count, as_non_negative_float, as_positive_float, as_positive_int, read_only
from ..errors import InvalidInputError, InvalidTypeError, ModelTooLargeError
from ._bounded_milp import bounded_milp
from ._dual_bound import dual_bound
from ._greedy import CoverageProblem, GreedyResult
from ._swap_search import swap_search, undominated

MAX_MODEL_BYTES = 4 << 30
"""Default memory allowed for the integer program (estimated before it is built): 4 GiB."""

# Bytes per constraint non-zero through scipy's sparse matrix, HiGHS's column copy, its presolved
# copy and the LP factor (measured on Table 1's terrains: about 60 per non-zero at peak).
_BYTES_PER_NONZERO = 64
MAX_TIME_LIMIT_S = 1e9
"""Longest ``time_limit`` (s, about 30 years): beyond, the timers of the solver child overflow."""
# Solver shares carry the rounding of summing up to T float64 weights (as the LP dual bound's).
_ROUNDING = 4.0 * float(np.finfo(np.float64).eps)
# The LP dual bound's clusters, metres (as CoverageProblem.dual_bound's default).
_DUAL_CELL = 3.0
# Seconds left below which no program is built (the child's start-up alone takes about one).
_LEAST_SOLVER_S = 2.0
# More conflict pairs than this many per candidate: one aggregated row per candidate instead.
_PAIRS_PER_CANDIDATE = 4

STATUSES = ("optimal", "time limit", "node limit")
"""What :attr:`ExactResult.status` may say: proved optimal (within the gap target), or stopped at
the time or the node limit (then :attr:`ExactResult.gap` states how far off it may be)."""


@dataclass(frozen=True)
class ExactResult:
    """The best placement of ``k`` candidates found, and the proof of how good it is.

    Attributes
    ----------
    positions : (n, 3) float64 ndarray
        The chosen candidates, metres, in index order.
    poses : (n, 5) float64 ndarray or None
        Their ``(x, y, z, yaw, pitch)`` for camera candidates.
    picks : (n,) int64 ndarray
        The candidates' indices, increasing.
    coverage : float
        The placement's weighted share of the targets seen (as greedy's coverage is summed).
    bound : float
        Proven: no ``k`` candidates kept ``d_safe`` apart see more. The solver's dual bound, or,
        stopped early, the smallest of it, greedy's online bound and the LP dual bound.
    gap : float
        ``bound - coverage`` (share): at most this much better placement may exist; 0 up to the
        gap target when ``status == "optimal"``.
    status : str
        ``"optimal"`` (proved within the gap target), ``"time limit"`` or ``"node limit"``
        (stopped: ``gap`` states how far off it may be).
    k : int
        Team size asked for.
    incumbent : str
        Where the placement comes from: ``"greedy"``, ``"swaps"`` (greedy's improved by
        swapping one pick at a time) or ``"solver"`` (HiGHS found a better one).
    solver : str
        What became of HiGHS: ``"not run"`` (greedy's bound proved it optimal first),
        ``"finished"``, ``"stopped at its limit"`` (its own time, node or gap limit), or
        ``"killed at the deadline"`` (it overran; its work is lost, the bounds of greedy and
        the LP stand).
    d_safe : float
        Separation kept between the chosen candidates, metres.
    greedy_coverage : float
        Greedy's coverage on the same problem (the result is never below it).
    holds_for : str
        What the bound bounds, in words.
    n_candidates : int
    n_kept : int
        Candidates left in the program: those the LP dual bound does not exclude from every
        placement better than the incumbent, less the dominated ones.
    n_rows : int
        Rows of targets in the program (groups of targets seen by the same candidates); 0 when
        greedy's placement was proved optimal without one (its bound met its coverage).
    n_conflict_rows : int
        Separation rows.
    n_nodes : int
        Branch-and-bound nodes the solver explored.
    model_time_s, swap_time_s, solve_time_s : float
        Wall time of reducing the candidates and building the program, of the swaps, and of the
        solver (its child process included), seconds.
    """

    positions: np.ndarray
    poses: np.ndarray | None
    picks: np.ndarray
    coverage: float
    bound: float
    gap: float
    status: str
    k: int
    incumbent: str
    d_safe: float
    greedy_coverage: float
    holds_for: str
    n_candidates: int
    n_kept: int
    n_rows: int
    n_conflict_rows: int
    n_nodes: int
    model_time_s: float
    swap_time_s: float
    solve_time_s: float
    solver: str

    @property
    def relative_gap(self) -> float:
        """``gap / bound`` (0 when the bound is 0)."""
        return self.gap / self.bound if self.bound > 0 else 0.0


def target_groups(seen: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Targets seen by exactly the same candidates, grouped.

    Parameters
    ----------
    seen : (C, T) bool ndarray
        Which candidate sees which target.

    Returns
    -------
    first : (G,) int64 ndarray
        A target of each group (its lowest index), groups in the order of their first target.
    group : (T,) int64 ndarray
        Each target's group.
    """
    seen = np.asarray(seen, dtype=bool)
    _n_candidates, n_targets = seen.shape
    if n_targets == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    # each target's column packed into bytes, hashed as one opaque value by np.unique
    packed = np.ascontiguousarray(np.packbits(seen, axis=0).T)
    keys = packed.view(np.dtype((np.void, packed.shape[1]))).ravel()
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")  # groups numbered by first target: independent of the hash order
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    return first[order].astype(np.int64), rank[inverse.ravel()].astype(np.int64)


def conflict_pairs(positions: np.ndarray, d_safe: float) -> np.ndarray:
    """``(P, 2)`` int64: the pairs ``a < b`` of ``positions`` closer than ``d_safe`` (as greedy keeps them apart)."""
    from scipy.spatial import cKDTree

    if d_safe <= 0.0 or positions.shape[0] < 2:
        return np.zeros((0, 2), dtype=np.int64)
    pairs: np.ndarray = np.asarray(cKDTree(positions).query_pairs(d_safe, output_type="ndarray"), dtype=np.int64)
    if pairs.size == 0:
        return np.zeros((0, 2), dtype=np.int64)
    offset = positions[pairs[:, 0]] - positions[pairs[:, 1]]
    pairs = pairs[np.einsum("ij,ij->i", offset, offset) < d_safe * d_safe]
    ordered: np.ndarray = pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]
    return ordered


def _conflict_rows(pairs: np.ndarray, n_candidates: int) -> tuple[object, np.ndarray]:
    """The separation rows: one per pair, or one per candidate over its later neighbours when pairs are many."""
    from scipy.sparse import coo_matrix

    if pairs.shape[0] <= _PAIRS_PER_CANDIDATE * n_candidates:
        rows = np.repeat(np.arange(pairs.shape[0]), 2)
        matrix = coo_matrix((np.ones(rows.size), (rows, pairs.ravel())), shape=(pairs.shape[0], n_candidates))
        return matrix.tocsr(), np.ones(pairs.shape[0])
    owners, degree = np.unique(pairs[:, 0], return_counts=True)
    row_of = np.full(n_candidates, -1, dtype=np.int64)
    row_of[owners] = np.arange(owners.size)
    rows = np.concatenate([row_of[owners], row_of[pairs[:, 0]]])
    cols = np.concatenate([owners, pairs[:, 1]])
    values = np.concatenate([degree.astype(np.float64), np.ones(pairs.shape[0])])
    matrix = coo_matrix((values, (rows, cols)), shape=(owners.size, n_candidates))
    return matrix.tocsr(), degree.astype(np.float64)


def exact_placement(
    problem: CoverageProblem,
    k: int,
    d_safe: float = 0.0,
    *,
    time_limit: float = 60.0,
    gap: float = 1e-4,
    node_limit: int | None = None,
    max_model_bytes: int = MAX_MODEL_BYTES,
) -> ExactResult:
    """The best ``k`` of ``problem``'s candidates kept ``d_safe`` apart, by integer programming.

    Parameters
    ----------
    problem : CoverageProblem
        The candidates and which targets each sees (terrain lattices, structure offsets, camera
        poses alike).
    k : int
        Team size.
    d_safe : float, default 0.0
        Least distance between two chosen candidates, metres (pairs closer conflict, as in greedy).
    time_limit : float, default 60.0
        Seconds the call may take from its start (wall time: the result then depends on the
        machine's speed); hard, up to the child's start-up and a one-second grace.
    gap : float, default 1e-4
        Relative gap at which the solver stops and calls the placement optimal.
    node_limit : int, optional
        Branch-and-bound nodes the solver may explore (deterministic, unlike the time limit).
    max_model_bytes : int, default 4 GiB
        Memory the program may take (estimated from the matrix's size and its non-zeros before
        either is built).

    Returns
    -------
    ExactResult
        Never below greedy's coverage; ``bound >= coverage`` always.

    Raises
    ------
    ModelTooLargeError
        The program would take more than ``max_model_bytes``.
    InvalidInputError, InvalidTypeError
        A bad ``k``, ``d_safe``, ``time_limit``, ``gap``, ``node_limit`` or ``max_model_bytes``.

    Examples
    --------
    >>> import uavcov
    >>> from uavcov.cover import CoverageProblem, GreedySettings, exact_placement, viewpoint_lattice
    >>> from uavcov.limits import Constraints
    >>> hills = uavcov.gaussian_hills(size=30.0, spacing=1.0, n_hills=3, rng=1)
    >>> lattice = viewpoint_lattice(hills, Constraints(h_min=2.0, h_max=10.0, z_max=60.0), GreedySettings(spacing=6.0, n_heights=1))
    >>> best = exact_placement(CoverageProblem(uavcov.Visibility(hills, 8.0), lattice), 3)
    >>> best.status, best.greedy_coverage <= best.coverage <= best.bound
    ('optimal', True)
    """
    if not isinstance(problem, CoverageProblem):
        raise InvalidTypeError(f"problem must be a uavcov.cover.CoverageProblem, got {type(problem).__name__}")
    k = as_count(k, "k", MAX_UAVS)
    d_safe = as_non_negative_float(d_safe, "d_safe")
    time_limit = as_positive_float(time_limit, "time_limit")
    if time_limit > MAX_TIME_LIMIT_S:  # the solver's clock cannot hold more
        raise InvalidInputError(f"time_limit must be at most {MAX_TIME_LIMIT_S:.0e} s, got {time_limit}")
    gap = as_non_negative_float(gap, "gap")
    if node_limit is not None:
        node_limit = as_count(node_limit, "node_limit", 1 << 40)
    max_model_bytes = as_positive_int(max_model_bytes, "max_model_bytes")
    n_candidates, n_targets = problem.viewpoints.n, problem._matrix.n_targets
    # the dense matrix and the LP dual's float copy of it come first: refused before they are made
    if n_candidates * n_targets * 9 > max_model_bytes:
        raise ModelTooLargeError(
            f"{n_candidates:,} candidates x {n_targets:,} targets take {n_candidates * n_targets * 9 / 2**30:.1f} GiB "
            f"as the program's matrices, more than max_model_bytes = {max_model_bytes / 2**30:.1f} GiB: use fewer candidates or targets"
        )
    started = time.perf_counter()
    deadline = started + time_limit
    greedy = problem.greedy(k, d_safe)
    seen = problem.dense()
    weights = np.asarray(problem._visibility.targets.weights, dtype=np.float64)
    shares = weights / weights.sum()
    seen_csr = _sparse(seen)
    targets = problem._visibility.targets
    certificate = dual_bound(
        seen, targets.weights, k, targets.points, _DUAL_CELL, time_limit=0.5 * max(deadline - time.perf_counter(), 0.0), sparse=seen_csr
    )
    search = _Search(greedy.picks, greedy.coverage, min(greedy.bound, certificate.bound))
    survivors, model = np.zeros(0, dtype=np.int64), None
    if search.bound - search.coverage <= gap * search.bound:  # greedy is already proved optimal: no program
        search.status = "optimal"
    else:
        _improve(problem, seen, seen_csr, shares, search, d_safe, deadline)
    if search.status != "optimal" and search.bound - search.coverage <= gap * search.bound:  # the swaps met the bound
        search.status = "optimal"
    elif search.status != "optimal" and deadline - time.perf_counter() > _LEAST_SOLVER_S:
        before = time.perf_counter()
        survivors = _survivors(seen_csr, shares, certificate.u, k, search)
        if conflict_pairs(problem.viewpoints.positions[survivors], d_safe).size == 0:
            first, _group = target_groups(seen[survivors])
            survivors = survivors[undominated(seen[np.ix_(survivors, first)], k, deadline)]
        model = _model(
            problem, seen, shares, survivors, d_safe, k, exactly=greedy.picks.size == k, max_model_bytes=max_model_bytes, deadline=deadline
        )
        search.model_time += time.perf_counter() - before
        if model is not None:  # else the deadline passed while it was made: the solver is not run
            _round(problem, search, survivors, model, k, (deadline, gap, node_limit))
    return _result(problem, greedy, search, survivors, model, k, d_safe, gap)


def _improve(
    problem: CoverageProblem, seen: np.ndarray, seen_csr: Any, shares: np.ndarray, search: _Search, d_safe: float, deadline: float
) -> None:
    """Swaps from greedy's placement (:func:`swap_search`); ``search`` takes the result if it covers more."""
    from scipy.sparse import coo_matrix

    before = time.perf_counter()
    first, group = target_groups(seen)
    weights = np.bincount(group, weights=shares, minlength=first.size)
    pairs = conflict_pairs(problem.viewpoints.positions, d_safe)
    n = seen.shape[0]
    conflicts = None
    if pairs.size:
        both = np.concatenate([pairs, pairs[:, ::-1]])
        conflicts = coo_matrix((np.ones(both.shape[0]), (both[:, 0], both[:, 1])), shape=(n, n)).tocsc()
    picks = swap_search(seen_csr[:, first], weights, search.picks, conflicts, deadline)
    value = _coverage_of(problem, picks)
    if value > search.coverage:
        search.picks, search.coverage, search.incumbent = picks, value, "swaps"
    search.swap_time = time.perf_counter() - before


@dataclass
class _Search:
    """The best placement so far and the smallest proven bound, over the rounds."""

    picks: np.ndarray
    coverage: float
    bound: float
    incumbent: str = "greedy"
    solver: str = "not run"
    status: str = "time limit"
    n_nodes: int = 0
    model_time: float = 0.0
    solve_time: float = 0.0
    swap_time: float = 0.0


def _model(
    problem: CoverageProblem,
    seen: np.ndarray,
    shares: np.ndarray,
    survivors: np.ndarray,
    d_safe: float,
    k: int,
    *,
    exactly: bool,
    max_model_bytes: int,
    deadline: float = float("inf"),
) -> _Program | None:
    """The program on the candidates ``survivors``, its targets grouped; refused when too large, None past ``deadline``."""
    first, group = target_groups(seen[survivors])
    if time.perf_counter() > deadline:
        return None
    weights = np.bincount(group, weights=shares, minlength=first.size)
    columns = seen[np.ix_(survivors, first)]
    kept = columns.any(axis=0)  # a group no candidate sees adds nothing to any placement
    columns, weights = columns[:, kept], weights[kept]
    pairs = conflict_pairs(problem.viewpoints.positions[survivors], d_safe)
    nonzeros = int(np.count_nonzero(columns)) + int(columns.shape[1]) + 2 * int(pairs.shape[0]) + survivors.size
    if nonzeros * _BYTES_PER_NONZERO > max_model_bytes:
        raise ModelTooLargeError(
            f"the integer program would have {nonzeros:,} non-zeros, about {nonzeros * _BYTES_PER_NONZERO / 2**30:.1f} GiB, "
            f"more than max_model_bytes = {max_model_bytes / 2**30:.1f} GiB: use fewer candidates or targets"
        )
    return None if time.perf_counter() > deadline else _program(columns, weights, pairs, k, exactly=exactly)


# HiGHS's presolve finds nothing to remove in these programs (Table 1: 0 rows, 0 columns) and
# took 21.8 s on a 1.5-million-non-zero one before the root LP started: switched off.
_HIGHS_OPTIONS: dict[str, object] = {"presolve": False}


def _round(
    problem: CoverageProblem, search: _Search, survivors: np.ndarray, model: _Program, k: int, limits: tuple[float, float, int | None]
) -> None:
    """HiGHS on ``model`` until the deadline (a child process killed then), the relative gap or the node limit.

    ``search`` takes its placement if better, and its bound. The solver's bound holds for the
    placements of the candidates left; every other placement is below the best coverage so far
    (or matched by one of the candidates left), so ``max(bound, coverage)`` holds for all.
    """
    deadline, gap, node_limit = limits
    options: dict[str, object] = {"mip_rel_gap": gap, **_HIGHS_OPTIONS}
    if node_limit is not None:
        options["node_limit"] = node_limit
    arguments = {
        "c": model.cost,
        "integrality": model.integrality,
        "bounds": model.bounds,
        "constraints": model.constraints,
        "options": options,
    }
    outcome = bounded_milp(arguments, deadline)
    search.solve_time += outcome.wall_s
    search.n_nodes += outcome.n_nodes
    if outcome.killed:
        search.solver = "killed at the deadline"
        return
    search.solver = "finished" if outcome.status == 0 else "stopped at its limit"
    if outcome.x is not None:
        chosen = survivors[np.flatnonzero(outcome.x[: survivors.size] > 0.5)]
        value = _coverage_of(problem, chosen)
        if value > search.coverage:
            search.picks, search.coverage, search.incumbent = chosen, value, "solver"
    if np.isfinite(outcome.dual_bound):
        search.bound = min(search.bound, max(-outcome.dual_bound + (k + 1) * problem._matrix.n_targets * _ROUNDING, search.coverage))
    if outcome.status == 0 or search.bound - search.coverage <= gap * search.bound:
        search.status = "optimal"
    elif node_limit is not None and outcome.n_nodes >= node_limit:
        search.status = "node limit"


def _result(
    problem: CoverageProblem,
    greedy: GreedyResult,
    search: _Search,
    survivors: np.ndarray,
    model: _Program | None,
    k: int,
    d_safe: float,
    gap: float,
) -> ExactResult:
    """The search as an :class:`ExactResult`."""
    picks = np.sort(np.asarray(search.picks, dtype=np.int64))
    bound = max(search.bound, search.coverage)  # every bound holds for this placement too
    status = "optimal" if bound - search.coverage <= gap * bound else search.status
    positions = problem.viewpoints.positions
    poses = problem.viewpoints.poses
    return ExactResult(
        positions=read_only(positions[picks].copy()),
        poses=None if poses is None else read_only(poses[picks].copy()),
        picks=read_only(picks),
        coverage=float(search.coverage),
        bound=float(bound),
        gap=float(bound - search.coverage),
        status=status,
        k=k,
        incumbent=search.incumbent,
        solver=search.solver,
        d_safe=d_safe,
        greedy_coverage=greedy.coverage,
        holds_for=f"the best {k} of these candidates ({problem.viewpoints.description}) kept {d_safe:g} m apart, "
        f"on these {problem._matrix.n_targets} targets",
        n_candidates=problem.viewpoints.n,
        n_kept=int(survivors.size),
        n_rows=0 if model is None else model.n_rows,
        n_conflict_rows=0 if model is None else model.n_conflict_rows,
        n_nodes=search.n_nodes,
        model_time_s=search.model_time,
        swap_time_s=search.swap_time,
        solve_time_s=search.solve_time,
    )


def _survivors(seen: Any, shares: np.ndarray, u: np.ndarray, k: int, best: _Search) -> np.ndarray:
    """The candidates that may belong to a placement better than the best so far, increasing (its picks always).

    The LP dual point ``u`` bounds every placement ``S`` of ``k`` candidates by
    ``sum_{s in S} c_s + sum_t (shares_t - u_t)`` with ``c_s = sum_{t seen by s} u_t`` (weak
    duality, as :mod:`uavcov.cover._dual_bound`); a placement holding ``s`` is then at most
    ``c_s`` plus the ``k - 1`` largest of the other ``c``. A candidate whose bound is below
    the best coverage so far is in no better placement, and is left out of the program.
    """
    u = np.clip(u, 0.0, shares)
    per_candidate = np.asarray(seen @ u).ravel()
    rest = float(np.sum(shares - u))
    top = np.sort(per_candidate)[::-1][: k + 1]
    if top.size < k + 1:
        return np.arange(seen.shape[0], dtype=np.int64)
    # c_s + the k - 1 largest others: the k largest when s is among them, else s and the k - 1 largest
    others = np.where(per_candidate >= top[k - 1], float(np.sum(top[:k])) - per_candidate, float(np.sum(top[: k - 1])))
    margin = (k + 1) * max(seen.shape[1], 1) * _ROUNDING
    keep = per_candidate + others + rest + margin >= best.coverage
    keep[best.picks] = True
    return np.flatnonzero(keep).astype(np.int64)


@dataclass(frozen=True)
class _Program:
    """The integer program in scipy's form, and its sizes."""

    cost: np.ndarray
    integrality: np.ndarray
    bounds: object
    constraints: object
    n_rows: int
    n_conflict_rows: int


def _program(columns: np.ndarray, shares: np.ndarray, pairs: np.ndarray, k: int, *, exactly: bool) -> _Program:
    """Variables ``x`` (one per candidate) then ``z`` (one per group); rows as in the module's docstring."""
    from scipy.optimize import Bounds, LinearConstraint
    from scipy.sparse import csr_matrix, hstack, identity, vstack

    n_candidates, n_groups = columns.shape
    group_of, candidate_of = np.nonzero(columns.T)  # the sparse rows straight from the non-zeros: no dense float copy
    seen_by = csr_matrix((-np.ones(group_of.size), (group_of, candidate_of)), shape=(n_groups, n_candidates))
    coverage_rows = hstack([seen_by, identity(n_groups, format="csr")])
    conflicts, conflict_upper = _conflict_rows(pairs, n_candidates)
    blocks = [coverage_rows, hstack([csr_matrix(np.ones((1, n_candidates))), csr_matrix((1, n_groups))])]
    upper = [np.zeros(n_groups), np.array([float(k)])]
    lower = [np.full(n_groups, -np.inf), np.array([float(k) if exactly else 0.0])]
    if conflict_upper.size:
        blocks.append(hstack([conflicts, csr_matrix((conflict_upper.size, n_groups))]))
        upper.append(conflict_upper)
        lower.append(np.full(conflict_upper.size, -np.inf))
    matrix = vstack(blocks, format="csr")
    return _Program(
        cost=np.concatenate([np.zeros(n_candidates), -shares]),
        integrality=np.concatenate([np.ones(n_candidates), np.zeros(n_groups)]),
        bounds=Bounds(np.zeros(n_candidates + n_groups), np.ones(n_candidates + n_groups)),
        constraints=LinearConstraint(matrix, np.concatenate(lower), np.concatenate(upper)),
        n_rows=n_groups,
        n_conflict_rows=int(conflict_upper.size),
    )


def _sparse(seen: np.ndarray) -> Any:
    """``seen`` as a 0/1 float64 CSR matrix, made from its non-zeros (no dense float copy)."""
    from scipy.sparse import csr_matrix

    rows, cols = np.nonzero(seen)
    return csr_matrix((np.ones(rows.size), (rows, cols)), shape=seen.shape)


def _coverage_of(problem: CoverageProblem, picks: np.ndarray) -> float:
    """The picks' share of the targets, summed exactly as greedy's coverage is (in Rust, target order)."""
    seen = problem.dense()[picks].any(axis=0) if picks.size else np.zeros(problem._matrix.n_targets, dtype=bool)
    coverage, _ = problem._matrix.bound(np.ascontiguousarray(seen), max(int(picks.size), 1), problem._n_threads)
    return float(coverage)
