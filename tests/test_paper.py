"""The paper's experiment settings and published numbers (uavcov.paper._data)."""

from __future__ import annotations

import pickle
import re
from pathlib import Path

import numpy as np
import pytest

from uavcov import Constraints, StartSettings
from uavcov.errors import InvalidInputError, InvalidTypeError
from uavcov.experiments import Experiment, RunSpec
from uavcov.paper import _data as paper

EXCERPTS = Path(__file__).resolve().parents[1] / "docs" / "paper-excerpts.md"
PAPER_TEX = Path(__file__).resolve().parents[2] / "shared" / "reference" / "paper.tex"


def _excerpts() -> str:
    return EXCERPTS.read_text(encoding="utf-8")


def _blocks() -> list[str]:
    return re.findall(r"```latex\n(.*?)\n```", _excerpts(), flags=re.DOTALL)


# --- the published numbers are the paper's ---------------------------------------------------


def test_table1_is_the_papers_table():
    text = _excerpts()
    table = text[text.index("\\begin{tabular}") : text.index("\\end{tabular}")]
    rows = re.findall(r"^\s*(\d+)\s*&(.*?)\\\\", table, flags=re.MULTILINE)
    assert [int(n) for n, _ in rows] == [5, 8, 12, 20]
    for size, rest in rows:
        values = [float(v) for v in re.findall(r"\d\.\d+", rest)]
        assert len(values) == 10
        cvt_i, cvt_is, cvt_m, cvt_ms, rnd_i, rnd_is, rnd_m, rnd_ms, cor_m, cor_ms = values
        pub = paper.PUBLISHED_TABLE1
        n = int(size)
        assert pub[(n, "cvt", "initial")] == paper.PublishedValue(cvt_i, cvt_is)
        assert pub[(n, "cvt", "max")] == paper.PublishedValue(cvt_m, cvt_ms)
        assert pub[(n, "random", "initial")] == paper.PublishedValue(rnd_i, rnd_is)
        assert pub[(n, "random", "max")] == paper.PublishedValue(rnd_m, rnd_ms)
        assert pub[(n, "corner", "max")] == paper.PublishedValue(cor_m, cor_ms)
    assert len(paper.PUBLISHED_TABLE1) == 4 * len(paper.TABLE1_COLUMNS)


def test_pyramid_and_fig6_numbers_are_the_papers():
    text = " ".join(_excerpts().split())
    found = re.search(
        r"initialization with this input surface is \$(\d\.\d+)\$ with a standard deviation "
        r"\$\\sigma=(\d\.\d+)\$, while the final maximum coverage achieved is \$(\d\.\d+)\$ "
        r"with a standard deviation \$\\sigma=(\d\.\d+)\$",
        text,
    )
    assert found, "the pyramid sentence was not found in the excerpts"
    i, i_sd, m, m_sd = (float(v) for v in found.groups())
    assert paper.PUBLISHED_PYRAMID["initial"] == paper.PublishedValue(i, i_sd)
    assert paper.PUBLISHED_PYRAMID["max"] == paper.PublishedValue(m, m_sd)
    fig6 = re.search(r"maximum obtained values for the three strategies are (\d\.\d+), (\d\.\d+) and (\d\.\d+)", text)
    assert fig6, "the Fig. 6 caption was not found in the excerpts"
    # the caption lists red (corner), blue (random), green (CVT)
    assert dict(zip(("corner", "random", "cvt"), (float(v) for v in fig6.groups()), strict=True)) == dict(paper.PUBLISHED_FIG6_MAX)


def test_the_excerpts_are_verbatim_in_the_paper():
    blocks = _blocks()
    assert len(blocks) == 4
    if not PAPER_TEX.exists():
        pytest.skip(f"the paper's source is not beside the repository ({PAPER_TEX}); the excerpts are checked where it is")
    source = PAPER_TEX.read_text(encoding="utf-8")
    for block in blocks:
        assert block in source, block[:80]


# --- the settings are the paper's where it gives them, and consistent -------------------------


def test_experiments_follow_the_paper():
    t = paper.TABLE1
    assert (t.team_sizes, t.starts, t.d_max, t.mission.n_prior, t.iterations) == (
        (5, 8, 12, 20),
        ("cvt", "random", "corner", "greedy"),
        25.0,
        30,
        500,
    )
    assert t.prior == "random" and t.seeds == tuple(range(40)) and len(t.cells()) == 16
    assert t.terrain.size == 100.0 and t.terrain.n_hills == 7 and t.terrain.spacing == 1.0
    p = paper.PYRAMID
    assert (p.team_sizes, p.starts, p.prior, p.d_max, p.terrain, p.seeds) == ((12,), ("cvt",), "pyramid", 25.0, t.terrain, t.seeds)
    assert (paper.EXAMPLE.team_sizes, paper.EXAMPLE.d_max, paper.EXAMPLE.mission.n_prior) == ((9,), 35.0, 30)
    assert paper.COMPARISON.team_sizes == (10,) and set(paper.COMPARISON.starts) == {"cvt", "random", "corner"}
    b = paper.BUILDINGS
    assert (b.team_sizes, b.d_max, b.terrain.size) == ((4,), 8.0, 24.0)
    assert set(paper.EXPERIMENTS) == {"table1", "pyramid", "example", "comparison", "buildings"}
    assert not set(paper.DEV_SEEDS) & set(paper.HELD_OUT_SEEDS)


@pytest.mark.parametrize("name", sorted(paper.EXPERIMENTS))
def test_every_experiment_runs_the_papers_model(name):
    """Every constraint of eq. 2 active, no mechanism the paper's simulations lack."""
    mission = paper.EXPERIMENTS[name].mission
    limits, start = mission.constraints, mission.start
    assert limits.h_max is not None and 0.0 < limits.h_min < limits.h_max  # minimum and maximum height of flight
    assert limits.check_moves is True and limits.d_safe > 0.0  # robot-ground and robot-robot, every move
    assert mission.cao.measurement_noise == 0.0  # the paper measures coverage exactly
    assert start.corner_altitude is None and start.random_altitude is None  # one altitude rule for every start
    assert 0.5 < mission.cao.decay <= 1.0  # the step meets the paper's conditions (sum infinite, squares finite)


@pytest.mark.parametrize("name", sorted(paper.EXPERIMENTS))
def test_every_team_fits_under_the_ceiling(name):
    """The highest ground of a few scenarios plus the start altitude stays under z_max, so no start is infeasible."""
    e = paper.EXPERIMENTS[name]
    limits, start = e.mission.constraints, e.mission.start
    assert limits.h_min <= start.altitude or start.altitude == 0.0
    for seed in (0, 1, 1000):
        terrain = e.terrain.make(seed)
        assert float(terrain.bounds[1, 2]) + start.altitude < limits.z_max


def test_experiments_pickle_and_compare_equal():
    for e in paper.EXPERIMENTS.values():
        assert pickle.loads(pickle.dumps(e)) == e
    assert paper.PaperExperiment is Experiment


def test_with_changes_sets_nested_fields_and_refuses_unknown_groups():
    e = paper.TABLE1.with_changes(**{"constraints.h_min": 3.0, "cao.alpha0": 2.5, "terrain.sigma": 7.0, "iterations": 9})
    m = e.mission
    assert (m.constraints.h_min, m.cao.alpha0, e.terrain.sigma, e.iterations) == (3.0, 2.5, 7.0, 9)
    # the other fields are kept, and the original is left as it was
    assert m.constraints.d_safe == paper.TABLE1.mission.constraints.d_safe and m.cao.decay == paper.TABLE1.mission.cao.decay
    assert paper.TABLE1.with_changes() == paper.TABLE1 and e != paper.TABLE1
    with pytest.raises(InvalidInputError):
        paper.TABLE1.with_changes(**{"nothing.x": 1})
    with pytest.raises(InvalidInputError):
        paper.TABLE1.with_changes(**{"flight.h_min": 1.0})  # the group of earlier releases is gone
    with pytest.raises(InvalidInputError):
        Constraints(h_min=10.0, z_max=5.0)
    with pytest.raises(InvalidInputError):
        paper.HillsGenerator(heights=(30.0, 10.0))


# --- a tiny run with the paper's settings ----------------------------------------------------

_TINY = paper.TABLE1.with_changes(**{"terrain.spacing": 4.0})


def _run(experiment: Experiment, seed: int, n_uavs: int, start: str, iterations: int | None = None):
    if iterations is not None:
        experiment = experiment.with_changes(iterations=iterations)
    return RunSpec(experiment, seed, n_uavs, start).run(n_threads=1)


@pytest.mark.parametrize("start", ["cvt", "random", "corner"])
def test_tiny_table1_run_works_and_is_deterministic(start):
    a = _run(_TINY, 1000, 5, start, iterations=4)
    b = _run(_TINY, 1000, 5, start, iterations=4)
    assert a.coverage.shape == (5,)
    assert 0.0 <= a.initial_coverage <= a.best_coverage <= 1.0
    np.testing.assert_array_equal(a.trajectory, b.trajectory)
    limits = _TINY.mission.constraints
    x0 = a.initial_positions
    clearance = x0[:, 2] - a.terrain.ground_height(x0[:, :2])
    assert (clearance >= limits.h_min - 1e-9).all() and (x0[:, 2] <= limits.z_max).all()
    assert a.settings.d_max == 25.0 and a.settings.constraints.h_min == limits.h_min and a.settings.cao == _TINY.mission.cao.resolved(5)
    assert a.settings.start.kind == start and (a.cvt is not None) == (start == "cvt")


def test_corner_start_is_the_lattice_of_the_chosen_spacing():
    e = _TINY.with_changes(**{"start.corner_spacing": 4.0})
    r = _run(e, 1001, 5, "corner", iterations=0)
    xy = np.sort(r.initial_positions[:, 0]), np.sort(r.initial_positions[:, 1])
    # 5 UAVs: a 3-column lattice, 4 m apart, 2 m in from the south-west corner
    np.testing.assert_allclose(np.unique(xy[0]), [2.0, 6.0, 10.0])
    np.testing.assert_allclose(np.unique(xy[1]), [2.0, 6.0])


def test_pyramid_run_uses_five_known_points():
    r = _run(paper.PYRAMID.with_changes(**{"terrain.spacing": 4.0}), 1000, 12, "cvt", iterations=0)
    assert r.prior_points.shape == (5, 3) and r.prior_kind == "pyramid"


def test_buildings_pairs_start_on_opposite_sides():
    e = paper.BUILDINGS.with_changes(**{"terrain.spacing": 1.0})
    r = _run(e, 0, 4, "pairs", iterations=2)
    x = r.initial_positions[:, 0]
    assert (np.sort(x)[:2] < 6.0).all() and (np.sort(x)[2:] > 18.0).all()
    assert 0.0 <= r.best_coverage <= 1.0
    assert r.prior_kind == "surface"  # the team was given the simplified map


def test_bad_arguments_raise_clear_errors():
    with pytest.raises(InvalidInputError):
        RunSpec(_TINY, 1, 5, "pairs")
    with pytest.raises(InvalidInputError):
        RunSpec(_TINY, 1.5, 5, "cvt")  # type: ignore[arg-type]
    with pytest.raises(InvalidTypeError):
        RunSpec("table1", 1, 5, "cvt")  # type: ignore[arg-type]


# --- where the starts fly ---------------------------------------------------------------------


def test_prior_referenced_start_flies_above_s_prime_or_climbs_over_the_real_ground():
    """Against an independent S': scipy's linear interpolant of the same prior points."""
    from scipy.interpolate import LinearNDInterpolator

    e = _TINY.with_changes(**{"start.altitude_reference": "prior", "start.altitude": 2.0, "constraints.h_min": 1.0, "start.climb": 1.0})
    seed = 1002
    r = _run(e, seed, 8, "random", iterations=0)
    terrain = r.terrain
    s_prime = LinearNDInterpolator(r.prior_points[:, :2], r.prior_points[:, 2])
    xy = r.start_positions[:, :2]
    np.testing.assert_allclose(r.start_positions[:, 2], s_prime(xy) + 2.0, atol=1e-9)
    ground = terrain.ground_height(xy)
    expected = np.where(s_prime(xy) + 2.0 < ground + 1.0, ground + 2.0, s_prime(xy) + 2.0)
    assert r.prior_points.shape == (34, 3)  # 30 random points and the 4 corners
    # the mission started from exactly these positions, lifted where the real ground asked for it
    np.testing.assert_allclose(r.initial_positions[:, :2], xy, atol=1e-6)
    np.testing.assert_allclose(r.initial_positions[:, 2], expected, atol=1e-6)


def test_random_altitude_and_corner_altitude():
    e = _TINY.with_changes(
        **{
            "start.altitude_reference": "ground",
            "start.random_altitude": (3.0, 9.0),
            "start.corner_altitude": 7.0,
            "start.climb": 0.0,
            "constraints.h_min": 1.0,
        }
    )
    r = _run(e, 1004, 20, "random", iterations=0)
    x = r.start_positions
    height = x[:, 2] - r.terrain.ground_height(x[:, :2])
    assert (height >= 3.0 - 1e-9).all() and (height <= 9.0 + 1e-9).all() and np.ptp(height) > 1.0
    c = _run(e, 1004, 5, "corner", iterations=0).start_positions
    np.testing.assert_allclose(c[:, 2] - r.terrain.ground_height(c[:, :2]), 7.0)
    with pytest.raises(InvalidInputError):
        StartSettings(random_altitude=(5.0, 1.0))
    with pytest.raises(InvalidInputError):
        StartSettings(altitude_reference="sea")


def test_experiment_fields_are_checked():
    with pytest.raises(InvalidInputError):
        paper.TABLE1.with_changes(starts=("cvt", "spiral"))
    with pytest.raises(InvalidInputError):
        paper.TABLE1.with_changes(team_sizes=(5, 0))
    with pytest.raises(InvalidInputError):
        paper.TABLE1.with_changes(prior="map")
    with pytest.raises(InvalidInputError):
        paper.TABLE1.with_changes(d_max=-1.0)
    with pytest.raises(InvalidTypeError):
        paper.TABLE1.with_changes(cao={"alpha0": 1.0})


def test_paper_module_runs_nothing():
    """uavcov.paper._data is data: no function of its own (the sweep runs experiments)."""
    import inspect

    own = [name for name, value in vars(paper).items() if inspect.isfunction(value) and value.__module__ == paper.__name__]
    assert own == []


def test_every_ablation_is_found_by_its_own_unique_name():
    assert list(paper.ABLATIONS_BY_NAME) == [a.name for a in paper.ABLATIONS]
    assert all(paper.ABLATIONS_BY_NAME[a.name] is a for a in paper.ABLATIONS)
