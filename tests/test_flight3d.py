"""Flight limits in 3D: ``Constraints(clearance="standoff")`` on structures.

The Rust answers (``Terrain.distance``, ``Terrain.inside``, the fused ``admissible_check``) are
compared with an independent implementation written here from the definitions: trimesh's
closest-point query for the standoff, the analytic boxes of the test structure for "inside a
solid", and a numpy Moller-Trumbore test of every move against every triangle.
"""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest

from tiny import tiny_experiment
from uavcov import Constraints, Terrain
from uavcov.errors import InfeasibleError, InvalidInputError, InvalidTypeError
from uavcov.experiments._sweep import experiment_settings, settings_hash
from uavcov.limits import closest_admissible, feasibility
from uavcov.limits._constraints import feasible_mask, trajectory_feasible

trimesh = pytest.importorskip("trimesh")

# the box's corners: bit 0 picks x, bit 1 y, bit 2 z; each quad wound outward
_QUADS = ((0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5))


def _box(lo, hi, base: int) -> tuple[list[list[float]], list[list[int]]]:
    v = [[(lo, hi)[k & 1][0], (lo, hi)[(k >> 1) & 1][1], (lo, hi)[(k >> 2) & 1][2]] for k in range(8)]
    f = []
    for a, b, c, d in _QUADS:
        f += [[base + a, base + b, base + c], [base + a, base + c, base + d]]
    return v, f


# A 40 m x 20 m ground, two piers and a deck 10-11 m up (the bridge), and a tower.
BOXES = (
    ((-12.0, -3.0, 0.0), (-10.0, 3.0, 10.0)),
    ((10.0, -3.0, 0.0), (12.0, 3.0, 10.0)),
    ((-15.0, -3.0, 10.0), (15.0, 3.0, 11.0)),
    ((-4.0, 6.0, 0.0), (-1.0, 9.0, 16.0)),
)


def _structure() -> tuple[np.ndarray, np.ndarray]:
    vertices = [[-20.0, -10.0, 0.0], [20.0, -10.0, 0.0], [20.0, 10.0, 0.0], [-20.0, 10.0, 0.0]]
    faces = [[0, 1, 2], [0, 2, 3]]
    for lo, hi in BOXES:
        v, f = _box(lo, hi, len(vertices))
        vertices += v
        faces += f
    return np.array(vertices), np.array(faces)


@pytest.fixture(scope="module")
def bridge() -> Terrain:
    return Terrain(*_structure())


def standoff(**changes) -> Constraints:
    settings = {"h_min": 2.0, "h_max": 8.0, "z_max": 25.0, "d_safe": 2.0, "check_moves": True, "clearance": "standoff"}
    return Constraints(**(settings | changes))


# ---------------------------------------------------------------------------------------------
# the independent reference
# ---------------------------------------------------------------------------------------------


def ref_distance(points: np.ndarray) -> np.ndarray:
    """trimesh's point-triangle closest point, every point against every triangle."""
    vertices, faces = _structure()
    triangles = vertices[faces]
    points = np.asarray(points, dtype=np.float64)
    pairs_t = np.tile(triangles, (len(points), 1, 1))
    pairs_p = np.repeat(points, len(triangles), axis=0)
    closest = trimesh.triangles.closest_point(pairs_t, pairs_p)
    return np.linalg.norm(closest - pairs_p, axis=1).reshape(len(points), len(triangles)).min(axis=1)


def ref_inside(points: np.ndarray) -> np.ndarray:
    p = np.asarray(points)[:, None, :]
    lo = np.array([b[0] for b in BOXES])[None]
    hi = np.array([b[1] for b in BOXES])[None]
    return ((p > lo) & (p < hi)).all(axis=2).any(axis=1)


def ref_above_ground(points: np.ndarray) -> np.ndarray:
    x, y, z = np.asarray(points).T
    return (x >= -20) & (x <= 20) & (y >= -10) & (y <= 10) & (z >= 0)


def ref_segment_hits(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Moller-Trumbore of every segment ``a -> b`` against every triangle (ends and edges count)."""
    vertices, faces = _structure()
    t0, t1, t2 = (vertices[faces[:, k]][None] for k in range(3))
    o = np.asarray(a)[:, None, :]
    d = (np.asarray(b) - np.asarray(a))[:, None, :]
    e1, e2 = t1 - t0, t2 - t0
    pvec = np.cross(d, e2)
    det = np.einsum("stk,stk->st", e1 * np.ones_like(pvec), pvec)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        tvec = o - t0
        u = np.einsum("stk,stk->st", tvec, pvec) * inv
        qvec = np.cross(tvec, e1)
        v = np.einsum("stk,stk->st", d * np.ones_like(qvec), qvec) * inv
        t = np.einsum("stk,stk->st", e2 * np.ones_like(qvec), qvec) * inv
        eps = 1e-9
        hit = (np.abs(det) > 1e-14) & (u >= -eps) & (v >= -eps) & (u + v <= 1 + eps) & (t >= -eps) & (t <= 1 + eps)
    return hit.any(axis=1)


# ---------------------------------------------------------------------------------------------
# the queries
# ---------------------------------------------------------------------------------------------


def test_distance_and_inside_match_the_reference_and_any_thread_count(bridge):
    rng = np.random.default_rng(1)
    points = rng.uniform([-22, -12, -3], [22, 12, 20], size=(3000, 3))
    dist = bridge.distance(points, n_threads=1)
    np.testing.assert_allclose(dist, ref_distance(points), rtol=1e-10, atol=1e-10)
    inside = bridge.inside(points, n_threads=1)
    above = points[:, 2] >= 0.0
    np.testing.assert_array_equal(inside[above], ref_inside(points[above]))
    assert 50 < inside.sum() < 2900
    # under the ground plane, its rays cross the ground once: "inside" where they all meet it
    deep = (points[:, 2] < 0.0) & (np.abs(points[:, 0]) < 19.0) & (np.abs(points[:, 1]) < 9.0)
    assert deep.sum() > 100 and inside[deep].all()
    for n in (2, 3):
        np.testing.assert_array_equal(bridge.distance(points, n_threads=n), dist)
        np.testing.assert_array_equal(bridge.inside(points, n_threads=n), inside)


def test_a_grid_answers_the_distance_too():
    grid = Terrain.from_grid(np.zeros((11, 11)), spacing=1.0)
    np.testing.assert_allclose(grid.distance([[5.0, 5.0, 3.0], [13.0, 9.0, 4.0]]), [3.0, 5.0])
    assert not grid.inside([[5.0, 5.0, 3.0]]).any()


@pytest.mark.parametrize("method", ["distance", "inside"])
@pytest.mark.parametrize(
    "points, error",
    [
        ([[0.0, 0.0, np.nan]], InvalidInputError),
        ([[0.0, 0.0, 1e300]], InvalidInputError),
        ([[0.0, 0.0]], InvalidInputError),
        ([[[0.0, 0.0, 1.0]]], InvalidInputError),
        ("abc", (InvalidInputError, InvalidTypeError)),
    ],
)
def test_bad_points_raise(bridge, method, points, error):
    with pytest.raises(error):
        getattr(bridge, method)(points)


# ---------------------------------------------------------------------------------------------
# the limits
# ---------------------------------------------------------------------------------------------


def test_under_the_deck_is_admissible_with_a_standoff_and_lifted_over_it_without(bridge):
    under = np.array([[0.0, 0.0, 5.0]])
    assert feasible_mask(standoff(), bridge, under, under[None])[0]
    np.testing.assert_array_equal(closest_admissible(standoff(), bridge, under), under)
    vertical = Constraints(h_min=2.0, z_max=25.0, check_moves=True)
    lifted = closest_admissible(vertical, bridge, under)
    assert lifted[0, 2] > 13.0 - 1e-3  # today's meaning: above the highest surface, the deck


def test_each_standoff_rule_refuses_on_its_own(bridge):
    c = standoff(check_moves=False, h_max=None)
    for q in ([0.0, 0.0, 9.0], [-11.0, 0.0, 5.0], [0.0, 0.0, -3.0], [0.0, 0.0, 26.0], [25.0, 0.0, 5.0]):
        x = np.array([q])
        assert not feasible_mask(c, bridge, x, x[None])[0], q
    far = np.array([[-18.0, -8.0, 20.0]])  # 20 m over the ground, > 8 m from everything
    assert feasible_mask(c, bridge, far, far[None])[0]
    assert not feasible_mask(standoff(check_moves=False), bridge, far, far[None])[0]
    # a move up through the deck: both ends keep their standoff, the move does not
    now, over = np.array([[0.0, 0.0, 5.0]]), np.array([[0.0, 0.0, 14.0]])
    assert feasible_mask(standoff(), bridge, over, over[None])[0]
    assert not feasible_mask(standoff(), bridge, now, over[None])[0]
    np.testing.assert_array_equal(trajectory_feasible(standoff(), bridge, np.stack([now, now, over])), [True, True, False])


@pytest.fixture(scope="module")
def random_batch(bridge):
    """Admissible teams of 4 around the bridge, and 600 random candidates near each."""
    rng = np.random.default_rng(7)
    teams = [closest_admissible(standoff(), bridge, rng.uniform([-18, -8, 1], [18, 8, 14], size=(4, 3)), climb=0.5) for _ in range(5)]
    candidates = [team[None] + rng.normal(scale=3.0, size=(600, 4, 3)) for team in teams]
    return teams, candidates


def test_every_accepted_configuration_keeps_every_limit_by_the_reference(bridge, random_batch):
    c = standoff().resolve(bridge)
    accepted = refused = 0
    for team, cand in zip(*random_batch, strict=True):
        mask = feasible_mask(c, bridge, team, cand)
        ok = cand[mask]
        accepted += len(ok)
        refused += len(cand) - len(ok)
        flat = ok.reshape(-1, 3)
        dist = ref_distance(flat)
        assert (dist >= c.h_min - 1e-9).all() and (dist <= c.h_max + 1e-9).all()
        assert not ref_inside(flat).any() and ref_above_ground(flat).all()
        assert (flat[:, 2] <= c.z_max).all()
        starts = np.broadcast_to(team[None], ok.shape).reshape(-1, 3)
        assert not ref_segment_hits(starts, flat).any()
        for i in range(4):
            for j in range(i + 1, 4):
                assert (np.linalg.norm(ok[:, i] - ok[:, j], axis=1) >= c.d_safe).all()
        # and what is refused breaks a rule (a candidate within 1e-6 m of a limit excepted)
        bad = cand[~mask]
        flat = bad.reshape(-1, 3)
        dist = ref_distance(flat).reshape(bad.shape[:2])
        starts = np.broadcast_to(team[None], bad.shape).reshape(-1, 3)
        broken = (
            (dist < c.h_min + 1e-6)
            | (dist > c.h_max - 1e-6)
            | ref_inside(flat).reshape(bad.shape[:2])
            | ~ref_above_ground(flat).reshape(bad.shape[:2])
            | ref_segment_hits(starts, flat).reshape(bad.shape[:2])
            | (bad[..., 2] > c.z_max)
            | (np.abs(bad[..., 0]) > 20)
            | (np.abs(bad[..., 1]) > 10)
        ).any(axis=1)
        gaps = np.linalg.norm(bad[:, :, None] - bad[:, None], axis=3) + np.eye(4) * 1e9
        broken |= (gaps < c.d_safe + 1e-6).any(axis=(1, 2))
        assert broken.all()
    assert accepted > 300 and refused > 300


class Plain:
    """A world without the fused check: feasible_mask queries it kind by kind."""

    def __init__(self, terrain):
        self.t = terrain

    def __getattr__(self, name):
        if name == "admissible_check":
            raise AttributeError(name)
        return getattr(self.t, name)


def test_the_fused_check_is_the_generic_one_and_the_same_for_any_thread_count(bridge, random_batch):
    c = standoff()
    for team, cand in zip(*random_batch, strict=True):
        fused = feasible_mask(c, bridge, team, cand, n_threads=1)
        np.testing.assert_array_equal(feasible_mask(c, Plain(bridge), team, cand), fused)
        np.testing.assert_array_equal(feasible_mask(c, bridge, team, cand, n_threads=3), fused)
        np.testing.assert_array_equal(feasibility(c, bridge, n_threads=2)(team, cand), fused)


@pytest.mark.parametrize(
    "start, most",
    [
        ([-11.0, 0.0, 5.0], 3.0 + 1e-3),  # inside a pier: out through its nearest face, 1 m away
        ([0.0, 0.0, 10.5], 2.5 + 1e-3),  # inside the deck
        ([0.0, 0.0, 9.5], 1.5 + 1e-3),  # under the deck, too close to it
        ([5.0, -5.0, -2.0], 4.0 + 1e-3),  # under the ground
        ([-2.5, 7.5, 17.0], 1.0 + 1e-3),  # over the tower, too close
    ],
)
def test_closest_admissible_pushes_out_to_a_near_admissible_position(bridge, start, most):
    x = np.array([start])
    out = closest_admissible(standoff(), bridge, x)
    assert feasible_mask(standoff(), bridge, out, out[None])[0]
    assert np.linalg.norm(out - x) <= most
    assert ref_distance(out)[0] >= 2.0 and not ref_inside(out).any() and ref_above_ground(out).all()


@pytest.mark.parametrize("family, seed", [("building", 0), ("building", 1001), ("girder_bridge", 1001), ("pylon", 1)])
def test_a_uav_clamped_onto_the_edge_where_the_ray_down_misses_is_moved_just_inside(family, seed):
    """The flight box is the mesh's extent: a UAV beyond it is clamped onto the ground's boundary
    edge, where the ray straight down misses by round-off at some points (found by scanning
    the edge). It is moved 1e-6 m inside and admitted, instead of a refused start (a CVT start
    on a Poisson S' of girder bridge 1001 was)."""
    from uavcov.structures import STRUCTURE_FAMILIES

    surface = STRUCTURE_FAMILIES[family](rng=seed).surface
    (xmin, _, _), (xmax, ymax, top) = surface.bounds
    edge = np.column_stack([np.linspace(xmin, xmax, 4001), np.full(4001, ymax), np.full(4001, top + 3.0)])
    missed = edge[~np.isfinite(surface.clearance(edge))]
    assert missed.size  # the case this guards
    limits = Constraints(clearance="standoff", h_min=2.0, z_max=top + 10.0, d_safe=1.0, check_moves=True)
    start = missed[:1] + [0.0, 5.0, 0.0]  # 5 m beyond the edge: clamped onto the missed point
    out = closest_admissible(limits, surface, start)
    assert feasible_mask(limits.resolve(surface), surface, out, out[None])[0]
    assert out[0, 1] == pytest.approx(ymax - 1e-6, abs=1e-9) and out[0, 0] == missed[0, 0] and out[0, 2] == missed[0, 2]


def test_closest_admissible_separates_a_team_deterministically(bridge):
    x = np.array([[0.0, 0.0, 5.0]] * 3 + [[-11.0, 0.0, 5.0], [0.0, 0.0, -1.0]])
    out = closest_admissible(standoff(), bridge, x)
    assert feasible_mask(standoff(), bridge, out, out[None])[0]
    np.testing.assert_array_equal(closest_admissible(standoff(), bridge, x), out)


def test_move_step_refuses_a_move_past_a_corner_and_uavs_whose_paths_cross(bridge):
    """Both moves have admissible ends and cross no surface (eq. 2's waypoints and the move check
    admit them); checked between the ends, in step, the first passes 0.54 m from the tower's
    corner (h_min 2 m) and the second swaps two UAVs 3 m apart through each other (d_safe 2 m)."""
    team = np.array([[1.5, 8.0, 5.0], [0.0, -6.0, 5.0], [3.0, -6.0, 5.0]])
    corner = team.copy()
    corner[0] = [-2.5, 3.5, 5.0]
    swap = team.copy()
    swap[[1, 2]] = team[[2, 1]]
    both = np.stack([corner, swap])
    assert ref_distance(np.array([[1.5 - 4 * 0.4, 8.0 - 4.5 * 0.4, 5.0]]))[0] < 2.0  # near the corner mid-move
    assert feasible_mask(standoff(), bridge, team, both).all()
    stepped = standoff(move_step=0.1)
    assert not feasible_mask(stepped, bridge, team, both).any()
    assert not feasibility(stepped, bridge)(team, both).any()
    away = team.copy()
    away[0] = [1.5, 12.0 - 3.0, 5.0]  # a short move along the tower's face, 2.5 m off it: kept
    away[1] = [0.0, -7.0, 5.0]
    assert feasible_mask(stepped, bridge, team, away[None])[0]


def test_move_step_is_the_same_through_the_fused_and_the_generic_check(bridge, random_batch):
    stepped, refused_more = standoff(move_step=0.25), 0
    for team, cand in zip(*random_batch, strict=True):
        fused = feasible_mask(stepped, bridge, team, cand, n_threads=1)
        np.testing.assert_array_equal(feasible_mask(stepped, Plain(bridge), team, cand), fused)
        np.testing.assert_array_equal(feasibility(stepped, bridge, n_threads=2)(team, cand), fused)
        ends_only = feasible_mask(standoff(), bridge, team, cand)
        assert not (fused & ~ends_only).any()  # it only ever refuses more
        refused_more += int((ends_only & ~fused).sum())
    assert refused_more > 0


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), float("inf"), "0.1", True])
def test_move_step_refuses_what_is_not_a_length(bad):
    with pytest.raises((InvalidInputError, InvalidTypeError)):
        Constraints(move_step=bad)  # type: ignore[arg-type]


def test_a_move_sampled_too_finely_is_a_clear_error(bridge):
    team = np.array([[0.0, -6.0, 5.0]])
    far = np.array([[[5.0, -6.0, 5.0]]])
    with pytest.raises(InvalidInputError, match="samples"):
        feasible_mask(standoff(move_step=1e-6), bridge, team, far)
    many = np.array([[0.0, -6.0, 5.0], [5.0, -6.0, 5.0], [-5.0, -6.0, 5.0]])
    batch = many[None] + np.array([[0.0, -2.0, 0.0]]) * np.linspace(0.0, 1.0, 2000)[:, None, None]
    with pytest.raises(InvalidInputError, match="sampled positions"):  # 2000 x 3 x ~4000 positions: refused before allocating
        feasible_mask(standoff(move_step=5e-4), bridge, many, batch)


def test_check_team_and_settings():
    with pytest.raises(InvalidInputError):
        Constraints(clearance="sideways")
    with pytest.raises(InvalidTypeError):
        Constraints(clearance=3)  # type: ignore[arg-type]
    c = standoff()
    assert pickle.loads(pickle.dumps(c)) == c
    assert Constraints().clearance == "vertical"
    ground = Terrain(*_structure())
    with pytest.raises(InfeasibleError):
        standoff(d_safe=200.0).check_team(3, ground)
    # a standoff's h_max bounds a shell, not a height band: 600 UAVs fit where a 0.1 m band would not
    standoff(h_min=2.0, h_max=2.1, d_safe=2.0).check_team(600, ground)
    with pytest.raises(InfeasibleError):
        Constraints(h_min=2.0, h_max=2.1, d_safe=2.0, z_max=25.0).check_team(600, ground)
    with pytest.raises(InvalidInputError):
        ground.admissible_check(bounds=(0, 0, 1, 1), h_min=1, h_max=None, z_max=5, d_safe=0, check_moves=True, clearance="up")


def test_the_new_setting_keeps_old_settings_hashes():
    exp = tiny_experiment()
    assert "clearance" not in experiment_settings(exp)["mission"]["constraints"]
    mission = exp.mission
    changed = dataclasses.replace(exp, mission=dataclasses.replace(mission, constraints=standoff()))
    same_but_vertical = dataclasses.replace(changed, mission=dataclasses.replace(mission, constraints=standoff(clearance="vertical")))
    assert settings_hash(changed) != settings_hash(same_but_vertical)
    assert "move_step" not in experiment_settings(changed)["mission"]["constraints"]
    stepped = dataclasses.replace(exp, mission=dataclasses.replace(mission, constraints=standoff(move_step=0.1)))
    assert settings_hash(stepped) != settings_hash(changed)


def test_bad_candidates_are_refused_or_raise(bridge):
    team = np.array([[0.0, 0.0, 5.0], [5.0, 0.0, 5.0]])
    nan = team.copy()
    nan[1, 2] = np.nan
    with pytest.raises(InvalidInputError):
        feasible_mask(standoff(), bridge, team, nan[None])
    deep = team.copy()
    deep[1, 2] = -1e300  # inside the x-y bounds and under z_max: too far to query
    with pytest.raises(InvalidInputError):
        feasible_mask(standoff(), bridge, team, deep[None])
    with pytest.raises(InvalidInputError):
        feasible_mask(standoff(), bridge, team, np.zeros((3, 3, 3)))
    with pytest.raises(InvalidInputError):
        closest_admissible(standoff(), bridge, [[0.0, 0.0, np.inf]])
