"""The paper's experiment settings and published numbers (uavcov.paper)."""

from __future__ import annotations

import pickle
import re
from pathlib import Path

import numpy as np
import pytest

from uavcov import paper
from uavcov.errors import InvalidInputError, InvalidTypeError

PAPER_TEX = Path(__file__).resolve().parents[2] / "shared" / "reference" / "paper.tex"


def _paper_text() -> str:
    if not PAPER_TEX.exists():
        pytest.skip(f"the paper's source is not beside the repository ({PAPER_TEX})")
    return PAPER_TEX.read_text()


# --- the published numbers are the paper's ---------------------------------------------------


def test_table1_is_the_papers_table():
    text = _paper_text()
    table = text[text.index("\\begin{tabular}") : text.index("\\end{tabular}")]
    rows = re.findall(r"^\s*(\d+)\s*&(.*?)\\\\", table, flags=re.MULTILINE)
    assert [int(n) for n, _ in rows] == [5, 8, 12, 20]
    for n, rest in rows:
        values = [float(v) for v in re.findall(r"\d\.\d+", rest)]
        assert len(values) == 10
        cvt_i, cvt_is, cvt_m, cvt_ms, rnd_i, rnd_is, rnd_m, rnd_ms, cor_m, cor_ms = values
        pub = paper.PUBLISHED_TABLE1
        n = int(n)
        assert pub[(n, "cvt", "initial")] == paper.PublishedValue(cvt_i, cvt_is)
        assert pub[(n, "cvt", "max")] == paper.PublishedValue(cvt_m, cvt_ms)
        assert pub[(n, "random", "initial")] == paper.PublishedValue(rnd_i, rnd_is)
        assert pub[(n, "random", "max")] == paper.PublishedValue(rnd_m, rnd_ms)
        assert pub[(n, "corner", "max")] == paper.PublishedValue(cor_m, cor_ms)
    assert len(paper.PUBLISHED_TABLE1) == 4 * len(paper.TABLE1_COLUMNS)


def test_pyramid_and_fig6_numbers_are_the_papers():
    text = " ".join(_paper_text().split())
    found = re.search(r"initialization with this input surface is \$(\d\.\d+)\$ with a standard deviation "
                      r"\$\\sigma=(\d\.\d+)\$, while the final maximum coverage achieved is \$(\d\.\d+)\$ "
                      r"with a standard deviation \$\\sigma=(\d\.\d+)\$", text)
    assert found, "the pyramid sentence was not found in the paper"
    i, i_sd, m, m_sd = (float(v) for v in found.groups())
    assert paper.PUBLISHED_PYRAMID["initial"] == paper.PublishedValue(i, i_sd)
    assert paper.PUBLISHED_PYRAMID["max"] == paper.PublishedValue(m, m_sd)
    fig6 = re.search(r"maximum obtained values for the three strategies are (\d\.\d+), (\d\.\d+) and (\d\.\d+)", text)
    assert fig6, "the Fig. 6 caption was not found in the paper"
    # the caption lists red (corner), blue (random), green (CVT)
    assert dict(zip(("corner", "random", "cvt"), (float(v) for v in fig6.groups()))) == dict(paper.PUBLISHED_FIG6_MAX)


# --- the settings are the paper's where it gives them, and consistent -------------------------


def test_experiments_follow_the_paper():
    t = paper.TABLE1
    assert (t.team_sizes, t.starts, t.d_max, t.n_prior, t.iterations) == ((5, 8, 12, 20), ("cvt", "random", "corner"), 25.0, 30, 500)
    assert t.prior == "random" and t.seeds == tuple(range(40)) and len(t.cells()) == 12
    assert t.terrain.size == 100.0 and t.terrain.n_hills == 7 and t.terrain.spacing == 1.0
    p = paper.PYRAMID
    assert (p.team_sizes, p.starts, p.prior, p.d_max, p.terrain, p.seeds) == ((12,), ("cvt",), "pyramid", 25.0, t.terrain, t.seeds)
    assert (paper.EXAMPLE.team_sizes, paper.EXAMPLE.d_max, paper.EXAMPLE.n_prior) == ((9,), 35.0, 30)
    assert paper.COMPARISON.team_sizes == (10,) and set(paper.COMPARISON.starts) == {"cvt", "random", "corner"}
    b = paper.BUILDINGS
    assert (b.team_sizes, b.d_max, b.terrain.size) == ((4,), 8.0, 24.0)
    assert set(paper.EXPERIMENTS) == {"table1", "pyramid", "example", "comparison", "buildings"}
    assert not set(paper.DEV_SEEDS) & set(paper.HELD_OUT_SEEDS)


@pytest.mark.parametrize("name", sorted(paper.EXPERIMENTS))
def test_every_team_fits_under_the_ceiling(name):
    """The highest ground of a few scenarios plus h_min stays under z_max, so no start is infeasible."""
    e = paper.EXPERIMENTS[name]
    assert e.flight.h_min <= e.flight.start_altitude or e.flight.start_altitude == 0.0
    for seed in (0, 1, 1000):
        terrain = e.terrain.make(seed)
        assert float(terrain.bounds[1, 2]) + e.flight.start_altitude < e.flight.z_max


def test_experiments_pickle_and_compare_equal():
    for e in paper.EXPERIMENTS.values():
        assert pickle.loads(pickle.dumps(e)) == e


def test_with_changes_sets_nested_fields_and_refuses_unknown_groups():
    e = paper.TABLE1.with_changes(**{"flight.h_min": 3.0, "cao.alpha0": 2.5, "terrain.sigma": 7.0, "iterations": 9})
    assert (e.flight.h_min, e.cao.alpha0, e.terrain.sigma, e.iterations) == (3.0, 2.5, 7.0, 9)
    # the other fields are kept, and the original is left as it was
    assert e.flight.d_safe == paper.TABLE1.flight.d_safe and e.cao.decay == paper.TABLE1.cao.decay
    assert paper.TABLE1.with_changes() == paper.TABLE1 and e != paper.TABLE1
    with pytest.raises(InvalidInputError):
        paper.TABLE1.with_changes(**{"nothing.x": 1})
    with pytest.raises(InvalidInputError):
        paper.Flight(h_min=10.0, z_max=5.0)
    with pytest.raises(InvalidInputError):
        paper.HillsTerrain(heights=(30.0, 10.0))


# --- a tiny run with the paper's settings ----------------------------------------------------

_TINY = paper.TABLE1.with_changes(**{"terrain.spacing": 4.0})


@pytest.mark.parametrize("start", ["cvt", "random", "corner"])
def test_tiny_table1_run_works_and_is_deterministic(start):
    a = paper.run_paper_mission(_TINY, seed=1000, n_uavs=5, start=start, iterations=4)
    b = paper.run_paper_mission(_TINY, seed=1000, n_uavs=5, start=start, iterations=4)
    assert a.coverage.shape == (5,)
    assert 0.0 <= a.initial_coverage <= a.best_coverage <= 1.0
    np.testing.assert_array_equal(a.trajectory, b.trajectory)
    f = _TINY.flight
    x0 = a.initial_positions
    clearance = x0[:, 2] - a.terrain.ground_height(x0[:, :2])
    assert (clearance >= f.h_min - 1e-9).all() and (x0[:, 2] <= f.z_max).all()
    assert a.settings.d_max == 25.0 and a.settings.h_min == f.h_min and a.settings.cao == _TINY.cao.resolved(5)


def test_corner_start_is_the_lattice_of_the_chosen_spacing():
    e = _TINY.with_changes(**{"flight.corner_spacing": 4.0})
    r = paper.run_paper_mission(e, seed=1001, n_uavs=5, start="corner", iterations=0)
    xy = np.sort(r.initial_positions[:, 0]), np.sort(r.initial_positions[:, 1])
    # 5 UAVs: a 3-column lattice, 4 m apart, 2 m in from the south-west corner
    np.testing.assert_allclose(np.unique(xy[0]), [2.0, 6.0, 10.0])
    np.testing.assert_allclose(np.unique(xy[1]), [2.0, 6.0])


def test_pyramid_run_uses_five_known_points():
    r = paper.run_paper_mission(paper.PYRAMID.with_changes(**{"terrain.spacing": 4.0}), seed=1000, n_uavs=12, start="cvt", iterations=0)
    assert r.prior_points.shape == (5, 3) and r.settings.prior_kind == "pyramid"


def test_buildings_pairs_start_on_opposite_sides():
    e = paper.BUILDINGS.with_changes(**{"terrain.spacing": 1.0})
    r = paper.run_paper_mission(e, seed=0, n_uavs=4, start="pairs", iterations=2)
    x = r.initial_positions[:, 0]
    assert (np.sort(x)[:2] < 6.0).all() and (np.sort(x)[2:] > 18.0).all()
    assert 0.0 <= r.best_coverage <= 1.0


def test_bad_arguments_raise_clear_errors():
    with pytest.raises(InvalidInputError):
        paper.run_paper_mission(_TINY, seed=1, n_uavs=5, start="pairs", iterations=0)
    with pytest.raises(InvalidTypeError):
        paper.run_paper_mission(_TINY, seed=1.5, n_uavs=5, start="cvt", iterations=0)  # type: ignore[arg-type]
    with pytest.raises(InvalidTypeError):
        paper.run_paper_mission("table1", seed=1, n_uavs=5, start="cvt", iterations=0)  # type: ignore[arg-type]


# --- where the starts fly ---------------------------------------------------------------------


def test_prior_referenced_start_flies_above_s_prime_or_climbs_over_the_real_ground():
    """Against an independent S': scipy's linear interpolant of the same prior points."""
    from scipy.interpolate import LinearNDInterpolator

    e = _TINY.with_changes(**{"flight.altitude_reference": "prior", "flight.start_altitude": 2.0,
                              "flight.h_min": 1.0, "flight.climb_margin": 1.0})
    seed = 1002
    r = paper.run_paper_mission(e, seed=seed, n_uavs=8, start="random", iterations=0)
    terrain = e.terrain.make(seed)
    given = paper.start_positions(e, terrain, 8, "random", seed)
    s_prime = LinearNDInterpolator(r.prior_points[:, :2], r.prior_points[:, 2])
    ground = terrain.ground_height(given[:, :2])
    expected = s_prime(given[:, :2]) + 2.0
    expected = np.where(expected < ground + 1.0, ground + 2.0, expected)
    np.testing.assert_allclose(given[:, 2], expected, atol=1e-9)
    assert r.prior_points.shape == (34, 3)  # 30 random points and the 4 corners
    # the mission started from exactly these positions (all of them already admissible)
    np.testing.assert_allclose(r.initial_positions, given, atol=1e-6)


def test_ground_referenced_start_is_the_missions_own():
    """start_positions rebuilds what run_mission builds itself for cvt and random starts."""
    from uavcov.mission import run_mission
    from uavcov.prior import Prior

    e = _TINY.with_changes(**{"flight.altitude_reference": "ground", "flight.start_altitude": 5.0, "flight.h_min": 2.0})
    seed = 1003
    terrain = e.terrain.make(seed)
    for start in ("cvt", "random"):
        own = paper.run_paper_mission(e, seed=seed, n_uavs=6, start=start, iterations=3)
        given = paper.start_positions(e, terrain, 6, start, seed)
        ground = terrain.ground_height(given[:, :2])
        np.testing.assert_allclose(given[:, 2] - ground, 5.0, atol=1e-9)
        again = run_mission(terrain, n_uavs=6, d_max=25.0, prior=Prior(own.prior_points, kind="random"), start=given, iterations=3,
                            settings=e.cao, h_min=2.0, z_max=e.flight.z_max, d_safe=e.flight.d_safe, rng=seed, n_threads=1)
        np.testing.assert_allclose(again.trajectory, own.trajectory, atol=1e-9)


def test_random_altitude_and_corner_altitude():
    e = _TINY.with_changes(**{"flight.altitude_reference": "ground", "flight.random_altitude": (3.0, 9.0),
                              "flight.corner_altitude": 7.0, "flight.climb_margin": 0.0, "flight.h_min": 1.0})
    terrain = e.terrain.make(1004)
    x = paper.start_positions(e, terrain, 20, "random", 1004)
    height = x[:, 2] - terrain.ground_height(x[:, :2])
    assert (height >= 3.0).all() and (height <= 9.0).all() and np.ptp(height) > 1.0
    c = paper.start_positions(e, terrain, 5, "corner", 1004)
    np.testing.assert_allclose(c[:, 2] - terrain.ground_height(c[:, :2]), 7.0)
    with pytest.raises(InvalidInputError):
        paper.Flight(random_altitude=(5.0, 1.0))
    with pytest.raises(InvalidInputError):
        paper.Flight(altitude_reference="sea")


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
