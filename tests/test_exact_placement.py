"""The exact placement by integer programming (uavcov.cover.exact_placement) against brute force."""

from __future__ import annotations

import itertools
import math
import pickle
import time
from typing import Any

import numpy as np
import pytest

import uavcov
from uavcov.cover import CoverageProblem, GreedySettings, Viewpoints, _exact, exact_placement, viewpoint_lattice, viewpoint_offsets
from uavcov.errors import InvalidInputError, InvalidTypeError, ModelTooLargeError
from uavcov.limits import Constraints
from uavcov.structures import girder_bridge


def _terrain_problem(n_threads: int = 2) -> CoverageProblem:
    hills = uavcov.gaussian_hills(size=30.0, spacing=2.0, n_hills=4, rng=3)
    lattice = viewpoint_lattice(hills, Constraints(h_min=1.0, h_max=8.0, z_max=60.0), GreedySettings(spacing=3.0, n_heights=3))
    return CoverageProblem(uavcov.Visibility(hills, 9.0), lattice, n_threads=n_threads)


def _bridge_problem() -> CoverageProblem:
    bridge = girder_bridge(rng=0)
    limits = Constraints(clearance="standoff", h_min=2.0, z_max=25.0, d_safe=1.0)
    offsets = viewpoint_offsets(bridge.surface, limits, [3.0, 6.0], spacing=6.0, n_threads=2)
    every = max(1, offsets.n // 200)  # brute force over every triple: a couple of hundred of them
    candidates = Viewpoints(offsets.positions[::every].copy(), None, "given", "every other normal offset")
    targets = bridge.targets(spacing=2.0)
    return CoverageProblem(uavcov.Visibility(bridge.surface, 15.0, targets, n_threads=2), candidates, n_threads=2)


def _brute_force(problem: CoverageProblem, k: int, d_safe: float, candidates: np.ndarray) -> float:
    """The best weighted share of ``k`` of ``candidates`` kept ``d_safe`` apart, over every k-subset."""
    seen = problem.dense()[candidates]
    weights = problem._visibility.targets.weights
    shares = weights / weights.sum()
    positions = problem.viewpoints.positions[candidates]
    close = np.linalg.norm(positions[:, None] - positions[None], axis=2) < d_safe
    best = 0.0
    for combo in itertools.combinations(range(len(candidates)), k - 1):
        if any(close[a, b] for a, b in itertools.combinations(combo, 2)):
            continue
        union = seen[list(combo)].any(axis=0)
        last = [c for c in range(combo[-1] + 1 if combo else 0, len(candidates)) if not close[c, list(combo)].any()]
        if last:
            best = max(best, float(((seen[last] | union) @ shares).max()))
    return best


@pytest.mark.parametrize("k, d_safe, step", [(1, 0.0, 1), (2, 4.0, 1), (3, 4.0, 3), (3, 0.0, 3)])
def test_equals_brute_force_on_a_terrain(k: int, d_safe: float, step: int) -> None:
    problem = _terrain_problem()
    subset = np.arange(0, problem.viewpoints.n, step)
    small = CoverageProblem(
        problem._visibility, Viewpoints(problem.viewpoints.positions[subset].copy(), None, "given", "subset"), n_threads=2
    )
    assert 100 <= small.viewpoints.n <= 500
    best = exact_placement(small, k, d_safe)
    expected = _brute_force(small, k, d_safe, np.arange(small.viewpoints.n))
    assert best.status == "optimal"
    assert math.isclose(best.coverage, expected, rel_tol=1e-12, abs_tol=1e-14), (best.coverage, expected)
    assert best.coverage <= best.bound <= best.coverage * (1 + 1e-4) + 1e-12
    assert best.coverage >= best.greedy_coverage
    _assert_separated(best.positions, d_safe)
    assert best.picks.size == k


@pytest.mark.parametrize("k", [2, 3])
def test_equals_brute_force_on_a_structure(k: int) -> None:
    problem = _bridge_problem()
    assert 100 <= problem.viewpoints.n <= 400, problem.viewpoints.n
    best = exact_placement(problem, k, 1.0)
    expected = _brute_force(problem, k, 1.0, np.arange(problem.viewpoints.n))
    assert best.status == "optimal"
    assert math.isclose(best.coverage, expected, rel_tol=1e-12), (best.coverage, expected)
    _assert_separated(best.positions, 1.0)


def _assert_separated(positions: np.ndarray, d_safe: float) -> None:
    for a, b in itertools.combinations(range(len(positions)), 2):
        assert np.linalg.norm(positions[a] - positions[b]) >= d_safe


def test_never_below_greedy_and_the_bound_holds_when_stopped_early() -> None:
    problem = _terrain_problem()
    for k, d_safe in [(4, 0.0), (6, 3.5), (9, 4.0)]:
        stopped = exact_placement(problem, k, d_safe, node_limit=1)
        full = exact_placement(problem, k, d_safe)
        greedy = problem.greedy(k, d_safe)
        for result in (stopped, full):
            assert result.coverage >= greedy.coverage
            assert result.greedy_coverage == greedy.coverage
            assert result.coverage <= result.bound <= 1.0
            assert result.gap == result.bound - result.coverage
            assert result.status in _exact.STATUSES
            _assert_separated(result.positions, d_safe)
        assert full.status == "optimal"
        assert stopped.bound >= full.coverage - 1e-12  # the early bound holds for the optimum too
        assert stopped.status == "optimal" or stopped.gap > 0


def test_the_same_answer_for_any_thread_count_and_it_pickles() -> None:
    one = exact_placement(_terrain_problem(n_threads=1), 5, 3.5)
    two = exact_placement(_terrain_problem(n_threads=2), 5, 3.5)
    assert np.array_equal(one.picks, two.picks)
    assert (one.coverage, one.bound, one.status, one.n_rows) == (two.coverage, two.bound, two.status, two.n_rows)
    again = pickle.loads(pickle.dumps(one))
    assert np.array_equal(again.picks, one.picks) and again.coverage == one.coverage


def test_aggregated_separation_rows_have_the_same_optimum(monkeypatch: pytest.MonkeyPatch) -> None:
    problem = _terrain_problem()
    monkeypatch.setattr(_exact, "_PAIRS_PER_CANDIDATE", 10**9)
    pairwise = exact_placement(problem, 5, 6.5)
    monkeypatch.setattr(_exact, "_PAIRS_PER_CANDIDATE", 0)
    aggregated = exact_placement(problem, 5, 6.5)
    assert aggregated.n_conflict_rows < pairwise.n_conflict_rows
    assert math.isclose(aggregated.coverage, pairwise.coverage, rel_tol=1e-12)
    _assert_separated(aggregated.positions, 6.5)


def test_aggregated_separation_rows_accept_the_same_placements(monkeypatch: pytest.MonkeyPatch) -> None:
    positions = _terrain_problem().viewpoints.positions
    pairs = _exact.conflict_pairs(positions, 6.5)
    monkeypatch.setattr(_exact, "_PAIRS_PER_CANDIDATE", 10**9)
    pairwise, upper = _exact._conflict_rows(pairs, len(positions))
    monkeypatch.setattr(_exact, "_PAIRS_PER_CANDIDATE", 0)
    aggregated, aggregated_upper = _exact._conflict_rows(pairs, len(positions))
    assert aggregated.shape[0] < pairwise.shape[0] == len(pairs)
    rng = np.random.default_rng(1)
    for _ in range(300):
        x = np.zeros(len(positions))
        x[rng.choice(len(positions), size=rng.integers(1, 6), replace=False)] = 1.0
        separated = all(np.linalg.norm(positions[a] - positions[b]) >= 6.5 for a, b in itertools.combinations(np.flatnonzero(x), 2))
        assert np.all(pairwise @ x <= upper) == separated == np.all(aggregated @ x <= aggregated_upper)


def test_target_groups_are_the_targets_of_equal_columns() -> None:
    rng = np.random.default_rng(0)
    seen = rng.random((70, 400)) < 0.1
    seen[:, 200:] = seen[:, :200]  # every target has a twin
    first, group = _exact.target_groups(seen)
    assert np.array_equal(first, np.sort(first))
    for t in range(seen.shape[1]):
        assert np.array_equal(seen[:, t], seen[:, first[group[t]]])
    assert len(first) == len({seen[:, t].tobytes() for t in range(seen.shape[1])}) <= 200


def test_a_time_limit_gives_a_stated_gap_not_a_hang() -> None:
    problem = _terrain_problem()
    result = exact_placement(problem, 8, 0.0, time_limit=1e-3)
    assert result.status in ("optimal", "time limit")
    assert result.coverage <= result.bound and result.gap >= 0.0
    assert result.solve_time_s < 30.0


@pytest.mark.parametrize(
    "kwargs, error",
    [
        ({"k": 0}, InvalidInputError),
        ({"k": 2.5}, InvalidTypeError),
        ({"k": "3"}, InvalidTypeError),
        ({"d_safe": math.nan}, InvalidInputError),
        ({"d_safe": -1.0}, InvalidInputError),
        ({"time_limit": 0.0}, InvalidInputError),
        ({"time_limit": math.nan}, InvalidInputError),
        ({"gap": -1e-3}, InvalidInputError),
        ({"gap": math.inf}, InvalidInputError),
        ({"node_limit": 0}, InvalidInputError),
        ({"node_limit": 1 << 60}, InvalidInputError),
        ({"max_model_bytes": 0}, InvalidInputError),
        ({"max_model_bytes": True}, InvalidTypeError),
        ({"max_model_bytes": 1e300}, InvalidTypeError),
        ({"max_model_bytes": 1000}, ModelTooLargeError),
    ],
)
def test_bad_input_is_a_clear_error(kwargs: dict[str, Any], error: type[Exception]) -> None:
    problem = _terrain_problem()
    arguments: dict[str, Any] = {"k": 3, **kwargs}
    k = arguments.pop("k")
    with pytest.raises(error):
        exact_placement(problem, k, **arguments)


def test_refuses_what_is_not_a_coverage_problem() -> None:
    with pytest.raises(InvalidTypeError):
        exact_placement("problem", 3)  # type: ignore[arg-type]


def test_the_oracle_solves_the_optimum_and_the_report_sets_each_start_against_it(tmp_path: Any) -> None:
    from uavcov.experiments._results import ResultsFolder
    from uavcov.paper import TABLE1, oracle
    from uavcov.paper._bounds import bounds_markdown, read_bounds, write_bounds

    small = TABLE1.with_changes(**{"terrain.size": 40.0})
    plain = oracle(small, seeds=[0], team_sizes=[2, 3], settings=GreedySettings(spacing=5.0), n_threads=2)
    rows = oracle(small, seeds=[0], team_sizes=[2, 3], settings=GreedySettings(spacing=5.0), n_threads=2, exact=True)
    for row, without in zip(rows, plain, strict=True):
        assert row.optimum_status == "optimal" and not without.optimum_status and without.optimum is None
        assert row.optimum is not None and row.optimum_bound is not None
        assert row.coverage <= row.optimum <= row.optimum_bound <= row.bound + 1e-12
        assert (row.coverage, row.bound) == (without.coverage, without.bound)  # the other columns do not move
    folder = ResultsFolder(tmp_path / "with")
    assert read_bounds(write_bounds(folder, rows)) == rows
    old = write_bounds(ResultsFolder(tmp_path / "without"), plain)
    assert "optimum" not in old.read_text().splitlines()[0] and read_bounds(old) == plain
    runs = [{"seed": 0, "n_uavs": r.n_uavs, "init": "cvt", "max_coverage": 0.9 * r.optimum, "error": ""} for r in rows]
    text = bounds_markdown(runs, rows)
    assert "## Table 1 against the lattice optimum" in text
    assert "| 2 | 1 | 1 |" in text and "| 0.900 |" in text
    assert "lattice optimum" not in bounds_markdown(runs, plain)


def test_greedy_proved_optimal_by_its_bound_needs_no_program() -> None:
    problem = _terrain_problem()
    everyone = exact_placement(problem, problem.viewpoints.n)  # every candidate: greedy reaches the ceiling
    assert everyone.status == "optimal" and everyone.n_rows == 0 and everyone.incumbent == "greedy"
    assert everyone.coverage == everyone.bound == problem.ceiling()


def _table1_problem() -> tuple[CoverageProblem, float]:
    """Table 1's first terrain on its 5 m lattice (1,323 candidates): a program HiGHS cannot finish in seconds."""
    from uavcov.paper import TABLE1

    terrain = TABLE1.terrain.make(0)
    limits = TABLE1.mission.constraints.resolve(terrain)
    lattice = viewpoint_lattice(terrain, limits, GreedySettings(spacing=5.0, n_heights=3), n_threads=2)
    return CoverageProblem(uavcov.Visibility(terrain, TABLE1.d_max, n_threads=2), lattice, n_threads=2), limits.d_safe


def test_a_tight_limit_on_a_large_instance_returns_its_incumbent_with_a_stated_gap() -> None:
    problem, d_safe = _table1_problem()
    started = time.perf_counter()
    result = exact_placement(problem, 8, d_safe, time_limit=3.0)
    wall = time.perf_counter() - started
    assert result.status == "time limit" and result.gap > 0.0
    assert result.solver in ("not run", "killed at the deadline", "stopped at its limit")
    assert result.greedy_coverage <= result.coverage < result.bound <= problem.greedy(8, d_safe).bound
    assert wall < 3.0 + 30.0  # a hang check (the limit is hard: the solver's child is killed), not a speed test
    _assert_separated(result.positions, d_safe)


def test_the_solver_child_is_killed_at_the_deadline() -> None:
    from uavcov.cover._bounded_milp import _GRACE_S, bounded_milp

    problem, d_safe = _table1_problem()
    seen = problem.dense()
    shares = problem._visibility.targets.weights / problem._visibility.targets.weights.sum()
    model = _exact._model(problem, seen, shares, np.arange(seen.shape[0]), d_safe, 8, exactly=True, max_model_bytes=1 << 32)
    assert model is not None
    arguments = {"c": model.cost, "integrality": model.integrality, "bounds": model.bounds, "constraints": model.constraints}
    started = time.perf_counter()
    outcome = bounded_milp({**arguments, "options": {"presolve": True}}, started + 0.2)
    assert outcome.killed or outcome.status == 1  # killed, or stopped by its own (shorter) limit
    assert not outcome.killed or (outcome.x is None and math.isnan(outcome.dual_bound))
    assert time.perf_counter() - started < 0.2 + _GRACE_S + 10.0  # hang check
    assert bounded_milp(arguments, started - 1.0).killed  # no time left: no child at all


def test_swaps_never_lose_coverage_and_keep_the_separation() -> None:
    from scipy.sparse import coo_matrix

    from uavcov.cover._swap_search import swap_search

    problem = _terrain_problem()
    seen = problem.dense()
    shares = problem._visibility.targets.weights / problem._visibility.targets.weights.sum()
    for k, d_safe in [(3, 0.0), (5, 4.0), (8, 6.5)]:
        greedy = problem.greedy(k, d_safe)
        pairs = _exact.conflict_pairs(problem.viewpoints.positions, d_safe)
        both = np.concatenate([pairs, pairs[:, ::-1]])
        n = seen.shape[0]
        conflicts = coo_matrix((np.ones(len(both)), (both[:, 0], both[:, 1])), shape=(n, n)).tocsc() if pairs.size else None
        picks = swap_search(seen.astype(np.float64), shares, greedy.picks, conflicts, time.perf_counter() + 60.0)
        assert picks.size == k == np.unique(picks).size
        assert seen[picks].any(axis=0) @ shares >= greedy.coverage - 1e-12
        _assert_separated(problem.viewpoints.positions[picks], d_safe)


def test_dominated_candidates_are_those_another_sees_more_than() -> None:
    from uavcov.cover._swap_search import undominated

    columns = np.array(
        [
            [1, 1, 0, 0],  # inside candidate 2's
            [0, 0, 1, 1],  # kept: nobody sees both its groups but candidate 3, which is its twin with a higher index
            [1, 1, 1, 0],
            [0, 0, 1, 1],  # dominated by its twin 1 (the lower index stays)
            [0, 0, 0, 0],  # sees nothing
        ],
        dtype=bool,
    )
    assert undominated(columns, 2, time.perf_counter() + 60.0).tolist() == [False, True, True, False, False]
    assert undominated(columns, 3, time.perf_counter() + 60.0).all()  # fewer than k left: all kept


def test_the_sweep_summary_counts_proved_gaps_and_the_overshoot() -> None:
    from uavcov.paper import OracleRow
    from uavcov.paper._bounds import optimum_sweep_markdown

    def row(seed: int, n: int, optimum: float, bound: float, status: str, seconds: float) -> OracleRow:
        return OracleRow(seed, n, 0.5, 1.0, 1.0, 10, 0.1, 0.1, "", 1.0, 1.0, 0.1, optimum, bound, status, seconds)

    rows = [
        row(0, 5, 0.7, 0.7, "optimal", 2.0),
        row(1, 5, 0.7, 0.7005, "time limit", 61.5),  # relative gap 7.1e-4
        row(0, 8, 0.9, 0.91, "time limit", 60.5),
        OracleRow(1, 8, 0.5, 1.0, 1.0, 10, 0.1, 0.1, "", 1.0, 1.0, 0.1),  # without the optimum's columns: skipped
    ]
    lines = optimum_sweep_markdown(rows, 60.0).splitlines()
    assert lines[2].startswith("| 5 | 2 | 1 | 2 | ") and lines[2].endswith("| 61.5 | +1.5 |")
    assert lines[3].startswith("| 8 | 1 | 0 | 0 | 1.1e-02 | 1.1e-02 | 60.5 | 60.5 | +0.5 |")
    assert lines[4].startswith("| all | 3 | 1 | 2 | ")
