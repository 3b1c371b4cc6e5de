"""Every solver of uavcov.cover.exact_placement (scipy's HiGHS, highspy) against brute force, and their errors."""

from __future__ import annotations

import importlib.util
import itertools
import math
import time
from typing import Any

import numpy as np
import pytest

import uavcov
from uavcov.cover import CoverageProblem, GreedySettings, Viewpoints, _exact, exact_placement, viewpoint_lattice
from uavcov.errors import InvalidInputError, InvalidTypeError, MissingExtraError
from uavcov.limits import Constraints

HAVE_HIGHSPY = importlib.util.find_spec("highspy") is not None
SOLVERS = [
    "highs",
    pytest.param("highspy", marks=pytest.mark.skipif(not HAVE_HIGHSPY, reason="highspy not installed (uavcov[highspy])")),
]


def _random_problem(seed: int, n_threads: int = 1) -> CoverageProblem:
    """Hills drawn from ``seed``, every third candidate of a 3 m lattice x 3 heights: about 120 candidates."""
    hills = uavcov.gaussian_hills(size=30.0, spacing=2.0, n_hills=4, rng=seed)
    lattice = viewpoint_lattice(hills, Constraints(h_min=1.0, h_max=8.0, z_max=60.0), GreedySettings(spacing=3.0, n_heights=3))
    every_third = lattice.positions[::3].copy()
    return CoverageProblem(uavcov.Visibility(hills, 9.0), Viewpoints(every_third, None, "given", "every third"), n_threads=n_threads)


def _brute_force(problem: CoverageProblem, k: int, d_safe: float) -> float:
    """The best weighted share of ``k`` candidates kept ``d_safe`` apart, over every k-subset (the last pick vectorised)."""
    seen = problem.dense()
    weights = problem._visibility.targets.weights
    shares = weights / weights.sum()
    positions = problem.viewpoints.positions
    close = np.linalg.norm(positions[:, None] - positions[None], axis=2) < d_safe
    best = 0.0
    for combo in itertools.combinations(range(len(positions)), k - 1):
        if any(close[a, b] for a, b in itertools.combinations(combo, 2)):
            continue
        union = seen[list(combo)].any(axis=0)
        last = [c for c in range(combo[-1] + 1, len(positions)) if not close[c, list(combo)].any()]
        if last:
            best = max(best, float(((seen[last] | union) @ shares).max()))
    return best


def _assert_separated(positions: np.ndarray, d_safe: float) -> None:
    for a, b in itertools.combinations(range(len(positions)), 2):
        assert np.linalg.norm(positions[a] - positions[b]) >= d_safe


# (seed, k, d_safe): instances on which greedy and the swaps are not proved optimal before the
# program, so that the solver itself runs (each test asserts it did)
_CASES = [(7, 3, 12.0), (4, 3, 0.0), (7, 2, 0.0), (11, 3, 8.0), (12, 3, 12.0)]  # 7 and 12 at 12 m: the separation binds


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("seed, k, d_safe", _CASES)
def test_every_solver_equals_brute_force(solver: str, seed: int, k: int, d_safe: float) -> None:
    problem = _random_problem(seed)
    expected = _brute_force(problem, k, d_safe)
    best = exact_placement(problem, k, d_safe, solver=solver)
    assert best.solver == "finished" and best.n_rows > 0, best  # the solver ran, and finished
    assert best.status == "optimal" and best.mip_solver == solver
    assert math.isclose(best.coverage, expected, rel_tol=1e-12, abs_tol=1e-14), (best.coverage, expected)
    assert best.coverage <= best.bound <= best.coverage * (1 + 1e-4) + 1e-12
    assert best.bound >= expected - 1e-12
    assert best.greedy_coverage <= best.coverage and best.picks.size == k
    _assert_separated(best.positions, d_safe)


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("seed, k, d_safe", _CASES[:3])
def test_a_bound_stopped_early_still_holds_for_the_optimum(solver: str, seed: int, k: int, d_safe: float) -> None:
    problem = _random_problem(seed)
    expected = _brute_force(problem, k, d_safe)
    for limits in ({"node_limit": 1}, {"time_limit": 2.5}):
        stopped = exact_placement(problem, k, d_safe, solver=solver, **limits)
        assert stopped.bound >= expected - 1e-12, (limits, stopped.bound, expected)  # never below the true optimum
        assert stopped.greedy_coverage <= stopped.coverage <= expected + 1e-12
        assert stopped.status in _exact.STATUSES and (stopped.status == "optimal" or stopped.gap > 0.0)
        _assert_separated(stopped.positions, d_safe)


@pytest.mark.parametrize("solver", SOLVERS)
def test_the_same_answer_for_any_thread_count(solver: str) -> None:
    one = exact_placement(_random_problem(7, n_threads=1), 3, 12.0, solver=solver)
    two = exact_placement(_random_problem(7, n_threads=2), 3, 12.0, solver=solver)
    assert one.solver == "finished"
    assert np.array_equal(one.picks, two.picks)
    assert (one.coverage, one.bound, one.status, one.n_nodes) == (two.coverage, two.bound, two.status, two.n_nodes)


@pytest.mark.skipif(not HAVE_HIGHSPY, reason="highspy not installed (uavcov[highspy])")
def test_the_highspy_child_is_killed_at_the_deadline() -> None:
    from uavcov.cover._bounded_milp import _GRACE_S, bounded_milp
    from uavcov.paper import TABLE1

    terrain = TABLE1.terrain.make(0)
    limits = TABLE1.mission.constraints.resolve(terrain)
    lattice = viewpoint_lattice(terrain, limits, GreedySettings(spacing=5.0, n_heights=3), n_threads=2)
    problem = CoverageProblem(uavcov.Visibility(terrain, TABLE1.d_max, n_threads=2), lattice, n_threads=2)
    seen = problem.dense()
    shares = problem._visibility.targets.weights / problem._visibility.targets.weights.sum()
    model = _exact._model(problem, seen, shares, np.arange(seen.shape[0]), limits.d_safe, 8, exactly=True, max_model_bytes=1 << 32)
    assert model is not None
    arguments = {"c": model.cost, "integrality": model.integrality, "bounds": model.bounds, "constraints": model.constraints}
    started = time.perf_counter()
    outcome = bounded_milp({**arguments, "options": {"presolve": "on", "threads": 1}}, started + 0.5, "highspy")
    assert outcome.killed or outcome.status == 1  # killed, or stopped by its own (shorter) limit
    assert not outcome.killed or (outcome.x is None and math.isnan(outcome.dual_bound))
    assert time.perf_counter() - started < 0.5 + _GRACE_S + 10.0  # hang check


def test_a_missing_extra_is_a_clear_error(monkeypatch: pytest.MonkeyPatch) -> None:
    real = importlib.util.find_spec

    def without_highspy(name: str, *args: Any, **kwargs: Any) -> Any:
        return None if name == "highspy" else real(name, *args, **kwargs)

    monkeypatch.setattr(importlib.util, "find_spec", without_highspy)
    with pytest.raises(MissingExtraError, match=r"uavcov\[highspy\]"):
        exact_placement(_random_problem(3), 3, solver="highspy")
    assert exact_placement(_random_problem(3), 3, solver="highs").status == "optimal"  # the default needs only scipy


@pytest.mark.parametrize(
    "solver, error",
    [("cplex", InvalidInputError), ("HIGHS", InvalidInputError), ("", InvalidInputError), (None, InvalidTypeError), (3, InvalidTypeError)],
)
def test_an_unknown_solver_is_a_clear_error(solver: Any, error: type[Exception]) -> None:
    with pytest.raises(error, match="solver"):
        exact_placement(_random_problem(3), 3, solver=solver)
