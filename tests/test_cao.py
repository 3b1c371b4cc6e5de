"""CAO: settings, the optimiser's contract, and what it reaches on problems with a known optimum."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from cao_reference import _design, _fit_and_score_numpy, _fit_and_score_robots_numpy, _ridge, _robot_design
from uavcov import CAOSettings
from uavcov.errors import InfeasibleError, InvalidInputError, InvalidTypeError
from uavcov.optim import MARGINAL_OPTIMIZERS, OPTIMIZERS, OptimizerTrace, cao, per_robot_cao
from uavcov.optim._escape import escape_cao
from uavcov.optim._monomials import _all_monomials, _draw_monomials, _n_distinct_monomials
from uavcov.optim._surrogate import _fit_and_score, _fit_and_score_robots


def quadratic(target: np.ndarray, weights: np.ndarray | None = None):
    """A concave quadratic with its maximum 0 at ``target`` (N, 3)."""
    w = np.ones_like(target) if weights is None else weights

    def f(x: np.ndarray) -> float:
        return -float(np.sum(w * (x - target) ** 2))

    return f


def marginal_quadratic(target: np.ndarray):
    """Team value and per-UAV parts of a separable quadratic, for the per-robot variant."""

    def f(x: np.ndarray):
        parts = -np.sum((x - target) ** 2, axis=1)
        return float(parts.sum()), parts

    return f


def run_both(measure_team, measure_marg, x0, **kwargs):
    return cao(measure_team, x0, **kwargs), per_robot_cao(measure_marg, x0, **kwargs)


# ---------------------------------------------------------------------------------------------
# Settings
# ---------------------------------------------------------------------------------------------


def test_default_settings_follow_the_setup_notes():
    s = CAOSettings()
    assert (s.history, s.n_candidates, s.alpha0, s.stability, s.decay) == (10, 200, 1.5, 50.0, 0.602)
    assert s.measurement_noise == 0.0
    assert s.regressors_for(5) == 1 + 15 + 10
    assert s.regressors_for(12) == 1 + 36 + 12
    assert s.regressors_for(20) == 1 + 60 + 20
    assert s.robot_regressors_value() == 10
    r = s.resolved(12)
    assert r.n_regressors == 49 and r.robot_regressors == 10
    assert pickle.loads(pickle.dumps(r)) == r


def test_step_sizes_follow_the_formula_and_the_conditions():
    s = CAOSettings(alpha0=2.0, stability=10.0, decay=0.7)
    k = np.arange(5000)
    alpha = s.step_size(k)
    np.testing.assert_allclose(alpha, 2.0 * (11.0 / (k + 11.0)) ** 0.7)
    assert s.step_size(0) == 2.0
    assert np.all(np.diff(alpha) < 0)
    # the decay exponent in (0.5, 1] gives sum alpha = inf and sum alpha^2 < inf: the partial
    # sums of alpha grow like k^0.3, those of alpha^2 converge (tail bound of a p-series, p = 1.4)
    assert alpha[:5000].sum() > 1.9 * alpha[:500].sum()
    tail = 4.0 * 11.0**1.4 * 5000.0 ** (-0.4) / 0.4
    assert np.sum(alpha**2) < np.sum(alpha[:5000] ** 2) + tail


@pytest.mark.parametrize(
    "kwargs, error",
    [
        (dict(n_candidates=0), InvalidInputError),
        (dict(n_candidates=-3), InvalidInputError),
        (dict(n_candidates=2.5), InvalidTypeError),
        (dict(history=-1), InvalidInputError),
        (dict(alpha0=0.0), InvalidInputError),
        (dict(alpha0=math.nan), InvalidInputError),
        (dict(alpha0=math.inf), InvalidInputError),
        (dict(stability=-1.0), InvalidInputError),
        (dict(decay=math.nan), InvalidInputError),
        (dict(decay=-0.1), InvalidInputError),
        (dict(ridge=0.0), InvalidInputError),
        (dict(ridge=math.inf), InvalidInputError),
        (dict(measurement_noise=-0.01), InvalidInputError),
        (dict(measurement_noise=math.nan), InvalidInputError),
        (dict(keep_fraction=1.5), InvalidInputError),
        (dict(n_regressors=0), InvalidInputError),
        (dict(n_regressors=True), InvalidTypeError),
        (dict(robot_regressors=3), InvalidInputError),
        (dict(robot_regressors=21), InvalidInputError),
        (dict(perturbation="cauchy"), InvalidInputError),
        (dict(perturbation=1), InvalidTypeError),
    ],
)
def test_bad_settings_raise(kwargs, error):
    with pytest.raises(error):
        CAOSettings(**kwargs)


def test_regressor_count_is_checked_against_the_team():
    with pytest.raises(InvalidInputError, match="at least 1 \\+ 3N"):
        CAOSettings(n_regressors=10).regressors_for(5)
    assert CAOSettings(n_regressors=16).regressors_for(5) == 16  # linear model only
    with pytest.raises(InvalidInputError, match="distinct"):
        CAOSettings(n_regressors=1 + 3 + 17).regressors_for(1)  # 3 variables have 16 monomials
    with pytest.raises(InvalidInputError):
        cao(lambda x: 0.0, np.zeros((5, 3)), feasible=None, iterations=3, settings=CAOSettings(n_regressors=10))


# ---------------------------------------------------------------------------------------------
# The building blocks, against direct computations
# ---------------------------------------------------------------------------------------------


def test_monomials_are_distinct_and_of_degree_two_or_three():
    assert _n_distinct_monomials(3) == 16 == len(_all_monomials(3))
    assert _n_distinct_monomials(12) == len({tuple(r) for r in _all_monomials(12).tolist()})
    rng = np.random.default_rng(0)
    for dim in (3, 6, 30):
        terms = _draw_monomials(min(40, _n_distinct_monomials(dim)), dim, np.empty((0, 3), int), rng)
        rows = {tuple(r) for r in terms.tolist()}
        assert len(rows) == len(terms)
        assert np.all(np.diff(terms, axis=1) >= 0)  # sorted triples: a canonical form
        assert np.all(terms[:, :2] < dim) and np.all(terms[:, 2] <= dim)
    # every distinct monomial of 3 variables, when all are asked for
    all3 = _draw_monomials(16, 3, np.empty((0, 3), int), rng)
    assert {tuple(r) for r in all3.tolist()} == {tuple(r) for r in _all_monomials(3).tolist()}
    # new ones never repeat those kept, whether drawn from the full list (few variables) or by rejection
    for dim, n_kept, count in ((3, 8, 8), (3, 10, 3), (6, 20, 10), (30, 20, 20)):
        for _ in range(20):
            kept = _all_monomials(dim)[rng.choice(_n_distinct_monomials(dim), n_kept, replace=False)]
            fresh = _draw_monomials(count, dim, kept, rng)
            rows = {tuple(r) for r in fresh.tolist()}
            assert len(rows) == count and not rows & {tuple(r) for r in kept.tolist()}


def test_design_matrix_matches_explicit_products():
    rng = np.random.default_rng(1)
    u = rng.normal(size=(7, 4))
    terms = np.array([[0, 1, 4], [2, 2, 2], [1, 3, 3], [0, 0, 4]])  # u0 u1, u2^3, u1 u3^2, u0^2
    phi = _design(u, terms)
    expected = np.column_stack([np.ones(7), u, u[:, 0] * u[:, 1], u[:, 2] ** 3, u[:, 1] * u[:, 3] ** 2, u[:, 0] ** 2])
    np.testing.assert_allclose(phi, expected)
    # one term set per robot, as masks over the 16 monomials of 3 variables: the active
    # columns are those of the single-estimator path, the others are zero
    u3 = rng.normal(size=(2, 5, 3))
    selected = np.zeros((2, 16), dtype=bool)
    selected[0, [0, 5, 15, 7]] = True
    selected[1, [3, 2, 9, 11]] = True
    batched = _robot_design(u3, selected)
    for i in range(2):
        full = _design(u3[i], _all_monomials(3))
        np.testing.assert_allclose(batched[i][:, :4], full[:, :4])
        np.testing.assert_allclose(batched[i][:, 4:][:, selected[i]], full[:, 4:][:, selected[i]])
        assert np.all(batched[i][:, 4:][:, ~selected[i]] == 0.0)


@pytest.mark.parametrize("n_window", [0, 1, 7, 40, 91])
def test_the_rust_surrogate_gives_the_numpy_references_fit_and_scores(n_window):
    """Coefficients, candidate scores and monomial strengths agree to rounding, centralised
    (36 coordinates, 12 monomials) and per robot (5 robots, 6 of 16 monomials each)."""
    rng = np.random.default_rng(n_window)
    dim = 36
    terms = _draw_monomials(12, dim, np.empty((0, 3), dtype=np.int64), rng)
    window = rng.normal(size=(n_window, dim))
    values = 0.6 + 0.05 * rng.normal(size=n_window)
    candidates = 0.3 * rng.normal(size=(200, dim))
    for ridge in (1e-3, 10.0):
        got = _fit_and_score(window, values, terms, candidates, ridge)
        ref = _fit_and_score_numpy(window, values, terms, candidates, ridge)
        for a, b in zip(got, ref, strict=True):
            np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-12)
    active = np.zeros((5, 16), dtype=bool)
    for row in active:
        row[rng.choice(16, size=6, replace=False)] = True
    window3 = rng.normal(size=(5, n_window, 3))
    values3 = rng.normal(size=(5, n_window))
    candidates3 = 0.3 * rng.normal(size=(5, 50, 3))
    got = _fit_and_score_robots(np.swapaxes(window3, 0, 1).swapaxes(0, 1), values3, active, candidates3, 1e-3)
    ref = _fit_and_score_robots_numpy(window3, values3, active, candidates3, 1e-3)
    for a, b in zip(got, ref, strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-12)
    assert np.all(got[0][:, 4:][~active] == 0.0)  # inactive monomials have no coefficient


@pytest.mark.parametrize("optimizer", ["cao", "per_robot"])
def test_runs_on_the_rust_and_the_numpy_kernels_are_the_same(monkeypatch, optimizer):
    """Same random streams: 40 iterations of a coverage mission end at the same positions (longer
    runs may part where rounding flips a near-tie between candidates)."""
    import sys

    from uavcov import MissionSettings, gaussian_hills, run_mission

    terrain = gaussian_hills(spacing=2.0, rng=4)
    spec = MissionSettings(n_uavs=6, d_max=20.0, iterations=40, optimizer=optimizer)
    rust = run_mission(terrain, spec, rng=4, n_threads=1)
    monkeypatch.setattr(sys.modules["uavcov.optim._cao"], "_fit_and_score", _fit_and_score_numpy)
    monkeypatch.setattr(sys.modules["uavcov.optim._per_robot"], "_fit_and_score_robots", _fit_and_score_robots_numpy)
    reference = run_mission(terrain, spec, rng=4, n_threads=1)
    np.testing.assert_allclose(rust.trace.trajectory, reference.trace.trajectory, rtol=0, atol=1e-9)
    np.testing.assert_allclose(rust.coverage, reference.coverage, rtol=0, atol=1e-12)


def test_the_rust_surrogate_refuses_bad_arrays():
    from uavcov import _core

    terms = np.array([[0, 1, 2]], dtype=np.int64)
    good = (np.zeros((4, 2)), np.zeros(4), terms, np.zeros((3, 2)), 1e-3)
    assert _core.Surrogate.fit(*good)[1].shape == (3,)
    bad = [
        (np.zeros((4, 2)), np.zeros(3), terms, np.zeros((3, 2)), 1e-3),  # values of another length
        (np.zeros((4, 2)), np.zeros(4), terms, np.zeros((3, 3)), 1e-3),  # candidates of another dimension
        (np.zeros((4, 2)), np.zeros(4), np.array([[0, 1, 3]]), np.zeros((3, 2)), 1e-3),  # index beyond the one
        (np.zeros((4, 2)), np.zeros(4), np.array([[0, -1, 2]]), np.zeros((3, 2)), 1e-3),  # negative index
        (np.full((4, 2), np.nan), np.zeros(4), terms, np.zeros((3, 2)), 1e-3),
        (np.zeros((4, 2)), np.zeros(4), terms, np.zeros((3, 2)), 0.0),
    ]
    for args in bad:
        with pytest.raises(InvalidInputError):
            _core.Surrogate.fit(*args)
    all3 = _all_monomials(3)
    with pytest.raises(InvalidInputError):
        _core.Surrogate.fit_robots(np.zeros((2, 4, 3)), np.zeros((2, 4)), all3, np.ones((3, 16), bool), np.zeros((2, 5, 3)), 1e-3)


def test_zero_columns_do_not_change_a_ridge_fit():
    rng = np.random.default_rng(5)
    phi = np.column_stack([np.ones(12), rng.normal(size=(12, 4))])
    y = rng.normal(size=12)
    padded = np.column_stack([phi[:, :3], np.zeros(12), phi[:, 3:], np.zeros((12, 2))])
    a = _ridge(phi, y, 1e-2)
    b = _ridge(padded, y, 1e-2)
    np.testing.assert_allclose(b[[0, 1, 2, 4, 5]], a, rtol=1e-12, atol=1e-14)
    assert np.all(b[[3, 6, 7]] == 0.0)


def test_ridge_fit_matches_an_augmented_least_squares_solve():
    scipy_linalg = pytest.importorskip("scipy.linalg")
    rng = np.random.default_rng(2)
    x = rng.normal(size=(30, 6))
    y = 3.0 + x @ rng.normal(size=6) + 0.1 * rng.normal(size=30)
    phi = np.column_stack([np.ones(30), x])
    for ridge in (1e-3, 0.5):
        theta = _ridge(phi, y, ridge)
        # mean(r^2) + ridge |theta[1:]|^2 is the plain least squares of the stacked system
        # [phi / sqrt(n); sqrt(ridge) [0 I]] theta = [y / sqrt(n); 0], solved by SVD here
        penalty = np.sqrt(ridge) * np.eye(7)[1:]
        a = np.vstack([phi / np.sqrt(30), penalty])
        b = np.concatenate([y / np.sqrt(30), np.zeros(6)])
        ref = scipy_linalg.lstsq(a, b)[0]
        np.testing.assert_allclose(theta, ref, rtol=1e-9, atol=1e-11)
    # the penalty shrinks the slope, never the constant: a large ridge leaves the mean
    flat = _ridge(phi, y, 1e9)
    assert flat[0] == pytest.approx(y.mean()) and np.abs(flat[1:]).max() < 1e-6
    # a single sample: the constant only, no NaN
    theta = _ridge(phi[:1], y[:1], 1e-3)
    assert theta[0] == pytest.approx(y[0]) and np.all(theta[1:] == 0.0)


# ---------------------------------------------------------------------------------------------
# The optimiser's contract
# ---------------------------------------------------------------------------------------------


def test_trace_shapes_bookkeeping_and_pickling():
    target = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
    calls = []

    def measure(x):
        calls.append(x.copy())
        return quadratic(target)(x)

    tr = cao(measure, np.zeros((2, 3)), feasible=None, iterations=40, rng=0)
    assert isinstance(tr, OptimizerTrace) and tr.kind == "cao"
    assert tr.trajectory.shape == (41, 2, 3) and tr.values.shape == (41,) and tr.step_sizes.shape == (40,)
    assert tr.evaluations == len(calls) == 41 and tr.n_iterations == 40
    # values are exactly what measure returned at the recorded positions
    np.testing.assert_array_equal(np.stack(calls), tr.trajectory)
    np.testing.assert_array_equal(tr.values, [quadratic(target)(x) for x in tr.trajectory])
    np.testing.assert_array_equal(tr.measured, tr.values)  # no noise asked for
    np.testing.assert_allclose(tr.step_sizes, CAOSettings().step_size(np.arange(40)))
    assert tr.best_value == tr.values.max() and tr.best_iteration == int(np.argmax(tr.values))
    np.testing.assert_array_equal(tr.best_positions, tr.trajectory[tr.best_iteration])
    np.testing.assert_array_equal(tr.final_positions, tr.trajectory[-1])
    # iterations 0 and 1 fit no sample and one (eq. 4's window ends at k - 1): a flat
    # surrogate, all 200 candidates tie and all are checked; afterwards the first batch of 16
    # settles it (nothing is infeasible)
    assert np.all(tr.n_checked[:2] == 200) and np.all(tr.n_checked[2:] == 16)
    np.testing.assert_array_equal(tr.n_feasible, tr.n_checked)
    assert tr.settings.n_regressors == 1 + 6 + 10
    assert min(tr.time_measure_s, tr.time_feasibility_s, tr.time_optimizer_s) >= 0.0
    with pytest.raises(ValueError, match="read-only"):
        tr.trajectory[0, 0, 0] = 1.0
    back = pickle.loads(pickle.dumps(tr))
    np.testing.assert_array_equal(back.trajectory, tr.trajectory)
    assert back.best_value == tr.best_value and back.settings == tr.settings


def test_every_move_is_a_perturbation_of_size_alpha():
    # with Gaussian zeta, (x_{k+1} - x_k) / alpha_k over all coordinates has a spread ~1
    tr = cao(quadratic(np.zeros((4, 3))), np.full((4, 3), 5.0), feasible=None, iterations=60, rng=3)
    steps = np.diff(tr.trajectory, axis=0).reshape(60, 12) / tr.step_sizes[:, None]
    moved = np.any(steps != 0.0, axis=1)
    assert moved.sum() >= 55
    assert 0.6 < steps[moved].std() < 1.8


def test_zero_iterations_measures_the_start_once():
    tr = cao(lambda x: 0.25, np.ones((3, 3)), feasible=None, iterations=0, rng=0)
    assert tr.trajectory.shape == (1, 3, 3) and tr.evaluations == 1 and tr.best_value == 0.25
    assert tr.step_sizes.shape == (0,) and tr.n_feasible.shape == (0,)


@pytest.mark.parametrize("optimizer", [cao, per_robot_cao])
def test_same_seed_same_trajectory_and_different_seeds_differ(optimizer):
    target = np.array([[3.0, -1.0, 2.0], [0.0, 4.0, 1.0], [-2.0, 2.0, 5.0]])
    measure = quadratic(target) if optimizer is cao else marginal_quadratic(target)
    s = CAOSettings(measurement_noise=0.5)
    kw = dict(feasible=None, iterations=60, settings=s)
    a = optimizer(measure, np.zeros((3, 3)), rng=7, **kw)
    b = optimizer(measure, np.zeros((3, 3)), rng=np.random.default_rng(7), **kw)
    c = optimizer(measure, np.zeros((3, 3)), rng=8, **kw)
    np.testing.assert_array_equal(a.trajectory, b.trajectory)
    np.testing.assert_array_equal(a.measured, b.measured)
    assert not np.array_equal(a.trajectory, c.trajectory)


@pytest.mark.parametrize("optimizer", [cao, per_robot_cao])
def test_noise_is_added_to_what_the_optimiser_sees_only(optimizer):
    target = np.zeros((2, 3))
    measure = quadratic(target) if optimizer is cao else marginal_quadratic(target)
    tr = optimizer(measure, np.ones((2, 3)), feasible=None, iterations=200, settings=CAOSettings(measurement_noise=0.3), rng=1)
    truth = np.array([quadratic(target)(x) for x in tr.trajectory])
    np.testing.assert_allclose(tr.values, truth)
    noise = tr.measured - tr.values
    assert 0.2 < noise.std() < 0.4 and abs(noise.mean()) < 0.1
    assert tr.best_value == pytest.approx(truth.max(), rel=1e-12)  # best by the noise-free value
    assert tr.best_iteration == int(np.argmax(truth))


@pytest.mark.parametrize("optimizer", [cao, per_robot_cao])
def test_best_so_far_never_decreases_even_when_coverage_falls(optimizer):
    rng = np.random.default_rng(4)
    target = rng.normal(size=(3, 3))
    measure = quadratic(target) if optimizer is cao else marginal_quadratic(target)
    tr = optimizer(measure, np.full((3, 3), 3.0), feasible=None, iterations=150, settings=CAOSettings(measurement_noise=2.0), rng=5)
    best = tr.best_so_far()
    assert np.all(np.diff(best) >= 0.0)
    assert best[-1] == tr.best_value
    assert np.any(np.diff(tr.values) < 0.0)  # the run itself does go down at times


def test_a_flat_objective_does_not_freeze_the_team():
    # every measurement equal: the surrogate is flat, ties are broken at random, so the team
    # keeps exploring instead of choosing "stay" for ever
    for optimizer, measure in ((cao, lambda x: 0.5), (per_robot_cao, lambda x: (0.5, np.zeros(len(x))))):
        tr = optimizer(measure, np.zeros((3, 3)), feasible=None, iterations=30, rng=0)
        moved = np.any(np.diff(tr.trajectory, axis=0) != 0.0, axis=(1, 2))
        assert moved.sum() >= 28


# ---------------------------------------------------------------------------------------------
# Feasibility
# ---------------------------------------------------------------------------------------------


class RecordingHalfSpace:
    """Feasible when every UAV keeps x + y <= limit; records what it was asked and answered."""

    def __init__(self, limit: float):
        self.limit = limit
        self.calls: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []

    def __call__(self, current, candidates):
        mask = np.all(candidates[..., 0] + candidates[..., 1] <= self.limit, axis=1)
        self.calls.append((current.copy(), candidates.copy(), mask.copy()))
        return mask


@pytest.mark.parametrize("optimizer", [cao, per_robot_cao])
def test_infeasible_candidates_are_never_chosen(optimizer):
    # the maximum lies outside the feasible half-space: the team presses against its border
    target = np.array([[6.0, 6.0, 1.0], [8.0, 2.0, 0.0]])
    measure = quadratic(target) if optimizer is cao else marginal_quadratic(target)
    feasible = RecordingHalfSpace(limit=5.0)
    x0 = np.array([[0.0, 0.0, 0.0], [1.0, -2.0, 0.0]])
    # every candidate checked at once: one call per iteration for CAO; per robot, one for every
    # UAV's own moves and, when some UAV moves, one for the team's
    tr = optimizer(measure, x0, feasible=feasible, iterations=200, settings=CAOSettings(check_batch=None), rng=2)
    assert np.all(tr.trajectory[..., 0] + tr.trajectory[..., 1] <= 5.0)
    calls = iter(feasible.calls[1:])  # call 0 checks the start
    for k in range(200):
        these = [next(calls)]
        while sum(len(c[1]) for c in these) < tr.n_checked[k]:
            these.append(next(calls))
        assert tr.n_checked[k] == sum(len(c[1]) for c in these) and tr.n_feasible[k] == sum(c[2].sum() for c in these)
        current, candidates, mask = these[-1]  # the call that decides the move
        np.testing.assert_array_equal(current, tr.trajectory[k])
        nxt = tr.trajectory[k + 1]
        chosen = np.flatnonzero(np.all(candidates == nxt, axis=(1, 2)))
        assert (chosen.size >= 1 and mask[chosen].all()) or (len(these) == 1 and np.array_equal(nxt, current))
    assert next(calls, None) is None
    assert tr.n_feasible.min() < tr.n_checked.max() // 2  # the constraint did bind
    # and it gets close to the constrained optimum (UAV 0 to the line x + y = 5)
    assert tr.best_positions[0, 0] + tr.best_positions[0, 1] > 4.0


@pytest.mark.parametrize("optimizer", [cao, per_robot_cao])
def test_lazy_feasibility_checks_choose_exactly_as_checking_everything(optimizer):
    target = np.array([[6.0, 6.0, 1.0], [8.0, 2.0, 0.0], [0.0, 9.0, 2.0]])
    measure = quadratic(target) if optimizer is cao else marginal_quadratic(target)
    x0 = np.array([[0.0, 0.0, 0.0], [1.0, -2.0, 0.0], [-3.0, 3.0, 0.0]])
    runs = {}
    for batch in (None, 1, 16, 150):
        feasible = RecordingHalfSpace(limit=5.0)
        tr = optimizer(measure, x0, feasible=feasible, iterations=150, settings=CAOSettings(check_batch=batch), rng=4)
        runs[batch] = (tr, sum(len(c[1]) for c in feasible.calls[1:]))
    full, full_checked = runs[None]
    for batch in (1, 16, 150):
        tr, checked = runs[batch]
        np.testing.assert_array_equal(tr.trajectory, full.trajectory)
        assert checked == tr.n_checked.sum() <= full_checked
        assert np.all(tr.n_feasible <= full.n_feasible)
    # even with the optimum outside the feasible set (the best-rated candidates are often
    # infeasible), the lazy default checks fewer candidates
    assert runs[16][1] < full_checked


@pytest.mark.parametrize("optimizer", [cao, per_robot_cao])
def test_when_nothing_is_feasible_the_team_stays_and_the_run_ends(optimizer):
    answers = []

    def only_the_start(current, candidates):
        answers.append(len(candidates))
        return np.zeros(len(candidates), dtype=bool) if len(answers) > 1 else np.ones(len(candidates), bool)

    measure = (lambda x: 1.0) if optimizer is cao else (lambda x: (1.0, np.ones(len(x))))
    x0 = np.arange(6, dtype=float).reshape(2, 3)
    tr = optimizer(measure, x0, feasible=only_the_start, iterations=25, rng=0)
    assert sum(answers[1:]) == sum(tr.n_checked)  # each candidate checked once: never redrawn
    np.testing.assert_array_equal(tr.trajectory, np.broadcast_to(x0, (26, 2, 3)))
    np.testing.assert_array_equal(tr.n_feasible, np.zeros(25))
    if optimizer is cao:
        assert np.all((tr.n_checked >= 200) & (tr.n_checked <= 201))  # all M (+ "stay") tried, once
    else:
        assert np.all(tr.n_checked == 2 * 200)  # each UAV's M moves tried once; nothing left for the team


def test_infeasible_start_raises_before_measuring():
    measured = []

    def measure(x):
        measured.append(1)
        return 0.0

    with pytest.raises(InfeasibleError, match="closest_admissible"):
        cao(measure, np.zeros((2, 3)), feasible=lambda c, m: np.zeros(len(m), bool), iterations=5)
    assert not measured


# ---------------------------------------------------------------------------------------------
# Bad input: a clear error before any work
# ---------------------------------------------------------------------------------------------


def _never_called(x):
    raise AssertionError("measure must not be called on bad input")


@pytest.mark.parametrize("optimizer", [cao, per_robot_cao])
@pytest.mark.parametrize(
    "x0, kwargs, error",
    [
        (np.zeros((0, 3)), {}, InvalidInputError),  # N = 0
        (np.zeros((3, 2)), {}, InvalidInputError),  # wrong shape
        (np.zeros((2, 3, 1)), {}, InvalidInputError),
        (np.array([[0.0, np.nan, 0.0]]), {}, InvalidInputError),
        (np.array([[0.0, np.inf, 0.0]]), {}, InvalidInputError),
        (np.array([["a", "b", "c"]]), {}, InvalidTypeError),
        (np.zeros((2, 3)), dict(iterations=-1), InvalidInputError),
        (np.zeros((2, 3)), dict(iterations=2.0), InvalidTypeError),
        (np.zeros((2, 3)), dict(settings=dict(n_candidates=5)), InvalidTypeError),
        (np.zeros((2, 3)), dict(feasible="yes"), InvalidTypeError),
    ],
)
def test_bad_input_raises_before_any_work(optimizer, x0, kwargs, error):
    args = dict(feasible=None, iterations=10)
    args.update(kwargs)
    with pytest.raises(error):
        optimizer(_never_called, x0, **args)


def test_bad_callables_raise_clear_errors():
    with pytest.raises(InvalidTypeError):
        cao("coverage", np.zeros((2, 3)), feasible=None, iterations=3)
    with pytest.raises(InvalidInputError, match="iteration 0"):
        cao(lambda x: math.nan, np.zeros((2, 3)), feasible=None, iterations=3)
    with pytest.raises(InvalidTypeError):
        cao(lambda x: [0.5], np.zeros((2, 3)), feasible=None, iterations=3)
    with pytest.raises(InvalidInputError, match="bool"):
        cao(lambda x: 0.5, np.zeros((2, 3)), feasible=lambda c, m: np.ones(len(m)), iterations=3)
    with pytest.raises(InvalidInputError, match="bool"):
        cao(lambda x: 0.5, np.zeros((2, 3)), feasible=lambda c, m: np.ones(3, bool), iterations=3)
    with pytest.raises(InvalidTypeError, match="marginals"):
        per_robot_cao(lambda x: 0.5, np.zeros((2, 3)), feasible=None, iterations=3)
    with pytest.raises(InvalidInputError, match="marginals"):
        per_robot_cao(lambda x: (0.5, np.zeros(3)), np.zeros((2, 3)), feasible=None, iterations=3)
    with pytest.raises(InvalidInputError, match="marginals"):
        per_robot_cao(lambda x: (0.5, np.array([0.1, np.nan])), np.zeros((2, 3)), feasible=None, iterations=3)


def test_registry():
    assert OPTIMIZERS["cao"] is cao and OPTIMIZERS["per_robot"] is per_robot_cao and OPTIMIZERS["escape"] is escape_cao
    assert isinstance(MARGINAL_OPTIMIZERS, frozenset) and set(MARGINAL_OPTIMIZERS) == {"per_robot", "escape"}
    with pytest.raises(TypeError):
        OPTIMIZERS["other"] = cao  # read-only


# ---------------------------------------------------------------------------------------------
# It optimises: smooth functions with a known maximum
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_centralised_cao_climbs_a_concave_quadratic(seed):
    rng = np.random.default_rng(100 + seed)
    target = rng.uniform(0.0, 20.0, size=(3, 3))
    f = quadratic(target)
    x0 = target + 8.0  # 8 m off in every coordinate: rms distance 13.9 m per UAV
    tr = cao(f, x0, feasible=None, iterations=400, rng=seed)
    start_rms = math.sqrt(-tr.values[0] / 3)
    best_rms = math.sqrt(-tr.best_value / 3)
    # the step size ends near 0.4 m per coordinate; within a few steps of the optimum
    assert best_rms < 2.0 < start_rms / 5
    # and most of the progress is made early: half the distance gone in 100 iterations
    assert math.sqrt(-tr.best_so_far()[100] / 3) < start_rms / 2


@pytest.mark.parametrize("seed", [0, 1])
def test_per_robot_cao_climbs_a_separable_quadratic(seed):
    rng = np.random.default_rng(200 + seed)
    target = rng.uniform(0.0, 20.0, size=(5, 3))
    tr = per_robot_cao(marginal_quadratic(target), target + 8.0, feasible=None, iterations=300, rng=seed)
    assert math.sqrt(-tr.best_value / 5) < 0.5
    assert tr.kind == "per_robot"


def test_anisotropic_quadratic_uses_the_fitted_slope():
    # a steep and a shallow direction: CAO must still reach the ridge of the steep one fast
    target = np.zeros((2, 3))
    weights = np.array([[10.0, 0.1, 1.0], [1.0, 10.0, 0.1]])
    f = quadratic(target, weights)
    x0 = np.full((2, 3), 6.0)
    tr = cao(f, x0, feasible=None, iterations=300, rng=0)
    assert tr.best_value > 0.01 * tr.values[0]


# ---------------------------------------------------------------------------------------------
# With the coverage engine: four UAVs on a flat plane, where the optimum is known
# ---------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def flat_plane_case():
    try:
        from uavcov import Terrain, Visibility
    except ImportError as exc:
        pytest.skip(f"uavcov engine not available: {exc}")
    from uavcov import Constraints
    from uavcov.limits import feasibility

    # a 44 m square at z = 0, 1 m targets; at h_min = 2 m a UAV sees a disk of radius 10 m.
    # Four such disks fit in the square without overlap, so the optimum is 4 pi 10^2 / 44^2
    # (up to the grid's discretisation) and no configuration can beat it by more than that.
    h_min, radius, size = 2.0, 10.0, 44.0
    terrain = Terrain.from_grid(np.zeros((45, 45)), 1.0)
    vis = Visibility(terrain, math.hypot(radius, h_min))
    optimum = 4.0 * math.pi * radius**2 / size**2
    # z_max = 8 m < d_max keeps every UAV within sensing range of the ground: above d_max a
    # UAV sees nothing, its coordinates no longer change the coverage, and CAO cannot bring it
    # back (with z_max = 30 m, 3 of 10 seeds lose a UAV that way from this corner start)
    constraints = Constraints.for_world(terrain, h_min=h_min, z_max=8.0, d_safe=2.0)
    corner = np.array([[1.0, 1.0, 5.0], [4.0, 1.0, 5.0], [1.0, 4.0, 5.0], [4.0, 4.0, 5.0]])
    return terrain, vis, optimum, constraints, feasibility(constraints, terrain), corner


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_flat_plane_four_uavs_from_the_corner_reach_95_percent(flat_plane_case, seed):
    from uavcov.limits._constraints import trajectory_feasible

    terrain, vis, optimum, constraints, feasible, corner = flat_plane_case
    tr = cao(vis.coverage, corner, feasible=feasible, iterations=500, rng=seed)
    assert tr.values[0] < 0.2 * optimum
    assert tr.best_value >= 0.95 * optimum
    assert tr.best_value <= optimum * 1.02  # the grid may add a little, never much
    # every constraint holds at every iteration, moves included
    assert trajectory_feasible(constraints, terrain, tr.trajectory).all()
    traj = tr.trajectory
    assert np.all(traj[..., 2] >= 2.0) and np.all(traj[..., 2] <= 8.0)
    assert np.all((traj[..., :2] >= 0.0) & (traj[..., :2] <= 44.0))
    d = np.linalg.norm(traj[:, :, None] - traj[:, None], axis=3)
    i, j = np.triu_indices(4, 1)
    assert d[:, i, j].min() >= 2.0
    # the best configuration spreads the UAVs over the four quadrants, low
    best = tr.best_positions
    quadrants = {(int(x > 22.0), int(y > 22.0)) for x, y in best[:, :2]}
    assert len(quadrants) == 4
    assert np.all(best[:, 2] < 4.0)


def test_flat_plane_per_robot_variant(flat_plane_case):
    terrain, vis, optimum, constraints, feasible, corner = flat_plane_case

    def measure(x):
        return vis.coverage(x), vis.per_uav(x).exclusive_share

    tr = per_robot_cao(measure, corner, feasible=feasible, iterations=400, rng=0)
    assert tr.best_value >= 0.95 * optimum
    from uavcov.limits._constraints import trajectory_feasible

    assert trajectory_feasible(constraints, terrain, tr.trajectory).all()


# ---------------------------------------------------------------------------------------------
# With the engine and the real constraints: every constraint at every iteration
# ---------------------------------------------------------------------------------------------


def _independent_constraint_check(terrain, constraints, traj):
    """Each rule of eq. 2 evaluated straight on the terrain, one iteration at a time."""
    xmin, ymin, xmax, ymax = constraints.bounds
    n = traj.shape[1]
    i, j = np.triu_indices(n, 1)
    for k in range(traj.shape[0]):
        x = traj[k]
        assert np.all((x[:, 0] >= xmin) & (x[:, 0] <= xmax) & (x[:, 1] >= ymin) & (x[:, 1] <= ymax)), k
        assert np.all(x[:, 2] <= constraints.z_max), k
        clearance = terrain.clearance(x)
        assert np.all(np.isfinite(clearance) & (clearance >= constraints.h_min)), k
        assert np.all(np.linalg.norm(x[i] - x[j], axis=1) >= constraints.d_safe), k
        if constraints.check_moves and k > 0:
            moved = np.any(traj[k - 1] != x, axis=1)
            if moved.any():
                assert terrain.segments_clear(traj[k - 1][moved], x[moved]).all(), k


@pytest.mark.parametrize("optimizer", ["cao", "per_robot"])
def test_constraints_hold_at_every_iteration_on_real_scenes(optimizer):
    try:
        from uavcov import Visibility, gaussian_hills
        from uavcov.terrain import buildings_scene
    except ImportError as exc:
        pytest.skip(f"uavcov engine not available: {exc}")
    from uavcov import Constraints
    from uavcov.limits import closest_admissible, feasibility

    hills = gaussian_hills(size=50.0, spacing=2.0, sigma=6.0, rng=1001)
    town = buildings_scene(size=24.0, spacing=1.0, rng=1002)
    cases = [
        # hills: UAVs start low in one corner, tight altitude band, safety distance that binds
        (hills, Constraints.for_world(hills, h_min=2.0, z_max=30.0, d_safe=3.0), 15.0, 5, [2.0, 2.0, 0.0]),
        # buildings: moves checked against walls and roofs
        (town, Constraints.for_world(town, h_min=1.0, z_max=16.0, d_safe=2.0, check_moves=True), 8.0, 4, [1.0, 1.0, 0.0]),
    ]
    for seed, (terrain, constraints, d_max, n, corner) in enumerate(cases):
        vis = Visibility(terrain, d_max)
        lattice = np.array([[a * 2.5, b * 2.5, 0.0] for a in range(3) for b in range(2)])[:n] + corner
        start = closest_admissible(constraints, terrain, lattice)
        if optimizer == "cao":
            measure = vis.coverage
        else:

            def measure(x, vis=vis):
                return vis.coverage(x), vis.per_uav(x).exclusive_share

        run = OPTIMIZERS[optimizer]
        tr = run(measure, start, feasible=feasibility(constraints, terrain), iterations=150, rng=seed)
        _independent_constraint_check(terrain, constraints, tr.trajectory)
        assert tr.best_value > tr.values[0]  # and it did improve the coverage
        assert np.any(tr.n_feasible < tr.n_checked)  # some candidates were refused along the way


@pytest.mark.parametrize("optimizer", ["cao", "per_robot"])
def test_each_fit_uses_the_window_of_eq_4(monkeypatch, optimizer):
    """Iteration k fits exactly the measurements l_k ... k - 1, l_k = max(0, k - L - T_h)."""
    import sys

    # the package exports the function cao under the name of its module
    module = sys.modules["uavcov.optim._cao" if optimizer == "cao" else "uavcov.optim._per_robot"]
    fits: list[np.ndarray] = []
    name = "_fit_and_score" if optimizer == "cao" else "_fit_and_score_robots"
    real_fit = getattr(module, name)

    def recording_fit(window, values, *args):
        fits.append(np.array(values, copy=True))
        return real_fit(window, values, *args)

    monkeypatch.setattr(module, name, recording_fit)
    top = np.array([[3.0, -2.0, 1.0], [-1.0, 4.0, 2.0]])
    settings = CAOSettings(history=3, n_candidates=30, robot_regressors=6, measurement_noise=0.1)
    if optimizer == "cao":
        trace = cao(lambda x: -float(np.sum((x - top) ** 2)), np.zeros((2, 3)), feasible=None, iterations=40, settings=settings, rng=5)
        n_window = settings.regressors_for(2) + 3
        seen = [trace.measured[max(0, k - n_window) : k] for k in range(40)]
    else:

        def measure(x):
            return -float(np.sum((x - top) ** 2)), -np.sum((x - top) ** 2, axis=1)

        trace = per_robot_cao(measure, np.zeros((2, 3)), feasible=None, iterations=40, settings=settings, rng=5)
        n_window = 6 + 3
        seen = [None] * 40  # the marginals are not in the trace: check the window lengths only
    assert len(fits) == 40
    for k, y in enumerate(fits):
        assert y.shape[-1] == min(k, n_window), k
        if seen[k] is not None:
            np.testing.assert_array_equal(y, seen[k])  # noisy values, and never x_k's own


def test_holding_an_inadmissible_uav_lets_the_others_move():
    # UAV 0 may never leave its start; UAV 1 may go anywhere. Dropping whole candidates freezes
    # the team (every candidate perturbs UAV 0); holding UAV 0 lets UAV 1 climb to its target.
    target = np.array([[5.0, 5.0, 5.0], [4.0, -3.0, 2.0]])
    x0 = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]])

    def uav0_stays(current, candidates):
        if candidates.shape[1] == 1 and not np.array_equal(current[0], x0[0]):
            return np.ones(len(candidates), dtype=bool)  # UAV 1 judged alone: anywhere is fine
        return np.all(candidates[:, 0] == x0[0], axis=1)  # the team, or UAV 0 alone

    settings = CAOSettings(check_batch=None)
    dropped = cao(quadratic(target), x0, feasible=uav0_stays, iterations=150, settings=settings, rng=3)
    np.testing.assert_array_equal(dropped.trajectory, np.broadcast_to(x0, dropped.trajectory.shape))
    held = cao(quadratic(target), x0, feasible=uav0_stays, iterations=150, settings=CAOSettings(check_batch=None, infeasible="hold"), rng=3)
    np.testing.assert_array_equal(held.trajectory[:, 0], np.zeros((151, 3)))  # UAV 0 held every time
    assert np.abs(held.best_positions[1] - target[1]).max() < 0.3  # UAV 1 reached its optimum
    with pytest.raises(InvalidInputError, match="infeasible"):
        CAOSettings(infeasible="clip")


def test_the_hold_rule_stays_out_of_the_papers_settings_hashes():
    from uavcov.experiments._sweep import experiment_settings, settings_hash
    from uavcov.paper import _data as paper

    for experiment in paper.EXPERIMENTS.values():
        assert "infeasible" not in experiment_settings(experiment)["mission"]["cao"]
    assert settings_hash(paper.TABLE1) == "e0746840"
    assert settings_hash(paper.TABLE1.with_changes(**{"cao.infeasible": "hold"})) != settings_hash(paper.TABLE1)
