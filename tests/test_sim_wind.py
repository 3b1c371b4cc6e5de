"""Dryden gusts (uavcov.sim.DrydenGusts) under ``rng=``: the Dryden statistics, a seed that flies
the same states twice, and gusts beyond the vehicles' thrust as a recorded failure."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

import uavcov
from uavcov.sim import DrydenGusts, SimSettings, dryden_scales


def test_gusts_have_the_dryden_spread_and_correlation_time() -> None:
    """A first-order Dryden process sampled exactly: stationary standard deviation sigma on each
    axis, lag correlation exp(-V dt / L) with RotorPy's scale lengths (MIL-F-8785C, V = 1 m/s)."""
    sigma, dt = np.array([1.0, 2.0, 0.5]), 0.01
    gusts = DrydenGusts([3.0, 0.0, 0.0], sigma, dt, 2.0, np.random.default_rng(7))
    n = 400_000
    samples = np.array([gusts.update(0.0, np.zeros(3)) for _ in range(n)]) - [3.0, 0.0, 0.0]
    scales = dryden_scales(2.0)
    # Altitude 2 m = 6.56 ft: L_z = 2 m, L_x = L_y = 6.56 / (0.177 + 0.000823 * 6.56)^1.2 ft.
    assert scales[2] == pytest.approx(2.0)
    assert scales[0] == pytest.approx(6.562 / (0.177 + 0.000823 * 6.562) ** 1.2 / 3.281, rel=1e-3)
    # The vertical axis decorrelates in 2 s (about 200 samples): its spread is known to about 2 %.
    assert samples[:, 2].std() == pytest.approx(sigma[2], rel=0.05)
    lag = 50
    expected = np.exp(-lag * dt / scales[2])
    measured = np.corrcoef(samples[:-lag, 2], samples[lag:, 2])[0, 1]
    assert measured == pytest.approx(expected, abs=0.03)
    # Horizontal axes decorrelate in ~15 s: fewer independent samples, a looser bound.
    assert samples[:, 0].std() == pytest.approx(sigma[0], rel=0.2)


def test_the_same_seed_draws_the_same_gusts() -> None:
    def draw(seed: int) -> np.ndarray:
        gusts = DrydenGusts([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], 0.01, 3.0, np.random.default_rng(seed))
        return np.array([gusts.update(0.0, np.zeros(3)) for _ in range(100)])

    assert np.array_equal(draw(3), draw(3))
    assert not np.array_equal(draw(3), draw(4))


rotorpy = pytest.importorskip("rotorpy")


def test_a_gusty_flown_mission_repeats_with_its_seed() -> None:
    from uavcov.paper import BUILDINGS
    from uavcov.sim import FlightSettings, SimSettings, fly_mission

    terrain, known = BUILDINGS.terrain.make(1000), BUILDINGS.known(1000)
    spec = BUILDINGS.mission_settings(4, "cvt").with_changes(iterations=2)
    gusty = SimSettings(flight=FlightSettings(wind=(1.0, 0.0, 0.0), gusts=(0.8, 0.8, 0.3)), render=False)
    first = fly_mission(terrain, spec, gusty, known=known, rng=1000)
    again = fly_mission(terrain, spec, gusty, known=known, rng=1000)
    other = fly_mission(terrain, spec, gusty, known=known, rng=np.random.default_rng(1000).spawn(1)[0])
    calm = fly_mission(terrain, spec, SimSettings(render=False), known=known, rng=1000)
    assert first.failure is None
    assert np.array_equal(first.states, again.states) and np.array_equal(first.exact, again.exact)
    common = min(len(first.states), len(calm.states))
    assert np.abs(first.states[:common] - calm.states[:common]).max() > 1e-3  # the gusts push the team
    assert first.states.shape != other.states.shape or not np.array_equal(first.states, other.states)


def test_gusts_beyond_thrust_are_a_recorded_failure_and_the_rows_are_kept(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """A 35 m/s mean wind with 8 m/s gusts: the run ends with its failure recorded (never a
    hang: each leg has max_leg_s), the resumable rows and the flown states are on disk."""
    from uavcov.paper import BUILDINGS
    from uavcov.paper._realistic import _config, fly_experiment
    from uavcov.sim import FlightSettings, SimSettings, load_flown

    storm = SimSettings(flight=FlightSettings(wind=(35.0, 0.0, 0.0), gusts=(8.0, 8.0, 3.0), max_leg_s=2.0), render=False)
    config = _config("realistic", 4, (1000,), ("cvt",), ("exact",), 3, storm)
    rows = fly_experiment(tmp_path, BUILDINGS, config, storm, resume=False, progress=None)
    assert len(rows) == 1 and rows[0]["failure"]
    assert ("settle" in rows[0]["failure"]) or ("hit" in rows[0]["failure"]) or ("diverged" in rows[0]["failure"])
    assert (tmp_path / "rows.jsonl").read_text().count("\n") == 1
    run = load_flown(tmp_path / "states" / "s1000_cvt_exact.npz")
    assert run.failure == rows[0]["failure"] and run.flown_states.shape[0] > 0
    assert (tmp_path / "realistic.md").is_file()


def test_the_flown_experiment_resumes_to_the_rows_of_an_uninterrupted_run(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """Rows appended one by one: a run cut off mid-write (a torn last line) resumes to the rows of
    an uninterrupted run; a folder of other settings, or one resumed without --resume, is refused."""
    from uavcov.errors import ConfigError
    from uavcov.paper import BUILDINGS
    from uavcov.paper._realistic import _config, fly_experiment
    from uavcov.sim import SimSettings

    sim = SimSettings()
    config = _config("realistic", 4, (1000,), ("cvt",), ("exact", "sensed"), 1, sim)
    whole = fly_experiment(tmp_path / "whole", BUILDINGS, config, sim, resume=False, progress=None)
    cut = tmp_path / "cut"
    fly_experiment(cut, BUILDINGS, config, sim, resume=False, progress=None)
    lines = (cut / "rows.jsonl").read_text().splitlines()
    (cut / "rows.jsonl").write_text(lines[0] + "\n" + lines[1][: len(lines[1]) // 2])  # killed mid-write
    with pytest.raises(ConfigError, match="resume"):
        fly_experiment(cut, BUILDINGS, config, sim, resume=False, progress=None)
    other = _config("realistic", 4, (1000,), ("cvt",), ("exact", "sensed"), 2, sim)
    with pytest.raises(ConfigError, match="other settings"):
        fly_experiment(cut, BUILDINGS, other, sim, resume=True, progress=None)
    said: list[str] = []
    resumed = fly_experiment(cut, BUILDINGS, config, sim, resume=True, progress=said.append)
    assert len(said) == 1 and "sensed" in said[0]  # only the torn run flew again

    def same(row: dict) -> dict:  # type: ignore[type-arg]
        return {k: v for k, v in row.items() if k != "wall_time_s"}

    assert [same(r) for r in resumed] == [same(r) for r in whole]
    assert "2 of 2 runs done" in (cut / "realistic.md").read_text()


def test_table1_flown_starts_where_its_kinematic_twin_starts(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """Table 1 flown (N = 12 on a hills terrain): the same prior, start and streams as the
    kinematic mission, so both measure the same coverage at the start; rows, states and report
    on disk."""
    from uavcov.cli import EXIT_OK, main
    from uavcov.paper import TABLE1
    from uavcov.sim import load_flown

    assert main(["reproduce", "flown-table1", "--out", str(tmp_path), "--seeds", "0", "--starts", "corner", "--iterations", "2"]) == EXIT_OK
    (row,) = [json.loads(line) for line in (tmp_path / "rows.jsonl").read_text().splitlines()]
    assert row["flown_initial"] == pytest.approx(row["kinematic_initial"], abs=0.005)  # the hover holds the start to 1e-16 m
    run = load_flown(tmp_path / "states" / "s0000_corner_exact.npz")
    assert run.trajectory.shape == (3, 12, 3) and run.settings.n_uavs == 12
    assert run.settings.d_max == TABLE1.mission.d_max and run.flown_states.shape[1] == 12
    assert "table1" in (tmp_path / "config.json").read_text() and (tmp_path / "realistic.md").is_file()


@pytest.mark.parametrize(
    "gusts",
    [(float("nan"), 0.0, 0.0), (-1.0, 0.0, 0.0), (1e300, 0.0, 0.0), (float("inf"), 1.0, 1.0), (1.0, 1.0), "1 1 1", (51.0, 0.0, 0.0)],
)
def test_bad_gusts_are_refused(gusts: object) -> None:
    """Gust deviations that are not 3 finite numbers in [0, 50] m/s raise the project's error."""
    from uavcov.errors import InvalidInputError
    from uavcov.sim import FlightSettings

    with pytest.raises(InvalidInputError, match="gusts"):
        FlightSettings(gusts=gusts)  # type: ignore[arg-type]


def test_the_realistic_scenario_under_a_standoff_keeps_the_team_off_the_walls(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """``standoff=1``: the folder says so (config and report), the mission plans 0.08 m inside
    the limits (h_min 1.08 m, d_safe 1.08 m), the flown states of dev scene 1000 are judged
    against the limits themselves and keep them all, and a resume under the paper's limits, or
    another standoff, is refused."""
    from uavcov.errors import ConfigError
    from uavcov.paper import reproduce_realistic
    from uavcov.paper._realistic import LIMITS_MARGIN
    from uavcov.sim import load_flown

    sim = SimSettings(render=False)
    choice = {"seeds": [1000], "starts": ("cvt",), "measurements": ("exact",), "iterations": 3, "sim": sim}
    rows = reproduce_realistic(tmp_path, standoff=1.0, **choice)  # type: ignore[arg-type]
    config = json.loads((tmp_path / "config.json").read_text())
    assert config["standoff_m"] == 1.0 and config["sim"]["limits_margin"] == LIMITS_MARGIN and config["sim"]["flight"]["synchronous"]
    assert "3D standoff" in (tmp_path / "realistic.md").read_text()
    planned = load_flown(tmp_path / "states" / "s1000_cvt_exact.npz").settings.constraints
    assert planned.h_min == pytest.approx(1.0 + LIMITS_MARGIN) and planned.move_step == 0.1
    assert not rows[0]["failure"] and rows[0]["violations"] == 0 and rows[0]["min_distance_m"] >= 1.0
    for standoff in (None, 2.0):
        with pytest.raises(ConfigError, match="other settings"):
            reproduce_realistic(tmp_path, standoff=standoff, resume=True, **choice)  # type: ignore[arg-type]


@pytest.mark.parametrize("margin", [-0.1, 1.5, float("nan"), "x"])
def test_the_limits_margin_refuses_what_is_not_a_margin(margin: object) -> None:
    from uavcov.errors import InvalidInputError, InvalidTypeError

    with pytest.raises((InvalidInputError, InvalidTypeError)):
        SimSettings(limits_margin=margin)  # type: ignore[arg-type]


def test_the_flight_limits_are_the_planned_ones_widened_by_the_margin() -> None:
    planned = uavcov.limits.Constraints(h_min=1.08, h_max=5.92, d_safe=1.08, z_max=19.92, clearance="standoff", move_step=0.1)
    judged = SimSettings(limits_margin=0.08).flight_limits(planned)
    assert (judged.h_min, judged.h_max, judged.d_safe, judged.z_max) == pytest.approx((1.0, 6.0, 1.0, 20.0))
    assert judged.clearance == "standoff" and SimSettings().flight_limits(planned) is planned
    boxed = SimSettings(limits_margin=0.08).flight_limits(dataclasses.replace(planned, bounds=(0.08, 0.08, 23.92, 23.92)))
    assert boxed.bounds == pytest.approx((0.0, 0.0, 24.0, 24.0))


@pytest.mark.parametrize(
    "args",
    [
        ((1e300, 0, 0), (1, 1, 1), 0.01, 10.0, 0),  # a wind no vehicle meets: a unit typo
        ((0, 0, 0), (1, float("nan"), 1), 0.01, 10.0, 0),
        ((0, 0, 0), (-1, 1, 1), 0.01, 10.0, 0),
        ((0, 0), (1, 1, 1), 0.01, 10.0, 0),
        ((0, 0, 0), (1, 1, 1), 0.0, 10.0, 0),
        ((0, 0, 0), (1, 1, 1), float("inf"), 10.0, 0),
        ((0, 0, 0), (1, 1, 1), 0.01, 1e300, 0),  # overflowed MIL-F-8785C's scale lengths
        ((0, 0, 0), (1, 1, 1), 0.01, float("nan"), 0),
        ((0, 0, 0), "abc", 0.01, 10.0, 0),
        ((0, 0, 0), (1, 1, 1), 0.01, 10.0, "seed"),
    ],
)
def test_dryden_gusts_refuse_hostile_settings(args: tuple) -> None:  # type: ignore[type-arg]
    from uavcov.errors import InvalidInputError, InvalidTypeError

    with pytest.raises((InvalidInputError, InvalidTypeError)):
        DrydenGusts(*args)


def test_the_sim_helpers_refuse_what_is_not_theirs() -> None:
    """camera_rotation, vehicle_parameters, hover_rotor_speed and check_flight answer wrong or
    degenerate input with uavcov's errors, not IndexError or numpy's ambiguity."""
    from uavcov.errors import InvalidInputError, InvalidTypeError
    from uavcov.sim import DepthCamera, camera_rotation, check_flight, hover_rotor_speed, vehicle_parameters

    camera = DepthCamera.omnidirectional(8.0)
    for quaternion in (1e300, (0, 0, 0, 0), (0, 0, 1), (0, 0, float("nan"), 1), "wxyz"):
        with pytest.raises((InvalidInputError, InvalidTypeError)):
            camera_rotation(quaternion, camera)
    with pytest.raises(InvalidTypeError):
        camera_rotation((0, 0, 0, 1), "camera")
    np.testing.assert_allclose(
        camera_rotation((0, 0, 0, 2.0), DepthCamera(64, 48, (90.0, 60.0), 8.0, pitch_deg=0.0)), np.eye(3), atol=1e-12
    )
    for name in (np.zeros((2, 3)), None, 5, "blimp"):
        with pytest.raises(InvalidInputError):
            vehicle_parameters(name)  # type: ignore[arg-type]
    for params in (1e300, {"mass": 1.0}, None):
        with pytest.raises(InvalidInputError):
            hover_rotor_speed(params)  # type: ignore[arg-type]
    plane = uavcov.Terrain(np.array([[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]], float), np.array([[0, 1, 2], [0, 2, 3]]))
    limits = uavcov.limits.Constraints(h_min=1.0).resolve(plane)
    good = np.full((2, 1, 3), 5.0)
    for bad in (
        (1e300, limits, good, [0, 0], good[:1], good[:1]),
        (plane, uavcov.limits.Constraints(h_min=1.0), good, [0, 0], good[:1], good[:1]),  # unresolved
        (plane, limits, np.full((2, 1, 3), np.nan), [0, 0], good[:1], good[:1]),
        (plane, limits, good, [0, 1], good[:1], good[:1]),  # a leg that is not there
        (plane, limits, good, [0], good[:1], good[:1]),
        (plane, limits, good, [0, 0], np.full((1, 2, 3), 5.0), good[:1]),
    ):
        with pytest.raises((InvalidInputError, InvalidTypeError)):
            check_flight(*bad)  # type: ignore[arg-type]


@pytest.mark.parametrize("name, folder", [("realistic", "scenario"), ("standoff", "standoff"), ("table1", "table1")])
def test_the_realistic_page_is_its_committed_rows(tmp_path, name: str, folder: str) -> None:  # type: ignore[no-untyped-def]
    """docs/realistic.md's generated sections are the reports of the rows in docs/realistic_experiment
    (what scripts/realistic_docs.py writes), figures aside."""
    import re
    import shutil
    from pathlib import Path

    from uavcov.paper import write_realistic_report

    root = Path(__file__).resolve().parent.parent
    copy = tmp_path / folder
    copy.mkdir()
    for file in ("config.json", "rows.jsonl"):
        shutil.copyfile(root / "docs" / "realistic_experiment" / folder / file, copy / file)
    body = write_realistic_report(copy).read_text(encoding="utf-8").split("\n", 1)[1].strip()
    body = re.sub(r"!\[[^\]]*\]\([^)]*\)\n*", "", body).strip()
    page = (root / "docs" / "realistic.md").read_text(encoding="utf-8")
    section = page.split(f"<!-- generated: {name} -->", 1)[1].split(f"<!-- end: {name} -->", 1)[0]
    section = re.sub(r"!\[[^\]]*\]\([^)]*\)\n*", "", section.split("\n", 3)[3]).strip()  # without the folder line
    assert section == body
