"""The two-step mission: prior -> S' -> start -> closest admissible -> CAO."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import uavcov
from uavcov import CAOSettings, Constraints, CVTSettings, MissionSettings, StartSettings, run_mission
from uavcov.errors import InfeasibleError, InvalidInputError, InvalidTypeError, UavcovError
from uavcov.limits._constraints import trajectory_feasible
from uavcov.mission import iterations_to_fraction
from uavcov.records import load_mission, save_mission


def _spec(n_uavs: int, d_max: float = 25.0, *, start: str = "cvt", iterations: int = 40, **changes) -> MissionSettings:
    return MissionSettings(n_uavs=n_uavs, d_max=d_max, iterations=iterations, start=StartSettings(kind=start)).with_changes(**changes)


@pytest.fixture(scope="module")
def hills() -> uavcov.Terrain:
    return uavcov.gaussian_hills(spacing=2.0, rng=1001)


@pytest.fixture(scope="module")
def short_run(hills):
    return run_mission(hills, _spec(6), rng=7, n_threads=1)


def _constraints(result) -> Constraints:
    return result.settings.constraints  # resolved against the true surface by run_mission


@pytest.mark.parametrize("start", ["cvt", "random", "corner"])
@pytest.mark.parametrize("ceiling", [None, 6.0])
def test_every_constraint_holds_at_every_iteration(hills, start, ceiling):
    changes = {} if ceiling is None else {"constraints.h_max": ceiling, "constraints.check_moves": True}
    result = run_mission(hills, _spec(8, start=start, **changes), rng=3, n_threads=1)
    assert result.trajectory.shape == (41, 8, 3)
    assert result.settings.constraints.bounds == (0.0, 0.0, 100.0, 100.0)
    assert result.settings.constraints.check_moves is (ceiling is not None)
    assert trajectory_feasible(_constraints(result), hills, result.trajectory).all()
    # Checked again from the definitions, independently of the constraints module.
    t = result.trajectory.reshape(-1, 3)
    assert (hills.clearance(t) >= result.settings.constraints.h_min - 1e-9).all()
    assert (t[:, 2] <= result.settings.constraints.z_max + 1e-9).all()
    if ceiling is not None:
        height = t[:, 2] - hills.ground_height(t[:, :2])
        assert (height <= ceiling + 1e-9).all() and height.max() > ceiling - 1.0  # held, and reached
        moves = result.trajectory[1:] != result.trajectory[:-1]
        assert moves.any()
        a, b = result.trajectory[:-1].reshape(-1, 3), result.trajectory[1:].reshape(-1, 3)
        assert hills.segments_clear(a, b).all()  # every move, on the grid, crosses no ground
    lo, hi = hills.bounds
    assert ((t[:, :2] >= lo[:2] - 1e-9) & (t[:, :2] <= hi[:2] + 1e-9)).all()
    for x in result.trajectory:
        d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
        assert d[np.triu_indices(8, 1)].min() >= result.settings.constraints.d_safe - 1e-9


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
    again = run_mission(hills, _spec(6), rng=7, n_threads=2)
    np.testing.assert_array_equal(again.trajectory, short_run.trajectory)
    np.testing.assert_array_equal(again.coverage, short_run.coverage)
    other = run_mission(hills, _spec(6), rng=8, n_threads=1)
    assert not np.array_equal(other.trajectory, short_run.trajectory)


def test_the_start_comes_from_the_approximating_surface(short_run):
    # The CVT generators lie on S' (not on the true surface), the start flies above them at the
    # start altitude over the real ground, and the prior holds the 4 corners.
    s_prime = short_run.approximation
    gens = short_run.cvt.generators
    assert np.abs(s_prime.closest_point(gens) - gens).max() < 1e-6
    np.testing.assert_array_equal(short_run.start_positions[:, :2], gens[:, :2])
    altitude = short_run.settings.start.altitude
    np.testing.assert_array_equal(short_run.start_positions[:, 2], short_run.terrain.ground_height(gens[:, :2]) + altitude)
    assert short_run.prior_points.shape == (34, 3)
    corners = {(x, y) for x, y in short_run.prior_points[:, :2]}
    assert {(0.0, 0.0), (100.0, 0.0), (0.0, 100.0), (100.0, 100.0)} <= corners


def test_cvt_start_ends_higher_than_corner_start_on_average():
    cvt_best, corner_best = [], []
    for seed in (1000, 1001, 1002):
        terrain = uavcov.gaussian_hills(spacing=2.0, rng=seed)
        for start, out in (("cvt", cvt_best), ("corner", corner_best)):
            r = run_mission(terrain, _spec(8, start=start, iterations=60), rng=seed, n_threads=1)
            out.append(r.best_coverage)
    assert np.mean(cvt_best) > np.mean(corner_best) + 0.05


def test_pyramid_prior_and_given_surface_and_given_start(hills):
    pyramid = run_mission(hills, _spec(5, iterations=5, prior="pyramid"), rng=1, n_threads=1)
    assert pyramid.prior_points.shape == (5, 3) and pyramid.prior_kind == "pyramid"
    surface = run_mission(hills, _spec(5, iterations=5), known=pyramid.approximation, rng=1)
    assert surface.prior_kind == "surface" and surface.prior_points.shape == (0, 3)
    np.testing.assert_array_equal(surface.start_positions, pyramid.start_positions)
    start = np.array([[10.0, 10.0, 40.0], [30.0, 10.0, 40.0], [50.0, 10.0, 40.0], [70.0, 10.0, 40.0], [90.0, 10.0, 40.0]])
    given = run_mission(hills, _spec(5, iterations=3), start_positions=start, rng=1)
    assert given.cvt is None
    np.testing.assert_array_equal(given.start_positions, start)
    np.testing.assert_array_equal(given.trajectory[0], start)  # admissible as given: unchanged


def test_per_robot_optimizer_and_measurement_noise(hills):
    spec = _spec(4, iterations=15, optimizer="per_robot", cao=CAOSettings(measurement_noise=0.01))
    r = run_mission(hills, spec, rng=2)
    assert r.settings.optimizer == "per_robot" and r.settings.cao.measurement_noise == 0.01
    assert not np.array_equal(r.trace.measured, r.trace.values)  # the optimiser saw noise
    vis = uavcov.Visibility(hills, 25.0)
    assert r.coverage[-1] == vis.coverage(r.trajectory[-1])  # the record did not


def test_buildings_scene_checks_moves():
    scene = uavcov.terrain.buildings_scene(rng=3)
    r = run_mission(scene, _spec(4, 8.0, iterations=20, **{"constraints.z_max": 20.0}), rng=3, n_threads=1)
    assert r.settings.constraints.check_moves
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
    assert loaded.settings == short_run.settings and loaded.seed == 7 and loaded.prior_kind == short_run.prior_kind
    assert loaded.best_coverage == short_run.best_coverage


def test_loading_a_bad_file_names_the_problem(tmp_path):
    with pytest.raises(uavcov.errors.ResultsFormatError, match="no run file"):
        load_mission(tmp_path / "missing.npz")
    np.savez(tmp_path / "other.npz", header=np.array('{"format": "someone-else/9"}'))
    with pytest.raises(uavcov.errors.ResultsFormatError, match="format"):
        load_mission(tmp_path / "other.npz")
    np.savez(tmp_path / "partial.npz", header=np.array('{"format": "uavcov.mission/2", "spec": {}}'))
    with pytest.raises(uavcov.errors.ResultsFormatError, match="scalars"):
        load_mission(tmp_path / "partial.npz")


@pytest.mark.parametrize(
    "changes, error",
    [
        (dict(n_uavs=0), InvalidInputError),
        (dict(n_uavs=2.5), InvalidTypeError),
        (dict(d_max=0.0), InvalidInputError),
        (dict(d_max=float("nan")), InvalidInputError),
        ({"constraints.h_min": 60.0, "constraints.z_max": 50.0}, InfeasibleError),
        ({"constraints.d_safe": 200.0}, InfeasibleError),
        ({"n_uavs": 20, "constraints.d_safe": 60.0}, InfeasibleError),
        ({"start.kind": "middle"}, InvalidInputError),
        (dict(optimizer="annealing"), InvalidInputError),
        (dict(iterations=-1), InvalidInputError),
        ({"start.altitude": float("inf")}, InvalidInputError),
        (dict(cao="fast"), InvalidTypeError),
        (dict(prior="everything"), InvalidInputError),
        (dict(colour="red"), InvalidInputError),
    ],
)
def test_bad_settings_fail_before_any_work(hills, changes, error):
    with pytest.raises(error):
        run_mission(hills, _spec(4, iterations=5).with_changes(**changes), rng=0)


@pytest.mark.parametrize("start", [np.zeros((3, 2)), np.zeros((2, 3))])
def test_bad_start_positions_are_refused(hills, start):
    with pytest.raises(InvalidInputError):
        run_mission(hills, _spec(4, iterations=5), start_positions=start, rng=0)


def test_bad_optimizer_constants_are_refused():
    with pytest.raises(UavcovError):
        uavcov.CAOSettings(n_candidates=0)
    with pytest.raises(UavcovError):
        uavcov.CAOSettings(alpha0=float("nan"))
    with pytest.raises(InvalidTypeError):
        run_mission("not a terrain", _spec(2))  # type: ignore[arg-type]
    with pytest.raises(InvalidTypeError):
        run_mission(uavcov.gaussian_hills(spacing=10.0, rng=0), "a spec")  # type: ignore[arg-type]


def test_known_points_as_prior_and_a_start_exactly_at_h_min(hills):
    xy = np.random.default_rng(5).uniform(0.0, 100.0, (12, 2))
    known = np.c_[xy, hills.ground_height(xy)]
    r = run_mission(hills, _spec(4, iterations=3), known=known, rng=1)
    assert r.prior_kind == "points" and r.prior_points.shape[0] >= 12
    # A start exactly on the h_min boundary is admissible after the closest-admissible step.
    start = np.c_[xy[:4], hills.ground_height(xy[:4]) + 2.0]
    on_boundary = run_mission(hills, _spec(4, iterations=2), start_positions=start, rng=1)
    assert (hills.clearance(on_boundary.trajectory[0]) >= 2.0).all()
    lifted = run_mission(hills, _spec(4, iterations=2, **{"start.climb": 1.0}), start_positions=start - [0, 0, 1.0], rng=1)
    np.testing.assert_allclose(lifted.trajectory[0][:, 2], hills.ground_height(xy[:4]) + 3.0)


def test_mission_spec_is_a_frozen_picklable_value_and_round_trips_as_data():
    spec = _spec(7, 20.0, start="random", **{"start.random_altitude": (1.0, 4.0), "cvt.preset": "lloyd", "cao.alpha0": 2.5})
    assert pickle.loads(pickle.dumps(spec)) == spec and hash(pickle.loads(pickle.dumps(spec))) == hash(spec)
    assert MissionSettings.from_dict(spec.as_dict()) == spec
    import json

    assert MissionSettings.from_dict(json.loads(json.dumps(spec.as_dict()))) == spec  # tuples come back from lists
    with pytest.raises(AttributeError):
        spec.n_uavs = 3  # type: ignore[misc]
    with pytest.raises(InvalidInputError, match="unknown field"):
        MissionSettings.from_dict({**spec.as_dict(), "colour": "red"})
    with pytest.raises(InvalidInputError, match="no field"):
        spec.with_changes(**{"start.colour": "red"})


def test_start_configuration_is_the_one_start_pipeline(hills):
    """Heights above the real ground or above S', corner and random altitudes, from one function."""
    prior = uavcov.terrain.sample_prior(hills, 30, rng=4)
    s_prime = uavcov.terrain.approximate_surface(prior)
    on_prime, _ = uavcov.placement.start_configuration(
        StartSettings(kind="corner", altitude=3.0, altitude_reference="prior"), s_prime, hills, 4
    )
    on_the_surface = StartSettings(kind="corner", altitude=0.0, altitude_reference="prior")
    lattice, _ = uavcov.placement.start_configuration(on_the_surface, s_prime, s_prime, 4)
    np.testing.assert_array_equal(on_prime, lattice + [0.0, 0.0, 3.0])
    above_ground, _ = uavcov.placement.start_configuration(
        StartSettings(kind="corner", altitude=3.0, corner_altitude=6.0), s_prime, hills, 4
    )
    np.testing.assert_array_equal(above_ground[:, 2], hills.ground_height(lattice[:, :2]) + 6.0)
    spec = StartSettings(kind="random", random_altitude=(2.0, 9.0), altitude_reference="prior")
    a, _ = uavcov.placement.start_configuration(spec, s_prime, hills, 6, rng=1)
    b, _ = uavcov.placement.start_configuration(spec, s_prime, hills, 6, rng=1)
    np.testing.assert_array_equal(a, b)
    height = a[:, 2] - s_prime.ground_height(a[:, :2])
    assert ((height >= 2.0 - 1e-9) & (height <= 9.0 + 1e-9)).all() and np.ptp(height) > 0.5
    tessellated, tessellation = uavcov.placement.start_configuration(
        StartSettings(), s_prime, hills, 5, cvt_settings=CVTSettings(preset="lloyd"), rng=3
    )
    np.testing.assert_array_equal(tessellated[:, :2], tessellation.generators[:, :2])
    # the same start as a mission draws it from its start stream
    run = run_mission(hills, _spec(5, iterations=0, cvt=CVTSettings(preset="lloyd")), known=prior, rng=np.random.default_rng(11))
    _, start_rng, _ = np.random.default_rng(11).spawn(3)
    expected, _ = uavcov.placement.start_configuration(
        StartSettings(), run.approximation, hills, 5, cvt_settings=CVTSettings(preset="lloyd"), rng=start_rng
    )
    np.testing.assert_array_equal(run.start_positions, expected)


def test_a_lifted_uav_climbs_by_the_start_s_climb(hills):
    low = StartSettings(kind="corner", altitude=0.0, climb=1.5)
    r = run_mission(hills, _spec(4, iterations=0).with_changes(start=low), rng=0)
    ground = hills.ground_height(r.trajectory[0][:, :2])
    np.testing.assert_allclose(r.trajectory[0][:, 2], ground + r.settings.constraints.h_min + 1.5)


def test_format_1_run_files_still_load(short_run, tmp_path):
    import json

    path = save_mission(short_run, tmp_path / "run.npz")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    header = json.loads(str(arrays["header"]))
    spec = short_run.settings
    header.pop("spec"), header.pop("seed"), header.pop("prior_kind")
    header["format"] = "uavcov.mission/1"
    header["settings"] = {
        "n_uavs": spec.n_uavs,
        "d_max": spec.d_max,
        "start": "given",
        "optimizer": spec.optimizer,
        "iterations": spec.iterations,
        "start_altitude": 5.0,
        "h_min": 2.0,
        "z_max": 50.0,
        "d_safe": 2.0,
        "check_moves": False,
        "cao": spec.cao.__dict__,
        "prior_kind": "random",
        "n_prior": 34,
        "seed": 7,
    }
    arrays["header"] = np.array(json.dumps(header))
    np.savez(tmp_path / "old.npz", **arrays)
    old = load_mission(tmp_path / "old.npz")
    assert old.settings.start.kind == "cvt" and old.seed == 7 and old.settings.constraints.h_min == 2.0
    np.testing.assert_array_equal(old.coverage, short_run.coverage)


def test_a_team_that_stays_is_not_measured_again(hills, monkeypatch):
    calls = []
    for cls, name in ((uavcov.Visibility, "coverage"), (uavcov.Visibility, "per_uav"), (uavcov.engine.CoverageTracker, "coverage")):
        original = getattr(cls, name)
        monkeypatch.setattr(cls, name, lambda self, *a, _f=original, **k: calls.append(1) or _f(self, *a, **k))
    # a big first step in a narrow band: many iterations find nothing admissible and stay
    spec = _spec(
        5,
        iterations=60,
        cao=CAOSettings(alpha0=20.0, stability=5.0, decay=1.0),
        **{"start.altitude": 2.0, "start.climb": 1.0},
        constraints=Constraints(h_min=1.0, h_max=3.0, z_max=80.0, d_safe=1.0),
    )
    r = run_mission(hills, spec, rng=3)
    moves = int((r.trajectory[1:] != r.trajectory[:-1]).any(axis=(1, 2)).sum())
    assert r.evaluations == 61 and moves < 60  # the optimiser counts every measurement, some repeated
    assert len(calls) == 1 + moves  # the engine ran once per new configuration
    monkeypatch.undo()
    vis = uavcov.Visibility(hills, 25.0)
    assert [vis.coverage(x) for x in r.trajectory] == r.coverage.tolist()  # every value is its configuration's
