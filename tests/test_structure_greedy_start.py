"""A structure's "greedy" start (issue 42): the full-knowledge reference's greedy on S' alone,
its candidates flown out of S' as the CVT start's generators are."""

from __future__ import annotations

import numpy as np
import pytest

import uavcov
from uavcov.cover import GreedySettings, surface_normals
from uavcov.errors import InfeasibleError, InvalidInputError
from uavcov.limits import Constraints
from uavcov.placement import StartSettings, start_configuration
from uavcov.placement._starts import structure_greedy_start
from uavcov.placement._starts3d import fly_out
from uavcov.structures import STRUCTURE_FAMILIES, Structure, reconstruct_structure, sample_structure_prior

BOX = np.array([[0, 0, 0], [12, 0, 0], [12, 9, 0], [0, 9, 0], [0, 0, 16], [12, 0, 16], [12, 9, 16], [0, 9, 16]], float)
WALLS = [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]
LIMITS = Constraints(clearance="standoff", h_min=2.0, d_safe=1.0, z_max=26.0, check_moves=True)


def _box() -> Structure:
    ground = np.array([[-20, -20, 0], [30, -20, 0], [30, 30, 0], [-20, 30, 0]], float)
    faces = np.vstack([[[0, 1, 2], [0, 2, 3]], np.array(WALLS) + 4])
    return Structure(
        "box", uavcov.Terrain(np.vstack([ground, BOX]), faces), np.array([0, 0, 1, 1] + [2] * 10), ("ground", "contact", "building"), 0
    )


def _spec(altitude: float = 3.0, spacing: float = 3.0) -> StartSettings:
    return StartSettings(kind="greedy", altitude=altitude, altitude_reference="normal", greedy=GreedySettings(spacing=spacing))


def _spread(surface: uavcov.Terrain, spacing: float, at_least: int) -> uavcov.Targets:
    """S''s targets at one per cell^2, the cell the spacing or less so that the area holds
    ``at_least``; on a mesh with more triangles than that (S' grown into its envelope), the first
    of each cube of the cell holding the cube's weight (a loop, as documented)."""
    cell = min(spacing, np.sqrt(surface.area / at_least))
    targets = surface.default_targets(density=1.0 / cell**2)
    if surface.n_faces <= surface.area / cell**2:
        return targets
    low = targets.points.min(axis=0)
    cubes: dict[tuple[int, ...], list] = {}
    for point, weight in zip(targets.points, targets.weights, strict=True):
        key = tuple(int(k) for k in np.floor((point - low) / cell))
        cubes.setdefault(key, [point, 0.0])[1] += weight
    ordered = sorted(cubes.items())
    return uavcov.Targets(np.array([p for _, (p, _) in ordered]), np.array([w for _, (_, w) in ordered]))


def _candidates(surface: uavcov.Terrain, spacing: float, altitude: float, n: int, keep_out=None) -> np.ndarray:
    """The start's candidates rebuilt from the pieces it is documented to use (no flight box cut: the box is wide)."""
    anchors, normals = surface_normals(surface, _spread(surface, spacing, 2 * n).points)
    return fly_out(surface, anchors, normals, altitude, floor=0.0, keep_out=keep_out)[0]


@pytest.mark.parametrize("seed", range(3))
def test_the_greedy_start_stays_out_of_s_prime_and_the_box_and_keeps_its_separation(seed: int) -> None:
    box = _box()
    prior = sample_structure_prior(box, 100, rng=seed)
    surface = reconstruct_structure(prior, rng=seed)
    positions, placed = start_configuration(
        _spec(), surface, box.surface, 8, d_max=15.0, constraints=LIMITS, keep_out=prior.behind, rng=seed
    )
    assert positions.shape == (8, 3)
    assert not surface.inside(positions).any() and not box.surface.inside(positions).any()
    assert not prior.behind(positions).any()
    assert (positions[:, 2] >= 3.0 - 1e-9).all()  # over the sensed ground by the offset
    gaps = np.linalg.norm(positions[:, None] - positions[None], axis=2)[np.triu_indices(8, 1)]
    assert gaps.min() >= 1.0
    # Its coverage is S''s, recounted independently of the seen-matrix; the picks are candidates.
    assert surface.n_faces > 1000  # S' is the envelope: the start thins its points
    recount = uavcov.Visibility(surface, 15.0, _spread(surface, 1.0, 100)).coverage(np.ascontiguousarray(positions))
    assert placed.coverage == pytest.approx(recount, abs=1e-12)
    candidates = _candidates(surface, 3.0, 3.0, 8, prior.behind)
    assert all(np.isclose(candidates, p).all(axis=1).any() for p in positions)
    assert placed.coverage <= placed.bound + 1e-12


def test_the_first_pick_is_the_best_single_candidate_by_brute_force() -> None:
    box = _box()
    surface = reconstruct_structure(sample_structure_prior(box, 100, rng=0), rng=0)
    placed = structure_greedy_start(_spec(altitude=4.0, spacing=4.0), surface, box.surface, 1, 15.0, LIMITS)
    vis = uavcov.Visibility(surface, 15.0, _spread(surface, 1.0, 100))
    alone = [vis.coverage(np.ascontiguousarray(c[None])) for c in _candidates(surface, 4.0, 4.0, 1)]
    assert placed.coverage == pytest.approx(max(alone), abs=1e-12)


def test_the_greedy_start_is_deterministic_and_ignores_the_thread_count() -> None:
    structure = STRUCTURE_FAMILIES["girder_bridge"](rng=1000)
    prior = sample_structure_prior(structure, 100, rng=1000)
    surface = reconstruct_structure(prior, rng=1000)
    runs = [
        structure_greedy_start(_spec(), surface, structure.surface, 8, 15.0, keep_out=prior.behind, n_threads=t).positions
        for t in (1, 3, 1)
    ]
    assert np.array_equal(runs[0], runs[1]) and np.array_equal(runs[0], runs[2])


@pytest.mark.parametrize("spacing", [1.0, 2.0, 4.0])
def test_the_start_weighs_as_many_points_as_the_area_asks_whatever_the_tessellation(spacing: float) -> None:
    from uavcov.placement._starts import _spread as library_spread

    prior = sample_structure_prior(_box(), 100, rng=4)
    through, envelope = reconstruct_structure(prior, margin=0.0, rng=4), reconstruct_structure(prior, rng=4)
    # At 1 m the surface through the points has fewer triangles than the area asks: its own targets.
    assert through.n_faces < through.area
    assert np.array_equal(library_spread(through, 1.0, 100).points, through.default_targets(density=1.0).points)
    spread = library_spread(envelope, spacing, 16)
    assert spread.weights.sum() == pytest.approx(envelope.area, rel=1e-9)
    # A cube of side s holds at most about 3 s^2 of a surface that bends no tighter than the
    # envelope, and the surface crosses every cube that holds a point.
    assert envelope.area / (3.0 * spacing**2) <= len(spread) <= 3.0 * envelope.area / spacing**2
    # A surface too small for 500 points at the spacing gets a finer cell: about 500.
    assert 500 / 3.0 <= len(library_spread(envelope, spacing, 500)) <= 3.0 * 500
    assert len(spread) < envelope.n_faces
    mine = _spread(envelope, spacing, 16)
    assert np.allclose(spread.points[np.lexsort(spread.points.T[::-1])], mine.points[np.lexsort(mine.points.T[::-1])])


def test_bad_greedy_starts_are_clear_errors() -> None:
    box = _box()
    # The surface through the points: its bottom at the ground, so a 1 m ceiling is under every candidate.
    surface = reconstruct_structure(sample_structure_prior(box, 100, rng=0), margin=0.0, rng=0)
    with pytest.raises(InvalidInputError, match="d_max"):
        structure_greedy_start(_spec(), surface, box.surface, 8, None, LIMITS)
    with pytest.raises(InvalidInputError, match="altitude"):
        structure_greedy_start(_spec(altitude=0.0), surface, box.surface, 8, 15.0, LIMITS)
    for d_max in (float("nan"), -1.0, 0.0):
        with pytest.raises(InvalidInputError):
            structure_greedy_start(_spec(), surface, box.surface, 8, d_max, LIMITS)
    # A ceiling under every candidate, and more UAVs than fit 10 m apart round the box: nothing
    # to place (the start takes two candidates per UAV, however sparse the spacing asked).
    with pytest.raises(InfeasibleError):
        structure_greedy_start(_spec(), surface, box.surface, 8, 15.0, Constraints(clearance="standoff", z_max=1.0))
    apart = Constraints(clearance="standoff", h_min=2.0, d_safe=10.0, z_max=40.0, check_moves=True)
    with pytest.raises(InfeasibleError, match="d_safe apart"):
        structure_greedy_start(_spec(spacing=30.0), surface, box.surface, 300, 15.0, apart)
