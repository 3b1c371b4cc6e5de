"""Distance flown, mission time, and the escape optimiser (issue 36, point 4)."""

from __future__ import annotations

import dataclasses
import math
import pickle

import numpy as np
import pytest

import uavcov
from uavcov import Constraints, EscapeSettings, MissionSettings, mission_time, run_mission
from uavcov.errors import InvalidInputError, InvalidTypeError, ResultsFormatError
from uavcov.experiments import experiment_specs, read_runs, run_specs
from uavcov.experiments._results import LATER_RUN_COLUMNS, RUN_COLUMNS
from uavcov.experiments._sweep import experiment_settings, settings_hash
from uavcov.limits import feasibility
from uavcov.optim import CAOSettings, cao
from uavcov.optim._escape import escape_cao
from uavcov.paper import TABLE1


@pytest.fixture(scope="module")
def hills():
    return uavcov.gaussian_hills(size=40.0, spacing=2.0, n_hills=3, rng=1)


def escape_spec(**escape):
    return MissionSettings(
        n_uavs=4,
        d_max=12.0,
        iterations=80,
        optimizer="escape",
        constraints=Constraints(h_min=1.0, h_max=6.0, d_safe=1.0, check_moves=True),
        escape=EscapeSettings(**{"patience": 4, "hop": 3.0, **escape}),
    )


@pytest.fixture(scope="module")
def escaped(hills):
    return run_mission(hills, escape_spec(), rng=0)


# ---------------------------------------------------------------------------------------------
# Distance flown and mission time


def with_trajectory(result, trajectory):
    trajectory = np.asarray(trajectory, dtype=float)
    return dataclasses.replace(result, trace=dataclasses.replace(result.trace, trajectory=trajectory))


def test_distance_flown_of_a_hand_computed_trajectory(escaped):
    # UAV 0: (0,0,0) -> (3,4,0) -> (3,4,12): 5 + 12 m; UAV 1 holds still; UAV 2: 1 m up, 1 m back
    path = [
        [[0, 0, 0], [9, 9, 9], [1, 1, 1]],
        [[3, 4, 0], [9, 9, 9], [1, 1, 2]],
        [[3, 4, 12], [9, 9, 9], [1, 1, 1]],
    ]
    result = with_trajectory(escaped, path)
    np.testing.assert_allclose(result.distance_flown, [17.0, 0.0, 2.0], rtol=0, atol=1e-12)
    # moves are synchronous: 5 m then 12 m, the longest of each move at 2 m/s, and 3 hovers of 1 s
    assert mission_time(result, 2.0) == pytest.approx(8.5, abs=1e-12)
    assert mission_time(result, 2.0, hover_s=1.0) == pytest.approx(11.5, abs=1e-12)


def test_mission_time_waits_for_the_slowest_uav_of_each_move(escaped):
    # each UAV flies 5 m in all, but not at the same time: 10 m of waiting at 5 m/s
    path = [[[0, 0, 0], [10, 0, 0]], [[3, 4, 0], [10, 0, 0]], [[3, 4, 0], [13, 4, 0]]]
    result = with_trajectory(escaped, path)
    np.testing.assert_allclose(result.distance_flown, [5.0, 5.0])
    assert mission_time(result, 5.0) == pytest.approx(2.0)
    assert mission_time(result, 5.0) > result.distance_flown.max() / 5.0


def test_a_mission_of_the_start_alone_flies_nothing(escaped):
    result = with_trajectory(escaped, np.asarray(escaped.trajectory)[:1])
    np.testing.assert_array_equal(result.distance_flown, np.zeros(4))
    assert mission_time(result, 3.0, hover_s=2.0) == 2.0


def test_distance_flown_of_a_mission_is_its_path_length(escaped):
    path = np.asarray(escaped.trajectory)
    expected = [sum(math.dist(path[k, i], path[k + 1, i]) for k in range(path.shape[0] - 1)) for i in range(path.shape[1])]
    np.testing.assert_allclose(escaped.distance_flown, expected, rtol=1e-12)
    assert escaped.distance_flown.shape == (4,)


@pytest.mark.parametrize("speed", [0.0, -1.0, -math.inf, math.nan, math.inf])
def test_mission_time_refuses_a_bad_speed(escaped, speed):
    with pytest.raises(InvalidInputError):
        mission_time(escaped, speed)


@pytest.mark.parametrize("hover", [-1.0, math.nan, math.inf])
def test_mission_time_refuses_a_bad_hover_time(escaped, hover):
    with pytest.raises(InvalidInputError):
        mission_time(escaped, 5.0, hover_s=hover)


def test_mission_time_refuses_something_else_than_a_result():
    with pytest.raises(InvalidTypeError):
        mission_time("a mission", 5.0)  # type: ignore[arg-type]


# ---------------------------------------------------------------------------------------------
# Records and runs.csv


def test_records_keep_distance_and_escapes(escaped, tmp_path):
    path = uavcov.save_mission(escaped, tmp_path / "run.npz")
    back = uavcov.load_mission(path)
    np.testing.assert_array_equal(back.distance_flown, escaped.distance_flown)
    np.testing.assert_array_equal(back.relocations, escaped.relocations)
    assert back.relocation_distance == escaped.relocation_distance
    assert back.settings == escaped.settings and back.settings.escape == escaped.settings.escape
    assert mission_time(back, 4.0, hover_s=0.5) == mission_time(escaped, 4.0, hover_s=0.5)
    assert np.load(path)["distance_flown"].tolist() == escaped.distance_flown.tolist()


def test_records_refuse_a_distance_that_disagrees_with_the_trajectory(escaped, tmp_path):
    path = uavcov.save_mission(escaped, tmp_path / "run.npz")
    arrays = dict(np.load(path))
    arrays["distance_flown"] = arrays["distance_flown"] + 1.0
    np.savez_compressed(path, **arrays)
    with pytest.raises(ResultsFormatError, match="distance_flown"):
        uavcov.load_mission(path)


def test_records_refuse_escapes_outside_the_run(escaped, tmp_path):
    import json

    path = uavcov.save_mission(escaped, tmp_path / "run.npz")
    arrays = dict(np.load(path))
    header = json.loads(str(arrays["header"]))
    header["trace"]["relocations"] = [[0, 5, 500]]
    arrays["header"] = np.array(json.dumps(header))
    np.savez_compressed(path, **arrays)
    with pytest.raises(ResultsFormatError, match="relocations"):
        uavcov.load_mission(path)


def test_runs_table_has_the_distance_columns(tmp_path):
    small = TABLE1.with_changes(**{"terrain.spacing": 4.0, "iterations": 5})
    specs = experiment_specs(small, seeds=[0], team_sizes=[5], starts=["cvt"])
    (row,) = run_specs(specs, workers=1, out=tmp_path / "out")
    (stored,) = read_runs(tmp_path / "out" / "runs.csv")
    assert set(LATER_RUN_COLUMNS) <= set(RUN_COLUMNS)
    assert stored["distance_max_m"] == row["distance_max_m"] >= stored["distance_mean_m"] == row["distance_mean_m"] > 0.0
    result = specs[0].run()
    assert row["distance_mean_m"] == float(result.distance_flown.mean())


def test_a_runs_table_from_before_the_distance_columns_is_read_and_resumed(tmp_path):
    small = TABLE1.with_changes(**{"terrain.spacing": 4.0, "iterations": 3})
    specs = experiment_specs(small, seeds=[0, 1], team_sizes=[5], starts=["cvt"])
    out = tmp_path / "out"
    run_specs(specs[:1], workers=1, out=out)
    runs = out / "runs.csv"
    older = [c for c in RUN_COLUMNS if c not in LATER_RUN_COLUMNS]
    lines = runs.read_text().splitlines()
    keep = [RUN_COLUMNS.index(c) for c in older]
    import csv
    import io

    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    runs.write_text("".join(",".join(r[i] for i in keep) + "\n" for r in rows))
    assert read_runs(runs)[0]["max_coverage"] > 0.0
    run_specs(specs, workers=1, out=out, resume=True)
    stored = read_runs(runs)
    assert len(stored) == 2 and "distance_mean_m" not in stored[1]


def test_the_new_settings_keep_every_settings_hash():
    settings = experiment_settings(TABLE1)
    assert "escape" not in settings["mission"]
    escaping = TABLE1.with_changes(**{"mission.optimizer": "escape"})
    assert "escape" not in experiment_settings(escaping)["mission"]
    tuned = TABLE1.with_changes(**{"mission.escape": EscapeSettings(patience=7)})
    assert experiment_settings(tuned)["mission"]["escape"]["patience"] == 7
    assert settings_hash(tuned) != settings_hash(TABLE1)


# ---------------------------------------------------------------------------------------------
# The escape optimiser


def test_escape_is_deterministic_and_pickles(hills, escaped):
    again = run_mission(hills, escape_spec(), rng=0)
    np.testing.assert_array_equal(again.trajectory, escaped.trajectory)
    np.testing.assert_array_equal(again.coverage, escaped.coverage)
    np.testing.assert_array_equal(again.relocations, escaped.relocations)
    other = run_mission(hills, escape_spec(), rng=1)
    assert not np.array_equal(other.trajectory, escaped.trajectory)
    copy = pickle.loads(pickle.dumps(escaped.trace))
    np.testing.assert_array_equal(copy.relocations, escaped.trace.relocations)


def test_every_configuration_visited_is_a_checked_move(hills, escaped):
    assert len(escaped.relocations) >= 3  # the test is about escapes: there must be some
    check = feasibility(escaped.settings.constraints, hills)
    path = np.asarray(escaped.trajectory)
    assert escaped.settings.constraints.check_moves  # moves crossing the surface are refused
    for k in range(path.shape[0] - 1):
        assert check(path[k], path[k + 1][None])[0], k
    assert escaped.evaluations == escaped.settings.iterations + 1 == path.shape[0]


def test_an_escape_flight_moves_one_uav_in_legs_of_at_most_hop(escaped):
    path = np.asarray(escaped.trajectory)
    hop = escaped.settings.escape.hop
    for uav, first, last in escaped.relocations:
        legs = path[first + 1 : last + 1] - path[first:last]
        others = np.delete(legs, uav, axis=1)
        np.testing.assert_array_equal(others, 0.0)
        assert (np.linalg.norm(legs[:, uav, :2], axis=1) <= hop + 1e-9).all()
        assert (escaped.trace.step_sizes[first:last] == 0.0).all()
    expected = sum(np.linalg.norm(np.diff(path[f : e + 1, u], axis=0), axis=1).sum() for u, f, e in escaped.relocations)
    assert escaped.relocation_distance == pytest.approx(expected, rel=1e-12)


def test_escape_never_loses_the_best_configuration(hills, escaped):
    trace = escaped.trace
    assert trace.best_value == trace.values.max() == escaped.best_coverage
    np.testing.assert_array_equal(escaped.best_positions, escaped.trajectory[int(np.argmax(trace.values))])
    # up to its first stall it is plain CAO, draw for draw: its best is at least CAO's best of that stretch
    first = int(escaped.relocations[0, 1])
    plain = run_mission(hills, escape_spec().with_changes(optimizer="cao"), rng=0)
    np.testing.assert_array_equal(escaped.trajectory[: first + 1], plain.trajectory[: first + 1])
    assert escaped.best_coverage >= plain.coverage[: first + 1].max()


def test_without_a_stall_escape_is_plain_cao():
    top = np.array([[10.0, 20.0, 30.0]])

    def value(x):
        return -float(np.sum((x - top) ** 2))

    plain = cao(value, np.zeros((1, 3)), feasible=None, iterations=60, rng=3)
    never = escape_cao(
        lambda x: (value(x), np.array([1.0])), np.zeros((1, 3)), feasible=None, iterations=60, rng=3, escape=EscapeSettings(patience=1000)
    )
    np.testing.assert_array_equal(never.trajectory, plain.trajectory)
    np.testing.assert_array_equal(never.values, plain.values)
    assert never.kind == "escape" and never.relocations.shape == (0, 3)


def test_an_escape_that_cannot_be_flown_is_not_flown(hills):
    refuse_far = feasibility(Constraints(h_min=1.0, h_max=6.0, d_safe=1.0, check_moves=True).resolve(hills), hills)

    def short_moves_only(current, candidates):
        ok = refuse_far(current, candidates)
        return ok & (np.linalg.norm(candidates - current, axis=2).max(axis=1) <= 1.4)

    vis = uavcov.Visibility(hills, 12.0)
    x0 = np.asarray(run_mission(hills, escape_spec(), rng=0).trajectory[0])

    def measure(x):
        counts = vis.per_uav(x)
        return counts.coverage, counts.exclusive_share

    trace = escape_cao(
        measure,
        x0,
        feasible=short_moves_only,
        iterations=60,
        settings=CAOSettings(alpha0=0.2),
        rng=0,
        escape=EscapeSettings(patience=3, hop=3.0),
    )
    assert trace.relocations.shape == (0, 3)  # destinations >= 3 m away: legs > 1.5 m, refused
    assert trace.evaluations == 61
    assert (np.linalg.norm(np.diff(trace.trajectory, axis=0), axis=2) <= 1.4).all()


@pytest.mark.parametrize(
    "changes, error",
    [
        ({"patience": 0}, InvalidInputError),
        ({"patience": 2.5}, InvalidTypeError),
        ({"hop": 0.0}, InvalidInputError),
        ({"hop": math.nan}, InvalidInputError),
        ({"hop": 1e300 * 1e300}, InvalidInputError),
        ({"climb_search": -1.0}, InvalidInputError),
        ({"climb_step": 0.0}, InvalidInputError),
        ({"climb_search": 1e6, "climb_step": 1e-3}, InvalidInputError),
        ({"max_relocations": 0}, InvalidInputError),
        ({"movers": 0}, InvalidInputError),
        ({"destinations": -2}, InvalidInputError),
        ({"min_gain": -0.1}, InvalidInputError),
        ({"restart_step": "yes"}, InvalidTypeError),
        ({"hop": "far"}, InvalidTypeError),
    ],
)
def test_bad_escape_settings(changes, error):
    with pytest.raises(error):
        EscapeSettings(**changes)


def test_bad_escape_arguments():
    with pytest.raises(InvalidTypeError):
        MissionSettings(n_uavs=2, d_max=10.0, escape="often")  # type: ignore[arg-type]
    with pytest.raises(InvalidTypeError):
        escape_cao(lambda x: (0.0, np.zeros(1)), np.zeros((1, 3)), feasible=None, iterations=3, escape={"patience": 3})  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError):  # marginals of the wrong shape
        escape_cao(lambda x: (0.0, np.zeros(2)), np.zeros((1, 3)), feasible=None, iterations=3)
    with pytest.raises(InvalidInputError):
        MissionSettings(n_uavs=2, d_max=10.0, optimizer="escape", objective="quality")
    assert MissionSettings.from_dict(escape_spec().as_dict()) == escape_spec()
