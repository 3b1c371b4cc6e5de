"""The paper's claims measured on rows (uavcov.claims): gains, robustness, speed, convergence."""

from __future__ import annotations

import numpy as np
import pytest

from uavcov import claims, paper
from uavcov.results import ResultsFolder
from uavcov.sweep import experiment_specs, run_specs


def _rows(values: dict[tuple[int, str], list[float]]) -> list[dict]:
    rows = []
    for (n, start), column in values.items():
        for seed, value in enumerate(column):
            rows.append(
                {
                    "run_id": f"t-{start}-{n}-{seed}",
                    "n_uavs": n,
                    "init": start,
                    "seed": seed,
                    "max_coverage": value,
                    "iterations_to_95": 10 * seed,
                    "error": "",
                }
            )
    return rows


def test_published_gains_are_the_papers_table():
    # "between a minimum of 5 % and a maximum of 12 %": 0.65/0.61, 0.84/0.75, 0.92/0.86, 0.98/0.93
    assert {n: round(100 * g, 1) for n, g in claims.PUBLISHED_GAIN.items()} == {5: 6.6, 8: 12.0, 12: 7.0, 20: 5.4}


def test_headline_is_paired_and_its_intervals_cover_a_known_gain():
    rng = np.random.default_rng(3)
    terrain = rng.uniform(0.5, 0.8, 40)  # what each terrain allows: shared by both starts
    rows = _rows({(8, "cvt"): list(terrain * 1.10 + rng.normal(0, 0.002, 40)), (8, "random"): list(terrain)})
    (gain,) = claims.headline(rows)
    assert gain.pairs == 40 and gain.gain == pytest.approx(0.10, abs=0.003)
    assert gain.gain_ci[0] < 0.10 < gain.gain_ci[1] and gain.gain_ci[1] - gain.gain_ci[0] < 0.01  # pairing removes the terrain spread
    assert gain.difference_ci[0] < gain.difference < gain.difference_ci[1]
    assert not gain.within() and gain.published == claims.PUBLISHED_GAIN[8]
    assert claims.headline(rows) == claims.headline(list(reversed(rows)))  # reproducible, order-free
    # a terrain with one start only is not a pair
    assert claims.headline(rows[:-1])[0].pairs == 39


def test_robustness_and_speed_verdicts():
    rows = _rows({(5, "cvt"): [0.70, 0.71, 0.72], (5, "random"): [0.60, 0.70, 0.65], (5, "corner"): [0.50, 0.505, 0.51]})
    (row,) = claims.robustness(rows)
    assert row.cvt_highest_mean and not row.cvt_smallest_sigma  # corner is tighter here
    assert claims.speed(rows)[(5, "cvt")] == (10.0, 10.0)
    text = claims.claims_markdown(rows)
    assert "| 5 | 3 |" in text and "NO" in text


def test_convergence_reads_the_stored_curves(tmp_path):
    small = paper.TABLE1.with_changes(**{"terrain.spacing": 5.0, "iterations": 6})
    folder = ResultsFolder(tmp_path)
    rows = run_specs(experiment_specs(small, seeds=[0], team_sizes=[5], starts=["cvt", "corner"]), out=folder, workers=1)
    loose = claims.convergence(folder, rows, from_iteration=3, band=1.0)
    assert (loose.runs, loose.converged, loose.share) == (2, 2, 1.0)
    strict = claims.convergence(folder, rows, from_iteration=3, band=0.0)
    from uavcov.records import load_mission

    curves = [load_mission(folder.run_file(r["run_id"])).coverage for r in rows]
    expected = sum(float(c.max() - c[3:].min()) <= 1e-12 for c in curves)
    assert strict.converged == expected and strict.runs == 2
    assert claims.convergence(folder, rows, from_iteration=7).runs == 0  # 7 measurements: too short to judge
    assert "Convergence" in claims.claims_markdown(rows, folder)
