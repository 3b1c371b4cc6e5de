"""The LP relaxation's dual bound (uavcov.cover.CoverageProblem.dual_bound) and its report."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import uavcov
from uavcov.cover import CoverageProblem, GreedySettings, Viewpoints, viewpoint_lattice
from uavcov.experiments._results import ResultsFolder
from uavcov.limits import Constraints
from uavcov.paper import OracleRow
from uavcov.paper._bounds import bounds_markdown, read_bounds, write_bounds
from uavcov.terrain import buildings_scene


def _scenes() -> list[tuple[str, uavcov.Visibility, Viewpoints]]:
    hills = uavcov.gaussian_hills(size=30.0, spacing=2.0, n_hills=4, rng=3)
    limits = Constraints(h_min=1.0, h_max=8.0, z_max=60.0, d_safe=1.0)
    town = buildings_scene(size=24.0, n_buildings=3, spacing=1.0, rng=2)
    return [
        ("hills", uavcov.Visibility(hills, 9.0), viewpoint_lattice(hills, limits, GreedySettings(spacing=3.0, n_heights=3))),
        (
            "buildings",
            uavcov.Visibility(town, 8.0),
            viewpoint_lattice(town, Constraints(h_min=1.0, z_max=16.0, d_safe=1.0), GreedySettings(spacing=3.0)),
        ),
    ]


def _optimum(m: np.ndarray, w: np.ndarray, k: int) -> float:
    """The best weighted union of k rows of ``m``, by brute force (targets of equal columns merged)."""
    patterns, inverse = np.unique(m.T, axis=0, return_inverse=True)
    weights = np.bincount(inverse.ravel(), weights=w, minlength=patterns.shape[0])
    cols = patterns.T.astype(bool)
    best = float((cols @ weights).max())
    for a in range(cols.shape[0]):
        if k >= 2:
            pair = cols[a][None, :] | cols[a + 1 :]
            if pair.size:
                best = max(best, float((pair @ weights).max()))
            if k == 3:
                for i in range(pair.shape[0]):
                    rest = cols[a + i + 2 :]
                    if rest.size:
                        best = max(best, float(((pair[i][None, :] | rest) @ weights).max()))
    return best


def _certificate_by_hand(m: np.ndarray, shares: np.ndarray, u: np.ndarray, k: int) -> float:
    """The weak-duality bound of ``u``, recomputed here: exact sums, candidate by candidate."""
    assert (u >= 0).all() and (u <= shares).all()
    best = max(math.fsum(u[row]) for row in m)
    return k * best + math.fsum(shares - u)


@pytest.mark.parametrize("k", [1, 2, 3])
@pytest.mark.parametrize("cell", [None, 4.0])
def test_the_dual_bound_is_never_below_the_optimum_nor_greedy(k: int, cell: float | None) -> None:
    for name, vis, full in _scenes():
        lattice = Viewpoints(full.positions[::3].copy(), None, "given", "every third lattice point") if k == 3 else full
        problem = CoverageProblem(vis, lattice, n_threads=2)
        m = problem.dense()
        w = vis.targets.weights
        shares = w / w.sum()
        best = _optimum(m, w, k) / w.sum()
        certificate = problem.dual_bound(k, cell=cell)
        greedy = problem.greedy(k, 1.0)
        assert certificate.bound >= best - 1e-12, (name, k, cell)
        assert certificate.bound >= greedy.coverage
        assert certificate.bound <= problem.ceiling() + 1e-9
        by_hand = _certificate_by_hand(m, shares, np.asarray(certificate.u), k)
        assert by_hand <= certificate.bound <= by_hand + 1e-9
        # weak duality is tight at the LP's optimum: the certificate is the LP value
        assert certificate.bound == pytest.approx(certificate.lp_value, abs=1e-6)


def test_the_dual_bound_beats_the_online_bound_where_that_one_is_trivial() -> None:
    hills = uavcov.gaussian_hills(size=40.0, spacing=1.0, n_hills=5, rng=4)
    limits = Constraints(h_min=1.0, h_max=8.0, z_max=60.0, d_safe=1.0)
    problem = CoverageProblem(uavcov.Visibility(hills, 12.0), viewpoint_lattice(hills, limits, GreedySettings(spacing=5.0)), n_threads=2)
    greedy = problem.greedy(6, 1.0)
    full, clustered = problem.dual_bound(6, cell=None), problem.dual_bound(6)
    assert greedy.coverage <= full.bound <= clustered.bound + 1e-9
    assert clustered.bound < greedy.bound  # the online bound is looser here
    assert problem.certified_bound(6, 1.0) == min(greedy.bound, clustered.bound)


def test_bad_input_to_the_dual_bound_is_a_clear_error() -> None:
    _, vis, lattice = _scenes()[0]
    problem = CoverageProblem(vis, lattice)
    for bad in (0, -1, 1.5, "3", 10**9):
        with pytest.raises((uavcov.errors.InvalidInputError, uavcov.errors.InvalidTypeError)):
            problem.dual_bound(bad)  # type: ignore[arg-type]
    for cell in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(uavcov.errors.InvalidInputError):
            problem.dual_bound(2, cell=cell)


def _row(seed: int, n: int, bound: float) -> OracleRow:
    return OracleRow(seed, n, bound - 0.01, bound, 1.0, 100, 0.5, 0.1, "the best", 1.0, bound, 0.2)


def test_the_bounds_report_sets_each_start_against_its_terrains_bound(tmp_path: Any) -> None:
    bounds = [_row(s, 5, 0.8) for s in range(3)]
    folder = ResultsFolder(tmp_path)
    assert read_bounds(write_bounds(folder, bounds)) == bounds
    runs = [
        {"seed": s, "n_uavs": 5, "init": init, "max_coverage": 0.8 * share, "distance_mean_m": 40.0 + s, "start_time_s": 0.5, "error": ""}
        for s in range(3)
        for init, share in (("cvt", 0.9 + 0.01 * s), ("greedy", 0.95 + 0.01 * s))
    ]
    text = bounds_markdown(runs, bounds)
    assert "| 5 | 3 | 0.800 | 1.000 / 0.800 | 0.790 | 0.910 [" in text
    assert "| 5 | greedy | 3 | 0.050 [0.050, 0.050] | 41.00 | 0.50 |" in text
    (tmp_path / "bad.csv").write_text("seed,n_uavs\n1,x\n", encoding="utf-8")
    with pytest.raises(uavcov.errors.ResultsFormatError):
        read_bounds(tmp_path / "bad.csv")
