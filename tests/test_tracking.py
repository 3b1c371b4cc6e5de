"""CoverageTracker: the objective along a moving team's path, to the last bit."""

from __future__ import annotations

import pickle
from dataclasses import replace

import numpy as np
import pytest

import uavcov
from uavcov.errors import InvalidInputError, InvalidTypeError
from uavcov.paper import _data as paper


@pytest.fixture(scope="module")
def hills() -> uavcov.Terrain:
    return paper.TABLE1.terrain.make(4242)


def _path(terrain: uavcov.Terrain, n_uavs: int, steps: int, seed: int) -> list[np.ndarray]:
    """A team's random walk over the terrain: steps shrinking from 2 m to 2.5 cm, heights from
    grazing (5 cm) to 12 m above the ground, one UAV under it."""
    rng = np.random.default_rng(seed)
    lo, hi = np.asarray(terrain.bounds, dtype=float)
    xy = lo[:2] + (hi[:2] - lo[:2]) * rng.uniform(0.1, 0.9, (n_uavs, 2))
    height = np.linspace(0.05, 12.0, n_uavs)
    height[1] = -0.5
    out = []
    for k in range(steps):
        xy = np.clip(xy + rng.normal(0.0, 2.0 / (1.0 + k), xy.shape), lo[:2], hi[:2])
        ground = terrain.ground_height(xy)
        out.append(np.column_stack([xy, ground + height]))
    return out


@pytest.mark.parametrize("margin", [0.5, 1.0, 3.0, None])
def test_the_tracker_measures_what_the_objective_does_along_a_path(hills, margin):
    vis = uavcov.Visibility(hills, 25.0, n_threads=2)
    tracker = vis.tracker(margin=margin)
    assert tracker.certifies and tracker.margin == margin and tracker.visibility is vis
    settled, seen = [], []
    for team in _path(hills, 6, 80, seed=int((margin or 2.0) * 10)):
        assert tracker.coverage(team) == vis.coverage(team)  # to the last bit
        mask = vis.seen(team)
        np.testing.assert_array_equal(tracker.seen(team), mask)
        settled.append(tracker.settled)
        seen.append(mask.sum())
    # Once the steps are small, certificates settle a good share of the seen targets.
    assert np.mean(settled[40:]) > 0.3 * np.mean(seen[40:])


def test_on_the_mesh_method_the_tracker_is_the_plain_objective(hills):
    vis = uavcov.Visibility(hills, 25.0, method="mesh")
    tracker = vis.tracker()
    assert not tracker.certifies
    for team in _path(hills, 3, 5, seed=1):
        assert tracker.coverage(team) == vis.coverage(team)
        assert tracker.settled == 0


def test_a_mission_measures_with_the_objectives_values(hills):
    spec = replace(paper.TABLE1.mission, n_uavs=5, iterations=60)
    result = uavcov.run_mission(hills, spec, rng=3, n_threads=1)
    vis = uavcov.Visibility(hills, spec.d_max, n_threads=1)
    values = [vis.coverage(x) for x in result.trajectory]
    np.testing.assert_array_equal(result.coverage, values)


def test_bad_margins_and_teams_are_refused(hills):
    vis = uavcov.Visibility(hills, 25.0)
    for margin in (0.0, -1.0, float("nan"), float("inf"), 1e309):
        with pytest.raises(InvalidInputError):
            vis.tracker(margin=margin)
    with pytest.raises(InvalidTypeError):
        vis.tracker(margin="1")  # type: ignore[arg-type]
    with pytest.raises(InvalidTypeError):
        uavcov.engine.CoverageTracker("vis", 1.0)  # type: ignore[arg-type]
    tracker = vis.tracker()
    for team in ([], [[1.0, 2.0]], [[1.0, np.nan, 3.0]], [[1.0, 2.0, 1e300]]):
        with pytest.raises((InvalidInputError, InvalidTypeError)):
            tracker.coverage(team)
    with pytest.raises(TypeError):
        pickle.dumps(tracker)
