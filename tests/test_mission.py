"""The two-step mission: prior -> S' -> start -> closest admissible -> CAO."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import uavcov
from uavcov.constraints import Constraints, trajectory_feasible
from uavcov.errors import InfeasibleError, InvalidInputError, InvalidTypeError, UavcovError
from uavcov.mission import iterations_to_fraction, run_mission
from uavcov.records import load_mission, save_mission


@pytest.fixture(scope="module")
def hills() -> uavcov.Terrain:
    return uavcov.gaussian_hills(spacing=2.0, rng=1001)


@pytest.fixture(scope="module")
def short_run(hills):
    return run_mission(hills, n_uavs=6, d_max=25.0, iterations=40, rng=7, n_threads=1)


def _constraints(result) -> Constraints:
    s = result.settings
    return Constraints.for_world(result.terrain, h_min=s.h_min, z_max=s.z_max, d_safe=s.d_safe, check_moves=s.check_moves)


@pytest.mark.parametrize("start", ["cvt", "random", "corner"])
def test_every_constraint_holds_at_every_iteration(hills, start):
    result = run_mission(hills, n_uavs=8, d_max=25.0, start=start, iterations=40, rng=3, n_threads=1)
    assert result.trajectory.shape == (41, 8, 3)
    assert trajectory_feasible(_constraints(result), hills, result.trajectory).all()
    # Checked again from the definitions, independently of the constraints module.
    t = result.trajectory.reshape(-1, 3)
    assert (hills.clearance(t) >= result.settings.h_min - 1e-9).all()
    assert (t[:, 2] <= result.settings.z_max + 1e-9).all()
    lo, hi = hills.bounds
    assert ((t[:, :2] >= lo[:2] - 1e-9) & (t[:, :2] <= hi[:2] + 1e-9)).all()
    for x in result.trajectory:
        d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
        assert d[np.triu_indices(8, 1)].min() >= result.settings.d_safe - 1e-9


def test_recorded_coverage_is_the_true_coverage(short_run):
    vis = uavcov.Visibility(short_run.terrain, short_run.settings.d_max)
    for k in (0, 10, 40):
        assert short_run.coverage[k] == vis.coverage(short_run.trajectory[k])
    assert short_run.best_coverage == short_run.coverage.max()
    assert short_run.initial_coverage == short_run.coverage[0]
    assert short_run.final_coverage == short_run.coverage[-1]
    np.testing.assert_array_equal(short_run.best_positions, short_run.trajectory[short_run.best_iteration])
    assert short_run.evaluations == 41


def test_best_so_far_never_decreases_and_iterations_to_95(short_run):
    best = np.maximum.accumulate(short_run.coverage)
    assert (np.diff(best) >= 0).all()
    k = short_run.iterations_to_95
    assert short_run.coverage[k] >= 0.95 * short_run.best_coverage
    assert (short_run.coverage[:k] < 0.95 * short_run.best_coverage).all()
    assert iterations_to_fraction(np.array([0.1, 0.5, 0.96, 1.0])) == 2


def test_same_seed_same_mission_and_other_seed_differs(hills, short_run):
    again = run_mission(hills, n_uavs=6, d_max=25.0, iterations=40, rng=7, n_threads=2)
    np.testing.assert_array_equal(again.trajectory, short_run.trajectory)
    np.testing.assert_array_equal(again.coverage, short_run.coverage)
    other = run_mission(hills, n_uavs=6, d_max=25.0, iterations=40, rng=8, n_threads=1)
    assert not np.array_equal(other.trajectory, short_run.trajectory)


def test_the_start_comes_from_the_approximating_surface(short_run):
    # The CVT generators lie on S' (not on the true surface), and the prior holds the 4 corners.
    s_prime = short_run.approximation
    gens = short_run.cvt.generators
    assert np.abs(s_prime.closest_point(gens) - gens).max() < 1e-6
    np.testing.assert_array_equal(short_run.start_positions, gens)
    assert short_run.prior_points.shape == (34, 3)
    corners = {(x, y) for x, y in short_run.prior_points[:, :2]}
    assert {(0.0, 0.0), (100.0, 0.0), (0.0, 100.0), (100.0, 100.0)} <= corners


def test_cvt_start_ends_higher_than_corner_start_on_average():
    cvt_best, corner_best = [], []
    for seed in (1000, 1001, 1002):
        terrain = uavcov.gaussian_hills(spacing=2.0, rng=seed)
        for start, out in (("cvt", cvt_best), ("corner", corner_best)):
            r = run_mission(terrain, n_uavs=8, d_max=25.0, start=start, iterations=60, rng=seed, n_threads=1)
            out.append(r.best_coverage)
    assert np.mean(cvt_best) > np.mean(corner_best) + 0.05


def test_pyramid_prior_and_given_surface_and_given_start(hills):
    pyramid = run_mission(hills, n_uavs=5, d_max=25.0, prior="pyramid", iterations=5, rng=1, n_threads=1)
    assert pyramid.prior_points.shape == (5, 3) and pyramid.settings.prior_kind == "pyramid"
    surface = run_mission(hills, n_uavs=5, d_max=25.0, prior=pyramid.approximation, iterations=5, rng=1)
    assert surface.settings.prior_kind == "surface" and surface.prior_points.shape == (0, 3)
    np.testing.assert_array_equal(surface.start_positions, pyramid.start_positions)
    start = np.array([[10.0, 10.0, 40.0], [30.0, 10.0, 40.0], [50.0, 10.0, 40.0], [70.0, 10.0, 40.0], [90.0, 10.0, 40.0]])
    given = run_mission(hills, n_uavs=5, d_max=25.0, start=start, iterations=3, rng=1)
    assert given.settings.start == "given" and given.cvt is None
    np.testing.assert_array_equal(given.trajectory[0], start)  # admissible as given: unchanged


def test_per_robot_optimizer_and_measurement_noise(hills):
    settings = uavcov.CAOSettings(measurement_noise=0.01)
    r = run_mission(hills, n_uavs=4, d_max=25.0, optimizer="per_robot", settings=settings, iterations=15, rng=2)
    assert r.settings.optimizer == "per_robot" and r.settings.cao.measurement_noise == 0.01
    assert not np.array_equal(r.trace.measured, r.trace.values)  # the optimiser saw noise
    vis = uavcov.Visibility(hills, 25.0)
    assert r.coverage[-1] == vis.coverage(r.trajectory[-1])  # the record did not


def test_buildings_scene_checks_moves():
    scene = uavcov.buildings_scene(rng=3)
    r = run_mission(scene, n_uavs=4, d_max=8.0, iterations=20, z_max=20.0, rng=3, n_threads=1)
    assert r.settings.check_moves
    t = r.trajectory
    assert scene.segments_clear(t[:-1].reshape(-1, 3), t[1:].reshape(-1, 3)).all()


def test_result_pickles_and_round_trips_through_a_file(short_run, tmp_path):
    back = pickle.loads(pickle.dumps(short_run))
    np.testing.assert_array_equal(back.trajectory, short_run.trajectory)
    path = save_mission(short_run, tmp_path / "run.npz")
    loaded = load_mission(path)
    np.testing.assert_array_equal(loaded.trajectory, short_run.trajectory)
    np.testing.assert_array_equal(loaded.cvt.generators, short_run.cvt.generators)
    np.testing.assert_array_equal(loaded.terrain.vertices, short_run.terrain.vertices)
    assert loaded.settings == short_run.settings
    assert loaded.best_coverage == short_run.best_coverage


def test_loading_a_bad_file_names_the_problem(tmp_path):
    with pytest.raises(uavcov.errors.ResultsFormatError, match="no run file"):
        load_mission(tmp_path / "missing.npz")
    np.savez(tmp_path / "other.npz", header=np.array('{"format": "someone-else/9"}'))
    with pytest.raises(uavcov.errors.ResultsFormatError, match="format"):
        load_mission(tmp_path / "other.npz")
    np.savez(tmp_path / "partial.npz", header=np.array('{"format": "uavcov.mission/1", "settings": {}}'))
    with pytest.raises(uavcov.errors.ResultsFormatError, match="scalars"):
        load_mission(tmp_path / "partial.npz")


@pytest.mark.parametrize(
    "kwargs, error",
    [
        (dict(n_uavs=0), InvalidInputError),
        (dict(n_uavs=2.5), InvalidTypeError),
        (dict(d_max=0.0), InvalidInputError),
        (dict(d_max=float("nan")), InvalidInputError),
        (dict(h_min=60.0, z_max=50.0), InfeasibleError),
        (dict(d_safe=200.0), InfeasibleError),
        (dict(n_uavs=20, d_safe=60.0), InfeasibleError),
        (dict(start="middle"), InvalidInputError),
        (dict(start=np.zeros((3, 2))), InvalidInputError),
        (dict(start=np.zeros((2, 3))), InvalidInputError),
        (dict(optimizer="annealing"), InvalidInputError),
        (dict(iterations=-1), InvalidInputError),
        (dict(start_altitude=float("inf")), InvalidInputError),
        (dict(settings="fast"), InvalidTypeError),
        (dict(prior="everything"), InvalidInputError),
    ],
)
def test_bad_settings_fail_before_any_work(hills, kwargs, error):
    args = dict(n_uavs=4, d_max=25.0, iterations=5, rng=0)
    args.update(kwargs)
    with pytest.raises(error):
        run_mission(hills, **args)


def test_bad_optimizer_constants_are_refused():
    with pytest.raises(UavcovError):
        uavcov.CAOSettings(n_candidates=0)
    with pytest.raises(UavcovError):
        uavcov.CAOSettings(alpha0=float("nan"))
    with pytest.raises(InvalidTypeError):
        run_mission("not a terrain", n_uavs=2, d_max=10.0)  # type: ignore[arg-type]


def test_known_points_as_prior_and_a_start_exactly_at_h_min(hills):
    xy = np.random.default_rng(5).uniform(0.0, 100.0, (12, 2))
    known = np.c_[xy, hills.ground_height(xy)]
    r = run_mission(hills, n_uavs=4, d_max=25.0, prior=known, iterations=3, rng=1)
    assert r.settings.prior_kind == "points" and r.prior_points.shape[0] >= 12
    # A start exactly on the h_min boundary is admissible after the closest-admissible step.
    start = np.c_[xy[:4], hills.ground_height(xy[:4]) + 2.0]
    on_boundary = run_mission(hills, n_uavs=4, d_max=25.0, start=start, h_min=2.0, iterations=2, rng=1)
    assert (hills.clearance(on_boundary.trajectory[0]) >= 2.0).all()
    lifted = run_mission(hills, n_uavs=4, d_max=25.0, start=start - [0, 0, 1.0], climb=1.0, iterations=2, rng=1)
    np.testing.assert_allclose(lifted.trajectory[0][:, 2], hills.ground_height(xy[:4]) + 3.0)
